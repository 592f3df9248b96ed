//! The reference driver's last step only near the EVs.
//!
//! A step whose masks are not yet contained at the EVs (\[G\] Prop. 4.8: Binary-Ternary's
//! first) runs by the reference driver, which scatters every vertex's mask over the whole
//! mesh. Away from the EVs that step is the tensor product of its 1D plan, as every
//! depth-first step is (\[G\] §2.2: the bivariate scheme is the tensor product of the
//! univariate one on regular regions). So the last such step scatters only the vertices whose
//! masks reach a face near an EV ([`Near::skip`], its map built once, `patch/reference.rs`),
//! and each face farther away takes its points from its own patch with ring, one level
//! before, by the step's plan. Both give every point the same masks; they differ in the order
//! of the sums (rounding).
//!
//! Near, in rings of base faces around an EV: r + ⌈d/2⌉, where a mask reaches (r old edges: its
//! longest half in new knots over the shortest rule), the vertices its words' rays pass
//! (⌈d/2⌉ − 1, \[G\] §2.2.2), and the walk across a corner (one more), each counted in base
//! edges (every base edge is at least one old edge).

use super::{lifted, Base, Numbering, Passes, Plan, STRIP_BYTES};
use crate::real::Real;
use crate::topology::Topology;
use lsubdiv_runtime::curve::{CurveTables, NO_CHILD};
use std::collections::{HashMap, VecDeque};

/// Where the last reference step runs, and the plan of the faces away from it.
pub(super) struct Near {
    /// Faces no special vertex is near: their points by `plan`.
    far: Vec<u32>,
    /// Per base face: its points at the level before the step are scattered (some special
    /// vertex is within reach of a face whose points they reach).
    scatter: Vec<bool>,
    /// The step's 1D plan, without a ring: new points 0..=N' from the old −1..=N+1.
    pub(super) plan: Plan,
    /// Per far face ([`Near::index`]): its patch with ring at the level before, as indices
    /// into that level's points in the reference driver's numbering (x-major, `u32::MAX`
    /// reads zero), and its new points' indices in the start level, [y'][x'].
    gather: Vec<u32>,
    put: Vec<u32>,
}

impl Near {
    /// The split for the reference steps `0..first` (the last of them local), or None if every
    /// face is near a special vertex or the step's plan needs more than a patch's ring.
    pub(super) fn new(
        t: &CurveTables<'_>,
        lookup: &HashMap<&[u8], u32>,
        base: &Base<'_>,
        word: &[u8],
    ) -> Option<Near> {
        let plan = Plan::new(t, lookup, word, 0).ok().filter(|p| p.complete)?;
        // New knots from a mask's child to its farthest entry, either way (the whole mask
        // where it has no child: even degrees).
        let longest = (0..t.word_count())
            .map(|w| {
                let len = t.mask_range(w).len();
                match t.mask_children[w] {
                    NO_CHILD => len.saturating_sub(1),
                    c => (c as usize).max(len.saturating_sub(c as usize + 1)),
                }
            })
            .max()
            .unwrap_or(0);
        let shortest = (0..t.symbol_count() as u8)
            .map(|a| t.rule(a).len())
            .min()
            .unwrap_or(1)
            .max(1);
        let reach = longest.div_ceil(shortest);
        let near = reach + t.degree.div_ceil(2);
        // A vertex scatters where its mask reaches a near face: `reach` from its own face.
        let scattered = near + reach + 2;
        let dist = rings(base.topo, &base.special, scattered + 1);
        let closest = |f: u32| {
            (0..4)
                .map(|c| dist[base.topo.vertex(f, c) as usize])
                .fold(usize::MAX, usize::min)
        };
        let faces = 0..base.topo.face_count() as u32;
        let far: Vec<u32> = faces.clone().filter(|&f| closest(f) > near).collect();
        if far.is_empty() {
            return None;
        }
        let scatter = faces.map(|f| closest(f) <= scattered).collect();
        Some(Near {
            far,
            scatter,
            plan,
            gather: Vec::new(),
            put: Vec::new(),
        })
    }

    /// The faces whose points come by the plan ([`Near::far_faces`] sets them).
    pub(super) fn far(&self) -> &[u32] {
        &self.far
    }

    /// The vertices of the level before the last reference step (its quads `before`, base
    /// face by base face, as many each) that the step does not scatter: those of faces no
    /// special vertex is within reach of (their points are wrong: [`Near::far_faces`] sets
    /// them).
    pub(super) fn skip(&self, before: &[[u32; 4]], vertices: usize) -> Vec<bool> {
        let per_face = before.len() / self.scatter.len();
        let mut skip = vec![true; vertices];
        for (quad, _) in before
            .iter()
            .zip(
                self.scatter
                    .iter()
                    .flat_map(|&s| std::iter::repeat_n(s, per_face)),
            )
            .filter(|&(_, s)| s)
        {
            for &v in quad {
                skip[v as usize] = false;
            }
        }
        skip
    }

    /// Finds, once, where each far face reads its patch in the level before the last
    /// reference step (its quads `before`, `first` − 1 steps) and where its new points go in
    /// the start level (numbering `num`).
    pub(super) fn index(
        &mut self,
        t: &CurveTables<'_>,
        base: &Base<'_>,
        (before, first): (&[[u32; 4]], usize),
        num: &Numbering,
    ) {
        let old = num.with_n(self.plan.old_side as i64 - 3);
        // Level 0 is the base mesh in its own order; a refined level is lifted.
        let from = (first > 1).then(|| lifted(t, before, first - 1, &old));
        let layout = super::ring_layout(old.n, true);
        let m = layout.side * layout.side;
        self.gather = vec![u32::MAX; self.far.len() * m];
        for (&f, table) in self.far.iter().zip(self.gather.chunks_exact_mut(m)) {
            old.gather(base, f, |x, y, i| {
                table[layout.at(x, y) / 3] = from.as_ref().map_or(i as u32, |l| l[i]);
            });
        }
        let side = self.plan.new_side() as i64;
        self.put = (self.far.iter())
            .flat_map(|&f| {
                let at = move |(y, x)| num.index(f as usize, x, y).0 as u32;
                (0..side).flat_map(move |y| (0..side).map(move |x| at((y, x))))
            })
            .collect();
    }

    /// The start level's points the far faces write ([`Near::index`]).
    pub(super) fn written(&self) -> &[u32] {
        &self.put
    }

    /// Sets the points of the far faces in `start`: each face's patch with its ring at the
    /// level before (`before`, the reference driver's numbering) refined by the plan along x
    /// and y ([`Near::index`] found where they are).
    pub(super) fn far_faces<T: Real>(&self, before: &[[f64; 3]], start: &mut [[T; 3]]) {
        let m = self.gather.len() / self.far.len().max(1);
        let mut patch = vec![0.0f64; m * 3];
        let side = self.plan.new_side();
        let (mut passes, mut new) = (Passes::default(), vec![0.0f64; side * side * 3]);
        let tables = self.gather.chunks_exact(m.max(1));
        for (table, put) in tables.zip(self.put.chunks_exact(side * side)) {
            for (p, &i) in patch.chunks_exact_mut(3).zip(table) {
                p.copy_from_slice(&before.get(i as usize).copied().unwrap_or_default());
            }
            // [y'][x'] of side N' + 1.
            self.plan
                .step_transposing(&patch, &mut passes, STRIP_BYTES, &mut new);
            for (p, &i) in new.chunks_exact(3).zip(put) {
                start[i as usize] = [p[0], p[1], p[2]].map(T::from_f64);
            }
        }
    }

    /// Bytes of its tables.
    pub(super) fn bytes(&self) -> usize {
        (self.far.capacity() + self.gather.capacity() + self.put.capacity()) * size_of::<u32>()
            + self.scatter.capacity()
    }
}

/// Rings of faces from the vertices `from` to every vertex (vertices of a face are one ring
/// apart), counted up to `most` (farther vertices get `most`).
fn rings(topo: &Topology, from: &[u32], most: usize) -> Vec<usize> {
    let mut dist = vec![most; topo.vertex_count()];
    let mut queue: VecDeque<u32> = from.iter().copied().collect();
    for &v in from {
        dist[v as usize] = 0;
    }
    while let Some(v) = queue.pop_front() {
        let d = dist[v as usize] + 1;
        if d >= most {
            continue;
        }
        for w in topo.rotation(v) {
            for c in 0..4 {
                let u = topo.vertex(w.face, c) as usize;
                if d < dist[u] {
                    dist[u] = d;
                    queue.push_back(u as u32);
                }
            }
        }
    }
    dist
}
