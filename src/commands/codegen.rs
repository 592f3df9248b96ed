//! `lsubdiv codegen`: the generated Rust source of a scheme.

use crate::commands::{build, load};
use lsubdiv::compiler::exact::codegen::generate;
use lsubdiv::compiler::exact::Tables;
use lsubdiv::compiler::Error;
use lsubdiv_cli::output::write_atomic;

/// Arguments of `lsubdiv codegen`.
#[derive(clap::Args)]
pub struct CodegenArgs {
    scheme: String,
    #[arg(long)]
    degree: Option<usize>,
    /// Output file (written whole or not at all).
    #[arg(short, long)]
    output: std::path::PathBuf,
}

/// Writes the generated source, whole or not at all.
pub fn run(a: CodegenArgs) -> Result<(), Error> {
    let s = build(&load(&a.scheme, a.degree)?)?;
    write_atomic(&a.output, generate(&Tables::new(s)?).as_bytes())?;
    Ok(())
}
