//! `lsubdiv schemes`: the shipped schemes.

use crate::commands::Failure;

/// Prints one name per line.
pub fn run() -> Result<(), Failure> {
    for n in lsubdiv_cli::builtin_names() {
        println!("{n}");
    }
    Ok(())
}
