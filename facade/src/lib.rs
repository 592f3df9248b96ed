//! lsubdiv: exact non-uniform B-spline subdivision schemes from L-systems, for programs.
//!
//! The facade re-exports the four crates: [`compiler`] (exact, build-time), [`runtime`] (tiny,
//! what generated code links against), [`mesh`] (the mesh refiner: topology, features, the
//! polygon step, patches, limits, face-varying data) and [`generated`] (the shipped schemes,
//! compiled); it adds the dynamic path ([`generic`]: tables computed at run time from any
//! scheme file) and file formats.
//!
//! # Quick start: a scheme file at run time
//!
//! ```
//! use lsubdiv::compiler::exact::{scheme, Scheme};
//! use lsubdiv::generic::GenericScheme;
//! use lsubdiv::{Curve, CurveScheme};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! # let dir = std::env::temp_dir().join(format!("lsubdiv-doc-{}", std::process::id()));
//! # std::fs::create_dir_all(&dir)?;
//! let path = dir.join("golden.toml");
//! std::fs::write(&path, "name = \"golden\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LS\"\nS = \"L\"\n")?;
//! // Exact compilation (errors name file, line and column), then run-time tables.
//! let mut golden = GenericScheme::new(Scheme::build(scheme::load(&path)?)?)?;
//! let hexagon: Vec<[f64; 3]> = (0..6)
//!     .map(|k| {
//!         let a = k as f64 * std::f64::consts::TAU / 6.0;
//!         [a.cos(), a.sin(), 0.0]
//!     })
//!     .collect();
//! let coarse = Curve::with_axiom(&golden.tables(), hexagon, true);
//! golden.prepare(&coarse)?; // masks of words the axiom never makes, if the labels have any
//! let fine = lsubdiv::refine(&golden, &coarse, 4)?;
//! assert!(fine.points.len() > 6 * 4);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok(())
//! # }
//! ```
//!
//! # Compiled schemes
//!
//! A crate that depends on `lsubdiv` alone (and on `lsubdiv-compiler` in its build script)
//! compiles a scheme in `build.rs` (`lsubdiv_compiler::compile(&["schemes/my.toml"])`) and
//! includes it with [`include_scheme!`]: `lsubdiv::include_scheme!(my);` then
//! `lsubdiv::refine(&my::Scheme, &curve, steps)`. The shipped schemes are in [`generated`].

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
