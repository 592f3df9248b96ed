//! Connectivity of a 2-manifold quad mesh, oriented or not, closed or with boundaries, and what
//! can be wrong with it (faces, edges and vertices named by index).
//!
//! A boundary edge has one face; the faces around a vertex form one fan: a cycle for an
//! interior vertex, an open chain from one boundary edge to the other for a boundary vertex.
//!
//! Nothing here assumes that adjacent faces list a shared edge in opposite directions, so
//! non-orientable meshes (Klein bottles, Möbius-glued closed meshes) work. Everything is stored
//! in flat arrays indexed by half-edge `4 * face + local` and, for the vertex rotations, in CSR
//! layout (`offsets` + concatenated wedges).

use crate::mesh::QuadMesh;
use std::fmt;

/// Why a mesh is not a 2-manifold quad mesh lsubdiv can refine; faces and vertices are
/// 0-based indices into the [`QuadMesh`] (a file reader places them at their lines).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TopologyError {
    /// The mesh has no faces.
    NoFaces,
    /// More vertices or faces than 32-bit indices can address.
    TooLarge {
        /// Vertex count.
        vertices: usize,
        /// Face count.
        faces: usize,
    },
    /// A face names a vertex that does not exist.
    FaceIndexOutOfRange {
        /// Face index.
        face: u32,
        /// The vertex index.
        index: u32,
        /// Vertex count of the mesh.
        vertices: usize,
    },
    /// A face lists the same vertex twice.
    RepeatedVertex {
        /// Face index.
        face: u32,
        /// The repeated vertex.
        vertex: u32,
    },
    /// Two faces have the same vertex set.
    DuplicateFaces {
        /// The earlier face.
        first: u32,
        /// The later face.
        second: u32,
    },
    /// An edge with only one face, where a closed mesh is needed.
    BoundaryEdge {
        /// Endpoints, smaller first.
        edge: [u32; 2],
        /// The face.
        face: u32,
    },
    /// An edge with more than two faces.
    NonManifoldEdge {
        /// Endpoints, smaller first.
        edge: [u32; 2],
        /// Number of faces on it.
        faces: usize,
        /// The first face on it.
        face: u32,
    },
    /// The faces around a vertex form more than one fan.
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
        /// Number of separate fans (cycles or chains).
        fans: usize,
    },
    /// A vertex used by no face.
    IsolatedVertex {
        /// The vertex.
        vertex: u32,
    },
    /// An interior vertex with fewer than two faces.
    LowValence {
        /// The vertex.
        vertex: u32,
        /// Its valence.
        valence: usize,
    },
}

/// `n` and the noun, singular for one: `1 vertex`, `8 vertices`.
fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Faces, edges and vertices by their 0-based index in the mesh.
impl fmt::Display for TopologyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TopologyError::NoFaces => write!(f, "empty mesh: no faces"),
            TopologyError::TooLarge { vertices, faces } => write!(
                f,
                "mesh too large: {vertices} vertices and {faces} faces (at most {} vertices and {} faces are supported)",
                u32::MAX,
                u32::MAX / 4
            ),
            TopologyError::FaceIndexOutOfRange {
                face,
                index,
                vertices,
            } => write!(
                f,
                "face {face}: vertex index {index} out of range (the mesh has {})",
                plural(*vertices, "vertex", "vertices")
            ),
            TopologyError::RepeatedVertex { face, vertex } => {
                write!(f, "face {face} repeats vertex {vertex}")
            }
            TopologyError::DuplicateFaces { first, second } => {
                write!(f, "faces {first} and {second} are duplicates")
            }
            TopologyError::BoundaryEdge { edge, face } => write!(
                f,
                "edge ({}, {}) of face {face} has no other face (open boundary)",
                edge[0], edge[1]
            ),
            TopologyError::NonManifoldEdge { edge, faces, face } => write!(
                f,
                "edge ({}, {}) of face {face} is shared by {faces} faces (non-manifold edge)",
                edge[0], edge[1]
            ),
            TopologyError::NonManifoldVertex { vertex, fans } => write!(
                f,
                "vertex {vertex}: its faces form {fans} separate fans (non-manifold vertex)"
            ),
            TopologyError::IsolatedVertex { vertex } => {
                write!(f, "vertex {vertex} is used by no face")
            }
            TopologyError::LowValence { vertex, valence } => write!(
                f,
                "vertex {vertex} has valence {valence}; an interior vertex has two faces at least"
            ),
        }
    }
}

impl std::error::Error for TopologyError {}

/// One entry of a vertex's rotation: a face around the vertex, the vertex's corner in it, and
/// which of the corner's two face edges is shared with the NEXT entry of the rotation:
/// `next_is_plus == true` means the edge from corner c to corner (c+1)%4, false means the edge
/// from c to (c+3)%4. Consecutive entries k, k+1 (cyclically) share exactly that edge; the other
/// edge of entry k is shared with entry k-1. At a boundary vertex the rotation is a chain: the
/// previous edge of the first entry and the next edge of the last are boundary edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Wedge {
    /// Face index.
    pub face: u32,
    /// The vertex's corner in the face, 0..4.
    pub corner: u8,
    /// Whether the edge shared with the next wedge is the corner's `c -> c+1` edge (else
    /// `c -> c+3`).
    pub next_is_plus: bool,
}

impl Wedge {
    /// Local index (in the wedge's face) of the edge shared with the next wedge.
    pub fn next_local(&self) -> u8 {
        if self.next_is_plus {
            self.corner
        } else {
            (self.corner + 3) % 4
        }
    }

    /// Local index (in the wedge's face) of the edge shared with the previous wedge.
    pub fn prev_local(&self) -> u8 {
        if self.next_is_plus {
            (self.corner + 3) % 4
        } else {
            self.corner
        }
    }
}

/// Connectivity of a validated 2-manifold quad mesh.
#[derive(Clone, Debug)]
pub struct Topology {
    vertex_count: usize,
    /// The faces' corners: the vertex of half-edge/corner `4 f + i` is `faces[f][i]`.
    faces: Vec<[u32; 4]>,
    /// Edge id of half-edge `4 f + i` (the edge from corner i to i+1).
    face_edges: Vec<u32>,
    /// The other half-edge of the same edge (`NONE` on a boundary edge).
    mates: Vec<u32>,
    /// Endpoints of each edge, smaller first.
    edge_verts: Vec<[u32; 2]>,
    /// One half-edge of each edge (the first met scanning faces in order).
    edge_half: Vec<u32>,
    /// Rotation of vertex v is `rot[rot_offsets[v]..rot_offsets[v + 1]]`.
    rot_offsets: Vec<u32>,
    rot: Vec<Wedge>,
}

const NONE: u32 = u32::MAX;

impl Topology {
    /// Validates that the mesh is a 2-manifold quad mesh (boundaries allowed) and builds the
    /// connectivity.
    ///
    /// Checks, in this order (the first failure is returned): no faces; size fits 32-bit
    /// indices; index out of range; face repeating a vertex; duplicate faces (same vertex set);
    /// non-manifold edge (>2 faces), first in edge order; isolated vertex (used by no face);
    /// non-manifold vertex (faces around it form more than one fan). Edges are numbered in the
    /// order they are first met scanning faces in order and local edges 0..4. The rotation of
    /// an interior vertex starts at its first corner in face order, with `next_is_plus ==
    /// true`; that of a boundary vertex at one end of its chain.
    pub fn build<T>(mesh: &QuadMesh<T>) -> Result<Topology, TopologyError> {
        let nv = mesh.positions.len();
        let nf = mesh.faces.len();
        if nf == 0 {
            return Err(TopologyError::NoFaces);
        }
        if nv > u32::MAX as usize || nf > (u32::MAX / 4) as usize {
            return Err(TopologyError::TooLarge {
                vertices: nv,
                faces: nf,
            });
        }
        for (f, face) in mesh.faces.iter().enumerate() {
            check_corners(f as u32, face, nv)?;
        }
        // Duplicate faces: bucket faces by their smallest vertex, sort each bucket by vertex set.
        let keys: Vec<[u32; 4]> = mesh
            .faces
            .iter()
            .map(|f| {
                let mut k = *f;
                k.sort_unstable();
                k
            })
            .collect();
        let mins: Vec<u32> = keys.iter().map(|k| k[0]).collect();
        let (offsets, mut order) = buckets(nv, &mins);
        drop(mins);
        let mut duplicate: Option<(u32, u32)> = None;
        for b in offsets.windows(2) {
            let bucket = &mut order[b[0] as usize..b[1] as usize];
            bucket.sort_unstable_by_key(|&f| (keys[f as usize], f));
            for run in bucket.chunk_by(|&f, &g| keys[f as usize] == keys[g as usize]) {
                // The run is in face order: its first two faces are the earliest pair.
                if let [first, second, ..] = *run {
                    if !matches!(duplicate, Some((_, s)) if s < second) {
                        duplicate = Some((first, second));
                    }
                }
            }
        }
        if let Some((first, second)) = duplicate {
            return Err(TopologyError::DuplicateFaces { first, second });
        }
        drop((keys, offsets, order));

        // Edges: bucket half-edges by their smaller endpoint, then group by the larger one.
        // O(V + F) apart from sorting the (tiny) buckets.
        let face_verts = mesh.faces.as_flattened();
        let nh = 4 * nf;
        let ends = |h: usize| {
            let a = face_verts[h];
            let b = face_verts[h - h % 4 + (h + 1) % 4];
            if a < b {
                (a, b)
            } else {
                (b, a)
            }
        };
        let los: Vec<u32> = (0..nh).map(|h| ends(h).0).collect();
        let (offsets, mut order) = buckets(nv, &los);
        drop(los);
        let mut mates = vec![NONE; nh];
        // rep[h]: the first half-edge (in scanning order) of h's edge.
        let mut rep = vec![NONE; nh];
        // The edge of more than two faces whose first half-edge comes first, and its faces.
        let mut crowded: Option<(u32, usize)> = None;
        for b in offsets.windows(2) {
            let bucket = &mut order[b[0] as usize..b[1] as usize];
            bucket.sort_unstable_by_key(|&h| (ends(h as usize).1, h));
            for run in bucket.chunk_by(|&g, &h| ends(g as usize).1 == ends(h as usize).1) {
                for &h in run {
                    rep[h as usize] = run[0];
                }
                match *run {
                    [a, b] => {
                        mates[a as usize] = b;
                        mates[b as usize] = a;
                    }
                    [first, _, _, ..] if crowded.is_none_or(|(h, _)| first < h) => {
                        crowded = Some((first, run.len()));
                    }
                    _ => {}
                }
            }
        }
        if let Some((h, faces)) = crowded {
            let (lo, hi) = ends(h as usize);
            return Err(TopologyError::NonManifoldEdge {
                edge: [lo, hi],
                faces,
                face: h / 4,
            });
        }
        drop((offsets, order));
        let mut face_edges = vec![0u32; nh];
        let mut edge_verts: Vec<[u32; 2]> = Vec::with_capacity(2 * nf);
        let mut edge_half: Vec<u32> = Vec::with_capacity(2 * nf);
        for h in 0..nh {
            let r = rep[h] as usize;
            if r == h {
                let (lo, hi) = ends(h);
                face_edges[h] = edge_verts.len() as u32;
                edge_verts.push([lo, hi]);
                edge_half.push(h as u32);
            } else {
                face_edges[h] = face_edges[r];
            }
        }
        drop(rep);

        // Rotations (CSR). Every corner is in exactly one rotation, so 4F wedges in all.
        let mut rot_offsets = vec![0u32; nv + 1];
        let mut first_corner = vec![NONE; nv];
        for (h, &v) in face_verts.iter().enumerate() {
            rot_offsets[v as usize + 1] += 1;
            if first_corner[v as usize] == NONE {
                first_corner[v as usize] = h as u32;
            }
        }
        if let Some(v) = first_corner.iter().position(|&h| h == NONE) {
            return Err(TopologyError::IsolatedVertex { vertex: v as u32 });
        }
        for v in 0..nv {
            rot_offsets[v + 1] += rot_offsets[v];
        }
        let mut rot: Vec<Wedge> = Vec::with_capacity(4 * nf);
        for v in 0..nv {
            let valence = (rot_offsets[v + 1] - rot_offsets[v]) as usize;
            let start = first_corner[v];
            let first = Wedge {
                face: start / 4,
                corner: (start % 4) as u8,
                next_is_plus: true,
            };
            let fan = fan(face_verts, &mates, v as u32, first, valence);
            if fan.len() < valence {
                let fans = count_fans(face_verts, &mates, v as u32);
                return Err(TopologyError::NonManifoldVertex {
                    vertex: v as u32,
                    fans,
                });
            }
            rot.extend(fan);
        }
        Ok(Topology {
            vertex_count: nv,
            faces: mesh.faces.clone(),
            face_edges,
            mates,
            edge_verts,
            edge_half,
            rot_offsets,
            rot,
        })
    }

    /// Refuses the first interior vertex of valence below 2 (a face meeting itself; valence 2,
    /// two faces sharing two consecutive edges, is refined: `EvCoefficients::alpha`).
    /// Boundary vertices may have any number of faces.
    pub fn check_valences(&self) -> Result<(), TopologyError> {
        match (0..self.vertex_count as u32).find(|&v| self.valence(v) < 2 && !self.is_boundary(v)) {
            Some(v) => Err(TopologyError::LowValence {
                vertex: v,
                valence: self.valence(v),
            }),
            None => Ok(()),
        }
    }

    /// The faces (four vertex indices each, in corner order), as in the mesh it was built from.
    pub fn faces(&self) -> &[[u32; 4]] {
        &self.faces
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Number of (undirected) edges; twice the face count for a closed quad mesh.
    pub fn edge_count(&self) -> usize {
        self.edge_verts.len()
    }

    /// Undirected edge id of local edge i of face f (the edge from corner i to corner (i+1)%4).
    pub fn edge_of(&self, face: u32, local: u8) -> u32 {
        self.face_edges[half(face, local)]
    }

    /// Whether local edge `local` of `face` runs from its edge's smaller vertex.
    pub fn from_smaller(&self, face: u32, local: u8) -> bool {
        self.vertex(face, local) == self.edge_vertices(self.edge_of(face, local))[0]
    }

    /// Endpoints of an edge, smaller vertex index first.
    pub fn edge_vertices(&self, edge: u32) -> [u32; 2] {
        self.edge_verts[edge as usize]
    }

    /// The end of `edge` other than `v` (v one of its ends).
    pub fn other_end(&self, edge: u32, v: u32) -> u32 {
        let [x, y] = self.edge_vertices(edge);
        debug_assert!(v == x || v == y, "vertex {v} is not an end of edge {edge}");
        if x == v {
            y
        } else {
            x
        }
    }

    /// The sides of an edge as (face, local edge index): the first where the edge is first met
    /// scanning faces in order, the second none on a boundary edge.
    pub fn edge_faces(&self, edge: u32) -> ((u32, u8), Option<(u32, u8)>) {
        let h = self.edge_half[edge as usize];
        let side = |h: u32| (h / 4, (h % 4) as u8);
        let m = self.mates[h as usize];
        (side(h), (m != NONE).then(|| side(m)))
    }

    /// The other face on local edge `local` of `face` and that edge's local index in it; none
    /// on a boundary edge.
    pub fn across(&self, face: u32, local: u8) -> Option<(u32, u8)> {
        let m = self.mates[half(face, local)];
        (m != NONE).then_some((m / 4, (m % 4) as u8))
    }

    /// Whether local edge `local` of `face` is a boundary edge (it has no other face).
    pub fn is_boundary_edge(&self, face: u32, local: u8) -> bool {
        self.mates[half(face, local)] == NONE
    }

    /// The edges of v's rotation E_0, E_1, …: E_k is wedge k's previous edge; at a boundary
    /// vertex the last wedge's next edge (a boundary edge) follows.
    pub fn spokes(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let rot = self.rotation(v);
        let last = rot[rot.len() - 1];
        let closing = self
            .is_boundary(v)
            .then(|| self.edge_of(last.face, last.next_local()));
        rot.iter()
            .map(move |w| self.edge_of(w.face, w.prev_local()))
            .chain(closing)
    }

    /// The edge between vertices a and b, if they share one (found among the spokes of the
    /// one of smaller valence, so that looking up every edge at a vertex of valence n costs
    /// O(n), not O(n²)).
    pub fn edge_between(&self, a: u32, b: u32) -> Option<u32> {
        if a as usize >= self.vertex_count || b as usize >= self.vertex_count {
            return None;
        }
        let from = if self.valence(a) <= self.valence(b) {
            a
        } else {
            b
        };
        self.spokes(from).find(|&e| {
            let [x, y] = self.edge_vertices(e);
            (x, y) == (a.min(b), a.max(b))
        })
    }

    /// Whether vertex v is on the boundary: the first wedge of its rotation (a chain then)
    /// has a boundary edge before it.
    pub fn is_boundary(&self, v: u32) -> bool {
        let w = self.rotation(v)[0];
        self.is_boundary_edge(w.face, w.prev_local())
    }

    /// Whether the mesh has no boundary edge.
    pub fn is_closed(&self) -> bool {
        !self.mates.contains(&NONE)
    }

    /// The first boundary edge, as an error for the drivers that need a closed mesh.
    pub fn require_closed(&self) -> Result<(), TopologyError> {
        match self.mates.iter().position(|&m| m == NONE) {
            None => Ok(()),
            Some(h) => Err(TopologyError::BoundaryEdge {
                edge: self.edge_verts[self.face_edges[h] as usize],
                face: (h / 4) as u32,
            }),
        }
    }

    /// The rotation around vertex v: its wedges, cyclic at an interior vertex, a chain from
    /// boundary edge to boundary edge at a boundary vertex; its length is the valence (the
    /// number of faces at v).
    pub fn rotation(&self, v: u32) -> &[Wedge] {
        let v = v as usize;
        &self.rot[self.rot_offsets[v] as usize..self.rot_offsets[v + 1] as usize]
    }

    /// Number of faces around vertex v (and of edges, at an interior vertex; one more at a
    /// boundary vertex).
    pub fn valence(&self, v: u32) -> usize {
        let v = v as usize;
        (self.rot_offsets[v + 1] - self.rot_offsets[v]) as usize
    }

    /// The vertex at a corner.
    pub fn vertex(&self, face: u32, corner: u8) -> u32 {
        self.faces.as_flattened()[half(face, corner)]
    }
}

/// Stable counting sort of the items 0..keys.len() by key (< nb): bucket k is
/// `order[offsets[k]..offsets[k + 1]]`, items in increasing order.
fn buckets(nb: usize, keys: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; nb + 1];
    for &k in keys {
        offsets[k as usize + 1] += 1;
    }
    for i in 0..nb {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets[..nb].to_vec();
    let mut order = vec![0u32; keys.len()];
    for (i, &k) in keys.iter().enumerate() {
        order[fill[k as usize] as usize] = i as u32;
        fill[k as usize] += 1;
    }
    (offsets, order)
}

fn half(face: u32, local: u8) -> usize {
    assert!(local < 4, "local index {local} is not in 0..4");
    4 * face as usize + local as usize
}

/// The wedge after `w` in the rotation of `v`: across w's next edge, entered through the edge
/// just crossed, so it leaves through its other edge; none across a boundary edge.
fn step(face_verts: &[u32], mates: &[u32], v: u32, w: Wedge) -> Option<Wedge> {
    let m = mates[4 * w.face as usize + w.next_local() as usize];
    if m == NONE {
        return None;
    }
    let (g, l) = (m / 4, m % 4);
    Some(if face_verts[m as usize] == v {
        // Entered through g's edge l -> l+1, i.e. the plus edge of corner l.
        Wedge {
            face: g,
            corner: l as u8,
            next_is_plus: false,
        }
    } else {
        // Entered through the minus edge of corner l+1.
        Wedge {
            face: g,
            corner: ((l + 1) % 4) as u8,
            next_is_plus: true,
        }
    })
}

/// The fan of v that holds wedge `first`, at most `max` wedges: the cycle from `first` when it
/// closes, else the chain from one boundary edge to the other (walked forward to one end,
/// then back from it).
fn fan(face_verts: &[u32], mates: &[u32], v: u32, first: Wedge, max: usize) -> Vec<Wedge> {
    let corner = |w: Wedge| 4 * w.face + u32::from(w.corner);
    let mut out = vec![first];
    let mut w = first;
    while out.len() < max {
        match step(face_verts, mates, v, w) {
            Some(n) if corner(n) == corner(first) => return out,
            Some(n) => {
                out.push(n);
                w = n;
            }
            None => {
                // An end of the chain: start again from it, turned around.
                let mut end = Wedge {
                    next_is_plus: !w.next_is_plus,
                    ..w
                };
                out.clear();
                out.push(end);
                while out.len() < max {
                    match step(face_verts, mates, v, end) {
                        Some(n) => {
                            out.push(n);
                            end = n;
                        }
                        None => break,
                    }
                }
                return out;
            }
        }
    }
    out
}

/// Number of separate fans (cycles or chains) of faces around `v` (only called on the error
/// path).
fn count_fans(face_verts: &[u32], mates: &[u32], v: u32) -> usize {
    let corners: Vec<u32> = (0..face_verts.len() as u32)
        .filter(|&h| face_verts[h as usize] == v)
        .collect();
    let mut visited = vec![false; corners.len()];
    let mut fans = 0;
    for k in 0..corners.len() {
        if visited[k] {
            continue;
        }
        fans += 1;
        let start = Wedge {
            face: corners[k] / 4,
            corner: (corners[k] % 4) as u8,
            next_is_plus: true,
        };
        for w in fan(face_verts, mates, v, start, corners.len()) {
            if let Ok(i) = corners.binary_search(&(4 * w.face + u32::from(w.corner))) {
                visited[i] = true;
            }
        }
    }
    fans
}

/// The corners of face `f` index one of `nv` vertices each, none twice; the error names the
/// first corner that fails, in order (an index out of range before a repeat at the same
/// corner). A large polygon's repeats are found by sorting its corners, not by comparing each
/// with those before it.
pub(crate) fn check_corners(f: u32, face: &[u32], nv: usize) -> Result<(), TopologyError> {
    let out_of_range = face.iter().position(|&v| v as usize >= nv);
    let repeat = if face.len() <= 32 {
        (1..face.len()).find(|&i| face[..i].contains(&face[i]))
    } else {
        let mut sorted: Vec<(u32, usize)> = face.iter().copied().zip(0..).collect();
        sorted.sort_unstable();
        sorted
            .windows(2)
            .filter(|w| w[0].0 == w[1].0)
            .map(|w| w[1].1)
            .min()
    };
    match (out_of_range, repeat) {
        (Some(i), r) if r.is_none_or(|r| i <= r) => Err(TopologyError::FaceIndexOutOfRange {
            face: f,
            index: face[i],
            vertices: nv,
        }),
        (_, Some(r)) => Err(TopologyError::RepeatedVertex {
            face: f,
            vertex: face[r],
        }),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{cube, klein_bottle, prism, quad_split, star, torus};
    use std::collections::BTreeMap;

    fn valence_histogram(t: &Topology) -> BTreeMap<usize, usize> {
        let mut h = BTreeMap::new();
        for v in 0..t.vertex_count() as u32 {
            *h.entry(t.valence(v)).or_insert(0) += 1;
        }
        h
    }

    fn euler(t: &Topology) -> i64 {
        t.vertex_count() as i64 - t.edge_count() as i64 + t.face_count() as i64
    }

    /// Checks every invariant of the structure against the mesh.
    fn check_consistent(mesh: &QuadMesh, t: &Topology) {
        assert_eq!(t.vertex_count(), mesh.positions.len());
        assert_eq!(t.face_count(), mesh.faces.len());
        let boundary = (0..t.face_count() as u32)
            .flat_map(|f| (0..4).map(move |i| (f, i)))
            .filter(|&(f, i)| t.is_boundary_edge(f, i))
            .count();
        assert_eq!(2 * t.edge_count(), 4 * t.face_count() + boundary);
        assert_eq!(t.is_closed(), boundary == 0);
        let mut corner_seen = vec![false; 4 * t.face_count()];
        for f in 0..t.face_count() as u32 {
            for i in 0..4u8 {
                assert_eq!(t.vertex(f, i), mesh.faces[f as usize][i as usize]);
                let e = t.edge_of(f, i);
                let (a, b) = (t.vertex(f, i), t.vertex(f, (i + 1) % 4));
                assert_eq!(t.edge_vertices(e), [a.min(b), a.max(b)]);
                assert_eq!((t.other_end(e, a), t.other_end(e, b)), (b, a));
                // across is an involution and lands on the same edge.
                let (first, second) = t.edge_faces(e);
                let Some((g, l)) = t.across(f, i) else {
                    assert_eq!((first, second), ((f, i), None));
                    continue;
                };
                assert_ne!(g, f);
                assert_eq!(t.across(g, l), Some((f, i)));
                assert_eq!(t.edge_of(g, l), e);
                let sides = [Some(first), second];
                assert!(sides.contains(&Some((f, i))) && sides.contains(&Some((g, l))));
            }
        }
        let mut total = 0;
        for v in 0..t.vertex_count() as u32 {
            let r = t.rotation(v);
            assert_eq!(r.len(), t.valence(v));
            let open = t.is_boundary(v);
            assert!(r.len() >= 2 || open);
            if open {
                let last = r[r.len() - 1];
                assert!(t.is_boundary_edge(last.face, last.next_local()));
            }
            total += r.len();
            for (k, w) in r.iter().enumerate() {
                if open && k + 1 == r.len() {
                    assert_eq!(t.vertex(w.face, w.corner), v);
                    let h = 4 * w.face as usize + w.corner as usize;
                    assert!(!corner_seen[h], "corner in two rotations");
                    corner_seen[h] = true;
                    continue;
                }
                assert_eq!(t.vertex(w.face, w.corner), v);
                let h = 4 * w.face as usize + w.corner as usize;
                assert!(!corner_seen[h], "corner in two rotations");
                corner_seen[h] = true;
                let n = r[(k + 1) % r.len()];
                // The stated edge of w is the other edge of the next wedge.
                assert_eq!(
                    t.edge_of(w.face, w.next_local()),
                    t.edge_of(n.face, n.prev_local())
                );
                assert_eq!(
                    t.across(w.face, w.next_local()),
                    Some((n.face, n.prev_local()))
                );
                // The shared edge contains v.
                assert!(t
                    .edge_vertices(t.edge_of(w.face, w.next_local()))
                    .contains(&v));
            }
        }
        assert_eq!(total, 4 * t.face_count());
        assert!(corner_seen.iter().all(|&s| s));
    }

    /// Tries to orient all faces consistently (two faces agree when they traverse their shared
    /// edge in opposite directions).
    fn is_orientable(t: &Topology) -> bool {
        let nf = t.face_count();
        let mut sign = vec![0i8; nf];
        for seed in 0..nf {
            if sign[seed] != 0 {
                continue;
            }
            sign[seed] = 1;
            let mut stack = vec![seed as u32];
            while let Some(f) = stack.pop() {
                for i in 0..4u8 {
                    let Some((g, l)) = t.across(f, i) else {
                        continue;
                    };
                    let same_dir = t.vertex(f, i) == t.vertex(g, l);
                    let want = if same_dir {
                        -sign[f as usize]
                    } else {
                        sign[f as usize]
                    };
                    match sign[g as usize] {
                        0 => {
                            sign[g as usize] = want;
                            stack.push(g);
                        }
                        s if s != want => return false,
                        _ => {}
                    }
                }
            }
        }
        true
    }

    fn build(mesh: &QuadMesh) -> Topology {
        let t = Topology::build(mesh).unwrap();
        check_consistent(mesh, &t);
        t
    }

    fn hist(pairs: &[(usize, usize)]) -> BTreeMap<usize, usize> {
        pairs.iter().copied().collect()
    }

    /// Large polygons' corners are checked by sorting them: the same error as comparing each
    /// corner with those before it, on random faces of 3 to 200 corners.
    #[test]
    fn corners_are_checked_alike_at_any_size() {
        let naive = |f: u32, face: &[u32], nv: usize| {
            for (i, &v) in face.iter().enumerate() {
                if v as usize >= nv {
                    return Err(TopologyError::FaceIndexOutOfRange {
                        face: f,
                        index: v,
                        vertices: nv,
                    });
                }
                if face[..i].contains(&v) {
                    return Err(TopologyError::RepeatedVertex { face: f, vertex: v });
                }
            }
            Ok(())
        };
        let mut state = 12345u64;
        let mut next = move |m: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % m
        };
        let mut seen = [0; 3];
        for f in 0..3000 {
            let k = 3 + next(198) as usize;
            let nv = k + next(2 * k as u64) as usize;
            // Values up to a little past nv: some out of range, some repeated.
            let face: Vec<u32> = (0..k).map(|_| next(nv as u64 + 2) as u32).collect();
            let got = check_corners(f, &face, nv);
            assert_eq!(got, naive(f, &face, nv), "{face:?} of {nv}");
            seen[match got {
                Ok(()) => 0,
                Err(TopologyError::RepeatedVertex { .. }) => 1,
                Err(_) => 2,
            }] += 1;
        }
        assert!(seen.iter().all(|&n| n > 0), "{seen:?}");
    }

    #[test]
    fn torus_topology() {
        for (r, c) in [(3, 3), (3, 5), (8, 8), (5, 12)] {
            let m = torus(r, c);
            let t = build(&m);
            assert_eq!(euler(&t), 0);
            assert_eq!(valence_histogram(&t), hist(&[(4, r * c)]));
            assert!(is_orientable(&t));
        }
    }

    #[test]
    fn cube_topology() {
        let t = build(&cube());
        assert_eq!(
            (t.vertex_count(), t.edge_count(), t.face_count()),
            (8, 12, 6)
        );
        assert_eq!(euler(&t), 2);
        assert_eq!(valence_histogram(&t), hist(&[(3, 8)]));
        assert!(is_orientable(&t));
        // Orientation-agnostic: flipping one face of the cube changes nothing structurally.
        let mut m = cube();
        m.faces[2].reverse();
        let t = build(&m);
        assert_eq!(euler(&t), 2);
        assert!(is_orientable(&t));
    }

    #[test]
    fn prism_topology() {
        for n in [3, 4, 5, 7, 9] {
            let t = build(&prism(n));
            assert_eq!(euler(&t), 2);
            assert_eq!(t.vertex_count(), 6 * n + 2);
            let mut expected = BTreeMap::new();
            *expected.entry(3).or_insert(0) += 2 * n;
            *expected.entry(n).or_insert(0) += 2;
            *expected.entry(4).or_insert(0) += 3 * n + n;
            assert_eq!(valence_histogram(&t), expected, "n = {n}");
            assert!(is_orientable(&t));
        }
    }

    #[test]
    fn star_topology() {
        let m = star();
        let t = build(&m);
        assert_eq!(euler(&t), 2);
        assert_eq!(
            valence_histogram(&t),
            hist(&[(3, 20), (4, 38), (5, 2), (9, 2)])
        );
        assert!(is_orientable(&t));
        // Extraordinary vertices are pairwise non-adjacent.
        for e in 0..t.edge_count() as u32 {
            let [a, b] = t.edge_vertices(e);
            assert!(
                t.valence(a) == 4 || t.valence(b) == 4,
                "EVs {a} and {b} adjacent"
            );
        }
    }

    #[test]
    fn klein_bottle_topology() {
        for (r, c) in [(3, 3), (4, 3), (3, 4), (6, 8), (7, 5)] {
            let t = build(&klein_bottle(r, c));
            assert_eq!(euler(&t), 0);
            assert_eq!(valence_histogram(&t), hist(&[(4, r * c)]));
            assert!(!is_orientable(&t), "{r} x {c}");
        }
    }

    #[test]
    fn mixed_orientation_is_accepted() {
        // The same torus with every other face reversed: structurally identical.
        let mut m = torus(4, 6);
        for (i, f) in m.faces.iter_mut().enumerate() {
            if i % 2 == 1 {
                f.reverse();
            }
        }
        let t = build(&m);
        assert_eq!(euler(&t), 0);
        assert_eq!(valence_histogram(&t), hist(&[(4, 24)]));
        assert!(is_orientable(&t));
    }

    #[test]
    fn split_of_klein_bottle_is_non_orientable() {
        let k = klein_bottle(4, 4);
        let polys: Vec<Vec<u32>> = k.faces.iter().map(|f| f.to_vec()).collect();
        let t = build(&quad_split(&k.positions, &polys));
        assert_eq!(euler(&t), 0);
        assert!(!is_orientable(&t));
    }

    #[test]
    fn valence_two_vertex_is_fine() {
        // A new vertex 8 on the cube edge (0, 1) makes both faces on it pentagons; after
        // quad_split, vertex 8 has valence 2 (two faces sharing two consecutive edges).
        let c = cube();
        let mut polys: Vec<Vec<u32>> = c.faces.iter().map(|f| f.to_vec()).collect();
        for p in &mut polys {
            let n = p.len();
            for i in 0..n {
                let (a, b) = (p[i], p[(i + 1) % n]);
                if (a, b) == (0, 1) || (a, b) == (1, 0) {
                    p.insert(i + 1, 8);
                    break;
                }
            }
        }
        let mut pos = c.positions.clone();
        pos.push([0.0, -1.0, -1.0]);
        let t = build(&quad_split(&pos, &polys));
        assert_eq!(t.valence(8), 2);
        assert_eq!(euler(&t), 2);
        // A valid manifold, refined with the valence-2 rule.
        assert_eq!(t.check_valences(), Ok(()));
        assert_eq!(build(&c).check_valences(), Ok(()));
    }

    fn two_cubes_sharing(shared: &[u32]) -> QuadMesh {
        // Second cube shifted by (3, 0, 0); its vertices listed in `shared` are the first's.
        let a = cube();
        let mut positions = a.positions.clone();
        positions.extend(a.positions.iter().map(|p| [p[0] + 3.0, p[1], p[2]]));
        let map = |v: u32| if shared.contains(&v) { v } else { v + 8 };
        let mut faces = a.faces.clone();
        faces.extend(a.faces.iter().map(|f| f.map(map)));
        // Drop unused copies of the shared vertices by renumbering.
        let used: Vec<bool> = (0..16u32)
            .map(|v| faces.iter().any(|f| f.contains(&v)))
            .collect();
        let mut new_index = [0u32; 16];
        let mut kept = Vec::new();
        for v in 0..16 {
            if used[v] {
                new_index[v] = kept.len() as u32;
                kept.push(positions[v]);
            }
        }
        QuadMesh {
            positions: kept,
            faces: faces
                .iter()
                .map(|f| f.map(|v| new_index[v as usize]))
                .collect(),
        }
    }

    #[test]
    fn errors() {
        let c = cube();
        let err = |m: &QuadMesh| Topology::build(m).expect_err("should be rejected");

        // Boundary: the cube without its last face is an open mesh; drivers that need a
        // closed one say which edge is open.
        let mut m = c.clone();
        m.faces.pop();
        let t = build(&m);
        assert!(!t.is_closed());
        let e = t.require_closed().expect_err("open");
        assert!(matches!(e, TopologyError::BoundaryEdge { .. }), "{e}");
        assert_eq!(
            e.to_string(),
            "edge (4, 6) of face 0 has no other face (open boundary)"
        );

        // Non-manifold edge: a fin of one extra face on edge (0, 1).
        let mut m = c.clone();
        m.positions.push([0.0, -2.0, -1.0]);
        m.positions.push([0.0, -2.0, 0.0]);
        m.faces.push([0, 1, 8, 9]);
        let e = err(&m);
        assert_eq!(
            e,
            TopologyError::NonManifoldEdge {
                edge: [0, 1],
                faces: 3,
                face: 2
            }
        );
        assert_eq!(
            e.to_string(),
            "edge (0, 1) of face 2 is shared by 3 faces (non-manifold edge)"
        );

        // Two fins: the edge whose first face comes first is named, (4, 6) of face 0 before
        // (0, 1) of face 2, though its smaller end is larger.
        m.positions.push([1.0, 3.0, 1.0]);
        m.positions.push([1.0, 3.0, 0.0]);
        m.faces.push([4, 6, 10, 11]);
        assert_eq!(
            err(&m),
            TopologyError::NonManifoldEdge {
                edge: [4, 6],
                faces: 3,
                face: 0
            }
        );

        // Two cubes sharing an edge: 4 faces on it.
        let e = err(&two_cubes_sharing(&[0, 1]));
        assert!(
            matches!(e, TopologyError::NonManifoldEdge { faces: 4, .. }),
            "{e}"
        );

        // Non-manifold vertex: two cones (cube corners) glued at a vertex.
        let e = err(&two_cubes_sharing(&[0]));
        assert_eq!(e, TopologyError::NonManifoldVertex { vertex: 0, fans: 2 });
        assert_eq!(
            e.to_string(),
            "vertex 0: its faces form 2 separate fans (non-manifold vertex)"
        );

        // Isolated vertex.
        let mut m = c.clone();
        m.positions.insert(3, [9.0; 3]);
        for f in &mut m.faces {
            for v in f.iter_mut() {
                if *v >= 3 {
                    *v += 1;
                }
            }
        }
        let e = err(&m);
        assert_eq!(e, TopologyError::IsolatedVertex { vertex: 3 });
        assert_eq!(e.to_string(), "vertex 3 is used by no face");

        // Duplicate faces (same vertex set, here reversed).
        let mut m = c.clone();
        let mut dup = m.faces[2];
        dup.reverse();
        m.faces.insert(5, dup);
        let e = err(&m);
        assert_eq!(
            e,
            TopologyError::DuplicateFaces {
                first: 2,
                second: 5
            }
        );
        assert_eq!(e.to_string(), "faces 2 and 5 are duplicates");

        // Repeated vertex.
        let mut m = c.clone();
        m.faces[4] = [0, 6, 3, 6];
        let e = err(&m);
        assert_eq!(e, TopologyError::RepeatedVertex { face: 4, vertex: 6 });
        assert_eq!(e.to_string(), "face 4 repeats vertex 6");

        // Index out of range.
        let mut m = c.clone();
        m.faces[1][2] = 8;
        let e = err(&m);
        assert_eq!(
            e,
            TopologyError::FaceIndexOutOfRange {
                face: 1,
                index: 8,
                vertices: 8
            }
        );
        assert_eq!(
            e.to_string(),
            "face 1: vertex index 8 out of range (the mesh has 8 vertices)"
        );

        // No faces.
        let m = QuadMesh {
            positions: c.positions.clone(),
            faces: vec![],
        };
        assert_eq!(err(&m), TopologyError::NoFaces);
        assert_eq!(err(&m).to_string(), "empty mesh: no faces");
    }

    #[test]
    fn edge_ids_in_first_met_order() {
        for m in [cube(), star(), klein_bottle(3, 5)] {
            let t = build(&m);
            let mut next = 0;
            for f in 0..t.face_count() as u32 {
                for i in 0..4 {
                    let e = t.edge_of(f, i);
                    assert!(e <= next);
                    if e == next {
                        assert_eq!(t.edge_faces(e).0, (f, i));
                        next += 1;
                    }
                }
            }
            assert_eq!(next as usize, t.edge_count());
        }
    }

    #[test]
    fn rotation_starts_at_first_corner() {
        let m = torus(3, 4);
        let t = build(&m);
        for v in 0..t.vertex_count() as u32 {
            let w = t.rotation(v)[0];
            assert!(w.next_is_plus);
            let first = m.faces.iter().flatten().position(|&x| x == v).unwrap();
            assert_eq!(4 * w.face as usize + w.corner as usize, first);
        }
    }

    /// Random connectivity (in and out of range) never panics the builder.
    #[test]
    fn random_meshes_never_panic() {
        // A linear congruential generator (Knuth's MMIX constants).
        let mut state = 777u64;
        let mut below = |n: usize| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 33) % n as u64) as usize
        };
        for round in 0..400 {
            let nv = 1 + below(12);
            let nf = below(16);
            let faces = (0..nf)
                .map(|_| std::array::from_fn(|_| below(nv + usize::from(round % 5 == 0)) as u32))
                .collect();
            let mesh = QuadMesh {
                positions: vec![[0.0; 3]; nv],
                faces,
            };
            let _ = Topology::build(&mesh);
        }
        // Mutations of valid meshes: one face index changed.
        for round in 0..300 {
            let mut m = if round % 2 == 0 { torus(3, 3) } else { cube() };
            let f = below(m.faces.len());
            let c = below(4);
            m.faces[f][c] = below(m.positions.len()) as u32;
            if round % 7 == 0 {
                let f = below(m.faces.len());
                m.faces.swap_remove(f);
            }
            let _ = Topology::build(&m);
        }
    }
}
