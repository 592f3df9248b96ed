//! The children of special vertices after a step: a corner stays, a crease vertex takes its
//! curve's rule along its two sharp edges, an EV its 1-ring rule
//! (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)) (\[G\] §3), an ordinary smooth vertex
//! the tensor vertex mask.

use super::handoff::CornerPoint;
use super::{Base, Plan};
use crate::features::VertexRule;
use crate::grid::{corner_at, TOWARD_NEXT, TOWARD_PREV};
use crate::real::Real;
use crate::topology::Topology;

/// The child of special vertex v by its rule after step k (`plan`, the EVs' 1-ring weights
/// `ring`), from the old level (side N) as `point(face, x, y)` reads it: a corner stays, a
/// crease takes its curve rule ([`crease_child`]), a smooth vertex its 1-ring rule (the
/// tensor vertex mask at valence 4, α's elsewhere, \[G\] §3). Where the rule changes across
/// the step with a fractional weight (OpenSubdiv's rule transition), the blend of the two.
pub(super) fn vertex_child<T: Real>(
    base: &Base<'_>,
    (v, rule, alpha): (u32, VertexRule, f64),
    (plan, ring, k): (&Plan, [f64; 2], usize),
    n: i64,
    point: impl Fn(u32, i64, i64) -> [T; 3],
) -> [T; 3] {
    let child =
        |rule, sharp_at| rule_child(base, (v, rule, alpha), (plan, ring, sharp_at), n, &point);
    match base.transition(v, k) {
        None => child(rule, k),
        Some((next, w)) => {
            let (a, b) = (child(rule, k), child(next, k + 1));
            std::array::from_fn(|i| T::from_f64((1.0 - w) * a[i].to_f64() + w * b[i].to_f64()))
        }
    }
}

/// The child of v by one rule, a crease's along the edges sharp at step `sharp_at`.
fn rule_child<T: Real>(
    base: &Base<'_>,
    (v, rule, alpha): (u32, VertexRule, f64),
    (plan, ring, sharp_at): (&Plan, [f64; 2], usize),
    n: i64,
    point: &impl Fn(u32, i64, i64) -> [T; 3],
) -> [T; 3] {
    let topo = base.topo;
    let spot = |_, w: crate::topology::Wedge, spot| {
        let (x, y) = CornerPoint::of_ring(w, spot).xy(n);
        point(w.face, x, y)
    };
    match rule {
        VertexRule::Corner => {
            let w = topo.rotation(v)[0];
            let (cx, cy) = corner_at(w.corner, n, n);
            point(w.face, cx, cy)
        }
        VertexRule::Crease => crease_child(base, plan, (v, sharp_at), n, point),
        VertexRule::Smooth if topo.valence(v) == 4 => {
            ev_child(topo, v, vertex_rule_weights(plan), spot)
        }
        VertexRule::Smooth => ev_child(topo, v, (alpha, ring), spot),
    }
}

/// The child of a crease vertex: the curve rule along its two sharp edges, the 1D plan's
/// weights for its new point X' = 0 (the mask of its word, which is a palindrome: the word
/// at a vertex of the symmetric W_s, \[G\] Cor. 4.4) on the points at distance |x| along
/// the two sharp edges of the old level (side N, `point(face, x, y)`).
fn crease_child<T: Real>(
    base: &Base<'_>,
    plan: &Plan,
    (v, k): (u32, usize),
    n: i64,
    point: &impl Fn(u32, i64, i64) -> [T; 3],
) -> [T; 3] {
    let rot = base.topo.rotation(v);
    let sharp = base.features.sharp_spokes(base.topo, v, k);
    let mut along = sharp.iter().enumerate().filter(|&(_, &s)| s).map(|(i, _)| {
        let (w, dir) = spoke(base.topo, v, i);
        (rot[w], dir)
    });
    let (behind, ahead) = (along.next(), along.next());
    let (Some(behind), Some(ahead)) = (behind, ahead) else {
        unreachable!("a crease vertex has two sharp edges");
    };
    let h = (plan.rows.len() - plan.n_new as usize - 1) / 2;
    let mut acc = [0.0f64; 3];
    for &(x, wt) in &plan.parents[plan.rows[h].clone()] {
        let x = x as i64 - 1;
        let (w, (dx, dy)) = if x < 0 { behind } else { ahead };
        let (cx, cy) = corner_at(w.corner, n, n);
        let p = point(w.face, cx + x.abs() * dx, cy + x.abs() * dy);
        for (a, q) in acc.iter_mut().zip(p) {
            *a += wt * q.to_f64();
        }
    }
    acc.map(T::from_f64)
}

/// Where a crease turns inside one face (its two sharp edges are sides of one face, as at a
/// boundary vertex with one face under edge-only): the new points near v along both edges,
/// each the curve's rule with the line continued along the other edge, where the face's
/// phantoms continue it straight on (a boundary is the scheme's curve, docs/real-meshes.md;
/// `Cut::curves` does the same at a reference step). Per point: its edge, its distance from v
/// (new level) and its value; only points whose masks reach past v. From the old level
/// (side N, `point(face, x, y)`), the plan of the step.
pub(super) fn turning_line<T: Real>(
    base: &Base<'_>,
    plan: &Plan,
    (v, k): (u32, usize),
    n: i64,
    point: &impl Fn(u32, i64, i64) -> [T; 3],
) -> Vec<(u32, i64, [T; 3])> {
    let topo = base.topo;
    let Some(w) = (topo.rotation(v).iter()).find(|w| {
        base.rules(w.face, k).corners[w.corner as usize] == crate::features::CornerKind::Both
    }) else {
        return Vec::new();
    };
    let c = w.corner as usize;
    let (cx, cy) = corner_at(w.corner, n, n);
    // The two sides at the corner: (edge, unit step from v).
    let sides = [
        (topo.edge_of(w.face, w.corner), TOWARD_NEXT[c]),
        (topo.edge_of(w.face, (w.corner + 3) % 4), TOWARD_PREV[c]),
    ];
    let h = (plan.rows.len() - plan.n_new as usize - 1) / 2;
    let mut out = Vec::new();
    for (i, &(edge, (dx, dy))) in sides.iter().enumerate() {
        let (_, (ox, oy)) = sides[1 - i];
        for t in 1..plan.n_new {
            let parents = &plan.parents[plan.rows[h + t as usize].clone()];
            if parents.iter().all(|&(x, _)| x > 0) {
                continue;
            }
            let mut acc = [0.0f64; 3];
            for &(x, wt) in parents {
                let x = x as i64 - 1;
                let (sx, sy) = if x < 0 { (ox, oy) } else { (dx, dy) };
                let p = point(w.face, cx + x.abs() * sx, cy + x.abs() * sy);
                for (a, q) in acc.iter_mut().zip(p) {
                    *a += wt * q.to_f64();
                }
            }
            out.push((edge, t, acc.map(T::from_f64)));
        }
    }
    out
}

/// The faces at v that hold the point at distance t from v along edge e (side N), each with
/// its place there.
pub(super) fn holders(
    topo: &Topology,
    (v, e, t): (u32, u32, i64),
    n: i64,
) -> impl Iterator<Item = (u32, (i64, i64))> + '_ {
    topo.rotation(v).iter().filter_map(move |w| {
        let c = w.corner;
        let (cx, cy) = corner_at(c, n, n);
        let (dx, dy) = if topo.edge_of(w.face, c) == e {
            TOWARD_NEXT[c as usize]
        } else if topo.edge_of(w.face, (c + 3) % 4) == e {
            TOWARD_PREV[c as usize]
        } else {
            return None;
        };
        Some((w.face, (cx + t * dx, cy + t * dy)))
    })
}

/// Spoke i of v's rotation (wedge i's previous edge; the last spoke of a boundary vertex is
/// the last wedge's next edge): the wedge that holds it, and the unit step along it from the
/// vertex in that wedge's face.
pub(super) fn spoke(topo: &Topology, v: u32, i: usize) -> (usize, (i64, i64)) {
    let rot = topo.rotation(v);
    let (w, prev) = if i < rot.len() {
        (i, true)
    } else {
        (rot.len() - 1, false)
    };
    let c = rot[w].corner as usize;
    let dir = if prev == rot[w].next_is_plus {
        TOWARD_PREV[c]
    } else {
        TOWARD_NEXT[c]
    };
    (w, dir)
}

/// Where a point of a vertex's 1-ring lies, seen from one wedge of its rotation.
#[derive(Clone, Copy)]
pub(super) enum Spot {
    /// The vertex.
    Centre,
    /// The far end of the wedge's edge shared with the previous wedge.
    Spoke,
    /// The wedge face's corner opposite the vertex.
    Diagonal,
}

impl Spot {
    /// Its place, seen from wedge k, in a vertex's 1-ring laid out in the order [`one_ring`]
    /// reads it: the vertex, then per wedge its spoke and its diagonal.
    pub(super) fn in_ring(self, k: usize) -> usize {
        match self {
            Spot::Centre => 0,
            Spot::Spoke => 1 + 2 * k,
            Spot::Diagonal => 2 + 2 * k,
        }
    }
}

/// The rule (α·P + Σ_k (E1·R_k + E2·D_k)) / (α + n(E1 + E2)) on v's 1-ring, `point(w, spot)`
/// reading it: the EV child (\[G\] §3) with `(α, [E1, E2])` from the tables, and the
/// tensor-product vertex rule at valence 4 with [`vertex_rule_weights`].
pub(super) fn one_ring(
    topo: &Topology,
    v: u32,
    (alpha, ring): (f64, [f64; 2]),
    point: impl Fn(usize, crate::topology::Wedge, Spot) -> [f64; 3],
) -> [f64; 3] {
    let rot = topo.rotation(v);
    let mut acc = point(0, rot[0], Spot::Centre).map(|x| alpha * x);
    for (k, &w) in rot.iter().enumerate() {
        for (spot, weight) in [(Spot::Spoke, ring[0]), (Spot::Diagonal, ring[1])] {
            for (a, x) in acc.iter_mut().zip(point(k, w, spot)) {
                *a += weight * x;
            }
        }
    }
    let norm = alpha + rot.len() as f64 * (ring[0] + ring[1]);
    acc.map(|a| a / norm)
}

/// The tensor product of the vertex mask (the plan's new point 0 from old points 0 and ±1, a
/// palindrome) as [`one_ring`] weights: (w0², [w0·w1, w1²]).
pub(super) fn vertex_rule_weights(plan: &Plan) -> (f64, [f64; 2]) {
    let h = (plan.rows.len() - plan.n_new as usize - 1) / 2;
    let weight = |x: usize| {
        plan.parents[plan.rows[h].clone()]
            .iter()
            .find(|&&(i, _)| i == x)
            .map_or(0.0, |&(_, w)| w)
    };
    let (w0, w1) = (weight(1), weight(2));
    (w0 * w0, [w0 * w1, w1 * w1])
}

/// The child of v from its old 1-ring ([`one_ring`]), `point(k, wedge, spot)` reading it
/// (from the old level's patches, the level before's points, or the handoff's box).
pub(super) fn ev_child<T: Real>(
    topo: &Topology,
    v: u32,
    rule: (f64, [f64; 2]),
    point: impl Fn(usize, crate::topology::Wedge, Spot) -> [T; 3],
) -> [T; 3] {
    let child = one_ring(topo, v, rule, |k, w, spot| {
        point(k, w, spot).map(|c| c.to_f64())
    });
    child.map(T::from_f64)
}
