//! `lsubdiv subdivide`: refines a polygon mesh (closed or open, creases, corners and holes from
//! OBJ `t` tags) read from an OBJ or PLY file; the refining that `render` shares.

use crate::commands::args::{BoundaryArgs, RefineArgs};
use crate::commands::{build, check_output, load, one_stdin, threads};
use lsubdiv::compiler::Error;
use lsubdiv::mesh::facevarying::UvRule;
use lsubdiv::mesh_file::Checked;
pub use lsubdiv::Limit;
use lsubdiv::{Options, Plan, Refined, Scheme};
use lsubdiv_cli::implementation::{Geometry, Implementation, PathChoice};
use lsubdiv_cli::output::{format_by_extension, registered};
use lsubdiv_cli::Resolved;

/// Arguments of `lsubdiv subdivide`.
#[derive(clap::Args)]
pub struct SubdivideArgs {
    #[command(flatten)]
    refine: RefineArgs,
    /// Input mesh: OBJ or PLY (ASCII or binary), told apart by content; `-` for standard input.
    input: std::path::PathBuf,
    /// Output mesh, in the format `--format` names, else its extension's (`.obj` or `.ply`, any
    /// case; another is refused), else, for a name without one, the input's (`-`: standard
    /// output; a device or FIFO such as `/dev/null` is written, never replaced). Written whole
    /// or not at all.
    #[arg(short, long)]
    output: std::path::PathBuf,
    /// The output's format; default: the output's extension, else the input's format.
    #[arg(long, value_enum)]
    format: Option<MeshFormat>,
    /// Worker threads (the result does not depend on it); default: all cores.
    #[arg(long, value_parser = crate::commands::args::thread_count)]
    threads: Option<usize>,
    #[command(flatten)]
    boundary: BoundaryArgs,
    /// Every output vertex moved to its point on the limit surface, with the limit normal
    /// there (OBJ `vn` and faces `v//vn`; PLY `nx ny nz`), in the vertices' order.
    #[arg(long)]
    limit: bool,
    /// How texture coordinates (OBJ `vt`, PLY `u v`) are refined, OpenSubdiv's face-varying
    /// modes: `linear` (alias `all`), bilinear in each base face at the refined vertices'
    /// knots (FVAR_LINEAR_ALL); `smooth` (alias `none`), the scheme applied to the texture
    /// layout, its seams edge-only boundaries (FVAR_LINEAR_NONE); `corners-only`,
    /// `corners-plus1`, `corners-plus2`, `boundaries`: as smooth, with more values kept as
    /// corners (FVAR_LINEAR_CORNERS_ONLY, _PLUS1, _PLUS2, _BOUNDARIES). Default: the file's
    /// `t facevaryinginterpolateboundary`, else `linear`.
    #[arg(long, value_enum)]
    uv: Option<UvArg>,
    /// Binary PLY (little-endian doubles and `uint` indices) instead of ASCII: about a third of
    /// the size, written several times faster; `.ply` output only.
    #[arg(long)]
    binary: bool,
}

/// `--uv`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum UvArg {
    #[value(alias = "all")]
    Linear,
    #[value(alias = "none")]
    Smooth,
    CornersOnly,
    CornersPlus1,
    CornersPlus2,
    Boundaries,
}

impl UvArg {
    fn rule(self) -> UvRule {
        match self {
            UvArg::Linear => UvRule::Linear,
            UvArg::Smooth => UvRule::Smooth,
            UvArg::CornersOnly => UvRule::CornersOnly,
            UvArg::CornersPlus1 => UvRule::CornersPlus1,
            UvArg::CornersPlus2 => UvRule::CornersPlus2,
            UvArg::Boundaries => UvRule::Boundaries,
        }
    }
}

/// The output formats of `subdivide`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum MeshFormat {
    /// Wavefront OBJ.
    Obj,
    /// PLY (ASCII, or binary with `--binary`).
    Ply,
}

impl MeshFormat {
    /// The format `--format` names, else `output`'s extension's; `None` (the input's) for a
    /// name without an extension (`-`, `/dev/null`, `out`). Another extension is refused.
    fn named(
        flag: Option<MeshFormat>,
        output: &std::path::Path,
    ) -> Result<Option<MeshFormat>, Error> {
        if flag.is_some() || lsubdiv_cli::output::extension(output).is_none() {
            return Ok(flag);
        }
        let formats = [("obj", MeshFormat::Obj), ("ply", MeshFormat::Ply)];
        format_by_extension(output, "mesh", &formats)
            .map(Some)
            .map_err(|e| e.with_hint("add --format obj or --format ply to write it anyway"))
    }

    /// The input's format.
    fn of(input: lsubdiv::mesh_file::Format) -> MeshFormat {
        match input {
            lsubdiv::mesh_file::Format::Obj => MeshFormat::Obj,
            lsubdiv::mesh_file::Format::Ply => MeshFormat::Ply,
        }
    }

    /// Refuses `--binary` for OBJ (`None`: not known yet).
    fn check_binary(
        format: Option<MeshFormat>,
        binary: bool,
        output: &std::path::Path,
    ) -> Result<(), Error> {
        if binary && matches!(format, Some(MeshFormat::Obj)) {
            return Err(Error::in_file(
                output.display(),
                "--binary: the output is OBJ, a text format",
            )
            .with_hint("name a `.ply` output, or add --format ply"));
        }
        Ok(())
    }
}

/// Reads an OBJ or PLY, refines it (patch path), writes OBJ or PLY atomically.
pub fn run(a: SubdivideArgs) -> Result<(), Error> {
    let SubdivideArgs {
        refine,
        input,
        output,
        threads: t,
        boundary,
        limit,
        uv,
        binary,
        format,
    } = a;
    check_output(&output)?;
    one_stdin(&[
        ("scheme", std::path::Path::new(&refine.scheme)),
        ("mesh", &input),
    ])?;
    let named = MeshFormat::named(format, &output)?;
    MeshFormat::check_binary(named, binary, &output)?;
    let r = load(&refine.scheme, None)?;
    let in_name = input.display().to_string();
    let stages = lsubdiv_cli::progress::Stages::new(3);
    stages.next(format!("reading {in_name}"));
    let (mesh, input_format) = lsubdiv_cli::limits::read_mesh(
        &input,
        refine.limit.bytes(),
        boundary.rule(),
        uv.map(UvArg::rule),
    )?;
    let format = named.unwrap_or(MeshFormat::of(input_format));
    MeshFormat::check_binary(Some(format), binary, &output)?;
    let steps = refine.steps;
    stages.next(format!("refining: {steps} steps of {}", r.ls.name));
    let job = MeshJob {
        name: &in_name,
        steps,
        path: refine.path,
        threads: threads(t),
        max_memory: refine.limit.bytes(),
        limit: if limit { Limit::On } else { Limit::Off },
        uv: true,
        join: true,
    };
    let fine = refine_mesh(&r, mesh, &job)?;
    if let Some(note) = approximate_note(&in_name, &fine) {
        eprintln!("{note}");
    }
    stages.next(format!(
        "writing {} vertices, {} quads to {}",
        fine.mesh.positions.len(),
        fine.mesh.faces.len(),
        output.display()
    ));
    let extras = fine.extras();
    // Checked first, then streamed to the file: the text is never held whole in memory.
    let mesh = &fine.mesh;
    registered(&output, || match format {
        MeshFormat::Obj => lsubdiv::obj::write_with(&output, mesh, extras),
        MeshFormat::Ply => lsubdiv::ply::write_with(&output, mesh, extras, binary),
    })
}

/// The note for a limit with vertices not derived in closed form, if it has any.
pub fn approximate_note(name: &str, fine: &Refined) -> Option<String> {
    (!fine.approximate.is_empty()).then(|| format!(
        "{name}: note: {} vertices have no derived limit normal (darts, creases with a sector other than two faces, corners with a sector of more than one face, interior vertices of valence 2): theirs is the mean of their limit 1-ring faces' (a dart's limit point is the smooth rule's, as OpenSubdiv's; docs/surfaces.md)",
        fine.approximate.len()
    ))
}

/// How `subdivide` and `render` refine a mesh.
pub struct MeshJob<'a> {
    /// Where the mesh came from (a file or a built-in mesh), for messages.
    pub name: &'a str,
    pub steps: usize,
    pub path: PathChoice,
    pub threads: usize,
    pub max_memory: u64,
    /// Whether to take the vertices to the limit surface, with normals.
    pub limit: Limit,
    /// Whether to refine the input's texture coordinates (by the rule they were read with).
    pub uv: bool,
    /// Whether the refined copies of a non-manifold mesh's points are joined (a file's
    /// vertices, as OpenSubdiv's), or kept apart (each fan its own 2-manifold, for drawing).
    pub join: bool,
}

/// Refines a mesh (read and checked, with its features) through the library's plan
/// (`lsubdiv::Plan`), by the picked implementation, after the size guard (`--max-memory`) has
/// accepted the prediction. A mesh that had faces other than quads was read as its first step
/// (one Catmull–Clark step, `lsubdiv::mesh::polygon`): the scheme takes the other steps, and
/// it needs at least one.
pub fn refine_mesh(r: &Resolved, input: Checked, job: &MeshJob<'_>) -> Result<Refined, Error> {
    let MeshJob {
        name,
        steps,
        threads,
        ..
    } = *job;
    let error = |e| cli_error(name, e);
    let steps_of_scheme = Plan::scheme_steps(name, &input, steps).map_err(error)?;
    // A shipped scheme on the generated path runs no exact computation: its tables are
    // compiled in.
    let scheme = match job.path.pick(r, Geometry::Surface)? {
        Implementation::Generated => Scheme::shipped(&r.ls.name),
        Implementation::Generic => Scheme::from_exact(build(r)?),
    }
    .map_err(error)?;
    let tables = lsubdiv::CurveScheme::tables(&scheme);
    let contained_from = scheme.contained_from().map_err(error)?;
    let what = steps_of(steps_of_scheme, input.split, &r.ls.name, name);
    let m = &input.mesh;
    let positions = lsubdiv_cli::limits::surface(
        &tables,
        contained_from,
        &input.topology,
        &input.features,
        steps_of_scheme,
        8,
        threads,
    )
    .holding(lsubdiv::scale::copy_bytes(
        &m.positions,
        16 * m.faces.len() as u128,
    ))
    .with_extras(job.limit != Limit::Off, input.uv.is_some() && job.uv);
    // A texture layout refined by a smooth rule is a mesh of its own, built by the plan: what
    // building it holds is counted before it is built, what refining it holds from its
    // topology and features.
    if input.uv.is_some() && job.uv && input.uv_rule.is_smooth() {
        let building = lsubdiv_cli::limits::layout_building(m.faces.len());
        positions.holding(building).check(&what, job.max_memory)?;
    }
    let options = Options {
        steps,
        threads,
        boundary: None,
        uv_rule: None,
        uv: job.uv,
        limit: job.limit,
        join: job.join,
    };
    let plan = Plan::new(&scheme, name, input, options).map_err(error)?;
    let layout_bytes = plan.layout().map_or(0, |layout| {
        let (lt, lf) = (&layout.topology, &layout.features);
        lsubdiv_cli::limits::layout(&tables, contained_from, lt, lf, steps_of_scheme, threads)
    });
    positions
        .holding(layout_bytes)
        .check(&what, job.max_memory)?;
    plan.refine().map_err(error)
}

/// The command line's diagnostic for the library's error about the mesh `name`: the same
/// message, with a hint that names the flags.
fn cli_error(name: &str, e: lsubdiv::Error) -> Error {
    use lsubdiv::mesh::facevarying::UvError;
    use lsubdiv::mesh::surface::SurfaceError;
    // The library's note on how steps count, in the flag's words.
    let with_note = |m: String, note: Option<String>| match note {
        Some(_) => format!(
            "{m} (steps of the scheme: --steps counts one more, the first Catmull–Clark step)"
        ),
        None => m,
    };
    match e {
        lsubdiv::Error::File(d) | lsubdiv::Error::Scheme(d) => d,
        lsubdiv::Error::CurvesOnly { why, .. } => *why,
        lsubdiv::Error::NoSteps { .. } => {
            Error::in_file(name, lsubdiv::Error::NO_STEPS).with_hint("use --steps 1 or more")
        }
        lsubdiv::Error::NoLimit { why, note, .. } => Error::in_file(name, with_note(why, note))
            .with_hint("take the steps it names, or leave out --limit"),
        lsubdiv::Error::Uv { error, .. } => {
            let hint = matches!(error, UvError::Layout(_));
            let e = Error::in_file(name, format!("texture coordinates: {error}"));
            if hint {
                e.with_hint("use --uv linear")
            } else {
                e
            }
        }
        lsubdiv::Error::Refine { error, note, .. } => match error {
            SurfaceError::Topology(e) => Error::in_file(name, e.to_string())
                .with_hint("the refined mesh must be a 2-manifold: see docs/real-meshes.md"),
            SurfaceError::Ev(e) => Error::in_file(name, e.to_string())
                .with_hint("valences and schemes supported: `lsubdiv ev SCHEME --valence N`"),
            SurfaceError::Features(e) => Error::in_file(name, e.to_string())
                .with_hint("check the file's `t crease`, `t corner` and `t hole` tags"),
            SurfaceError::Unsupported(m) => Error::in_file(name, with_note(m, note))
                .with_hint("docs/real-meshes.md lists, per feature, what each scheme refines"),
            e @ (SurfaceError::Axiom | SurfaceError::UnknownWord(_)) => {
                Error::internal(None, e.to_string())
            }
        },
        e => Error::internal(None, e.to_string()),
    }
}

/// What refining the mesh `name` by `steps` steps of `scheme` is, for messages; `split`: after
/// the first step, a Catmull–Clark step counted apart (`--steps` is one more).
fn steps_of(steps: usize, split: bool, scheme: &str, name: &str) -> String {
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    if split {
        format!(
            "{steps} step{} of {scheme} after the first, Catmull–Clark step (--steps {}) on {name}",
            plural(steps),
            steps + 1
        )
    } else {
        format!("{steps} step{} of {scheme} on {name}", plural(steps))
    }
}
