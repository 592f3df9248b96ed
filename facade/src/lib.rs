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

pub mod points;

use std::path::Path;

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
