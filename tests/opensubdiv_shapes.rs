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

/// A refined mesh: positions, each with a taint (OpenSubdiv's; 0 for lsubdiv's), and faces.
struct Mesh {
    points: Vec<([f64; 3], f64)>,
    faces: Vec<Vec<usize>>,
}

/// Reads `v x y z [taint]` and `f a b c …` lines (OBJ's 1-based indices when `one_based`).
fn parse(text: &str, one_based: bool) -> Mesh {
    let mut m = Mesh {
        points: Vec::new(),
        faces: Vec::new(),
    };
    for line in text.lines() {
        let mut t = line.split_ascii_whitespace();
        match t.next() {
            Some("v") => {
                let x: Vec<f64> = t.map(|s| s.parse().unwrap()).collect();
                m.points
                    .push(([x[0], x[1], x[2]], x.get(3).copied().unwrap_or(0.0)));
            }
            Some("f") => m.faces.push(
                t.map(|s| {
                    let i: usize = s.split('/').next().unwrap().parse().unwrap();
                    i - usize::from(one_based)
                })
                .collect(),
            ),
            _ => {}
        }
    }
    m
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
        for &v in f {
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
    let (lo, hi) = osd
        .points
        .iter()
        .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), (p, _)| {
            (
                std::array::from_fn(|i| lo[i].min(p[i])),
                std::array::from_fn(|i| hi[i].max(p[i])),
            )
        });
    let size = (0..3)
        .map(|i| hi[i] - lo[i])
        .fold(0.0, f64::max)
        .max(1e-300);
    let tol = 1e-9 * size;
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

#[test]
fn uniform_binary_equals_opensubdiv_on_its_regression_shapes() {
    let Some(dir) = shapes() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let Some(osd) = driver(tmp.path()) else {
        return;
    };
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("shapes.json")).unwrap()).unwrap();
    let mut failures = Vec::new();
    let mut compared = 0;
    for (name, shape) in json["shapes"].as_object().unwrap() {
        let opt = &shape["options"];
        let option = |k: &str| opt[k].as_str().unwrap().to_string();
        let (boundary, crease, tri) = (option("boundary"), option("crease"), option("tri"));
        let obj = dir.join(format!("{name}.obj"));
        let obj = obj.to_str().unwrap();
        let out = tmp.path().join("out.obj");
        for level in 1..=2 {
            let reference = Command::new(&osd)
                .args([obj, &level.to_string(), &boundary, &crease, &tri])
                .output()
                .unwrap();
            assert!(reference.status.success(), "{name}: {}", stderr(&reference));
            let ours = lsubdiv(&[
                "subdivide",
                "uniform-binary",
                "--steps",
                &level.to_string(),
                obj,
                "-o",
                out.to_str().unwrap(),
                "--boundary",
                &boundary,
            ]);
            if !ours.status.success() {
                // Chaikin's creasing is refused, with its reason (docs/real-meshes.md).
                let chaikin = crease == "chaikin"
                    && stderr(&ours).contains("Chaikin creasing is not supported");
                if !chaikin {
                    failures.push(format!("{name} level {level}: refused: {}", stderr(&ours)));
                }
                break;
            }
            assert_ne!(crease, "chaikin", "{name}: Chaikin creasing is refused");
            let osd_mesh = parse(&String::from_utf8(reference.stdout).unwrap(), false);
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
