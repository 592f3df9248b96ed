//! The first steps of a mesh of small fans, level by level.
//!
//! Faces with an EV corner (or a corner whose vertex a rule sets) step in lock-step as whole
//! patches (`Refiner::fan_faces`). In the first steps those patches are small (side 4 at
//! N = 1), and a face's step there — its patch loaded and stored, two passes with a transpose
//! between, its ring handed on, its writers — costs several times its sums: refined once, the
//! icosphere's faces (each at two EVs) took 200 ns each against OpenSubdiv's 47
//! (the history of docs/benchmarks.md). On a mesh whose faces are mostly such fans (a triangle mesh split
//! into quads, open or closed, creased or not, with holes or not: a hole is refined like every
//! face, its points only left out of the output mesh) those steps run level by level
//! instead, every level stored whole in its numbering (`Numbering`): each face computes only
//! the points it owns (its interior, the edges and corners it owns) from its patch of the
//! level before — gathered by one index table per level, its phantoms set by the step's
//! rules (`Base::load_phantoms`: odd reflections across sharp edges, corners by their kind) —
//! by the step's 1D plan along x then along y (\[G\] §2.2: the tensor product of the
//! univariate step; whole rows at a time, AVX2 where the CPU has it); each vertex a rule sets
//! gets its child by that rule (`vertex_child`: an EV's from its old 1-ring by an index
//! table). With contained masks (\[G\] Prop. 4.8) an EV's missing diagonal only reaches the
//! EV's child and ring points outside the face, so no point a face writes needs it. The last
//! such level is the patches' start level, or the output.
//!
//! A refinement to side 2 (one binary step) takes this step on every mesh, ordinary faces
//! too: for 9 points a face the composed kernel's fixed costs made it half as fast ([`ALONE`]).

use super::vertices::{holders, turning_line};
use super::{
    ev_child, owned_border, ring_layout, vertex_child, Base, CornerPoint, Numbering, Plan,
    SharedOut, Simd, Spot,
};
use crate::features::VertexRule;
use crate::real::{axpy_slab, Real};
use crate::threads::in_threads;
use crate::topology::Wedge;

/// The largest side N' a level-by-level step refines to ([`leading`]).
const SIDE: i64 = 4;

/// Faces (or EVs) a worker takes in a level-by-level step at least: a face's step is short
/// (under 50 ns at N' = 2), and on the 2-vCPU VM a thread starts and joins in ~47 µs; two
/// workers of the icosphere's 15,360 faces ran its second level in 2.2 ms against one
/// worker's 1.7.
const PER_WORKER: usize = 16384;

/// The largest side N' of a whole refinement that runs level by level on any mesh. At N' = 2
/// (one binary step) the composed kernel's fixed costs per face — its gather, a tile of 32
/// values for 14, its writers' runs of single points — made it half as fast as this step
/// (one thread, alternated, M/s composed against level by level: torus 256 × 256 uniform
/// binary 27–41 against 69–86, Fibonacci 42 against 76–83, the creased torus 34–37 against
/// 73–75, grid-cube:64 34 against 88); at N' = 3 (Binary-Ternary's step) they were even, and
/// at N' = 4 (two steps) the composed kernel 1.5× faster.
const ALONE: i64 = 2;

/// How many of the leading depth-first steps (new sides `sides`, in order) run level by
/// level: all of them where the last side is at most [`ALONE`]; on a mesh whose faces are
/// at least half fans, those to a side of at most [`SIDE`]; none elsewhere (a mesh of
/// ordinary faces composes every step, `patch/composed.rs`, which a stored level would only
/// slow down).
pub(super) fn leading(
    base: &Base<'_>,
    fan_faces: usize,
    sides: impl Iterator<Item = i64>,
) -> usize {
    // Sides never shrink (every symbol rewrites to one or more): stop at the first past SIDE.
    let (mut small, mut alone) = (0, true);
    for n in sides {
        if n > SIDE {
            alone = false;
            break;
        }
        alone &= n <= ALONE;
        small += 1;
    }
    if alone || 2 * fan_faces >= base.topo.face_count() {
        small
    } else {
        0
    }
}

/// One step run level by level: level k (side N, numbered `old`) to level k + 1 (`new`).
pub(super) struct Step {
    plan: Plan,
    /// The step's index k (its sharpness, phantoms and vertex rules).
    k: usize,
    old: Numbering,
    new: Numbering,
    /// The step's 1D matrix as a band: per new point X' = 0..=N' the first old point of its
    /// band (`lo`, from x = −1) and its weights on the `band` old points from there (zeros
    /// where the plan has no parent: adding their products changes no bit, so the sums are
    /// the plan's, `combine`).
    lo: Vec<usize>,
    weights: Vec<f64>,
    band: usize,
    /// Per face, its patch of level k (ring included) as indices into that level, x-major.
    gather: Vec<u32>,
    /// Per face (from `border_at[f]`), the border points it owns but those a vertex rule sets:
    /// (Y'·(N'+1) + X', index in level k + 1).
    border: Vec<(u32, u32)>,
    border_at: Vec<u32>,
    /// Per special vertex (from `ring_at[i]`), its 1-ring in level k as
    /// [`one_ring`](super::vertices::one_ring) reads it: the vertex, then per wedge its spoke
    /// and its diagonal.
    rings: Vec<u32>,
    ring_at: Vec<u32>,
    /// The 1-ring weights of this step (\[G\] §3).
    ring: [f64; 2],
    /// Per face, whether its patch has phantoms to set at this step beside its EV corners'
    /// missing diagonals (which, as in the gather above, reach no point it writes).
    phantoms: Vec<bool>,
}

impl Step {
    pub(super) fn new(base: &Base<'_>, plan: Plan, (n, k): (i64, usize), ring: [f64; 2]) -> Step {
        let old = Numbering::new(base.topo, n);
        let new = old.with_n(plan.n_new);
        let m = ring_layout(n, true);
        let side = (plan.n_new + 1) as usize;
        let h = (plan.rows.len() - side) / 2;
        let parents = |xn: usize| &plan.parents[plan.rows[xn + h].clone()];
        // Parents come in increasing x: the band spans the first to the last.
        let span = |ps: &[(usize, f64)]| ps.last().map_or(0, |l| l.0 + 1 - ps[0].0);
        let band = (0..side).map(|xn| span(parents(xn))).max().unwrap_or(0);
        let lo: Vec<usize> = (0..side)
            .map(|xn| parents(xn).first().map_or(0, |p| p.0).min(m.side - band))
            .collect();
        let mut weights = vec![0.0; side * band];
        for (xn, w) in weights.chunks_exact_mut(band).enumerate() {
            for &(x, wt) in parents(xn) {
                w[x - lo[xn]] = wt;
            }
        }
        let faces = base.topo.face_count();
        let mut gather = old.gather_table(base);
        for t in gather.chunks_exact_mut(m.side * m.side) {
            // An EV's missing diagonal reaches no point the face writes (its product weight
            // is an exact zero there): it reads the face's corner 0 instead, so that the
            // gather needs no test.
            let corner = t[m.at(0, 0) / 3];
            t.iter_mut()
                .filter(|i| **i == u32::MAX)
                .for_each(|i| *i = corner);
        }
        let (mut border, mut border_at) = (Vec::new(), vec![0]);
        let all = 0..=new.n;
        let rules = base.vertex_rules(k);
        for f in 0..faces {
            let put = |x: i64, y: i64, i: usize| {
                let at = base.special_at.get(i).copied().unwrap_or(u32::MAX);
                let ruled = rules.get(at as usize).is_some_and(Option::is_some);
                if !ruled {
                    border.push(((y as usize * side + x as usize) as u32, i as u32));
                }
            };
            owned_border(&new, f, &all, &all, put);
            border_at.push(border.len() as u32);
        }
        let (mut rings, mut ring_at) = (Vec::new(), vec![0]);
        for &v in &base.special {
            let at = |w: Wedge, spot| {
                let (x, y) = CornerPoint::of_ring(w, spot).xy(n);
                gather[w.face as usize * m.side * m.side + m.at(x, y) / 3]
            };
            let rot = base.topo.rotation(v);
            let from = rings.len();
            rings.resize(from + 1 + 2 * rot.len(), 0);
            for (k, &w) in rot.iter().enumerate() {
                let centre = (k == 0).then_some(Spot::Centre);
                for spot in centre.into_iter().chain([Spot::Spoke, Spot::Diagonal]) {
                    rings[from + spot.in_ring(k)] = at(w, spot);
                }
            }
            ring_at.push(rings.len() as u32);
        }
        Step {
            plan,
            k,
            old,
            new,
            lo,
            weights,
            band,
            gather,
            border,
            border_at,
            rings,
            ring_at,
            ring,
            phantoms: (0..faces as u32)
                .map(|f| base.rules(f, k).has_phantoms_beside_evs())
                .collect(),
        }
    }

    /// Refines level `old` into `new` (every point of it written: each by the face that owns
    /// it, each EV by its child), with `threads` workers; `alphas` per special vertex.
    pub(super) fn run<T: Real>(
        &self,
        base: &Base<'_>,
        alphas: &[f64],
        old: &[[T; 3]],
        new: &mut Vec<[T; 3]>,
        (threads, simd): (usize, Simd),
    ) {
        let m = (self.old.n + 3) as usize;
        let side = (self.new.n + 1) as usize;
        let weights: Vec<T> = self.weights.iter().map(|&w| T::from_f64(w)).collect();
        new.resize(self.new.len(), [T::default(); 3]);
        let out = &SharedOut::new(new);
        let faces = base.topo.face_count();
        let chunk = faces.div_ceil(threads).max(PER_WORKER);
        in_threads((0..faces).step_by(chunk), |from| {
            let faces = from..(from + chunk).min(faces);
            let job = Job {
                base,
                sizes: (m, side, self.band),
                weights: &weights,
                faces,
                old,
                out,
            };
            match simd {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Simd::Avx2` and `Simd::Avx512` are only handed out where the CPU has
                // AVX2.
                Simd::Avx2 | Simd::Avx512 => unsafe { self.faces_avx2(job) },
                _ => self.faces_sized(job),
            }
        });
        // Each special vertex's child by its rule (an EV's from its 1-ring by the table).
        let per = base.special.len().div_ceil(threads).max(PER_WORKER);
        let work = base.special.iter().enumerate().step_by(per);
        let rules = base.vertex_rules(self.k);
        let layout = ring_layout(self.old.n, true);
        let point = |f: u32, x: i64, y: i64| {
            old[self.gather[f as usize * m * m + layout.at(x, y) / 3] as usize]
        };
        in_threads(work, |(from, _)| {
            let to = (from + per).min(base.special.len());
            for (i, &v) in base.special[from..to].iter().enumerate() {
                let i = from + i;
                let Some(rule) = rules[i] else {
                    continue; // Its face's patch gives it.
                };
                let child = if rule == VertexRule::Smooth && base.topo.valence(v) != 4 {
                    let ring = &self.rings[self.ring_at[i] as usize..self.ring_at[i + 1] as usize];
                    ev_child(base.topo, v, (alphas[i], self.ring), |k, _, spot| {
                        old[ring[spot.in_ring(k)] as usize]
                    })
                } else {
                    let (plan, ring) = (&self.plan, self.ring);
                    vertex_child(
                        base,
                        (v, rule, alphas[i]),
                        (plan, ring, self.k),
                        self.old.n,
                        point,
                    )
                };
                // SAFETY: no face writes a vertex a rule sets; each is written by its own
                // worker only.
                unsafe { out.write(v as usize, &child) };
            }
        });
        // Where a crease turns inside one face, its points near the turn by the curve, from
        // the face's patch with its phantoms.
        let patch_point = |f: u32, x: i64, y: i64| {
            let mut patch = vec![T::default(); m * m * 3];
            let table = &self.gather[f as usize * m * m..][..m * m];
            super::load(table, old, layout, &mut patch);
            base.load_phantoms((f, self.old.n, self.k), layout, &mut patch);
            let at = layout.at(x, y);
            [patch[at], patch[at + 1], patch[at + 2]]
        };
        let creases =
            (base.special.iter().zip(rules)).filter(|(_, r)| **r == Some(VertexRule::Crease));
        for (&v, _) in creases {
            for (e, t, p) in turning_line(base, &self.plan, (v, self.k), self.old.n, &patch_point) {
                if let Some((f, (x, y))) = holders(base.topo, (v, e, t), self.new.n).next() {
                    // SAFETY: the workers are done.
                    unsafe { out.write(self.new.index(f as usize, x, y).0, &p) };
                }
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn faces_avx2<T: Real>(&self, job: Job<'_, T>) {
        self.faces_sized(job);
    }

    /// [`Step::faces`] with the common sizes as constants, so that the loops over them unroll.
    #[inline(always)]
    fn faces_sized<T: Real>(&self, job: Job<'_, T>) {
        match job.sizes {
            (4, 3, 3) => self.faces((4, 3, 3), job),
            (5, 5, 3) => self.faces((5, 5, 3), job),
            sizes => self.faces(sizes, job),
        }
    }

    /// The job's faces' points: each face's patch (side m, x-major) gathered, refined along x
    /// (slabs of whole rows), transposed, and refined along y into the points of its (N'+1)²
    /// (`side` a row) that it owns.
    #[inline(always)]
    fn faces<T: Real>(&self, (m, side, band): (usize, usize, usize), job: Job<'_, T>) {
        let Job {
            base,
            weights,
            faces,
            old,
            out,
            ..
        } = job;
        let (n, layout) = (self.old.n, ring_layout(self.old.n, true));
        let zero = T::default();
        let (mut patch, mut along_x) = (vec![zero; m * m * 3], vec![zero; side * m * 3]);
        let mut across = vec![zero; m * side * 3];
        let (k, row) = (side - 2, side * 3);
        for f in faces {
            for (p, &i) in patch
                .chunks_exact_mut(3)
                .zip(&self.gather[f * m * m..][..m * m])
            {
                p.copy_from_slice(&old[i as usize]);
            }
            // Across sharp edges and at corners without a diagonal: the phantoms of step k.
            if self.phantoms[f] {
                base.load_phantoms((f as u32, n, self.k), layout, &mut patch);
            }
            // Along x: new row X' (old points y) from the rows of its band.
            for (xn, a) in along_x.chunks_exact_mut(m * 3).enumerate() {
                let w = &weights[xn * band..][..band];
                banded(a, w, &patch[self.lo[xn] * m * 3..], (m * 3, m * 3));
            }
            // Transposed: per old y, the new points X'.
            for (xn, a) in along_x.chunks_exact(m * 3).enumerate() {
                for (y, p) in a.chunks_exact(3).enumerate() {
                    across[(y * side + xn) * 3..][..3].copy_from_slice(p);
                }
            }
            // Along y, only the points the face writes: its interior rows straight into its
            // run of the level (none at N' = 1), then each border point it owns.
            if k > 0 {
                // SAFETY: face f is the only writer of its interior.
                let inside = unsafe { out.run(self.new.interior(f), k * k) }.as_flattened_mut();
                for (yn, dst) in (1..side - 1).zip(inside.chunks_exact_mut(k * 3)) {
                    let w = &weights[yn * band..][..band];
                    banded(dst, w, &across[self.lo[yn] * row + 3..], (k * 3, row));
                }
            }
            let border = self.border_at[f] as usize..self.border_at[f + 1] as usize;
            for &(g, i) in &self.border[border] {
                let (yn, xn) = (g as usize / side, g as usize % side);
                let mut p = [zero; 3];
                let w = &weights[yn * band..][..band];
                banded(&mut p, w, &across[self.lo[yn] * row + xn * 3..], (3, row));
                // SAFETY: face f is the only writer of the border points it owns.
                unsafe { out.write(i as usize, &p) };
            }
        }
    }
}

/// What a worker refines: its faces, from level `old` into `out`, with the step's band
/// weights in `T` and its sizes (m, N' + 1, band).
struct Job<'a, T> {
    base: &'a Base<'a>,
    sizes: (usize, usize, usize),
    weights: &'a [T],
    faces: std::ops::Range<usize>,
    old: &'a [[T; 3]],
    out: &'a SharedOut<T>,
}

/// `dst = Σ_i w[i] · src[i·stride ..][..len]`, in increasing i (element-wise, a row at a
/// time: vectorises).
#[inline(always)]
fn banded<T: Real>(dst: &mut [T], w: &[T], src: &[T], (len, stride): (usize, usize)) {
    let dst = &mut dst[..len];
    for (d, &s) in dst.iter_mut().zip(&src[..len]) {
        *d = w[0] * s;
    }
    for (i, &w) in w.iter().enumerate().skip(1) {
        axpy_slab(dst, w, &src[i * stride..][..len]);
    }
}
