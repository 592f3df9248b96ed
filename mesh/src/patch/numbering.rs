//! The final numbering of a refinement and the output it is written into.
//!
//! Base vertices first, then N − 1 points per base edge (from its smaller vertex), then
//! (N − 1)² per face, row by row: each point has exactly one writing face, so workers write
//! the shared output at disjoint indices. The reference driver's levels are lifted into it
//! ([`lifted`]).

use super::stream::Stream;
use super::{ring_layout, Base, Simd};
use crate::grid::{along_edge, corner_at, site, Site, TOWARD_NEXT, TOWARD_PREV};
use crate::topology::Topology;
use lsubdiv_runtime::curve::{rewrite, CurveTables};

/// Where the points of a patch go in the final numbering: base vertices, then N−1 points per
/// base edge (from its smaller vertex), then (N−1)² per face, row by row.
pub(super) struct Numbering {
    pub(super) n: i64,
    pub(super) nv: usize,
    ne: usize,
    /// Per face, its edges and corners in the numbering. Shared by every level.
    pub(super) faces: std::sync::Arc<[FaceNumbering]>,
}

/// A face's edges and corners in the [`Numbering`]: one record of 36 bytes, read once per face.
#[derive(Clone, Copy, Debug)]
pub(super) struct FaceNumbering {
    /// Edge id of local edge l (from corner l to l + 1).
    edge: [u32; 4],
    /// Vertex of corner l.
    pub(super) vertex: [u32; 4],
    /// Per l: [`FaceNumbering::FORWARD`], [`FaceNumbering::OWNS_EDGE`],
    /// [`FaceNumbering::OWNS_CORNER`].
    bits: [u8; 4],
}

impl FaceNumbering {
    /// Edge l's points run from corner l (its smaller vertex).
    const FORWARD: u8 = 1;
    /// This face writes edge l's points (the first face of the edge does).
    const OWNS_EDGE: u8 = 2;
    /// This face writes corner l's vertex (its first face does).
    const OWNS_CORNER: u8 = 4;

    /// Local edge l: its edge id, whether its points run from corner l, and whether this face
    /// writes them.
    #[inline(always)]
    pub(super) fn edge(&self, l: usize) -> (u32, bool, bool) {
        let b = self.bits[l];
        (
            self.edge[l],
            b & Self::FORWARD != 0,
            b & Self::OWNS_EDGE != 0,
        )
    }

    /// Whether this face writes the vertex of corner c.
    #[inline(always)]
    pub(super) fn owns_corner(&self, c: usize) -> bool {
        self.bits[c] & Self::OWNS_CORNER != 0
    }
}

impl Numbering {
    pub(super) fn new(topo: &Topology, n: i64) -> Numbering {
        let nf = topo.face_count();
        let mut edge_done = vec![false; topo.edge_count()];
        let mut vertex_done = vec![false; topo.vertex_count()];
        let faces = (0..nf as u32)
            .map(|f| {
                let mut r = FaceNumbering {
                    edge: [0; 4],
                    vertex: [0; 4],
                    bits: [0; 4],
                };
                for l in 0..4u8 {
                    let (e, v, i) = (topo.edge_of(f, l), topo.vertex(f, l), l as usize);
                    let bit = |yes: bool, b: u8| if yes { b } else { 0 };
                    (r.edge[i], r.vertex[i]) = (e, v);
                    r.bits[i] = bit(topo.from_smaller(f, l), FaceNumbering::FORWARD)
                        | bit(
                            !std::mem::replace(&mut edge_done[e as usize], true),
                            FaceNumbering::OWNS_EDGE,
                        )
                        | bit(
                            !std::mem::replace(&mut vertex_done[v as usize], true),
                            FaceNumbering::OWNS_CORNER,
                        );
                }
                r
            })
            .collect();
        Numbering {
            n,
            nv: topo.vertex_count(),
            ne: topo.edge_count(),
            faces,
        }
    }

    /// The same mesh's numbering at another N (the ownership tables are shared).
    pub(super) fn with_n(&self, n: i64) -> Numbering {
        Numbering {
            n,
            nv: self.nv,
            ne: self.ne,
            faces: self.faces.clone(),
        }
    }

    pub(super) fn len(&self) -> usize {
        let k = (self.n - 1) as usize;
        self.nv + self.ne * k + self.faces.len() * k * k
    }

    /// The index of point (x, y) of face f, and whether face f writes it.
    #[inline]
    pub(super) fn index(&self, f: usize, x: i64, y: i64) -> (usize, bool) {
        let n = self.n;
        let k = (n - 1) as usize;
        match site(x, y, n, n) {
            Site::Corner(c) => (
                self.faces[f].vertex[c as usize] as usize,
                self.faces[f].owns_corner(c as usize),
            ),
            Site::Edge(l, t) => {
                let (e, forward, owner) = self.faces[f].edge(l as usize);
                (self.nv + e as usize * k + along_edge(t, n, forward), owner)
            }
            Site::Inside(i) => (self.interior(f) + i, true),
        }
    }

    /// The base edge point i lies on strictly between its ends, if it is an edge point.
    pub(super) fn edge_at(&self, i: usize) -> Option<u32> {
        let k = (self.n - 1) as usize;
        (i >= self.nv && i < self.nv + self.ne * k).then(|| ((i - self.nv) / k) as u32)
    }

    /// The index of point x (0..=N) along base edge e with ends `ends` (smaller first).
    pub(super) fn along(&self, e: u32, [a, b]: [u32; 2], x: i64) -> usize {
        match x {
            0 => a as usize,
            x if x == self.n => b as usize,
            x => self.nv + e as usize * (self.n - 1) as usize + x as usize - 1,
        }
    }

    /// The index of face f's first interior point (x, y) = (1, 1); the others follow row by
    /// row.
    #[inline(always)]
    pub(super) fn interior(&self, f: usize) -> usize {
        let k = (self.n - 1) as usize;
        self.nv + self.ne * k + f * k * k
    }
}

impl Numbering {
    /// Every face's patch with its ring as indices into this numbering, x-major
    /// ([`load`](super::load)), `u32::MAX` where a point does not exist
    /// ([`Numbering::gather`]).
    pub(super) fn gather_table(&self, base: &Base<'_>) -> Vec<u32> {
        let m = ring_layout(self.n, true);
        let mut table = vec![u32::MAX; base.topo.face_count() * m.side * m.side];
        for (f, t) in table.chunks_exact_mut(m.side * m.side).enumerate() {
            self.gather(base, f as u32, |x, y, i| t[m.at(x, y) / 3] = i as u32);
        }
        table
    }

    /// Face f's patch with its ring (side N+3): `put(x, y, i)` for each point and its index
    /// in this numbering; ring points across a boundary and the diagonal point at an
    /// extraordinary corner do not exist and are not handed.
    pub(super) fn gather(&self, base: &Base<'_>, f: u32, mut put: impl FnMut(i64, i64, usize)) {
        let n = self.n;
        let kk = (n - 1) as usize;
        let fu = f as usize;
        // The patch: interior rows, then corners, then each edge as a run (forward or backward
        // in the numbering).
        let (inner, _) = self.index(fu, 1, 1);
        for y in 1..n {
            for x in 1..n {
                put(x, y, inner + (y - 1) as usize * kk + (x - 1) as usize);
            }
        }
        for c in 0..4u8 {
            let (x, y) = corner_at(c, n, n);
            put(x, y, self.faces[fu].vertex[c as usize] as usize);
        }
        for l in 0..4u8 {
            let (e, forward, _) = self.faces[fu].edge(l as usize);
            let first = self.nv + e as usize * kk;
            let (cx, cy) = corner_at(l, n, n);
            let (dx, dy) = TOWARD_NEXT[l as usize];
            for t in 1..n {
                put(cx + t * dx, cy + t * dy, first + along_edge(t, n, forward));
            }
        }
        // The ring along the four edges (none across a boundary: phantoms, set after loading).
        for l in 0..4u8 {
            for ((x, y), owner) in base.ring(f, l, n) {
                if let Some((g, gx, gy)) = owner {
                    put(x, y, self.index(g as usize, gx, gy).0);
                }
            }
        }
        // Corners: the diagonal point across an ordinary vertex; none elsewhere.
        for c in 0..4u8 {
            if let Some((g, gc)) = base.diagonal(f, c) {
                let (cx, cy) = corner_at(c, n, n);
                let (ax, ay) = TOWARD_NEXT[c as usize];
                let (bx, by) = TOWARD_PREV[c as usize];
                let (gx, gy) = corner_at(gc, n, n);
                let (hx, hy) = TOWARD_NEXT[gc as usize];
                let (kx, ky) = TOWARD_PREV[gc as usize];
                let i = self.index(g as usize, gx + hx + kx, gy + hy + ky).0;
                put(cx - ax - bx, cy - ay - by, i);
            }
        }
    }
}

/// The output positions, written by several workers at disjoint indices.
pub(super) struct SharedOut<T> {
    ptr: *mut [T; 3],
    len: usize,
}

// SAFETY: workers write disjoint indices (each point has exactly one writing face, see
// `Numbering::index`), and the buffer outlives the scoped threads.
unsafe impl<T: Send> Send for SharedOut<T> {}
unsafe impl<T: Send> Sync for SharedOut<T> {}

impl<T: Copy> SharedOut<T> {
    pub(super) fn new(v: &mut [[T; 3]]) -> SharedOut<T> {
        SharedOut {
            ptr: v.as_mut_ptr(),
            len: v.len(),
        }
    }

    /// Writes point i.
    ///
    /// # Safety
    /// No other thread reads or writes index i during the call.
    pub(super) unsafe fn write(&self, i: usize, p: &[T; 3]) {
        assert!(i < self.len, "output index in range");
        // SAFETY: in range (checked); exclusive to this caller (the function's contract).
        unsafe { self.ptr.add(i).write(*p) };
    }

    /// Points i..i + len, to write.
    ///
    /// # Safety
    /// No other thread reads or writes them while the slice lives.
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn run(&self, i: usize, len: usize) -> &mut [[T; 3]] {
        assert!(i + len <= self.len, "output run in range");
        // SAFETY: in range (checked); exclusive to this caller (the function's contract).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(i), len) }
    }

    /// A writer of runs of the output's values ([`Stream::new`]: non-temporal where
    /// `streaming`, with the vectors of `simd`).
    ///
    /// # Safety
    /// No other thread or writer reads or writes the indices it is handed until
    /// [`Stream::finish`] and a `stream::fence` on this thread; `simd` only a path the CPU has.
    pub(super) unsafe fn stream(&self, streaming: bool, simd: Simd) -> Stream<'_, T>
    where
        T: Default,
    {
        // SAFETY: the buffer holds `len` points of three values and outlives `self`; the rest
        // is the caller's contract.
        unsafe { Stream::new(self.ptr.cast::<T>(), self.len * 3, streaming, simd) }
    }
}

/// Per point of the numbering `num`, its index in a mesh refined `k` ≥ 1 times by the
/// reference driver (its quads `quads`; `u32::MAX` for none). Its faces come old face by old
/// face, each base face's as a block of W_k × W_k cells in the same order ([`cells`]); each
/// point is taken from the one cell whose corner 0 it is, or, on the face's last row and
/// column, from the cell beside it.
pub(super) fn lifted(
    t: &CurveTables<'_>,
    quads: &[[u32; 4]],
    k: usize,
    num: &Numbering,
) -> Vec<u32> {
    let cells = cells(t, k);
    let n = num.n;
    let mut from = vec![u32::MAX; num.len()];
    // (A mesh with ghost faces has them after the base faces: they are left out.)
    let faces = quads.chunks_exact(cells.len()).take(num.faces.len());
    for (f, quads) in faces.enumerate() {
        for (&(x, y, _), quad) in cells.iter().zip(quads) {
            let last = (x + 1 == n, y + 1 == n);
            for c in [0u8, 1, 2, 3] {
                let wanted = match c {
                    0 => true,
                    1 => last.0,
                    2 => last.0 && last.1,
                    _ => last.1,
                };
                if wanted {
                    let (dx, dy) = corner_at(c, 1, 1);
                    from[num.index(f, x + dx, y + dy).0] = quad[c as usize];
                }
            }
        }
    }
    from
}

/// The quads of the base mesh refined `k` times by the reference driver, in the order it makes
/// them, over this numbering's points (N = W_k), and their labels ([`crate::surface`]'s
/// `[label of edge 0, label of edge 1]`): a level of the reference steps without its ghosts.
pub(super) fn level_mesh(
    t: &CurveTables<'_>,
    k: usize,
    num: &Numbering,
) -> (Vec<[u32; 4]>, Vec<[u8; 2]>) {
    let cells = cells(t, k);
    let mut faces = Vec::with_capacity(cells.len() * num.faces.len());
    for f in 0..num.faces.len() {
        faces.extend(cells.iter().map(|&(x, y, _)| {
            [0u8, 1, 2, 3].map(|c| {
                let (dx, dy) = corner_at(c, 1, 1);
                num.index(f, x + dx, y + dy).0 as u32
            })
        }));
    }
    let labels = cells.iter().map(|&(_, _, l)| l);
    let labels = std::iter::repeat_n(labels, num.faces.len())
        .flatten()
        .collect();
    (faces, labels)
}

/// The cells of a base face refined `k` times by the reference driver, in the order it makes
/// them: each cell of step k − 1 becomes its rule's block, row by row; (x, y) of each cell's
/// corner 0 in the face's grid and its labels (every base face alike: its edges all carry the
/// axiom).
fn cells(t: &CurveTables<'_>, k: usize) -> Vec<(i64, i64, [u8; 2])> {
    let mut cells = vec![(0i64, 0i64, t.axiom[0], t.axiom[0])];
    let mut word = t.axiom.to_vec();
    for _ in 0..k {
        let mut off = vec![0i64];
        for &a in &word {
            off.push(off.last().copied().unwrap_or(0) + t.rule(a).len() as i64);
        }
        cells = cells
            .iter()
            .flat_map(|&(x, y, a, b)| {
                let (ra, rb) = (t.rule(a), t.rule(b));
                let (x0, y0) = (off[x as usize], off[y as usize]);
                rb.iter().enumerate().flat_map(move |(j, &lb)| {
                    ra.iter()
                        .enumerate()
                        .map(move |(i, &la)| (x0 + i as i64, y0 + j as i64, la, lb))
                })
            })
            .collect();
        let mut next = Vec::new();
        rewrite(t, &word, &mut next);
        word = next;
    }
    cells
        .into_iter()
        .map(|(x, y, a, b)| (x, y, [a, b]))
        .collect()
}
