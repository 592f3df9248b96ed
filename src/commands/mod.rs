//! One module per command (or command family) of the `lsubdiv` binary, and what they share:
//! scheme loading, flag checks and the output check. Every command returns the one diagnostic
//! type, [`Error`], which `main` renders.

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

use lsubdiv::compiler::exact::scheme::MAX_DEGREE;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::compiler::Error;
use lsubdiv_cli::{resolve, Resolved};

/// Refuses, before any work, an output path that cannot be written: its folder must exist and
/// it must not be a folder itself (the write itself may still fail, leaving nothing behind).
pub fn check_output(path: &std::path::Path) -> Result<(), Error> {
    let fail = |what: &str| {
        Error::in_file(path.display(), what).with_hint("name a file in an existing folder")
    };
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

/// Refuses two inputs named `-` (`what` names each): standard input can be read once, and the
/// first would take all of it, leaving the second empty.
pub fn one_stdin(inputs: &[(&str, &std::path::Path)]) -> Result<(), Error> {
    let stdin: Vec<&str> = (inputs.iter())
        .filter(|(_, p)| p.as_os_str() == "-")
        .map(|(what, _)| *what)
        .collect();
    if let [first, second, ..] = stdin[..] {
        return Err(Error::input(format!(
            "the {first} and the {second} are both `-`: standard input can be read only once"
        ))
        .with_hint(format!("give the {first} or the {second} as a file")));
    }
    Ok(())
}

/// Checks `--degree`: 1 to [`MAX_DEGREE`].
pub fn check_degree(d: usize) -> Result<(), Error> {
    if d == 0 || d > MAX_DEGREE {
        return Err(Error::input(format!(
            "--degree {d} is out of range (1 to {MAX_DEGREE})"
        )));
    }
    Ok(())
}

/// The scheme named on the command line, at `--degree` when given (then no generated code
/// applies unless it is the file's own degree).
pub fn load(scheme: &str, degree: Option<usize>) -> Result<Resolved, Error> {
    let mut r = resolve(scheme)?;
    if let Some(d) = degree {
        check_degree(d)?;
        if d != r.ls.degree {
            r.ls.degree = d;
            r.builtin = false; // the generated tables are for the file's degree
        }
    }
    Ok(r)
}

/// The exact, certified scheme.
pub fn build(r: &Resolved) -> Result<Scheme, Error> {
    Scheme::build(r.ls.clone())
}

/// `--threads`, or all cores.
pub fn threads(flag: Option<usize>) -> usize {
    flag.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    })
}
