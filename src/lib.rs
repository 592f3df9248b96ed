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

pub mod bench;
pub mod charmap;
pub mod fuzzing;
pub mod graph_picture;
pub mod limits;
pub mod picture;
pub mod plot;
pub mod points;
pub mod progress;
pub mod render;
pub mod report;
pub mod tables;

use lsubdiv_compiler::{lsystem::LSystem, scheme, Error};
use std::path::Path;

mod builtin {
    include!(concat!(env!("OUT_DIR"), "/builtin.rs"));
}

/// A scheme named on the command line: its L-system, where it came from, and whether it is a
/// shipped scheme (so that its generated code applies).
#[derive(Clone, Debug)]
pub struct Resolved {
    /// The parsed L-system (its `source` names the file).
    pub ls: LSystem,
    /// True for a shipped scheme given by name.
    pub builtin: bool,
}

/// Names of the shipped schemes.
pub fn builtin_names() -> Vec<&'static str> {
    builtin::BUILTIN.iter().map(|(n, _, _)| *n).collect()
}

/// Resolves `arg`: a path to a scheme file, or the name of a shipped scheme.
pub fn resolve(arg: &str) -> Result<Resolved, Error> {
    let path = Path::new(arg);
    if path.exists() {
        return Ok(Resolved {
            ls: scheme::load(path)?,
            builtin: false,
        });
    }
    match builtin::BUILTIN.iter().find(|(n, _, _)| *n == arg) {
        Some((_, file, text)) => Ok(Resolved {
            ls: scheme::parse(file, text)?,
            builtin: true,
        }),
        None => Err(Error::Io {
            path: arg.to_string(),
            message: format!(
                "no such scheme file, and no shipped scheme of that name (shipped: {})",
                builtin_names().join(", ")
            ),
        }),
    }
}

/// Reads a closed quad mesh (2-manifold, valences ≥ 3) from an OBJ file, with the reader's
/// warnings (such as skipped `vn` lines); errors name the file's line, vertex or edge.
pub fn read_obj(path: &Path) -> Result<(runtime::mesh::QuadMesh, Vec<String>), String> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: error: {e}"))?;
    let (m, warnings) = runtime::mesh::parse_obj(&text).map_err(|e| e.in_obj(&name, &text))?;
    runtime::topology::Topology::build(&m)
        .and_then(|t| t.check_valences())
        .map_err(|e| e.in_obj(&name, &text))?;
    Ok((m, warnings))
}
