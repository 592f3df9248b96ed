//! `lsubdiv curve`: refines a control polygon read from a points file.

use crate::commands::args::{MemoryLimit, PathChoice, PolygonArgs};
use crate::commands::{bad, build, check_output, load, Failure};
use lsubdiv::compiler::exact::generic::GenericScheme;
use lsubdiv::points::{self, Points};
use lsubdiv::{Curve, CurveError};
use lsubdiv_cli::output::write_atomic;
use lsubdiv_cli::Resolved;

/// Arguments of `lsubdiv curve`.
#[derive(clap::Args)]
pub struct CurveArgs {
    scheme: String,
    /// Number of subdivision steps.
    #[arg(long)]
    steps: usize,
    /// Input points.
    input: std::path::PathBuf,
    /// Output points, full f64 precision.
    #[arg(short, long)]
    output: std::path::PathBuf,
    #[command(flatten)]
    polygon: PolygonArgs,
    /// Which implementation refines: the generated kernels of a shipped scheme, the generic
    /// table-driven path, or `auto` (generated when available).
    #[arg(long, value_enum, default_value_t = PathChoice::Auto)]
    path: PathChoice,
    #[command(flatten)]
    limit: MemoryLimit,
}

/// Reads the points, refines them, writes them at full f64 precision.
pub fn run(a: CurveArgs) -> Result<(), Failure> {
    let CurveArgs {
        scheme,
        steps,
        input,
        output,
        polygon: PolygonArgs {
            closed,
            labels,
            degree,
        },
        path,
        limit,
    } = a;
    check_output(&output)?;
    let r = load(&scheme, degree)?;
    let in_name = input.display().to_string();
    let stages = lsubdiv_cli::progress::Stages::new(3);
    stages.next(format!("reading {in_name}"));
    lsubdiv_cli::limits::input(&input, limit.bytes()).map_err(bad)?;
    let text =
        std::fs::read_to_string(&input).map_err(|e| bad(format!("{in_name}: error: {e}")))?;
    let pts = points::parse(&in_name, &text).map_err(bad)?;
    drop(text);
    stages.next(format!("refining: {steps} steps of {}", r.ls.name));
    let job = CurveJob {
        what: format!("{steps} steps of {} on {in_name}", r.ls.name),
        closed,
        labels,
        steps,
        path,
        max_memory: limit.bytes(),
    };
    let out = match pts {
        Points::D2(p) => points::format(&refine_cli(&r, p, job)?),
        Points::D3(p) => points::format(&refine_cli(&r, p, job)?),
    };
    stages.next(format!("writing {}", output.display()));
    write_atomic(&output, out.as_bytes())?;
    Ok(())
}

/// What `lsubdiv curve` was asked to do, apart from the points.
struct CurveJob {
    /// `N steps of SCHEME on FILE`, for the size guard's message.
    what: String,
    closed: bool,
    labels: Option<String>,
    steps: usize,
    path: PathChoice,
    max_memory: u64,
}

/// Refines with the requested path; `auto` uses the generated kernels for shipped schemes and
/// the generic path otherwise (or when the labels make words the generated tables lack).
/// Refuses, before refining, a result predicted to need more than `--max-memory`.
fn refine_cli<const D: usize>(
    r: &Resolved,
    points: Vec<[f64; D]>,
    job: CurveJob,
) -> Result<Vec<[f64; D]>, Failure> {
    let CurveJob {
        closed,
        steps,
        path,
        ..
    } = job;
    let scheme = build(r)?;
    let mut generic = GenericScheme::new(scheme);
    let mut curve = Curve::with_axiom(&lsubdiv::CurveScheme::tables(&generic), points, closed);
    if let Some(l) = job.labels {
        curve.labels =
            r.ls.parse_word(&l)
                .map_err(|e| bad(format!("error: --labels: {e}")))?;
    }
    let curve_err = |e: CurveError| bad(format!("error: {e}"));
    let t = lsubdiv::CurveScheme::tables(&generic);
    curve.check(&t).map_err(curve_err)?;
    lsubdiv_cli::limits::curve(&t, &curve.labels, closed, curve.points.len(), D, steps)
        .check(&job.what, job.max_memory)
        .map_err(bad)?;
    let generated = || -> Option<Result<Curve<D>, CurveError>> {
        r.builtin
            .then(|| lsubdiv::generated::refine_curve(&r.ls.name, &curve, steps))
            .flatten()
    };
    let refined = match path {
        PathChoice::Generated => generated()
            .ok_or_else(|| bad(format!("error: `{}` has no generated code (only shipped schemes at their own degree do)", r.ls.name)))?
            .map_err(curve_err)?,
        PathChoice::Auto => match generated() {
            Some(Ok(c)) => c,
            Some(Err(CurveError::UnknownWord(_))) | None => {
                generic.prepare(&curve);
                lsubdiv::refine(&generic, &curve, steps).map_err(curve_err)?
            }
            Some(Err(e)) => return Err(curve_err(e)),
        },
        PathChoice::Generic => {
            generic.prepare(&curve);
            lsubdiv::refine(&generic, &curve, steps).map_err(curve_err)?
        }
    };
    Ok(refined.points)
}
