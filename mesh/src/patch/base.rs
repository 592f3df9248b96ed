//! The base mesh as the patches see it: its topology and resolved features, and per face the
//! rules of each step (\[G\] §2.2 with docs/real-meshes.md): which corners are EVs or take a
//! vertex rule, which sides are sharp, and the phantoms (odd reflections 2P − Q) that stand
//! for the ring across a sharp edge or at a corner without a diagonal.

use super::handoff::CornerPoint;
use super::{patch_len, Layout, STACK_FACES, STACK_FACES_APART};
use crate::features::{CornerKind, Resolved, VertexRule};
use crate::grid::{corner_at, TOWARD_NEXT, TOWARD_PREV};
use crate::real::Real;
use crate::surface::SurfaceError;
use crate::topology::Topology;

/// Base-mesh connectivity the patches need: the topology and its features, and per face
/// corner the diagonal corner across an ordinary interior vertex, packed as face·4 + corner
/// (`u32::MAX`: none).
pub(super) struct Base<'t> {
    pub(super) topo: &'t Topology,
    pub(super) features: Resolved,
    diagonal: Vec<[u32; 4]>,
    /// Vertices whose child is set by their vertex rule after some step (interior EVs, and
    /// the boundary and crease configurations the patches alone do not give).
    pub(super) special: Vec<u32>,
    /// Per vertex: its faces are refined in lock-step (special, or its sharpness changes).
    pub(super) lockstep: Vec<bool>,
    /// Per vertex: its place in `special` (`u32::MAX` if it is not special).
    pub(super) special_at: Vec<u32>,
    /// Some face corner has no diagonal ring point at some step ([`CornerKind::Ev`]): the
    /// depth-first steps need masks contained there (\[G\] Prop. 4.8).
    pub(super) needs_containment: bool,
    /// Per step k < `decided` (the rules of the last hold for every later step), per face:
    /// its [`FaceRules`], at `k · F + f`. Resolved once here, so that setting a patch's
    /// phantoms reads eight bytes instead of walking the corners' rotations.
    pub(super) rules: Vec<FaceRules>,
    /// Per step k < `decided`, per special vertex (at `k · special.len() + i`): its vertex
    /// rule if its child needs it after step k.
    pub(super) vertex_rules: Vec<Option<VertexRule>>,
    /// Per (special vertex, step) where its rule changes with a fractional weight: the next
    /// rule and its weight ([`Base::transition`]).
    transitions: std::collections::HashMap<(u32, usize), (VertexRule, f64)>,
    decided: usize,
}

/// What a face's phantom points at a step are made from: which of its edges are sharp, and
/// what holds the ring point diagonal to each corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FaceRules {
    sharp: [bool; 4],
    /// Per sharp edge, how much of the sharp rule it takes ([`Resolved::edge_weight`]): its
    /// ring row is w·(2P − Q) + (1 − w)·R, R the real row (1: the odd reflection alone).
    weight: [f32; 4],
    pub(super) corners: [CornerKind; 4],
}

impl FaceRules {
    /// No phantom: no edge sharp, every diagonal a real point.
    fn is_plain(&self) -> bool {
        self.sharp == [false; 4] && self.corners == [CornerKind::Real; 4]
    }

    /// Whether the ring across local edge l is the odd reflection alone (nothing of the
    /// real ring across it is read).
    pub(super) fn reflects(&self, l: u8) -> bool {
        self.sharp[l as usize] && self.weight[l as usize] >= 1.0
    }

    /// A phantom other than an EV corner's missing diagonal: an edge sharp, or a corner set
    /// by its kind.
    pub(super) fn has_phantoms_beside_evs(&self) -> bool {
        let set = |c: &CornerKind| !matches!(c, CornerKind::Real | CornerKind::Ev);
        self.sharp.contains(&true) || self.corners.iter().any(set)
    }
}

impl<'t> Base<'t> {
    pub(super) fn new(
        topo: &'t Topology,
        features: Resolved,
        steps: usize,
    ) -> Result<Base<'t>, SurfaceError> {
        topo.check_valences()?;
        // Vertex by vertex, each wedge's corner across an ordinary interior vertex.
        let mut diagonal = vec![[u32::MAX; 4]; topo.face_count()];
        for v in 0..topo.vertex_count() as u32 {
            let rot = topo.rotation(v);
            if rot.len() == 4 && !topo.is_boundary(v) {
                for (i, w) in rot.iter().enumerate() {
                    let d = rot[(i + 2) % 4];
                    diagonal[w.face as usize][w.corner as usize] = d.face * 4 + u32::from(d.corner);
                }
            }
        }
        // Sharpness changes only in the first `changing_steps` steps: the rules of the last
        // of them hold for every later step.
        let decided = steps.min(features.changing_steps() + 1).max(1);
        let nv = topo.vertex_count() as u32;
        let plain = features.is_plain();
        // On a plain mesh the special vertices are the EVs, without resolving every rule.
        let special: Vec<u32> = (0..nv)
            .filter(|&v| {
                if plain {
                    topo.valence(v) != 4
                } else {
                    (0..decided).any(|k| features.needs_rule(topo, v, k))
                }
            })
            .collect();
        let mut lockstep = vec![false; nv as usize];
        let mut special_at = vec![u32::MAX; nv as usize];
        for (i, &v) in special.iter().enumerate() {
            lockstep[v as usize] = true;
            special_at[v as usize] = i as u32;
        }
        for v in (0..nv).filter(|_| !plain) {
            if features.changes_at(topo, v) {
                lockstep[v as usize] = true;
            }
        }
        // Per step, each face's sharp sides, and its corners' kinds vertex by vertex.
        let faces = topo.face_count();
        let mut rules = Vec::with_capacity(decided * faces);
        for k in 0..decided {
            rules.extend((0..faces as u32).map(|f| {
                let weight = [0, 1, 2, 3].map(|l| features.edge_weight(topo.edge_of(f, l), k));
                FaceRules {
                    sharp: weight.map(|w| w > 0.0),
                    weight: weight.map(|w| w as f32),
                    corners: [CornerKind::Real; 4],
                }
            }));
            let step = &mut rules[k * faces..];
            for v in 0..nv {
                for (w, kind) in topo
                    .rotation(v)
                    .iter()
                    .zip(features.corner_kinds(topo, v, k))
                {
                    step[w.face as usize].corners[w.corner as usize] = kind;
                }
            }
        }
        let vertex_rules = (0..decided)
            .flat_map(|k| {
                let features = &features;
                special.iter().map(move |&v| {
                    features
                        .needs_rule(topo, v, k)
                        .then(|| features.vertex_rule(topo, v, k))
                })
            })
            .collect();
        // Where a vertex's rule changes across a step with a fractional weight.
        let transitions = (0..decided)
            .flat_map(|k| {
                let features = &features;
                special.iter().filter_map(move |&v| {
                    let t = features.transition(topo, v, k)?;
                    Some(((v, k), t))
                })
            })
            .collect();
        // A plain mesh's corners lack their diagonal exactly at its EVs.
        let needs_containment = if plain {
            !special.is_empty()
        } else {
            rules.iter().any(|r| r.corners.contains(&CornerKind::Ev))
        };
        Ok(Base {
            topo,
            features,
            diagonal,
            special,
            lockstep,
            special_at,
            needs_containment,
            rules,
            vertex_rules,
            transitions,
            decided,
        })
    }

    /// Vertex v's α among `alphas` (one per special vertex), 0 where it is not special.
    pub(super) fn alpha(&self, alphas: &[f64], v: u32) -> f64 {
        alphas
            .get(self.special_at[v as usize] as usize)
            .copied()
            .unwrap_or(0.0)
    }

    /// Where special vertex v's rule changes across step k with a fractional weight: the
    /// rule of step k + 1 and its weight ([`Resolved::transition`]).
    pub(super) fn transition(&self, v: u32, k: usize) -> Option<(VertexRule, f64)> {
        if self.transitions.is_empty() {
            return None;
        }
        self.transitions.get(&(v, k)).copied()
    }

    /// The rule of each special vertex whose child needs it after step k.
    pub(super) fn vertex_rules(&self, k: usize) -> &[Option<VertexRule>] {
        let k = k.min(self.decided - 1);
        &self.vertex_rules[k * self.special.len()..][..self.special.len()]
    }

    /// Face f's rules at step k.
    pub(super) fn rules(&self, f: u32, k: usize) -> FaceRules {
        let k = k.min(self.decided - 1);
        self.rules[k * self.topo.face_count() + f as usize]
    }

    /// The face across local edge l of face f, its local edge, and whether the parameter runs
    /// backwards there; none across a boundary edge.
    pub(super) fn across(&self, f: u32, l: u8) -> Option<(u32, u8, bool)> {
        let (g, gl) = self.topo.across(f, l)?;
        Some((g, gl, self.topo.vertex(f, l) != self.topo.vertex(g, gl)))
    }

    /// The diagonal (face, corner) across corner c of face f when that vertex is an ordinary
    /// interior vertex.
    pub(super) fn diagonal(&self, f: u32, c: u8) -> Option<(u32, u8)> {
        let d = self.diagonal[f as usize][c as usize];
        (d != u32::MAX).then_some((d / 4, (d % 4) as u8))
    }

    /// Whether face g stacks on face f for the composed kernel at start step k (`composed`,
    /// `Faces::load`): g's edge 0 is f's edge 2 in the same direction (g's corners 0 and 1
    /// are f's corners 3 and 2), and neither has a phantom, so that g's start patch is f's
    /// moved up by N₀ rows.
    fn stacks(&self, f: u32, g: u32, k: usize) -> bool {
        let t = self.topo;
        t.across(f, 2) == Some((g, 0))
            && (t.vertex(g, 0), t.vertex(g, 1)) == (t.vertex(f, 3), t.vertex(f, 2))
            && self.rules(f, k).is_plain()
            && self.rules(g, k).is_plain()
    }

    /// The faces of `ordinary` (in their order) in chains of faces each stacking on the one
    /// before ([`Base::stacks`]), at most [`STACK_FACES`] long ([`STACK_FACES_APART`] if not
    /// consecutive in the order), each chain through the first face not yet taken, up from it
    /// or, if it cannot go up, down: a grid's faces in stacks whichever way their order runs
    /// (along y: consecutive faces; along x: a column at a time, a band of rows after the
    /// other). Also per face: whether the next one stacks on it.
    pub(super) fn chains(&self, ordinary: &[u32], k: usize) -> (Vec<u32>, Vec<bool>) {
        let nf = self.topo.face_count();
        let mut free = vec![false; nf];
        for &f in ordinary {
            free[f as usize] = true;
        }
        let (mut order, mut stacks) = (Vec::with_capacity(ordinary.len()), Vec::new());
        let mut chain = Vec::with_capacity(STACK_FACES);
        for &f in ordinary {
            if !std::mem::replace(&mut free[f as usize], false) {
                continue;
            }
            chain.clear();
            chain.push(f);
            // Up from f (across edge 2): a chain of faces that follow each other in the order
            // writes one run, and may be as long as the kernel takes.
            let mut consecutive = true;
            while let Some(&top) = chain.last() {
                let Some((g, 0)) = self.topo.across(top, 2) else {
                    break;
                };
                consecutive &= g == top + 1;
                let most = if consecutive {
                    STACK_FACES
                } else {
                    STACK_FACES_APART
                };
                if !free[g as usize] || chain.len() >= most || !self.stacks(top, g, k) {
                    break;
                }
                free[g as usize] = false;
                chain.push(g);
            }
            // Else down from f (across edge 0), where the faces' y runs against the order.
            if chain.len() == 1 {
                while chain.len() < STACK_FACES_APART {
                    let Some((h, 2)) = self.topo.across(chain[0], 0) else {
                        break;
                    };
                    if !free[h as usize] || !self.stacks(h, chain[0], k) {
                        break;
                    }
                    free[h as usize] = false;
                    chain.insert(0, h);
                }
            }
            order.extend_from_slice(&chain);
            stacks.extend((1..=chain.len()).map(|i| i < chain.len()));
        }
        (order, stacks)
    }

    /// Whether face f is refined depth first on its own: no corner at a lock-step vertex.
    pub(super) fn ordinary(&self, f: u32) -> bool {
        (0..4).all(|c| !self.lockstep[self.topo.vertex(f, c) as usize])
    }

    /// Points t = 0..=N of face f's ring across its local edge l (which runs from corner l to
    /// l+1; side N): each one's place in f's frame, and the (face, x, y) that owns it, one
    /// step inside the neighbour (none across a boundary edge).
    pub(super) fn ring(&self, f: u32, l: u8, n: i64) -> impl Iterator<Item = RingPoint> {
        let (cx, cy) = corner_at(l, n, n);
        let (dx, dy) = TOWARD_NEXT[l as usize];
        // Outward normal of edge l: the opposite of the step toward corner l−1.
        let (ox, oy) = TOWARD_PREV[l as usize];
        let across = self.across(f, l);
        (0..=n).map(move |t| {
            let owner = across.map(|(g, gl, back)| {
                let u = if back { n - t } else { t };
                let (gx, gy) = inward_xy(gl, u, 1, n);
                (g, gx, gy)
            });
            ((cx + t * dx - ox, cy + t * dy - oy), owner)
        })
    }

    /// The phantom points of face f's patch (side N) at step k, in the order they must be
    /// computed: the ring across every edge sharp at step k is the odd reflection of the
    /// face (2P − Q, P on the edge), then each corner's diagonal by its [`CornerKind`].
    fn phantoms(&self, f: u32, n: i64, k: usize, mut each: impl FnMut(Phantom)) {
        let rules = self.rules(f, k);
        if rules.is_plain() {
            return;
        }
        for l in 0..4u8 {
            if !rules.sharp[l as usize] {
                continue;
            }
            let (ix, iy) = TOWARD_PREV[l as usize];
            let w = f64::from(rules.weight[l as usize]);
            for ((x, y), _) in self.ring(f, l, n) {
                let on = (x + ix, y + iy);
                let inside = (on.0 + ix, on.1 + iy);
                if w < 1.0 {
                    each(Phantom::new(
                        (x, y),
                        &[(on, 2.0 * w), (inside, -w), ((x, y), 1.0 - w)],
                    ));
                } else {
                    each(Phantom::new((x, y), &[(on, 2.0), (inside, -1.0)]));
                }
            }
        }
        for c in 0..4u8 {
            let at = |i: i8, j: i8| CornerPoint::new(c, i, j).xy(n);
            let terms: &[((i64, i64), f64)] = match rules.corners[c as usize] {
                CornerKind::Real => continue,
                CornerKind::Ev => &[],
                CornerKind::Both => &[
                    (at(0, 0), 4.0),
                    (at(1, 0), -2.0),
                    (at(0, 1), -2.0),
                    (at(1, 1), 1.0),
                ],
                // The edge toward corner c − 1 (along b) is sharp: reflect the ring across
                // edge c (the row j = −1) over the line i = 0.
                CornerKind::OneSide(true) => &[(at(0, -1), 2.0), (at(1, -1), -1.0)],
                CornerKind::OneSide(false) => &[(at(-1, 0), 2.0), (at(-1, 1), -1.0)],
            };
            each(Phantom::new(at(-1, -1), terms));
        }
    }
}

impl Base<'_> {
    /// Sets the phantom points of face f's patch (side N, for step k) in `buf`; nothing
    /// where the face has none ([`FaceRules::is_plain`]).
    pub(super) fn load_phantoms<T: Real>(
        &self,
        (f, n, k): (u32, i64, usize),
        layout: Layout,
        buf: &mut [T],
    ) {
        self.phantoms(f, n, k, |p| p.apply(layout, buf));
    }

    /// After a step, the ring of lock-step face f (side N, `layout`) from its lock-step
    /// neighbours' new patches: every row across an edge not sharp at step k, and the
    /// diagonal across each ordinary interior corner. Rows toward faces that are not in
    /// lock-step keep the values f's own step gave them (exact there: nothing at those points
    /// changes between steps). On a mesh without features, or where f had no phantom but its
    /// EV corners' diagonals in the step before, f's own step gives every ring point but the
    /// two next to each EV corner (its diagonal is missing, and with contained masks it
    /// reaches only those and the EV child, \[G\] Prop. 4.8): only those are copied.
    pub(super) fn refresh_ring<T: Real>(
        &self,
        (f, n, k): (u32, i64, usize),
        layout: Layout,
        slot: &[u32],
        patches: &[T],
        put: &mut impl FnMut(usize, [T; 3]),
    ) {
        let patches = (patches, patch_len(n));
        // Point (x, y) of a lock-step face's patch, as its offset.
        let at = |(x, y): (i64, i64)| layout.at(x, y) as isize;
        let rules = self.rules(f, k);
        // Each edge's ring row is the row next to the edge in the face across: both run with
        // a constant step, so the row is copied point by point at two strides. The points
        // read are inside their face and those written outside f, so none is both.
        // A face with no phantom beside its EV corners' diagonals in the step just taken
        // (k − 1; nor after it: sharpness only decays) computed its whole new ring itself, as
        // on a mesh without features, but the two points next to each EV corner.
        let plain = self.features.is_plain() || !self.rules(f, k - 1).has_phantoms_beside_evs();
        let ev = |c: u8| self.lockstep[self.topo.vertex(f, c % 4) as usize];
        for l in 0..4u8 {
            let Some((g, gl, back)) = self.across(f, l).filter(|_| !rules.reflects(l)) else {
                continue;
            };
            let (cx, cy) = corner_at(l, n, n);
            let ((dx, dy), (ox, oy)) = (TOWARD_NEXT[l as usize], TOWARD_PREV[l as usize]);
            let to_at = |t: i64| at((cx + t * dx - ox, cy + t * dy - oy));
            let from_at = |t: i64| at(inward_xy(gl, if back { n - t } else { t }, 1, n));
            let row = |(t, count): (i64, i64)| {
                let (from, to) = (from_at(t), to_at(t));
                let steps = (from_at(t + 1) - from, to_at(t + 1) - to);
                ((g, from, steps.0), (to, steps.1), count)
            };
            if !plain {
                let (from, to, count) = row((0, n + 1));
                copy_points(patches, slot, from, to, count, put);
                continue;
            }
            for t in [(ev(l), 0), (ev(l + 1), n)].into_iter().filter(|e| e.0) {
                let (from, to, count) = row((t.1, 1));
                copy_points(patches, slot, from, to, count, put);
            }
        }
        for c in (0..4u8).filter(|_| !plain) {
            let (Some((g, gc)), CornerKind::Real) =
                (self.diagonal(f, c), rules.corners[c as usize])
            else {
                continue;
            };
            // g's point diagonal to its corner gc, to f's ring point diagonal to corner c.
            let from = at(CornerPoint::new(gc, 1, 1).xy(n));
            let to = at(CornerPoint::new(c, -1, -1).xy(n));
            copy_points(patches, slot, (g, from, 0), (to, 0), 1, put);
        }
    }
}

/// Hands `count` points of face g's patch (offset `from`, then every `from_step` values; the
/// level's patches one after the other, `len` values each) to `put` with their offsets in the
/// patch being refreshed (`at`, then every `to_step`); nothing if g is not in lock-step (no
/// slot).
fn copy_points<T: Copy>(
    (patches, len): (&[T], usize),
    slot: &[u32],
    (g, from, from_step): (u32, isize, isize),
    (at, to_step): (isize, isize),
    count: i64,
    put: &mut impl FnMut(usize, [T; 3]),
) {
    let Some(&src) = slot.get(g as usize).filter(|&&s| s != u32::MAX) else {
        return;
    };
    let patch = &patches[src as usize * len..][..len];
    for t in 0..count as isize {
        let (i, j) = ((from + t * from_step) as usize, (at + t * to_step) as usize);
        put(j, [patch[i], patch[i + 1], patch[i + 2]]);
    }
}

/// A ring point of a face: (x, y) in that face, and (face, x, y) of its owner (none across a
/// boundary).
type RingPoint = ((i64, i64), Option<(u32, i64, i64)>);

/// A point of a patch that is an affine combination of other points of the same patch (a
/// phantom across a sharp edge, or a corner's diagonal), or zero with no terms.
#[derive(Clone, Copy, Debug)]
struct Phantom {
    at: (i64, i64),
    terms: [((i64, i64), f64); 4],
    len: u8,
}

impl Phantom {
    fn new(at: (i64, i64), terms: &[((i64, i64), f64)]) -> Phantom {
        let mut t = [((0, 0), 0.0); 4];
        t[..terms.len()].copy_from_slice(terms);
        Phantom {
            at,
            terms: t,
            len: terms.len() as u8,
        }
    }

    /// Sets the point in the patch `buf` (in `layout`).
    fn apply<T: Real>(&self, layout: Layout, buf: &mut [T]) {
        let mut p = [T::default(); 3];
        for &((x, y), w) in &self.terms[..self.len as usize] {
            let i = layout.at(x, y);
            for (o, q) in p.iter_mut().zip(&buf[i..i + 3]) {
                *o += T::from_f64(w) * *q;
            }
        }
        let i = layout.at(self.at.0, self.at.1);
        buf[i..i + 3].copy_from_slice(&p);
    }
}

/// The point `inward` steps into a face from its local edge `gl`, at parameter u along that
/// edge (from corner gl), in the face's frame (side N).
fn inward_xy(gl: u8, u: i64, inward: i64, n: i64) -> (i64, i64) {
    match gl {
        0 => (u, inward),
        1 => (n - inward, u),
        2 => (n - u, n - inward),
        _ => (inward, n - u),
    }
}
