//! The first steps of a mesh of small fans, level by level.
//!
//! Faces with an EV corner step in lock-step as whole patches (`Refiner::fan_faces`). In the
//! first steps those patches are small (side 4 at N = 1), and a face's step there — its
//! patch loaded and stored, two passes with a transpose between, its ring handed on, its
//! writers — costs several times its sums: refined once, the icosphere's faces (each at two
//! EVs) took 200 ns each against OpenSubdiv's 47 (docs/benchmarks.md). On a mesh without
//! features whose faces are mostly such fans those steps run level by level instead, every
//! level stored whole in its numbering (`Numbering`): each face computes only the points it
//! owns (its interior, the edges and corners it owns) from its patch of the level before,
//! gathered by one index table per level, by the step's 1D plan along x then along y (\[G\]
//! §2.2: the tensor product of the univariate step), and each EV's child comes from its old
//! 1-ring (`one_ring`). With contained masks (\[G\] Prop. 4.8) an EV's missing diagonal only
//! reaches the EV's child and ring points outside the face, so no point a face owns needs it
//! (it loads as zero, as in the patches). The last such level is the patches' start level, or
//! the output.

use super::{
    ev_child, in_threads, owned_border, ring_layout, Base, CornerPoint, Numbering, Plan, SharedOut,
    Spot, BETWEEN,
};
use crate::real::Real;
use crate::topology::Wedge;

/// The largest side N' a level-by-level step refines to ([`leading`]).
const SIDE: i64 = 4;

/// How many of the leading depth-first steps (new sides `sides`, in order) run level by
/// level: on a mesh without features or holes whose faces are at least half fans, those to a
/// side of at most [`SIDE`]; none elsewhere (a mesh of ordinary faces composes every step,
/// `patch/composed.rs`, which a stored level would only slow down).
pub(super) fn leading(
    base: &Base<'_>,
    fan_faces: usize,
    sides: impl Iterator<Item = i64>,
) -> usize {
    let features = &base.features;
    let mostly_fans = 2 * fan_faces >= base.topo.face_count();
    if !features.is_plain() || features.has_holes() || !mostly_fans {
        return 0;
    }
    sides.take_while(|&n| n <= SIDE).count()
}

/// One step run level by level: level k (side N, numbered `old`) to level k + 1 (`new`).
pub(super) struct Step {
    old: Numbering,
    new: Numbering,
    /// The step's 1D matrix, dense: per new point X' = 0..=N' its weights on the old points
    /// x = −1..=N+1 (zeros where the plan has no parent: adding their products changes no
    /// bit, so the sums are the plan's, `combine`).
    weights: Vec<f64>,
    /// Per face, its patch of level k (ring included) as indices into that level, x-major
    /// (`u32::MAX` where an EV's diagonal is missing).
    gather: Vec<u32>,
    /// Per face (from `border_at[f]`), the border points it owns but EVs: (Y'·(N'+1) + X',
    /// index in level k + 1).
    border: Vec<(u32, u32)>,
    border_at: Vec<u32>,
    /// Per special vertex (from `ring_at[i]`), its 1-ring in level k as [`one_ring`] reads
    /// it: the vertex, then per wedge its spoke and its diagonal.
    rings: Vec<u32>,
    ring_at: Vec<u32>,
    /// The 1-ring weights of this step (\[G\] §3).
    ring: [f64; 2],
}

impl Step {
    pub(super) fn new(base: &Base<'_>, plan: &Plan, n: i64, ring: [f64; 2]) -> Step {
        let old = Numbering::new(base.topo, n);
        let new = old.with_n(plan.n_new);
        let m = ring_layout(n, true);
        let side = (plan.n_new + 1) as usize;
        let h = (plan.rows.len() - side) / 2;
        let mut weights = vec![0.0; side * m.side];
        for (xn, w) in weights.chunks_exact_mut(m.side).enumerate() {
            for &(x, wt) in &plan.parents[plan.rows[xn + h].clone()] {
                w[x] = wt;
            }
        }
        let faces = base.topo.face_count();
        let mut gather = vec![u32::MAX; faces * m.side * m.side];
        for (f, t) in gather.chunks_exact_mut(m.side * m.side).enumerate() {
            old.gather(base, f as u32, |x, y, i| t[m.at(x, y) / 3] = i as u32);
        }
        let (mut border, mut border_at) = (Vec::new(), vec![0]);
        let all = 0..=new.n;
        for f in 0..faces {
            let put = |x: i64, y: i64, i: usize| {
                let ev = i < base.special_at.len() && base.special_at[i] != u32::MAX;
                if !ev {
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
            rings.push(at(rot[0], Spot::Centre));
            for &w in rot {
                rings.extend([at(w, Spot::Spoke), at(w, Spot::Diagonal)]);
            }
            ring_at.push(rings.len() as u32);
        }
        Step {
            old,
            new,
            weights,
            gather,
            border,
            border_at,
            rings,
            ring_at,
            ring,
        }
    }

    /// The numbering of the level before the step.
    pub(super) fn old(&self) -> &Numbering {
        &self.old
    }

    /// Refines level `old` into `new` (every point of it written: each by the face that owns
    /// it, each EV by its child), with `threads` workers; `alphas` per special vertex.
    pub(super) fn run<T: Real>(
        &self,
        base: &Base<'_>,
        alphas: &[f64],
        old: &[[T; 3]],
        new: &mut Vec<[T; 3]>,
        threads: usize,
    ) {
        let m = (self.old.n + 3) as usize;
        let side = (self.new.n + 1) as usize;
        let weights: Vec<T> = self.weights.iter().map(|&w| T::from_f64(w)).collect();
        new.resize(self.new.len(), [T::default(); 3]);
        let out = &SharedOut::new(new);
        let faces = base.topo.face_count();
        let chunk = faces.div_ceil(threads).max(BETWEEN);
        in_threads((0..faces).step_by(chunk), |from| {
            let faces = from..(from + chunk).min(faces);
            // The common sizes as constants, so that the loops over them unroll.
            match (m, side) {
                (4, 3) => self.faces(4, 3, &weights, faces, old, out),
                (5, 5) => self.faces(5, 5, &weights, faces, old, out),
                _ => self.faces(m, side, &weights, faces, old, out),
            }
        });
        // Each EV's child from its old 1-ring.
        let per = base.special.len().div_ceil(threads).max(BETWEEN);
        let work = base.special.iter().enumerate().step_by(per);
        in_threads(work, |(from, _)| {
            let to = (from + per).min(base.special.len());
            for (i, &v) in base.special[from..to].iter().enumerate() {
                let i = from + i;
                let ring = &self.rings[self.ring_at[i] as usize..self.ring_at[i + 1] as usize];
                let child = ev_child(base.topo, v, (alphas[i], self.ring), |k, _, spot| {
                    let at = match spot {
                        Spot::Centre => 0,
                        Spot::Spoke => 1 + 2 * k,
                        Spot::Diagonal => 2 + 2 * k,
                    };
                    old[ring[at] as usize]
                });
                // SAFETY: no face writes an EV; each EV is written by its own worker only.
                unsafe { out.write(v as usize, &child) };
            }
        });
    }

    /// Faces `faces`' points: each face's patch (side m) gathered, refined along x, then
    /// along y into its (N'+1)² points (`side` a row), of which it writes those it owns.
    #[inline(always)]
    fn faces<T: Real>(
        &self,
        m: usize,
        side: usize,
        weights: &[T],
        faces: std::ops::Range<usize>,
        old: &[[T; 3]],
        out: &SharedOut<T>,
    ) {
        let zero = [T::default(); 3];
        let (mut patch, mut along_x) = (vec![zero; m * m], vec![zero; side * m]);
        let mut grid = vec![zero; side * side];
        let k = side - 2;
        for f in faces {
            for (p, &i) in patch.iter_mut().zip(&self.gather[f * m * m..][..m * m]) {
                *p = old.get(i as usize).copied().unwrap_or(zero);
            }
            // Along x: each new X' for every old row y (patch x-major: P[x·m + y]).
            for (a, w) in along_x.chunks_exact_mut(m).zip(weights.chunks_exact(m)) {
                for (y, a) in a.iter_mut().enumerate() {
                    *a = sum(w, |x| patch[x * m + y]);
                }
            }
            // Along y: the face's rows Y'.
            for (row, w) in grid.chunks_exact_mut(side).zip(weights.chunks_exact(m)) {
                for (g, a) in row.iter_mut().zip(along_x.chunks_exact(m)) {
                    *g = sum(w, |y| a[y]);
                }
            }
            let first = self.new.interior(f);
            for y in 1..side - 1 {
                for x in 1..side - 1 {
                    // SAFETY: face f is the only writer of its interior.
                    unsafe { out.write(first + (y - 1) * k + x - 1, &grid[y * side + x]) };
                }
            }
            let border = self.border_at[f] as usize..self.border_at[f + 1] as usize;
            for &(g, i) in &self.border[border] {
                // SAFETY: face f is the only writer of the border points it owns.
                unsafe { out.write(i as usize, &grid[g as usize]) };
            }
        }
    }
}

/// `Σ_x w[x] · p(x)`, in increasing x.
#[inline(always)]
fn sum<T: Real>(w: &[T], p: impl Fn(usize) -> [T; 3]) -> [T; 3] {
    let mut acc = p(0).map(|c| w[0] * c);
    for (x, &w) in w.iter().enumerate().skip(1) {
        for (a, c) in acc.iter_mut().zip(p(x)) {
            *a += w * c;
        }
    }
    acc
}
