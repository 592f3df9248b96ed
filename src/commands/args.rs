//! Arguments shared by several commands.

use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericScheme;
use lsubdiv::points::Points;
use lsubdiv::Curve;
use lsubdiv_cli::implementation::PathChoice;
use lsubdiv_cli::output::write_atomic;
use lsubdiv_cli::{tables, Resolved};

/// What `curve` and `subdivide` share: the scheme, the steps, the implementation and the size
/// guard.
#[derive(clap::Args)]
pub struct RefineArgs {
    pub scheme: String,
    /// Number of subdivision steps.
    #[arg(long)]
    pub steps: usize,
    /// Which implementation refines: the generated kernels of a shipped scheme, the generic
    /// table-driven path, or `auto` (generated when available).
    #[arg(long, value_enum, default_value_t = PathChoice::Auto)]
    pub path: PathChoice,
    #[command(flatten)]
    pub limit: MemoryLimit,
}

/// How `curve` and `plot` read a polygon: open or closed, its labels, the scheme's degree.
#[derive(clap::Args)]
pub struct PolygonArgs {
    /// The polygon is closed (cyclic).
    #[arg(long)]
    pub closed: bool,
    /// Interval labels (a word: m + d symbols for an open polygon of m points, m if closed);
    /// default: the axiom repeated from the first interval on.
    #[arg(long)]
    pub labels: Option<String>,
    /// Override the scheme's degree.
    #[arg(long)]
    pub degree: Option<usize>,
}

/// `--boundary`: how boundary vertices with one face are refined (OpenSubdiv's
/// `VtxBoundaryInterpolation`, see `lsubdiv::mesh::features::Boundary`).
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum BoundaryArg {
    /// Boundary edges sharp, vertices with one face interpolated corners (USD's default).
    EdgeAndCorner,
    /// Boundary edges sharp, vertices with one face smooth.
    EdgeOnly,
    /// The faces at the boundary are holes (not written), the rest refined edge-only
    /// (OpenSubdiv's VTX_BOUNDARY_NONE).
    None,
}

/// `--boundary`, for the commands that read meshes.
#[derive(clap::Args)]
pub struct BoundaryArgs {
    /// Boundary rule: boundary vertices with one face are interpolated corners
    /// (`edge-and-corner`) or smooth (`edge-only`), or the boundary faces are dropped
    /// (`none`). Default: the file's `t interpolateboundary` tag, else edge-and-corner.
    #[arg(long, value_enum)]
    pub boundary: Option<BoundaryArg>,
}

impl BoundaryArgs {
    /// The rule asked for, if any.
    pub fn rule(&self) -> Option<lsubdiv::mesh::features::Boundary> {
        self.boundary.map(BoundaryArg::rule)
    }
}

impl BoundaryArg {
    /// The runtime's boundary rule.
    pub fn rule(self) -> lsubdiv::mesh::features::Boundary {
        match self {
            BoundaryArg::EdgeAndCorner => lsubdiv::mesh::features::Boundary::EdgeAndCorner,
            BoundaryArg::EdgeOnly => lsubdiv::mesh::features::Boundary::EdgeOnly,
            BoundaryArg::None => lsubdiv::mesh::features::Boundary::None,
        }
    }
}

/// `--max-memory`, for the commands that refine.
#[derive(clap::Args)]
pub struct MemoryLimit {
    /// Refuse, before refining, a run whose predicted peak memory exceeds this: bytes, or a
    /// number with K, M, G or T (powers of 1024). Default: half of the machine's memory
    /// (`MemTotal` of /proc/meminfo; 8 GiB where that cannot be read).
    #[arg(long, value_parser = lsubdiv_cli::limits::parse_size)]
    pub max_memory: Option<u64>,
}

impl MemoryLimit {
    pub fn bytes(&self) -> u64 {
        self.max_memory
            .unwrap_or_else(lsubdiv_cli::limits::default_max_memory)
    }
}

/// Output options shared by `enumerate` and `search`.
#[derive(clap::Args)]
pub struct TableArgs {
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
    pub emit_scheme: Option<std::path::PathBuf>,
}

impl TableArgs {
    pub fn format(&self) -> tables::Format {
        if self.json {
            tables::Format::Json
        } else if self.csv {
            tables::Format::Csv
        } else {
            tables::Format::Markdown
        }
    }

    /// Prints the rows and writes the scheme files.
    pub fn emit(&self, rows: &[lsubdiv_explorer::Row]) -> Result<(), Error> {
        if let Some(dir) = &self.emit_scheme {
            if dir.exists() && !dir.is_dir() {
                return Err(Error::in_file(dir.display(), "--emit-scheme: not a folder")
                    .with_hint("name a folder (it is made if missing)"));
            }
        }
        print!("{}", tables::render(rows, self.format()));
        if let Some(dir) = &self.emit_scheme {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, &e))?;
            for r in rows {
                let path = dir.join(format!("{}.toml", r.ls.name));
                write_atomic(&path, lsubdiv_explorer::scheme_toml(r).as_bytes())?;
            }
        }
        Ok(())
    }
}

/// The control polygon of `points` for `generic` (the scheme `r`), labelled by `--labels` or,
/// by default, the axiom repeated.
pub fn polygon<const D: usize>(
    r: &Resolved,
    generic: &GenericScheme,
    points: Vec<[f64; D]>,
    closed: bool,
    labels: Option<&str>,
) -> Result<Curve<D>, Error> {
    let mut curve = Curve::with_axiom(&lsubdiv::CurveScheme::tables(generic), points, closed);
    if let Some(l) = labels {
        curve.labels =
            r.ls.parse_word(l)
                .map_err(|e| Error::input(format!("--labels: {e}")))?;
    }
    Ok(curve)
}

/// Reads a points file (2 or 3 coordinates per line) under `--max-memory` `max`
/// ([`lsubdiv_cli::limits::read_input`]).
pub fn read_points(path: &std::path::Path, max: u64) -> Result<Points, Error> {
    let (path, bytes) = lsubdiv_cli::limits::read_input(path, max)?;
    lsubdiv::points::parse(&path.display().to_string(), &lsubdiv::compiler::text(bytes))
}

/// Most worker threads a command accepts: each holds its own buffers, so a number far beyond
/// any machine's cores only exhausts memory.
pub const MAX_THREADS: usize = 1024;

/// `--threads N`: 1 to [`MAX_THREADS`] (clap reports the error, exit status 2).
pub fn thread_count(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if (1..=MAX_THREADS).contains(&n) => Ok(n),
        _ => Err(format!("expected 1 to {MAX_THREADS} worker threads")),
    }
}
