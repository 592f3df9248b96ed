//! Meshes that are not 2-manifolds, refined as OpenSubdiv refines them, by every scheme.
//!
//! OpenSubdiv's Vtr (`Level::completeTopologyFromFaceVertices`, `orderVertexFacesAndEdges`)
//! tags an edge non-manifold when it has more than two faces, when one face uses it twice, when
//! its two faces use it in the same direction, or when it is degenerate (a face repeats a
//! vertex in consecutive corners), and a vertex when it
//! ends such an edge or its faces form more than one fan. Far
//! (`TopologyRefinerFactoryBase::prepareComponentTagsAndSharpness`) then makes every
//! non-manifold edge infinitely sharp and every non-manifold vertex an infinitely sharp corner,
//! except on a non-manifold crease: exactly two non-manifold edges, no boundary edge and more
//! faces than edges (fins meeting along a line), where the vertex keeps the crease rule.
//!
//! Sharp edges are lines of odd symmetry, refined from the points on them alone, and corners
//! stay where they are: so the faces on either side of a non-manifold edge or vertex never read
//! each other's points. [`separate`] gives each fan of a vertex its own copy of it (each face
//! corner joins the corners across the manifold edges at it: the fans are the components), tags
//! the copies and the edges between them as OpenSubdiv tags the originals, and drops vertices no
//! face uses. The result is a 2-manifold with boundaries that every scheme refines with its own
//! boundary and crease rules; [`Weld`] joins the refined copies of one point again.
//!
//! Two faces that use an edge in the same direction (opposite orientations) make it
//! non-manifold too, as in Vtr: a file's faces are taken as oriented. (The topology itself is
//! orientation-agnostic: a mesh built in memory, a Klein bottle, is refined smoothly across
//! such edges.)
//!
//! [`Boundary::None`] (OpenSubdiv's `VTX_BOUNDARY_NONE`) is applied here too: the faces at a
//! vertex with a boundary edge that is not tagged infinitely sharp become holes, and the
//! boundary is refined edge-only.

use crate::features::{Boundary, Features, Sharpness};
use crate::mesh::QuadMesh;
use crate::patch::Refined;
use crate::polygon::{PolyMesh, Split};
use crate::topology::TopologyError;
use std::collections::HashMap;

/// A mesh made a 2-manifold: the input's vertices that faces use, in order, then one copy for
/// each further fan of a non-manifold vertex; the faces as in the input (the same count, each
/// corner renamed); the features carried over, with OpenSubdiv's sharpness at the non-manifold
/// places.
#[derive(Clone, Debug, PartialEq)]
pub struct Separated {
    /// The manifold mesh.
    pub mesh: PolyMesh,
    /// Its features: the input's renamed (creases by their edge's copy, corners by each copy of
    /// their vertex), non-manifold edges infinitely sharp, non-manifold vertices infinitely
    /// sharp corners or ([`Features::fins`]) on a non-manifold crease; with
    /// [`Boundary::None`], the boundary faces holes and the boundary edge-only.
    pub features: Features,
    /// Per vertex of `mesh`, the input's vertex it stands for.
    pub origin: Vec<u32>,
    /// Per edge of `mesh` (its ends, smaller first), the input's edge it stands for, numbered
    /// as Vtr makes them (an edge a face uses again is another edge).
    pub edge_origin: HashMap<[u32; 2], u32>,
    /// How many input vertices no face uses (dropped).
    pub isolated: usize,
    /// How many input vertices are non-manifold.
    pub vertices: usize,
    /// How many input edges are non-manifold (each degenerate edge counted).
    pub edges: usize,
}

/// Union–find over face corners, with path halving.
struct Corners(Vec<u32>);

impl Corners {
    fn root(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let up = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = up;
            x = up;
        }
        x
    }

    fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.root(a), self.root(b));
        self.0[a.max(b) as usize] = a.min(b);
    }
}

/// A polygon mesh's edges as Vtr makes them, flat: half-edges (a corner stands for the one
/// from its vertex to the next corner's) grouped by their two vertices; a half-edge joins the
/// first edge of its two vertices unless that edge's last half-edge is of the same face (the
/// face uses the edge again: an edge of its own), and each degenerate half-edge (a face
/// repeating a vertex in consecutive corners) is an edge of its own.
struct Edges {
    /// The half-edges, edge after edge.
    half: Vec<u32>,
    /// Where each edge's half-edges start in `half`; one more than the edges.
    start: Vec<u32>,
    /// Per edge: degenerate.
    degenerate: Vec<bool>,
    /// Per edge: its two vertices have another edge.
    multi: Vec<bool>,
    /// The first edge of each pair of vertices ([`pair_key`]), sorted.
    first: Vec<(u64, u32)>,
}

/// Two vertices as one sortable key, the smaller in the high half.
fn pair_key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

impl Edges {
    fn of(m: &PolyMesh, face_of: &[u32]) -> Edges {
        let mut keyed = Vec::with_capacity(m.corners.len());
        let mut degenerate_half = Vec::new();
        for f in 0..m.face_count() {
            for c in m.offsets[f]..m.offsets[f + 1] {
                let (a, b) = (m.corners[c], m.corners[next(m, f, c)]);
                if a == b {
                    degenerate_half.push(c as u32);
                } else {
                    keyed.push((pair_key(a, b), c as u32));
                }
            }
        }
        // By vertex pair, then in face order.
        keyed.sort_unstable();
        let mut e = Edges {
            half: Vec::with_capacity(m.corners.len()),
            start: vec![0],
            degenerate: Vec::new(),
            multi: Vec::new(),
            first: Vec::new(),
        };
        let mut again = Vec::new();
        for group in keyed.chunk_by(|x, y| x.0 == y.0) {
            let (from, mut last) = (e.half.len(), u32::MAX);
            again.clear();
            for &(_, c) in group {
                if face_of[c as usize] == last {
                    again.push(c);
                } else {
                    e.half.push(c);
                    last = face_of[c as usize];
                }
            }
            e.first.push((group[0].0, e.degenerate.len() as u32));
            let multi = !again.is_empty();
            e.push(from, false, multi);
            for &c in &again {
                let from = e.half.len();
                e.half.push(c);
                e.push(from, false, true);
            }
        }
        for c in degenerate_half {
            let from = e.half.len();
            e.half.push(c);
            e.push(from, true, false);
        }
        e
    }

    /// Closes the edge whose half-edges start at `from`.
    fn push(&mut self, from: usize, degenerate: bool, multi: bool) {
        debug_assert_eq!(self.start.last(), Some(&(from as u32)));
        self.start.push(self.half.len() as u32);
        self.degenerate.push(degenerate);
        self.multi.push(multi);
    }

    fn len(&self) -> usize {
        self.degenerate.len()
    }

    /// The half-edges of edge e.
    fn get(&self, e: usize) -> &[u32] {
        &self.half[self.start[e] as usize..self.start[e + 1] as usize]
    }

    /// The first edge of vertices a and b, if they have one.
    fn first(&self, a: u32, b: u32) -> Option<usize> {
        let i = (self.first)
            .binary_search_by_key(&pair_key(a, b), |f| f.0)
            .ok()?;
        Some(self.first[i].1 as usize)
    }
}

/// The corner after corner `c` (an index into [`PolyMesh::corners`]) of face f.
fn next(m: &PolyMesh, f: usize, c: usize) -> usize {
    if c + 1 == m.offsets[f + 1] {
        m.offsets[f]
    } else {
        c + 1
    }
}

/// Separates the non-manifold vertices and edges of `m` (the rules of the [module](self)),
/// drops the vertices no face uses and applies [`Boundary::None`]; `None` when the mesh needs
/// none of it. `features` must fit `m` ([`crate::polygon::check_features`]). Errors: a corner
/// index out of range. A face may repeat its vertices as it likes (degenerate edges, as Vtr
/// takes them, even a face of one distinct vertex).
pub fn separate(m: &PolyMesh, features: &Features) -> Result<Option<Separated>, TopologyError> {
    let nv = m.positions.len();
    if m.face_count() == 0 {
        return Err(TopologyError::NoFaces);
    }
    if nv > u32::MAX as usize || m.corners.len() >= u32::MAX as usize {
        return Err(TopologyError::TooLarge {
            vertices: nv,
            faces: m.face_count(),
        });
    }
    for f in 0..m.face_count() {
        if let Some(&index) = m.face(f).iter().find(|&&v| v as usize >= nv) {
            return Err(TopologyError::FaceIndexOutOfRange {
                face: f as u32,
                index,
                vertices: nv,
            });
        }
    }
    let mut face_of = vec![0u32; m.corners.len()];
    for f in 0..m.face_count() {
        face_of[m.offsets[f]..m.offsets[f + 1]].fill(f as u32);
    }
    let edges = Edges::of(m, &face_of);
    // Two half-edges of different faces, in opposite directions.
    let manifold = |hs: &[u32]| {
        hs.len() == 2
            && face_of[hs[0] as usize] != face_of[hs[1] as usize]
            && m.corners[hs[0] as usize] != m.corners[hs[1] as usize]
    };
    let ends = |hs: &[u32]| {
        let c = hs[0] as usize;
        [m.corners[c], m.corners[next(m, face_of[c] as usize, c)]]
    };
    // An edge whose vertices have another edge (a face used it again) is non-manifold, as
    // every degenerate one, as Vtr tags them.
    let is_manifold = |e: usize| !edges.multi[e] && manifold(edges.get(e));
    let is_nonmanifold = |e: usize| {
        let hs = edges.get(e);
        edges.degenerate[e] || (!manifold(hs) && (hs.len() > 1 || edges.multi[e]))
    };
    let mut fans = Corners((0..m.corners.len() as u32).collect());
    let mut nonmanifold_vertex = vec![false; nv];
    // Per vertex: faces (corners), edges, boundary and non-manifold edges, as Far counts them.
    let mut faces_at = vec![0u32; nv];
    let mut edges_at = vec![0u32; nv];
    let mut boundary_at = vec![0u32; nv];
    let mut nonmanifold_at = vec![0u32; nv];
    let mut nonmanifold_edges = 0;
    for &v in &m.corners {
        faces_at[v as usize] += 1;
    }
    for e in 0..edges.len() {
        let hs = edges.get(e);
        let [a, b] = ends(hs);
        // A degenerate edge is met once at its vertex by each of its two ends.
        for v in [a, b] {
            edges_at[v as usize] += 1;
            boundary_at[v as usize] += u32::from(hs.len() == 1);
        }
        if is_manifold(e) {
            let (c, d) = (hs[0] as usize, hs[1] as usize);
            let after = |c: usize| next(m, face_of[c] as usize, c) as u32;
            fans.join(c as u32, after(d));
            fans.join(after(c), d as u32);
        } else if is_nonmanifold(e) {
            nonmanifold_edges += 1;
            for v in [a, b] {
                nonmanifold_vertex[v as usize] = true;
                nonmanifold_at[v as usize] += 1;
            }
        }
    }
    // One copy per fan: the vertex's first fan (by its first corner) keeps the vertex.
    let mut copy_of_root: HashMap<u32, u32> = HashMap::new();
    let mut first_fan = vec![u32::MAX; nv];
    let mut origin: Vec<u32> = Vec::new();
    let mut renamed = vec![0u32; nv];
    let used: Vec<bool> = faces_at.iter().map(|&k| k > 0).collect();
    for v in (0..nv).filter(|&v| used[v]) {
        renamed[v] = origin.len() as u32;
        origin.push(v as u32);
    }
    let mut corners = vec![0u32; m.corners.len()];
    for (c, &v) in m.corners.iter().enumerate() {
        let r = fans.root(c as u32);
        let v = v as usize;
        corners[c] = if first_fan[v] == u32::MAX || first_fan[v] == r {
            first_fan[v] = r;
            renamed[v]
        } else {
            nonmanifold_vertex[v] = true;
            *copy_of_root.entry(r).or_insert_with(|| {
                origin.push(v as u32);
                (origin.len() - 1) as u32
            })
        };
    }
    // A fan that meets one face twice (possible only around non-manifold edges) gives the
    // later corner a copy of its own, so that no face repeats a vertex: each copy is stamped
    // with the last face met at it (linear in the corners, whatever the polygons' sizes).
    let mut stamp = vec![u32::MAX; origin.len()];
    for f in 0..m.face_count() {
        for corner in &mut corners[m.offsets[f]..m.offsets[f + 1]] {
            let k = *corner as usize;
            if stamp[k] == f as u32 {
                let v = origin[k];
                nonmanifold_vertex[v as usize] = true;
                origin.push(v);
                stamp.push(f as u32);
                *corner = (origin.len() - 1) as u32;
            } else {
                stamp[k] = f as u32;
            }
        }
    }
    let isolated = used.iter().filter(|&&u| !u).count();
    let vertices = nonmanifold_vertex.iter().filter(|&&n| n).count();
    if isolated == 0 && vertices == 0 && features.boundary != Boundary::None {
        return Ok(None);
    }
    // Far's sharpening: every non-manifold vertex but one on a non-manifold crease.
    let crease =
        |v: usize| nonmanifold_at[v] == 2 && boundary_at[v] == 0 && faces_at[v] > edges_at[v];
    let sharpened = |v: usize| nonmanifold_vertex[v] && !crease(v);
    let mut copies: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (k, &v) in origin.iter().enumerate() {
        copies[v as usize].push(k as u32);
    }
    let mut out = Features {
        boundary: features.boundary,
        holes: features.holes.clone(),
        triangles: features.triangles,
        creasing: features.creasing,
        ..Features::default()
    };
    // Creases: a manifold edge's tag moves to its copy; every copy of a non-manifold edge is
    // infinitely sharp (whatever its tag).
    let copy_ends = |c: usize| {
        let f = face_of[c] as usize;
        let (a, b) = (corners[c], corners[next(m, f, c)]);
        [a.min(b), a.max(b)]
    };
    for &([a, b], s) in &features.creases {
        // A tag names the first edge of its two vertices, as Far's `findEdge` does.
        if let Some(e) = edges.first(a, b) {
            if !is_nonmanifold(e) {
                out.creases.push((copy_ends(edges.get(e)[0] as usize), s));
            }
        }
    }
    let mut sharp_copies: Vec<[u32; 2]> = Vec::new();
    for e in (0..edges.len()).filter(|&e| is_nonmanifold(e)) {
        sharp_copies.extend(edges.get(e).iter().map(|&c| copy_ends(c as usize)));
    }
    sharp_copies.sort_unstable();
    sharp_copies.dedup();
    let tagged: std::collections::HashSet<[u32; 2]> = out.creases.iter().map(|c| c.0).collect();
    out.creases.extend(
        sharp_copies
            .into_iter()
            .filter(|e| !tagged.contains(e))
            .map(|e| (e, Sharpness::INFINITE)),
    );
    // Corners: every copy of a sharpened vertex infinitely sharp; a tag on any other vertex
    // moves to each of its copies; fins as Far leaves them.
    let mut tag = vec![None; nv];
    for &(v, s) in &features.corners {
        tag[v as usize] = Some(s);
    }
    for v in (0..nv).filter(|&v| used[v]) {
        let s = if sharpened(v) {
            Some(Sharpness::INFINITE)
        } else {
            tag[v]
        };
        if let Some(s) = s {
            out.corners.extend(copies[v].iter().map(|&k| (k, s)));
        }
        if nonmanifold_vertex[v] && crease(v) {
            out.fins.extend(&copies[v]);
        }
    }
    if features.boundary == Boundary::None {
        // Far: the faces at a vertex with a boundary edge not tagged infinitely sharp are
        // holes (`makeBoundaryFacesHoles`), before boundary edges are sharpened.
        let inf: std::collections::HashSet<[u32; 2]> = features
            .creases
            .iter()
            .filter(|c| c.1.is_infinite())
            .map(|&([a, b], _)| [a.min(b), a.max(b)])
            .collect();
        let mut open = vec![false; nv];
        for hs in (0..edges.len())
            .map(|e| edges.get(e))
            .filter(|hs| hs.len() == 1)
        {
            let [a, b] = ends(hs);
            if a == b || !inf.contains(&[a.min(b), a.max(b)]) {
                open[a as usize] = true;
                open[b as usize] = true;
            }
        }
        let mut hole = vec![false; m.face_count()];
        for &h in &features.holes {
            hole[h as usize] = true;
        }
        for (c, &v) in m.corners.iter().enumerate() {
            hole[face_of[c] as usize] |= open[v as usize];
        }
        out.holes = (0..m.face_count() as u32)
            .filter(|&f| hole[f as usize])
            .collect();
        out.boundary = Boundary::EdgeOnly;
    }
    // Each edge of the separated mesh: the input edge it copies.
    let mut edge_origin = HashMap::new();
    for e in 0..edges.len() {
        for &c in edges.get(e) {
            edge_origin.entry(copy_ends(c as usize)).or_insert(e as u32);
        }
    }
    let positions = origin.iter().map(|&v| m.positions[v as usize]).collect();
    Ok(Some(Separated {
        mesh: PolyMesh {
            positions,
            offsets: m.offsets.clone(),
            corners,
        },
        features: out,
        origin,
        edge_origin,
        isolated,
        vertices,
        edges: nonmanifold_edges,
    }))
}

/// Which vertices of the quad mesh a refiner takes are copies of one point ([`separate`]), so
/// that the refined copies are joined again.
#[derive(Clone, Debug, PartialEq)]
pub struct Weld {
    /// Per vertex of the quad mesh, the point it stands for: copies share it.
    point: Vec<u32>,
    /// Whether more than one vertex stands for the point.
    shared: Vec<bool>,
    /// Per edge of the quad mesh (ends smaller first) that copies an input edge: that edge.
    edge: HashMap<[u32; 2], u32>,
}

impl Weld {
    /// For the separated mesh itself (all quads), from [`Separated::origin`] and
    /// [`Separated::edge_origin`].
    pub fn new(origin: &[u32], edge_origin: &HashMap<[u32; 2], u32>) -> Weld {
        Weld::of(origin.to_vec(), edge_origin.clone())
    }

    /// Per vertex of the quad mesh, the point it stands for (copies share it).
    pub fn points(&self) -> &[u32] {
        &self.point
    }

    /// For the first Catmull–Clark step of the separated mesh: its vertices stand for their
    /// origins ([`Separated::origin`]), each edge point for its edge's input edge
    /// ([`Separated::edge_origin`]), each face point for itself.
    pub fn after_split(
        origin: &[u32],
        edge_origin: &HashMap<[u32; 2], u32>,
        split: &Split,
    ) -> Weld {
        let mut point = origin.to_vec();
        let base = (origin.iter().map(|&v| v + 1).max().unwrap_or(0)).max(origin.len() as u32);
        let edges = edge_origin.values().map(|&e| e + 1).max().unwrap_or(0);
        let mut next = base + edges;
        for e in &split.edges {
            point.push(match edge_origin.get(e) {
                Some(&input) => base + input,
                None => {
                    next += 1;
                    next - 1
                }
            });
        }
        let rest = split.mesh.positions.len() - point.len();
        point.extend((0..rest as u32).map(|k| next + k));
        Weld::of(point, HashMap::new())
    }

    fn of(point: Vec<u32>, edge: HashMap<[u32; 2], u32>) -> Weld {
        let mut count: HashMap<u32, u32> = HashMap::new();
        for &p in &point {
            *count.entry(p).or_insert(0) += 1;
        }
        let shared = point.iter().map(|p| count[p] > 1).collect();
        Weld {
            point,
            shared,
            edge,
        }
    }

    /// Joins the copies in a refinement of the quad mesh whose faces are `base` and whose hole
    /// faces are `holes`: `faces` are the refined quads, an N × N grid per base face that is
    /// not a hole, in order, row by row from the face's first corner along its first edge
    /// (`patch::Refiner::faces`). Each point on a shared vertex or on an edge between two
    /// shared vertices is named by the points it stands for and its place along the edge; the
    /// first refined vertex of each name stays ([`Joined`]).
    pub fn join(
        &self,
        base: &[[u32; 4]],
        holes: &[u32],
        vertices: usize,
        faces: &[[u32; 4]],
    ) -> Joined {
        let mut hole = vec![false; base.len()];
        for &h in holes {
            hole[h as usize] = true;
        }
        let kept_faces = hole.iter().filter(|&&h| !h).count();
        let n = (0..=faces.len())
            .find(|n| n * n * kept_faces >= faces.len())
            .unwrap_or(0);
        let mut rep: Vec<u32> = (0..vertices as u32).collect();
        if n == 0 || n * n * kept_faces != faces.len() {
            return Joined {
                index: rep.clone(),
                kept: rep,
            };
        }
        let mut first: HashMap<(u32, u32, usize), u32> = HashMap::new();
        let live = base.iter().enumerate().filter(|(f, _)| !hole[*f]);
        for (k, (_, face)) in live.enumerate() {
            let quads = &faces[k * n * n..(k + 1) * n * n];
            // The grid point (x, y) of this face.
            let at = |x: usize, y: usize| {
                let (qx, qy) = (x.min(n - 1), y.min(n - 1));
                let q = quads[qy * n + qx];
                match (x == n, y == n) {
                    (false, false) => q[0],
                    (true, false) => q[1],
                    (true, true) => q[2],
                    (false, true) => q[3],
                }
            };
            // Corner l at (0,0), (n,0), (n,n), (0,n); edge l from corner l to corner l + 1.
            let corner = [(0, 0), (n, 0), (n, n), (0, n)];
            for l in 0..4 {
                let (a, b) = (face[l] as usize, face[(l + 1) % 4] as usize);
                let (pa, pb) = (self.point[a], self.point[b]);
                let ((x0, y0), (x1, y1)) = (corner[l], corner[(l + 1) % 4]);
                let along = |t: usize| {
                    let lerp = |u: usize, w: usize| (u * (n - t) + w * t) / n;
                    at(lerp(x0, x1), lerp(y0, y1))
                };
                let mut name = |key: (u32, u32, usize), v: u32| {
                    let r = *first.entry(key).or_insert(v);
                    rep[v as usize] = r;
                };
                if self.shared[a] {
                    name((pa, u32::MAX, 0), along(0));
                }
                if self.shared[a] && self.shared[b] && pa != pb {
                    // An edge is named by the input edge it copies, else by its ends.
                    let ends = match self.edge.get(&[a.min(b) as u32, a.max(b) as u32]) {
                        Some(&e) => (u32::MAX - 1, e),
                        None => (pa.min(pb), pa.max(pb)),
                    };
                    for t in 1..n {
                        let from_smaller = if pa < pb { t } else { n - t };
                        name((ends.0, ends.1, from_smaller), along(t));
                    }
                }
            }
        }
        let mut index = vec![u32::MAX; vertices];
        let mut kept = Vec::new();
        for v in 0..vertices {
            if rep[v] as usize == v {
                index[v] = kept.len() as u32;
                kept.push(v as u32);
            }
        }
        for v in 0..vertices {
            index[v] = index[rep[v] as usize];
        }
        Joined { index, kept }
    }

    /// `fine`, a refinement of the quad mesh `base` with hole faces `holes`, with the copies
    /// joined ([`Weld::join`]): the first copy's position and normal stay.
    pub fn apply<T: Copy>(&self, base: &[[u32; 4]], holes: &[u32], fine: Refined<T>) -> Refined<T> {
        let Refined {
            mesh,
            normals,
            approximate,
        } = fine;
        let joined = self.join(base, holes, mesh.positions.len(), &mesh.faces);
        Refined {
            normals: if normals.is_empty() {
                normals
            } else {
                joined.values(&normals)
            },
            mesh: QuadMesh {
                positions: joined.values(&mesh.positions),
                faces: joined.faces(&mesh.faces),
            },
            approximate: joined.vertices(&approximate),
        }
    }
}

/// A refinement's copies joined ([`Weld::join`]): per refined vertex its index among the kept
/// ones, and the kept ones' indices in the refinement.
#[derive(Clone, Debug, PartialEq)]
pub struct Joined {
    index: Vec<u32>,
    kept: Vec<u32>,
}

impl Joined {
    /// Per-vertex values (positions, normals) of the kept vertices.
    pub fn values<X: Copy>(&self, values: &[X]) -> Vec<X> {
        self.kept.iter().map(|&v| values[v as usize]).collect()
    }

    /// Quads in the kept vertices' numbering.
    pub fn faces(&self, faces: &[[u32; 4]]) -> Vec<[u32; 4]> {
        faces
            .iter()
            .map(|q| q.map(|v| self.index[v as usize]))
            .collect()
    }

    /// Vertices in the kept vertices' numbering, ascending, each once.
    pub fn vertices(&self, vertices: &[u32]) -> Vec<u32> {
        let mut joined: Vec<u32> = vertices.iter().map(|&v| self.index[v as usize]).collect();
        joined.sort_unstable();
        joined.dedup();
        joined
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(faces: &[&[u32]], vertices: usize) -> PolyMesh {
        let mut m = PolyMesh::new();
        m.positions = (0..vertices).map(|i| [i as f64, 0.0, 0.0]).collect();
        for f in faces {
            m.push_face(f);
        }
        m
    }

    #[test]
    fn edges_as_vtr_makes_them() {
        // Face 0 uses the pair 0–1 twice and 0–2 twice; face 1 shares 0–1 once more.
        let m = poly(&[&[0, 1, 0, 2], &[1, 0, 3]], 4);
        let face_of = [0, 0, 0, 0, 1, 1, 1];
        let e = Edges::of(&m, &face_of);
        let pair = |i: usize| {
            let c = e.get(i)[0] as usize;
            let f = face_of[c] as usize;
            let (a, b) = (m.corners[c], m.corners[next(&m, f, c)]);
            [a.min(b), a.max(b)]
        };
        let of = |p: [u32; 2]| (0..e.len()).filter(|&i| pair(i) == p).collect::<Vec<_>>();
        // 0–1: the first edge holds face 0's first use and face 1's; face 0's second use is
        // an edge of its own; both are non-manifold (multi).
        let zero_one = of([0, 1]);
        assert_eq!(zero_one.len(), 2);
        assert_eq!(e.get(zero_one[0]), &[0, 4]);
        assert_eq!(e.get(zero_one[1]), &[1]);
        assert!(zero_one.iter().all(|&i| e.multi[i]));
        assert_eq!(e.first(1, 0), Some(zero_one[0]));
        assert_eq!(of([0, 2]).len(), 2);
        assert_eq!(of([1, 3]).len(), 1);
        assert!(!e.multi[of([1, 3])[0]]);
    }

    #[test]
    fn separated_faces_never_repeat_a_vertex_and_welds_name_the_copies() {
        // A bow-tie (two triangles sharing vertex 0) and a face repeating vertex 5.
        let m = poly(&[&[0, 1, 2], &[0, 3, 4], &[5, 6, 5, 7]], 8);
        let s = separate(&m, &Features::default()).unwrap().unwrap();
        for f in s.mesh.faces() {
            let mut v = f.to_vec();
            v.sort_unstable();
            v.dedup();
            assert_eq!(v.len(), f.len(), "{f:?}");
        }
        // Vertices 0 and 5 have copies. Non-manifold, so corners: 0 (two fans), and 5, 6, 7,
        // the ends of the edges face 2 uses twice.
        let copies = |v: u32| s.origin.iter().filter(|&&o| o == v).count();
        assert_eq!((copies(0), copies(5)), (2, 2));
        for (k, &o) in s.origin.iter().enumerate() {
            let corner = s.features.corners.iter().any(|c| c.0 == k as u32);
            assert_eq!(corner, [0, 5, 6, 7].contains(&o), "copy {k} of {o}");
        }
        assert_eq!((s.vertices, s.edges), (4, 4));
        // A manifold mesh needs nothing.
        let quad = poly(&[&[0, 1, 2, 3]], 4);
        assert_eq!(separate(&quad, &Features::default()).unwrap(), None);
        // An index out of range is refused.
        let bad = poly(&[&[0, 1, 9]], 4);
        assert!(matches!(
            separate(&bad, &Features::default()),
            Err(TopologyError::FaceIndexOutOfRange { index: 9, .. })
        ));
    }
}
