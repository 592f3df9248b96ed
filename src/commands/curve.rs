//! `lsubdiv curve`: refines a control polygon read from a points file.

use crate::commands::args::{polygon, read_points, PolygonArgs, RefineArgs};
use crate::commands::{build, check_output, load, one_stdin};
use lsubdiv::compiler::exact::lsystem::Part;
use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericScheme;
use lsubdiv::points::{self, Points};
use lsubdiv::{CurveError, EndCurve};
use lsubdiv_cli::implementation::{Geometry, Implementation, PathChoice};
use lsubdiv_cli::output::write_atomic_with;
use lsubdiv_cli::Resolved;

/// Arguments of `lsubdiv curve`.
#[derive(clap::Args)]
pub struct CurveArgs {
    #[command(flatten)]
    refine: RefineArgs,
    /// Input points.
    input: std::path::PathBuf,
    /// Output points, full f64 precision.
    #[arg(short, long)]
    output: std::path::PathBuf,
    #[command(flatten)]
    polygon: PolygonArgs,
    /// The ends of an open polygon: `shrink` ([N] §2.3: the new points that have all their
    /// parents; m + d labels) or `interpolate` (the end points stay, by the odd-symmetric
    /// extension; m − 1 labels, one per edge; odd degrees, a symmetric scheme).
    #[arg(long, value_enum, default_value_t = Ends::Shrink)]
    ends: Ends,
    /// Write the refined points' limit points instead (on the limit curve, by the exact limit
    /// masks: degrees 1 and 3); an open polygon's two end points have none with `--ends
    /// shrink`.
    #[arg(long)]
    limit: bool,
    /// With `--limit`: the limit curve's derivative at each point as extra columns (with
    /// respect to the refined level's parameter, in which intervals have the scheme's lengths).
    #[arg(long, requires = "limit")]
    tangents: bool,
}

/// How an open polygon's ends are refined (`--ends`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
#[allow(missing_docs)]
pub enum Ends {
    // [N] §2.3: new points without all their parents are not computed.
    Shrink,
    // The odd-symmetric extension: the end points are interpolated.
    Interpolate,
}

/// Reads the points, refines them, writes them at full f64 precision.
pub fn run(a: CurveArgs) -> Result<(), Error> {
    let CurveArgs {
        refine,
        input,
        output,
        polygon,
        ends,
        limit,
        tangents,
    } = a;
    check_output(&output)?;
    one_stdin(&[
        ("scheme", std::path::Path::new(&refine.scheme)),
        ("points", &input),
    ])?;
    let r = load(&refine.scheme, polygon.degree)?;
    let implementation = refine.path.pick(&r, Geometry::Curve)?;
    let in_name = input.display().to_string();
    let stages = lsubdiv_cli::progress::Stages::new(3);
    stages.next(format!("reading {in_name}"));
    let pts = read_points(&input, refine.limit.bytes())?;
    let steps = refine.steps;
    stages.next(format!("refining: {steps} steps of {}", r.ls.name));
    let job = CurveJob {
        file: &in_name,
        what: format!("{steps} steps of {} on {in_name}", r.ls.name),
        polygon: &polygon,
        ends,
        steps,
        path: refine.path,
        implementation,
        max_memory: refine.limit.bytes(),
        limit,
    };
    let write = Output {
        stages: &stages,
        output: &output,
    };
    match (pts, limit) {
        (Points::D2(p), false) => write.points(&[&refine_cli(&r, p, &job)?.points]),
        (Points::D3(p), false) => write.points(&[&refine_cli(&r, p, &job)?.points]),
        (Points::D2(p), true) => write.limit(limit_cli(&r, p, &job)?, tangents),
        (Points::D3(p), true) => write.limit(limit_cli(&r, p, &job)?, tangents),
    }
}

/// Where the points go: streamed to the output, whole or not at all.
struct Output<'a> {
    stages: &'a lsubdiv_cli::progress::Stages,
    output: &'a std::path::Path,
}

impl Output<'_> {
    /// Line i: point i of each column set in turn ([`points::Text::with_columns`]).
    fn points<const D: usize>(&self, columns: &[&[[f64; D]]]) -> Result<(), Error> {
        let text = points::Text::with_columns(columns.to_vec())?;
        self.stages
            .next(format!("writing {}", self.output.display()));
        write_atomic_with(self.output, |out| write!(out, "{text}"))
    }

    /// The limit points, with their tangents as extra columns when asked.
    fn limit<const D: usize>(
        &self,
        l: lsubdiv::CurveLimit<D>,
        tangents: bool,
    ) -> Result<(), Error> {
        match tangents {
            true => self.points(&[&l.positions, &l.tangents]),
            false => self.points(&[&l.positions]),
        }
    }
}

/// What `lsubdiv curve` was asked to do, apart from the points.
struct CurveJob<'a> {
    /// The points file, named by the errors about the polygon it holds.
    file: &'a str,
    /// `N steps of SCHEME on FILE`, for the size guard's message.
    what: String,
    polygon: &'a PolygonArgs,
    ends: Ends,
    steps: usize,
    path: PathChoice,
    implementation: Implementation,
    max_memory: u64,
    /// `--limit`: the limit pass follows the refinement (the size guard counts it).
    limit: bool,
}

impl CurveJob<'_> {
    /// Refuses, before refining, a run the size guard predicts over `--max-memory`: the
    /// refinement's `prediction`, the input (`labels` with it) copied at another scale
    /// (`lsubdiv_cli::scale`), and with `--limit` the limit pass (`ends`: the degree, for
    /// interpolated ends).
    fn guard<const D: usize>(
        &self,
        prediction: lsubdiv_cli::limits::Prediction,
        input: &[[f64; D]],
        labels: usize,
        ends: Option<usize>,
    ) -> Result<(), Error> {
        let p = prediction.holding(lsubdiv::scale::copy_bytes(input, labels as u128));
        let p = match self.limit {
            true => p.with_curve_limit(D, ends),
            false => p,
        };
        p.check(&self.what, self.max_memory)
    }

    /// A curve error as a diagnostic about the points file.
    fn input_error(&self, e: CurveError) -> Error {
        Error::in_file(self.file, e.to_string())
    }
}

/// `--limit`: the refined curve's limit points and derivatives (`lsubdiv::runtime::limit`), by
/// the generic path's tables (the same exact masks the generated tables hold).
fn limit_cli<const D: usize>(
    r: &Resolved,
    points: Vec<[f64; D]>,
    job: &CurveJob<'_>,
) -> Result<lsubdiv::CurveLimit<D>, Error> {
    let Refined {
        points,
        labels,
        mut generic,
    } = refine_cli(r, points, job)?;
    let input_error = |e| job.input_error(e);
    if job.ends == Ends::Interpolate {
        let sigma = lsubdiv::compiler::exact::symmetry::rule_mirror(&r.ls)
            .ok_or_else(|| Error::internal(None, "interpolated ends without a mirror"))?;
        let curve = EndCurve { points, labels };
        // The extension is tabulated and dropped: `end_limit` makes its own.
        let extended = curve.extended(&lsubdiv::CurveScheme::tables(&generic), &sigma);
        generic.prepare(&extended.map_err(input_error)?)?;
        return lsubdiv::end_limit(&generic, &sigma, &curve).map_err(input_error);
    }
    let curve = lsubdiv::Curve {
        points,
        labels,
        closed: job.polygon.closed,
    };
    generic.prepare(&curve)?;
    lsubdiv::curve_limit(&generic, &curve).map_err(input_error)
}

/// Refines by the picked implementation; under `auto`, labels that make words the generated
/// tables lack go to the generic path. Refuses, before refining, a result predicted to need
/// more than `--max-memory`.
fn refine_cli<const D: usize>(
    r: &Resolved,
    points: Vec<[f64; D]>,
    job: &CurveJob<'_>,
) -> Result<Refined<D>, Error> {
    if job.ends == Ends::Interpolate {
        return refine_ends_cli(r, points, job);
    }
    let steps = job.steps;
    let input_error = |e| job.input_error(e);
    let mut generic = GenericScheme::new(build(r)?)?;
    let closed = job.polygon.closed;
    let curve = polygon(r, &generic, points, closed, job.polygon.labels.as_deref())?;
    let t = lsubdiv::CurveScheme::tables(&generic);
    curve.check(&t).map_err(input_error)?;
    job.guard(
        lsubdiv_cli::limits::curve(&t, &curve.labels, closed, curve.points.len(), D, steps),
        &curve.points,
        curve.labels.len(),
        None,
    )?;
    // Huge or tiny coordinates are refined scaled to magnitude 1 (`lsubdiv_cli::scale`).
    let (labels, points) = lsubdiv::scale::refine_scaled(job.file, &curve.points, |scaled| {
        let scaled = scaled.map(|points| lsubdiv::Curve {
            points,
            labels: curve.labels.clone(),
            closed,
        });
        let curve = scaled.as_ref().unwrap_or(&curve);
        let generated = generated(r, job, || {
            lsubdiv::generated::refine_curve(&r.ls.name, curve, steps)
        })?;
        let refined = match generated {
            Some(c) => c,
            None => {
                generic.prepare(curve)?;
                lsubdiv::refine(&generic, curve, steps).map_err(input_error)?
            }
        };
        Ok((refined.labels, refined.points))
    })?;
    Ok(Refined {
        points,
        labels,
        generic,
    })
}

/// A refined curve, and the generic tables built for it (the limit pass tabulates its words
/// there instead of compiling the scheme again).
struct Refined<const D: usize> {
    points: Vec<[f64; D]>,
    labels: Vec<u8>,
    generic: GenericScheme,
}

/// `--ends interpolate`: the odd-symmetric extension across each end (`lsubdiv::runtime::ends`)
/// by the picked implementation (under `auto`, mirrored words the generated tables lack go to
/// the generic path, which tabulates them), under the size guard.
fn refine_ends_cli<const D: usize>(
    r: &Resolved,
    points: Vec<[f64; D]>,
    job: &CurveJob<'_>,
) -> Result<Refined<D>, Error> {
    let input_error = |e| job.input_error(e);
    if job.polygon.closed {
        return Err(Error::input(
            "--ends interpolate is for open polygons: drop --closed (a closed polygon has no ends)",
        ));
    }
    let sigma = lsubdiv::compiler::exact::symmetry::rule_mirror(&r.ls).ok_or_else(|| {
        r.ls.error(
            Part::Rules,
            format!(
                "`{}` has no mirror symmetry σ with π(σ(A)) = σ̄(π(A)) ([G] eq. (14)): interpolated ends reflect the curve across them",
                r.ls.name
            ),
            Some("use --ends shrink, or a symmetric scheme (e.g. uniform-binary, binary-ternary)".into()),
        )
    })?;
    let mut generic = GenericScheme::new(build(r)?)?;
    let t = lsubdiv::CurveScheme::tables(&generic);
    let mut curve = EndCurve::with_axiom(&t, points);
    if let Some(l) = job.polygon.labels.as_deref() {
        curve.labels =
            r.ls.parse_word(l)
                .map_err(|e| Error::input(format!("--labels: {e}")))?;
    }
    let extended = curve.extended(&t, &sigma).map_err(input_error)?;
    job.guard(
        lsubdiv_cli::limits::curve_ends(&t, &curve.labels, curve.points.len(), D, job.steps),
        &curve.points,
        curve.labels.len(),
        Some(t.degree),
    )?;
    let (labels, points) = lsubdiv::scale::refine_scaled(job.file, &curve.points, |scaled| {
        let scaled = scaled.map(|points| EndCurve {
            points,
            labels: curve.labels.clone(),
        });
        let curve = scaled.as_ref().unwrap_or(&curve);
        let generated = generated(r, job, || {
            lsubdiv::generated::refine_ends(&r.ls.name, &sigma, curve, job.steps)
        })?;
        let fine = match generated {
            Some(c) => c,
            None => {
                generic.prepare(&extended)?;
                lsubdiv::refine_ends(&generic, &sigma, curve, job.steps).map_err(input_error)?
            }
        };
        Ok((fine.labels, fine.points))
    })?;
    Ok(Refined {
        points,
        labels,
        generic,
    })
}

/// The generated kernels' result by `run` (a registry call) when the picked implementation is
/// generated; `None` for the generic path, or, under `auto`, when the curve makes a word the
/// generated tables lack.
fn generated<T>(
    r: &Resolved,
    job: &CurveJob<'_>,
    run: impl FnOnce() -> Option<Result<T, CurveError>>,
) -> Result<Option<T>, Error> {
    if job.implementation == Implementation::Generic {
        return Ok(None);
    }
    match run()
        .ok_or_else(|| Error::internal(None, format!("`{}` is not in the registry", r.ls.name)))?
    {
        Err(CurveError::UnknownWord(_)) if job.path == PathChoice::Auto => Ok(None),
        c => c.map(Some).map_err(|e| job.input_error(e)),
    }
}
