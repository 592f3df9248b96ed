//! `lsubdiv subdivide`: refines a polygon mesh (closed or open, creases, corners and holes from
//! OBJ `t` tags) read from an OBJ or PLY file; the refining that `render` shares.

use crate::commands::args::{BoundaryArgs, RefineArgs};
use crate::commands::{build, check_output, load, one_stdin, threads};
use lsubdiv::compiler::Error;
use lsubdiv::mesh::facevarying::{Layout, Points, QuadUv, RefineLayout, RefineUv, UvError, UvRule};
use lsubdiv::mesh::patch::{limit_available, Refined, Subdivide};
use lsubdiv::mesh::surface::SurfaceVisitor;
use lsubdiv::mesh::QuadMesh;
use lsubdiv::mesh_file::{Checked, Extras};
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
        uv: Some(mesh.uv_rule),
        join: true,
    };
    let RefinedMesh { fine, uv, .. } = refine_mesh(&r, &mesh, &job)?;
    if let Some(note) = approximate_note(&in_name, &fine) {
        eprintln!("{note}");
    }
    stages.next(format!(
        "writing {} vertices, {} quads to {}",
        fine.mesh.positions.len(),
        fine.mesh.faces.len(),
        output.display()
    ));
    let extras = Extras {
        normals: limit.then_some(fine.normals.as_slice()),
        uv: uv.as_ref(),
    };
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
    /// Whether to refine the input's texture coordinates, and by which rule (the one they
    /// were read with).
    pub uv: Option<UvRule>,
    /// Whether the refined copies of a non-manifold mesh's points are joined (a file's
    /// vertices, as OpenSubdiv's), or kept apart (each fan its own 2-manifold, for drawing).
    pub join: bool,
}

/// Whether [`refine_mesh`] takes the vertices to the limit surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// The refined control points.
    Off,
    /// The limit surface, or the runtime's refusal as the error.
    On,
    /// The limit surface where the runtime has it; where it refuses it (too few steps for the
    /// EVs' limit, a semi-sharp feature still sharp: `patch::limit_available`, asked before
    /// refining) the refined control points.
    IfAvailable,
}

/// Refines a mesh (read and checked, with its features) by the picked implementation, after the size guard
/// (`--max-memory`) has accepted the prediction. A mesh that had faces other than quads was
/// read as its first step (one Catmull–Clark step, `lsubdiv::mesh::polygon`): the scheme
/// takes the other steps, and it needs at least one.
pub fn refine_mesh(r: &Resolved, input: &Checked, job: &MeshJob<'_>) -> Result<RefinedMesh, Error> {
    use lsubdiv::mesh::surface::{SurfaceError, SurfaceScheme};
    let MeshJob {
        name,
        steps,
        threads,
        ..
    } = *job;
    let (m, topology) = (&input.mesh, &input.topology);
    let steps = match (input.split, steps) {
        (false, s) => s,
        (true, 0) => {
            return Err(Error::in_file(
                name,
                "the mesh has faces that are not quads: its first step is a Catmull–Clark step, so it takes at least one step",
            )
            .with_hint("use --steps 1 or more"))
        }
        (true, s) => s - 1,
    };
    let surface = lsubdiv::generic::GenericSurface::new(build(r)?)?;
    let tables = lsubdiv::CurveScheme::tables(&surface);
    let contained_from = surface.surface().contained_from;
    let points = Points(input.weld.as_ref().map_or(&[], |w| w.points()));
    let what = steps_of(steps, input.split, &r.ls.name, name);
    let positions = lsubdiv_cli::limits::surface(
        &tables,
        contained_from,
        topology,
        &input.features,
        steps,
        8,
        threads,
    )
    .holding(lsubdiv_cli::scale::copy_bytes(
        &m.positions,
        16 * m.faces.len() as u128,
    ))
    .with_extras(
        job.limit != Limit::Off,
        input.uv.is_some() && job.uv.is_some(),
    );
    // A texture layout refined by a smooth rule is a mesh of its own, refined after the
    // positions: what building it holds is counted before it is built, what refining it
    // holds from its topology and features.
    // It is built once, here, and refined after the positions.
    let uv_error = |e: UvError| {
        let error = Error::in_file(name, format!("texture coordinates: {e}"));
        match e {
            UvError::Layout(_) => error.with_hint("use --uv linear"),
            _ => error,
        }
    };
    let (layout, layout_bytes) = match (&input.uv, job.uv) {
        (Some(uv), Some(rule)) if rule.is_smooth() => {
            let building = lsubdiv_cli::limits::layout_building(m.faces.len());
            positions.holding(building).check(&what, job.max_memory)?;
            let layout = Layout::new(m, &input.features, uv, rule, points).map_err(uv_error)?;
            let (lt, lf) = (&layout.topology, &layout.features);
            let bytes =
                lsubdiv_cli::limits::layout(&tables, contained_from, lt, lf, steps, threads);
            (Some(layout), bytes)
        }
        _ => (None, 0),
    };
    positions
        .holding(layout_bytes)
        .check(&what, job.max_memory)?;
    let implementation = job.path.pick(r, Geometry::Surface)?;
    let error = |e: SurfaceError| surface_error(name, input.split, e, REFUSED_HINT);
    // Whether the limit is available, before refining: refused, or left out where it is only
    // wanted if available.
    let available = || match limit_available(&surface, topology, &input.features, steps) {
        Err(SurfaceError::Unsupported(why)) => Err(why),
        // Anything else the refinement itself reports.
        _ => Ok(()),
    };
    let (limit, refused) = match job.limit {
        Limit::Off => (false, None),
        Limit::On => {
            available().map_err(|why| {
                let hint = "take the steps it names, or leave out --limit";
                surface_error(name, input.split, SurfaceError::Unsupported(why), hint)
            })?;
            (true, None)
        }
        Limit::IfAvailable => match available() {
            Ok(()) => (true, None),
            Err(why) => (false, Some(why)),
        },
    };
    // Huge or tiny coordinates are refined scaled to magnitude 1 (`lsubdiv_cli::scale`).
    let (rest, positions) = lsubdiv_cli::scale::refine_scaled(name, &m.positions, |scaled| {
        let scaled = scaled.map(|positions| QuadMesh {
            positions,
            faces: m.faces.clone(),
        });
        let mesh = scaled.as_ref().unwrap_or(m);
        let run = |limit: bool| {
            let refine = Subdivide {
                mesh,
                topology,
                features: &input.features,
                steps,
                threads,
                limit,
            };
            visit(r, implementation, &surface, refine)
        };
        let fine = run(limit)?.map_err(error)?;
        let Refined {
            mesh,
            normals,
            approximate,
        } = fine;
        Ok(((mesh.faces, normals, approximate, refused), mesh.positions))
    })?;
    let (faces, normals, approximate, refused) = rest;
    // The texture coordinates (which do not scale) by the rule they were read with, to the
    // layout's limit where the positions went to theirs.
    let limit = !normals.is_empty();
    let uv = match (&input.uv, job.uv, &layout) {
        (_, _, Some(layout)) => {
            let job = RefineLayout {
                layout,
                limit,
                steps,
                threads,
            };
            Some(visit(r, implementation, &surface, job)?.map_err(uv_error)?)
        }
        (Some(uv), Some(rule), None) => {
            let job = RefineUv {
                mesh: m,
                topology,
                features: &input.features,
                uv,
                points,
                rule: (rule, limit),
                steps,
                threads,
            };
            Some(visit(r, implementation, &surface, job)?.map_err(uv_error)?)
        }
        _ => None,
    };
    let fine = Refined {
        mesh: QuadMesh { positions, faces },
        normals,
        approximate,
    };
    // A mesh that was not a 2-manifold: the refined copies of each point joined again.
    let fine = match &input.weld {
        Some(weld) if job.join => weld.apply(&m.faces, &input.features.holes, fine),
        _ => fine,
    };
    Ok(RefinedMesh { fine, uv, refused })
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

/// The diagnostic for a refinement of the mesh `name` refused or failed by the runtime; `split`:
/// the mesh had faces other than quads, so its first step came before the scheme's; `hint`: the
/// hint of a refusal.
fn surface_error(
    name: &str,
    split: bool,
    e: lsubdiv::mesh::surface::SurfaceError,
    hint: &str,
) -> Error {
    use lsubdiv::mesh::surface::SurfaceError;
    match e {
        SurfaceError::Topology(e) => Error::in_file(name, e.to_string())
            .with_hint("the refined mesh must be a 2-manifold: see docs/real-meshes.md"),
        SurfaceError::Ev(e) => Error::in_file(name, e.to_string())
            .with_hint("valences and schemes supported: `lsubdiv ev SCHEME --valence N`"),
        SurfaceError::Features(e) => Error::in_file(name, e.to_string())
            .with_hint("check the file's `t crease`, `t corner` and `t hole` tags"),
        // The runtime counts the scheme's steps; a polygon mesh's first step came before.
        SurfaceError::Unsupported(m) if split => Error::in_file(
            name,
            format!(
                "{m} (steps of the scheme: --steps counts one more, the first Catmull–Clark step)"
            ),
        )
        .with_hint(hint),
        SurfaceError::Unsupported(m) => Error::in_file(name, m).with_hint(hint),
        e @ (SurfaceError::Axiom | SurfaceError::UnknownWord(_)) => {
            Error::internal(None, e.to_string())
        }
    }
}

/// The hint of a refinement the runtime refuses.
const REFUSED_HINT: &str = "docs/real-meshes.md lists, per feature, what each scheme refines";

/// What [`refine_mesh`] gives.
pub struct RefinedMesh {
    /// The refined mesh, on the limit surface with normals if asked.
    pub fine: Refined,
    /// Its texture coordinates, if the input had some and the job asked for them.
    pub uv: Option<QuadUv>,
    /// With [`Limit::IfAvailable`], the reason the limit was refused, if it was.
    pub refused: Option<String>,
}

/// Runs `job` on the scheme by the picked implementation: the generated registry's, or the
/// dynamic path's `surface`.
fn visit<V: SurfaceVisitor>(
    r: &Resolved,
    implementation: Implementation,
    surface: &lsubdiv::generic::GenericSurface,
    job: V,
) -> Result<V::Output, Error> {
    match implementation {
        Implementation::Generated => {
            lsubdiv::generated::visit_surface(&r.ls.name, job).ok_or_else(|| {
                Error::internal(None, format!("`{}` is not in the registry", r.ls.name))
            })
        }
        Implementation::Generic => Ok(job.visit(surface)),
    }
}
