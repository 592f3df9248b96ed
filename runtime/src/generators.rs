//! Standard closed quad meshes for tests and examples. Faces are oriented counter-clockwise seen
//! from outside wherever the surface is orientable.

use crate::mesh::QuadMesh;
use crate::polygon::PolyMesh;
use std::collections::HashMap;
use std::f64::consts::TAU;

/// Torus with `rows` × `cols` quads (all vertices valence 4), major radius 1, minor 0.35.
/// Vertex `i * cols + j` sits at angle 2πi/rows around the axis (z) and 2πj/cols around the
/// tube. Panics unless rows, cols >= 3.
pub fn torus(rows: usize, cols: usize) -> QuadMesh {
    assert!(rows >= 3 && cols >= 3, "torus needs rows, cols >= 3");
    let (big, small) = (1.0, 0.35);
    let mut positions = Vec::with_capacity(rows * cols);
    for i in 0..rows {
        let u = TAU * i as f64 / rows as f64;
        for j in 0..cols {
            let v = TAU * j as f64 / cols as f64;
            let r = big + small * v.cos();
            positions.push([r * u.cos(), r * u.sin(), small * v.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % rows) * cols + j % cols) as u32;
    let mut faces = Vec::with_capacity(rows * cols);
    for i in 0..rows {
        for j in 0..cols {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    QuadMesh { positions, faces }
}

/// The cube [-1,1]^3: 8 vertices of valence 3, 6 quads. Vertex `x + 2y + 4z` (bits) sits at
/// the corner with those coordinates set to 1 (else -1).
pub fn cube() -> QuadMesh {
    let positions = (0..8)
        .map(|i| {
            let c = |bit: usize| if i >> bit & 1 == 1 { 1.0 } else { -1.0 };
            [c(0), c(1), c(2)]
        })
        .collect();
    let faces = vec![
        [0, 4, 6, 2], // x = -1
        [1, 3, 7, 5], // x = +1
        [0, 1, 5, 4], // y = -1
        [2, 6, 7, 3], // y = +1
        [0, 2, 3, 1], // z = -1
        [4, 5, 7, 6], // z = +1
    ];
    QuadMesh { positions, faces }
}

/// One Catmull–Clark *topological* split of a closed polygonal mesh given as faces of any degree
/// (positions: face points = face centroid, edge points = edge midpoints, old vertices
/// unchanged). Face points get valence = face degree; old vertices keep theirs.
///
/// Output numbering: the old vertices, then one edge point per edge in the order edges are first
/// met scanning polygons in order, then one face point per polygon. Corner i of a polygon
/// (v_0..v_{k-1}) becomes the quad (v_i, e(v_i v_{i+1}), f, e(v_{i-1} v_i)), which keeps the
/// polygon's orientation. Panics if a polygon has fewer than 3 vertices or an index is out of
/// range.
pub fn quad_split(positions: &[[f64; 3]], polygons: &[Vec<u32>]) -> QuadMesh {
    let nv = positions.len();
    let corners: usize = polygons.iter().map(Vec::len).sum();
    assert!(
        nv + corners + polygons.len() <= u32::MAX as usize,
        "mesh too large"
    );
    let mut out = positions.to_vec();
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    // Edge point index of every polygon corner's outgoing edge, in corner order.
    let mut corner_edges = Vec::with_capacity(corners);
    for poly in polygons {
        assert!(poly.len() >= 3, "polygon with {} vertices", poly.len());
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            assert!((a as usize) < nv && (b as usize) < nv, "index out of range");
            let key = (a.min(b), a.max(b));
            let e = *edges.entry(key).or_insert_with(|| {
                let (p, q) = (positions[a as usize], positions[b as usize]);
                out.push(std::array::from_fn(|c| 0.5 * (p[c] + q[c])));
                (out.len() - 1) as u32
            });
            corner_edges.push(e);
        }
    }
    let mut faces = Vec::with_capacity(corners);
    let mut base = 0;
    for poly in polygons {
        let k = poly.len();
        let mut centroid = [0.0; 3];
        for &v in poly {
            for c in 0..3 {
                centroid[c] += positions[v as usize][c];
            }
        }
        out.push(centroid.map(|x| x / k as f64));
        let f = (out.len() - 1) as u32;
        for i in 0..k {
            let next = corner_edges[base + i];
            let prev = corner_edges[base + (i + k - 1) % k];
            faces.push([poly[i], next, f, prev]);
        }
        base += k;
    }
    QuadMesh {
        positions: out,
        faces,
    }
}

/// The n-gonal prism before splitting: bottom vertices 0..n at z = -1, top n..2n at z = 1, on
/// the unit circle; polygons bottom, top, then side i = (i, i+1, n+i+1, n+i).
fn prism_polygons(n: usize) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let mut positions = Vec::with_capacity(2 * n);
    for z in [-1.0, 1.0] {
        for i in 0..n {
            let a = TAU * i as f64 / n as f64;
            positions.push([a.cos(), a.sin(), z]);
        }
    }
    let n32 = n as u32;
    let mut polygons = vec![(0..n32).rev().collect(), (n32..2 * n32).collect()];
    for i in 0..n32 {
        let j = (i + 1) % n32;
        polygons.push(vec![i, j, n32 + j, n32 + i]);
    }
    (positions, polygons)
}

/// The n-gonal prism as a polygon mesh: two n-gon caps and n side quads (triangles for n = 3,
/// pentagons for n = 5), for the first step on meshes that are not all quads
/// ([`crate::polygon`]). n ≥ 3.
pub fn polygon_prism(n: usize) -> PolyMesh {
    let (positions, polygons) = prism_polygons(n);
    let mut m = PolyMesh::new();
    m.positions = positions;
    for p in &polygons {
        m.push_face(p);
    }
    m
}

/// The n-gonal prism (two n-gons + n side quads), split once with [`quad_split`]: EVs of valence
/// n (2, at the cap centres) and 3 (2n, the prism corners), all separated by ordinary vertices.
/// 6n + 2 vertices, 6n faces. n >= 3 (for n = 4 this is the split cube, for n = 3 the cap
/// centres also have valence 3).
pub fn prism(n: usize) -> QuadMesh {
    assert!(n >= 3, "prism needs n >= 3");
    let (positions, polygons) = prism_polygons(n);
    quad_split(&positions, &polygons)
}

/// A closed quad mesh with EVs of valences 3, 5 and 9, pairwise non-adjacent.
///
/// Construction: the 9-gonal prism (bottom vertices 0..9 at z = -1, top 9..18 at z = 1) with
/// vertices 18 and 19 added at the middles of the vertical edges (0, 9) and (1, 10), joined by
/// an edge. The side quad between them becomes two quads and its two neighbouring side quads
/// become pentagons. The polyhedron has 20 vertices (all valence 3), 30 edges and 12 faces
/// (2 nonagons, 2 pentagons, 8 quads); [`quad_split`] of it has 62 vertices and 60 quads with
/// valence histogram {3: 20, 4: 38, 5: 2, 9: 2}: the old vertices (valence 3), the face points
/// of the pentagons (5) and nonagons (9), all separated by ordinary edge and quad-face points.
pub fn star() -> QuadMesh {
    let (mut positions, mut polygons) = prism_polygons(9);
    let mid = |a: usize, b: usize, p: &[[f64; 3]]| -> [f64; 3] {
        std::array::from_fn(|c| 0.5 * (p[a][c] + p[b][c]))
    };
    let p0 = mid(0, 9, &positions);
    let p1 = mid(1, 10, &positions);
    positions.push(p0); // 18
    positions.push(p1); // 19

    // Side i is polygons[2 + i]: side 0 = (0, 1, 10, 9), side 1 = (1, 2, 11, 10),
    // side 8 = (8, 0, 9, 17).
    polygons[2] = vec![0, 1, 19, 18];
    polygons.push(vec![18, 19, 10, 9]);
    polygons[3] = vec![1, 2, 11, 10, 19];
    polygons[10] = vec![8, 0, 18, 9, 17];
    quad_split(&positions, &polygons)
}

/// A non-orientable closed quad mesh: a Klein bottle grid of `rows` × `cols` quads (all
/// vertices valence 4), rows, cols >= 3. Vertex `i * cols + j` is the figure-eight immersion at
/// u = 2πi/rows, v = 2πj/cols (it self-intersects); row `rows` is glued to row 0 with the tube
/// reflected (column j to column -j).
pub fn klein_bottle(rows: usize, cols: usize) -> QuadMesh {
    assert!(rows >= 3 && cols >= 3, "klein_bottle needs rows, cols >= 3");
    let big = 3.0;
    let mut positions = Vec::with_capacity(rows * cols);
    for i in 0..rows {
        let u = TAU * i as f64 / rows as f64;
        let (s, c) = (0.5 * u).sin_cos();
        for j in 0..cols {
            let v = TAU * j as f64 / cols as f64;
            let r = big + c * v.sin() - s * (2.0 * v).sin();
            positions.push([r * u.cos(), r * u.sin(), s * v.sin() + c * (2.0 * v).sin()]);
        }
    }
    let id = |i: usize, j: usize| {
        let j = j % cols;
        if i == rows {
            ((cols - j) % cols) as u32
        } else {
            (i * cols + j) as u32
        }
    };
    let mut faces = Vec::with_capacity(rows * cols);
    for i in 0..rows {
        for j in 0..cols {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    QuadMesh { positions, faces }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume by the divergence theorem (each quad as two triangles); positive when the
    /// faces are oriented outward.
    fn volume(m: &QuadMesh) -> f64 {
        let p = |v: u32| m.positions[v as usize];
        let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        };
        m.faces
            .iter()
            .map(|f| tri(p(f[0]), p(f[1]), p(f[2])) + tri(p(f[0]), p(f[2]), p(f[3])))
            .sum()
    }

    /// Every directed edge appears once (consistent orientation of a closed mesh).
    fn consistently_oriented(m: &QuadMesh) -> bool {
        let mut seen = std::collections::HashSet::new();
        m.faces
            .iter()
            .all(|f| (0..4).all(|i| seen.insert((f[i], f[(i + 1) % 4]))))
            && seen.iter().all(|&(a, b)| seen.contains(&(b, a)))
    }

    #[test]
    fn volumes_are_positive_and_plausible() {
        let v = volume(&cube());
        assert!((v - 8.0).abs() < 1e-12, "{v}");
        let v = volume(&torus(48, 32));
        let exact = 2.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.35f64.powi(2);
        assert!((v - exact).abs() < 0.03 * exact, "{v} vs {exact}");
        for n in [3, 5, 9] {
            let v = volume(&prism(n));
            let exact = 2.0 * 0.5 * n as f64 * (TAU / n as f64).sin();
            assert!((v - exact).abs() < 1e-12, "n = {n}: {v} vs {exact}");
        }
        // The star is the 9-gonal prism with extra points on its boundary.
        let v = volume(&star());
        let exact = 9.0 * (TAU / 9.0).sin();
        assert!((v - exact).abs() < 1e-12, "{v} vs {exact}");
    }

    #[test]
    fn orientable_generators_are_consistently_oriented() {
        assert!(consistently_oriented(&cube()));
        assert!(consistently_oriented(&torus(3, 7)));
        assert!(consistently_oriented(&prism(6)));
        assert!(consistently_oriented(&star()));
        assert!(!consistently_oriented(&klein_bottle(5, 5)));
    }

    #[test]
    fn counts() {
        let m = torus(4, 7);
        assert_eq!((m.positions.len(), m.faces.len()), (28, 28));
        let m = prism(7);
        assert_eq!((m.positions.len(), m.faces.len()), (44, 42));
        let m = star();
        assert_eq!((m.positions.len(), m.faces.len()), (62, 60));
        let m = klein_bottle(3, 4);
        assert_eq!((m.positions.len(), m.faces.len()), (12, 12));
        for m in [torus(5, 5), cube(), prism(5), star(), klein_bottle(4, 6)] {
            assert!(m.positions.iter().flatten().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn quad_split_numbering_and_positions() {
        // A single square, split: 4 old vertices, 4 edge points, 1 face point.
        let pos = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
        ];
        let m = quad_split(&pos, &[vec![0, 1, 2, 3]]);
        assert_eq!(m.positions.len(), 9);
        assert_eq!(m.positions[4], [1.0, 0.0, 0.0]);
        assert_eq!(m.positions[7], [0.0, 1.0, 0.0]);
        assert_eq!(m.positions[8], [1.0, 1.0, 0.0]);
        assert_eq!(
            m.faces,
            vec![[0, 4, 8, 7], [1, 5, 8, 4], [2, 6, 8, 5], [3, 7, 8, 6]]
        );
    }
}
