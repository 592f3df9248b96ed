//! A level of the reference steps cut open along its sharp edges and extended by ghost faces,
//! for the reference driver's step on a mesh with features (`patch/reference.rs`): a crease
//! is a boundary for both of its sides, and three layers of ghost faces beyond every boundary
//! give the scatter the odd reflections the patches use as phantoms (docs/real-meshes.md).
//! After the step, the points on the sharp lines are set by the scheme's curve rule
//! ([`Cut::curves`]), a dart's child by its smooth rule.

use super::{add3, sub3, vertex_child, Base, Numbering, Plan};
use crate::features::{Resolved, VertexRule};
use crate::mesh::QuadMesh;
use crate::real::Real;
use crate::topology::Topology;
use std::collections::HashMap;

/// Level k of the reference steps (side N = W_k per base face, numbered by `num`) cut along
/// the base edges sharp at step k, for the step's scatter with ghost faces ([`Ghosts`]): each
/// vertex gets one copy per sector (faces between sharp edges), so a crease is a boundary for
/// both sides. `source[i]` is the level's point copy i came from; the faces are the level's,
/// in order.
pub(super) struct Cut {
    pub(super) topo: Topology,
    pub(super) source: Vec<u32>,
    /// The level's face labels (`[label of edge 0, label of edge 1]`).
    pub(super) labels: Vec<[u8; 2]>,
    /// The 1D plan of step k along a whole base edge (no ring): its new points 0..=N' from
    /// its points −1..=N+1 (W_k is a palindrome under σ, \[G\] Cor. 4.4, so every sharp line
    /// reads it from either end).
    pub(super) line: Plan,
    /// The step.
    pub(super) k: usize,
    /// Per base edge sharp at step k: the edge, its ends a and b, and the base edge the sharp
    /// line continues along beyond each end (none: the odd reflection).
    sharp: Vec<(u32, [u32; 2], [Option<u32>; 2])>,
    /// The darts: smooth vertices with a sharp edge.
    darts: Vec<u32>,
}

impl Cut {
    /// The cut at step k (`features`' edges sharp at k) of the level `level` (the base mesh at
    /// k = 0) over the points of `num`, its faces labelled `labels`; none if the level is not
    /// a manifold. At a dart (one sharp edge at an
    /// interior vertex) the cut is at most a slit: the dart keeps one copy, whose child
    /// [`Cut::curves`] sets by the smooth rule.
    pub(super) fn new(
        base: &Topology,
        features: &Resolved,
        (k, level, num): (usize, &Topology, &Numbering),
        labels: Vec<[u8; 2]>,
        line: Plan,
    ) -> Option<Cut> {
        let mut faces = level.faces().to_vec();
        let mut source: Vec<u32> = (0..level.vertex_count() as u32).collect();
        // Per edge of the level: whether it lies on a base edge sharp at step k.
        let sharp_edge: Vec<bool> = (0..level.edge_count() as u32)
            .map(|e| {
                base_edge(base, num, level.edge_vertices(e))
                    .is_some_and(|e| features.edge_sharp(e, k))
            })
            .collect();
        for v in 0..level.vertex_count() as u32 {
            let sharp: Vec<bool> = level.spokes(v).map(|e| sharp_edge[e as usize]).collect();
            let interior = !level.is_boundary(v);
            // Wedge w lies between spokes w and w + 1; its sector is the number of sharp
            // spokes up to it, less one (at a boundary vertex spoke 0 is the boundary; at an
            // interior one the wedges before the first sharp spoke close the last sector).
            let count = sharp.iter().filter(|&&s| s).count();
            if count == 0 {
                continue;
            }
            let first_copy = source.len() as u32;
            let sectors = if interior { count } else { count - 1 };
            source.extend(std::iter::repeat_n(v, sectors.saturating_sub(1)));
            let mut seen = 0;
            for (w, wedge) in level.rotation(v).iter().enumerate() {
                seen += usize::from(sharp[w]);
                let sector = (seen + count - 1) % count;
                if sector > 0 {
                    faces[wedge.face as usize][wedge.corner as usize] =
                        first_copy + sector as u32 - 1;
                }
            }
        }
        let mesh = QuadMesh {
            positions: vec![[(); 3]; source.len()],
            faces,
        };
        let cut = Topology::build(&mesh).ok()?;
        // Each base vertex's rule, resolved once (an end of many sharp edges is met once per
        // edge).
        let rules: Vec<VertexRule> = (0..base.vertex_count() as u32)
            .map(|v| features.vertex_rule(base, v, k))
            .collect();
        // The base edge the sharp line through a continues along, away from edge e.
        let beyond = |a: u32, e: u32| match rules[a as usize] {
            VertexRule::Crease => base
                .spokes(a)
                .find(|&s| s != e && features.edge_sharp(s, k)),
            VertexRule::Smooth if base.valence(a) == 4 && !base.is_boundary(a) => {
                let spokes: Vec<u32> = base.spokes(a).collect();
                let i = spokes.iter().position(|&s| s == e);
                i.map(|i| spokes[(i + 2) % 4])
            }
            _ => None,
        };
        let sharp = (0..base.edge_count() as u32)
            .filter(|&e| features.edge_sharp(e, k))
            .map(|e| {
                let [a, b] = base.edge_vertices(e);
                (e, [a, b], [beyond(a, e), beyond(b, e)])
            })
            .collect();
        let darts = (0..base.vertex_count() as u32)
            .filter(|&v| {
                rules[v as usize] == VertexRule::Smooth
                    && base.spokes(v).any(|e| features.edge_sharp(e, k))
            })
            .collect();
        Some(Cut {
            topo: cut,
            source,
            labels,
            line,
            k,
            sharp,
            darts,
        })
    }

    /// After the step from `level` (numbered `num`) to `next` (numbered `next_num`): every
    /// point on a line sharp at step k set to the scheme's curve refinement of that line (a
    /// boundary is the scheme's curve, docs/real-meshes.md), the 1D plan on the points along
    /// it: beyond a crease vertex the line continues along its other sharp edge, beyond a dart
    /// of valence 4 straight on (the line is sharp, the vertex smooth, as in OpenSubdiv),
    /// elsewhere it is odd-reflected. A dart's child is its smooth rule on its 1-ring
    /// ([`vertex_child`]; `alphas` per special vertex, `ring` the step's EV 1-ring weights). The
    /// scatter near a boundary EV drops the entries that pass through it; on the lines, the
    /// principle decides.
    pub(super) fn curves<T: Real>(
        &self,
        base: &Base<'_>,
        (alphas, ring): (&[f64], [f64; 2]),
        (level, num): (&[[f64; 3]], &Numbering),
        next_num: &Numbering,
        next: &mut [[T; 3]],
    ) {
        let topo = base.topo;
        let n = num.n;
        let at = |i: usize| level[i];
        let mut old = Vec::with_capacity(n as usize + 3);
        for &(e, ends, beyond) in &self.sharp {
            let point = |x: i64| at(num.along(e, ends, x));
            // The point next to v on the sharp line's continuation s, or the reflection of
            // the one next to it on e.
            let past = |s: Option<u32>, v: u32, inner: [f64; 3]| match s {
                Some(s) => {
                    let ends = topo.edge_vertices(s);
                    at(num.along(s, ends, if ends[0] == v { 1 } else { n - 1 }))
                }
                None => std::array::from_fn(|i| 2.0 * at(v as usize)[i] - inner[i]),
            };
            old.clear();
            old.push(past(beyond[0], ends[0], point(1)));
            old.extend((0..=n).map(point));
            old.push(past(beyond[1], ends[1], point(n - 1)));
            for (xn, row) in self.line.rows.iter().enumerate() {
                let mut p = [0.0f64; 3];
                for &(x, w) in &self.line.parents[row.clone()] {
                    for (o, q) in p.iter_mut().zip(old[x]) {
                        *o += w * q;
                    }
                }
                next[next_num.along(e, ends, xn as i64)] = p.map(T::from_f64);
            }
        }
        let point = |f: u32, x: i64, y: i64| at(num.index(f as usize, x, y).0);
        for &v in &self.darts {
            let child = (v, VertexRule::Smooth, base.alpha(alphas, v));
            let plan = (&self.line, ring, self.k);
            next[v as usize] = vertex_child(base, child, plan, n, point).map(T::from_f64);
        }
    }
}

/// The base edge that the edge between points p and q of a level (numbered `num`) lies on.
fn base_edge(base: &Topology, num: &Numbering, [p, q]: [u32; 2]) -> Option<u32> {
    let vertex = |i: u32| (i as usize) < num.nv;
    match (num.edge_at(p as usize), num.edge_at(q as usize)) {
        (Some(e), Some(g)) => (e == g).then_some(e),
        (Some(e), None) => vertex(q).then_some(e),
        (None, Some(e)) => vertex(p).then_some(e),
        (None, None) if vertex(p) && vertex(q) => {
            base.spokes(p).find(|&e| base.other_end(e, p) == q)
        }
        _ => None,
    }
}

/// The mesh extended past its boundary by [`LAYERS`] layers of ghost faces, for a step of the
/// reference driver on an open level whose boundary vertices have two faces, or one (a
/// corner): across each boundary edge a → b of face (a, b, c, d) the quads (b, a, a₁, b₁),
/// (b₁, a₁, a₂, b₂), …, with a_i = a + i(a − d), b_i = b + i(b − c) (the odd reflection the
/// patches use, continued; a vertex with two faces shares its ghosts between its two boundary
/// edges); at a corner, the quads of the diagonal quadrant, the first at the double reflection
/// 4a − 2b − 2d + c. A ghost face's labels are its mirror image's: along the boundary the
/// boundary edge's, across it the level's word W_k read away from the boundary (`outward`:
/// every line leaving a boundary of a level reads W_k). Only the first layer is scattered:
/// the rays of its vertices' words pass the second (\[G\] §2.2.2: two labels each way at
/// degree 3), which the third makes ordinary; the outer layers' masks reach no real new point
/// (a mask reaches less than two old edges from its vertex). Real vertices and faces keep
/// their indices; the ghosts follow. Found once ([`Extended::new`]); each refine only makes
/// the ghosts' points ([`Ghosts::extend`]).
#[derive(Default)]
pub(super) struct Ghosts {
    /// The ghosts in the order they are made, each from points made before it.
    made: Vec<Ghost>,
}

/// Layers of ghost faces beyond a boundary ([`Ghosts`]).
pub(super) const LAYERS: usize = 3;

/// How ghosts are made ([`Ghosts`]).
pub(super) enum Ghost {
    /// a_i = a + i(a − p), i = 1..=LAYERS, from [a, p].
    Pair([u32; 2]),
    /// A corner's diagonal quadrant from its face [a, b, c, d] and its ghosts [g_out, g_in]
    /// across its outgoing and incoming boundary edges.
    Corner([u32; 4], [u32; 2]),
}

/// A cut level extended by its ghost faces ([`Ghosts`]).
pub(super) struct Extended {
    pub(super) ghosts: Ghosts,
    /// The level's quads, then the ghosts'.
    pub(super) faces: Vec<[u32; 4]>,
    pub(super) labels: Vec<[u8; 2]>,
    /// Per point: whether it is an outer ghost (not scattered).
    pub(super) outer: Vec<bool>,
}

impl Extended {
    /// The ghost layers of the cut level `cut`, `sigma` the scheme's involution on labels,
    /// `word` the level's W_k.
    pub(super) fn new(cut: &Cut, sigma: &[u8], word: &[u8]) -> Extended {
        let topo = &cut.topo;
        let mut ghosts = Ghosts::default();
        let mut next = topo.vertex_count() as u32;
        let mut faces = topo.faces().to_vec();
        let mut labels = cut.labels.clone();
        let sigma = |a: u8| sigma[a as usize];
        // The labels of the lines leaving the boundary, layer by layer.
        let outward: [u8; LAYERS] = std::array::from_fn(|i| word[i % word.len()]);
        const L: u32 = LAYERS as u32;
        let mut shared: HashMap<u32, u32> = HashMap::new();
        // The ghost pairs made once per edge (not shared), and each corner's first diagonal
        // ghost.
        let mut pairs: Vec<u32> = Vec::new();
        let mut diagonals: Vec<u32> = Vec::new();
        // Per corner: its ghost across its outgoing boundary edge and across its incoming one.
        let mut corners: HashMap<u32, [u32; 2]> = HashMap::new();
        for f in 0..topo.face_count() as u32 {
            for l in (0..4u8).filter(|&l| topo.is_boundary_edge(f, l)) {
                let v = |k: u8| topo.vertex(f, (l + k) % 4);
                let (a, b, c, d) = (v(0), v(1), v(2), v(3));
                let mut pair = |a, p| {
                    if let Some(&g) = shared.get(&a) {
                        return g;
                    }
                    // Once per vertex with two faces (both its boundary edges reflect across
                    // the same line), once per edge otherwise.
                    let g = next;
                    ghosts.made.push(Ghost::Pair([a, p]));
                    next += L;
                    if topo.valence(a) == 2 {
                        shared.insert(a, g);
                    }
                    g
                };
                let (a1, b1) = (pair(a, d), pair(b, c));
                for (v, g) in [(a, a1), (b, b1)] {
                    if topo.valence(v) != 2 {
                        pairs.push(g);
                    }
                }
                faces.push([b, a, a1, b1]);
                faces.extend((1..L).map(|i| [b1 + i - 1, a1 + i - 1, a1 + i, b1 + i]));
                // Edge a → b's label, read from corner l (as the scatter reads it).
                let [la, lb] = cut.labels[f as usize];
                let along = [la, lb, sigma(la), sigma(lb)][l as usize];
                labels.extend(outward.map(|w| [sigma(along), w]));
                if topo.valence(a) == 1 {
                    corners.entry(a).or_insert([u32::MAX; 2])[0] = a1;
                }
                if topo.valence(b) == 1 {
                    corners.entry(b).or_insert([u32::MAX; 2])[1] = b1;
                }
            }
        }
        let mut corners: Vec<(u32, [u32; 2])> = corners.into_iter().collect();
        corners.sort_unstable();
        for (a, [g_out, g_in]) in corners {
            // The corner's face (a, b, c, d): g_out = 2a − d (across a → b), g_in = 2a − b.
            let w = topo.rotation(a)[0];
            let face = [0, 1, 2, 3].map(|i| topo.vertex(w.face, (w.corner + i) % 4));
            ghosts.made.push(Ghost::Corner(face, [g_out, g_in]));
            // The quadrant's points P(i, j), i along g_out's line and j along g_in's: a, the
            // ghosts of the two boundary edges, and the L × L diagonal ghosts, row by row.
            let d11 = next;
            next += L * L;
            diagonals.push(d11);
            let point = |i: u32, j: u32| match (i, j) {
                (0, 0) => a,
                (i, 0) => g_out + i - 1,
                (0, j) => g_in + j - 1,
                (i, j) => d11 + (i - 1) + L * (j - 1),
            };
            for j in 0..L {
                for i in 0..L {
                    faces.push([
                        point(i + 1, j),
                        point(i, j),
                        point(i, j + 1),
                        point(i + 1, j + 1),
                    ]);
                    let (wi, wj) = (outward[i as usize], outward[j as usize]);
                    labels.push([sigma(wi), wj]);
                }
            }
        }
        // The outer layers: every ghost pair's but its first, each corner's but its first.
        let mut outer = vec![false; next as usize];
        for &g in shared.values().chain(&pairs) {
            outer[g as usize + 1..(g + L) as usize].fill(true);
        }
        for &d11 in &diagonals {
            outer[d11 as usize + 1..(d11 + L * L) as usize].fill(true);
        }
        Extended {
            ghosts,
            faces,
            labels,
            outer,
        }
    }
}

impl Ghosts {
    /// Bytes it holds.
    pub(super) fn bytes(&self) -> usize {
        self.made.capacity() * size_of::<Ghost>()
    }

    /// Appends the ghosts' points to the mesh's `points`, in the order [`Extended::new`] made
    /// them.
    pub(super) fn extend(&self, points: &mut Vec<[f64; 3]>) {
        for ghost in &self.made {
            match *ghost {
                Ghost::Pair([a, p]) => {
                    let (pa, pp) = (points[a as usize], points[p as usize]);
                    for layer in 1..=LAYERS {
                        let (m, n) = (layer as f64 + 1.0, layer as f64);
                        points.push(std::array::from_fn(|i| m * pa[i] - n * pp[i]));
                    }
                }
                Ghost::Corner(face, [g_out, g_in]) => {
                    let [pa, pb, pc, pd] = face.map(|v| points[v as usize]);
                    let g = |i: u32| points[i as usize];
                    let d11: [f64; 3] =
                        std::array::from_fn(|i| 4.0 * pa[i] - 2.0 * pb[i] - 2.0 * pd[i] + pc[i]);
                    let along_out = sub3(g(g_out + 1), g(g_out));
                    let along_in = sub3(g(g_in + 1), g(g_in));
                    // Row by row: each row the one before moved along g_in's line.
                    let first = points.len();
                    let mut at = d11;
                    for _ in 0..LAYERS {
                        points.push(at);
                        at = add3(at, along_out);
                    }
                    for i in LAYERS..LAYERS * LAYERS {
                        points.push(add3(points[first + i - LAYERS], along_in));
                    }
                }
            }
        }
    }
}
