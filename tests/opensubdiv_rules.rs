//! Uniform binary (the cubic B-spline, Catmull–Clark on regular regions) against the
//! testkit's independent Catmull–Clark with OpenSubdiv's boundary, corner, crease and hole
//! rules (`lsubdiv_testkit::catmull_clark`, each rule cited there from OpenSubdiv's Sdc and
//! docs), on meshes without interior extraordinary vertices: there lsubdiv's rules are
//! exactly Catmull–Clark's. At interior EVs the L-system rule (\[G\] §3, α by eigenanalysis)
//! is not Catmull–Clark's vertex rule; those regions are tested by the properties in
//! `tests/boundaries.rs` and `tests/surface.rs` instead.

use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::GenericSurface;
use lsubdiv::mesh::features::{Boundary, Features, Sharpness};
use lsubdiv::mesh::generators::{creased_cube, grid_with_hole, open_grid, torus, tube};
use lsubdiv::mesh::patch::subdivide_with;
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use lsubdiv_testkit::catmull_clark::catmull_clark_features_steps;

fn uniform_binary() -> GenericSurface {
    let r = lsubdiv_cli::resolve("uniform-binary").unwrap();
    GenericSurface::new(Scheme::build(r.ls).unwrap()).unwrap()
}

/// The positions a mesh's faces use (but the holes').
fn used_points(m: &QuadMesh, holes: &[u32]) -> Vec<[f64; 3]> {
    let mut used = vec![false; m.positions.len()];
    for (f, q) in m.faces.iter().enumerate() {
        if !holes.contains(&(f as u32)) {
            for &v in q {
                used[v as usize] = true;
            }
        }
    }
    m.positions
        .iter()
        .zip(&used)
        .filter(|(_, &u)| u)
        .map(|(p, _)| *p)
        .collect()
}

/// The largest distance from a point of `a` to its match in `b`, each point of `b` matched
/// once (the two refiners number points differently): points are bucketed in cells of 1e-6.
fn matched_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    use std::collections::HashMap;
    let cell = |p: &[f64; 3]| p.map(|x| (x * 1e6).floor() as i64);
    let mut buckets: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, q) in b.iter().enumerate() {
        buckets.entry(cell(q)).or_default().push(i);
    }
    let mut taken = vec![false; b.len()];
    let mut worst = 0.0f64;
    for p in a {
        let c = cell(p);
        let mut best: Option<(f64, usize)> = None;
        for d in 0..27 {
            let k = [c[0] + d % 3 - 1, c[1] + d / 3 % 3 - 1, c[2] + d / 9 - 1];
            for &i in buckets.get(&k).into_iter().flatten() {
                let dist = (0..3).map(|j| (p[j] - b[i][j]).abs()).fold(0.0, f64::max);
                if !taken[i] && best.is_none_or(|(bd, _)| dist < bd) {
                    best = Some((dist, i));
                }
            }
        }
        let Some((dist, i)) = best else {
            return f64::INFINITY;
        };
        taken[i] = true;
        worst = worst.max(dist);
    }
    worst
}

/// lsubdiv and the reference agree to 1e-12 after 1..=`steps` steps.
fn agrees(what: &str, mesh: &QuadMesh, features: &Features, steps: usize) {
    let s = uniform_binary();
    let topo = Topology::build(mesh).unwrap();
    let polygons: Vec<Vec<u32>> = mesh.faces.iter().map(|f| f.to_vec()).collect();
    for k in 1..=steps {
        let ours: QuadMesh = subdivide_with(&s, mesh, &topo, features, k, 2)
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let (theirs, tf) = catmull_clark_features_steps(&mesh.positions, &polygons, features, k);
        assert_eq!(
            ours.faces.len(),
            theirs.faces.len() - tf.holes.len(),
            "{what} steps={k}: faces"
        );
        let (a, b) = (used_points(&ours, &[]), used_points(&theirs, &tf.holes));
        assert_eq!(a.len(), b.len(), "{what} steps={k}: vertices");
        let worst = matched_distance(&a, &b);
        assert!(worst < 1e-12, "{what} steps={k}: off by {worst:e}");
    }
}

#[test]
fn open_grids_and_tubes_in_both_boundary_modes() {
    for mode in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
        let f = Features::with_boundary(mode);
        agrees(&format!("open grid {mode:?}"), &open_grid(3, 4), &f, 3);
        agrees(&format!("tube {mode:?}"), &tube(3, 6), &f, 3);
    }
}

#[test]
fn a_grid_with_a_hole() {
    let (mesh, features) = grid_with_hole(3);
    agrees("grid with a hole", &mesh, &features, 3);
}

/// A torus with a sharp crease loop (around the tube at row 0) and a semi-sharp one of
/// sharpness 2 (around the axis at column 2): every vertex has valence 4, the crease
/// vertices two sharp edges opposite each other, the crossings four.
#[test]
fn sharp_and_semi_sharp_crease_loops() {
    let (rows, cols) = (6, 8);
    let mesh = torus(rows, cols);
    let id = |i: usize, j: usize| ((i % rows) * cols + j % cols) as u32;
    let mut features = Features::default();
    for j in 0..cols {
        features
            .creases
            .push(([id(0, j), id(0, j + 1)], Sharpness::INFINITE));
    }
    for i in 0..rows {
        features
            .creases
            .push(([id(i, 2), id(i + 1, 2)], Sharpness::steps(2)));
    }
    agrees("torus with crease loops", &mesh, &features, 4);
}

#[test]
fn a_cube_with_every_edge_sharp() {
    let (mesh, features) = creased_cube();
    agrees("creased cube", &mesh, &features, 3);
}

/// The first step of a mesh with triangles and pentagons is one Catmull–Clark step with
/// OpenSubdiv's boundary rules (`runtime::polygon`), in both boundary modes; later steps
/// are the scheme's.
#[test]
fn the_first_step_of_triangles_and_pentagons() {
    use lsubdiv::mesh::generators::{pentagon_star, pentagonal_pyramid};
    use lsubdiv::mesh::polygon::catmull_clark;
    for mode in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
        let features = Features::with_boundary(mode);
        for (what, poly) in [("star", pentagon_star()), ("pyramid", pentagonal_pyramid())] {
            let split = catmull_clark(&poly, &features).unwrap();
            let polygons: Vec<Vec<u32>> = poly.faces().map(<[u32]>::to_vec).collect();
            let (theirs, _) =
                catmull_clark_features_steps(&poly.positions, &polygons, &features, 1);
            let worst = matched_distance(&split.mesh.positions, &theirs.positions);
            assert_eq!(
                split.mesh.faces.len(),
                theirs.faces.len(),
                "{what} {mode:?}"
            );
            assert!(worst < 1e-12, "{what} {mode:?}: off by {worst:e}");
            // The scheme takes the later steps on the split, its features carried.
            let topo = Topology::build(&split.mesh).unwrap();
            let s = uniform_binary();
            let fine: QuadMesh =
                subdivide_with(&s, &split.mesh, &topo, &split.features, 2, 1).unwrap();
            assert_eq!(
                fine.faces.len(),
                16 * split.mesh.faces.len(),
                "{what} {mode:?}"
            );
        }
    }
}
