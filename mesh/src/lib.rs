//! The mesh refiner of lsubdiv: quad and polygon meshes of any topology refined by any surface
//! scheme of `lsubdiv-runtime` (generated or table-driven). It holds the topology
//! ([`topology`]) with its creases, corners and holes ([`features`]), meshes that are not
//! 2-manifolds ([`nonmanifold`]), the first, Catmull–Clark step of polygon meshes
//! ([`polygon`]), the patch refiner ([`patch`]: plan, kernels, limit surface), the reference
//! driver it is checked against ([`surface`]) and face-varying data ([`facevarying`]), with
//! generators of test meshes (`generators`, with the feature of that name).

pub mod facevarying;
pub mod features;
#[cfg(any(test, feature = "generators"))]
pub mod generators;
mod grid;
mod mesh;
pub mod nonmanifold;
pub mod patch;
pub mod polygon;
pub mod real;
mod stencil;
pub mod surface;
mod threads;
pub mod topology;

pub use mesh::QuadMesh;
