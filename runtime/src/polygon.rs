//! Polygon meshes (triangles, quads, n-gons) and the step that makes them quad meshes: one
//! Catmull–Clark step, as OpenSubdiv's Catmark scheme takes on a mesh with faces that are not
//! quads. Every n-gon becomes n quads; afterwards the mesh is all quads and any scheme refines it
//! (every new edge carrying the axiom, as every edge of a quad mesh does).
//!
//! The rules (Catmull & Clark 1978; OpenSubdiv, "Subdivision Surfaces", Catmark), for a closed
//! 2-manifold: the face point is the centroid of the face; the edge point of edge ab with faces
//! f, g is (a + b + F_f + F_g)/4; the vertex of valence n becomes (Q + 2R + (n − 3)v)/n, Q the
//! mean of the face points of its faces and R the mean of the midpoints of its edges.

use crate::mesh::QuadMesh;
use crate::topology::{check_corners, TopologyError};
use std::collections::HashMap;

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

/// One Catmull–Clark step of a polygon mesh: the quad mesh, and for each of its quads the face
/// it lies in. The first `V` vertices are the input's (so errors about them name the input's
/// vertices), then one per edge, then one per face.
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    /// The quads.
    pub mesh: QuadMesh,
    /// The input face of each quad.
    pub face_of: Vec<u32>,
}

/// One Catmull–Clark step of a closed 2-manifold polygon mesh. Errors name the input's faces,
/// vertices and edges: an index out of range, a vertex twice in a face, an edge with one face
/// (a boundary: not refined yet) or with more than two.
pub fn catmull_clark(m: &PolyMesh) -> Result<Split, TopologyError> {
    let nv = m.positions.len();
    let nf = m.face_count();
    if nf == 0 {
        return Err(TopologyError::NoFaces);
    }
    // Edges by first appearance, with their faces.
    let mut edge_index: HashMap<[u32; 2], u32> = HashMap::new();
    let mut edge_faces: Vec<Vec<u32>> = Vec::new();
    let mut edges: Vec<[u32; 2]> = Vec::new();
    for (f, face) in m.faces().enumerate() {
        let f = f as u32;
        check_corners(f, face, nv)?;
        for (i, &a) in face.iter().enumerate() {
            let b = face[(i + 1) % face.len()];
            let key = [a.min(b), a.max(b)];
            let e = *edge_index.entry(key).or_insert_with(|| {
                edges.push(key);
                edge_faces.push(Vec::new());
                (edges.len() - 1) as u32
            });
            edge_faces[e as usize].push(f);
        }
    }
    for (e, faces) in edge_faces.iter().enumerate() {
        match faces.len() {
            2 => {}
            1 => {
                return Err(TopologyError::BoundaryEdge {
                    edge: edges[e],
                    face: faces[0],
                })
            }
            n => {
                return Err(TopologyError::NonManifoldEdge {
                    edge: edges[e],
                    faces: n,
                    face: faces[2],
                })
            }
        }
    }
    let add = |a: [f64; 3], b: [f64; 3]| [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    let scale = |a: [f64; 3], s: f64| [a[0] * s, a[1] * s, a[2] * s];
    let face_points: Vec<[f64; 3]> = m
        .faces()
        .map(|face| {
            let sum = face
                .iter()
                .fold([0.0; 3], |s, &v| add(s, m.positions[v as usize]));
            scale(sum, 1.0 / face.len() as f64)
        })
        .collect();
    let edge_points: Vec<[f64; 3]> = edges
        .iter()
        .zip(&edge_faces)
        .map(|(&[a, b], faces)| {
            let ends = add(m.positions[a as usize], m.positions[b as usize]);
            let sides = add(
                face_points[faces[0] as usize],
                face_points[faces[1] as usize],
            );
            scale(add(ends, sides), 0.25)
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
    for &[a, b] in &edges {
        let mid = scale(add(m.positions[a as usize], m.positions[b as usize]), 0.5);
        for v in [a, b] {
            let s = &mut r[v as usize];
            *s = (add(s.0, mid), s.1 + 1);
        }
    }
    let mut positions: Vec<[f64; 3]> = (0..nv)
        .map(|v| {
            let (p, (qs, nq), (rs, n)) = (m.positions[v], q[v], r[v]);
            if n == 0 {
                return p; // an isolated vertex: the topology check reports it
            }
            let n_f = n as f64;
            let qm = scale(qs, 1.0 / nq as f64);
            let rm = scale(rs, 1.0 / n_f);
            scale(add(add(qm, scale(rm, 2.0)), scale(p, n_f - 3.0)), 1.0 / n_f)
        })
        .collect();
    positions.extend(edge_points);
    positions.extend(face_points);
    let edge_vertex = |a: u32, b: u32| nv as u32 + edge_index[&[a.min(b), a.max(b)]];
    let mut faces = Vec::with_capacity(m.corners.len());
    let mut face_of = Vec::with_capacity(m.corners.len());
    for (f, face) in m.faces().enumerate() {
        let centre = (nv + edges.len() + f) as u32;
        let n = face.len();
        for i in 0..n {
            let (prev, v, next) = (face[(i + n - 1) % n], face[i], face[(i + 1) % n]);
            faces.push([v, edge_vertex(v, next), centre, edge_vertex(prev, v)]);
            face_of.push(f as u32);
        }
    }
    Ok(Split {
        mesh: QuadMesh { positions, faces },
        face_of,
    })
}

impl TopologyError {
    /// The error with its face numbers mapped by `face_of` (a quad of a [`Split`] to the face
    /// it lies in), so that an error found on the split mesh names the input's face.
    pub fn in_faces(self, face_of: &[u32]) -> TopologyError {
        let map = |f: u32| face_of.get(f as usize).copied().unwrap_or(f);
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
            TopologyError::BoundaryEdge { edge, face } => TopologyError::BoundaryEdge {
                edge,
                face: map(face),
            },
            TopologyError::NonManifoldEdge { edge, faces, face } => {
                TopologyError::NonManifoldEdge {
                    edge,
                    faces,
                    face: map(face),
                }
            }
            e => e,
        }
    }
}
