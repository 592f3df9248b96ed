//! Meshes as people have them, every surface scheme: non-manifold edges and
//! vertices, faces that repeat a vertex, vertices no face uses, boundary interpolation none,
//! fractional sharpness. Each is checked against the same surface reached another way: a
//! non-manifold mesh against its manifold pieces refined alone with OpenSubdiv's tags, unused
//! vertices against the mesh without them, `none` against its holes tagged by hand, a
//! fractional crease against the blend of the two integer ones around it.

mod common;

use common::cli::{lsubdiv, stderr, write};

use common::SURFACE_SCHEMES as SCHEMES;

const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

/// A refined mesh as written: positions and faces (0-based).
struct Obj {
    v: Vec<[f64; 3]>,
    f: Vec<[usize; 4]>,
}

/// Refines `text` (written as `name` in `dir`) by `scheme`, `steps` steps, with `extra`
/// arguments; the output and the warnings.
fn refine(
    dir: &std::path::Path,
    (name, text): (&str, &str),
    scheme: &str,
    steps: usize,
    extra: &[&str],
) -> (Obj, String) {
    let input = write(dir, name, text);
    let label = std::path::Path::new(scheme)
        .file_stem()
        .unwrap()
        .to_str()
        .unwrap();
    let out = dir.join(format!("{name}.{label}.out.obj"));
    let steps = steps.to_string();
    let mut args = vec![
        "subdivide",
        scheme,
        "--steps",
        &steps,
        &input,
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = lsubdiv(&args);
    assert!(o.status.success(), "{name} {scheme}: {}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut obj = Obj {
        v: Vec::new(),
        f: Vec::new(),
    };
    for line in text.lines() {
        let t: Vec<&str> = line.split_ascii_whitespace().collect();
        match t.first() {
            Some(&"v") => obj.v.push([1, 2, 3].map(|i| t[i].parse().unwrap())),
            Some(&"f") => obj.f.push(
                [1, 2, 3, 4].map(|i| t[i].split('/').next().unwrap().parse::<usize>().unwrap() - 1),
            ),
            _ => {}
        }
    }
    (obj, stderr(&o))
}

/// The points sorted, for comparing meshes numbered differently.
fn sorted(mut v: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
    v.sort_by(|a, b| {
        (a[0].total_cmp(&b[0]))
            .then(a[1].total_cmp(&b[1]))
            .then(a[2].total_cmp(&b[2]))
    });
    v
}

/// Whether two point sets are the same to `tol`, point by point once sorted; points closer
/// than that to each other are joined first (the copies of one point).
fn same_points(a: Vec<[f64; 3]>, b: Vec<[f64; 3]>, tol: f64) -> Result<(), String> {
    let dedup = |v: Vec<[f64; 3]>| {
        let mut out: Vec<[f64; 3]> = Vec::new();
        for p in sorted(v) {
            if !out
                .iter()
                .any(|q| (0..3).all(|i| (p[i] - q[i]).abs() <= tol))
            {
                out.push(p);
            }
        }
        sorted(out)
    };
    let (a, b) = (dedup(a), dedup(b));
    if a.len() != b.len() {
        return Err(format!("{} distinct points against {}", a.len(), b.len()));
    }
    for p in &a {
        if !b.iter().any(|q| (0..3).all(|i| (p[i] - q[i]).abs() <= tol)) {
            return Err(format!("{p:?} has no match"));
        }
    }
    Ok(())
}

/// The cube and a second cube touching it at its vertex 7: the second cube's other vertex
/// lines follow the first's.
fn bow_tie() -> String {
    let mut text = CUBE.to_string();
    // The second cube: the first moved by (2, 2, 2), so that its vertex 1 lands on the
    // first's vertex 7 (1, 1, 1), which it shares.
    for (i, line) in CUBE.lines().filter(|l| l.starts_with("v ")).enumerate() {
        if i == 0 {
            continue;
        }
        let p: Vec<f64> = line[2..].split(' ').map(|t| t.parse().unwrap()).collect();
        text += &format!("v {} {} {}\n", p[0] + 2.0, p[1] + 2.0, p[2] + 2.0);
    }
    // Second cube vertex i (1-based): 1 is the first cube's 7, i > 1 is 8 + i − 1.
    let second = |i: usize| if i == 1 { 7 } else { 7 + i };
    for line in CUBE.lines().filter(|l| l.starts_with("f ")) {
        let idx: Vec<String> = line[2..]
            .split(' ')
            .map(|t| second(t.parse().unwrap()).to_string())
            .collect();
        text += &format!("f {}\n", idx.join(" "));
    }
    text
}

#[test]
fn a_bow_tie_vertex_is_a_corner_of_each_fan() {
    // Two cubes touching at one vertex: each refined as the cube alone with that vertex an
    // infinitely sharp corner (OpenSubdiv sharpens a non-manifold vertex).
    let dir = tempfile::tempdir().unwrap();
    let tie = bow_tie();
    // The second cube alone: the cube moved by (2, 2, 2), its vertex 1 on (1, 1, 1).
    let mut second = String::new();
    for line in CUBE.lines() {
        match line.strip_prefix("v ") {
            Some(xyz) => {
                let p: Vec<f64> = xyz.split(' ').map(|t| t.parse().unwrap()).collect();
                second += &format!("v {} {} {}\n", p[0] + 2.0, p[1] + 2.0, p[2] + 2.0);
            }
            None => second += &format!("{line}\n"),
        }
    }
    second += "t corner 1/1/0 0 10\n";
    let first = format!("{CUBE}t corner 1/1/0 6 10\n");
    for scheme in SCHEMES {
        let (whole, warnings) = refine(dir.path(), ("tie.obj", &tie), scheme, 2, &[]);
        assert!(warnings.contains("1 non-manifold vertex"), "{warnings}");
        let (a, _) = refine(dir.path(), ("a.obj", &first), scheme, 2, &[]);
        let (b, _) = refine(dir.path(), ("b.obj", &second), scheme, 2, &[]);
        assert_eq!(
            whole.v.len(),
            a.v.len() + b.v.len() - 1,
            "{scheme}: one shared vertex"
        );
        assert_eq!(whole.f.len(), a.f.len() + b.f.len(), "{scheme}");
        let pieces = [a.v, b.v].concat();
        same_points(whole.v.clone(), pieces, 1e-12).unwrap_or_else(|e| panic!("{scheme}: {e}"));
        assert!(
            whole.v.contains(&[1.0, 1.0, 1.0]),
            "{scheme}: the shared vertex stays"
        );
    }
}

#[test]
fn a_fin_on_an_edge_is_refined_on_its_own_with_the_edge_sharp() {
    // A quad standing on the cube's edge 1–2 (three faces on it): the cube with the edge
    // infinitely sharp and its ends corners, and the fin alone (an open quad whose corners
    // are interpolated), share the edge's points.
    let dir = tempfile::tempdir().unwrap();
    let fin = format!("{CUBE}v 1 -3 -1\nv -1 -3 -1\nf 2 1 10 9\n");
    let cube = format!("{CUBE}t crease 2/1/0 0 1 10\nt corner 2/1/0 0 1 10\n");
    let alone = "v -1 -1 -1\nv 1 -1 -1\nv 1 -3 -1\nv -1 -3 -1\nf 2 1 4 3\n";
    for scheme in SCHEMES {
        let (whole, warnings) = refine(dir.path(), ("fin.obj", &fin), scheme, 2, &[]);
        assert!(
            warnings.contains("2 non-manifold vertices and 1 non-manifold edge"),
            "{warnings}"
        );
        let (a, _) = refine(dir.path(), ("cube.obj", &cube), scheme, 2, &[]);
        let (b, _) = refine(dir.path(), ("alone.obj", alone), scheme, 2, &[]);
        let n = ((b.f.len()) as f64).sqrt() as usize;
        assert_eq!(
            whole.v.len(),
            a.v.len() + b.v.len() - (n + 1),
            "{scheme}: the edge once"
        );
        assert_eq!(whole.f.len(), a.f.len() + b.f.len(), "{scheme}");
        same_points(whole.v.clone(), [a.v, b.v].concat(), 1e-12)
            .unwrap_or_else(|e| panic!("{scheme}: {e}"));
        // The edge is refined as a segment between corners: its points on it.
        let on_edge = whole
            .v
            .iter()
            .filter(|p| (p[1] + 1.0).abs() < 1e-12 && (p[2] + 1.0).abs() < 1e-12)
            .count();
        assert_eq!(on_edge, n + 1, "{scheme}");
    }
}

#[test]
fn faces_that_repeat_a_vertex_refine_as_opensubdiv_counts_them() {
    // A pyramid whose four sides are quads with the apex twice (a degenerate edge each): the
    // apex is non-manifold (a corner), each degenerate edge its own edge, as in Far.
    let dir = tempfile::tempdir().unwrap();
    let pyramid = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\nf 4 3 2 1\nf 1 2 5 5\nf 2 3 5 5\nf 3 4 5 5\nf 4 1 5 5\n";
    for scheme in SCHEMES {
        let (m, warnings) = refine(dir.path(), ("pyramid.obj", pyramid), scheme, 1, &[]);
        assert!(warnings.contains("non-manifold"), "{warnings}");
        let n = ((m.f.len() / 5) as f64).sqrt() as usize;
        // 5 vertices, 12 edges (8 and 4 degenerate), 5 faces.
        assert_eq!(
            m.v.len(),
            5 + 12 * (n - 1) + 5 * (n - 1) * (n - 1),
            "{scheme}"
        );
        assert!(m.v.contains(&[0.0, 0.0, 1.0]), "{scheme}: the apex stays");
        for f in &m.f {
            assert!(f.iter().all(|&v| v < m.v.len()), "{scheme}");
        }
    }
}

#[test]
fn unused_vertices_are_dropped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let extra = format!("{CUBE}v 5 5 5\nv 6 6 6\n");
    for scheme in ["uniform-binary", "binary-ternary"] {
        let (with, warnings) = refine(dir.path(), ("extra.obj", &extra), scheme, 2, &[]);
        assert!(
            warnings.contains("2 vertices used by no face: dropped"),
            "{warnings}"
        );
        let (without, _) = refine(dir.path(), ("cube.obj", CUBE), scheme, 2, &[]);
        assert_eq!(with.v, without.v, "{scheme}");
        assert_eq!(with.f, without.f, "{scheme}");
    }
}

/// An open 3 × 3 grid, bumped.
fn grid() -> String {
    let mut t = String::new();
    for i in 0..4 {
        for j in 0..4 {
            t += &format!("v {j} {i} {}\n", 0.1 * (i * j) as f64);
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let v = |i: usize, j: usize| i * 4 + j + 1;
            t += &format!(
                "f {} {} {} {}\n",
                v(i, j),
                v(i, j + 1),
                v(i + 1, j + 1),
                v(i + 1, j)
            );
        }
    }
    t
}

#[test]
fn boundary_none_drops_the_faces_at_the_boundary() {
    // OpenSubdiv's VTX_BOUNDARY_NONE: every face at a boundary vertex is a hole; the middle
    // face stays, refined edge-only.
    let dir = tempfile::tempdir().unwrap();
    let none = format!("{}t interpolateboundary 1/0/0 0\n", grid());
    let holes = format!("{}t hole 8/0/0 0 1 2 3 5 6 7 8\n", grid());
    for scheme in SCHEMES {
        let (a, _) = refine(dir.path(), ("none.obj", &none), scheme, 2, &[]);
        let (b, _) = refine(
            dir.path(),
            ("holes.obj", &holes),
            scheme,
            2,
            &["--boundary", "edge-only"],
        );
        let (c, _) = refine(
            dir.path(),
            ("cli.obj", &grid()),
            scheme,
            2,
            &["--boundary", "none"],
        );
        assert_eq!(a.v, b.v, "{scheme}");
        assert_eq!(a.f, b.f, "{scheme}");
        assert_eq!((&a.v, &a.f), (&c.v, &c.f), "{scheme}: --boundary none");
        let n = ((a.f.len()) as f64).sqrt() as usize;
        assert_eq!(a.f.len(), n * n, "{scheme}: one face kept");
    }
}

#[test]
fn a_fractional_crease_blends_the_two_integer_ones() {
    // A crease loop of sharpness 0.5 around the cube: at the first step every point on it is
    // half the crease's and half the smooth rule's (OpenSubdiv's `ComputeEdgeVertexMask`, and
    // `ComputeFractionalWeightAtVertex` = 0.5 at each of its vertices), and the steps after
    // are linear and the same: the refinement is the mean of sharpness 1's and sharpness 0's
    // (for Binary-Ternary, whose first step runs the reference driver on the mesh cut along
    // its sharp lines, by the blend of that step cut along the crease and not).
    // A corner of sharpness 0.5 likewise (its rule blends the corner's and the smooth one).
    let dir = tempfile::tempdir().unwrap();
    let crease = |s: &str| format!("{CUBE}t crease 8/1/0 0 1 1 2 2 3 3 0 {s}\n");
    let corner = |s: &str| format!("{CUBE}t corner 1/1/0 0 {s}\n");
    // Sharpness `s` refines to the mean of sharpness `lo` and `hi`.
    let mean_of =
        |scheme: &str, what: &str, tagged: &dyn Fn(&str) -> String, [s, lo, hi]: [&str; 3]| {
            let (mid, _) = refine(dir.path(), ("mid.obj", &tagged(s)), scheme, 3, &[]);
            let (hi, _) = refine(dir.path(), ("hi.obj", &tagged(hi)), scheme, 3, &[]);
            let (lo, _) = refine(dir.path(), ("lo.obj", &tagged(lo)), scheme, 3, &[]);
            assert_eq!(mid.f, hi.f, "{scheme}");
            for (i, (p, (a, b))) in mid.v.iter().zip(hi.v.iter().zip(&lo.v)).enumerate() {
                let mean: [f64; 3] = std::array::from_fn(|c| 0.5 * (a[c] + b[c]));
                let off = (0..3).map(|c| (p[c] - mean[c]).abs()).fold(0.0, f64::max);
                assert!(
                    off < 1e-12,
                    "{scheme}, {what} {s}: vertex {i}: {p:?}, mean {mean:?}"
                );
            }
        };
    for scheme in SCHEMES {
        for (what, tagged) in [
            ("crease", &crease as &dyn Fn(&str) -> String),
            ("corner", &corner),
        ] {
            mean_of(scheme, what, tagged, ["0.5", "0", "1"]);
        }
        let tagged = crease;
        let (point_seven, _) = refine(dir.path(), ("p7.obj", &tagged("1.7")), scheme, 3, &[]);
        assert!(
            point_seven
                .v
                .iter()
                .all(|p| p.iter().all(|x| x.is_finite())),
            "{scheme}"
        );
    }
    // Schemes whose first two or three steps run the reference driver, each on its level cut
    // along the lines sharp at that step: sharpness 1.5 blends at the second step (its edges
    // at weight 0.5, its vertices' rule transition at 0.5), so it is the mean of sharpness 1's
    // (smooth from the second step) and 2's (sharp at it).
    for (i, text) in common::DELAYED.iter().enumerate() {
        let scheme = write(dir.path(), &format!("delayed-{i}.toml"), text);
        for s in [["1.5", "1", "2"], ["0.5", "0", "1"]] {
            mean_of(&scheme, "crease", &crease, s);
        }
    }
}

#[test]
fn chaikin_creasing_takes_its_steps_one_level_at_a_time() {
    // Chaikin's children (OpenSubdiv's `CREASE_CHAIKIN`) vary along an edge, so lsubdiv takes
    // the steps one at a time, each level a base mesh. Where no two semi-sharp creases meet,
    // the children are uniform creasing's (s − 1), and the refinement is the one refinement's,
    // face for face, with a hole, a semi-sharp corner and an infinitely sharp crease carried
    // through the levels.
    let dir = tempfile::tempdir().unwrap();
    let tags = "t crease 2/1/0 0 1 2.5\nt crease 2/1/0 2 3 1.5\nt crease 2/1/0 6 7 10\n\
                t corner 1/1/0 5 2\nt hole 1/0/0 4\n";
    let chaikin = "t creasemethod 0/0/1 chaikin\n";
    // How far uniform creasing's and Chaikin's refinements of `text` are apart, corner for
    // corner of the same quads in the same order (the levels number their points their own
    // way).
    let gap = |text: &str| {
        let (uniform, _) = refine(dir.path(), ("u.obj", text), "uniform-binary", 3, &[]);
        let text = text.to_string() + chaikin;
        let (stepped, _) = refine(dir.path(), ("c.obj", &text), "uniform-binary", 3, &[]);
        corner_gap(&uniform, &stepped)
    };
    let apart = gap(&format!("{CUBE}{tags}"));
    assert!(apart < 1e-12, "apart by {apart:e}");
    // Where semi-sharp creases of 2 and 4 meet, their children there are 1.5 and 2.5, not 1
    // and 3: the surfaces differ (tests/opensubdiv_shapes.rs compares them with OpenSubdiv's).
    let meeting = format!("{CUBE}t crease 2/1/0 0 1 2\nt crease 2/1/0 1 2 4\n");
    let apart = gap(&meeting);
    assert!(
        apart > 1e-3,
        "Chaikin's surface is uniform creasing's: {apart:e}"
    );
    // A scheme whose levels are not base meshes refuses it, saying why.
    let input = write(dir.path(), "m.obj", &(meeting + chaikin));
    let out = dir.path().join("f.obj");
    let o = lsubdiv(&[
        "subdivide",
        "fibonacci",
        "--steps",
        "2",
        &input,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("Chaikin creasing"), "{}", stderr(&o));
}

/// How far apart the corners of two refinements with the same quads in the same order are
/// (each numbering its points its own way).
fn corner_gap(a: &Obj, b: &Obj) -> f64 {
    assert_eq!((a.f.len(), a.v.len()), (b.f.len(), b.v.len()));
    let corners = a.f.iter().zip(&b.f).flat_map(|(f, g)| f.iter().zip(g));
    corners
        .flat_map(|(&i, &j)| (0..3).map(move |c| (a.v[i][c] - b.v[j][c]).abs()))
        .fold(0.0, f64::max)
}

/// Per number of faces k, the edges of `mesh` with k faces (distinct vertex pairs; a face's
/// degenerate edges left out).
fn edges_by_faces(
    mesh: &lsubdiv::mesh::polygon::PolyMesh,
) -> std::collections::BTreeMap<usize, usize> {
    let mut faces: std::collections::HashMap<[u32; 2], usize> = std::collections::HashMap::new();
    for f in mesh.faces() {
        for (i, &a) in f.iter().enumerate() {
            let b = f[(i + 1) % f.len()];
            if a != b {
                *faces.entry([a.min(b), a.max(b)]).or_insert(0) += 1;
            }
        }
    }
    let mut hist = std::collections::BTreeMap::new();
    for k in faces.into_values() {
        *hist.entry(k).or_insert(0) += 1;
    }
    hist
}

/// The public models of `../shared/models/`: every one refines with
/// every surface scheme (those over 5,000 faces by two or three of them), two steps, and
/// without cracks: each boundary edge (one face) and each
/// non-manifold edge (three or more) of the file becomes a run of as many refined edges with
/// the same number of faces, and no other edge has other than two. The ones with texture
/// coordinates refine them with `--uv smooth` too.
#[test]
fn every_public_model_refines_with_every_scheme_without_cracks() {
    let Some(files) = common::shared_files("models", "the public models are not refined") else {
        return;
    };
    let models: Vec<_> = (files.into_iter())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("obj" | "ply")))
        .collect();
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out.ply");
    for model in &models {
        let name = model.display().to_string();
        let input = lsubdiv::mesh_file::read_faces(&name, std::fs::read(model).unwrap()).unwrap();
        let before = edges_by_faces(&input.mesh);
        let corners = input.mesh.corners.len();
        let quads = input.mesh.all_quads();
        let textured = input.uv.is_some();
        // Larger models (a debug build takes seconds a run) by fewer schemes: the uniform one,
        // the one whose first step runs the reference driver, and below 20,000 faces an
        // irrational one.
        let schemes: &[&str] = match input.mesh.face_count() {
            0..=5_000 => &SCHEMES,
            5_001..=20_000 => &["uniform-binary", "fibonacci", "binary-ternary"],
            _ => &["uniform-binary", "binary-ternary"],
        };
        for scheme in schemes {
            let mut args = vec!["subdivide", scheme, "--steps", "2", &name, "-o"];
            args.extend([out.to_str().unwrap(), "--binary"]);
            if textured {
                args.extend(["--uv", "smooth"]);
            }
            let o = lsubdiv(&args);
            assert!(o.status.success(), "{name} {scheme}: {}", stderr(&o));
            let fine = lsubdiv::ply::parse("out.ply", &std::fs::read(&out).unwrap()).unwrap();
            let faces = fine.mesh.face_count();
            // Refined edges per file edge: N for a quad mesh (N² quads a face), 2N' for a
            // polygon mesh (a quad per corner, then N'² each).
            let (per, refined) = if quads {
                (input.mesh.face_count(), 1)
            } else {
                (corners, 2)
            };
            let n = (faces as f64 / per as f64).sqrt().round() as usize;
            assert_eq!(n * n * per, faces, "{name} {scheme}");
            let after = edges_by_faces(&fine.mesh);
            for (&k, &count) in before.iter().filter(|(&k, _)| k != 2) {
                assert_eq!(
                    after.get(&k).copied().unwrap_or(0),
                    count * n * refined,
                    "{name} {scheme}: edges of {k} faces"
                );
            }
            for (&k, &count) in after.iter().filter(|(&k, _)| k != 2) {
                assert!(
                    before.contains_key(&k),
                    "{name} {scheme}: {count} new edges of {k} faces"
                );
            }
        }
    }
}

/// OpenSubdiv's regression shapes with texture coordinates (`../shared/osd_shapes/`) refine
/// them by the smooth rule (`FVAR_LINEAR_NONE`'s), every layout however it is cut, non-manifold
/// ones included; only Chaikin's creasing is refused.
#[test]
fn regression_shapes_refine_their_texture_coordinates_smoothly() {
    let skipped = "the regression shapes are not refined";
    let Some(files) = common::shared_files("osd_shapes", skipped) else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out.ply");
    let mut textured = 0;
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if !text.lines().any(|l| l.starts_with("vt ")) {
            continue;
        }
        textured += 1;
        let name = path.display().to_string();
        let args = ["subdivide", "fibonacci", "--steps", "2", &name, "-o"];
        let o = lsubdiv(&[&args[..], &[out.to_str().unwrap(), "--uv", "smooth"]].concat());
        let chaikin = text.contains("creasemethod 0/0/1 chaikin");
        assert_eq!(o.status.success(), !chaikin, "{name}: {}", stderr(&o));
    }
    assert!(textured > 10, "{textured} shapes with texture coordinates");
}
