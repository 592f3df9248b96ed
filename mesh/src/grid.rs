//! The grid of a refined face and the numbering of refined points: one set of corner and
//! direction tables and one numbering, used by the reference driver ([`crate::surface`]) and
//! the fast driver ([`crate::patch`]) alike, so that both write every point at the same index.
//!
//! After refinement, face f of the old mesh is a p × q grid of points (x, y), 0 ≤ x ≤ p,
//! 0 ≤ y ≤ q: corner 0 at (0, 0), 1 at (p, 0), 2 at (p, q), 3 at (0, q), local edge l from
//! corner l to corner l + 1. The new points are numbered: the old vertices (their children)
//! first, in vertex order; then the interior points of each old edge, edges in id order, each
//! read from its smaller vertex; then the interior points of each face, row by row (\[G\] §2.2:
//! the mesh after a step is again a quad mesh, and this numbering is its vertex order).

/// Grid point of corner c of a p × q face grid.
#[inline]
pub(crate) fn corner_at(c: u8, p: i64, q: i64) -> (i64, i64) {
    [(0, 0), (p, 0), (p, q), (0, q)][c as usize]
}

/// Unit step from corner c toward corner c + 1 (along local edge c).
pub(crate) const TOWARD_NEXT: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// Unit step from corner c toward corner c − 1 (along local edge c − 1, backwards).
pub(crate) const TOWARD_PREV: [(i64, i64); 4] = [(0, 1), (-1, 0), (0, -1), (1, 0)];

/// Where a point of a p × q face grid lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Site {
    /// Corner c: the child of the face's vertex c.
    Corner(u8),
    /// Point t = 1..len of local edge l, counted from corner l.
    Edge(u8, i64),
    /// An interior point: its offset among the face's interior points, row by row.
    Inside(usize),
}

/// The site of grid point (x, y) of a p × q face grid.
#[inline]
pub(crate) fn site(x: i64, y: i64, p: i64, q: i64) -> Site {
    match (x, y) {
        (0, 0) => Site::Corner(0),
        (x, 0) if x == p => Site::Corner(1),
        (x, y) if x == p && y == q => Site::Corner(2),
        (0, y) if y == q => Site::Corner(3),
        (x, 0) => Site::Edge(0, x),
        (x, y) if x == p => Site::Edge(1, y),
        (x, y) if y == q => Site::Edge(2, p - x),
        (0, y) => Site::Edge(3, q - y),
        (x, y) => Site::Inside(((y - 1) * (p - 1) + (x - 1)) as usize),
    }
}

/// Offset of point t (1..len) of an edge of `len` segments among the edge's interior points,
/// which are numbered from its smaller vertex: `forward` when t counts from that vertex.
#[inline]
pub(crate) fn along_edge(t: i64, len: i64, forward: bool) -> usize {
    (if forward { t - 1 } else { len - t - 1 }) as usize
}
