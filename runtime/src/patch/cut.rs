//! The mesh cut open along its sharp edges and extended by ghost faces, for the reference
//! driver's step on a mesh with features (`patch/reference.rs`): a crease is a boundary for
//! both of its sides, and two layers of ghost faces beyond every boundary give the scatter
//! the odd reflections the patches use as phantoms (docs/real-meshes.md).

use super::{add3, one_ring, sub3, vertex_rule_weights, Base, Numbering, Plan, Spot};
use crate::features::{Resolved, VertexRule};
use crate::mesh::QuadMesh;
use crate::real::Real;
use crate::topology::Topology;
use std::collections::HashMap;

/// A mesh cut open along the edges sharp at its first step, for the reference driver's step
/// with ghost faces ([`Ghosts`]): each vertex gets one copy per sector (faces between sharp
/// edges), so a crease is a boundary for both sides. `source[i]` is the vertex copy i came
/// from; the faces are the mesh's, in order.
pub(super) struct Cut {
    pub(super) topo: Topology,
    pub(super) source: Vec<u32>,
    /// The 1D plan of the step (no ring): new points 0..=N' of an old interval from the
    /// points −1..=2 around it.
    pub(super) line: Plan,
    /// Per edge sharp at step 0: the edge, its ends a and b, and the vertex beyond each end
    /// along the sharp line through it (none: the reflection 2a − b).
    sharp: Vec<(u32, [u32; 2], [Option<u32>; 2])>,
    /// The darts: smooth vertices with a sharp edge.
    darts: Vec<u32>,
}

impl Cut {
    /// The cut of `topo` (none if it is not a manifold). At a dart (one sharp edge at an
    /// interior vertex) the cut is at most a slit: the dart keeps one copy, whose child
    /// [`Cut::curves`] sets by the smooth rule.
    pub(super) fn new(topo: &Topology, features: &Resolved, line: Plan) -> Option<Cut> {
        let mut faces = topo.faces().to_vec();
        let mut source: Vec<u32> = (0..topo.vertex_count() as u32).collect();
        for v in 0..topo.vertex_count() as u32 {
            let sharp = features.sharp_spokes(topo, v, 0);
            let interior = !topo.is_boundary(v);
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
            for (w, wedge) in topo.rotation(v).iter().enumerate() {
                seen += usize::from(sharp[w]);
                let sector = (seen + count - 1) % count;
                if sector > 0 {
                    faces[wedge.face as usize][wedge.corner as usize] =
                        first_copy + sector as u32 - 1;
                }
            }
        }
        let mesh = QuadMesh {
            positions: vec![[0.0f64; 3]; source.len()],
            faces,
        };
        let cut = Topology::build(&mesh).ok()?;
        // Each vertex's rule, resolved once (an end of many sharp edges is met once per edge).
        let rules: Vec<VertexRule> = (0..topo.vertex_count() as u32)
            .map(|v| features.vertex_rule(topo, v, 0))
            .collect();
        // The vertex beyond a, away from b, along the sharp line through a (edge e).
        let beyond = |a: u32, e: u32| {
            let next = match rules[a as usize] {
                VertexRule::Crease => topo
                    .spokes(a)
                    .find(|&s| s != e && features.edge_sharp(s, 0)),
                VertexRule::Smooth if topo.valence(a) == 4 && !topo.is_boundary(a) => {
                    let spokes: Vec<u32> = topo.spokes(a).collect();
                    spokes
                        .iter()
                        .position(|&s| s == e)
                        .map(|i| spokes[(i + 2) % 4])
                }
                _ => None,
            };
            next.map(|s| topo.other_end(s, a))
        };
        let sharp = (0..topo.edge_count() as u32)
            .filter(|&e| features.edge_sharp(e, 0))
            .map(|e| {
                let [a, b] = topo.edge_vertices(e);
                (e, [a, b], [beyond(a, e), beyond(b, e)])
            })
            .collect();
        let darts = (0..topo.vertex_count() as u32)
            .filter(|&v| {
                rules[v as usize] == VertexRule::Smooth
                    && features.sharp_spokes(topo, v, 0).contains(&true)
            })
            .collect();
        Some(Cut {
            topo: cut,
            source,
            line,
            sharp,
            darts,
        })
    }

    /// After the step: every point on a line sharp at step 0 set to the scheme's curve
    /// refinement of that line (a boundary is the scheme's curve, docs/real-meshes.md), the
    /// 1D plan on the points along it: beyond a crease vertex the line continues along its
    /// other sharp edge, beyond a dart of valence 4 straight on (the line is sharp, the vertex
    /// smooth, as in OpenSubdiv), elsewhere it is odd-reflected. A dart's child is its smooth
    /// rule on its 1-ring ([`dart_child`]). The scatter near a boundary EV drops the entries
    /// that pass through it; on the lines, the principle decides.
    pub(super) fn curves<T: Real>(
        &self,
        base: &Base<'_>,
        (alpha, ring): (&dyn Fn(u32) -> f64, [f64; 2]),
        positions: &[[f64; 3]],
        num: &Numbering,
        start: &mut [[T; 3]],
    ) {
        let at = |v: u32| positions[v as usize];
        let n = self.line.n_new;
        let k = (n - 1) as usize;
        for &(e, [a, b], [beyond_a, beyond_b]) in &self.sharp {
            let beyond = |v: Option<u32>, a: u32, b: u32| match v {
                Some(v) => at(v),
                None => std::array::from_fn(|i| 2.0 * at(a)[i] - at(b)[i]),
            };
            let old = [beyond(beyond_a, a, b), at(a), at(b), beyond(beyond_b, b, a)];
            for (xn, row) in self.line.rows.iter().enumerate() {
                let mut p = [0.0f64; 3];
                for &(x, w) in &self.line.parents[row.clone()] {
                    for (o, q) in p.iter_mut().zip(old[x]) {
                        *o += w * q;
                    }
                }
                let i = match xn as i64 {
                    0 => a as usize,
                    x if x == n => b as usize,
                    x => num.nv + e as usize * k + x as usize - 1,
                };
                start[i] = p.map(T::from_f64);
            }
        }
        for &v in &self.darts {
            let rule = (alpha(v), ring);
            start[v as usize] =
                dart_child(base.topo, &self.line, rule, positions, v).map(T::from_f64);
        }
    }
}

/// The child of a dart v (a smooth interior vertex with one sharp edge) by the smooth rule on
/// its 1-ring of base positions ([`one_ring`]): the tensor product of the vertex mask at
/// valence 4, the EV rule with `rule` = (α, [E1, E2]) at other valences.
fn dart_child(
    topo: &Topology,
    line: &Plan,
    rule: (f64, [f64; 2]),
    positions: &[[f64; 3]],
    v: u32,
) -> [f64; 3] {
    let rule = if topo.valence(v) == 4 {
        vertex_rule_weights(line)
    } else {
        rule
    };
    one_ring(topo, v, rule, |_, w, spot| {
        let c = match spot {
            Spot::Centre => w.corner,
            Spot::Spoke if w.next_is_plus => (w.corner + 3) % 4,
            Spot::Spoke => (w.corner + 1) % 4,
            Spot::Diagonal => (w.corner + 2) % 4,
        };
        positions[topo.vertex(w.face, c) as usize]
    })
}

/// The mesh extended past its boundary by two layers of ghost faces, for a step of the
/// reference driver on an open mesh whose boundary vertices have two faces, or one (a corner):
/// across each boundary edge a → b of face (a, b, c, d) the quads (b, a, a₁, b₁) and
/// (b₁, a₁, a₂, b₂), with a₁ = 2a − d, b₁ = 2b − c (the odd reflection the patches use; a
/// vertex with two faces shares its ghosts between its two boundary edges) and a₂ = 3a − 2d;
/// at a corner, the four quads of the diagonal quadrant, the first at the double reflection
/// 4a − 2b − 2d + c. The outer layer only makes the first one's vertices interior and
/// ordinary: in a complete step (every patch's new ring has its parents in the old ring) its
/// points reach no real new point, and the driver does not scatter them. Real vertices and
/// faces keep their indices; the ghosts follow. Found once ([`Ghosts::new`]); each refine
/// only makes the ghosts' points ([`Ghosts::extend`]).
#[derive(Default)]
pub(super) struct Ghosts {
    /// The ghosts in the order they are made, each from points made before it.
    made: Vec<Ghost>,
}

/// How ghosts are made ([`Ghosts`]).
pub(super) enum Ghost {
    /// a₁ = 2a − p and a₂ = 3a − 2p, from [a, p].
    Pair([u32; 2]),
    /// A corner's diagonal quadrant from its face [a, b, c, d] and its ghosts [g_out, g_in]
    /// across its outgoing and incoming boundary edges.
    Corner([u32; 4], [u32; 2]),
}

impl Ghosts {
    /// The ghost layers of `topo`: how the ghosts are made, the extended mesh's quads, and
    /// its outer ghosts (per point of the extended mesh).
    pub(super) fn new(topo: &Topology) -> (Ghosts, Vec<[u32; 4]>, Vec<bool>) {
        let mut ghosts = Ghosts::default();
        let mut next = topo.vertex_count() as u32;
        let mut faces = topo.faces().to_vec();
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
                    next += 2;
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
                faces.push([b1, a1, a1 + 1, b1 + 1]);
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
            let (d11, d21, d12, d22) = (next, next + 1, next + 2, next + 3);
            next += 4;
            diagonals.push(d11);
            faces.push([g_out, a, g_in, d11]);
            faces.push([g_out + 1, g_out, d11, d21]);
            faces.push([d11, g_in, g_in + 1, d12]);
            faces.push([d21, d11, d12, d22]);
        }
        // The outer layer: every a₂ (a ghost pair's second) and each corner's outer three.
        let mut outer = vec![false; next as usize];
        for &g in shared.values().chain(&pairs) {
            outer[g as usize + 1] = true;
        }
        for &d11 in &diagonals {
            outer[d11 as usize + 1..d11 as usize + 4].fill(true);
        }
        (ghosts, faces, outer)
    }

    /// Bytes it holds.
    pub(super) fn bytes(&self) -> usize {
        self.made.capacity() * size_of::<Ghost>()
    }

    /// Appends the ghosts' points to the mesh's `points`, in the order [`Ghosts::new`] made
    /// them.
    pub(super) fn extend(&self, points: &mut Vec<[f64; 3]>) {
        for ghost in &self.made {
            match *ghost {
                Ghost::Pair([a, p]) => {
                    let (pa, pp) = (points[a as usize], points[p as usize]);
                    points.push(std::array::from_fn(|i| 2.0 * pa[i] - pp[i]));
                    points.push(std::array::from_fn(|i| 3.0 * pa[i] - 2.0 * pp[i]));
                }
                Ghost::Corner(face, [g_out, g_in]) => {
                    let [pa, pb, pc, pd] = face.map(|v| points[v as usize]);
                    let g = |i: u32| points[i as usize];
                    let d11: [f64; 3] =
                        std::array::from_fn(|i| 4.0 * pa[i] - 2.0 * pb[i] - 2.0 * pd[i] + pc[i]);
                    let along_out = sub3(g(g_out + 1), g(g_out));
                    let along_in = sub3(g(g_in + 1), g(g_in));
                    let d21 = add3(d11, along_out);
                    points.extend([d11, d21, add3(d11, along_in), add3(d21, along_in)]);
                }
            }
        }
    }
}
