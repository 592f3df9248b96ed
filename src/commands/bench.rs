//! `lsubdiv bench`: times surface refinement ([`lsubdiv_cli::bench`]).

use crate::commands::args::{BenchPath, MemoryLimit};
use crate::commands::{bad, Failure};

/// Arguments of `lsubdiv bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
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
}

/// One JSON line per configuration.
pub fn run(a: BenchArgs) -> Result<(), Failure> {
    bench(
        &a.mesh,
        &a.scheme,
        a.steps,
        a.threads,
        a.path,
        a.f32,
        a.runs,
        a.limit.bytes(),
    )
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
    let m = bench::mesh(mesh).map_err(bad)?;
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
        bench::measure::<f32>(scheme, &surface, &m, p, threads, steps, runs)
    } else {
        bench::measure::<f64>(scheme, &surface, &m, p, threads, steps, runs)
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
