//! Standard meshes for tests and examples: closed quad meshes, open ones (boundaries, OpenSubdiv's
//! boundary rules), polygon meshes (n-gons), and meshes with sharp features ([`Features`]: creases,
//! holes). Faces are oriented counter-clockwise seen from outside (for an open mesh: from the side
//! its documentation names) wherever the surface is orientable.

use crate::features::{Features, Sharpness};
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

/// The cube [-1,1]^3 with each face a `k` × `k` grid of quads: 8 vertices of valence 3 (the
/// corners), every other vertex of valence 4, so that faces away from the corners are
/// ordinary (for k >= 3, some faces touch no corner). 6k² + 2 vertices, 6k² faces. Panics
/// unless k >= 1.
pub fn grid_cube(k: usize) -> QuadMesh {
    assert!(k >= 1, "grid_cube needs k >= 1");
    let mut index: HashMap<[usize; 3], u32> = HashMap::new();
    let mut positions = Vec::with_capacity(6 * k * k + 2);
    let mut faces = Vec::with_capacity(6 * k * k);
    let mut at = |p: [usize; 3]| -> u32 {
        *index.entry(p).or_insert_with(|| {
            positions.push(p.map(|c| -1.0 + 2.0 * c as f64 / k as f64));
            (positions.len() - 1) as u32
        })
    };
    for axis in 0..3 {
        // (u, v, axis) right-handed: counter-clockwise in (u, v) is seen from +axis.
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, k] {
            for i in 0..k {
                for j in 0..k {
                    let mut quad =
                        [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)].map(|(a, b)| {
                            let mut p = [0; 3];
                            (p[axis], p[u], p[v]) = (side, a, b);
                            at(p)
                        });
                    if side == 0 {
                        quad.reverse();
                    }
                    faces.push(quad);
                }
            }
        }
    }
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

/// An open quad grid of `rows` × `cols` quads over [-1, 1]², gently bumped: vertex
/// `i * (cols + 1) + j` sits at x = 2j/cols − 1, y = 2i/rows − 1, z = 0.15 sin(2x + 0.7)
/// cos(1.3y) (no symmetry, so a wrong index shows), and face `r * cols + c` is (r, c),
/// (r, c + 1), (r + 1, c + 1), (r + 1, c), counter-clockwise seen from +z. (rows + 1)(cols + 1)
/// vertices; the four corners have one face, the other boundary vertices two, the interior
/// ones four. Panics unless rows, cols ≥ 1.
pub fn open_grid(rows: usize, cols: usize) -> QuadMesh {
    assert!(rows >= 1 && cols >= 1, "open_grid needs rows, cols >= 1");
    let mut positions = Vec::with_capacity((rows + 1) * (cols + 1));
    for i in 0..=rows {
        let y = 2.0 * i as f64 / rows as f64 - 1.0;
        for j in 0..=cols {
            let x = 2.0 * j as f64 / cols as f64 - 1.0;
            positions.push([x, y, 0.15 * (2.0 * x + 0.7).sin() * (1.3 * y).cos()]);
        }
    }
    let id = |i: usize, j: usize| (i * (cols + 1) + j) as u32;
    let mut faces = Vec::with_capacity(rows * cols);
    for r in 0..rows {
        for c in 0..cols {
            faces.push([id(r, c), id(r, c + 1), id(r + 1, c + 1), id(r + 1, c)]);
        }
    }
    QuadMesh { positions, faces }
}

/// An open cylinder (no caps) of radius 1 around z, from z = −1 to 1: `cols` quads around,
/// `rows` along. Vertex `i * cols + j` sits at angle 2πj/cols and height 2i/rows − 1; face
/// `i * cols + j` is (i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j), oriented outward.
/// (rows + 1) cols vertices, rows · cols faces; two boundary loops of `cols` edges without
/// corners (every boundary vertex has two faces), interior vertices valence 4. Panics unless
/// rows ≥ 1 and cols ≥ 3.
pub fn tube(rows: usize, cols: usize) -> QuadMesh {
    assert!(rows >= 1 && cols >= 3, "tube needs rows >= 1, cols >= 3");
    let mut positions = Vec::with_capacity((rows + 1) * cols);
    for i in 0..=rows {
        let z = 2.0 * i as f64 / rows as f64 - 1.0;
        for j in 0..cols {
            let a = TAU * j as f64 / cols as f64;
            positions.push([a.cos(), a.sin(), z]);
        }
    }
    let id = |i: usize, j: usize| (i * cols + j % cols) as u32;
    let mut faces = Vec::with_capacity(rows * cols);
    for i in 0..rows {
        for j in 0..cols {
            faces.push([id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    QuadMesh { positions, faces }
}

/// [`open_grid`]`(n, n)` whose centre face, (n/2) n + n/2, is a hole (its only feature). Every
/// vertex of the hole has four faces, so the hole is surrounded by a ring of faces. Panics
/// unless n is odd and ≥ 3.
pub fn grid_with_hole(n: usize) -> (QuadMesh, Features) {
    assert!(n >= 3 && n % 2 == 1, "grid_with_hole needs an odd n >= 3");
    let features = Features {
        holes: vec![((n / 2) * n + n / 2) as u32],
        ..Features::default()
    };
    (open_grid(n, n), features)
}

/// The icosahedron with each triangle split into four `level` times, its vertices on the unit
/// sphere: a triangle mesh like a scanned or modelled one, 20 · 4^level triangles. Its 12 first
/// vertices have valence 5, the others 6; split once into quads (the first step on a polygon
/// mesh, [`crate::polygon`]) every quad has two extraordinary corners, so every face is refined
/// around an EV. Outward orientation. Panics above level 10 (20,971,520 triangles).
pub fn icosphere(level: usize) -> PolyMesh {
    assert!(level <= 10, "icosphere level {level} above 10");
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let unit = |p: [f64; 3]| {
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|c| c / r)
    };
    let mut positions: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(unit)
    .to_vec();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut middle: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<[f64; 3]>| {
            *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (positions[a as usize], positions[b as usize]);
                positions.push(unit(std::array::from_fn(|c| p[c] + q[c])));
                (positions.len() - 1) as u32
            })
        };
        triangles = triangles
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = mid(a, b, &mut positions);
                let bc = mid(b, c, &mut positions);
                let ca = mid(c, a, &mut positions);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let mut m = PolyMesh::new();
    m.positions = positions;
    for t in &triangles {
        m.push_face(t);
    }
    m
}

/// The closed pentagonal pyramid, triangles and a pentagon: base vertices 0..5 on the unit
/// circle at z = 0 (vertex i at angle 2πi/5), apex 5 at (0, 0, 1.2); faces the base (4, 3, 2,
/// 1, 0) then triangle i = (i, i + 1, 5), oriented outward. 6 vertices, 10 edges, 6 faces; the
/// apex has valence 5, the base vertices 3.
pub fn pentagonal_pyramid() -> PolyMesh {
    let mut m = PolyMesh::new();
    m.positions = unit_pentagon();
    m.positions.push([0.0, 0.0, 1.2]);
    m.push_face(&[4, 3, 2, 1, 0]);
    for i in 0..5 {
        m.push_face(&[i, (i + 1) % 5, 5]);
    }
    m
}

/// The regular pentagon on the unit circle at z = 0, vertex i at angle 2πi/5.
fn unit_pentagon() -> Vec<[f64; 3]> {
    (0..5)
        .map(|i| {
            let a = TAU * i as f64 / 5.0;
            [a.cos(), a.sin(), 0.0]
        })
        .collect()
}

/// An open mesh of a pentagon and five triangles, one on each of its edges (a five-pointed
/// star): pentagon vertices 0..5 on the unit circle at z = 0 (vertex i at angle 2πi/5), tip
/// 5 + i at radius 1.6, angle 2π(i + ½)/5 and z = 0.3; faces the pentagon (0, 1, 2, 3, 4) then
/// triangle i = (i, 5 + i, i + 1), counter-clockwise seen from +z. 10 vertices, 15 edges (10 on
/// the boundary), 6 faces. The tips have one face (corners in OpenSubdiv's edge-and-corner
/// mode), the pentagon's vertices three faces and two boundary edges.
pub fn pentagon_star() -> PolyMesh {
    let mut m = PolyMesh::new();
    m.positions = unit_pentagon();
    for i in 0..5 {
        let a = TAU * (i as f64 + 0.5) / 5.0;
        m.positions.push([1.6 * a.cos(), 1.6 * a.sin(), 0.3]);
    }
    m.push_face(&[0, 1, 2, 3, 4]);
    for i in 0..5 {
        m.push_face(&[i, 5 + i, (i + 1) % 5]);
    }
    m
}

/// The edges of [`cube`] (lower index first), each once, in the order first met scanning its
/// faces.
fn cube_edges() -> Vec<[u32; 2]> {
    let mut edges = Vec::with_capacity(12);
    for f in cube().faces {
        for i in 0..4 {
            let (a, b) = (f[i], f[(i + 1) % 4]);
            let e = [a.min(b), a.max(b)];
            if !edges.contains(&e) {
                edges.push(e);
            }
        }
    }
    edges
}

/// [`cube`] with its 12 edges infinitely sharp: every vertex has three sharp edges, so it is a
/// corner (OpenSubdiv's `Crease::DetermineVertexVertexRule`), and every face refines as a flat
/// patch: the limit surface is the cube itself.
pub fn creased_cube() -> (QuadMesh, Features) {
    let features = Features {
        creases: cube_edges()
            .into_iter()
            .map(|e| (e, Sharpness::INFINITE))
            .collect(),
        ..Features::default()
    };
    (cube(), features)
}

/// [`cube`] with the four edges around its top face (z = 1: vertices 4, 5, 7, 6) creased with
/// the given sharpness (e.g. `Sharpness::steps(2)`, semi-sharp: sharp for two steps): a closed
/// crease loop through four crease vertices (two sharp edges each).
pub fn cube_with_creased_top(sharpness: Sharpness) -> (QuadMesh, Features) {
    let top = [4, 5, 6, 7];
    let features = Features {
        creases: cube_edges()
            .into_iter()
            .filter(|e| e.iter().all(|v| top.contains(v)))
            .map(|e| (e, sharpness))
            .collect(),
        ..Features::default()
    };
    (cube(), features)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume by the divergence theorem (each face as a fan of triangles from its first
    /// corner); positive when the faces are oriented outward.
    fn volume<'a>(p: &[[f64; 3]], faces: impl IntoIterator<Item = &'a [u32]>) -> f64 {
        let p = |v: u32| p[v as usize];
        let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        };
        faces
            .into_iter()
            .map(|f| {
                (1..f.len() - 1)
                    .map(|i| tri(p(f[0]), p(f[i]), p(f[i + 1])))
                    .sum::<f64>()
            })
            .sum()
    }

    fn quads(m: &QuadMesh) -> impl Iterator<Item = &[u32]> {
        m.faces.iter().map(|f| &f[..])
    }

    /// How many faces each edge (lower index first) has.
    fn edge_faces<'a>(faces: impl IntoIterator<Item = &'a [u32]>) -> HashMap<(u32, u32), usize> {
        let mut uses = HashMap::new();
        for f in faces {
            for i in 0..f.len() {
                let (a, b) = (f[i], f[(i + 1) % f.len()]);
                *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        uses
    }

    /// How many faces each vertex has.
    fn vertex_faces<'a>(nv: usize, faces: impl IntoIterator<Item = &'a [u32]>) -> Vec<usize> {
        let mut n = vec![0; nv];
        for f in faces {
            for &v in f {
                n[v as usize] += 1;
            }
        }
        n
    }

    /// No directed edge appears twice: neighbouring faces agree on their orientation.
    fn directed_once<'a>(faces: impl IntoIterator<Item = &'a [u32]>) -> bool {
        let mut seen = std::collections::HashSet::new();
        faces
            .into_iter()
            .all(|f| (0..f.len()).all(|i| seen.insert((f[i], f[(i + 1) % f.len()]))))
    }

    /// Every edge has one or two faces (the mesh is a 2-manifold with boundary, edge-wise);
    /// returns the number of boundary edges.
    fn boundary_edges<'a>(faces: impl IntoIterator<Item = &'a [u32]>) -> usize {
        let uses = edge_faces(faces);
        assert!(uses.values().all(|&k| k == 1 || k == 2), "{uses:?}");
        uses.values().filter(|&&k| k == 1).count()
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
        let c = cube();
        let v = volume(&c.positions, quads(&c));
        assert!((v - 8.0).abs() < 1e-12, "{v}");
        let t = torus(48, 32);
        let v = volume(&t.positions, quads(&t));
        let exact = 2.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.35f64.powi(2);
        assert!((v - exact).abs() < 0.03 * exact, "{v} vs {exact}");
        for n in [3, 5, 9] {
            let m = prism(n);
            let v = volume(&m.positions, quads(&m));
            let exact = 2.0 * 0.5 * n as f64 * (TAU / n as f64).sin();
            assert!((v - exact).abs() < 1e-12, "n = {n}: {v} vs {exact}");
        }
        // The star is the 9-gonal prism with extra points on its boundary.
        let m = star();
        let v = volume(&m.positions, quads(&m));
        let exact = 9.0 * (TAU / 9.0).sin();
        assert!((v - exact).abs() < 1e-12, "{v} vs {exact}");
        for k in [1, 4] {
            let m = grid_cube(k);
            let v = volume(&m.positions, quads(&m));
            assert!((v - 8.0).abs() < 1e-12, "k = {k}: {v}");
        }
    }

    #[test]
    fn grid_cube_has_eight_evs_and_ordinary_faces() {
        let k = 4;
        let m = grid_cube(k);
        assert_eq!(
            (m.positions.len(), m.faces.len()),
            (6 * k * k + 2, 6 * k * k)
        );
        assert_eq!(boundary_edges(quads(&m)), 0);
        let valence = vertex_faces(m.positions.len(), quads(&m));
        assert_eq!(valence.iter().filter(|&&n| n == 3).count(), 8);
        assert!(valence.iter().all(|&n| n == 3 || n == 4));
        // Faces with no corner of valence 3: all but the 3 at each of the 8 corners.
        let ordinary = m
            .faces
            .iter()
            .filter(|f| f.iter().all(|&v| valence[v as usize] == 4));
        assert_eq!(ordinary.count(), 6 * k * k - 24);
        assert_eq!(grid_cube(1).faces.len(), cube().faces.len());
    }

    #[test]
    fn icosphere_is_a_closed_outward_triangle_mesh() {
        for level in 0..=2 {
            let m = icosphere(level);
            let (v, f) = (
                10 * 4usize.pow(level as u32) + 2,
                20 * 4usize.pow(level as u32),
            );
            assert_eq!((m.positions.len(), m.face_count()), (v, f));
            // Every directed edge once, and its reverse once: closed and consistently oriented.
            let mut directed = HashMap::new();
            let mut valence = vec![0; v];
            for t in m.corners.chunks_exact(3) {
                for i in 0..3 {
                    *directed.entry((t[i], t[(i + 1) % 3])).or_insert(0) += 1;
                    valence[t[i] as usize] += 1;
                }
                // Outward: the normal points away from the centre.
                let p = |i: usize| m.positions[t[i] as usize];
                let (a, b) = (sub(p(1), p(0)), sub(p(2), p(0)));
                let n = [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ];
                assert!((0..3).map(|c| n[c] * p(0)[c]).sum::<f64>() > 0.0);
            }
            assert!(directed
                .iter()
                .all(|(&(a, b), &k)| k == 1 && directed.get(&(b, a)) == Some(&1)));
            assert_eq!(valence.iter().filter(|&&n| n == 5).count(), 12);
            assert!(valence.iter().all(|&n| n == 5 || n == 6));
            let r = |p: &[f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!(m.positions.iter().all(|p| (r(p) - 1.0).abs() < 1e-15));
        }
    }

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|c| a[c] - b[c])
    }

    #[test]
    fn orientable_generators_are_consistently_oriented() {
        assert!(consistently_oriented(&cube()));
        assert!(consistently_oriented(&torus(3, 7)));
        assert!(consistently_oriented(&prism(6)));
        assert!(consistently_oriented(&star()));
        assert!(consistently_oriented(&grid_cube(3)));
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

    #[test]
    fn open_grid_counts_boundary_and_valences() {
        for (rows, cols) in [(1, 1), (3, 5), (4, 2)] {
            let m = open_grid(rows, cols);
            assert_eq!(m.positions.len(), (rows + 1) * (cols + 1));
            assert_eq!(m.faces.len(), rows * cols);
            assert_eq!(boundary_edges(quads(&m)), 2 * (rows + cols));
            assert!(directed_once(quads(&m)));
            let n = vertex_faces(m.positions.len(), quads(&m));
            let count = |k| n.iter().filter(|&&x| x == k).count();
            let (interior, boundary) = ((rows - 1) * (cols - 1), 2 * (rows + cols) - 4);
            assert_eq!((count(1), count(2), count(4)), (4, boundary, interior));
            assert_eq!(count(1) + count(2) + count(4), m.positions.len());
            for corner in [0, cols, rows * (cols + 1), (rows + 1) * (cols + 1) - 1] {
                assert_eq!(n[corner], 1);
            }
            // Counter-clockwise seen from +z: the first quad's signed area in xy is positive.
            let p = |v: u32| m.positions[v as usize];
            let f = m.faces[0];
            let area: f64 = (0..4)
                .map(|i| {
                    let (a, b) = (p(f[i]), p(f[(i + 1) % 4]));
                    a[0] * b[1] - a[1] * b[0]
                })
                .sum();
            assert!(area > 0.0);
            assert!(m.positions.iter().flatten().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn tube_has_two_boundary_loops_without_corners() {
        for (rows, cols) in [(1, 3), (4, 6)] {
            let m = tube(rows, cols);
            assert_eq!(m.positions.len(), (rows + 1) * cols);
            assert_eq!(m.faces.len(), rows * cols);
            assert_eq!(boundary_edges(quads(&m)), 2 * cols);
            assert!(directed_once(quads(&m)));
            let n = vertex_faces(m.positions.len(), quads(&m));
            for (v, &k) in n.iter().enumerate() {
                let on_boundary = v < cols || v >= rows * cols;
                assert_eq!(k, if on_boundary { 2 } else { 4 }, "vertex {v}");
            }
            // Outward: the first quad's normal points away from the axis.
            let p = |v: u32| m.positions[v as usize];
            let f = m.faces[0];
            let (a, b, c) = (p(f[0]), p(f[1]), p(f[3]));
            let (u, w) = (
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
            );
            let normal = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2]];
            assert!(normal[0] * (a[0] + b[0]) + normal[1] * (a[1] + b[1]) > 0.0);
        }
    }

    #[test]
    fn grid_with_hole_marks_its_centre_face() {
        for n in [3, 5] {
            let (m, f) = grid_with_hole(n);
            assert_eq!(m, open_grid(n, n));
            assert_eq!(f.holes.len(), 1);
            assert!(f.creases.is_empty() && f.corners.is_empty());
            let hole = m.faces[f.holes[0] as usize];
            let faces = vertex_faces(m.positions.len(), quads(&m));
            assert!(hole.iter().all(|&v| faces[v as usize] == 4));
            // The centre: its centroid is the grid's, (0, 0) in xy.
            for c in 0..2 {
                let mean: f64 = hole.iter().map(|&v| m.positions[v as usize][c]).sum();
                assert!(mean.abs() < 1e-12);
            }
        }
    }

    #[test]
    fn pentagonal_pyramid_is_closed_and_outward() {
        let m = pentagonal_pyramid();
        assert_eq!((m.positions.len(), m.face_count()), (6, 6));
        let degrees: Vec<usize> = m.faces().map(<[u32]>::len).collect();
        assert_eq!(degrees, vec![5, 3, 3, 3, 3, 3]);
        let uses = edge_faces(m.faces());
        assert_eq!(uses.len(), 10);
        assert!(uses.values().all(|&k| k == 2));
        assert!(directed_once(m.faces()));
        let n = vertex_faces(6, m.faces());
        assert_eq!(n, vec![3, 3, 3, 3, 3, 5]);
        // Base area (5/2) sin(2π/5), height 1.2.
        let exact = 2.5 * (TAU / 5.0).sin() * 1.2 / 3.0;
        let v = volume(&m.positions, m.faces());
        assert!((v - exact).abs() < 1e-12, "{v} vs {exact}");
    }

    #[test]
    fn pentagon_star_is_open_with_corner_tips() {
        let m = pentagon_star();
        assert_eq!((m.positions.len(), m.face_count()), (10, 6));
        let degrees: Vec<usize> = m.faces().map(<[u32]>::len).collect();
        assert_eq!(degrees, vec![5, 3, 3, 3, 3, 3]);
        assert_eq!(edge_faces(m.faces()).len(), 15);
        assert_eq!(boundary_edges(m.faces()), 10);
        assert!(directed_once(m.faces()));
        let n = vertex_faces(10, m.faces());
        assert_eq!(n, vec![3, 3, 3, 3, 3, 1, 1, 1, 1, 1]);
    }

    #[test]
    fn creased_cubes() {
        let (m, f) = creased_cube();
        assert_eq!(m, cube());
        assert!(f.corners.is_empty() && f.holes.is_empty());
        assert_eq!(f.creases.len(), 12);
        let edges = edge_faces(quads(&m));
        let mut sharp_at = [0; 8];
        for &([a, b], s) in &f.creases {
            assert!(s.is_infinite());
            assert!(edges.contains_key(&(a.min(b), a.max(b))));
            sharp_at[a as usize] += 1;
            sharp_at[b as usize] += 1;
        }
        // Three sharp edges at every vertex: corners.
        assert_eq!(sharp_at, [3; 8]);

        let (m, f) = cube_with_creased_top(Sharpness::steps(2));
        assert_eq!(m, cube());
        assert_eq!(f.creases.len(), 4);
        let mut sharp_at = [0; 8];
        for &([a, b], s) in &f.creases {
            assert_eq!(s, Sharpness::steps(2));
            assert!(edges.contains_key(&(a.min(b), a.max(b))));
            // Both ends on the top face z = 1.
            assert!(m.positions[a as usize][2] == 1.0 && m.positions[b as usize][2] == 1.0);
            sharp_at[a as usize] += 1;
            sharp_at[b as usize] += 1;
        }
        // A loop: two sharp edges at each top vertex (crease vertices), none below.
        assert_eq!(sharp_at, [0, 0, 0, 0, 2, 2, 2, 2]);
    }
}
