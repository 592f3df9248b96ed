//! An independent, deliberately plain Catmull–Clark reference for closed polygon meshes. It
//! uses only std and the `QuadMesh` type, none of the crate's connectivity code.
//!
//! Rules: face point = average of the face's vertices; edge point = average of the two endpoints
//! and the two adjacent face points; vertex point = (Q + 2R + (n − 3)S) / n with Q the average of
//! the adjacent face points, R the average of the midpoints of the adjacent edges, S the old
//! vertex, n the valence.
//!
//! Output numbering: the vertex points (input order), then one edge point per edge in the order
//! edges are first met scanning faces in order and local edges 0..3, then one face point per
//! face. Face (a, b, c, d) becomes (a', e_ab, f, e_da), (b', e_bc, f, e_ab), (c', e_cd, f, e_bc),
//! (d', e_da, f, e_cd).

use lsubdiv::runtime::mesh::QuadMesh;
use std::collections::HashMap;

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// One Catmull–Clark step of a closed quad mesh. Panics if an edge does not have exactly two
/// faces.
pub fn catmull_clark(mesh: &QuadMesh) -> QuadMesh {
    let faces: Vec<Vec<u32>> = mesh.faces.iter().map(|f| f.to_vec()).collect();
    catmull_clark_polygons(&mesh.positions, &faces)
}

/// One Catmull–Clark step of a closed polygon mesh (triangles, quads, n-gons): face f of n
/// corners becomes n quads (corner i, the edge point after it, the face point, the edge point
/// before it). Panics if an edge does not have exactly two faces.
pub fn catmull_clark_polygons(p: &[[f64; 3]], polygons: &[Vec<u32>]) -> QuadMesh {
    let nv = p.len();

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

    // Edges in first-met order, with their faces.
    let mut edge_id: HashMap<(u32, u32), usize> = HashMap::new();
    let mut edge_ends: Vec<(u32, u32)> = Vec::new();
    let mut edge_faces: Vec<Vec<usize>> = Vec::new();
    for (fi, f) in polygons.iter().enumerate() {
        for i in 0..f.len() {
            let (a, b) = (f[i], f[(i + 1) % f.len()]);
            let key = (a.min(b), a.max(b));
            let e = *edge_id.entry(key).or_insert_with(|| {
                edge_ends.push(key);
                edge_faces.push(Vec::new());
                edge_ends.len() - 1
            });
            edge_faces[e].push(fi);
        }
    }
    for (e, faces) in edge_faces.iter().enumerate() {
        assert_eq!(
            faces.len(),
            2,
            "edge {:?} is not shared by two faces",
            edge_ends[e]
        );
    }

    let edge_points: Vec<[f64; 3]> = edge_ends
        .iter()
        .zip(&edge_faces)
        .map(|(&(a, b), faces)| {
            let s = add(
                add(p[a as usize], p[b as usize]),
                add(face_points[faces[0]], face_points[faces[1]]),
            );
            scale(s, 0.25)
        })
        .collect();

    // Vertex points: gather adjacent faces and edges of every vertex.
    let mut q_sum = vec![[0.0; 3]; nv];
    let mut q_count = vec![0usize; nv];
    for (fi, f) in polygons.iter().enumerate() {
        for &v in f {
            q_sum[v as usize] = add(q_sum[v as usize], face_points[fi]);
            q_count[v as usize] += 1;
        }
    }
    let mut r_sum = vec![[0.0; 3]; nv];
    let mut r_count = vec![0usize; nv];
    for &(a, b) in &edge_ends {
        let mid = scale(add(p[a as usize], p[b as usize]), 0.5);
        for v in [a, b] {
            r_sum[v as usize] = add(r_sum[v as usize], mid);
            r_count[v as usize] += 1;
        }
    }
    let vertex_points: Vec<[f64; 3]> = (0..nv)
        .map(|v| {
            let n = r_count[v] as f64;
            assert_eq!(
                q_count[v], r_count[v],
                "vertex {v} is not a closed-manifold vertex"
            );
            let q = scale(q_sum[v], 1.0 / q_count[v] as f64);
            let r = scale(r_sum[v], 1.0 / n);
            let s = p[v];
            scale(add(add(q, scale(r, 2.0)), scale(s, n - 3.0)), 1.0 / n)
        })
        .collect();

    let ne = edge_ends.len();
    let mut positions = vertex_points;
    positions.extend(edge_points);
    positions.extend(face_points);

    let edge_vertex = |a: u32, b: u32| (nv + edge_id[&(a.min(b), a.max(b))]) as u32;
    let mut faces = Vec::new();
    for (fi, f) in polygons.iter().enumerate() {
        let centre = (nv + ne + fi) as u32;
        let n = f.len();
        for i in 0..n {
            let (before, v, after) = (f[(i + n - 1) % n], f[i], f[(i + 1) % n]);
            faces.push([v, edge_vertex(v, after), centre, edge_vertex(before, v)]);
        }
    }
    QuadMesh { positions, faces }
}

/// `steps` Catmull–Clark steps.
pub fn catmull_clark_steps(mesh: &QuadMesh, steps: usize) -> QuadMesh {
    let mut m = mesh.clone();
    for _ in 0..steps {
        m = catmull_clark(&m);
    }
    m
}
