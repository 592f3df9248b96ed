//! The `lsubdiv` command line. Exit status: 0 ok, 2 bad input (scheme, points, labels), 1
//! internal error.

use clap::{Parser, Subcommand, ValueEnum};
use lsubdiv::compiler::exact::codegen::generate;
use lsubdiv::compiler::exact::validity::analyse;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::compiler::exact::Tables;
use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericScheme;
use lsubdiv::points::{self, Points};
use lsubdiv::runtime::mesh::QuadMesh;
use lsubdiv::runtime::topology::Topology;
use lsubdiv::{Curve, CurveError};
use lsubdiv_cli::output::write_atomic;
use lsubdiv_cli::{report, resolve, tables, Resolved};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "lsubdiv",
    version,
    about = "Exact non-uniform B-spline subdivision from L-systems"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Validity, M, ρ, lengths, eigenvectors, masks (exact and f64), SCCs, transitional steps.
    Inspect {
        /// Scheme file, or the name of a shipped scheme (`lsubdiv schemes` lists them).
        scheme: String,
        /// Override the scheme's degree.
        #[arg(long)]
        degree: Option<usize>,
        /// One JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// The transition graph between (d+1)-words: DOT, or a picture ([N] Fig. 3).
    #[command(group(clap::ArgGroup::new("graph_format").required(true)))]
    Graph {
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
    },
    /// Writes the generated Rust source of a scheme.
    Codegen {
        scheme: String,
        #[arg(long)]
        degree: Option<usize>,
        /// Output file (written whole or not at all).
        #[arg(short, long)]
        output: std::path::PathBuf,
    },
    /// Refines a control polygon (one point per line, 2 or 3 coordinates).
    Curve {
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
    },
    /// Draws control polygons of successive steps and the limit curve, coloured by interval
    /// label ([N] Fig. 2), as SVG or PNG (by the output's extension).
    Plot {
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
    },
    /// α and the spectrum at extraordinary vertices (\[G\] §4.2.3), per valence.
    Ev {
        scheme: String,
        /// A valence `n` or a range `a..b` (inclusive).
        #[arg(long, default_value = "3..16")]
        valence: String,
        /// One JSON object per valence, in an array.
        #[arg(long)]
        json: bool,
        /// Draw the characteristic map's control net at the (single) valence ([G] Fig. 4).
        #[arg(long, requires = "output")]
        characteristic_map: bool,
        /// Output picture of --characteristic-map: `.svg` or `.png`.
        #[arg(short, long, requires = "characteristic_map")]
        output: Option<std::path::PathBuf>,
        /// Picture size in pixels, WxH.
        #[arg(long, default_value = "800x800")]
        size: String,
    },
    /// Refines a closed quad mesh (OBJ) of any topology.
    Subdivide {
        scheme: String,
        /// Number of subdivision steps.
        #[arg(long)]
        steps: usize,
        /// Input mesh (OBJ).
        input: std::path::PathBuf,
        /// Output mesh: OBJ, or PLY when the name ends in `.ply` (written whole or not at all).
        #[arg(short, long)]
        output: std::path::PathBuf,
        /// Which implementation refines (as for `curve`).
        #[arg(long, value_enum, default_value_t = PathChoice::Auto)]
        path: PathChoice,
        /// Worker threads (the result does not depend on it); default: all cores.
        #[arg(long)]
        threads: Option<usize>,
        #[command(flatten)]
        limit: MemoryLimit,
    },
    /// Times surface refinement: one JSON object per line with output vertices/s and peak RSS.
    Bench {
        /// `torus:R:C`, `cube`, `star` or an OBJ file.
        #[arg(long, default_value = "torus:256:256")]
        mesh: String,
        #[arg(long, default_value = "uniform-binary")]
        scheme: String,
        /// Steps; default: closest to 4.2 M output vertices.
        #[arg(long)]
        steps: Option<usize>,
        #[arg(long, default_value_t = 1)]
        threads: usize,
        /// `generated` or `generic`.
        #[arg(long, value_enum, default_value_t = BenchPath::Generated)]
        path: BenchPath,
        /// Positions in f32 instead of f64.
        #[arg(long)]
        f32: bool,
        /// Timed runs (median reported).
        #[arg(long, default_value_t = 5)]
        runs: usize,
        /// JSON output (the only format).
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        limit: MemoryLimit,
    },
    /// Draws a closed quad mesh to a PNG or PPM image (software, no GPU): flat, smooth,
    /// mean-curvature or reflection-line shading ([G] Fig. 6), optionally with its quad edges.
    Render(RenderArgs),
    /// Lists the shipped schemes.
    Schemes,
    /// The L-systems of a [G] §5.2 family, exactly, sorted by ρ then masks (Appendix B).
    Enumerate {
        /// lcr (eq. 44), slcr (45), lcdr (46), slcdr (47), or all.
        #[arg(long)]
        family: String,
        /// Longest π(C).
        #[arg(long, default_value_t = 3)]
        max_word_len: usize,
        /// Lift the paper's constraints on π(C) (symmetry, first and last letters; S allowed).
        #[arg(long)]
        unconstrained: bool,
        /// Keep integer ratios (Remark 5.5 leaves them out).
        #[arg(long)]
        include_integer: bool,
        /// Spline degree.
        #[arg(long, default_value_t = 3)]
        degree: usize,
        #[command(flatten)]
        out: TableArgs,
    },
    /// Searches symmetric L-systems for the Pareto front of (ρ, masks).
    Search {
        /// Alphabet size (2 to 6).
        #[arg(long)]
        symbols: usize,
        /// Longest rule (1 to 4).
        #[arg(long)]
        max_word_len: usize,
        /// Smallest ρ, exact (an integer, a fraction a/b or a decimal).
        #[arg(long)]
        rho_min: Option<String>,
        /// Largest ρ, exact.
        #[arg(long)]
        rho_max: Option<String>,
        /// Most masks (mirror pairs counted once).
        #[arg(long)]
        max_masks: Option<usize>,
        /// Keep only surface schemes ([G] §4.2: stationary and contained).
        #[arg(long)]
        require_surface: bool,
        /// Keep integer ratios.
        #[arg(long)]
        include_integer: bool,
        /// Also examine rule sets without an involution (curve schemes only).
        #[arg(long)]
        asymmetric: bool,
        /// Most rule sets examined (the whole space when smaller, else a deterministic sample).
        #[arg(long, default_value_t = 300_000)]
        limit: u64,
        /// Spline degree.
        #[arg(long, default_value_t = 3)]
        degree: usize,
        #[command(flatten)]
        out: TableArgs,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum BenchPath {
    Generated,
    Generic,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum PathChoice {
    Auto,
    Generated,
    Generic,
}

/// How `curve` and `plot` read a polygon: open or closed, its labels, the scheme's degree.
#[derive(clap::Args)]
struct PolygonArgs {
    /// The polygon is closed (cyclic).
    #[arg(long)]
    closed: bool,
    /// Interval labels (a word: m + d symbols for an open polygon of m points, m if closed);
    /// default: the axiom repeated from the first interval on.
    #[arg(long)]
    labels: Option<String>,
    /// Override the scheme's degree.
    #[arg(long)]
    degree: Option<usize>,
}

/// `--max-memory`, for the commands that refine.
#[derive(clap::Args)]
struct MemoryLimit {
    /// Refuse, before refining, a run whose predicted peak memory exceeds this: bytes, or a
    /// number with K, M, G or T (powers of 1024). Default: half of the machine's memory
    /// (`MemTotal` of /proc/meminfo; 8 GiB where that cannot be read).
    #[arg(long, value_parser = lsubdiv_cli::limits::parse_size)]
    max_memory: Option<u64>,
}

impl MemoryLimit {
    fn bytes(&self) -> u64 {
        self.max_memory
            .unwrap_or_else(lsubdiv_cli::limits::default_max_memory)
    }
}

/// Arguments of `lsubdiv render`.
#[derive(clap::Args)]
struct RenderArgs {
    /// An OBJ file, or a built-in mesh: `cube` (3-valent EVs), `star` (EVs of valence 3, 5, 9),
    /// `torus:R:C`.
    mesh: String,
    /// Output image, `.png` or `.ppm` (written whole or not at all).
    #[arg(short, long)]
    output: std::path::PathBuf,
    /// Image size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x600")]
    size: String,
    #[arg(long, value_enum, default_value_t = lsubdiv_cli::render::Shading::Smooth)]
    shading: lsubdiv_cli::render::Shading,
    /// Draw the quad edges on top.
    #[arg(long)]
    wireframe: bool,
    /// `azimuth,elevation[,distance]`: degrees about +z from +x, degrees above the xy-plane,
    /// distance in bounding-sphere radii (default 35,25 and the whole mesh in view).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "eye")]
    camera: Option<String>,
    /// Camera position `x,y,z` instead of --camera.
    #[arg(long, allow_hyphen_values = true)]
    eye: Option<String>,
    /// Point looked at from --eye, `x,y,z` (default: the centre of the bounding box).
    #[arg(long, allow_hyphen_values = true, requires = "eye")]
    target: Option<String>,
    /// Refine the mesh with this scheme first (as `subdivide` does).
    #[arg(long, requires = "steps")]
    scheme: Option<String>,
    /// Subdivision steps before drawing.
    #[arg(long, requires = "scheme")]
    steps: Option<usize>,
    /// Curvature colours span [−R, R] (default: the 98th percentile of |H| over the vertices of
    /// the faces in view).
    #[arg(long)]
    curvature_range: Option<f64>,
    /// Worker threads for the refinement; default: all cores.
    #[arg(long)]
    threads: Option<usize>,
    #[command(flatten)]
    limit: MemoryLimit,
}

/// A failure and its exit status.
struct Failure {
    code: u8,
    message: String,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure {
            code: if e.is_internal() { 1 } else { 2 },
            message: e.to_string(),
        }
    }
}

/// Output options shared by `enumerate` and `search`.
#[derive(clap::Args)]
struct TableArgs {
    /// A JSON array.
    #[arg(long, group = "format")]
    json: bool,
    /// CSV with a header.
    #[arg(long, group = "format")]
    csv: bool,
    /// A Markdown table (the default).
    #[arg(long, group = "format")]
    markdown: bool,
    /// Also write every listed system as a scheme file into this directory.
    #[arg(long)]
    emit_scheme: Option<std::path::PathBuf>,
}

impl TableArgs {
    fn format(&self) -> tables::Format {
        if self.json {
            tables::Format::Json
        } else if self.csv {
            tables::Format::Csv
        } else {
            tables::Format::Markdown
        }
    }

    /// Prints the rows and writes the scheme files.
    fn emit(&self, rows: &[lsubdiv_explorer::Row]) -> Result<(), Failure> {
        print!("{}", tables::render(rows, self.format()));
        if let Some(dir) = &self.emit_scheme {
            std::fs::create_dir_all(dir)
                .map_err(|e| bad(format!("{}: error: {e}", dir.display())))?;
            for r in rows {
                let path = dir.join(format!("{}.toml", r.ls.name));
                write_atomic(&path, lsubdiv_explorer::scheme_toml(r).as_bytes())?;
            }
        }
        Ok(())
    }
}

/// An exact rational from `3`, `7/2` or `1.45`.
fn rational(flag: &str, text: &str) -> Result<num_rational::BigRational, Failure> {
    let fail = || {
        bad(format!(
            "error: {flag} {text}: expected an integer, a fraction a/b or a decimal"
        ))
    };
    let int = |t: &str| t.trim().parse::<num_bigint::BigInt>().map_err(|_| fail());
    if let Some((a, b)) = text.split_once('/') {
        let b = int(b)?;
        if b == num_bigint::BigInt::from(0) {
            return Err(fail());
        }
        return Ok(num_rational::BigRational::new(int(a)?, b));
    }
    let (whole, frac) = text.split_once('.').unwrap_or((text, ""));
    if frac.starts_with(['-', '+']) || whole.is_empty() && frac.is_empty() {
        return Err(fail());
    }
    let digits = int(&format!("{whole}{frac}").replace("-", "").replace("+", ""))?;
    let sign = if text.trim_start().starts_with('-') {
        -1
    } else {
        1
    };
    let scale = num_bigint::BigInt::from(10).pow(frac.len() as u32);
    Ok(num_rational::BigRational::new(digits * sign, scale))
}

fn bad(message: String) -> Failure {
    Failure { code: 2, message }
}

/// Refuses, before any work, an output path that cannot be written: its folder must exist and
/// it must not be a folder itself (the write itself may still fail, leaving nothing behind).
fn check_output(path: &std::path::Path) -> Result<(), Failure> {
    let fail = |what: &str| bad(format!("{}: error: {what}", path.display()));
    if path.is_dir() {
        return Err(fail("is a directory; give a file name"));
    }
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => {
            Err(fail("no such directory to write into"))
        }
        _ => Ok(()),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Ctrl-C, SIGTERM, SIGHUP: outputs are replaced by a rename only, so an interrupted run
    // leaves the previous ones intact; remove the temporary file being written, if any.
    // (Nothing can be done on SIGKILL: a hidden `.NAME.PID.N.tmp` may then remain.)
    let _ = ctrlc::set_handler(|| {
        lsubdiv_cli::output::remove_partial_files();
        std::process::exit(130);
    });
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("{}", f.message);
            ExitCode::from(f.code)
        }
    }
}

fn load(scheme: &str, degree: Option<usize>) -> Result<Resolved, Failure> {
    let mut r = resolve(scheme)?;
    if let Some(d) = degree {
        if d == 0 || d > lsubdiv::compiler::exact::scheme::MAX_DEGREE {
            return Err(bad(format!(
                "error: --degree {d} is out of range (1 to {})",
                lsubdiv::compiler::exact::scheme::MAX_DEGREE
            )));
        }
        if d != r.ls.degree {
            r.ls.degree = d;
            r.builtin = false; // the generated tables are for the file's degree
        }
    }
    Ok(r)
}

fn build(r: &Resolved) -> Result<Scheme, Failure> {
    Ok(Scheme::build(r.ls.clone())?)
}

fn run(command: Option<Command>) -> Result<(), Failure> {
    match command {
        None => demo(),
        Some(Command::Enumerate {
            family,
            max_word_len,
            unconstrained,
            include_integer,
            degree,
            out,
        }) => {
            use lsubdiv_explorer::{enumerate, Enumeration, Family};
            let families = match family.as_str() {
                "all" => Family::ALL.to_vec(),
                f => vec![Family::parse(f).ok_or_else(|| {
                    bad(format!(
                        "error: --family {f}: expected lcr, slcr, lcdr, slcdr or all"
                    ))
                })?],
            };
            if !(1..=6).contains(&max_word_len)
                || !(1..=lsubdiv::compiler::exact::scheme::MAX_DEGREE).contains(&degree)
            {
                return Err(bad(format!("error: --max-word-len {max_word_len} must be 1 to 6 and --degree {degree} 1 to {}", lsubdiv::compiler::exact::scheme::MAX_DEGREE)));
            }
            let opts = Enumeration {
                max_word_len,
                unconstrained,
                include_integer,
                degree,
            };
            let mut rows = Vec::new();
            for f in families {
                rows.extend(enumerate(f, opts)?);
            }
            out.emit(&rows)
        }
        Some(Command::Search {
            symbols,
            max_word_len,
            rho_min,
            rho_max,
            max_masks,
            require_surface,
            include_integer,
            asymmetric,
            limit,
            degree,
            out,
        }) => {
            if !(2..=6).contains(&symbols) || !(1..=4).contains(&max_word_len) {
                return Err(bad(format!(
                    "error: --symbols {symbols} must be 2 to 6 and --max-word-len {max_word_len} 1 to 4"
                )));
            }
            if !(1..=lsubdiv::compiler::exact::scheme::MAX_DEGREE).contains(&degree) {
                return Err(bad(format!(
                    "error: --degree {degree} must be 1 to {}",
                    lsubdiv::compiler::exact::scheme::MAX_DEGREE
                )));
            }
            let opts = lsubdiv_explorer::Search {
                symbols,
                max_word_len,
                rho_min: rho_min.map(|t| rational("--rho-min", &t)).transpose()?,
                rho_max: rho_max.map(|t| rational("--rho-max", &t)).transpose()?,
                max_masks,
                require_surface,
                include_integer,
                asymmetric,
                limit,
                degree,
            };
            let bar = lsubdiv_cli::progress::bar(0, "rule sets");
            let found = lsubdiv_explorer::search(&opts, &|done, total| {
                bar.set_length(total);
                bar.set_position(done);
            })?;
            bar.finish_and_clear();
            eprintln!(
                "searched {} of {} rule sets ({}); {} distinct candidates; {} on the Pareto front",
                found.examined,
                found.space,
                if u128::from(found.examined) == found.space {
                    "all"
                } else {
                    "a deterministic sample"
                },
                found.candidates,
                found.front.len()
            );
            out.emit(&found.front)
        }
        Some(Command::Render(args)) => render(&args),
        Some(Command::Schemes) => {
            for n in lsubdiv_cli::builtin_names() {
                println!("{n}");
            }
            Ok(())
        }
        Some(Command::Inspect {
            scheme,
            degree,
            json,
        }) => {
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
            match a.invalid_error(&r.ls) {
                Some(e) => Err(e.into()),
                None => Ok(()),
            }
        }
        Some(Command::Ev {
            scheme,
            valence,
            json,
            characteristic_map,
            output,
            size,
        }) => match output {
            Some(out) if characteristic_map => charmap(&scheme, &valence, &out, &size),
            _ => ev_report(&scheme, &valence, json),
        },
        Some(Command::Subdivide {
            scheme,
            steps,
            input,
            output,
            path,
            threads,
            limit,
        }) => {
            let threads = threads.unwrap_or_else(|| {
                std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
            });
            subdivide(
                &scheme,
                steps,
                &input,
                &output,
                path,
                threads,
                limit.bytes(),
            )
        }
        Some(Command::Bench {
            mesh,
            scheme,
            steps,
            threads,
            path,
            f32,
            runs,
            limit,
            ..
        }) => bench(
            &mesh,
            &scheme,
            steps,
            threads,
            path,
            f32,
            runs,
            limit.bytes(),
        ),
        Some(Command::Graph {
            scheme,
            degree,
            svg,
            output,
            size,
            ..
        }) => graph(&scheme, degree, svg, output.as_deref(), size.as_deref()),
        Some(Command::Codegen {
            scheme,
            degree,
            output,
        }) => {
            let s = build(&load(&scheme, degree)?)?;
            write_atomic(&output, generate(&Tables::new(s)).as_bytes())?;
            Ok(())
        }
        Some(Command::Plot {
            scheme,
            steps,
            input,
            output,
            polygon,
            size,
        }) => plot(&scheme, steps, input.as_deref(), &output, polygon, &size),
        Some(Command::Curve {
            scheme,
            steps,
            input,
            output,
            polygon:
                PolygonArgs {
                    closed,
                    labels,
                    degree,
                },
            path,
            limit,
        }) => {
            check_output(&output)?;
            let r = load(&scheme, degree)?;
            let in_name = input.display().to_string();
            let stages = lsubdiv_cli::progress::Stages::new(3);
            stages.next(format!("reading {in_name}"));
            lsubdiv_cli::limits::input(&input, limit.bytes()).map_err(bad)?;
            let text = std::fs::read_to_string(&input)
                .map_err(|e| bad(format!("{in_name}: error: {e}")))?;
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
    }
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

/// `lsubdiv plot`: refines a planar polygon (a closed hexagon without input) with the generic
/// path and draws it ([`lsubdiv_cli::plot`]).
#[allow(clippy::too_many_arguments)]
fn plot(
    scheme: &str,
    steps: usize,
    input: Option<&std::path::Path>,
    output: &std::path::Path,
    polygon: PolygonArgs,
    size: &str,
) -> Result<(), Failure> {
    use lsubdiv_cli::picture;
    let PolygonArgs {
        closed,
        labels,
        degree,
    } = polygon;
    picture::format_of(output).map_err(bad)?;
    let size = picture::parse_size(size).map_err(bad)?;
    if steps > 12 {
        return Err(bad(format!(
            "error: --steps {steps}: plot draws at most 12 steps"
        )));
    }
    let r = load(scheme, degree)?;
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
    picture::save(&pic, output).map_err(bad)
}

/// `lsubdiv graph`: DOT or a picture of the transition graph, to a file or standard output.
fn graph(
    scheme: &str,
    degree: Option<usize>,
    svg: bool,
    output: Option<&std::path::Path>,
    size: Option<&str>,
) -> Result<(), Failure> {
    use lsubdiv_cli::picture;
    let size = size.map(picture::parse_size).transpose().map_err(bad)?;
    if let (true, Some(o)) = (svg, output) {
        picture::format_of(o).map_err(bad)?;
    }
    let s = build(&load(scheme, degree)?)?;
    match (svg, output) {
        (false, None) => print!("{}", report::dot(&s)),
        (false, Some(o)) => write_atomic(o, report::dot(&s).as_bytes())?,
        (true, None) => print!("{}", lsubdiv_cli::graph_picture::picture(&s, size).svg()),
        (true, Some(o)) => {
            picture::save(&lsubdiv_cli::graph_picture::picture(&s, size), o).map_err(bad)?
        }
    }
    Ok(())
}

/// Parses `n`, `a..b` or `a..=b` (both inclusive).
fn valences(text: &str) -> Result<std::ops::RangeInclusive<usize>, Failure> {
    let bad_range = || {
        bad(format!(
            "error: --valence `{text}`: expected `n` or `a..b` with 3 ≤ a ≤ b"
        ))
    };
    let parse = |s: &str| s.trim().parse::<usize>().map_err(|_| bad_range());
    let (a, b) = match text.split_once("..") {
        Some((a, b)) => (parse(a)?, parse(b.trim_start_matches('='))?),
        None => {
            let n = parse(text)?;
            (n, n)
        }
    };
    if a < 3 || b < a || b > 10_000 {
        return Err(bad_range());
    }
    Ok(a..=b)
}

/// `lsubdiv ev`: α, λ1, λ2, μ0 and the EV normalisation per valence.
fn ev_report(scheme: &str, valence: &str, json: bool) -> Result<(), Failure> {
    let range = valences(valence)?;
    let s = build(&load(scheme, None)?)?;
    let a = lsubdiv::compiler::exact::ev::analyse(&s)?;
    let c = a.coefficients_f64();
    let mut rows = Vec::new();
    for n in range {
        let sp = c.spectrum(n).map_err(|e| bad(format!("error: {e}")))?;
        rows.push(sp);
    }
    if json {
        let v: Vec<serde_json::Value> = rows
            .iter()
            .map(|sp| {
                serde_json::json!({
                    "n": sp.n, "alpha": sp.alpha, "lambda1": sp.lambda1, "lambda2": sp.lambda2,
                    "mu0": sp.mu0, "normalisation": sp.normalisation,
                })
            })
            .collect();
        println!("{}", serde_json::Value::Array(v));
    } else {
        print!("{}", report::ev_text(&s, &a, &rows));
    }
    Ok(())
}

/// `lsubdiv ev --characteristic-map`: finds the control net numerically, checks λ1 against
/// the closed form, draws it ([`lsubdiv_cli::charmap`]).
fn charmap(
    scheme: &str,
    valence: &str,
    output: &std::path::Path,
    size: &str,
) -> Result<(), Failure> {
    use lsubdiv_cli::picture;
    picture::format_of(output).map_err(bad)?;
    let size = picture::parse_size(size).map_err(bad)?;
    let range = valences(valence)?;
    let n = *range.start();
    if range.end() != range.start() {
        return Err(bad(format!(
            "error: --characteristic-map draws one valence; --valence {valence} is a range"
        )));
    }
    // The power iteration's net grows with n (about 0.4 s per valence unit in debug builds);
    // beyond this the picture's n-fold sectors are thinner than its lines anyway.
    const MAX_MAP_VALENCE: usize = 100;
    if n > MAX_MAP_VALENCE {
        return Err(bad(format!(
            "error: --characteristic-map draws valences 3 to {MAX_MAP_VALENCE}; --valence {n} is beyond"
        )));
    }
    let s = build(&load(scheme, None)?)?;
    let name = s.ls.name.clone();
    let rho = s.analysis.rho.to_f64();
    let surface = lsubdiv::generic::GenericSurface::new(s)?;
    let closed = surface
        .analysis()
        .coefficients_f64()
        .spectrum(n)
        .map_err(|e| bad(format!("error: {e}")))?
        .lambda1;
    // Refine the net until its quads are about a quarter of the net's.
    let steps = (4f64.ln() / rho.ln()).ceil().max(1.0) as usize;
    let bar = indicatif::ProgressBar::new_spinner().with_message("power iteration");
    let map = lsubdiv_cli::charmap::characteristic_map(&surface, n, steps, &|i| {
        bar.set_position(i as u64)
    })
    .map_err(bad)?;
    bar.finish_and_clear();
    println!(
        "{name}, valence {n}: lambda1 = {:.15} by power iteration on the {}-ring neighbourhood after {} steps ({} iterations, residual {:.1e}); closed form {:.15}",
        map.lambda, map.k, map.step, map.iterations, map.residual, closed
    );
    if (map.lambda - closed).abs() > 1e-9 * closed.abs() {
        return Err(Failure {
            code: 1,
            message: format!(
                "internal error: the numeric subdominant eigenvalue {} differs from the closed form {closed}",
                map.lambda
            ),
        });
    }
    picture::save(
        &lsubdiv_cli::charmap::picture(&name, &map, closed, size),
        output,
    )
    .map_err(bad)
}

/// `lsubdiv subdivide`: reads an OBJ, refines (patch path), writes OBJ or PLY atomically.
fn subdivide(
    scheme: &str,
    steps: usize,
    input: &std::path::Path,
    output: &std::path::Path,
    path: PathChoice,
    threads: usize,
    max_memory: u64,
) -> Result<(), Failure> {
    check_output(output)?;
    let r = load(scheme, None)?;
    let in_name = input.display().to_string();
    let stages = lsubdiv_cli::progress::Stages::new(3);
    stages.next(format!("reading {in_name}"));
    let (m, topology) = read_mesh(input, max_memory)?;
    stages.next(format!("refining: {steps} steps of {}", r.ls.name));
    let fine = refine_mesh(
        &r, &m, &topology, &in_name, steps, path, threads, max_memory,
    )?;
    stages.next(format!(
        "writing {} vertices, {} quads to {}",
        fine.positions.len(),
        fine.faces.len(),
        output.display()
    ));
    let bytes = if output.extension().is_some_and(|e| e == "ply") {
        lsubdiv::ply::format(&fine)
    } else {
        lsubdiv::obj::format(&fine)
    };
    write_atomic(output, bytes.as_bytes())
        .map_err(|e| bad(format!("{}: error: {e}", output.display())))?;
    Ok(())
}

/// Reads a closed quad mesh and its topology from an OBJ file (refused unread when reading it
/// could exceed `max_memory`): errors name the file's line, vertex or edge; warnings go to
/// stderr.
fn read_mesh(input: &std::path::Path, max_memory: u64) -> Result<(QuadMesh, Topology), Failure> {
    lsubdiv_cli::limits::input(input, max_memory).map_err(bad)?;
    let read = lsubdiv::read_obj(input)?;
    for w in read.warnings {
        eprintln!("{}: warning: {w}", input.display());
    }
    Ok((read.mesh, read.topology))
}

/// Refines a closed quad mesh (already validated; `name` says where it came from) by the
/// requested path, after the size guard (`--max-memory`) has accepted the prediction.
#[allow(clippy::too_many_arguments)]
fn refine_mesh(
    r: &Resolved,
    m: &QuadMesh,
    topology: &Topology,
    name: &str,
    steps: usize,
    path: PathChoice,
    threads: usize,
    max_memory: u64,
) -> Result<QuadMesh, Failure> {
    use lsubdiv::runtime::surface::{SurfaceError, SurfaceScheme, SurfaceVisitor};
    let surface = lsubdiv::generic::GenericSurface::new(build(r)?)?;
    lsubdiv_cli::limits::surface(
        &lsubdiv::CurveScheme::tables(&surface),
        surface.surface().contained_from,
        m,
        steps,
        8,
        threads,
        true,
    )
    .check(
        &format!("{steps} steps of {} on {name}", r.ls.name),
        max_memory,
    )
    .map_err(bad)?;
    let job = lsubdiv::runtime::patch::Subdivide {
        mesh: m,
        topology,
        steps,
        threads,
    };
    let generated = if path == PathChoice::Generic || !r.builtin {
        None
    } else {
        lsubdiv::generated::visit_surface(&r.ls.name, job)
    };
    let result = match (path, generated) {
        (_, Some(res)) => res,
        (PathChoice::Generated, None) => {
            return Err(bad(format!(
                "error: `{}` has no generated surface code",
                r.ls.name
            )))
        }
        (_, None) => job.visit(&surface),
    };
    result.map_err(|e| match e {
        SurfaceError::Topology(e) => bad(format!("{name}: error: {e}")),
        SurfaceError::Ev(e) => bad(format!("{name}: error: {e}")),
        e @ (SurfaceError::Axiom | SurfaceError::UnknownWord(_)) => Failure {
            code: 1,
            message: format!("internal error: {e}"),
        },
    })
}

/// `lsubdiv render`: reads or builds the mesh, refines it if asked, draws it, writes the image
/// atomically. Reports the curvature range on stderr.
fn render(a: &RenderArgs) -> Result<(), Failure> {
    use lsubdiv_cli::render::{self, camera::View, image::Format};
    let out_name = a.output.display().to_string();
    let format = Format::of(&a.output).map_err(|e| bad(format!("{out_name}: error: {e}")))?;
    let (width, height) = lsubdiv_cli::picture::parse_size(&a.size).map_err(bad)?;
    let (width, height) = (width as usize, height as usize);
    let numbers = |flag: &str, text: &str, n| {
        render::parse_numbers(flag, text, n).map_err(|e| bad(format!("error: {e}")))
    };
    let view = match (&a.camera, &a.eye) {
        (_, Some(eye)) => {
            let eye = numbers("--eye", eye, 3..=3)?;
            let target = a
                .target
                .as_deref()
                .map(|t| numbers("--target", t, 3..=3))
                .transpose()?;
            View::LookAt {
                eye: [eye[0], eye[1], eye[2]],
                target: target.map(|t| [t[0], t[1], t[2]]),
            }
        }
        (Some(c), None) => {
            let v = numbers("--camera", c, 2..=3)?;
            View::Orbit {
                azimuth: v[0],
                elevation: v[1],
                distance: v.get(2).copied(),
            }
        }
        (None, None) => View::default(),
    };
    if let Some(r) = a.curvature_range {
        if !(r > 0.0 && r.is_finite()) {
            return Err(bad(format!(
                "error: --curvature-range {r}: expected a positive number"
            )));
        }
    }
    let stages = lsubdiv_cli::progress::Stages::new(if a.scheme.is_some() { 4 } else { 3 });
    stages.next(format!("reading {}", a.mesh));
    let (mesh, topology) = if a.mesh == "cube" || a.mesh == "star" || a.mesh.starts_with("torus:") {
        lsubdiv_cli::bench::mesh(&a.mesh)?
    } else {
        read_mesh(std::path::Path::new(&a.mesh), a.limit.bytes())?
    };
    let scene_error = |e: String| bad(format!("{}: error: {e}", a.mesh));
    let (mesh, topology) = match (&a.scheme, a.steps) {
        (Some(scheme), Some(steps)) => {
            stages.next(format!("refining: {steps} steps of {scheme}"));
            let threads = a.threads.unwrap_or_else(|| {
                std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
            });
            let fine = refine_mesh(
                &load(scheme, None)?,
                &mesh,
                &topology,
                &a.mesh,
                steps,
                PathChoice::Auto,
                threads,
                a.limit.bytes(),
            )?;
            // The refined mesh's own connectivity (a closed manifold by construction).
            let t = Topology::build(&fine).map_err(|e| Failure {
                code: 1,
                message: format!("internal error: {e}"),
            })?;
            (fine, t)
        }
        _ => (mesh, topology),
    };
    stages.next(format!("drawing {} quads", mesh.faces.len()));
    let scene = render::Scene::new(&mesh, &topology).map_err(scene_error)?;
    let opts = render::Options {
        width,
        height,
        view,
        shading: a.shading,
        wireframe: a.wireframe,
        curvature_range: a.curvature_range,
    };
    let rendered = scene
        .render(&opts)
        .map_err(|e| bad(format!("error: {e}")))?;
    if let Some(r) = rendered.curvature {
        if !scene.orientable() {
            stages.note(&format!("{}: warning: the mesh is not orientable: the sign of the mean curvature flips across a seam", a.mesh));
        }
        stages.note(&format!(
            "mean curvature H in view from {:.4} to {:.4}; colours span ±{:.4} ({})",
            r.min,
            r.max,
            r.span,
            if r.percentile {
                "98th percentile of |H| over the vertices in view"
            } else {
                "--curvature-range"
            }
        ));
    }
    let bytes = rendered.image.encode(format).map_err(|e| Failure {
        code: 1,
        message: format!("internal error: {e}"),
    })?;
    stages.next(format!("writing {out_name}"));
    write_atomic(&a.output, &bytes).map_err(|e| bad(format!("{out_name}: error: {e}")))?;
    Ok(())
}

/// `lsubdiv bench`: one JSON line per configuration.
#[allow(clippy::too_many_arguments)]
fn bench(
    mesh: &str,
    scheme: &str,
    steps: Option<usize>,
    threads: usize,
    path: BenchPath,
    f32: bool,
    runs: usize,
    max_memory: u64,
) -> Result<(), Failure> {
    use lsubdiv::runtime::surface::SurfaceScheme;
    use lsubdiv_cli::bench;
    let (m, topology) = bench::mesh(mesh)?;
    let surface = bench::surface(scheme).map_err(|e| bad(format!("error: {e}")))?;
    let steps = steps.unwrap_or_else(|| bench::steps_for(&surface, &m, 4_200_000));
    let scalar = if f32 { 4 } else { 8 };
    lsubdiv_cli::limits::surface(
        &lsubdiv::CurveScheme::tables(&surface),
        surface.surface().contained_from,
        &m,
        steps,
        scalar,
        threads,
        false,
    )
    .check(&format!("{steps} steps of {scheme} on {mesh}"), max_memory)
    .map_err(bad)?;
    let p = match path {
        BenchPath::Generated => bench::Path::Generated,
        BenchPath::Generic => bench::Path::Generic,
    };
    let r = if f32 {
        bench::measure::<f32>(scheme, &surface, &m, &topology, p, threads, steps, runs)
    } else {
        bench::measure::<f64>(scheme, &surface, &m, &topology, p, threads, steps, runs)
    }
    .map_err(|e| bad(format!("error: {e}")))?;
    println!(
        "{}",
        serde_json::json!({
            "mesh": mesh, "scheme": scheme,
            "path": if p == bench::Path::Generated { "generated" } else { "generic" },
            "threads": threads, "steps": steps, "scalar": if f32 { "f32" } else { "f64" },
                        "output_vertices": r.output_vertices, "median_seconds": r.median_seconds,
            "mvps": r.mvps(), "peak_rss_bytes": bench::peak_rss_bytes(),
            "phase_seconds": {"start": r.phase_seconds[0], "ordinary": r.phase_seconds[1], "fans": r.phase_seconds[2]}, "level_seconds": r.level_seconds, "essential_bytes": r.essential_bytes,
        })
    );
    Ok(())
}

/// The default job: inspect the shipped Fibonacci scheme and refine a closed polygon with both
/// paths, checking that they agree bit for bit.
fn demo() -> Result<(), Failure> {
    let r = load("fibonacci", None)?;
    let a = analyse(&r.ls)?;
    let s = build(&r)?;
    print!("{}", report::text(&r.ls, &a, Some(&s)));
    let n = 12;
    let polygon: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            [t.cos(), t.sin(), if i % 2 == 0 { 0.25 } else { -0.25 }]
        })
        .collect();
    let generic = GenericScheme::new(s);
    let curve = Curve::with_axiom(&lsubdiv::CurveScheme::tables(&generic), polygon, true);
    let steps = 8;
    let a = lsubdiv::refine(&generic, &curve, steps).map_err(|e| bad(e.to_string()))?;
    let b = lsubdiv::generated::refine_curve(&r.ls.name, &curve, steps)
        .ok_or_else(|| bad("fibonacci is not generated".into()))?
        .map_err(|e| bad(e.to_string()))?;
    println!(
        "\nrefined a closed {n}-gon {steps} times: {} points; generic and generated paths {}",
        a.points.len(),
        if a == b {
            "agree bit for bit"
        } else {
            "DIFFER"
        }
    );
    if a != b {
        return Err(Failure {
            code: 1,
            message: "internal error: generic and generated paths differ".into(),
        });
    }
    // A surface: the cube (eight 3-valent EVs), three Binary-Ternary steps, both paths.
    let cube = lsubdiv::runtime::generators::cube();
    let surface = lsubdiv::generic::GenericSurface::new(build(&load("binary-ternary", None)?)?)?;
    let generic = lsubdiv::runtime::patch::subdivide::<_, f64>(&surface, &cube, 3, 2)
        .map_err(|e| bad(e.to_string()))?;
    let generated = lsubdiv::generated::subdivide::<f64>("binary-ternary", &cube, 3, 1)
        .ok_or_else(|| bad("binary-ternary is not generated".into()))?
        .map_err(|e| bad(e.to_string()))?;
    let same = generic == generated;
    println!(
        "refined the cube 3 times with binary-ternary: {} vertices, {} quads; generic (2 threads) and generated (1 thread) paths {}",
        generic.positions.len(),
        generic.faces.len(),
        if same { "agree bit for bit" } else { "DIFFER" }
    );
    if !same {
        return Err(Failure {
            code: 1,
            message: "internal error: generic and generated surface paths differ".into(),
        });
    }
    Ok(())
}
