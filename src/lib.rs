//! The internals of the `lsubdiv` command line (the commands themselves are in the binary,
//! `src/commands/`): reports and tables, the pictures and the software renderer, the benchmark
//! harness, the size guard, the choice of implementation and the output writer. Not a public
//! API: a program that uses lsubdiv depends on the facade `lsubdiv` instead.

pub mod bench;
pub mod charmap;
pub mod graph_picture;
pub mod implementation;
pub mod limits;
pub mod output;
pub mod picture;
pub mod plot;
pub mod progress;
pub mod render;
pub mod report;
pub mod tables;

use lsubdiv::compiler::exact::{lsystem::LSystem, scheme};
use lsubdiv::compiler::Error;
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

/// A refinement or analysis that the input made fail (labels the scheme lacks, too few points,
/// a valence out of range), as a diagnostic of no file.
pub fn input_error(e: impl std::fmt::Display) -> Error {
    Error::input(e.to_string())
}

/// Names of the shipped schemes.
pub fn builtin_names() -> Vec<&'static str> {
    builtin::BUILTIN.iter().map(|(n, _, _)| *n).collect()
}

/// Resolves `arg`: a path to a scheme file (`-`: standard input), or the name of a shipped scheme. A file wins over a
/// shipped name; a folder of the same name does not hide the shipped scheme.
pub fn resolve(arg: &str) -> Result<Resolved, Error> {
    // `-` is standard input, as for every other input.
    let path = Path::new(if arg == "-" { "/dev/stdin" } else { arg });
    let shipped = builtin::BUILTIN.iter().find(|(n, _, _)| *n == arg);
    if path.is_file() || (shipped.is_none() && path.exists()) {
        return Ok(Resolved {
            ls: scheme::load(path)?,
            builtin: false,
        });
    }
    match shipped {
        Some((_, file, text)) => Ok(Resolved {
            ls: scheme::parse(file, text)?,
            builtin: true,
        }),
        None => Err(Error::in_file(
            arg,
            format!(
                "no such scheme file, and no shipped scheme of that name (shipped: {})",
                builtin_names().join(", ")
            ),
        )),
    }
}
