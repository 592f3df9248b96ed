//! `lsubdiv subdivide`: refines a closed quad mesh read from an OBJ file; the mesh reading and
//! refining that `render` shares.

use crate::commands::args::{MemoryLimit, PathChoice};
use crate::commands::{bad, build, check_output, load, Failure};
use lsubdiv_cli::output::write_atomic;
use lsubdiv_cli::Resolved;

/// Arguments of `lsubdiv subdivide`.
#[derive(clap::Args)]
pub struct SubdivideArgs {
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
}

/// Reads, refines, writes.
pub fn run(a: SubdivideArgs) -> Result<(), Failure> {
    let threads = a.threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    subdivide(
        &a.scheme,
        a.steps,
        &a.input,
        &a.output,
        a.path,
        threads,
        a.limit.bytes(),
    )
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
    use lsubdiv::runtime::mesh;
    check_output(output)?;
    let r = load(scheme, None)?;
    let in_name = input.display().to_string();
    let stages = lsubdiv_cli::progress::Stages::new(3);
    stages.next(format!("reading {in_name}"));
    let m = read_mesh(input, max_memory)?;
    stages.next(format!("refining: {steps} steps of {}", r.ls.name));
    let fine = refine_mesh(&r, &m, &in_name, steps, path, threads, max_memory)?;
    stages.next(format!(
        "writing {} vertices, {} quads to {}",
        fine.positions.len(),
        fine.faces.len(),
        output.display()
    ));
    let bytes = if output.extension().is_some_and(|e| e == "ply") {
        mesh::to_ply(&fine)
    } else {
        mesh::to_obj(&fine)
    };
    write_atomic(output, bytes.as_bytes())
        .map_err(|e| bad(format!("{}: error: {e}", output.display())))?;
    Ok(())
}

/// Reads a closed quad mesh from an OBJ file (refused unread when reading it could exceed
/// `max_memory`): errors name the file's line, vertex or edge; warnings go to stderr.
pub fn read_mesh(
    input: &std::path::Path,
    max_memory: u64,
) -> Result<lsubdiv::runtime::mesh::QuadMesh, Failure> {
    lsubdiv_cli::limits::input(input, max_memory).map_err(bad)?;
    let (m, warnings) = lsubdiv::read_obj(input).map_err(bad)?;
    for w in warnings {
        eprintln!("{}: warning: {w}", input.display());
    }
    Ok(m)
}

/// Refines a closed quad mesh (already validated; `name` says where it came from) by the
/// requested path, after the size guard (`--max-memory`) has accepted the prediction.
pub fn refine_mesh(
    r: &Resolved,
    m: &lsubdiv::runtime::mesh::QuadMesh,
    name: &str,
    steps: usize,
    path: PathChoice,
    threads: usize,
    max_memory: u64,
) -> Result<lsubdiv::runtime::mesh::QuadMesh, Failure> {
    use lsubdiv::runtime::surface::{SurfaceError, SurfaceScheme};
    let surface = lsubdiv::compiler::exact::generic::GenericSurface::new(build(r)?)?;
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
    let generated = if path == PathChoice::Generic || !r.builtin {
        None
    } else {
        lsubdiv::generated::subdivide::<f64>(&r.ls.name, m, steps, threads)
    };
    let result = match (path, generated) {
        (_, Some(res)) => res,
        (PathChoice::Generated, None) => {
            return Err(bad(format!(
                "error: `{}` has no generated surface code",
                r.ls.name
            )))
        }
        (_, None) => lsubdiv::runtime::patch::subdivide::<_, f64>(&surface, m, steps, threads),
    };
    let fine = result.map_err(|e| match e {
        SurfaceError::Mesh(e) => bad(format!("{name}: error: {e}")),
        SurfaceError::Ev(e) => bad(format!("{name}: error: {e}")),
        e @ (SurfaceError::Axiom | SurfaceError::UnknownWord(_)) => Failure {
            code: 1,
            message: format!("internal error: {e}"),
        },
    })?;
    Ok(lsubdiv::runtime::mesh::QuadMesh {
        positions: fine.positions,
        faces: fine.faces,
    })
}
