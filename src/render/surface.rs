//! What shading needs from a quad mesh (closed or open) beyond its positions: a consistent orientation of
//! the faces (outward where the mesh is orientable) and vertex normals, area-weighted from the
//! faces or given (the limit surface's) and turned with the faces.
//!
//! Nothing assumes the file's windings agree: they are made consistent by a walk over the faces,
//! and a non-orientable mesh (or a seam the walk cannot avoid) is reported, not hidden.

use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use rayon::prelude::*;

/// Faces oriented consistently and vertex normals.
pub struct Oriented {
    /// Face f's corner order is to be read reversed (its winding disagrees with its neighbours',
    /// or its component was wound inward).
    pub flip: Vec<bool>,
    /// Every component could be oriented consistently.
    pub orientable: bool,
    /// Unit vertex normals (zero where the incident faces have no area, or the given normal is
    /// zero). Outward on orientable components; at a non-orientable seam, on the side of the
    /// vertex's first face.
    pub normals: Vec<[f64; 3]>,
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a / |a|`, or zero for the zero vector.
pub(crate) fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [0.0; 3]
    }
}

/// Vector area of a quad in its own winding: half the cross product of its diagonals (exact for
/// planar quads, the area-weighted mean normal of the two triangulations otherwise).
pub fn quad_area_vector(mesh: &QuadMesh, face: usize) -> [f64; 3] {
    let p = mesh.faces[face].map(|v| mesh.positions[v as usize]);
    scale(cross(sub(p[2], p[0]), sub(p[3], p[1])), 0.5)
}

/// Six times the signed volume of the cone from the origin over a quad (both triangles).
fn cone_volume6(p: [[f64; 3]; 4]) -> f64 {
    dot(p[0], cross(p[1], p[2])) + dot(p[0], cross(p[2], p[3]))
}

/// Orients the faces of each connected component consistently (breadth-first over shared
/// edges): a closed component outward (positive enclosed volume), an open one as most of its
/// faces are wound in the file (an open surface encloses nothing); then averages the vertex
/// normals, or takes `given` ones (one a vertex, oriented with the winding of the vertex's
/// first face in `topo`'s rotation, as [`lsubdiv::mesh::patch::limit_with`]'s are on a
/// consistently wound mesh) negated where that face was flipped.
pub fn orient(mesh: &QuadMesh, topo: &Topology, given: Option<Vec<[f64; 3]>>) -> Oriented {
    let nf = mesh.faces.len();
    let mut flip = vec![false; nf];
    let mut seen = vec![false; nf];
    let mut orientable = true;
    let mut queue = std::collections::VecDeque::new();
    let mut component = Vec::new();
    for start in 0..nf {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        queue.push_back(start);
        component.clear();
        let mut open = false;
        while let Some(f) = queue.pop_front() {
            component.push(f);
            for l in 0..4u8 {
                let Some((g, m)) = topo.across(f as u32, l) else {
                    open = true;
                    continue;
                };
                let g = g as usize;
                // Consistent windings traverse a shared edge in opposite directions.
                let same_direction = mesh.faces[g][m as usize] == mesh.faces[f][l as usize];
                let want = flip[f] ^ same_direction;
                if !seen[g] {
                    seen[g] = true;
                    flip[g] = want;
                    queue.push_back(g);
                } else if flip[g] != want {
                    orientable = false;
                }
            }
        }
        let inward = if open {
            2 * component.iter().filter(|&&f| flip[f]).count() > component.len()
        } else {
            let volume: f64 = component
                .iter()
                .map(|&f| {
                    let v = cone_volume6(mesh.faces[f].map(|v| mesh.positions[v as usize]));
                    if flip[f] {
                        -v
                    } else {
                        v
                    }
                })
                .sum();
            volume < 0.0
        };
        if inward {
            for &f in &component {
                flip[f] = !flip[f];
            }
        }
    }
    let normals = vertex_normals(mesh, topo, &flip, given);
    Oriented {
        flip,
        orientable,
        normals,
    }
}

/// The vertex normals: `given` ones, each negated where its vertex's first face is flipped;
/// averaged from the faces where none are given, and where the faces around the vertex are not
/// wound alike in the mesh (the given normal, summed over faces wound both ways, means nothing
/// there; on a non-orientable mesh this happens along its seam).
///
/// The average is the sum of the oriented vector areas of the faces around the vertex,
/// normalised. Around a vertex the faces form a disc, so their windings can always be matched
/// locally: a face whose winding runs the other way round the vertex than the first face's
/// (`Wedge::next_is_plus` differs, after the flips) counts negated. On an orientable mesh this
/// never happens.
fn vertex_normals(
    mesh: &QuadMesh,
    topo: &Topology,
    flip: &[bool],
    given: Option<Vec<[f64; 3]>>,
) -> Vec<[f64; 3]> {
    let areas: Vec<[f64; 3]> = (0..mesh.faces.len())
        .into_par_iter()
        .map(|f| {
            let a = quad_area_vector(mesh, f);
            if flip[f] {
                scale(a, -1.0)
            } else {
                a
            }
        })
        .collect();
    let average = |v: u32| {
        let rot = topo.rotation(v);
        let turn = |w: &lsubdiv::mesh::topology::Wedge| w.next_is_plus ^ flip[w.face as usize];
        let first = rot.first().map(turn);
        let mut n = [0.0; 3];
        for w in rot {
            let a = areas[w.face as usize];
            let s = if Some(turn(w)) == first { 1.0 } else { -1.0 };
            n = [n[0] + s * a[0], n[1] + s * a[1], n[2] + s * a[2]];
        }
        normalize(n)
    };
    match given {
        None => (0..mesh.positions.len() as u32)
            .into_par_iter()
            .map(average)
            .collect(),
        Some(mut normals) => {
            normals.par_iter_mut().enumerate().for_each(|(v, n)| {
                let rot = topo.rotation(v as u32);
                match rot.first() {
                    Some(w) if rot.iter().any(|x| x.next_is_plus != w.next_is_plus) => {
                        *n = average(v as u32)
                    }
                    Some(w) if flip[w.face as usize] => *n = scale(*n, -1.0),
                    _ => {}
                }
            });
            normals
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsubdiv::mesh::generators::{cube, klein_bottle, torus};

    fn oriented(m: &QuadMesh) -> Oriented {
        orient(m, &Topology::build(m).unwrap(), None)
    }

    #[test]
    fn cube_normals_point_outward_whatever_the_winding() {
        let mut m = cube();
        // Reverse two faces and then the whole mesh: the orientation is recovered.
        for f in [1, 4] {
            m.faces[f].reverse();
        }
        for reverse_all in [false, true] {
            if reverse_all {
                m.faces.iter_mut().for_each(|f| f.reverse());
            }
            let o = oriented(&m);
            assert!(o.orientable);
            for (p, n) in m.positions.iter().zip(&o.normals) {
                let expected = normalize(*p);
                assert!(dot(*n, expected) > 1.0 - 1e-12, "{n:?} at {p:?}");
            }
        }
    }

    /// The limit normals of a cube refined twice by binary-ternary, given as they come from
    /// the library (oriented with the face winding): with the cube wound outward they are used
    /// as they are; wound inward, every face is flipped and every normal negated with it, so
    /// both come out outward.
    #[test]
    fn given_normals_turn_with_the_faces() {
        use lsubdiv::mesh::features::Features;
        use lsubdiv::mesh::patch::Subdivide;
        for inward in [false, true] {
            let mut m = cube();
            if inward {
                m.faces.iter_mut().for_each(|f| f.reverse());
            }
            let topology = Topology::build(&m).unwrap();
            let job = Subdivide {
                mesh: &m,
                topology: &topology,
                features: &Features::default(),
                steps: 2,
                threads: 1,
                limit: true,
            };
            let fine = lsubdiv::generated::visit_surface("binary-ternary", job)
                .unwrap()
                .unwrap();
            let o = orient(
                &fine.mesh,
                &Topology::build(&fine.mesh).unwrap(),
                Some(fine.normals.clone()),
            );
            assert!(o.flip.iter().all(|&f| f == inward));
            let sign = if inward { -1.0 } else { 1.0 };
            for ((n, given), p) in o
                .normals
                .iter()
                .zip(&fine.normals)
                .zip(&fine.mesh.positions)
            {
                assert_eq!(*n, scale(*given, sign));
                assert!(dot(*n, normalize(*p)) > 0.9, "{n:?} at {p:?}");
            }
        }
    }

    /// The largest |cos| between a vertex normal and an edge at the vertex.
    fn worst_tangency(m: &QuadMesh, normals: &[[f64; 3]]) -> f64 {
        let mut worst = 0.0f64;
        for f in &m.faces {
            for i in 0..4 {
                let (a, b) = (f[i] as usize, f[(i + 1) % 4] as usize);
                let e = normalize(sub(m.positions[b], m.positions[a]));
                for v in [a, b] {
                    let n = normals[v];
                    assert!((dot(n, n) - 1.0).abs() < 1e-9, "{n:?} at {v}");
                    worst = worst.max(dot(n, e).abs());
                }
            }
        }
        worst
    }

    /// Along a Klein bottle's seam the faces around a vertex are wound both ways, and the
    /// library's limit normal there sums normals of both signs: those vertices take the
    /// averaged normal, so every normal is still a normal.
    #[test]
    fn given_normals_give_way_where_the_windings_disagree() {
        use lsubdiv::mesh::features::Features;
        use lsubdiv::mesh::patch::Subdivide;
        let m = klein_bottle(48, 32);
        let topology = Topology::build(&m).unwrap();
        let job = Subdivide {
            mesh: &m,
            topology: &topology,
            features: &Features::default(),
            steps: 1,
            threads: 1,
            limit: true,
        };
        let fine = lsubdiv::generated::visit_surface("uniform-binary", job)
            .unwrap()
            .unwrap();
        let o = orient(
            &fine.mesh,
            &Topology::build(&fine.mesh).unwrap(),
            Some(fine.normals),
        );
        assert!(!o.orientable);
        let worst = worst_tangency(&fine.mesh, &o.normals);
        assert!(worst < 0.4, "{worst}");
    }

    #[test]
    fn klein_bottle_is_reported_and_its_normals_are_normal() {
        assert!(oriented(&torus(6, 5)).orientable);
        let m = klein_bottle(96, 64);
        let o = oriented(&m);
        assert!(!o.orientable);
        // Even along the seam every vertex normal is a normal: nearly perpendicular to the edges
        // at the vertex (a cancelled sum would leave a tangent residue).
        let worst = worst_tangency(&m, &o.normals);
        // 0.28 here (it halves when the grid doubles); a plain sum leaves 0.96 at the seam.
        assert!(worst < 0.4, "{worst}");
    }
}
