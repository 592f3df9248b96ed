//! Uniform binary against OpenSubdiv itself (Far, uniform refinement, positions in double) on
//! OpenSubdiv's 87 Catmark regression shapes (`../shared/osd_shapes/`), each with the options
//! its regression drivers give it (`shapes.json`: boundary interpolation, creasing method,
//! triangle rule).
//!
//! The reference is `tests/opensubdiv/osd_refine.cpp`, compiled here against Debian's
//! `libosd-dev`. Where the shapes or OpenSubdiv are absent the test says so and passes; where
//! OpenSubdiv's headers are installed it must build.
//!
//! lsubdiv's uniform binary scheme is Catmull–Clark's but at smooth extraordinary vertices,
//! where [G] §3's rule picks another α. The driver taints every vertex that depends on such a
//! vertex's child (OpenSubdiv's own stencils, by the absolute values of their weights); every
//! other vertex OpenSubdiv makes must be one lsubdiv makes, to 1e-9 of the shape's size, and the
//! vertex and face counts must be OpenSubdiv's (less the hole faces and the vertices only they
//! use, which lsubdiv does not write). Shapes with Chaikin's creasing must be refused with its
//! reason.
//!
//! Texture coordinates likewise, in each of OpenSubdiv's six face-varying modes (`--uv`'s six
//! rules) on every shape that has them, at level 2: every untainted face corner of OpenSubdiv's
//! (position and value) must be one of lsubdiv's. The driver also taints the values of a
//! vertex whose values OpenSubdiv 3.5 miscounts (faces running A, B, A, B: see the driver).

mod common;

use common::cli::{lsubdiv, stderr};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The shapes, if they are there.
fn shapes() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/osd_shapes");
    if dir.join("shapes.json").is_file() {
        Some(dir)
    } else {
        eprintln!(
            "note: {} absent: OpenSubdiv comparison skipped",
            dir.display()
        );
        None
    }
}

/// The reference driver, compiled into `dir`, if OpenSubdiv's headers are installed.
fn driver(dir: &Path) -> Option<PathBuf> {
    let header = "opensubdiv/far/topologyRefinerFactory.h";
    let found = ["/usr/include", "/usr/local/include"]
        .iter()
        .any(|d| Path::new(d).join(header).is_file());
    if !found {
        eprintln!("note: OpenSubdiv's headers ({header}) absent: install libosd-dev to compare");
        return None;
    }
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/opensubdiv/osd_refine.cpp");
    let exe = dir.join("osd_refine");
    let out = Command::new("c++")
        .args(["-O1", "-std=c++14"])
        .arg(&source)
        .arg("-o")
        .arg(&exe)
        .arg("-losdCPU")
        .output()
        .expect("runs c++");
    assert!(
        out.status.success(),
        "OpenSubdiv is installed but the driver does not build: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

/// A refined mesh: positions and texture coordinates, each with a taint (OpenSubdiv's; 0 for
/// lsubdiv's), and faces, each corner a position and a texture coordinate (if any).
struct Mesh {
    points: Vec<([f64; 3], f64)>,
    uvs: Vec<([f64; 2], f64)>,
    faces: Vec<Vec<(usize, Option<usize>)>>,
}

/// Reads `v x y z [taint]`, `vt u v [taint]` and `f a[/t] …` lines (OBJ's 1-based indices when
/// `one_based`).
fn parse(text: &str, one_based: bool) -> Mesh {
    let mut m = Mesh {
        points: Vec::new(),
        uvs: Vec::new(),
        faces: Vec::new(),
    };
    let index = |s: &str| s.parse::<usize>().unwrap() - usize::from(one_based);
    for line in text.lines() {
        let mut t = line.split_ascii_whitespace();
        let tag = t.next();
        let x = |t: std::str::SplitAsciiWhitespace<'_>| -> Vec<f64> {
            t.map(|s| s.parse().unwrap()).collect()
        };
        match tag {
            Some("v") => {
                let x = x(t);
                m.points
                    .push(([x[0], x[1], x[2]], x.get(3).copied().unwrap_or(0.0)));
            }
            Some("vt") => {
                let x = x(t);
                m.uvs.push(([x[0], x[1]], x.get(2).copied().unwrap_or(0.0)));
            }
            Some("f") => m.faces.push(
                t.map(|s| {
                    let mut parts = s.split('/');
                    let v = index(parts.next().unwrap());
                    (v, parts.next().filter(|t| !t.is_empty()).map(index))
                })
                .collect(),
            ),
            _ => {}
        }
    }
    m
}

/// The largest extent of `points` along an axis (at least 1e-300).
fn size<const N: usize>(points: impl Iterator<Item = [f64; N]>) -> f64 {
    let (lo, hi) = points.fold(([f64::MAX; N], [f64::MIN; N]), |(lo, hi), p| {
        (
            std::array::from_fn(|i| lo[i].min(p[i])),
            std::array::from_fn(|i| hi[i].max(p[i])),
        )
    });
    (0..N)
        .map(|i| hi[i] - lo[i])
        .fold(0.0, f64::max)
        .max(1e-300)
}

/// Shapes where lsubdiv's vertex count is known to differ from OpenSubdiv's, and why: every
/// untainted point of OpenSubdiv's must still be one of lsubdiv's.
const GLUED: &[(&str, &str)] = &[(
    "catmark_nonman_edges",
    "two degenerate edges of one vertex, in faces whose fans meet, are two edges in Vtr and one \
     edge of the separated mesh in lsubdiv (docs/real-meshes.md): one edge point fewer",
)];

/// What differs between OpenSubdiv's refinement and lsubdiv's, or `None`.
/// With `glued` ([`GLUED`]) the counts are not compared.
fn compare(osd: &Mesh, ours: &Mesh, glued: bool) -> Option<String> {
    let mut used = vec![false; osd.points.len()];
    for f in &osd.faces {
        for &(v, _) in f {
            used[v] = true;
        }
    }
    let live = used.iter().filter(|&&u| u).count();
    if !glued && (live != ours.points.len() || osd.faces.len() != ours.faces.len()) {
        return Some(format!(
            "{live} vertices and {} faces in OpenSubdiv's, {} and {} in lsubdiv's",
            osd.faces.len(),
            ours.points.len(),
            ours.faces.len()
        ));
    }
    let tol = 1e-9 * size(osd.points.iter().map(|p| p.0));
    let mut sorted: Vec<[f64; 3]> = ours.points.iter().map(|p| p.0).collect();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut missing = Vec::new();
    let mut tainted = 0;
    for (v, (p, taint)) in osd.points.iter().enumerate().filter(|(v, _)| used[*v]) {
        if *taint > 0.0 {
            tainted += 1;
            continue;
        }
        let from = sorted.partition_point(|q| q[0] < p[0] - tol);
        let found = sorted[from..]
            .iter()
            .take_while(|q| q[0] <= p[0] + tol)
            .any(|q| (0..3).all(|i| (q[i] - p[i]).abs() <= tol));
        if !found {
            missing.push((v, *p));
        }
    }
    (!missing.is_empty()).then(|| {
        format!(
            "{} of {} untainted vertices of OpenSubdiv's not in lsubdiv's ({tainted} tainted), e.g. vertex {} at {:?}",
            missing.len(),
            live - tainted,
            missing[0].0,
            missing[0].1
        )
    })
}

/// What differs between OpenSubdiv's texture coordinates and lsubdiv's, or the numbers of
/// OpenSubdiv's face corners compared and in all: every face corner of OpenSubdiv's whose
/// position and value are untainted must be a corner of lsubdiv's at that position (1e-9 of
/// the shape's size) with that value (1e-9 of the layout's size).
fn compare_uv(osd: &Mesh, ours: &Mesh) -> Result<[usize; 2], String> {
    let tol = 1e-9 * size(osd.points.iter().map(|p| p.0));
    let uv_tol = 1e-9 * size(osd.uvs.iter().map(|p| p.0));
    let corners = |m: &Mesh| -> Vec<([f64; 3], [f64; 2], bool)> {
        let corners = m.faces.iter().flatten();
        corners
            .map(|&(v, t)| {
                let (p, pt) = m.points[v];
                let (uv, ut) = m.uvs[t.expect("a texture coordinate")];
                (p, uv, pt > 0.0 || ut > 0.0)
            })
            .collect()
    };
    let mut mine = corners(ours);
    mine.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    let theirs = corners(osd);
    let checked: Vec<_> = theirs.iter().filter(|c| !c.2).collect();
    let missing: Vec<_> = (checked.iter())
        .filter(|(p, uv, _)| {
            let from = mine.partition_point(|q| q.0[0] < p[0] - tol);
            !mine[from..]
                .iter()
                .take_while(|q| q.0[0] <= p[0] + tol)
                .any(|(q, w, _)| {
                    (0..3).all(|i| (q[i] - p[i]).abs() <= tol)
                        && (0..2).all(|i| (w[i] - uv[i]).abs() <= uv_tol)
                })
        })
        .collect();
    if missing.is_empty() {
        return Ok([checked.len(), theirs.len()]);
    }
    Err(format!(
        "{} of {} untainted corners of OpenSubdiv's not in lsubdiv's ({} tainted), e.g. at \
         {:?} with {:?}",
        missing.len(),
        checked.len(),
        theirs.len() - checked.len(),
        missing[0].0,
        missing[0].1
    ))
}

/// The shapes (name, path, options boundary, crease, triangle rule) and a directory with the
/// reference driver, or `None` (said why) where either is absent.
#[allow(clippy::type_complexity)]
fn setup() -> Option<(
    Vec<(String, String, [String; 3])>,
    tempfile::TempDir,
    PathBuf,
)> {
    let dir = shapes()?;
    let tmp = tempfile::tempdir().unwrap();
    let osd = driver(tmp.path())?;
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("shapes.json")).unwrap()).unwrap();
    let list = (json["shapes"].as_object().unwrap().iter())
        .map(|(name, shape)| {
            let option = |k: &str| shape["options"][k].as_str().unwrap().to_string();
            let obj = dir.join(format!("{name}.obj"));
            let options = [option("boundary"), option("crease"), option("tri")];
            (name.clone(), obj.to_str().unwrap().to_string(), options)
        })
        .collect();
    Some((list, tmp, osd))
}

/// OpenSubdiv's refinement of `obj` (`fvar`: with its texture coordinates in that mode).
fn reference(osd: &Path, obj: &str, level: usize, options: &[String; 3], fvar: &[&str]) -> Mesh {
    let reference = Command::new(osd)
        .arg(obj)
        .arg(level.to_string())
        .args(options)
        .args(fvar)
        .output()
        .unwrap();
    assert!(reference.status.success(), "{obj}: {}", stderr(&reference));
    parse(&String::from_utf8(reference.stdout).unwrap(), false)
}

/// `lsubdiv subdivide uniform-binary` of `obj`, `level` steps, to `out`, with `extra`.
fn uniform_binary(
    obj: &str,
    level: usize,
    boundary: &str,
    out: &Path,
    extra: &[&str],
) -> std::process::Output {
    let level = level.to_string();
    let mut args = vec!["subdivide", "uniform-binary", "--steps", &level, obj];
    args.extend(["-o", out.to_str().unwrap(), "--boundary", boundary]);
    args.extend(extra);
    lsubdiv(&args)
}

#[test]
fn uniform_binary_equals_opensubdiv_on_its_regression_shapes() {
    let Some((shapes, tmp, osd)) = setup() else {
        return;
    };
    let mut failures = Vec::new();
    let mut compared = 0;
    for (name, obj, options) in &shapes {
        let [boundary, _, _] = options;
        let out = tmp.path().join("out.obj");
        for level in 1..=2 {
            let ours = uniform_binary(obj, level, boundary, &out, &[]);
            if !ours.status.success() {
                failures.push(format!("{name} level {level}: refused: {}", stderr(&ours)));
                break;
            }
            let osd_mesh = reference(&osd, obj, level, options, &[]);
            let our_mesh = parse(&std::fs::read_to_string(&out).unwrap(), true);
            compared += 1;
            let glued = GLUED.iter().any(|g| g.0 == name);
            if let Some(why) = compare(&osd_mesh, &our_mesh, glued) {
                failures.push(format!("{name} level {level}: {why}"));
            }
        }
    }
    eprintln!("compared {compared} refinements with OpenSubdiv's");
    assert!(
        failures.is_empty(),
        "{} of the shapes differ from OpenSubdiv:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Chaikin creasing through a polygon mesh's first step (a Catmull–Clark step of its own,
/// `runtime::polygon`) and the steps after it, one level at a time: OpenSubdiv's Chaikin shape
/// with its first quad cut into two triangles, against OpenSubdiv.
#[test]
fn chaikin_creasing_after_a_polygon_step_equals_opensubdiv() {
    let Some((shapes, tmp, osd)) = setup() else {
        return;
    };
    let (_, obj, options) = (shapes.iter())
        .find(|s| s.0 == "catmark_chaikin1")
        .expect("OpenSubdiv's Chaikin shape");
    let text = std::fs::read_to_string(obj).unwrap();
    let quad = text.lines().find(|l| l.starts_with("f ")).unwrap();
    let [a, b, c, d] =
        <[&str; 4]>::try_from(quad.split_whitespace().skip(1).collect::<Vec<_>>()).expect("a quad");
    let triangles = text.replacen(quad, &format!("f {a} {b} {c}\nf {a} {c} {d}"), 1);
    let obj = tmp.path().join("triangles.obj");
    std::fs::write(&obj, triangles).unwrap();
    let obj = obj.to_str().unwrap();
    let out = tmp.path().join("out.obj");
    for level in 1..=3 {
        let ours = uniform_binary(obj, level, &options[0], &out, &[]);
        assert!(ours.status.success(), "{}", stderr(&ours));
        let osd_mesh = reference(&osd, obj, level, options, &[]);
        let our_mesh = parse(&std::fs::read_to_string(&out).unwrap(), true);
        if let Some(why) = compare(&osd_mesh, &our_mesh, false) {
            panic!("level {level}: {why}");
        }
    }
}

/// Chaikin's rule transitions: at a vertex of semi-sharp edges 1.2 and 0.4 (and 3 beyond)
/// both children are smooth under Chaikin, so the crease turns smooth with weight
/// (1.2 + 0.4)/2 (uniform creasing: 0.4 alone, the 1.2 edge's child still sharp). On a 4 × 4
/// grid, and with a quad cut into triangles (the polygon step's transitions), levels 1–3.
#[test]
fn chaikin_rule_transitions_equal_opensubdiv() {
    let Some((_, tmp, osd)) = setup() else {
        return;
    };
    let n = 4;
    let id = |i: usize, j: usize| i * (n + 1) + j;
    let mut text = String::new();
    for i in 0..=n {
        for j in 0..=n {
            text += &format!("v {j} {i} {}\n", 0.15 * ((i * 7 + j * 3) % 5) as f64);
        }
    }
    let quads: Vec<[usize; 4]> = (0..n * n)
        .map(|q| (q / n, q % n))
        .map(|(i, j)| [id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)])
        .collect();
    let face = |f: &[usize]| {
        f.iter()
            .fold("f".to_string(), |s, v| s + &format!(" {}", v + 1))
    };
    let (v, east, north) = (id(2, 2), id(2, 3), id(1, 2));
    let tags = format!(
        "t crease 2/1/0 {v} {east} 1.2\nt crease 2/1/0 {v} {north} 0.4\n\
         t crease 2/1/0 {east} {} 3\nt creasemethod 0/0/1 chaikin\n",
        id(2, 4)
    );
    let all: Vec<String> = quads.iter().map(|q| face(q)).collect();
    let [a, b, c, d] = quads[0];
    let cut = [face(&[a, b, c]), face(&[a, c, d])];
    let meshes = [
        ("grid", all.join("\n")),
        (
            "cut",
            all[1..]
                .iter()
                .chain(&cut)
                .cloned()
                .collect::<Vec<_>>()
                .join("\n"),
        ),
    ];
    let out = tmp.path().join("out.obj");
    let options = ["edge-and-corner", "chaikin", "catmark"].map(String::from);
    for (name, faces) in meshes {
        let obj = tmp.path().join(format!("{name}.obj"));
        std::fs::write(&obj, format!("{text}{faces}\n{tags}")).unwrap();
        let obj = obj.to_str().unwrap();
        for level in 1..=3 {
            let ours = uniform_binary(obj, level, &options[0], &out, &[]);
            assert!(ours.status.success(), "{}", stderr(&ours));
            let osd_mesh = reference(&osd, obj, level, &options, &[]);
            let our_mesh = parse(&std::fs::read_to_string(&out).unwrap(), true);
            if let Some(why) = compare(&osd_mesh, &our_mesh, false) {
                panic!("{name}, level {level}: {why}");
            }
        }
    }
}

/// OpenSubdiv's face-varying modes and `--uv`'s names for them.
const MODES: &[(&str, &str)] = &[
    ("none", "smooth"),
    ("corners-only", "corners-only"),
    ("corners-plus1", "corners-plus1"),
    ("corners-plus2", "corners-plus2"),
    ("boundaries", "boundaries"),
    ("all", "linear"),
];

#[test]
fn texture_coordinates_equal_opensubdiv_in_every_face_varying_mode() {
    let Some((shapes, tmp, osd)) = setup() else {
        return;
    };
    let mut failures = Vec::new();
    let mut compared = 0;
    let mut corners = [0; 2];
    let level = 2;
    for (name, obj, options) in &shapes {
        let [boundary, _, _] = options;
        let text = std::fs::read_to_string(obj).unwrap();
        if !text.lines().any(|l| l.starts_with("vt ")) {
            continue;
        }
        let out = tmp.path().join("out.obj");
        for (fvar, uv) in MODES {
            let ours = uniform_binary(obj, level, boundary, &out, &["--uv", uv]);
            if !ours.status.success() {
                failures.push(format!("{name} {uv}: refused: {}", stderr(&ours)));
                continue;
            }
            let osd_mesh = reference(&osd, obj, level, options, &[fvar]);
            let our_mesh = parse(&std::fs::read_to_string(&out).unwrap(), true);
            compared += 1;
            match compare_uv(&osd_mesh, &our_mesh) {
                Ok([checked, all]) => corners = [corners[0] + checked, corners[1] + all],
                Err(why) => failures.push(format!("{name} {uv}: {why}")),
            }
        }
    }
    eprintln!(
        "compared {compared} texture refinements with OpenSubdiv's: {} of {} face corners \
         untainted",
        corners[0], corners[1]
    );
    // Taint is the exception: most of OpenSubdiv's corners are compared (81 % on 3.5's shapes).
    assert!(
        !failures.is_empty() || 4 * corners[0] >= 3 * corners[1],
        "only {} of {} corners compared",
        corners[0],
        corners[1]
    );
    assert!(
        failures.is_empty(),
        "{} refinements differ from OpenSubdiv's:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A 5 × 5 grid whose texture has a seam along the column x = 2 (its values there moved
/// right on the right side, along a curve) and a crease of sharpness 2.5 along the row y = 2 that ends at
/// the seam: at its end the left value's faces meet at a semi-sharp edge and the right
/// value's do not, OpenSubdiv's dependent sharpness (corners-plus1, corners-plus2). Every
/// mode at level 3 against OpenSubdiv's.
#[test]
fn a_crease_ending_at_a_seam_equals_opensubdiv_in_every_mode() {
    let tmp = tempfile::tempdir().unwrap();
    let Some(osd) = driver(tmp.path()) else {
        return;
    };
    let n = 5;
    let mut obj = String::new();
    for y in 0..=n {
        for x in 0..=n {
            obj += &format!("v {x} {y} {}\n", 0.15 * ((x * x + 2 * y) % 3) as f64);
        }
    }
    // One value per (vertex, side of the seam), numbered as first used.
    let mut values: Vec<(usize, usize, bool)> = Vec::new();
    let mut value = |x: usize, y: usize, right: bool| {
        let key = (x, y, right && x == 2);
        let at = values.iter().position(|k| *k == key).unwrap_or_else(|| {
            values.push(key);
            values.len() - 1
        });
        at + 1
    };
    let mut faces = String::new();
    for y in 0..n {
        for x in 0..n {
            let corners = [(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)];
            faces += "f";
            for (cx, cy) in corners {
                faces += &format!(" {}/{}", 1 + cx + (n + 1) * cy, value(cx, cy, x >= 2));
            }
            faces += "\n";
        }
    }
    for &(x, y, moved) in &values {
        // The right side's seam values on a curve (a crease rule moves them, a corner not).
        let shift = if moved {
            0.05 + 0.01 * (y * y) as f64
        } else {
            0.0
        };
        obj += &format!(
            "vt {} {}\n",
            x as f64 / 5.0 + shift,
            (y as f64 + 0.05 * (x * y) as f64) / 5.0
        );
    }
    obj += &faces;
    obj += &format!(
        "t crease 4/1/0 {} {} {} {} 2.5\n",
        2 * (n + 1),
        2 * (n + 1) + 1,
        2 * (n + 1) + 1,
        2 * (n + 1) + 2
    );
    let input = tmp.path().join("seam.obj");
    std::fs::write(&input, obj).unwrap();
    let input = input.to_str().unwrap();
    let out = tmp.path().join("out.obj");
    let options = ["edge-only", "uniform", "catmark"].map(String::from);
    for (fvar, uv) in MODES {
        let ours = uniform_binary(input, 3, "edge-only", &out, &["--uv", uv]);
        assert!(ours.status.success(), "{uv}: {}", stderr(&ours));
        let osd_mesh = reference(&osd, input, 3, &options, &[fvar]);
        let our_mesh = parse(&std::fs::read_to_string(&out).unwrap(), true);
        let [checked, all] =
            compare_uv(&osd_mesh, &our_mesh).unwrap_or_else(|e| panic!("{uv}: {e}"));
        assert_eq!(
            checked, all,
            "{uv}: no extraordinary vertex, nothing tainted"
        );
    }
}
