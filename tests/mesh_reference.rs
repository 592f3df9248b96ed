//! Sanity checks of the independent Catmull–Clark reference in `tests/common`.

mod common;

use lsubdiv::mesh::generators::{cube, torus};
use lsubdiv::mesh::QuadMesh;
use lsubdiv_testkit::catmull_clark::{catmull_clark, catmull_clark_steps};
use std::collections::HashMap;

fn centroid(m: &QuadMesh) -> [f64; 3] {
    let mut s = [0.0; 3];
    for p in &m.positions {
        for c in 0..3 {
            s[c] += p[c];
        }
    }
    s.map(|x| x / m.positions.len() as f64)
}

fn edge_uses(m: &QuadMesh) -> HashMap<(u32, u32), usize> {
    let mut uses = HashMap::new();
    for f in &m.faces {
        for i in 0..4 {
            let (a, b) = (f[i], f[(i + 1) % 4]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

#[test]
fn torus_step_counts_and_centroid() {
    let m = torus(8, 8);
    let (v, e, f) = (m.positions.len(), edge_uses(&m).len(), m.faces.len());
    assert_eq!((v, e, f), (64, 128, 64));
    let s = catmull_clark(&m);
    assert_eq!(s.positions.len(), v + e + f);
    assert_eq!(s.faces.len(), 4 * f);
    // All vertices stay valence 4 and the mesh stays closed.
    assert!(edge_uses(&s).values().all(|&k| k == 2));
    // The torus is symmetric about the origin, and so is its refinement.
    let (c0, c1) = (centroid(&m), centroid(&s));
    for k in 0..3 {
        assert!((c0[k] - c1[k]).abs() < 1e-12, "{c0:?} vs {c1:?}");
    }
    assert!(s.positions.iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn cube_two_steps_is_closed() {
    let s = catmull_clark_steps(&cube(), 2);
    assert_eq!((s.positions.len(), s.faces.len()), (98, 96));
    let uses = edge_uses(&s);
    assert_eq!(uses.len(), 192);
    assert!(uses.values().all(|&k| k == 2));
    // Every output vertex is used.
    let mut used = vec![false; s.positions.len()];
    for f in &s.faces {
        for &v in f {
            used[v as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
}

#[test]
fn cube_first_step_values() {
    // Hand-computed values for the cube [-1, 1]^3.
    let s = catmull_clark(&cube());
    // Corner (-1,-1,-1): adjacent face points (-1,0,0), (0,-1,0), (0,0,-1) -> Q = -1/3 each;
    // adjacent edge midpoints (0,-1,-1), (-1,0,-1), (-1,-1,0) -> R = -2/3 each; n = 3:
    // (Q + 2R)/3 = (-1/3 - 4/3)/3 = -5/9.
    for c in 0..3 {
        assert!((s.positions[0][c] + 5.0 / 9.0).abs() < 1e-15);
    }
    // Edge point of edge (0, 4) (x = y = -1): ((-1,-1,-1) + (-1,-1,1) + (-1,0,0) + (0,-1,0))/4.
    let e = s.positions[8];
    assert!((e[0] + 0.75).abs() < 1e-15 && (e[1] + 0.75).abs() < 1e-15 && e[2].abs() < 1e-15);
    // Face point of face 0 (x = -1).
    assert_eq!(s.positions[8 + 12], [-1.0, 0.0, 0.0]);
}
