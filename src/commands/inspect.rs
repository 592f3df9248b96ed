//! `lsubdiv inspect`: validity, M, ρ, lengths, eigenvectors, masks, SCCs, transitional steps.

use crate::commands::{build, load};
use lsubdiv::compiler::exact::validity::analyse;
use lsubdiv::compiler::Error;
use lsubdiv_cli::report;

/// Arguments of `lsubdiv inspect`.
#[derive(clap::Args)]
pub struct InspectArgs {
    /// Scheme file, or the name of a shipped scheme (`lsubdiv schemes` lists them).
    scheme: String,
    /// Override the scheme's degree.
    #[arg(long)]
    degree: Option<usize>,
    /// One JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Prints the report (text or JSON); an invalid scheme is reported, then refused.
pub fn run(a: InspectArgs) -> Result<(), Error> {
    let InspectArgs {
        scheme,
        degree,
        json,
    } = a;
    let r = load(&scheme, degree)?;
    let a = analyse(&r.ls)?;
    let compiled = if a.valid && a.lengths.is_some() {
        Some(build(&r)?)
    } else {
        None
    };
    if json {
        println!("{}", report::json(&r.ls, &a, compiled.as_ref()));
    } else {
        print!("{}", report::text(&r.ls, &a, compiled.as_ref()));
    }
    a.invalid_error(&r.ls).map_or(Ok(()), Err)
}
