//! `lsubdiv graph`: the transition graph between (d+1)-words ([N] Fig. 3).

use crate::commands::{build, load};
use lsubdiv::compiler::Error;
use lsubdiv_cli::output::write_atomic;
use lsubdiv_cli::report;

/// Arguments of `lsubdiv graph`.
#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("graph_format").required(true)))]
pub struct GraphArgs {
    scheme: String,
    #[arg(long)]
    degree: Option<usize>,
    /// Graphviz DOT output.
    #[arg(long, group = "graph_format")]
    dot: bool,
    /// A drawn picture: SVG, or PNG when the output ends in `.png` ([N] Fig. 3).
    #[arg(long, group = "graph_format")]
    svg: bool,
    /// Output file (written whole or not at all); default: standard output (DOT or SVG).
    #[arg(short, long)]
    output: Option<std::path::PathBuf>,
    /// Picture size in pixels, WxH (with --svg); default: the layout's natural size.
    #[arg(long)]
    size: Option<String>,
    #[command(flatten)]
    limit: crate::commands::args::MemoryLimit,
}

/// DOT or a picture of the transition graph, to a file or standard output.
pub fn run(a: GraphArgs) -> Result<(), Error> {
    use lsubdiv_cli::picture;
    let GraphArgs {
        scheme,
        degree,
        svg,
        output,
        size,
        limit,
        ..
    } = a;
    let size = size.as_deref().map(picture::parse_size).transpose()?;
    if let (true, Some(o)) = (svg, &output) {
        picture::format_of(o)?;
    }
    let s = build(&load(&scheme, degree)?)?;
    match (svg, output) {
        (false, None) => print!("{}", report::dot(&s)),
        (false, Some(o)) => write_atomic(&o, report::dot(&s).as_bytes())?,
        (true, None) => print!("{}", lsubdiv_cli::graph_picture::picture(&s, size).svg()?),
        (true, Some(o)) => picture::save(
            &lsubdiv_cli::graph_picture::picture(&s, size),
            &o,
            limit.bytes(),
        )?,
    }
    Ok(())
}
