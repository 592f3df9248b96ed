//! Texture coordinates (`lsubdiv::mesh::facevarying`): the linear rule is bilinear
//! interpolation at the refined vertices' knots, exactly; the smooth rule on a seamless chart
//! is the scheme refining (u, v) as positions; seams keep their two sides apart; the refined
//! channel has one value index per refined face corner.

mod common;

use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::GenericSurface;
use lsubdiv::mesh::facevarying::{refine_uv, Points, PolyUv, QuadUv, UvRule};
use lsubdiv::mesh::features::{Boundary, Features};
use lsubdiv::mesh::generators::{open_grid, tube};
use lsubdiv::mesh::patch::subdivide_with;
use lsubdiv::mesh::polygon::PolyMesh;
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;

/// The compiled surface scheme `name`.
fn surface(name: &str) -> GenericSurface {
    GenericSurface::new(Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls).unwrap()).unwrap()
}

/// A grid with one texture coordinate per vertex, not an affine image of the positions.
fn grid_with_uv() -> (QuadMesh, QuadUv) {
    let mesh = open_grid(3, 4);
    let values = (mesh.positions.iter().enumerate())
        .map(|(i, p)| {
            [
                0.5 + 0.4 * p[0] + 0.03 * (i as f64).sin(),
                0.5 + 0.3 * p[1] * p[1],
            ]
        })
        .collect();
    let uv = QuadUv {
        values,
        faces: mesh.faces.clone(),
    };
    (mesh, uv)
}

fn refine(s: &GenericSurface, mesh: &QuadMesh, uv: &QuadUv, rule: UvRule, steps: usize) -> QuadUv {
    refine_with(s, (mesh, &Features::default()), uv, (rule, false), steps)
}

/// [`refine_uv`] of `uv` on `mesh` with `features`, two workers.
fn refine_with(
    s: &GenericSurface,
    (mesh, features): (&QuadMesh, &Features),
    uv: &QuadUv,
    rule: (UvRule, bool),
    steps: usize,
) -> QuadUv {
    let topo = Topology::build(mesh).unwrap();
    refine_uv(
        s,
        mesh,
        &topo,
        features,
        (uv, Points::default()),
        rule,
        steps,
        2,
    )
    .unwrap()
}

/// The layout of a channel with one value per vertex: the mesh's faces over its values.
fn layout_of(mesh: &QuadMesh, uv: &QuadUv) -> QuadMesh {
    QuadMesh {
        positions: uv.values.iter().map(|&[u, v]| [u, v, 0.0]).collect(),
        faces: mesh.faces.clone(),
    }
}

/// Linear: the value at corner (x, y) of refined face (base face f, cell x, y) is the
/// bilinear interpolation of f's corner values at (K_x / K_N, K_y / K_N), K the prefix sums
/// of W_s's exact lengths, for a uniform and two non-uniform schemes.
#[test]
fn linear_uvs_are_bilinear_at_the_knots() {
    let (mesh, uv) = grid_with_uv();
    for name in ["uniform-binary", "fibonacci", "binary-ternary"] {
        let s = surface(name);
        let steps = 2;
        let fine = refine(&s, &mesh, &uv, UvRule::Linear, steps);
        let k = common::knots(&s, steps);
        let n = k.len() - 1;
        assert_eq!(fine.faces.len(), mesh.faces.len() * n * n, "{name}");
        let mut worst = 0.0f64;
        for (q, corners) in fine.faces.iter().enumerate() {
            let (f, cell) = (q / (n * n), q % (n * n));
            let c = mesh.faces[f].map(|v| uv.values[v as usize]);
            let at = |x: usize, y: usize| {
                let (s, r) = (k[x] / k[n], k[y] / k[n]);
                [0, 1].map(|i| {
                    (1.0 - s) * (1.0 - r) * c[0][i]
                        + s * (1.0 - r) * c[1][i]
                        + s * r * c[2][i]
                        + (1.0 - s) * r * c[3][i]
                })
            };
            let (x, y) = (cell % n, cell / n);
            let want = [at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)];
            for (&i, w) in corners.iter().zip(want) {
                let got = fine.values[i as usize];
                worst = worst.max((got[0] - w[0]).abs().max((got[1] - w[1]).abs()));
            }
        }
        assert!(
            worst < 1e-15,
            "{name}: linear UVs off bilinear by {worst:e}"
        );
    }
}

/// Smooth on a seamless chart (one value per vertex; the chart's boundary is the mesh's):
/// exactly the scheme refining (u, v, 0) as positions with the mesh's boundary rule (under
/// edge-and-corner the chart's corners are the mesh's corners, sharp as OpenSubdiv makes
/// their values), and the refined channel shares a value wherever the refined mesh shares a
/// vertex.
#[test]
fn smooth_uvs_on_a_seamless_chart_are_the_refined_layout() {
    let (mesh, uv) = grid_with_uv();
    for (name, boundary) in [
        ("uniform-binary", Boundary::EdgeAndCorner),
        ("uniform-binary", Boundary::EdgeOnly),
        ("fibonacci", Boundary::EdgeAndCorner),
        ("binary-ternary", Boundary::EdgeOnly),
    ] {
        let s = surface(name);
        let f = Features::with_boundary(boundary);
        let fine = refine_with(&s, (&mesh, &f), &uv, (UvRule::Smooth, false), 2);
        let layout = layout_of(&mesh, &uv);
        let topo = Topology::build(&layout).unwrap();
        let want = subdivide_with::<_, f64>(&s, &layout, &topo, &f, 2, 1).unwrap();
        let positions = subdivide_with::<_, f64>(
            &s,
            &mesh,
            &Topology::build(&mesh).unwrap(),
            &Features::default(),
            2,
            1,
        )
        .unwrap();
        assert_eq!(fine.faces, want.faces, "{name}");
        assert_eq!(fine.faces, positions.faces, "{name}: one value per vertex");
        for (got, w) in fine.values.iter().zip(&want.positions) {
            assert_eq!(*got, [w[0], w[1]], "{name}");
        }
    }
}

/// With the limit, smooth values go to the layout's limit surface: on a seamless chart, the
/// library's `limit_with` of (u, v, 0) with edge-only boundaries.
#[test]
fn smooth_uvs_go_to_the_layouts_limit() {
    use lsubdiv::mesh::patch::limit_with;
    let (mesh, uv) = grid_with_uv();
    let s = surface("fibonacci");
    let f = Features::with_boundary(Boundary::EdgeOnly);
    let fine = refine_with(&s, (&mesh, &f), &uv, (UvRule::Smooth, true), 3);
    let layout = layout_of(&mesh, &uv);
    let lt = Topology::build(&layout).unwrap();
    let want = limit_with::<_, f64>(&s, &layout, &lt, &f, 3, 1).unwrap();
    assert_eq!(fine.faces, want.mesh.faces);
    for (got, w) in fine.values.iter().zip(&want.mesh.positions) {
        assert_eq!(*got, [w[0], w[1]]);
    }
    // And they moved: the limit is not the refined layout.
    let refined = refine(&s, &mesh, &uv, UvRule::Smooth, 3);
    assert_ne!(refined.values, fine.values);
}

/// A tube whose chart is cut along one line of edges (u = 0 on one side, u = 1 on the
/// other): under both rules every refined vertex on the seam has two values, one from each
/// side, exactly u = 0 and u = 1 away from the chart's corners (near them the smooth rule's
/// edge-only boundary rounds the corners, moving the values inward, as OpenSubdiv's
/// `FVAR_LINEAR_NONE`), and every other vertex one; the counts match the refined mesh's.
#[test]
fn seams_keep_their_two_sides_apart() {
    let (rows, cols) = (6, 5);
    let mesh = tube(rows, cols);
    // Value (i, j) for j = 0..=cols: column cols is the seam's other side.
    let value = |i: usize, j: usize| (i * (cols + 1) + j) as u32;
    let values = (0..=rows)
        .flat_map(|i| (0..=cols).map(move |j| [j as f64 / cols as f64, i as f64 / rows as f64]))
        .collect();
    let faces = (0..rows)
        .flat_map(|i| {
            (0..cols).map(move |j| {
                [
                    value(i, j),
                    value(i, j + 1),
                    value(i + 1, j + 1),
                    value(i + 1, j),
                ]
            })
        })
        .collect();
    let uv = QuadUv { values, faces };
    let topo = Topology::build(&mesh).unwrap();
    for rule in [UvRule::Linear, UvRule::Smooth] {
        for name in ["uniform-binary", "fibonacci"] {
            let s = surface(name);
            let fine = refine(&s, &mesh, &uv, rule, 2);
            let m = subdivide_with::<_, f64>(&s, &mesh, &topo, &Features::default(), 2, 1).unwrap();
            assert_eq!(fine.faces.len(), m.faces.len(), "{name} {rule:?}");
            // Per refined mesh vertex, the values its corners use.
            let mut used = vec![Vec::new(); m.positions.len()];
            for (pf, uf) in m.faces.iter().zip(&fine.faces) {
                for (&v, &u) in pf.iter().zip(uf) {
                    if !used[v as usize].contains(&u) {
                        used[v as usize].push(u);
                    }
                }
            }
            let mut seam = 0;
            for (v, us) in used.iter().enumerate() {
                let u: Vec<f64> = us.iter().map(|&i| fine.values[i as usize][0]).collect();
                let on_seam = m.positions[v][1].abs() < 1e-12 && m.positions[v][0] > 0.0;
                if on_seam {
                    seam += 1;
                    assert_eq!(us.len(), 2, "{name} {rule:?}: seam vertex {v}: {u:?}");
                    // Beyond two base edges (a cubic B-spline's reach) from the chart's ends.
                    let inner = m.positions[v][2].abs() < 0.3;
                    let (lo, hi) = (u[0].min(u[1]), u[0].max(u[1]));
                    let apart = if inner {
                        lo.abs() < 1e-12 && (hi - 1.0).abs() < 1e-12
                    } else {
                        lo < 0.5 && hi > 0.5
                    };
                    assert!(apart, "{name} {rule:?}: seam vertex {v}: {u:?}");
                } else {
                    assert_eq!(
                        us.len(),
                        1,
                        "{name} {rule:?}: vertex {v} off the seam: {u:?}"
                    );
                }
            }
            assert!(seam > rows, "{name} {rule:?}: {seam} seam vertices");
        }
    }
}

/// A polygon mesh's first (Catmull–Clark) step: linear UVs of a split quad are its corner's
/// value, the midpoint after it, the face's centroid and the midpoint before it.
#[test]
fn the_first_step_of_polygons_splits_uvs_linearly() {
    let mut mesh = PolyMesh::new();
    mesh.positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.5, 0.0],
    ];
    mesh.push_face(&[0, 1, 2, 3]);
    mesh.push_face(&[1, 4, 2]);
    let uv = PolyUv {
        values: vec![[0.0, 0.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5], [0.9, 0.2]],
        corners: vec![0, 1, 2, 3, 1, 4, 2],
    };
    let split = uv
        .split(
            &mesh,
            &Features::default(),
            UvRule::Linear,
            Points::default(),
        )
        .unwrap();
    assert_eq!(split.faces.len(), 7);
    let mid = |a: usize, b: usize| [0, 1].map(|i| (uv.values[a][i] + uv.values[b][i]) / 2.0);
    let tri = [1, 4, 2];
    let centroid = [0, 1].map(|i| tri.iter().map(|&v| uv.values[v][i]).sum::<f64>() / 3.0);
    // The triangle's second quad: corner 4, midpoint 4–2, centroid, midpoint 1–4.
    let q = split.faces[5].map(|i| split.values[i as usize]);
    let want = [uv.values[4], mid(4, 2), centroid, mid(1, 4)];
    for (g, w) in q.iter().zip(want) {
        assert!(
            (g[0] - w[0]).abs() < 1e-15 && (g[1] - w[1]).abs() < 1e-15,
            "{q:?} vs {want:?}"
        );
    }
    // The shared edge 1–2 has one midpoint: after corner 1 in the quad, before corner 1 and
    // after corner 2 in the triangle.
    let m = split.faces[1][1];
    assert_eq!((split.faces[4][3], split.faces[6][1]), (m, m));
    assert_eq!(split.values[m as usize], mid(1, 2));
}

/// The texture coordinates of an OBJ text, its `vt` lines.
fn vt_lines(text: &str) -> Vec<[f64; 2]> {
    (text.lines().filter_map(|l| l.strip_prefix("vt ")))
        .map(|l| {
            let x: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            [x[0], x[1]]
        })
        .collect()
}

/// `lsubdiv subdivide` carries texture coordinates through: OBJ `vt` in, `vt` and `v/vt` out
/// (`v/vt/vn` with `--limit`), the input's `vn` ignored with one warning; linear values are
/// the library's `refine_uv`; a value index used at two vertices is two values, as
/// OpenSubdiv's.
#[test]
fn subdivide_refines_texture_coordinates() {
    use common::cli::{lsubdiv, stderr, write};
    let dir = tempfile::tempdir().unwrap();
    // A 2 × 1 strip; the second quad's texture corners repeat the first's (a layout whose two
    // faces share all four values: not a 2-manifold), and normals to ignore.
    let strip = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0.5\n\
                 vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
                 f 1/1/1 2/2/1 5/3/1 4/4/1\nf 2/1/1 3/2/1 6/3/1 5/4/1\n";
    let input = write(dir.path(), "strip.obj", strip);
    let out = dir.path().join("out.obj");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "subdivide",
            "uniform-binary",
            input.as_str(),
            "--steps",
            "2",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", out.to_str().unwrap()]);
        lsubdiv(&args)
    };
    let o = run(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let warnings = stderr(&o).lines().filter(|l| l.contains("normals")).count();
    assert_eq!(warnings, 1, "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let vt = vt_lines(&text);
    let faces: Vec<[u32; 4]> = (text.lines().filter_map(|l| l.strip_prefix("f ")))
        .map(|l| {
            let c: Vec<u32> = (l.split_whitespace())
                .map(|c| c.split('/').nth(1).unwrap().parse::<u32>().unwrap() - 1)
                .collect();
            [c[0], c[1], c[2], c[3]]
        })
        .collect();
    // The library's linear refinement of the same channel.
    let read = lsubdiv::mesh_file::parse_checked("strip.obj", strip.as_bytes().to_vec()).unwrap();
    let s = surface("uniform-binary");
    let uv = read.uv.as_ref().unwrap();
    let want: QuadUv = refine_uv(
        &s,
        &read.mesh,
        &read.topology,
        &read.features,
        (uv, Points::default()),
        (UvRule::Linear, false),
        2,
        1,
    )
    .unwrap();
    assert_eq!(faces.len(), want.faces.len());
    for (f, w) in faces.iter().zip(&want.faces) {
        for (&a, &b) in f.iter().zip(w) {
            assert_eq!(vt[a as usize], want.values[b as usize]);
        }
    }
    // With --limit: v/vt/vn.
    let o = run(&["--limit"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let face = text.lines().find(|l| l.starts_with("f ")).unwrap();
    assert!(
        face.split_whitespace()
            .skip(1)
            .all(|c| c.split('/').count() == 3),
        "{face}"
    );
    // A value belongs to its vertex (OpenSubdiv's face-varying level): the two faces are two
    // charts of one quad each. Corners-only keeps their corners: straight sides with fixed
    // ends, which uniform binary refines bilinearly, the linear rule's values; smooth rounds
    // the corners in (FVAR_LINEAR_NONE's crease rule on a value of one face) where the mesh's
    // boundary rule does not make them corners.
    let near = |values: &[[f64; 2]], w: &[f64; 2]| {
        (values.iter()).any(|v| (v[0] - w[0]).abs() < 1e-12 && (v[1] - w[1]).abs() < 1e-12)
    };
    let o = run(&["--uv", "corners-only"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let corners = vt_lines(&std::fs::read_to_string(&out).unwrap());
    assert!(want.values.iter().all(|w| near(&corners, w)));
    let o = run(&["--uv", "smooth", "--boundary", "edge-only"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let smooth = vt_lines(&std::fs::read_to_string(&out).unwrap());
    assert!(!near(&smooth, &[0.0, 0.0]));
}

/// A layout that is not a 2-manifold (the spot models have such): on a 2 × 2 grid,
/// the two diagonal faces share the middle value and the other two each have their own, so
/// the middle value's faces form two fans. The smooth rule refines it as OpenSubdiv's
/// `FVAR_LINEAR_NONE` does: the value is a corner of each fan (it stays).
#[test]
fn a_bow_tie_in_the_layout_is_a_corner_of_each_fan() {
    let mesh = open_grid(2, 2);
    // Grid vertex i·3 + j at (j, i); the faces (i, j) in row order, corners from (i, j).
    let mut values: Vec<[f64; 2]> = (0..9)
        .map(|k| {
            [
                0.1 + 0.4 * (k % 3) as f64,
                0.1 + 0.4 * (k / 3) as f64 + 0.01 * k as f64,
            ]
        })
        .collect();
    values.push(values[4]); // 9: face (0, 1)'s own middle
    values.push(values[4]); // 10: face (1, 0)'s own middle
    let mut faces = mesh.faces.clone();
    for (f, own) in [(1, 9), (2, 10)] {
        for c in faces[f].iter_mut().filter(|c| **c == 4) {
            *c = own;
        }
    }
    let uv = QuadUv { values, faces };
    for name in ["uniform-binary", "fibonacci", "binary-ternary"] {
        let s = surface(name);
        let fine = refine(&s, &mesh, &uv, UvRule::Smooth, 2);
        let n = (fine.faces.len() / 4) as f64;
        assert_eq!(fine.faces.len(), 4 * (n.sqrt() as usize).pow(2), "{name}");
        assert!(
            fine.values.iter().flatten().all(|x| x.is_finite()),
            "{name}"
        );
        // The middle value stays where it is, one value for both fans (the faces' own copies
        // 9 and 10 are edge-only boundary vertices of the layout: they move).
        let middle = uv.values[4];
        let at_middle = fine.values.iter().filter(|v| **v == middle).count();
        assert_eq!(at_middle, 1, "{name}");
    }
}

/// A 3 × 3 grid of unit quads in OBJ, its texture coordinates the positions over 3, but the
/// interior vertex (1, 1) at (0.4, 0.3) (the layout is not affine there); with `dart`, the
/// vertex (1, 0) has a second value (the same point) in the face to its right, so the edge
/// (1, 0)–(1, 1) is a seam that ends at (1, 1); `tags` appended.
fn grid_obj(dart: bool, tags: &str) -> String {
    let mut text = String::new();
    for y in 0..4 {
        for x in 0..4 {
            text += &format!("v {x} {y} 0\n");
        }
    }
    for y in 0..4 {
        for x in 0..4 {
            let uv = match (x, y) {
                (1, 1) => [0.4, 0.3],
                _ => [x as f64 / 3.0, y as f64 / 3.0],
            };
            text += &format!("vt {} {}\n", uv[0], uv[1]);
        }
    }
    text += "vt 0.3333333333333333 0\n";
    for y in 0..3 {
        for x in 0..3 {
            let v = |dx: usize, dy: usize| {
                let (i, j) = (x + dx, y + dy);
                let vt = if dart && (i, j) == (1, 0) && x == 1 {
                    17
                } else {
                    1 + i + 4 * j
                };
                format!("{}/{vt}", 1 + i + 4 * j)
            };
            text += &format!("f {} {} {} {}\n", v(0, 0), v(1, 0), v(1, 1), v(0, 1));
        }
    }
    text + tags
}

/// `subdivide --steps n --boundary edge-only` of `obj` with `extra` arguments: its `vt` values.
fn refined_uvs(obj: &str, steps: &str, extra: &[&str]) -> Vec<[f64; 2]> {
    use common::cli::{lsubdiv, stderr, write};
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "grid.obj", obj);
    let out = dir.path().join("out.obj");
    let mut args = vec![
        "subdivide",
        "uniform-binary",
        input.as_str(),
        "--steps",
        steps,
    ];
    args.extend_from_slice(&["--boundary", "edge-only", "-o", out.to_str().unwrap()]);
    args.extend_from_slice(extra);
    let o = lsubdiv(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    vt_lines(&std::fs::read_to_string(&out).unwrap())
}

fn has(values: &[[f64; 2]], p: [f64; 2]) -> bool {
    values
        .iter()
        .any(|v| (v[0] - p[0]).abs() < 1e-12 && (v[1] - p[1]).abs() < 1e-12)
}

/// OpenSubdiv's face-varying modes: corners-only keeps a value with one face where smooth
/// moves it; the file's `t facevaryinginterpolateboundary` chooses the mode, `--uv` overrides
/// it; boundaries keeps the chart's boundary linear; corners-plus2 keeps a dart's value where
/// corners-plus1 smooths it.
#[test]
fn face_varying_modes_keep_what_opensubdiv_keeps() {
    let plain = grid_obj(false, "");
    let corner = [0.0, 0.0];
    assert!(!has(&refined_uvs(&plain, "2", &["--uv", "smooth"]), corner));
    assert!(has(
        &refined_uvs(&plain, "2", &["--uv", "corners-only"]),
        corner
    ));
    let tagged = grid_obj(false, "t facevaryinginterpolateboundary 1/0/0 1\n");
    assert!(has(&refined_uvs(&tagged, "2", &[]), corner));
    assert!(!has(&refined_uvs(&tagged, "2", &["--uv", "none"]), corner));
    // Along the bottom edge, linear: the twelfths; smooth: a B-spline's points, the corner's
    // moved in.
    let bottom = |values: &[[f64; 2]]| -> Vec<f64> {
        let mut u: Vec<f64> = (values.iter())
            .filter(|v| v[1].abs() < 1e-12)
            .map(|v| v[0])
            .collect();
        u.sort_by(f64::total_cmp);
        u
    };
    let linear = bottom(&refined_uvs(&plain, "2", &["--uv", "boundaries"]));
    assert_eq!(linear.len(), 13);
    for (k, u) in linear.iter().enumerate() {
        assert!((u - k as f64 / 12.0).abs() < 1e-12, "{linear:?}");
    }
    let smooth = bottom(&refined_uvs(&plain, "2", &["--uv", "smooth"]));
    assert!(smooth[0] > 1e-3, "{smooth:?}");
    // The seam from (1, 0) ends at (1, 1), whose value (0.4, 0.3) is not where the smooth rule
    // of its neighbours puts it.
    let dart = grid_obj(true, "");
    let value = [0.4, 0.3];
    assert!(has(
        &refined_uvs(&dart, "1", &["--uv", "corners-plus2"]),
        value
    ));
    assert!(!has(
        &refined_uvs(&dart, "1", &["--uv", "corners-plus1"]),
        value
    ));
}
