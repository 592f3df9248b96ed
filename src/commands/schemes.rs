//! `lsubdiv schemes`: the shipped schemes.

use lsubdiv::compiler::Error;

/// Prints one name per line.
pub fn run() -> Result<(), Error> {
    for n in lsubdiv_cli::builtin_names() {
        println!("{n}");
    }
    Ok(())
}
