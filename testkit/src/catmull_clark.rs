//! An independent, deliberately plain Catmull–Clark reference for polygon meshes (triangles,
//! quads, n-gons), closed or with boundaries, with OpenSubdiv's boundary, crease, corner and
//! hole rules. It uses only std and the `QuadMesh` and `Features` types, none of the crate's
//! connectivity code.
//!
//! # Rules
//!
//! Sources: the "Subdivision Surfaces" page of the OpenSubdiv documentation
//! (graphics.pixar.com/opensubdiv/docs/subdivision_surfaces.html, sections "Boundary
//! Interpolation Rules" and "Semi-Sharp Creases"), and OpenSubdiv 3.6's Sdc and Far sources:
//! `sdc/scheme.h`, `sdc/catmarkScheme.h`, `sdc/crease.cpp`, `sdc/crease.h` and
//! `far/topologyRefinerFactory.cpp` (`prepareComponentTagsAndSharpness`). Q is the average of
//! the adjacent face points, R the average of the midpoints of the incident edges, S the old
//! vertex, n its valence.
//!
//! * Face point: the centroid (`Scheme::ComputeFaceVertexMask`: weight 1/n on every corner).
//! * Edge point of a smooth interior edge: (v0 + v1 + f0 + f1)/4 with f0, f1 the face points
//!   (`Scheme<CATMARK>::assignSmoothMaskForEdge`, default triangle rule: vertex and face
//!   weights 1/4).
//! * Edge point of a boundary edge or of an edge sharp at this step: the midpoint
//!   (`Scheme::assignCreaseMaskForEdge`: 1/2, 1/2). A boundary edge is infinitely sharp
//!   (`prepareComponentTagsAndSharpness`: "eTag._boundary … eSharpness = SHARPNESS_INFINITE").
//! * Vertex point, by `Crease::DetermineVertexVertexRule`: a sharp vertex is a corner; else
//!   with c sharp incident edges (boundary edges included), c > 2 is a corner, c = 2 a crease,
//!   c = 1 a dart and c = 0 smooth.
//!   - smooth and dart (`Scheme::ComputeVertexVertexMask` gives a dart the smooth mask):
//!     (Q + 2R + (n − 3)S)/n (`Scheme<CATMARK>::assignSmoothMaskForVertex`: (n − 2)/n on S,
//!     1/n² on every edge's far end and every face point);
//!   - crease: (a + 6S + b)/8 with a, b the far ends of the two sharp edges
//!     (`Scheme<CATMARK>::assignCreaseMaskForVertex`: 3/4 on S, 1/8 on a and b);
//!   - corner: S (`Scheme::assignCornerMaskForVertex`: weight 1).
//! * Boundary modes ("Boundary Interpolation Rules", `Sdc::Options::VtxBoundaryInterpolation`):
//!   in [`Boundary::EdgeAndCorner`] a vertex with one face (and two edges) is made infinitely
//!   sharp, so a corner ("made to interpolate corner vertices (vertices with exactly one
//!   incident face)"; `prepareComponentTagsAndSharpness`: `isSharpenedCorner`). In
//!   [`Boundary::EdgeOnly`] it is not, and its two boundary edges make it a crease vertex.
//! * Semi-sharp integer sharpness s ("Semi-Sharp Creases"; `crease.h`, "Sharpness
//!   subdivision": "semi-sharp edges or verts are decremented by 1.0" with the uniform creasing
//!   method): an edge or vertex is sharp at a step while its current sharpness is > 0, and its
//!   children get s − 1. So an original sharpness s is sharp at steps 0..s. Where a vertex's
//!   rule changes from one level to the next, `Crease::ComputeFractionalWeightAtVertex` blends
//!   the parent's rule by the average of the parent sharpness of the edges with 0 < s ≤ 1 (and
//!   of the vertex, if it goes sharp to smooth), clamped to 1: with integer sharpness every
//!   such value is 1, so the parent's rule applies unblended, and likewise for edges
//!   (`Scheme::ComputeEdgeVertexMask`: "Sharpness >= 1.0 always a crease").
//! * Holes: a hole face is refined like any other and its children are holes
//!   (`Vtr::Refinement::populateFaceTagsFromParentFaces`: "Tags for faces originating from
//!   faces are inherited from the parent face"; "Hierarchical Edits" page: "none of their
//!   children will appear"). Holes change no position.
//! * A vertex with no faces stays where it is: OpenSubdiv tags it non-manifold
//!   (`Vtr::internal::Level::orderVertexFacesAndEdges` fails for no faces) and
//!   `prepareComponentTagsAndSharpness` makes a non-manifold vertex infinitely sharp, a corner.
//!
//! Limits: an edge with more than two faces panics; a vertex where several fans meet is not
//! detected as non-manifold (OpenSubdiv makes it a corner) unless it has three or more boundary
//! edges, which make it a corner here too.
//!
//! # Output numbering
//!
//! The vertex points (input order), then one edge point per edge in the order edges are first
//! met scanning faces in order and their local edges (corner i to i + 1), then one face point
//! per face. Corner i of face (v_0..v_{k−1}) becomes the quad (v_i, e(v_i v_{i+1}), f,
//! e(v_{i−1} v_i)); the quads of a face are consecutive, in face order and corner order. So
//! the quad (a, b, c, d) becomes (a', e_ab, f, e_da), (b', e_bc, f, e_ab), (c', e_cd, f, e_bc),
//! (d', e_da, f, e_cd).
//!
//! # Arithmetic
//!
//! In f64, in this order (the smooth rules are those of the closed reference this module
//! started as): face point = (Σ corners in face order) · (1/k); smooth edge point = ((v_lo +
//! v_hi) + (f0 + f1)) · 0.25 with v_lo the lower index and f0 the first face met; sharp edge
//! point = (v0 + v1) · 0.5; smooth vertex = ((Q + 2R) + (n − 3)S) · (1/n) with Q = (Σ face
//! points in face order) · (1/n) and R = (Σ midpoints (v_lo + v_hi) · 0.5 in edge order) · (1/n);
//! crease vertex = ((a + b) + 6S) · 0.125 with a before b in edge order.

use lsubdiv::mesh::features::{Boundary, Features, Sharpness};
use lsubdiv::mesh::QuadMesh;
use std::collections::HashMap;

#[cfg(test)]
mod tests;

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// The edges of a polygon list in first-met order (faces in order, corner i to i + 1), each with
/// its endpoints (lower index first) and its faces in the order met.
struct Edges {
    id: HashMap<(u32, u32), usize>,
    ends: Vec<(u32, u32)>,
    faces: Vec<Vec<usize>>,
}

impl Edges {
    fn of(polygons: &[Vec<u32>]) -> Edges {
        let mut edges = Edges {
            id: HashMap::new(),
            ends: Vec::new(),
            faces: Vec::new(),
        };
        for (fi, f) in polygons.iter().enumerate() {
            for i in 0..f.len() {
                let key = Edges::key(f[i], f[(i + 1) % f.len()]);
                let e = *edges.id.entry(key).or_insert_with(|| {
                    edges.ends.push(key);
                    edges.faces.push(Vec::new());
                    edges.ends.len() - 1
                });
                edges.faces[e].push(fi);
            }
        }
        edges
    }

    fn key(a: u32, b: u32) -> (u32, u32) {
        (a.min(b), a.max(b))
    }

    /// Panics unless every edge has `allowed` faces.
    fn assert_faces(&self, allowed: &[usize], what: &str) {
        for (e, faces) in self.faces.iter().enumerate() {
            assert!(
                allowed.contains(&faces.len()),
                "edge {:?} is not {what}",
                self.ends[e]
            );
        }
    }
}

/// One Catmull–Clark step of a closed quad mesh. Panics if an edge does not have exactly two
/// faces.
pub fn catmull_clark(mesh: &QuadMesh) -> QuadMesh {
    let faces: Vec<Vec<u32>> = mesh.faces.iter().map(|f| f.to_vec()).collect();
    catmull_clark_polygons(&mesh.positions, &faces)
}

/// One Catmull–Clark step of a closed polygon mesh (triangles, quads, n-gons), numbered as the
/// module says. Panics if an edge does not have exactly two faces.
pub fn catmull_clark_polygons(p: &[[f64; 3]], polygons: &[Vec<u32>]) -> QuadMesh {
    let edges = Edges::of(polygons);
    edges.assert_faces(&[2], "shared by two faces");
    refine(p, polygons, &edges, &Features::default()).0
}

/// `steps` Catmull–Clark steps of a closed quad mesh.
pub fn catmull_clark_steps(mesh: &QuadMesh, steps: usize) -> QuadMesh {
    let mut m = mesh.clone();
    for _ in 0..steps {
        m = catmull_clark(&m);
    }
    m
}

/// One Catmull–Clark step of a polygon mesh with boundaries and sharp features, by the rules
/// and with the numbering the module gives. Returns the quads and their features: a crease
/// ([a, b], s) still sharp after the step, s − 1 > 0, becomes ([a, e_ab], s − 1) and ([e_ab, b],
/// s − 1), in the input's order (vertex points keep their indices); a corner (v, s) becomes
/// (v, s − 1) while sharp; a hole face's quads are holes, in order; the boundary mode is copied.
/// Infinite sharpness stays infinite.
///
/// Panics if an edge has more than two faces, or a feature names an edge, vertex or face the
/// mesh lacks, or names an edge twice.
pub fn catmull_clark_features(
    p: &[[f64; 3]],
    polygons: &[Vec<u32>],
    features: &Features,
) -> (QuadMesh, Features) {
    let edges = Edges::of(polygons);
    edges.assert_faces(&[1, 2], "on one or two faces");
    refine(p, polygons, &edges, features)
}

/// `steps` ≥ 1 steps of [`catmull_clark_features`], each on the previous step's quads and
/// features.
pub fn catmull_clark_features_steps(
    p: &[[f64; 3]],
    polygons: &[Vec<u32>],
    features: &Features,
    steps: usize,
) -> (QuadMesh, Features) {
    assert!(steps >= 1, "at least one step (the input is not all quads)");
    let (mut m, mut f) = catmull_clark_features(p, polygons, features);
    for _ in 1..steps {
        let quads: Vec<Vec<u32>> = m.faces.iter().map(|q| q.to_vec()).collect();
        (m, f) = catmull_clark_features(&m.positions, &quads, &f);
    }
    (m, f)
}

/// How a vertex point is computed.
enum VertexRule {
    Smooth,
    /// The far ends of the two sharp edges, in edge order.
    Crease(u32, u32),
    Corner,
}

fn refine(
    p: &[[f64; 3]],
    polygons: &[Vec<u32>],
    edges: &Edges,
    features: &Features,
) -> (QuadMesh, Features) {
    let nv = p.len();
    let ne = edges.ends.len();

    let mut crease: HashMap<(u32, u32), Sharpness> = HashMap::new();
    for &([a, b], s) in &features.creases {
        let key = Edges::key(a, b);
        assert!(edges.id.contains_key(&key), "crease {a}-{b} is not an edge");
        assert!(crease.insert(key, s).is_none(), "crease {a}-{b} twice");
    }
    let mut corner = vec![false; nv];
    for &(v, s) in &features.corners {
        assert!((v as usize) < nv, "corner {v} is not a vertex");
        corner[v as usize] |= s.is_sharp();
    }
    for &f in &features.holes {
        assert!((f as usize) < polygons.len(), "hole {f} is not a face");
    }
    // Sharp at this step: a boundary edge, or a crease with sharpness left.
    let sharp: Vec<bool> = edges
        .ends
        .iter()
        .zip(&edges.faces)
        .map(|(key, faces)| faces.len() == 1 || crease.get(key).is_some_and(|s| s.is_sharp()))
        .collect();

    // Face points.
    let face_points: Vec<[f64; 3]> = polygons
        .iter()
        .map(|f| {
            let mut s = [0.0; 3];
            for &v in f {
                s = add(s, p[v as usize]);
            }
            scale(s, 1.0 / f.len() as f64)
        })
        .collect();

    let edge_points: Vec<[f64; 3]> = (0..ne)
        .map(|e| {
            let (a, b) = edges.ends[e];
            let ends = add(p[a as usize], p[b as usize]);
            if sharp[e] {
                scale(ends, 0.5)
            } else {
                let f = &edges.faces[e];
                scale(add(ends, add(face_points[f[0]], face_points[f[1]])), 0.25)
            }
        })
        .collect();

    // Per vertex: the adjacent face points' sum and count, the incident edges' midpoints' sum,
    // and the incident edges in edge order.
    let mut q_sum = vec![[0.0; 3]; nv];
    let mut q_count = vec![0usize; nv];
    for (fi, f) in polygons.iter().enumerate() {
        for &v in f {
            q_sum[v as usize] = add(q_sum[v as usize], face_points[fi]);
            q_count[v as usize] += 1;
        }
    }
    let mut r_sum = vec![[0.0; 3]; nv];
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); nv];
    for (e, &(a, b)) in edges.ends.iter().enumerate() {
        let mid = scale(add(p[a as usize], p[b as usize]), 0.5);
        for v in [a, b] {
            r_sum[v as usize] = add(r_sum[v as usize], mid);
            incident[v as usize].push(e);
        }
    }

    let rule = |v: usize| -> VertexRule {
        let far = |e: usize| {
            let (a, b) = edges.ends[e];
            if a as usize == v {
                b
            } else {
                a
            }
        };
        let sharp_far: Vec<u32> = incident[v]
            .iter()
            .filter(|&&e| sharp[e])
            .map(|&e| far(e))
            .collect();
        let topological_corner = q_count[v] == 1 && incident[v].len() == 2;
        if incident[v].is_empty()
            || corner[v]
            || (features.boundary == Boundary::EdgeAndCorner && topological_corner)
            || sharp_far.len() >= 3
        {
            VertexRule::Corner
        } else if sharp_far.len() == 2 {
            VertexRule::Crease(sharp_far[0], sharp_far[1])
        } else {
            assert_eq!(
                q_count[v],
                incident[v].len(),
                "vertex {v} takes the smooth rule but is not an interior manifold vertex"
            );
            VertexRule::Smooth
        }
    };
    let vertex_points: Vec<[f64; 3]> = (0..nv)
        .map(|v| {
            let s = p[v];
            match rule(v) {
                VertexRule::Corner => s,
                VertexRule::Crease(a, b) => {
                    scale(add(add(p[a as usize], p[b as usize]), scale(s, 6.0)), 0.125)
                }
                VertexRule::Smooth => {
                    let n = incident[v].len() as f64;
                    let q = scale(q_sum[v], 1.0 / q_count[v] as f64);
                    let r = scale(r_sum[v], 1.0 / n);
                    scale(add(add(q, scale(r, 2.0)), scale(s, n - 3.0)), 1.0 / n)
                }
            }
        })
        .collect();

    let mut positions = vertex_points;
    positions.extend(edge_points);
    positions.extend(face_points);

    let edge_vertex = |a: u32, b: u32| (nv + edges.id[&Edges::key(a, b)]) as u32;
    let mut faces = Vec::new();
    let mut first_child = Vec::with_capacity(polygons.len());
    for (fi, f) in polygons.iter().enumerate() {
        first_child.push(faces.len() as u32);
        let centre = (nv + ne + fi) as u32;
        let n = f.len();
        for i in 0..n {
            let (before, v, after) = (f[(i + n - 1) % n], f[i], f[(i + 1) % n]);
            faces.push([v, edge_vertex(v, after), centre, edge_vertex(before, v)]);
        }
    }

    let mut children = Features::with_boundary(features.boundary);
    for &([a, b], s) in &features.creases {
        let s = s.decremented();
        if s.is_sharp() {
            let e = edge_vertex(a, b);
            children.creases.push(([a, e], s));
            children.creases.push(([e, b], s));
        }
    }
    for &(v, s) in &features.corners {
        let s = s.decremented();
        if s.is_sharp() {
            children.corners.push((v, s));
        }
    }
    for &f in &features.holes {
        let first = first_child[f as usize];
        children
            .holes
            .extend(first..first + polygons[f as usize].len() as u32);
    }
    (QuadMesh { positions, faces }, children)
}
