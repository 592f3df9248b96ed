//! lsubdiv: exact non-uniform B-spline subdivision schemes from L-systems.
//!
//! The facade re-exports the three crates: [`compiler`] (exact, build-time), [`runtime`] (tiny,
//! what generated code links against) and [`generated`] (the shipped schemes, compiled).
//!
//! In a user's `build.rs`: `lsubdiv_compiler::compile(&["schemes/my.toml"])?;` and in the library:
//! `lsubdiv::include_scheme!(my);` then `lsubdiv::refine(&my::Scheme, &curve, steps)`.

pub use lsubdiv_compiler as compiler;
pub use lsubdiv_generated as generated;
pub use lsubdiv_runtime as runtime;
pub use lsubdiv_runtime::{
    include_scheme, refine, Curve, CurveError, CurveRefiner, CurveScheme, CurveTables,
};

pub use lsubdiv_compiler::{Error, Location};
pub use obj::read as read_obj;

pub mod obj;
pub mod ply;
pub mod points;
