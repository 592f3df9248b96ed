//! Hand-derived expectations for the reference: each rule is written out here from the grid's
//! known structure (neighbours by row and column), not from the reference's edge tables.

use super::*;

type P = [f64; 3];

fn mid(a: P, b: P) -> P {
    scale(add(a, b), 0.5)
}

fn centroid(ps: &[P]) -> P {
    let mut s = [0.0; 3];
    for &q in ps {
        s = add(s, q);
    }
    scale(s, 1.0 / ps.len() as f64)
}

fn crease(a: P, s: P, b: P) -> P {
    scale(add(add(a, b), scale(s, 6.0)), 0.125)
}

fn close(a: P, b: P) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() < 1e-13)
}

#[track_caller]
fn assert_close(got: P, want: P, what: &str) {
    assert!(close(got, want), "{what}: {got:?} vs {want:?}");
}

/// An open grid of `n` × `n` quads with irregular positions: vertex (i, j) = i(n + 1) + j,
/// face (r, c) = rn + c with corners (r, c), (r, c + 1), (r + 1, c + 1), (r + 1, c).
struct Grid {
    n: usize,
    p: Vec<P>,
    faces: Vec<Vec<u32>>,
}

impl Grid {
    fn new(n: usize) -> Grid {
        let mut p = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (j as f64, i as f64);
                p.push([
                    x + 0.1 * (1.3 * x + 2.1 * y).sin(),
                    y + 0.07 * (0.7 * x * y).cos(),
                    0.3 * (x + 2.0 * y).sin() + 0.05 * x * x,
                ]);
            }
        }
        let mut g = Grid {
            n,
            p,
            faces: Vec::new(),
        };
        for r in 0..n {
            for c in 0..n {
                g.faces.push(vec![
                    g.v(r, c),
                    g.v(r, c + 1),
                    g.v(r + 1, c + 1),
                    g.v(r + 1, c),
                ]);
            }
        }
        g
    }

    fn v(&self, i: usize, j: usize) -> u32 {
        (i * (self.n + 1) + j) as u32
    }

    fn at(&self, i: usize, j: usize) -> P {
        self.p[self.v(i, j) as usize]
    }

    /// Centroid of face (r, c).
    fn fp(&self, r: usize, c: usize) -> P {
        centroid(&[
            self.at(r, c),
            self.at(r, c + 1),
            self.at(r + 1, c + 1),
            self.at(r + 1, c),
        ])
    }

    /// The smooth valence-4 rule at interior vertex (i, j).
    fn smooth(&self, i: usize, j: usize) -> P {
        let q = centroid(&[
            self.fp(i - 1, j - 1),
            self.fp(i - 1, j),
            self.fp(i, j - 1),
            self.fp(i, j),
        ]);
        let s = self.at(i, j);
        let r = centroid(&[
            mid(s, self.at(i - 1, j)),
            mid(s, self.at(i + 1, j)),
            mid(s, self.at(i, j - 1)),
            mid(s, self.at(i, j + 1)),
        ]);
        scale(add(add(q, scale(r, 2.0)), s), 0.25)
    }

    /// The smooth rule at the horizontal interior edge (i, j)-(i, j + 1), 0 < i < n.
    fn smooth_row_edge(&self, i: usize, j: usize) -> P {
        centroid(&[
            self.at(i, j),
            self.at(i, j + 1),
            self.fp(i - 1, j),
            self.fp(i, j),
        ])
    }

    fn step(&self, f: &Features) -> (QuadMesh, Features) {
        catmull_clark_features(&self.p, &self.faces, f)
    }
}

/// The edge point of face `fi`'s edge from corner `i` to corner i + 1, read off the documented
/// child-quad layout (corner i's quad is (v_i, e(v_i v_{i+1}), f, e(v_{i−1} v_i))).
fn edge_point(m: &QuadMesh, polygons: &[Vec<u32>], fi: usize, i: usize) -> P {
    let first: usize = polygons[..fi].iter().map(Vec::len).sum();
    m.positions[m.faces[first + i][1] as usize]
}

fn bits(m: &QuadMesh) -> Vec<[u64; 3]> {
    m.positions.iter().map(|q| q.map(f64::to_bits)).collect()
}

#[test]
fn one_open_quad_numbering_and_both_boundary_modes() {
    let p = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.5],
        [2.5, 1.0, 0.0],
        [0.0, 2.0, 1.0],
    ];
    let faces = [vec![0, 1, 2, 3]];
    for mode in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
        let (m, f) = catmull_clark_features(&p, &faces, &Features::with_boundary(mode));
        assert_eq!(f, Features::with_boundary(mode));
        assert_eq!(m.positions.len(), 9);
        assert_eq!(
            m.faces,
            vec![[0, 4, 8, 7], [1, 5, 8, 4], [2, 6, 8, 5], [3, 7, 8, 6]]
        );
        // Boundary edges: midpoints, in first-met order 01, 12, 23, 30; the face point.
        for i in 0..4 {
            assert_close(m.positions[4 + i], mid(p[i], p[(i + 1) % 4]), "edge");
        }
        assert_close(m.positions[8], centroid(&p), "face");
        for i in 0..4 {
            let want = match mode {
                // One face: an interpolated corner.
                Boundary::EdgeAndCorner => p[i],
                // Two sharp (boundary) edges: a crease vertex.
                Boundary::EdgeOnly | Boundary::None => crease(p[(i + 3) % 4], p[i], p[(i + 1) % 4]),
            };
            assert_close(m.positions[i], want, "vertex");
        }
    }
}

#[test]
fn open_grid_vertex_and_edge_rules() {
    let g = Grid::new(3);
    for mode in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
        let (m, _) = g.step(&Features::with_boundary(mode));
        let vp = |i, j| m.positions[g.v(i, j) as usize];
        // The four corners (one face each).
        for (i, j, a, b) in [
            (0, 0, (0, 1), (1, 0)),
            (0, 3, (0, 2), (1, 3)),
            (3, 0, (2, 0), (3, 1)),
            (3, 3, (3, 2), (2, 3)),
        ] {
            let want = match mode {
                Boundary::EdgeAndCorner => g.at(i, j),
                Boundary::EdgeOnly | Boundary::None => {
                    crease(g.at(a.0, a.1), g.at(i, j), g.at(b.0, b.1))
                }
            };
            assert_close(vp(i, j), want, "corner");
        }
        // Boundary vertices with two faces: creases along the boundary, in either mode.
        for k in 1..3 {
            let row = |i| crease(g.at(i, k - 1), g.at(i, k), g.at(i, k + 1));
            let col = |j| crease(g.at(k - 1, j), g.at(k, j), g.at(k + 1, j));
            assert_close(vp(0, k), row(0), "bottom");
            assert_close(vp(3, k), row(3), "top");
            assert_close(vp(k, 0), col(0), "left");
            assert_close(vp(k, 3), col(3), "right");
        }
        // Interior vertices: smooth, valence 4.
        for (i, j) in [(1, 1), (1, 2), (2, 1), (2, 2)] {
            assert_close(vp(i, j), g.smooth(i, j), "interior");
        }
        // Edges: face (r, c)'s local edge 0 is (r, c)-(r, c + 1).
        for r in 0..3 {
            for c in 0..3 {
                let e = edge_point(&m, &g.faces, 3 * r + c, 0);
                let want = if r == 0 {
                    mid(g.at(0, c), g.at(0, c + 1))
                } else {
                    g.smooth_row_edge(r, c)
                };
                assert_close(e, want, "edge");
            }
        }
        // Face points.
        for r in 0..3 {
            for c in 0..3 {
                let first = 4 * (3 * r + c);
                assert_close(m.positions[m.faces[first][2] as usize], g.fp(r, c), "face");
            }
        }
    }
}

#[test]
fn the_boundary_curve_depends_on_the_boundary_alone() {
    // Edge-only: the boundary is refined as the cubic B-spline of the boundary polygon, so
    // moving interior vertices changes no boundary child.
    let g = Grid::new(4);
    let mut h = Grid::new(4);
    for i in 1..4 {
        for j in 1..4 {
            let v = h.v(i, j) as usize;
            h.p[v] = add(h.p[v], [0.3, -0.2, 0.7]);
        }
    }
    for mode in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
        let f = Features::with_boundary(mode);
        let (a, _) = g.step(&f);
        let (b, _) = h.step(&f);
        for j in 0..=4 {
            assert_eq!(
                a.positions[g.v(0, j) as usize],
                b.positions[g.v(0, j) as usize]
            );
        }
        for c in 0..4 {
            assert_eq!(
                edge_point(&a, &g.faces, c, 0),
                edge_point(&b, &h.faces, c, 0)
            );
        }
        // The interior moved.
        assert_ne!(
            a.positions[g.v(1, 1) as usize],
            b.positions[g.v(1, 1) as usize]
        );
    }
}

fn row_crease(g: &Grid, i: usize, s: Sharpness) -> Features {
    Features {
        creases: (0..g.n).map(|j| ([g.v(i, j), g.v(i, j + 1)], s)).collect(),
        ..Features::default()
    }
}

#[test]
fn a_crease_line_across_a_grid() {
    let g = Grid::new(4);
    let f = row_crease(&g, 2, Sharpness::INFINITE);
    let (m, children) = g.step(&f);
    let vp = |i, j| m.positions[g.v(i, j) as usize];
    // On the line: crease vertices; where it meets the boundary, two boundary edges and the
    // crease make three sharp edges: corners.
    for j in 1..4 {
        assert_close(
            vp(2, j),
            crease(g.at(2, j - 1), g.at(2, j), g.at(2, j + 1)),
            "line",
        );
    }
    assert_close(vp(2, 0), g.at(2, 0), "end");
    assert_close(vp(2, 4), g.at(2, 4), "end");
    // Off the line: the smooth rule still.
    for (i, j) in [(1, 1), (1, 3), (3, 2)] {
        assert_close(vp(i, j), g.smooth(i, j), "off the line");
    }
    // Edges on the line: midpoints; the row above is smooth.
    for c in 0..4 {
        let on = edge_point(&m, &g.faces, 4 * 2 + c, 0);
        assert_close(on, mid(g.at(2, c), g.at(2, c + 1)), "crease edge");
        let above = edge_point(&m, &g.faces, 4 * 3 + c, 0);
        assert_close(above, g.smooth_row_edge(3, c), "smooth edge");
    }
    // Each crease edge gives two child edges through its edge point, still infinite.
    assert_eq!(children.creases.len(), 8);
    for (k, &([a, b], s)) in children.creases.iter().enumerate() {
        assert_eq!(s, Sharpness::INFINITE);
        let ([pa, pb], _) = f.creases[k / 2];
        let e = m.faces[4 * (4 * 2 + k / 2)][1];
        assert_eq!([a, b], if k % 2 == 0 { [pa, e] } else { [e, pb] });
    }
}

#[test]
fn semi_sharp_is_infinitely_sharp_for_s_steps_then_smooth() {
    let g = Grid::new(3);
    for s in 1..=3u32 {
        let (semi, left) = catmull_clark_features_steps(
            &g.p,
            &g.faces,
            &row_crease(&g, 1, Sharpness::steps(s)),
            s as usize + 1,
        );
        assert!(left.creases.is_empty());
        let (sharp, _) = catmull_clark_features_steps(
            &g.p,
            &g.faces,
            &row_crease(&g, 1, Sharpness::INFINITE),
            s as usize,
        );
        let quads: Vec<Vec<u32>> = sharp.faces.iter().map(|q| q.to_vec()).collect();
        let (then_smooth, _) =
            catmull_clark_features(&sharp.positions, &quads, &Features::default());
        assert_eq!(bits(&semi), bits(&then_smooth), "s = {s}");
        // And it is neither the smooth nor the infinitely sharp surface.
        let (smooth, _) =
            catmull_clark_features_steps(&g.p, &g.faces, &Features::default(), s as usize + 1);
        let (inf, _) = catmull_clark_features_steps(
            &g.p,
            &g.faces,
            &row_crease(&g, 1, Sharpness::INFINITE),
            s as usize + 1,
        );
        assert_ne!(bits(&semi), bits(&smooth));
        assert_ne!(bits(&semi), bits(&inf));
    }
    // Children's sharpness is decremented.
    let (_, c) = g.step(&row_crease(&g, 1, Sharpness::steps(3)));
    assert!(c.creases.iter().all(|&(_, s)| s == Sharpness::steps(2)));
    assert_eq!(c.creases.len(), 6);
}

#[test]
fn darts_take_the_smooth_rule() {
    let g = Grid::new(4);
    let smooth = g.step(&Features::default()).0;
    // Edge (2,2)-(2,3): both ends interior with one sharp edge (darts).
    let f = Features {
        creases: vec![([g.v(2, 2), g.v(2, 3)], Sharpness::INFINITE)],
        ..Features::default()
    };
    let (m, _) = g.step(&f);
    assert_eq!(&m.positions[..25], &smooth.positions[..25]);
    let e = edge_point(&m, &g.faces, 4 * 2 + 2, 0);
    assert_close(e, mid(g.at(2, 2), g.at(2, 3)), "dart edge");
    assert_close(m.positions[g.v(2, 2) as usize], g.smooth(2, 2), "dart");
    // Edge (2,3)-(2,4): a dart inside, a corner on the boundary (three sharp edges).
    let f = Features {
        creases: vec![([g.v(2, 3), g.v(2, 4)], Sharpness::INFINITE)],
        ..Features::default()
    };
    let (m, _) = g.step(&f);
    assert_close(m.positions[g.v(2, 3) as usize], g.smooth(2, 3), "dart");
    assert_close(m.positions[g.v(2, 4) as usize], g.at(2, 4), "corner");
    let smooth_boundary = crease(g.at(1, 4), g.at(2, 4), g.at(3, 4));
    assert_close(
        smooth.positions[g.v(2, 4) as usize],
        smooth_boundary,
        "crease",
    );
}

#[test]
fn corner_tags() {
    let g = Grid::new(3);
    let v = g.v(1, 1);
    // Sharpness 1: a corner for one step, then smooth.
    let f = Features {
        corners: vec![(v, Sharpness::steps(1))],
        ..Features::default()
    };
    let (m, c) = g.step(&f);
    assert_eq!(m.positions[v as usize], g.at(1, 1));
    assert!(c.corners.is_empty());
    // Infinite: interpolated at every step (vertex points keep their indices).
    let f = Features {
        corners: vec![(v, Sharpness::INFINITE)],
        ..Features::default()
    };
    let (m, c) = catmull_clark_features_steps(&g.p, &g.faces, &f, 3);
    assert_eq!(m.positions[v as usize], g.at(1, 1));
    assert_eq!(c.corners, f.corners);
    // Sharpness 2 is decremented.
    let f = Features {
        corners: vec![(v, Sharpness::steps(2))],
        ..Features::default()
    };
    assert_eq!(g.step(&f).1.corners, vec![(v, Sharpness::steps(1))]);
}

#[test]
fn holes_are_refined_and_their_children_are_holes() {
    let g = Grid::new(3);
    let centre = 4;
    let f = Features {
        holes: vec![centre],
        ..Features::default()
    };
    let (m, c) = catmull_clark_features_steps(&g.p, &g.faces, &f, 2);
    let (plain, _) = catmull_clark_features_steps(&g.p, &g.faces, &Features::default(), 2);
    assert_eq!(bits(&m), bits(&plain));
    assert_eq!(m.faces, plain.faces);
    // Face 4's quads are 16..20 after one step, and theirs 64..80 after two.
    assert_eq!(c.holes, (64..80).collect::<Vec<u32>>());
    // Mixed degrees: a triangle and a pentagon before the hole.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [2.0, 0.5, 0.0],
        [2.0, 1.5, 0.0],
        [1.0, 2.0, 0.0],
        [0.0, 2.0, 0.3],
    ];
    let faces = [vec![0, 1, 2], vec![1, 3, 4, 5, 2], vec![2, 5, 6]];
    let f = Features {
        holes: vec![2],
        ..Features::default()
    };
    assert_eq!(
        catmull_clark_features(&p, &faces, &f).1.holes,
        vec![8, 9, 10]
    );
}

#[test]
fn a_cube_with_every_edge_sharp_stays_on_the_cube() {
    let p: Vec<P> = (0..8)
        .map(|i| {
            let c = |bit: usize| if i >> bit & 1 == 1 { 1.0 } else { -1.0 };
            [c(0), c(1), c(2)]
        })
        .collect();
    let faces = vec![
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 2, 3, 1],
        vec![4, 5, 7, 6],
    ];
    let mut creases = Vec::new();
    for f in &faces {
        for i in 0..4 {
            let (a, b) = (f[i], f[(i + 1) % 4]);
            if a < b {
                creases.push(([a, b], Sharpness::INFINITE));
            }
        }
    }
    assert_eq!(creases.len(), 12);
    let f = Features {
        creases,
        ..Features::default()
    };
    // One step: corners stay, edges split at midpoints, faces at centroids.
    let (m, _) = catmull_clark_features(&p, &faces, &f);
    assert_eq!(&m.positions[..8], &p[..]);
    assert!(m.positions[8..20]
        .iter()
        .all(|q| q.iter().filter(|x| x.abs() == 1.0).count() == 2));
    assert!(m.positions[20..]
        .iter()
        .all(|q| q.iter().filter(|x| x.abs() == 1.0).count() == 1));
    // Three steps: every point on the cube's surface, every cube edge still a line.
    let (m, c) = catmull_clark_features_steps(&p, &faces, &f, 3);
    assert_eq!(c.creases.len(), 12 * 8);
    for q in &m.positions {
        let on = q.iter().filter(|x| (x.abs() - 1.0).abs() < 1e-15).count();
        assert!(on >= 1 && q.iter().all(|x| x.abs() <= 1.0 + 1e-15), "{q:?}");
    }
    for &([a, b], _) in &c.creases {
        let (qa, qb) = (m.positions[a as usize], m.positions[b as usize]);
        let shared = (0..3).filter(|&k| qa[k] == qb[k] && qa[k].abs() == 1.0);
        assert_eq!(shared.count(), 2, "{qa:?} {qb:?}");
    }
}

#[test]
fn closed_meshes_ignore_the_boundary_mode() {
    let g = Grid::new(3);
    // A torus-like closing of the grid's quads would need new positions; the boundary rule is
    // irrelevant on any closed mesh, e.g. the octahedron of triangles.
    let p = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.1, 0.0],
        [0.0, 1.0, 0.2],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.1, 0.0, -1.0],
    ];
    let faces = vec![
        vec![0, 2, 4],
        vec![2, 1, 4],
        vec![1, 3, 4],
        vec![3, 0, 4],
        vec![2, 0, 5],
        vec![1, 2, 5],
        vec![3, 1, 5],
        vec![0, 3, 5],
    ];
    let a = catmull_clark_features(&p, &faces, &Features::with_boundary(Boundary::EdgeOnly)).0;
    let b = catmull_clark_features(&p, &faces, &Features::default()).0;
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(bits(&a), bits(&catmull_clark_polygons(&p, &faces)));
    // …while on an open one it matters.
    let a = g.step(&Features::with_boundary(Boundary::EdgeOnly)).0;
    let b = g.step(&Features::default()).0;
    assert_ne!(bits(&a), bits(&b));
}

#[test]
#[should_panic(expected = "on one or two faces")]
fn an_edge_with_three_faces_panics() {
    let p = [[0.0; 3]; 5];
    let faces = [vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]];
    catmull_clark_features(&p, &faces, &Features::default());
}

#[test]
#[should_panic(expected = "is not an edge")]
fn a_crease_that_is_not_an_edge_panics() {
    let g = Grid::new(2);
    let f = Features {
        creases: vec![([0, 4], Sharpness::INFINITE)],
        ..Features::default()
    };
    g.step(&f);
}

#[test]
#[should_panic(expected = "shared by two faces")]
fn the_closed_reference_refuses_a_boundary() {
    let g = Grid::new(2);
    catmull_clark_polygons(&g.p, &g.faces);
}

#[test]
fn the_built_in_open_meshes_through_the_reference() {
    use lsubdiv::mesh::generators::{pentagon_star, tube};
    // A tube has no corners: both boundary modes agree, and the boundary loops stay in their
    // planes z = ±1 (crease rule and midpoints of points with the same z).
    let t = tube(2, 8);
    let quads: Vec<Vec<u32>> = t.faces.iter().map(|q| q.to_vec()).collect();
    let (a, _) = catmull_clark_features_steps(&t.positions, &quads, &Features::default(), 2);
    let only = Features::with_boundary(Boundary::EdgeOnly);
    let (b, _) = catmull_clark_features_steps(&t.positions, &quads, &only, 2);
    assert_eq!(bits(&a), bits(&b));
    let rims = a.positions.iter().filter(|q| q[2].abs() == 1.0).count();
    assert_eq!(rims, 2 * 8 * 4);
    // The star's tips have one face: fixed with edge-and-corner, creases with edge-only.
    let s = pentagon_star();
    let polygons: Vec<Vec<u32>> = s.faces().map(<[u32]>::to_vec).collect();
    let (a, _) = catmull_clark_features(&s.positions, &polygons, &Features::default());
    let (b, _) = catmull_clark_features(&s.positions, &polygons, &only);
    for i in 0..5 {
        let tip = 5 + i;
        assert_eq!(a.positions[tip], s.positions[tip]);
        let want = crease(s.positions[i], s.positions[tip], s.positions[(i + 1) % 5]);
        assert_close(b.positions[tip], want, "tip");
    }
    assert_eq!(a.faces.len(), 5 + 5 * 3);
}

#[test]
fn a_vertex_without_faces_stays() {
    let g = Grid::new(1);
    let mut p = g.p.clone();
    p.push([5.0, 6.0, 7.0]);
    let (m, _) = catmull_clark_features(&p, &g.faces, &Features::default());
    assert_eq!(m.positions[4], [5.0, 6.0, 7.0]);
}
