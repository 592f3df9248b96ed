//! One module per command (or command family) of the `lsubdiv` binary, and what they share:
//! the failure type, scheme loading and the output check.

pub mod args;
pub mod bench;
pub mod codegen;
pub mod curve;
pub mod demo;
pub mod ev;
pub mod explore;
pub mod graph;
pub mod inspect;
pub mod plot;
pub mod render;
pub mod schemes;
pub mod subdivide;

use lsubdiv::compiler::exact::Scheme;
use lsubdiv::compiler::Error;
use lsubdiv_cli::{resolve, Resolved};

/// A failure and its exit status.
pub struct Failure {
    pub code: u8,
    pub message: String,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure {
            code: if e.is_internal() { 1 } else { 2 },
            message: e.to_string(),
        }
    }
}

pub fn bad(message: String) -> Failure {
    Failure { code: 2, message }
}

/// Refuses, before any work, an output path that cannot be written: its folder must exist and
/// it must not be a folder itself (the write itself may still fail, leaving nothing behind).
pub fn check_output(path: &std::path::Path) -> Result<(), Failure> {
    let fail = |what: &str| bad(format!("{}: error: {what}", path.display()));
    if path.is_dir() {
        return Err(fail("is a directory; give a file name"));
    }
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => {
            Err(fail("no such directory to write into"))
        }
        _ => Ok(()),
    }
}

pub fn load(scheme: &str, degree: Option<usize>) -> Result<Resolved, Failure> {
    let mut r = resolve(scheme)?;
    if let Some(d) = degree {
        if d == 0 || d > lsubdiv::compiler::exact::scheme::MAX_DEGREE {
            return Err(bad(format!(
                "error: --degree {d} is out of range (1 to {})",
                lsubdiv::compiler::exact::scheme::MAX_DEGREE
            )));
        }
        if d != r.ls.degree {
            r.ls.degree = d;
            r.builtin = false; // the generated tables are for the file's degree
        }
    }
    Ok(r)
}

pub fn build(r: &Resolved) -> Result<Scheme, Failure> {
    Ok(Scheme::build(r.ls.clone())?)
}
