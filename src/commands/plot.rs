//! `lsubdiv plot`: control polygons of successive steps and the limit curve ([N] Fig. 2).

use crate::commands::args::PolygonArgs;
use crate::commands::{bad, build, load, Failure};
use lsubdiv::compiler::exact::generic::GenericScheme;
use lsubdiv::points::{self, Points};
use lsubdiv::Curve;

/// Arguments of `lsubdiv plot`.
#[derive(clap::Args)]
pub struct PlotArgs {
    scheme: String,
    /// Number of subdivision steps drawn.
    #[arg(long, default_value_t = 3)]
    steps: usize,
    /// Input points (2 coordinates per line, as for `curve`); default: a closed regular
    /// hexagon.
    input: Option<std::path::PathBuf>,
    /// Output picture: `.svg` or `.png` (written whole or not at all).
    #[arg(short, long)]
    output: std::path::PathBuf,
    #[command(flatten)]
    polygon: PolygonArgs,
    /// Picture size in pixels, WxH.
    #[arg(long, default_value = "800x600")]
    size: String,
}

/// Refines a planar polygon (a closed hexagon without input) with the generic path and draws
/// it ([`lsubdiv_cli::plot`]).
pub fn run(a: PlotArgs) -> Result<(), Failure> {
    use lsubdiv_cli::picture;
    let PlotArgs {
        scheme,
        steps,
        input,
        output,
        polygon: PolygonArgs {
            closed,
            labels,
            degree,
        },
        size,
    } = a;
    picture::format_of(&output).map_err(bad)?;
    let size = picture::parse_size(&size).map_err(bad)?;
    if steps > 12 {
        return Err(bad(format!(
            "error: --steps {steps}: plot draws at most 12 steps"
        )));
    }
    let r = load(&scheme, degree)?;
    let (pts, closed) = match input {
        None => (lsubdiv_cli::plot::hexagon(), true),
        Some(path) => {
            let name = path.display().to_string();
            let text =
                std::fs::read_to_string(path).map_err(|e| bad(format!("{name}: error: {e}")))?;
            match points::parse(&name, &text).map_err(bad)? {
                Points::D2(p) => (p, closed),
                Points::D3(_) => {
                    return Err(bad(format!(
                        "{name}: error: plot draws planar polygons; give 2 coordinates per point"
                    )))
                }
            }
        }
    };
    let generic = GenericScheme::new(build(&r)?);
    let mut curve = Curve::with_axiom(&lsubdiv::CurveScheme::tables(&generic), pts, closed);
    if let Some(l) = labels {
        curve.labels =
            r.ls.parse_word(&l)
                .map_err(|e| bad(format!("error: --labels: {e}")))?;
    }
    let pic = lsubdiv_cli::plot::plot(generic, &curve, steps, size).map_err(bad)?;
    picture::save(&pic, &output).map_err(bad)
}
