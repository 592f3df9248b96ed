//! The diagnostics and files of lsubdiv, `std` only: one error type that says where, what is
//! wrong and how to fix it ([`Error`], [`Location`]), bounded reads ([`read_bytes`],
//! [`read_text`]) and outputs written whole or not at all ([`write_atomic`]). The compiler
//! reads scheme files through it, the facade meshes and points.

mod error;
mod input;
mod output;

pub use error::{Error, Kind, Location};
pub use input::{read_bytes, read_text, text};
pub use output::{temporary_files, write_atomic, write_atomic_with, write_if_changed};
