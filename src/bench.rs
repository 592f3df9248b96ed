//! The benchmark behind `lsubdiv bench`: standard meshes, refined with a scheme by one path at a
//! thread count, timed (median of repeated runs, refinement only, no I/O).

use crate::implementation::Implementation;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::GenericSurface;
use lsubdiv::mesh::features::{Boundary, Features};
use lsubdiv::mesh::generators::{
    creased_cube, cube, grid_cube, grid_with_hole, icosphere, open_grid, pentagon_star,
    polygon_prism, star, torus, tube,
};
use lsubdiv::mesh::patch::{output_counts, Refiner, Simd};
use lsubdiv::mesh::polygon::catmull_clark;
use lsubdiv::mesh::polygon::PolyMesh;
use lsubdiv::mesh::real::Real;
use lsubdiv::mesh::surface::{SurfaceScheme, SurfaceVisitor};
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use lsubdiv::mesh_file::Checked;
use lsubdiv::Diagnostic as Error;
use std::time::Instant;

/// Faces of the largest built-in torus (about 0.7 GB of mesh): larger ones are refused
/// instead of failing to allocate.
pub const MAX_TORUS_FACES: usize = 1 << 24;

/// Sides of the largest built-in prism.
pub const MAX_PRISM_SIDES: usize = 10_000;

/// Grid side of the largest built-in grid cube (6·K² faces, at most [`MAX_TORUS_FACES`]).
pub const MAX_GRID_CUBE: usize = 1_000;

/// Level of the largest built-in icosphere (20·4^L triangles, 60·4^L quads after its first
/// step: at most [`MAX_TORUS_FACES`]).
pub const MAX_ICOSPHERE_LEVEL: usize = 8;

/// A built-in mesh (`torus:R:C`, `torus:R:C:x` the same with its faces ordered along x,
/// `cube`, `grid-cube:K` (each face a K × K grid: 8 EVs beside ordinary faces), `star`,
/// `prism:N`: n-gon caps, split by a Catmull–Clark step; open: `grid` (8 × 8
/// quads), `tube` (8 along, 16 around), `hole` (a 9 × 9 grid whose centre face is a hole),
/// `pentagon-star` (a pentagon with a triangle on each edge, split first); `creased-cube`
/// (every edge sharp); `icosphere:L` (a triangle mesh, split first: every quad at two EVs))
/// or an OBJ or PLY file read
/// under `--max-memory max` ([`crate::limits::read_mesh`]), with its topology.
pub fn mesh(spec: &str, max: u64, boundary: Option<Boundary>) -> Result<Checked, Error> {
    let mut read = built(spec, max, boundary)?;
    if let Some(b) = boundary {
        read.features.boundary = b;
    }
    Ok(read)
}

/// A size `s` of the built-in mesh `spec`: an integer in `range`, else an error saying `what`
/// the sizes are.
fn size(
    spec: &str,
    s: &str,
    range: std::ops::RangeInclusive<usize>,
    what: &str,
) -> Result<usize, Error> {
    s.parse()
        .ok()
        .filter(|n| range.contains(n))
        .ok_or_else(|| Error::input(format!("`{spec}`: {what}")))
}

/// [`mesh`] before its boundary rule is set (a file's is set while reading).
fn built(spec: &str, max: u64, boundary: Option<Boundary>) -> Result<Checked, Error> {
    let parts: Vec<&str> = spec.split(':').collect();
    let featured = |(mesh, features)| checked(spec, mesh, false, features);
    let built = match parts.as_slice() {
        ["grid"] => open_grid(8, 8),
        ["tube"] => tube(8, 16),
        ["hole"] => return featured(grid_with_hole(9)),
        ["creased-cube"] => return featured(creased_cube()),
        ["torus", r, c] | ["torus", r, c, "x"] => {
            let what = "torus sizes are integers from 3 to 100000";
            let (r, c) = (
                size(spec, r, 3..=100_000, what)?,
                size(spec, c, 3..=100_000, what)?,
            );
            if r * c > MAX_TORUS_FACES {
                return Err(Error::input(format!(
                    "`{spec}`: {} faces; built-in tori have at most {MAX_TORUS_FACES} (R·C)",
                    r * c
                )));
            }
            let mut t = torus(r, c);
            if parts.len() == 4 {
                // Each face's corners from its second: edge 0 then runs along the row, so
                // that consecutive faces meet across edge 1 (the order of a row-major grid),
                // orientation kept.
                for f in &mut t.faces {
                    f.rotate_left(1);
                }
            }
            t
        }
        ["cube"] => cube(),
        ["grid-cube", k] => {
            let most = MAX_GRID_CUBE;
            let what = format!("a grid cube's faces are 1 × 1 to {most} × {most} grids");
            grid_cube(size(spec, k, 1..=most, &what)?)
        }
        ["star"] => star(),
        ["prism", n] => {
            let what = format!("a prism has 3 to {MAX_PRISM_SIDES} sides");
            let n = size(spec, n, 3..=MAX_PRISM_SIDES, &what)?;
            // n-gon caps: the first step is a Catmull–Clark step (`runtime::polygon`).
            return split(spec, &polygon_prism(n), boundary);
        }
        ["pentagon-star"] => return split(spec, &pentagon_star(), boundary),
        ["icosphere", l] => {
            let what = format!("an icosphere's level is 0 to {MAX_ICOSPHERE_LEVEL}");
            let l = size(spec, l, 0..=MAX_ICOSPHERE_LEVEL, &what)?;
            // Triangles: the first step is a Catmull–Clark step (`runtime::polygon`).
            return split(spec, &icosphere(l), boundary);
        }
        _ => {
            let path = std::path::Path::new(spec);
            return crate::limits::read_mesh(path, max, boundary, None).map(|(mesh, _)| mesh);
        }
    };
    checked(spec, built, false, Features::default())
}

/// A built-in polygon mesh after its first step, a Catmull–Clark step (`runtime::polygon`),
/// with the boundary rule (the default's if none).
fn split(spec: &str, mesh: &PolyMesh, boundary: Option<Boundary>) -> Result<Checked, Error> {
    let features = Features::with_boundary(boundary.unwrap_or_default());
    let split = catmull_clark(mesh, &features)
        .map_err(|e| Error::internal(None, format!("built-in mesh `{spec}`: {e}")))?;
    checked(spec, split.mesh, true, split.features)
}

/// A built-in mesh with its topology (`split`: after its first, Catmull–Clark, step).
fn checked(spec: &str, mesh: QuadMesh, split: bool, features: Features) -> Result<Checked, Error> {
    let topology = Topology::build(&mesh)
        .map_err(|e| Error::internal(None, format!("built-in mesh `{spec}`: {e}")))?;
    Ok(Checked {
        weld: None,
        mesh,
        split,
        topology,
        features,
        uv: None,
        uv_rule: Default::default(),
        warnings: Vec::new(),
    })
}

/// How to run a measurement: workers, steps, timed runs (the median is reported) and the
/// kernels' instruction set.
#[derive(Clone, Copy, Debug)]
pub struct Run {
    /// Workers.
    pub threads: usize,
    /// Steps of the scheme.
    pub steps: usize,
    /// Timed runs after one warm-up.
    pub runs: usize,
    /// The kernels' instruction set (`Refiner::set_simd`).
    pub simd: Simd,
}

/// One measurement.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// Output vertices of one refinement.
    pub output_vertices: usize,
    /// Median wall time of one refinement.
    pub median_seconds: f64,
    /// Wall time of building the refiner once (its tables, plans and the reference steps'
    /// maps: what OpenSubdiv's topology refiner and stencil tables do before refining).
    pub setup_seconds: f64,
    /// Median wall time of each phase (start level, ordinary faces, fans of the EVs).
    pub phase_seconds: [f64; 3],
    /// Median time of each depth-first step, summed over the workers
    /// (`Refiner::level_seconds`).
    pub level_seconds: Vec<f64>,
    /// Bytes of the input positions (f64), the output, and the largest intermediate level as
    /// unique vertices: the memory a level-by-level refinement cannot do without.
    pub essential_bytes: usize,
    /// The instruction set the kernels ran with.
    pub simd: Simd,
    /// [`file_rss_bytes`] after the timed runs, the refiner still alive: the code that ran,
    /// which peak RSS counts beside the job's own memory.
    pub file_rss_bytes: Option<u64>,
}

impl Measurement {
    /// Output vertices per second ÷ 1e6.
    pub fn mvps(&self) -> f64 {
        self.output_vertices as f64 / self.median_seconds / 1e6
    }
}

/// Times `Refiner::refine` (positions only, buffers reused, as OpenSubdiv's primvar refiner is
/// timed): one warm-up, then the median of `runs`.
struct Timed<'m, T> {
    mesh: &'m QuadMesh,
    topology: &'m Topology,
    features: &'m Features,
    threads: usize,
    steps: usize,
    runs: usize,
    simd: Simd,
    _scalar: std::marker::PhantomData<T>,
}

impl<T: Real> SurfaceVisitor for Timed<'_, T> {
    type Output = Result<Measurement, String>;
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) -> Self::Output {
        let setup = Instant::now();
        let mut r = Refiner::<S, T>::with_features(
            scheme,
            self.topology,
            self.features,
            self.steps,
            self.threads,
        )
        .map_err(|e| e.to_string())?;
        let setup_seconds = setup.elapsed().as_secs_f64();
        let simd = r.set_simd(self.simd);
        r.refine(&self.mesh.positions).map_err(|e| e.to_string())?;
        let mut times = Vec::with_capacity(self.runs);
        let mut phases: Vec<[f64; 3]> = Vec::new();
        let mut levels: Vec<Vec<f64>> = Vec::new();
        for _ in 0..self.runs.max(1) {
            let t = Instant::now();
            std::hint::black_box(r.refine(&self.mesh.positions).map_err(|e| e.to_string())?);
            times.push(t.elapsed().as_secs_f64());
            let p = r.phase_seconds();
            phases.push([p.start, p.ordinary, p.fans]);
            levels.push(r.level_seconds().to_vec());
        }
        let file_rss_bytes = file_rss_bytes();
        times.sort_by(f64::total_cmp);
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let phase_seconds = [0, 1, 2].map(|i| median(phases.iter().map(|l| l[i]).collect()));
        let level_seconds = (0..levels[0].len())
            .map(|s| median(levels.iter().map(|l| l[s]).collect()))
            .collect();
        Ok(Measurement {
            output_vertices: r.output_vertices(),
            median_seconds: times[times.len() / 2],
            setup_seconds,
            phase_seconds,
            level_seconds,
            essential_bytes: 0,
            simd,
            file_rss_bytes,
        })
    }
}

/// Refines `input` (its mesh, topology and features) with the scheme by `path` and reports
/// the median time of one refinement.
pub fn measure<T: Real>(
    scheme: &str,
    surface: &GenericSurface,
    input: &Checked,
    path: Implementation,
    run: Run,
) -> Result<Measurement, String> {
    let (mesh, topology) = (&input.mesh, &input.topology);
    let timed = Timed::<T> {
        mesh,
        topology,
        features: &input.features,
        threads: run.threads,
        steps: run.steps,
        runs: run.runs,
        simd: run.simd,
        _scalar: std::marker::PhantomData,
    };
    let mut m = match path {
        Implementation::Generated => lsubdiv::generated::visit_surface(scheme, timed)
            .ok_or_else(|| format!("`{scheme}` has no generated surface code"))??,
        Implementation::Generic => timed.visit(surface)?,
    };
    let ls = &surface.scheme().ls;
    let v = mesh.positions.len();
    let count = |n| unique_vertices(topology, n);
    let mut word = ls.axiom.clone();
    let mut prev = v;
    for _ in 0..run.steps.saturating_sub(1) {
        word = ls.rewrite(&word);
        prev = count(word.len());
    }
    let size = size_of::<T>();
    m.essential_bytes = v * 24 + (m.output_vertices + prev) * 3 * size;
    Ok(m)
}

/// The compiled surface scheme called `name` (shipped scheme or file).
pub fn surface(name: &str) -> Result<GenericSurface, String> {
    let r = crate::resolve(name).map_err(|e| e.to_string())?;
    let s = Scheme::build(r.ls).map_err(|e| e.to_string())?;
    GenericSurface::new(s).map_err(|e| e.to_string())
}

/// Peak resident set size of this process so far (Linux `VmHWM`), in bytes.
pub fn peak_rss_bytes() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// Resident pages of this process mapped from files (Linux `RssFile`), in bytes: the
/// program's code and libraries as far as they have run, not memory the job allocates.
pub fn file_rss_bytes() -> Option<u64> {
    status_bytes("RssFile:")
}

/// A size in kB of `/proc/self/status`, in bytes.
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Vertices of a quad mesh after every edge splits into n (`patch::output_counts`).
fn unique_vertices(topo: &Topology, n: usize) -> usize {
    let (v, e, f) = (topo.vertex_count(), topo.edge_count(), topo.face_count());
    usize::try_from(output_counts(v as u128, e as u128, f as u128, n as u128).0)
        .unwrap_or(usize::MAX)
}

/// The number of steps that brings `mesh` closest to `target` output vertices.
pub fn steps_for(surface: &GenericSurface, topology: &Topology, target: usize) -> usize {
    let ls = &surface.scheme().ls;
    let count = |n| unique_vertices(topology, n);
    let mut word = ls.axiom.clone();
    let mut best = (0, usize::MAX);
    for s in 0..40 {
        let diff = count(word.len()).abs_diff(target);
        if diff < best.1 {
            best = (s, diff);
        }
        if count(word.len()) > target {
            break;
        }
        word = ls.rewrite(&word);
    }
    best.0
}
