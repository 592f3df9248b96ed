//! `lsubdiv bench`: times surface refinement ([`lsubdiv_cli::bench`]).

use crate::commands::args::{BoundaryArgs, MemoryLimit};
use crate::commands::{build, load, one_stdin};
use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericSurface;
use lsubdiv::mesh::patch::Simd;
use lsubdiv::mesh::surface::SurfaceScheme;
use lsubdiv_cli::implementation::{Geometry, PathChoice};
use lsubdiv_cli::{bench, limits};

/// Arguments of `lsubdiv bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// `torus:R:C` (`torus:R:C:x`: its faces ordered along x, as a row-major grid), `cube`,
    /// `grid-cube:K` (each face a K × K grid), `star`, `prism:N` (n-gon caps), `icosphere:L`
    /// (triangles), open `grid`, `tube`, `hole`, `pentagon-star`, `creased-cube`, or an OBJ or
    /// PLY file.
    #[arg(long, default_value = "torus:256:256")]
    mesh: String,
    #[arg(long, default_value = "uniform-binary")]
    scheme: String,
    /// Steps; default: closest to 4.2 M output vertices.
    #[arg(long)]
    steps: Option<usize>,
    #[arg(long, default_value_t = 1, value_parser = crate::commands::args::thread_count)]
    threads: usize,
    /// Which implementation refines (`auto`: generated when available).
    #[arg(long, value_enum, default_value_t = PathChoice::Generated)]
    path: PathChoice,
    /// Positions in f32 instead of f64.
    #[arg(long)]
    f32: bool,
    /// Timed runs (median reported).
    #[arg(long, default_value_t = 5)]
    runs: usize,
    /// Instruction set of the kernels (default: the widest this CPU has).
    #[arg(long, value_enum)]
    simd: Option<SimdArg>,
    #[command(flatten)]
    limit: MemoryLimit,
    #[command(flatten)]
    boundary: BoundaryArgs,
    /// One JSON object (every field: phases, levels, memory) instead of the summary line.
    #[arg(long)]
    json: bool,
}

/// `--simd`: the kernels' instruction set ([`Simd`]).
#[derive(Clone, Copy, clap::ValueEnum)]
enum SimdArg {
    Avx512,
    Avx2,
    Baseline,
}

impl SimdArg {
    fn simd(self) -> Simd {
        match self {
            SimdArg::Avx512 => Simd::Avx512,
            SimdArg::Avx2 => Simd::Avx2,
            SimdArg::Baseline => Simd::Baseline,
        }
    }
}

/// One line: a summary, or with `--json` one JSON object.
pub fn run(a: BenchArgs) -> Result<(), Error> {
    let BenchArgs {
        mesh,
        scheme,
        steps,
        threads,
        path,
        f32,
        runs,
        simd,
        limit,
        boundary,
        json,
    } = a;
    let best = Simd::detect();
    let simd = match simd.map(SimdArg::simd) {
        Some(s) if s > best => {
            return Err(Error::input(format!(
                "--simd {}: this CPU runs {} at most",
                s.name(),
                best.name()
            )))
        }
        s => s.unwrap_or(best),
    };
    one_stdin(&[
        ("scheme", std::path::Path::new(&scheme)),
        ("mesh", std::path::Path::new(&mesh)),
    ])?;
    let input = bench::mesh(&mesh, limit.bytes(), boundary.rule())?;
    let (topology, features) = (&input.topology, &input.features);
    let r = load(&scheme, None)?;
    let surface = GenericSurface::new(build(&r)?)?;
    let implementation = path.pick(&r, Geometry::Surface)?;
    let steps = steps.unwrap_or_else(|| bench::steps_for(&surface, topology, 4_200_000));
    let scalar = if f32 { 4 } else { 8 };
    let guard = limits::surface(
        &lsubdiv::CurveScheme::tables(&surface),
        surface.surface().contained_from,
        topology,
        features,
        steps,
        scalar,
        threads,
    );
    guard.check(
        &format!("{steps} steps of {scheme} on {mesh}"),
        limit.bytes(),
    )?;
    // What the size guard counts for this run: it times positions only, so without the
    // output quads (16 bytes each) the guard counts for a refined mesh.
    let guard_bytes = guard
        .bytes
        .saturating_sub(guard.quads.unwrap_or(0).saturating_mul(16));
    // The scalar type is the only difference: one function pointer for both.
    let measure = if f32 {
        bench::measure::<f32>
    } else {
        bench::measure::<f64>
    };
    let r = measure(
        &r.ls.name,
        &surface,
        &input,
        implementation,
        bench::Run {
            threads,
            steps,
            runs,
            simd,
        },
    )
    .map_err(Error::input)?;
    let scalar = if f32 { "f32" } else { "f64" };
    let peak_rss = bench::peak_rss_bytes();
    if json {
        println!(
            "{}",
            serde_json::json!({
                "mesh": mesh, "scheme": scheme, "path": implementation.name(),
                "threads": threads, "steps": steps, "scalar": scalar,
                "simd": r.simd.name(),
                "output_vertices": r.output_vertices, "median_seconds": r.median_seconds,
                "setup_seconds": r.setup_seconds,
                "mvps": r.mvps(), "peak_rss_bytes": peak_rss,
                "file_rss_bytes": r.file_rss_bytes, "guard_bytes": guard_bytes as u64,
                "phase_seconds": {"start": r.phase_seconds[0], "ordinary": r.phase_seconds[1], "fans": r.phase_seconds[2]},
                "level_seconds": r.level_seconds, "essential_bytes": r.essential_bytes,
            })
        );
    } else {
        let threads = plural(threads, "thread");
        println!(
            "{mesh}, {scheme}, {} ({} path, {scalar}, {}, {threads}): {} output vertices \
             in {:.2} ms, {:.1} M vertices/s (median of {runs}); setup {:.1} ms{}",
            plural(steps, "step"),
            implementation.name(),
            r.simd.name(),
            limits::count(r.output_vertices as u128),
            r.median_seconds * 1e3,
            r.mvps(),
            r.setup_seconds * 1e3,
            peak_rss.map_or(String::new(), |b| format!(
                "; peak RSS {}",
                limits::size(u128::from(b))
            )),
        );
    }
    Ok(())
}

/// `n thing` or `n things`.
fn plural(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}
