//! `lsubdiv plot`: control polygons of successive steps and the limit curve ([N] Fig. 2).

use crate::commands::args::{polygon, read_points, MemoryLimit, PolygonArgs};
use crate::commands::{build, load, one_stdin};
use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericScheme;
use lsubdiv::points::Points;

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
    /// Output picture: `.svg` or `.png`; SVG for a name without an extension (`-`: standard
    /// output). Written whole or not at all.
    #[arg(short, long)]
    output: std::path::PathBuf,
    #[command(flatten)]
    polygon: PolygonArgs,
    /// Picture size in pixels, WxH.
    #[arg(long, default_value = "800x600")]
    size: String,
    #[command(flatten)]
    limit: MemoryLimit,
}

/// Refines a planar polygon (a closed hexagon without input) with the generic path and draws
/// it ([`lsubdiv_cli::plot`]).
pub fn run(a: PlotArgs) -> Result<(), Error> {
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
        limit,
    } = a;
    let format = picture::format_of(&output)?;
    let size = picture::parse_size(&size)?;
    let max = limit.bytes();
    if steps > 12 {
        return Err(Error::input(format!(
            "--steps {steps}: plot draws at most 12 steps"
        )));
    }
    if let Some(path) = &input {
        one_stdin(&[("scheme", std::path::Path::new(&scheme)), ("points", path)])?;
    }
    let r = load(&scheme, degree)?;
    let (pts, closed) = match input {
        None => (lsubdiv_cli::plot::hexagon(), true),
        Some(path) => match read_points(&path, max)? {
            Points::D2(p) => (p, closed),
            Points::D3(_) => {
                return Err(Error::in_file(
                    path.display(),
                    "plot draws planar polygons; give 2 coordinates per point",
                ))
            }
        },
    };
    let generic = GenericScheme::new(build(&r)?)?;
    let curve = polygon(&r, &generic, pts, closed, labels.as_deref())?;
    let t = lsubdiv::CurveScheme::tables(&generic);
    curve.check(&t).map_err(lsubdiv_cli::input_error)?;
    // Every level is kept and drawn: the sum over them.
    let levels: Vec<_> = (0..=steps)
        .map(|k| lsubdiv_cli::limits::curve(&t, &curve.labels, closed, curve.points.len(), 2, k))
        .collect();
    let sum = |f: fn(&lsubdiv_cli::limits::Prediction) -> u128| {
        levels.iter().map(f).fold(0u128, u128::saturating_add)
    };
    // The levels and the picture's text are held together while it is drawn, then a PNG's
    // rendering (counted again, exactly, before it is made: `picture::save`); what the limit
    // pass adds beyond the last level's points is counted as it refines, within what is left.
    let vertices: Vec<u128> = levels.iter().map(|p| p.vertices).collect();
    let drawing = lsubdiv_cli::plot::predicted(&t, &vertices);
    let png = format == picture::Format::Png;
    let start = (vertices[steps] + t.degree as u128)
        .saturating_mul(lsubdiv_cli::plot::limit_point_bytes(png));
    let drawn = sum(|p| p.bytes)
        .saturating_add(drawing.text.saturating_mul(2))
        .saturating_add(start);
    lsubdiv_cli::limits::Prediction {
        vertices: sum(|p| p.vertices),
        quads: None,
        bytes: drawn,
    }
    .check(&format!("{steps} steps of {} in a plot", r.ls.name), max)?;
    let rendered = match png {
        true => {
            lsubdiv_cli::limits::picture(size, &drawing, max)?;
            lsubdiv_cli::limits::picture_bytes(size, &drawing)
        }
        false => 0,
    };
    let left = u128::from(max).saturating_sub(drawn.max(rendered));
    let limit_points = left / lsubdiv_cli::plot::limit_point_bytes(png);
    let pic = lsubdiv_cli::plot::plot(generic, &curve, steps, size, limit_points)?;
    picture::save(&pic, &output, max)
}
