//! lsubdiv: exact non-uniform B-spline subdivision schemes from L-systems, for programs.
//!
//! The front door: a [`Scheme`] (shipped, chosen by name; compiled by your build script; or a
//! scheme file compiled at run time with the `compiler` feature), a [`Mesh`] as a file holds
//! it, and a [`Refiner`] that builds a [`Plan`] once and refines with it: positions, the limit
//! surface with normals, texture coordinates ([`Refined`], written whole by
//! [`Refined::write`]), frame after frame for an animation ([`Plan::frames`]). Errors are an
//! enum a program can match ([`Error`]).
//!
//! ```
//! # fn main() -> Result<(), lsubdiv::Error> {
//! let scheme = lsubdiv::Scheme::shipped("fibonacci")?;
//! let cube = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\n\
//!             v -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n\
//!             t crease 2/1/0 0 1 10\n";
//! let mesh = lsubdiv::Mesh::parse("cube.obj", cube.as_bytes().to_vec())?;
//! let plan = lsubdiv::Refiner::new(&scheme, &mesh).steps(3).limit(true).build()?;
//! let fine = plan.refine()?;
//! assert_eq!(fine.normals.map(|n| n.len()), Some(fine.mesh.positions.len()));
//! # Ok(())
//! # }
//! ```
//!
//! Curves refine with [`Scheme::refine_curve`] (the shipped schemes with their specialised
//! kernels):
//!
//! ```
//! use lsubdiv::{Curve, CurveScheme, Scheme};
//!
//! let golden = Scheme::shipped("fibonacci-curve")?;
//! let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
//! let coarse = Curve::with_axiom(&golden.tables(), square, true);
//! let fine = golden.refine_curve(&coarse, 4)?;
//! assert!(fine.points.len() > 4 * 4);
//! # Ok::<(), lsubdiv::Error>(())
//! ```
//!
//! Below the front door, the facade re-exports the crates it is made of: [`runtime`] (tiny, what
//! generated code links against), [`mesh`] (the mesh refiner: topology, features, the polygon
//! step, patches, limits, face-varying data), [`generated`] (the shipped schemes, compiled) and,
//! with the `compiler` feature, `compiler` (the exact pipeline) and `generic` (tables computed
//! at run time from a scheme file, masks added on demand); and file formats ([`obj`], [`ply`],
//! [`points`]) whose errors name the file's line.
//!
//! # Compiled schemes
//!
//! A crate that depends on `lsubdiv` alone (and on `lsubdiv-compiler` in its build script)
//! compiles a scheme in `build.rs` (`lsubdiv_compiler::compile(&["schemes/my.toml"])`) and
//! includes it with [`include_scheme!`]: `lsubdiv::include_scheme!(my);` then
//! `Scheme::compiled(&my::Scheme)`.

#[cfg(feature = "compiler")]
#[doc(inline)]
pub use lsubdiv_compiler as compiler;
#[doc(inline)]
pub use lsubdiv_generated as generated;
#[doc(inline)]
pub use lsubdiv_mesh as mesh;
#[doc(inline)]
pub use lsubdiv_runtime as runtime;
#[doc(inline)]
pub use lsubdiv_runtime::{
    curve_limit, end_limit, refine, refine_ends, Curve, CurveError, CurveLimit, CurveRefiner,
    CurveScheme, CurveTables, EndCurve,
};

pub use error::Error;
#[doc(inline)]
pub use lsubdiv_io::{write_atomic, write_atomic_with, Error as Diagnostic, Location};
#[doc(inline)]
pub use lsubdiv_mesh::facevarying::UvRule;
#[doc(inline)]
pub use lsubdiv_mesh::features::Boundary;
pub use mesh_file::Mesh;
pub use refiner::{Frame, Frames, Limit, Options, Plan, Refined, Refiner};
pub use scheme::Scheme;

mod error;
#[cfg(feature = "compiler")]
pub mod generic;
pub mod mesh_data;
pub mod mesh_file;
pub mod obj;
pub mod obj_tags;
pub mod ply;
pub mod points;
mod refiner;
pub mod scale;
mod scheme;

/// Includes the scheme `name` compiled by `lsubdiv_compiler` into `OUT_DIR` as `pub mod name`,
/// naming the runtime through this crate (`lsubdiv::runtime`): a crate that depends on `lsubdiv`
/// alone (and on `lsubdiv-compiler` in its build script) needs nothing else.
#[macro_export]
macro_rules! include_scheme {
    ($name:ident) => {
        $crate::runtime::include_scheme!($name, runtime = $crate::runtime);
    };
}
