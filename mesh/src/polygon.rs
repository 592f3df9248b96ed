//! Polygon meshes (triangles, quads, n-gons) and the step that makes them quad meshes: one
//! Catmull–Clark step, as OpenSubdiv's Catmark scheme takes on a mesh with faces that are not
//! quads. Every n-gon becomes n quads; afterwards the mesh is all quads and any scheme refines it
//! (every new edge carrying the axiom, as every edge of a quad mesh does).
//!
//! The rules (Catmull & Clark 1978; OpenSubdiv, "Subdivision Surfaces": Catmark, "Boundary
//! Interpolation Rules", "Semi-Sharp Creases"; `Sdc::Crease` rules smooth, dart, crease,
//! corner): the face point is the centroid of the face. The edge point of a smooth edge ab with
//! faces f, g is (a + b + F_f + F_g)/4; of a boundary edge, or an edge sharp at this step, the
//! midpoint (a + b)/2. A vertex is refined by its sharp edges (boundary edges count as sharp):
//! none or one (a dart), the smooth rule (Q + 2R + (n − 3)v)/n of valence n, Q the mean of the
//! face points of its faces and R the mean of the midpoints of its edges; two, the crease rule
//! (a + 6v + b)/8, a and b the other ends of the two; three or more, or a sharp vertex (a
//! corner tag), or a boundary vertex with one face in [`Boundary::EdgeAndCorner`](crate::features::Boundary::EdgeAndCorner) mode, the
//! corner rule v. Integer sharpness s is sharp at this step when s ≥ 1 and leaves children of
//! sharpness s − 1 (OpenSubdiv's uniform creasing; its rule-transition weight is 1 at integer
//! sharpness, so the rules are those of the current sharpness). Holes are refined like every
//! face; their children are holes.

use crate::features::{Creasing, FeatureError, Features, Sharpness, Triangles, VertexRule};
use crate::mesh::QuadMesh;
use crate::topology::{check_corners, TopologyError};
use std::collections::{HashMap, HashSet};

/// A polygon mesh: face f has the corners `corners[offsets[f]..offsets[f + 1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Start of each face's corners in `corners`, and their end: one more than the faces.
    pub offsets: Vec<usize>,
    /// 0-based vertex indices, face after face, in corner order.
    pub corners: Vec<u32>,
}

impl PolyMesh {
    /// No vertices, no faces.
    pub fn new() -> PolyMesh {
        PolyMesh {
            positions: Vec::new(),
            offsets: vec![0],
            corners: Vec::new(),
        }
    }

    /// Appends a face.
    pub fn push_face(&mut self, corners: &[u32]) {
        self.corners.extend_from_slice(corners);
        self.offsets.push(self.corners.len());
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The corners of face f.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.corners[self.offsets[f]..self.offsets[f + 1]]
    }

    /// The faces.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> {
        (0..self.face_count()).map(|f| self.face(f))
    }

    /// Every face is a quad.
    pub fn all_quads(&self) -> bool {
        self.offsets.windows(2).all(|w| w[1] - w[0] == 4)
    }

    /// The mesh as a quad mesh (its positions moved, not copied) when every face is a quad,
    /// else the mesh back.
    pub fn into_quads(self) -> Result<QuadMesh, PolyMesh> {
        if !self.all_quads() {
            return Err(self);
        }
        let faces = self
            .corners
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        Ok(QuadMesh {
            positions: self.positions,
            faces,
        })
    }
}

/// One Catmull–Clark step of a polygon mesh: the quad mesh, for each of its quads the face it
/// lies in, and its features. The first `V` vertices are the input's (so errors about them name
/// the input's vertices), then one per edge, then one per face; the quads of input face f are
/// numbered as its corners, `m.offsets[f]..m.offsets[f + 1]` of the input `m`.
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    /// The quads.
    pub mesh: QuadMesh,
    /// The input face of each quad.
    pub face_of: Vec<u32>,
    /// The input edge of each edge point: vertex `V + e` is the point of edge `edges[e]`
    /// (endpoints smaller first).
    pub edges: Vec<[u32; 2]>,
    /// The input's features one step on: a crease ab of sharpness s ≥ 2 becomes the two edges
    /// (a, m) and (m, b), m its edge point, of sharpness s − 1 (infinite stays infinite); a
    /// corner of sharpness s ≥ 2 keeps its vertex with sharpness s − 1; what becomes smooth is
    /// dropped; the quads of a
    /// hole are holes; the boundary rule is the input's.
    pub features: Features,
}

/// Why a polygon mesh and its features cannot be split.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SplitError {
    /// The connectivity: indices, non-manifold edges and vertices.
    Topology(TopologyError),
    /// A feature that does not fit the mesh.
    Feature(FeatureError),
}

impl From<TopologyError> for SplitError {
    fn from(e: TopologyError) -> SplitError {
        SplitError::Topology(e)
    }
}

impl From<FeatureError> for SplitError {
    fn from(e: FeatureError) -> SplitError {
        SplitError::Feature(e)
    }
}

impl std::fmt::Display for SplitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SplitError::Topology(e) => e.fmt(f),
            SplitError::Feature(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SplitError {}

/// The edges of a face, corner i to corner i + 1, endpoints smaller first.
fn face_edges(face: &[u32]) -> impl Iterator<Item = [u32; 2]> + '_ {
    let next = face.iter().cycle().skip(1);
    face.iter().zip(next).map(|(&a, &b)| [a.min(b), a.max(b)])
}

/// The edges of a polygon mesh in order of first appearance (face by face, corner by corner).
#[derive(Clone, Debug)]
struct Edges {
    /// Edge number by endpoints, smaller first.
    index: HashMap<[u32; 2], u32>,
    /// Endpoints of each edge, smaller first.
    ends: Vec<[u32; 2]>,
    /// The faces of each edge.
    faces: Vec<Vec<u32>>,
    /// For each corner of the mesh (as in [`PolyMesh::corners`]), the edge to the next corner
    /// of its face.
    after: Vec<u32>,
}

impl Edges {
    fn of(m: &PolyMesh) -> Edges {
        let mut index: HashMap<[u32; 2], u32> = HashMap::new();
        let mut ends = Vec::new();
        let mut faces: Vec<Vec<u32>> = Vec::new();
        let mut after = Vec::with_capacity(m.corners.len());
        for (f, face) in m.faces().enumerate() {
            for key in face_edges(face) {
                let e = *index.entry(key).or_insert_with(|| {
                    ends.push(key);
                    faces.push(Vec::new());
                    (ends.len() - 1) as u32
                });
                faces[e as usize].push(f as u32);
                after.push(e);
            }
        }
        Edges {
            index,
            ends,
            faces,
            after,
        }
    }

    /// The edge before corner `c` of face `f` (from the previous corner to it).
    fn before(&self, m: &PolyMesh, f: usize, c: usize) -> u32 {
        let prev = if c == m.offsets[f] {
            m.offsets[f + 1] - 1
        } else {
            c - 1
        };
        self.after[prev]
    }

    /// Refuses a vertex whose faces form more than one fan (a non-manifold vertex): around
    /// each vertex the faces, linked through the edges they share there, must form one cycle
    /// (an interior vertex) or one open chain (a boundary vertex). Each pair of a vertex and
    /// one of its edges is a node, each corner links the nodes of its two edges, and a vertex
    /// has as many fans as its nodes form components. Edges have at most two faces.
    fn check_fans(&self, m: &PolyMesh) -> Result<(), TopologyError> {
        let node = |v: u32, e: u32| 2 * e as usize + usize::from(self.ends[e as usize][1] == v);
        let mut parent: Vec<usize> = (0..2 * self.ends.len()).collect();
        let root = |parent: &mut Vec<usize>, mut x: usize| {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        };
        for f in 0..m.face_count() {
            for c in m.offsets[f]..m.offsets[f + 1] {
                let v = m.corners[c];
                let a = root(&mut parent, node(v, self.before(m, f, c)));
                let b = root(&mut parent, node(v, self.after[c]));
                parent[a.max(b)] = a.min(b);
            }
        }
        let mut fans = vec![0usize; m.positions.len()];
        for (n, &p) in parent.iter().enumerate() {
            if p == n {
                fans[self.ends[n / 2][n % 2] as usize] += 1;
            }
        }
        match fans.iter().position(|&k| k > 1) {
            Some(v) => Err(TopologyError::NonManifoldVertex {
                vertex: v as u32,
                fans: fans[v],
            }),
            None => Ok(()),
        }
    }
}

/// Checks `features` against a mesh of `vertices` vertices and these faces
/// ([`Features::validate`]), for a mesh that is not split ([`catmull_clark`] checks its own).
pub fn check_features<'a>(
    vertices: usize,
    faces: impl ExactSizeIterator<Item = &'a [u32]>,
    features: &Features,
) -> Result<(), FeatureError> {
    let count = faces.len();
    let edges: HashSet<[u32; 2]> = if features.creases.is_empty() {
        HashSet::new()
    } else {
        faces.flat_map(face_edges).collect()
    };
    features.validate(vertices, count, |e| edges.contains(&e))
}

/// The first Catmull–Clark step of a polygon mesh as a plan: its connectivity, sharpness and
/// vertex rules derived once ([`SplitPlan::new`]), the positions of any frame of the same mesh
/// computed from them ([`SplitPlan::positions`], the same operations in the same order as
/// [`catmull_clark`], which is both).
#[derive(Clone, Debug)]
pub struct SplitPlan {
    edges: Edges,
    /// Each edge's sharpness at this step.
    sharpness: Vec<Sharpness>,
    /// Each vertex's corner sharpness.
    corner: Vec<Sharpness>,
    /// Per vertex and level (this step, its child's): its sharp edges' count and the other
    /// ends of the first two.
    sharp_ends: Vec<[(usize, [u32; 2]); 2]>,
    /// Per vertex, the transition weight's sum and count.
    transition: Vec<(f32, u32)>,
    triangles: Triangles,
}

impl SplitPlan {
    /// The plan of `m`'s first step with `features`; errors as [`catmull_clark`]'s.
    pub fn new(m: &PolyMesh, features: &Features) -> Result<SplitPlan, SplitError> {
        let nv = m.positions.len();
        let nf = m.face_count();
        if nf == 0 {
            return Err(TopologyError::NoFaces.into());
        }
        for (f, face) in m.faces().enumerate() {
            check_corners(f as u32, face, nv)?;
        }
        let edges = Edges::of(m);
        let ne = edges.ends.len();
        if nv + ne + nf > u32::MAX as usize || m.corners.len() > (u32::MAX / 4) as usize {
            return Err(TopologyError::TooLarge {
                vertices: nv + ne + nf,
                faces: m.corners.len(),
            }
            .into());
        }
        if let Some(e) = edges.faces.iter().position(|f| f.len() > 2) {
            return Err(TopologyError::NonManifoldEdge {
                edge: edges.ends[e],
                faces: edges.faces[e].len(),
                face: edges.faces[e][2],
            }
            .into());
        }
        features.validate(nv, nf, |e| edges.index.contains_key(&e))?;
        edges.check_fans(m)?;
        let edge_of = |[a, b]: [u32; 2]| edges.index[&[a.min(b), a.max(b)]];
        // Sharpness: boundary edges infinitely sharp, creases and corners by their tags, and
        // under edge-and-corner a boundary vertex with one face (not a fin) a corner.
        let mut sharpness: Vec<Sharpness> = (edges.faces.iter())
            .map(|f| {
                if f.len() == 1 {
                    Sharpness::INFINITE
                } else {
                    Sharpness::SMOOTH
                }
            })
            .collect();
        for &(e, s) in &features.creases {
            let e = &mut sharpness[edge_of(e) as usize];
            if !e.is_infinite() {
                *e = s;
            }
        }
        // Each edge's children's sharpness at its two ends ([`Features::children`]).
        let children = features.edge_children(&sharpness, |[a, b]| {
            let e = edge_of([a, b]) as usize;
            Some((e, edges.ends[e][0] == a))
        });
        let mut corner = vec![Sharpness::SMOOTH; nv];
        for &(v, s) in &features.corners {
            corner[v as usize] = s;
        }
        let mut faces_at = vec![0usize; nv];
        for &v in &m.corners {
            faces_at[v as usize] += 1;
        }
        let by_boundary = features.corner_by_boundary();
        for (v, &faces) in faces_at.iter().enumerate() {
            if by_boundary(v as u32, faces) {
                corner[v] = Sharpness::INFINITE;
            }
        }
        // Per vertex and level (this step's sharpness, the children's): its sharp edges' count
        // and the other ends of the first two; the transition weight's sum and count.
        let mut sharp_ends = vec![[(0usize, [0u32; 2]); 2]; nv];
        let mut transition: Vec<(f32, u32)> = (corner.iter())
            .map(|c| match c.is_sharp() && !c.decremented().is_sharp() {
                true => (c.value(), 1),
                false => (0.0, 0),
            })
            .collect();
        for ((&[a, b], s), child) in edges.ends.iter().zip(&sharpness).zip(&children) {
            for (end, (v, other)) in [(a, b), (b, a)].into_iter().enumerate() {
                for (level, s) in [*s, child[end]].into_iter().enumerate() {
                    let e = &mut sharp_ends[v as usize][level];
                    if s.is_sharp() {
                        if e.0 < 2 {
                            e.1[e.0] = other;
                        }
                        e.0 += 1;
                    }
                }
                // `ComputeFractionalWeightAtVertex`: the sharp edges that end at v (uniform: those
                // of sharpness ≤ 1).
                let ends = match features.creasing {
                    Creasing::Uniform => s.value() <= 1.0,
                    Creasing::Chaikin => !child[end].is_sharp(),
                };
                if s.is_sharp() && ends {
                    let t = &mut transition[v as usize];
                    *t = (t.0 + s.value(), t.1 + 1);
                }
            }
        }
        Ok(SplitPlan {
            edges,
            sharpness,
            corner,
            sharp_ends,
            transition,
            triangles: features.triangles,
        })
    }

    /// The step's points for the positions `points` of the mesh `m` the plan was made for: its
    /// vertices' points, then one per edge, then one per face.
    pub fn positions(&self, m: &PolyMesh, points: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let SplitPlan {
            edges,
            sharpness,
            corner,
            sharp_ends,
            transition,
            triangles,
        } = self;
        let nv = points.len();
        let add = |a: [f64; 3], b: [f64; 3]| [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        let scale = |a: [f64; 3], s: f64| [a[0] * s, a[1] * s, a[2] * s];
        let face_points: Vec<[f64; 3]> = m
            .faces()
            .map(|face| {
                let sum = face
                    .iter()
                    .fold([0.0; 3], |s, &v| add(s, points[v as usize]));
                scale(sum, 1.0 / face.len() as f64)
            })
            .collect();
        // With the smooth-triangle rule, the face weight of an edge beside a triangle.
        let triangle_weight = |faces: &[u32]| {
            let tri = |f: u32| m.offsets[f as usize + 1] - m.offsets[f as usize] == 3;
            let weight = |f: u32| if tri(f) { 0.47 } else { 0.25 };
            (*triangles == Triangles::Smooth && faces.iter().any(|&f| tri(f)))
                .then(|| 0.5 * (weight(faces[0]) + weight(faces[1])))
        };
        let edge_points: Vec<[f64; 3]> = (edges.ends.iter().zip(&edges.faces).zip(sharpness))
            .map(|((&[a, b], faces), s)| {
                let ends = add(points[a as usize], points[b as usize]);
                let w = s.weight();
                if w >= 1.0 {
                    return scale(ends, 0.5);
                }
                let sides = add(
                    face_points[faces[0] as usize],
                    face_points[faces[1] as usize],
                );
                let smooth = match triangle_weight(faces) {
                    None => scale(add(ends, sides), 0.25),
                    // `assignSmoothMaskForEdge` with TRI_SUB_SMOOTH: both faces weigh the mean.
                    Some(fw) => add(scale(ends, 0.5 * (1.0 - 2.0 * fw)), scale(sides, fw)),
                };
                // Sharpness below 1: w of the crease rule (`ComputeEdgeVertexMask`).
                add(scale(ends, 0.5 * w), scale(smooth, 1.0 - w))
            })
            .collect();
        // Per vertex: the sum of its faces' points, of its edges' midpoints, and the counts.
        let mut q = vec![([0.0; 3], 0usize); nv];
        for (f, face) in m.faces().enumerate() {
            for &v in face {
                let s = &mut q[v as usize];
                *s = (add(s.0, face_points[f]), s.1 + 1);
            }
        }
        let mut r = vec![([0.0; 3], 0usize); nv];
        for &[a, b] in &edges.ends {
            let mid = scale(add(points[a as usize], points[b as usize]), 0.5);
            for v in [a, b] {
                let s = &mut r[v as usize];
                *s = (add(s.0, mid), s.1 + 1);
            }
        }
        let mut positions: Vec<[f64; 3]> = (0..nv)
            .map(|v| {
                let (p, (qs, nq), (rs, n)) = (points[v], q[v], r[v]);
                // The vertex's rule at a level (0: this step, 1: its child's), OpenSubdiv's
                // `Sdc::Crease::DetermineVertexVertexRule`.
                let rule = |level: usize| match sharp_ends[v][level] {
                    _ if [corner[v], corner[v].decremented()][level].is_sharp() => {
                        VertexRule::Corner
                    }
                    (3.., _) => VertexRule::Corner,
                    (2, _) => VertexRule::Crease,
                    _ => VertexRule::Smooth,
                };
                let child = |level: usize| match (rule(level), sharp_ends[v][level]) {
                    (VertexRule::Corner, _) => p,
                    (VertexRule::Crease, (_, [a, b])) => {
                        let ends = add(points[a as usize], points[b as usize]);
                        scale(add(ends, scale(p, 6.0)), 0.125)
                    }
                    _ if n == 0 => p,
                    _ => {
                        let n_f = n as f64;
                        let qm = scale(qs, 1.0 / nq as f64);
                        let rm = scale(rs, 1.0 / n_f);
                        scale(add(add(qm, scale(rm, 2.0)), scale(p, n_f - 3.0)), 1.0 / n_f)
                    }
                };
                let (parent, next) = (rule(0), rule(1));
                if parent == VertexRule::Smooth || parent == next {
                    return child(0);
                }
                // The rule changes: `ComputeFractionalWeightAtVertex` of the two.
                let (sum, count) = transition[v];
                let w = if count == 0 {
                    0.0
                } else {
                    f64::from((sum / count as f32).min(1.0))
                };
                add(scale(child(0), w), scale(child(1), 1.0 - w))
            })
            .collect();
        positions.extend(edge_points);
        positions.extend(face_points);
        positions
    }
}

/// One Catmull–Clark step of a 2-manifold polygon mesh with boundaries, creases, corners and
/// holes (the rules of the [module](self)). Errors name the input's faces, vertices and edges:
/// an index out of range, a vertex twice in a face, an edge with more than two faces, a vertex
/// whose faces form several fans, and features that do not fit ([`Features::validate`]).
pub fn catmull_clark(m: &PolyMesh, features: &Features) -> Result<Split, SplitError> {
    let plan = SplitPlan::new(m, features)?;
    let positions = plan.positions(m, &m.positions);
    let (nv, nf, edges) = (m.positions.len(), m.face_count(), &plan.edges);
    let ne = edges.ends.len();
    let edge_of = |[a, b]: [u32; 2]| edges.index[&[a.min(b), a.max(b)]];
    let mut faces = Vec::with_capacity(m.corners.len());
    let mut face_of = Vec::with_capacity(m.corners.len());
    for f in 0..nf {
        let centre = (nv + ne + f) as u32;
        for c in m.offsets[f]..m.offsets[f + 1] {
            let (after, before) = (edges.after[c], edges.before(m, f, c));
            faces.push([m.corners[c], nv as u32 + after, centre, nv as u32 + before]);
            face_of.push(f as u32);
        }
    }
    let features = features.stepped(
        |e| nv as u32 + edge_of(e),
        |f| (m.offsets[f as usize] as u32)..(m.offsets[f as usize + 1] as u32),
    );
    Ok(Split {
        mesh: QuadMesh { positions, faces },
        face_of,
        edges: plan.edges.ends,
        features,
    })
}

impl TopologyError {
    /// The error found on the mesh of `split` with its faces and edges mapped to the input's: a
    /// quad to the face it lies in, half an edge (an input vertex and the edge's point) to the
    /// edge.
    pub fn in_input(self, split: &Split) -> TopologyError {
        let map = |f: u32| split.face_of.get(f as usize).copied().unwrap_or(f);
        let faces = split.face_of.last().map_or(0, |&f| f as usize + 1);
        let first_point = (split.mesh.positions.len())
            .saturating_sub(split.edges.len())
            .saturating_sub(faces);
        let edge = |[v, m]: [u32; 2]| {
            let whole = (m as usize).checked_sub(first_point);
            match whole.and_then(|e| split.edges.get(e)) {
                Some(&ends) if (v as usize) < first_point && ends.contains(&v) => ends,
                _ => [v, m],
            }
        };
        match self {
            TopologyError::FaceIndexOutOfRange {
                face,
                index,
                vertices,
            } => TopologyError::FaceIndexOutOfRange {
                face: map(face),
                index,
                vertices,
            },
            TopologyError::RepeatedVertex { face, vertex } => TopologyError::RepeatedVertex {
                face: map(face),
                vertex,
            },
            TopologyError::DuplicateFaces { first, second } => TopologyError::DuplicateFaces {
                first: map(first),
                second: map(second),
            },
            TopologyError::BoundaryEdge { edge: e, face } => TopologyError::BoundaryEdge {
                edge: edge(e),
                face: map(face),
            },
            TopologyError::NonManifoldEdge {
                edge: e,
                faces,
                face,
            } => TopologyError::NonManifoldEdge {
                edge: edge(e),
                faces,
                face: map(face),
            },
            e => e,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::features::{Boundary, FeatureList, Sharpness};
    use crate::generators::cube;

    fn poly(positions: &[[f64; 3]], faces: &[&[u32]]) -> PolyMesh {
        let mut m = PolyMesh::new();
        m.positions = positions.to_vec();
        for f in faces {
            m.push_face(f);
        }
        m
    }

    fn cube_poly() -> PolyMesh {
        let c = cube();
        let faces: Vec<&[u32]> = c.faces.iter().map(|f| &f[..]).collect();
        poly(&c.positions, &faces)
    }

    fn with(boundary: Boundary, creases: &[([u32; 2], u32)], corners: &[(u32, u32)]) -> Features {
        Features {
            boundary,
            creases: creases
                .iter()
                .map(|&(e, s)| (e, Sharpness::steps(s)))
                .collect(),
            corners: corners
                .iter()
                .map(|&(v, s)| (v, Sharpness::steps(s)))
                .collect(),
            ..Features::default()
        }
    }

    fn assert_close(got: &[[f64; 3]], want: &[[f64; 3]]) {
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (i, (g, w)) in got.iter().zip(want).enumerate() {
            for c in 0..3 {
                assert!(
                    (g[c] - w[c]).abs() < 1e-12,
                    "point {i}: {g:?}, expected {w:?}"
                );
            }
        }
    }

    /// The point at `p` in the split mesh.
    fn vertex_at(s: &Split, p: [f64; 3]) -> u32 {
        let near = |q: &[f64; 3]| (0..3).all(|c| (q[c] - p[c]).abs() < 1e-12);
        s.mesh
            .positions
            .iter()
            .position(near)
            .expect("no such point") as u32
    }

    const SQUARE: [[f64; 3]; 4] = [[0., 0., 0.], [2., 0., 0.], [2., 2., 0.], [0., 2., 0.]];

    #[test]
    fn an_open_quad_keeps_its_corners_and_halves_its_edges() {
        let m = poly(&SQUARE, &[&[0, 1, 2, 3]]);
        let s = catmull_clark(&m, &Features::default()).unwrap();
        let mids = [[1., 0., 0.], [2., 1., 0.], [1., 2., 0.], [0., 1., 0.]];
        let want: Vec<[f64; 3]> = [&SQUARE[..], &mids, &[[1., 1., 0.]]].concat();
        assert_eq!(s.mesh.positions, want);
        assert_eq!(
            s.mesh.faces,
            vec![[0, 4, 8, 7], [1, 5, 8, 4], [2, 6, 8, 5], [3, 7, 8, 6]]
        );
        assert_eq!(s.face_of, vec![0; 4]);
        assert_eq!(s.features, Features::default());
        // Edge-only: each one-face vertex is a crease vertex of the boundary, (a + 6v + b)/8.
        let s = catmull_clark(&m, &Features::with_boundary(Boundary::EdgeOnly)).unwrap();
        let corners = [
            [0.25, 0.25, 0.],
            [1.75, 0.25, 0.],
            [1.75, 1.75, 0.],
            [0.25, 1.75, 0.],
        ];
        assert_eq!(s.mesh.positions[..4], corners);
        assert_eq!(s.mesh.positions[4..], want[4..]);
        assert_eq!(s.features, Features::with_boundary(Boundary::EdgeOnly));
    }

    #[test]
    fn errors_on_the_split_name_the_input() {
        let s = catmull_clark(&poly(&SQUARE, &[&[0, 1, 2, 3]]), &Features::default()).unwrap();
        assert_eq!(s.edges, vec![[0, 1], [1, 2], [2, 3], [0, 3]]);
        // Half of edge 2–3 (vertex 3 and point 6), and an edge inside the face.
        for (edge, input) in [
            ([3, 6], [2, 3]),
            ([2, 6], [2, 3]),
            ([1, 4], [0, 1]),
            ([6, 8], [6, 8]),
        ] {
            let e = TopologyError::BoundaryEdge { edge, face: 3 };
            assert_eq!(
                e.in_input(&s),
                TopologyError::BoundaryEdge {
                    edge: input,
                    face: 0
                }
            );
        }
        let e = TopologyError::NonManifoldEdge {
            edge: [0, 7],
            faces: 3,
            face: 2,
        };
        let input = TopologyError::NonManifoldEdge {
            edge: [0, 3],
            faces: 3,
            face: 0,
        };
        assert_eq!(e.in_input(&s), input);
        // Not half of an edge: vertex 0 is not on edge 1–2.
        let e = TopologyError::BoundaryEdge {
            edge: [0, 5],
            face: 1,
        };
        let same = TopologyError::BoundaryEdge {
            edge: [0, 5],
            face: 0,
        };
        assert_eq!(e.in_input(&s), same);
    }

    /// Three triangles around vertex 0, open: 0 is a boundary vertex with three faces.
    fn fan() -> PolyMesh {
        let p = [
            [0., 0., 0.],
            [24., 0., 0.],
            [24., 24., 0.],
            [0., 24., 0.],
            [-24., 24., 0.],
        ];
        poly(&p, &[&[0, 1, 2], &[0, 2, 3], &[0, 3, 4]])
    }

    #[test]
    fn a_triangle_fan_with_a_boundary() {
        let s = catmull_clark(&fan(), &Features::default()).unwrap();
        // Edges in order: 01 12 02 23 03 34 04; 02 and 03 are interior.
        let want = [
            [0., 3., 0.],    // (p1 + 6 p0 + p4)/8
            [24., 0., 0.],   // one face: a corner
            [21., 21., 0.],  // (p1 + 6 p2 + p3)/8
            [0., 24., 0.],   // (p2 + 6 p3 + p4)/8
            [-24., 24., 0.], // one face: a corner
            [12., 0., 0.],
            [24., 12., 0.],
            [12., 12., 0.], // (p0 + p2 + F0 + F1)/4
            [12., 24., 0.],
            [0., 14., 0.], // (p0 + p3 + F1 + F2)/4
            [-12., 24., 0.],
            [-12., 12., 0.],
            [16., 8., 0.],
            [8., 16., 0.],
            [-8., 16., 0.],
        ];
        assert_close(&s.mesh.positions, &want);
        assert_eq!(s.face_of, vec![0, 0, 0, 1, 1, 1, 2, 2, 2]);
        assert_eq!(s.mesh.faces[3], [0, 7, 13, 9]);
        let s = catmull_clark(&fan(), &Features::with_boundary(Boundary::EdgeOnly)).unwrap();
        let mut edge_only = want;
        edge_only[1] = [21., 3., 0.]; // (p0 + 6 p1 + p2)/8
        edge_only[4] = [-18., 21., 0.]; // (p3 + 6 p4 + p0)/8
        assert_close(&s.mesh.positions, &edge_only);
        // A crease from the boundary vertex 0 to the boundary vertex 3 makes both corners
        // (three sharp edges each) and is halved.
        let s =
            catmull_clark(&fan(), &with(Boundary::EdgeAndCorner, &[([3, 0], 10)], &[])).unwrap();
        let mut creased = want;
        creased[0] = [0., 0., 0.];
        creased[9] = [0., 12., 0.];
        assert_close(&s.mesh.positions, &creased);
        assert_eq!(
            s.features.creases,
            vec![([3, 9], Sharpness::INFINITE), ([9, 0], Sharpness::INFINITE)]
        );
    }

    #[test]
    fn a_crease_loop_on_a_cube() {
        // The four edges of the top face (z = 1), infinitely sharp.
        let loop_edges = [[4, 5], [5, 7], [7, 6], [6, 4]];
        let f = with(Boundary::EdgeAndCorner, &loop_edges.map(|e| (e, 10)), &[]);
        let s = catmull_clark(&cube_poly(), &f).unwrap();
        let p = &s.mesh.positions;
        for v in 0..8 {
            let c = cube().positions[v];
            let want = if c[2] > 0.0 {
                [0.75 * c[0], 0.75 * c[1], 1.0] // crease rule along the loop
            } else {
                c.map(|x| 5.0 / 9.0 * x) // smooth, valence 3
            };
            assert_close(&p[v..=v], &[want]);
        }
        // Crease edges are halved; the vertical ones are smooth.
        for e in loop_edges {
            let (a, b) = (
                cube().positions[e[0] as usize],
                cube().positions[e[1] as usize],
            );
            let m = vertex_at(&s, [0, 1, 2].map(|c| (a[c] + b[c]) / 2.0));
            assert!(m >= 8);
        }
        vertex_at(&s, [0.75, 0.75, 0.0]); // edge 3–7: (v3 + v7 + F(x=1) + F(y=1))/4
                                          // Each crease becomes its two halves, still infinitely sharp.
        let mut want = Vec::new();
        for [a, b] in loop_edges {
            let (pa, pb) = (cube().positions[a as usize], cube().positions[b as usize]);
            let m = vertex_at(&s, [0, 1, 2].map(|c| (pa[c] + pb[c]) / 2.0));
            want.push(([a, m], Sharpness::INFINITE));
            want.push(([m, b], Sharpness::INFINITE));
        }
        assert_eq!(s.features.creases, want);
    }

    #[test]
    fn darts_are_smooth_and_three_sharp_edges_make_a_corner() {
        let plain = catmull_clark(&cube_poly(), &Features::default()).unwrap();
        // One sharp edge 5–7: both ends are darts (the smooth rule); its point is its midpoint.
        let dart = with(Boundary::EdgeAndCorner, &[([5, 7], 10)], &[]);
        let s = catmull_clark(&cube_poly(), &dart).unwrap();
        assert_eq!(s.mesh.positions[..8], plain.mesh.positions[..8]);
        let m = vertex_at(&s, [1., 0., 1.]) as usize;
        assert_eq!(plain.mesh.positions[m], [0.75, 0., 0.75]);
        let differ: Vec<usize> = (0..s.mesh.positions.len())
            .filter(|&i| s.mesh.positions[i] != plain.mesh.positions[i])
            .collect();
        assert_eq!(differ, vec![m]);
        // Three sharp edges at vertex 7: a corner; their other ends are darts.
        let three = with(
            Boundary::EdgeAndCorner,
            &[([7, 5], 10), ([7, 6], 10), ([3, 7], 10)],
            &[],
        );
        let s = catmull_clark(&cube_poly(), &three).unwrap();
        assert_eq!(s.mesh.positions[7], [1., 1., 1.]);
        assert_eq!(s.mesh.positions[..7], plain.mesh.positions[..7]);
    }

    #[test]
    fn semi_sharp_creases_and_corners_lose_one_step() {
        let plain = catmull_clark(&cube_poly(), &Features::default()).unwrap();
        // Sharpness 1: sharp at this step (the midpoint), smooth children (dropped).
        let s =
            catmull_clark(&cube_poly(), &with(Boundary::EdgeOnly, &[([5, 7], 1)], &[])).unwrap();
        let m = vertex_at(&s, [1., 0., 1.]);
        assert_eq!(s.features, Features::with_boundary(Boundary::EdgeOnly));
        // Sharpness 3: children of sharpness 2; the same points.
        let s3 =
            catmull_clark(&cube_poly(), &with(Boundary::EdgeOnly, &[([5, 7], 3)], &[])).unwrap();
        assert_eq!(s3.mesh, s.mesh);
        let two = Sharpness::steps(2);
        assert_eq!(s3.features.creases, vec![([5, m], two), ([m, 7], two)]);
        // Sharpness 0: smooth now and after.
        let s0 =
            catmull_clark(&cube_poly(), &with(Boundary::EdgeOnly, &[([5, 7], 0)], &[])).unwrap();
        assert_eq!(s0.mesh, plain.mesh);
        assert!(s0.features.is_empty());
        // A corner tag of sharpness 2 holds its vertex and keeps sharpness 1; of 1, is dropped.
        for (sharpness, kept) in [(2, vec![(7, Sharpness::steps(1))]), (1, vec![])] {
            let f = with(Boundary::EdgeAndCorner, &[], &[(7, sharpness)]);
            let s = catmull_clark(&cube_poly(), &f).unwrap();
            assert_eq!(s.mesh.positions[7], [1., 1., 1.]);
            assert_eq!(s.mesh.positions[..7], plain.mesh.positions[..7]);
            assert_eq!(s.features.corners, kept);
        }
    }

    #[test]
    fn the_quads_of_a_hole_are_holes() {
        let f = Features {
            holes: vec![1],
            ..Features::default()
        };
        let s = catmull_clark(&fan(), &f).unwrap();
        assert_eq!(s.features.holes, vec![3, 4, 5]);
        assert_eq!(
            s.mesh,
            catmull_clark(&fan(), &Features::default()).unwrap().mesh
        );
        let s = catmull_clark(
            &cube_poly(),
            &Features {
                holes: vec![5, 0],
                ..f
            },
        )
        .unwrap();
        assert_eq!(s.features.holes, vec![20, 21, 22, 23, 0, 1, 2, 3]);
    }

    #[test]
    fn non_manifold_edges_and_vertices_are_refused() {
        let p = [[0.; 3]; 9];
        let three = poly(&p, &[&[0, 1, 2], &[1, 0, 3], &[0, 1, 4]]);
        assert_eq!(
            catmull_clark(&three, &Features::default()),
            Err(SplitError::Topology(TopologyError::NonManifoldEdge {
                edge: [0, 1],
                faces: 3,
                face: 2
            }))
        );
        let bowtie = poly(&p, &[&[0, 1, 2], &[0, 3, 4]]);
        let two_fans = Err(SplitError::Topology(TopologyError::NonManifoldVertex {
            vertex: 0,
            fans: 2,
        }));
        assert_eq!(catmull_clark(&bowtie, &Features::default()), two_fans);
        // Two closed tetrahedra sharing vertex 0: two cycles of faces.
        let tets = poly(
            &p,
            &[
                &[0, 1, 2],
                &[0, 2, 3],
                &[0, 3, 1],
                &[1, 3, 2],
                &[0, 5, 4],
                &[0, 6, 5],
                &[0, 4, 6],
                &[4, 5, 6],
            ],
        );
        assert_eq!(catmull_clark(&tets, &Features::default()), two_fans);
        // An open chain and a cycle at one vertex.
        let mixed = poly(
            &p,
            &[&[0, 1, 2], &[0, 2, 3], &[0, 3, 1], &[1, 3, 2], &[0, 7, 8]],
        );
        assert_eq!(catmull_clark(&mixed, &Features::default()), two_fans);
    }

    #[test]
    fn features_that_do_not_fit_are_refused() {
        let cases = [
            (
                with(Boundary::EdgeAndCorner, &[([4, 5], 1), ([0, 7], 1)], &[]),
                FeatureError::NoSuchEdge {
                    crease: 1,
                    edge: [0, 7],
                },
            ),
            (
                with(Boundary::EdgeAndCorner, &[([3, 3], 1)], &[]),
                FeatureError::NoSuchEdge {
                    crease: 0,
                    edge: [3, 3],
                },
            ),
            (
                with(Boundary::EdgeAndCorner, &[([9, 3], 1)], &[]),
                FeatureError::NoSuchEdge {
                    crease: 0,
                    edge: [9, 3],
                },
            ),
            (
                with(Boundary::EdgeAndCorner, &[], &[(1, 2), (8, 2)]),
                FeatureError::NoSuchVertex {
                    corner: 1,
                    vertex: 8,
                    vertices: 8,
                },
            ),
            (
                Features {
                    holes: vec![6],
                    ..Features::default()
                },
                FeatureError::NoSuchFace {
                    hole: 0,
                    face: 6,
                    faces: 6,
                },
            ),
            (
                with(
                    Boundary::EdgeAndCorner,
                    &[([4, 5], 1), ([5, 7], 2), ([5, 4], 1)],
                    &[],
                ),
                FeatureError::Repeated {
                    list: FeatureList::Creases,
                    first: 0,
                    second: 2,
                },
            ),
            (
                with(Boundary::EdgeAndCorner, &[], &[(1, 2), (1, 2)]),
                FeatureError::Repeated {
                    list: FeatureList::Corners,
                    first: 0,
                    second: 1,
                },
            ),
            (
                Features {
                    holes: vec![2, 3, 2],
                    ..Features::default()
                },
                FeatureError::Repeated {
                    list: FeatureList::Holes,
                    first: 0,
                    second: 2,
                },
            ),
        ];
        let c = cube();
        for (f, e) in cases {
            assert_eq!(
                catmull_clark(&cube_poly(), &f),
                Err(SplitError::Feature(e)),
                "{f:?}"
            );
            let faces = c.faces.iter().map(|f| &f[..]);
            assert_eq!(check_features(8, faces, &f), Err(e), "{f:?}");
        }
        assert_eq!(
            SplitError::Feature(FeatureError::NoSuchEdge {
                crease: 1,
                edge: [0, 7]
            })
            .to_string(),
            "crease 1: no such edge (0, 7) in the mesh"
        );
        let fits = with(Boundary::EdgeAndCorner, &[([4, 5], 1)], &[(7, 3)]);
        assert_eq!(
            check_features(8, c.faces.iter().map(|f| &f[..]), &fits),
            Ok(())
        );
    }
}
