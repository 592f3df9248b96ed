//! What the fan faces read from each other between two lock-step levels (`Refiner::fan_faces`):
//! each EV's old 1-ring, for its child (\[G\] §3), and, for a face without phantoms beside its EV
//! corners' diagonals, per EV corner the two new ring points next to it, which the face's own step
//! cannot give (its diagonal is missing; with contained masks it reaches only those and the EV
//! child, \[G\] Prop. 4.8). Read from the neighbours' patches after the step, these were cache
//! misses (a quarter of the time on a triangle mesh, every face at an EV, and 13 % on the open one:
//! `perf`, the history of docs/benchmarks.md). Here each face's worker pushes them into one small box right after
//! the face's step, while both of its patches are in cache, and the EV children and the rings read
//! the box in order. The same values are copied and summed in the same order: the same bits. A face
//! with other phantoms (an edge sharp, a corner set by its kind) takes whole rows from its
//! neighbours and makes its phantoms from them (`Base::refresh_ring`).

use super::{Base, Layout, SharedOut, Spot};
use crate::features::CornerKind;
use crate::grid::{corner_at, TOWARD_NEXT, TOWARD_PREV};
use crate::real::Real;
use crate::topology::Wedge;

/// A point near corner c of a face (side N): the corner plus i steps toward corner c + 1 and
/// j steps toward corner c − 1.
#[derive(Clone, Copy, Debug)]
pub(super) struct CornerPoint {
    corner: u8,
    i: i8,
    j: i8,
}

impl CornerPoint {
    /// The point i steps from corner c toward corner c + 1 and j toward corner c − 1.
    pub(super) fn new(corner: u8, i: i8, j: i8) -> CornerPoint {
        CornerPoint { corner, i, j }
    }

    /// The point `spot` of a vertex's 1-ring in the face of wedge `w` ([`super::one_ring`]):
    /// the vertex at the wedge's corner, the spoke it shares with the wedge before (the edge
    /// not toward `next`), the diagonal.
    pub(super) fn of_ring(w: Wedge, spot: Spot) -> CornerPoint {
        let (i, j) = match spot {
            Spot::Centre => (0, 0),
            Spot::Spoke if w.next_is_plus => (0, 1),
            Spot::Spoke => (1, 0),
            Spot::Diagonal => (1, 1),
        };
        CornerPoint::new(w.corner, i, j)
    }

    /// Where it lies in a face of side N.
    pub(super) fn xy(self, n: i64) -> (i64, i64) {
        let c = self.corner as usize;
        let (cx, cy) = corner_at(self.corner, n, n);
        let ((ax, ay), (bx, by)) = (TOWARD_NEXT[c], TOWARD_PREV[c]);
        let (i, j) = (i64::from(self.i), i64::from(self.j));
        (cx + i * ax + j * bx, cy + i * ay + j * by)
    }

    /// Its place among the 36 points next to the corners ([`Offsets`]).
    fn index(self) -> usize {
        self.corner as usize * 9 + (self.i + 1) as usize * 3 + (self.j + 1) as usize
    }
}

/// The offsets of the points next to the four corners (i, j = −1..=1) in a patch of side N
/// stored in a layout: found once per level, not once per point handed on.
pub(super) struct Offsets([usize; 36]);

impl Offsets {
    pub(super) fn new(n: i64, layout: Layout) -> Offsets {
        Offsets(std::array::from_fn(|k| {
            let p = CornerPoint::new((k / 9) as u8, (k / 3 % 3) as i8 - 1, (k % 3) as i8 - 1);
            let (x, y) = p.xy(n);
            layout.at(x, y)
        }))
    }

    fn at(&self, p: CornerPoint) -> usize {
        self.0[p.index()]
    }
}

/// One point a face hands on: from its old patch (an EV's 1-ring) or its new one (a
/// neighbour's ring), to its place in the box.
#[derive(Clone, Copy, Debug)]
struct Give {
    from: CornerPoint,
    old: bool,
    to: u32,
}

/// Per fan face (by slot) the points it gives and the ring points it takes; per special
/// vertex where its 1-ring lies in the box.
pub(super) struct Handoff {
    /// Face slot s gives `gives[give_at[s]..give_at[s + 1]]`.
    give_at: Vec<u32>,
    gives: Vec<Give>,
    /// Face slot s takes its ring points `takes[take_at[s]..take_at[s + 1]]` from the box at
    /// the same indices.
    take_at: Vec<u32>,
    takes: Vec<CornerPoint>,
    /// Per face slot, its corners at an EV (bit c), whose diagonal ring point does not exist
    /// and is kept zero (the face's only phantoms, `Base::phantoms`).
    ev_corners: Vec<u8>,
    /// Per face slot, whether its own step gives its ring but the points it takes from the
    /// box ([`Handoff::take`]): no phantom beside its EV corners' diagonals from step 0 on
    /// (sharpness only decays).
    ring: Vec<bool>,
    /// Whether every face's is (a mesh without features, or one whose features are
    /// only away from the fan faces).
    rings: bool,
    /// Special vertex i's old 1-ring in the box from `ring_at[i]`: the vertex, then per wedge
    /// of its rotation the spoke shared with the wedge before and the diagonal.
    ring_at: Vec<u32>,
    /// Points in the box.
    len: usize,
}

/// Bytes a [`Handoff`] holds at most per fan face, its box included (`patch::footprint`): a
/// face takes two ring points per corner and gives them to its neighbours, and gives each of
/// its corners' vertices at most three points of the 1-ring; `point` bytes per point.
pub(super) fn bytes_per_fan_face(point: u128) -> u128 {
    let (takes, gives) = (8u128, 8 + 12);
    let tables = takes * size_of::<CornerPoint>() as u128 + gives * size_of::<Give>() as u128;
    // The two slot tables and the EV corners, where each special vertex's 1-ring starts (at
    // most one per wedge, four per face), and the box's points (every take and every 1-ring
    // point).
    tables + 2 * 4 + 1 + 4 * 4 + (takes + 12) * point
}

impl Handoff {
    /// The handoff of `fans` (fan faces, and each face's slot among them): the 1-rings, and
    /// the ring points of the faces without phantoms beside their EV corners' diagonals;
    /// `None` where a special vertex's face is not a fan face.
    pub(super) fn new(base: &Base<'_>, fans: &[u32], slot: &[u32]) -> Option<Handoff> {
        let topo = base.topo;
        let slot_of = |f: u32| slot.get(f as usize).copied().filter(|&s| s != u32::MAX);
        let mut gives: Vec<Vec<Give>> = vec![Vec::new(); fans.len()];
        // The rings: across edge l of face f, at each end whose vertex is in lock-step, the
        // point of the face g across one step inside from the shared edge.
        let (mut take_at, mut takes) = (vec![0u32], Vec::new());
        let (mut ev_corners, mut ring) = (Vec::with_capacity(fans.len()), Vec::new());
        for &f in fans {
            // A face with a phantom beside its EV corners' diagonals (on a mesh with
            // features) takes its ring from its neighbours' rows (`Base::refresh_ring`).
            let rules = base.rules(f, 0);
            let own = !rules.has_phantoms_beside_evs();
            ring.push(own);
            let evs = rules.corners.iter().enumerate();
            ev_corners.push(evs.fold(0u8, |e, (c, k)| e | (u8::from(*k == CornerKind::Ev) << c)));
            if !own {
                take_at.push(takes.len() as u32);
                continue;
            }
            let lockstep = |c: u8| base.lockstep[topo.vertex(f, c % 4) as usize];
            for l in 0..4u8 {
                let Some((g, gl, back)) = base.across(f, l) else {
                    continue;
                };
                let Some(gs) = slot_of(g) else { continue };
                for at_start in [true, false] {
                    let c = if at_start { l } else { (l + 1) % 4 };
                    if !lockstep(c) {
                        continue;
                    }
                    // f's ring point next to corner c across edge l; in g, the edge's end at
                    // that vertex is gl's start when the parameters agree.
                    let (i, j) = if at_start { (0, -1) } else { (-1, 0) };
                    let (gc, gi, gj) = if at_start != back {
                        (gl, 0, 1)
                    } else {
                        ((gl + 1) % 4, 1, 0)
                    };
                    gives[gs as usize].push(Give {
                        from: CornerPoint::new(gc, gi, gj),
                        old: false,
                        to: takes.len() as u32,
                    });
                    takes.push(CornerPoint::new(c, i, j));
                }
            }
            take_at.push(takes.len() as u32);
        }
        // The 1-rings, after the ring points (if any).
        let mut len = takes.len();
        let mut ring_at = Vec::with_capacity(base.special.len());
        for &v in &base.special {
            ring_at.push(len as u32);
            let rot = topo.rotation(v);
            for (k, w) in rot.iter().enumerate() {
                let s = slot_of(w.face)? as usize;
                // In the 1-ring's order ([`Spot::in_ring`]), as [`OneRing::point`] reads it.
                let centre = (k == 0).then_some(Spot::Centre);
                for spot in centre.into_iter().chain([Spot::Spoke, Spot::Diagonal]) {
                    gives[s].push(Give {
                        from: CornerPoint::of_ring(*w, spot),
                        old: true,
                        to: (len + spot.in_ring(k)) as u32,
                    });
                }
            }
            len += 1 + 2 * rot.len();
        }
        let mut give_at = vec![0u32];
        for g in &gives {
            give_at.push(give_at.last().copied().unwrap_or(0) + g.len() as u32);
        }
        Some(Handoff {
            give_at,
            gives: gives.into_iter().flatten().collect(),
            take_at,
            takes,
            ev_corners,
            rings: ring.iter().all(|&r| r),
            ring,
            ring_at,
            len,
        })
    }

    /// Whether every face's ring is its own step's and the points next to its EV corners
    /// from the box ([`Handoff::hands_ring`]).
    pub(super) fn hands_rings(&self) -> bool {
        self.rings
    }

    /// Whether face slot s's ring is its own step's and the points next to its EV corners
    /// from the box, which [`Handoff::take`] sets (else it is refreshed from its neighbours'
    /// rows, `Base::refresh_ring`).
    pub(super) fn hands_ring(&self, s: usize) -> bool {
        self.ring[s]
    }

    /// Points in the box.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Face slot s's gives into `out` after its step: from its old patch and, unless this was
    /// the last step, from its new one (each with its [`Offsets`]).
    ///
    /// # Safety
    /// No other thread writes the box at the same time as this face's gives (each box point
    /// has one giver), nor reads it.
    pub(super) unsafe fn give<T: Real>(
        &self,
        s: usize,
        old: (&[T], &Offsets),
        new: Option<(&[T], &Offsets)>,
        out: &SharedOut<T>,
    ) {
        let range = self.give_at[s] as usize..self.give_at[s + 1] as usize;
        for g in &self.gives[range] {
            let (patch, offsets) = match (g.old, new) {
                (true, _) => old,
                (false, Some(new)) => new,
                (false, None) => continue,
            };
            let at = offsets.at(g.from);
            let p = [patch[at], patch[at + 1], patch[at + 2]];
            // SAFETY: box point `to` has this face as its only giver (the caller's contract).
            unsafe { out.write(g.to as usize, &p) };
        }
    }

    /// Sets face slot s's ring points next to its EV corners in its new patch (`offsets`)
    /// from the box, and zeroes the diagonal at those corners.
    pub(super) fn take<T: Real>(
        &self,
        s: usize,
        offsets: &Offsets,
        from: &[[T; 3]],
        patch: &mut [T],
    ) {
        let range = self.take_at[s] as usize..self.take_at[s + 1] as usize;
        for (p, to) in from[range.clone()].iter().zip(&self.takes[range]) {
            let at = offsets.at(*to);
            patch[at..at + 3].copy_from_slice(p);
        }
        for corner in (0..4).filter(|c| self.ev_corners[s] & (1 << c) != 0) {
            let at = offsets.at(CornerPoint::new(corner, -1, -1));
            patch[at..at + 3].fill(T::default());
        }
    }

    /// Special vertex i's old 1-ring in the box.
    pub(super) fn ring<'b, T>(&self, i: usize, from: &'b [[T; 3]]) -> OneRing<'b, T> {
        OneRing(&from[self.ring_at[i] as usize..])
    }
}

/// A special vertex's old 1-ring as [`Handoff::ring`] reads it from the box.
pub(super) struct OneRing<'b, T>(&'b [[T; 3]]);

impl<T: Copy> OneRing<'_, T> {
    /// The point `spot` of wedge k ([`super::one_ring`]).
    pub(super) fn point(&self, k: usize, spot: Spot) -> [T; 3] {
        self.0[spot.in_ring(k)]
    }
}
