//! The command line as a user runs it: JSON shape, errors with places and exit status 2,
//! point files in and out, DOT and codegen outputs.

mod common;

use common::cli::{json, lsubdiv, stderr, write};
use std::path::Path;
use std::process::{Command, Output};

#[test]
fn inspect_json_has_the_documented_fields() {
    let v = json(&["inspect", "fibonacci", "--json"]);
    assert_eq!(v["valid"], true);
    assert!(v["reason"].is_null());
    assert!((v["rho"].as_f64().unwrap() - 1.618033988749895).abs() < 1e-15);
    assert_eq!(v["minimal_polynomial"], serde_json::json!([-1, -1, 1]));
    assert_eq!(v["lengths"]["S"]["exact"], "2");
    assert_eq!(v["lengths"]["L"]["exact"], "(1 + √5)/2");
    let masks = v["masks"].as_array().unwrap();
    assert_eq!(masks.len(), 20);
    let ssss = masks.iter().find(|m| m["word"] == "SSSS").unwrap();
    assert_eq!(ssss["transitional"], true);
    let c = ssss["contributions"].as_array().unwrap();
    assert_eq!(c.len(), 5);
    assert_eq!(c[2]["word"], "LRLR");
    assert_eq!(c[2]["exact"], "3/4");
    assert_eq!(c[2]["weight"], 0.75);
    assert_eq!(c[2]["child"], true);
    assert_eq!(c[1]["child"], false);
    // [G] §3.2.2 / §4.2: stationary from the fourth step (our step 3), contained from the first.
    let s = &v["surface"];
    assert_eq!(s["ready"], true);
    assert_eq!(
        (s["stationary_from"].as_u64(), s["contained_from"].as_u64()),
        (Some(3), Some(0))
    );
    assert_eq!(s["sigma"]["L"], "R");
    assert_eq!(s["sigma"]["C"], "D");
    let o = lsubdiv(&["inspect", "fibonacci-curve", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["surface"]["ready"], false);
    assert!(v["surface"]["reason"]
        .as_str()
        .unwrap()
        .contains("degree 3"));
}

#[test]
fn inspect_with_degree_override() {
    let o = lsubdiv(&["inspect", "uniform-binary", "--degree", "2", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let w: Vec<&str> = v["masks"][0]["contributions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["exact"].as_str().unwrap())
        .collect();
    assert_eq!(w, ["1/4", "3/4", "3/4", "1/4"]);
}

#[test]
fn invalid_lsystem_reports_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        dir.path(),
        "swap.toml",
        "name = \"swap\"\ndegree = 3\naxiom = \"A1\"\n[rules]\nA1 = \"A2\"\nA2 = \"A1\"\n",
    );
    let o = lsubdiv(&["inspect", &f, "--json"]);
    assert_eq!(o.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["valid"], false);
    assert!(v["reason"].as_str().unwrap().contains("not greater than 1"));
    assert!(stderr(&o).contains("swap.toml"), "{}", stderr(&o));
    let o = lsubdiv(&[
        "codegen",
        &f,
        "-o",
        &dir.path().join("x.rs").display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.path().join("x.rs").exists(), "no output on failure");
}

#[test]
fn unknown_scheme_name_exits_2() {
    let o = lsubdiv(&["inspect", "no-such-scheme"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("fibonacci"),
        "lists the shipped schemes: {}",
        stderr(&o)
    );
}

#[test]
fn curve_reads_and_writes_point_files() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "in.txt", "# a square\n0 0\n1 0\n\n1 1\n0 1\n");
    let out = dir.path().join("out.txt").display().to_string();
    for path in ["generated", "generic"] {
        let o = lsubdiv(&[
            "curve",
            "binary-ternary",
            "--steps",
            "2",
            "--closed",
            "--path",
            path,
            &input,
            "-o",
            &out,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read_to_string(&out).unwrap();
        // 4 intervals labelled C: π²(C) = LCLCRCR has 7 symbols, so 28 closed points.
        assert_eq!(text.lines().count(), 28);
        for line in text.lines() {
            let xs: Vec<f64> = line.split(' ').map(|t| t.parse().unwrap()).collect();
            assert_eq!(xs.len(), 2);
        }
    }
    let o = lsubdiv(&[
        "curve",
        "fibonacci-curve",
        "--steps",
        "3",
        "--labels",
        "SSLSSL",
        &input,
        "-o",
        &out,
    ]);
    assert!(
        o.status.success(),
        "labels outside the tables go generic: {}",
        stderr(&o)
    );
}

#[test]
fn curve_rejects_bad_points_and_labels() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.txt");
    let out_s = out.display().to_string();
    std::fs::write(&out, "previous\n").unwrap();
    let bad = write(dir.path(), "bad.txt", "0 0\n1 x\n");
    let o = lsubdiv(&["curve", "fibonacci", "--steps", "1", &bad, "-o", &out_s]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bad.txt:2:3: error: `x` is not a number"),
        "{}",
        stderr(&o)
    );
    let mixed = write(dir.path(), "mixed.txt", "0 0\n1 1 1\n");
    let o = lsubdiv(&["curve", "fibonacci", "--steps", "1", &mixed, "-o", &out_s]);
    assert!(stderr(&o).contains("mixed.txt:2"), "{}", stderr(&o));
    let ok = write(dir.path(), "ok.txt", "0 0\n1 0\n1 1\n0 1\n");
    for (labels, expect) in [
        ("SSZ", "unknown symbol `Z`"),
        ("SS", "2 interval labels given, 7 needed"),
    ] {
        let o = lsubdiv(&[
            "curve",
            "fibonacci",
            "--steps",
            "1",
            "--labels",
            labels,
            &ok,
            "-o",
            &out_s,
        ]);
        assert_eq!(o.status.code(), Some(2));
        assert!(stderr(&o).contains(expect), "{}", stderr(&o));
    }
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "previous\n",
        "failed runs leave the output intact"
    );
}

#[test]
fn graph_dot_and_codegen() {
    let o = lsubdiv(&["graph", "fibonacci", "--dot"]);
    assert!(o.status.success());
    let dot = String::from_utf8(o.stdout).unwrap();
    assert!(dot.starts_with("digraph \"fibonacci\""));
    assert_eq!(
        dot.matches("style=dashed").count(),
        7,
        "7 transitional words"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fib.rs");
    let o = lsubdiv(&["codegen", "fibonacci", "-o", &out.display().to_string()]);
    assert!(o.status.success());
    let src = std::fs::read_to_string(out).unwrap();
    assert!(src.starts_with("// @generated"));
    assert!(src.contains("impl lsubdiv_runtime::CurveScheme for Scheme"));
}

#[test]
fn default_job_prints_a_short_summary() {
    let o = lsubdiv(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(out.matches("agree bit for bit").count(), 2, "{out}");
    assert!(out.contains("every weight exact in Q(√5)"), "{out}");
    assert!(out.contains("what to try next:"), "{out}");
    assert!(out.lines().count() <= 20, "{out}");
}

const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nvn 0 0 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

#[test]
fn subdivide_writes_obj_and_ply() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "cube.obj", CUBE);
    let obj = dir.path().join("out.obj").display().to_string();
    let o = lsubdiv(&[
        "subdivide",
        "binary-ternary",
        "--steps",
        "2",
        &input,
        "-o",
        &obj,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning"),
        "the skipped vn line is reported: {}",
        stderr(&o)
    );
    let text = std::fs::read_to_string(&obj).unwrap();
    // |π²(C)| = 7 sub-edges per edge: 6·49 faces, 6·49 + 2 vertices.
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 294);
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 296);
    let ply = dir.path().join("out.ply").display().to_string();
    let o = lsubdiv(&[
        "subdivide",
        "fibonacci",
        "--steps",
        "3",
        "--path",
        "generic",
        &input,
        "-o",
        &ply,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&ply)
        .unwrap()
        .starts_with("ply\nformat ascii 1.0"));
}

#[test]
fn ev_json_per_valence() {
    let v = json(&["ev", "binary-ternary", "--valence", "3..25", "--json"]);
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), 23);
    assert_eq!(rows[0]["n"], 3);
    for key in ["alpha", "lambda1", "lambda2", "mu0", "normalisation"] {
        assert!(rows[0][key].is_f64(), "{key}");
    }
    assert!(
        (rows[1]["normalisation"].as_f64().unwrap() - 1.0).abs() < 1e-12,
        "n = 4"
    );
    let o = lsubdiv(&["ev", "binary-ternary", "--valence", "1..5"]);
    assert_eq!(o.status.code(), Some(2));
    // Valence 2: OpenSubdiv's weight on the vertex, said so.
    let o = lsubdiv(&["ev", "uniform-binary", "--valence", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("valence 2: no alpha gives mu0"), "{text}");
    let row = json(&["ev", "uniform-binary", "--valence", "2", "--json"]);
    // Catmull-Clark at valence 2: alpha / normalisation = 1/8, alpha = 1/32.
    assert!((row[0]["alpha"].as_f64().unwrap() - 1.0 / 32.0).abs() < 1e-15);
}

#[test]
fn enumerate_json_has_the_documented_columns() {
    let v = json(&["enumerate", "--family", "slcdr", "--json"]);
    let rows = v.as_array().unwrap();
    let drl = rows.iter().find(|r| r["pi_c"] == "DRL").unwrap();
    for key in [
        "family",
        "pi_c",
        "rho",
        "minimal_polynomial",
        "masks",
        "words",
        "valid",
        "symmetric",
        "surface_ready",
    ] {
        assert!(!drl[key].is_null(), "{key}");
    }
    assert_eq!(drl["masks"], 7);
    assert_eq!(drl["minimal_polynomial"], serde_json::json!([-1, -2, 1]));
    assert_eq!(drl["surface_ready"], true);
    // Sorted by ρ: the golden-ratio rows first.
    assert!(rows[0]["rho"].as_f64().unwrap() < 1.62);
}

#[test]
fn enumerate_csv_and_bad_family() {
    let o = lsubdiv(&["enumerate", "--family", "lcr", "--csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(text.starts_with("family,pi_c,"), "{text}");
    assert_eq!(text.lines().count(), 2, "{text}");
    let o = lsubdiv(&["enumerate", "--family", "xyz"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--family xyz"), "{}", stderr(&o));
}

/// `lsubdiv search` on three letters and rules of up to two (exhaustive, fast), plus `extra`.
fn small_search(extra: &[&str]) -> Output {
    let mut args = vec!["search", "--symbols", "3", "--max-word-len", "2"];
    args.extend_from_slice(extra);
    lsubdiv(&args)
}

#[test]
fn search_emits_scheme_files_the_toolkit_accepts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("found");
    let o = small_search(&["--json", "--emit-scheme", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let n = v.as_array().unwrap().len();
    let files: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert_eq!(files.len(), n);
    for f in files {
        let p = f.unwrap().path();
        let o = lsubdiv(&["inspect", p.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", p.display(), stderr(&o));
    }
    let o = lsubdiv(&["search", "--symbols", "9", "--max-word-len", "2"]);
    assert_eq!(o.status.code(), Some(2));
    let o = small_search(&["--rho-min", "1.x"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--rho-min `1.x`"), "{}", stderr(&o));
}

#[test]
fn bench_json_has_the_documented_fields() {
    // A 16×16 torus, 2 steps of uniform binary: every face becomes 4 × 4, so V + E·3 + F·9
    // = 256 + 512·3 + 256·9 = 4096 output vertices; both steps run depth first.
    let v = json(&[
        "bench",
        "--json",
        "--mesh",
        "torus:16:16",
        "--scheme",
        "uniform-binary",
        "--steps",
        "2",
        "--threads",
        "2",
        "--runs",
        "1",
    ]);
    for key in [
        "mesh",
        "scheme",
        "path",
        "threads",
        "steps",
        "median_seconds",
        "setup_seconds",
        "mvps",
    ] {
        assert!(!v[key].is_null(), "{key} missing");
    }
    assert_eq!(v["output_vertices"], 4096);
    assert_eq!(v["threads"], 2);
    assert!(v["peak_rss_bytes"].as_u64().unwrap() > 0);
    assert!(v["file_rss_bytes"].as_u64().unwrap() <= v["peak_rss_bytes"].as_u64().unwrap());
    let levels = v["level_seconds"].as_array().unwrap();
    assert_eq!(levels.len(), 2);
    assert!(levels.iter().all(|t| t.as_f64().unwrap() >= 0.0));
    for phase in ["start", "ordinary", "fans"] {
        assert!(v["phase_seconds"][phase].as_f64().unwrap() >= 0.0);
    }
    assert!(["avx512", "avx2", "baseline"].contains(&v["simd"].as_str().unwrap()));
    // `--simd` picks the kernels' instruction set, and the JSON says which ran.
    let v = json(&[
        "bench",
        "--json",
        "--mesh",
        "torus:8:8",
        "--runs",
        "1",
        "--simd",
        "baseline",
    ]);
    assert_eq!(v["simd"], "baseline");
    // Without `--json`, one summary line naming the same run.
    let o = lsubdiv(&[
        "bench",
        "--mesh",
        "torus:8:8",
        "--steps",
        "1",
        "--runs",
        "1",
        "--simd",
        "baseline",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let line = String::from_utf8(o.stdout).unwrap();
    assert_eq!(line.lines().count(), 1, "{line}");
    assert!(
        line.starts_with("torus:8:8, uniform-binary, 1 step (generated path, f64, baseline, 1 thread): 256 output vertices in ")
            && line.contains(" M vertices/s (median of 1)"),
        "{line}"
    );
}

/// Long runs show their stages on a terminal (here a pseudo-terminal made by `script`, from
/// util-linux) and nothing when stderr is a pipe.
#[test]
fn progress_shows_on_a_terminal_only() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "cube.obj", CUBE);
    let out = dir.path().join("out.obj").display().to_string();
    let args = [
        "subdivide",
        "binary-ternary",
        "--steps",
        "3",
        &input,
        "-o",
        &out,
    ];
    let o = lsubdiv(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        !e.contains("refining") && !e.contains('\x1b'),
        "no progress on a pipe: {e}"
    );
    let script = Path::new("/usr/bin/script");
    if !script.exists() {
        eprintln!("no /usr/bin/script: the terminal half of this test did not run");
        return;
    }
    let command = std::iter::once(env!("CARGO_BIN_EXE_lsubdiv"))
        .chain(args)
        .collect::<Vec<_>>()
        .join(" ");
    let o = Command::new(script)
        .args(["-qec", &command, "/dev/null"])
        .output()
        .expect("runs script");
    assert!(o.status.success(), "{}", stderr(&o));
    let shown = String::from_utf8_lossy(&o.stdout);
    for stage in ["reading", "refining: 3 steps of binary-ternary", "writing"] {
        assert!(shown.contains(stage), "{stage} missing from {shown:?}");
    }
}

/// Outputs that are not regular files are written, never renamed over: `-` is standard output
/// (no file named `-` appears), a full device fails with exit 2 and stays a device.
#[test]
fn special_outputs_are_written_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let pts = write(dir.path(), "p.txt", "0 0 0\n1 0 0\n1 1 0\n0 1 0\n");
    let o = Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
        .current_dir(dir.path())
        .args([
            "curve",
            "uniform-binary",
            "--steps",
            "1",
            "--closed",
            &pts,
            "-o",
            "-",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 8);
    assert!(!dir.path().join("-").exists());

    use std::os::unix::fs::FileTypeExt as _;
    let full = Path::new("/dev/full");
    if !fs_is_char_device(full) {
        return; // no /dev/full on this system
    }
    let o = lsubdiv(&[
        "curve",
        "uniform-binary",
        "--steps",
        "1",
        &pts,
        "-o",
        "/dev/full",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("/dev/full: error:"), "{}", stderr(&o));
    assert!(std::fs::metadata(full)
        .unwrap()
        .file_type()
        .is_char_device());
}

fn fs_is_char_device(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt as _;
    std::fs::metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

/// `subdivide` picks its output format by extension in any case, and refuses one it does not
/// write before refining (it used to write OBJ text under any name).
#[test]
fn subdivide_output_format_comes_from_the_extension() {
    let dir = tempfile::tempdir().unwrap();
    let cube = dir.path().join("cube.obj");
    lsubdiv::obj::write(&cube, &lsubdiv::mesh::generators::cube()).unwrap();
    let cube = cube.display().to_string();
    let ply = dir.path().join("fine.PLY");
    let o = lsubdiv(&[
        "subdivide",
        "uniform-binary",
        "--steps",
        "1",
        &cube,
        "-o",
        &ply.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&ply).unwrap().starts_with("ply\n"));
    let stl = dir.path().join("fine.stl");
    let o = lsubdiv(&[
        "subdivide",
        "uniform-binary",
        "--steps",
        "1",
        &cube,
        "-o",
        &stl.display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("unknown mesh format `.stl`; the file name must end in .obj or .ply"),
        "{}",
        stderr(&o)
    );
    assert!(!stl.exists());
}

/// A folder named like a shipped scheme does not hide it; `graph --dot` quotes any symbol name
/// (scheme files allow `"` and `\` in names) into well-formed DOT.
#[test]
fn a_folder_named_like_a_scheme_and_quoted_symbols() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("fibonacci")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
        .current_dir(dir.path())
        .args(["inspect", "fibonacci"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));

    let scheme = write(
        dir.path(),
        "q.toml",
        "name = \"q\"\ndegree = 1\naxiom = 'a\"'\n[rules]\n'a\"' = 'a\" b\\'\n'b\\' = 'a\"'\n",
    );
    let o = lsubdiv(&["graph", &scheme, "--dot"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let dot = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(dot.contains(r#"label="a\" b\\""#), "{dot}");
    // Every line's quotes pair up once escapes are taken out.
    for line in dot.lines() {
        let unescaped = line.replace(r"\\", "").replace(r#"\""#, "");
        assert_eq!(unescaped.matches('"').count() % 2, 0, "{line}");
    }
}

/// A byte-order mark hides nothing, a Latin-1 comment passes, and a number with a non-UTF-8
/// byte is refused at its line (OBJ and point files).
#[test]
fn byte_order_marks_and_latin1_bytes_in_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let pts = d.join("p.txt");
    std::fs::write(&pts, b"\xEF\xBB\xBF0 0\n# caf\xE9\n1 0\n1 1\n0 1\n").unwrap();
    let out = d.join("o.txt").display().to_string();
    let o = lsubdiv(&[
        "curve",
        "uniform-binary",
        "--steps",
        "1",
        "--closed",
        &pts.display().to_string(),
        "-o",
        &out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&out).unwrap().lines().count(), 8);

    let mut obj = b"\xEF\xBB\xBF# r\xE9sum\xE9\n".to_vec();
    obj.extend(
        lsubdiv::obj::format(&lsubdiv::mesh::generators::cube())
            .unwrap()
            .bytes(),
    );
    let cube = d.join("cube.obj");
    std::fs::write(&cube, &obj).unwrap();
    let fine = d.join("fine.obj").display().to_string();
    let o = lsubdiv(&[
        "subdivide",
        "uniform-binary",
        "--steps",
        "1",
        &cube.display().to_string(),
        "-o",
        &fine,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));

    std::fs::write(&pts, b"0 0\n1 0\n1 \xE9\n").unwrap();
    let o = lsubdiv(&[
        "curve",
        "uniform-binary",
        "--steps",
        "1",
        &pts.display().to_string(),
        "-o",
        &out,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("p.txt:3:"), "{}", stderr(&o));
}

/// Errors about the polygon a point file holds name the file.
#[test]
fn too_few_points_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let one = write(dir.path(), "one.txt", "0 0\n");
    let out = dir.path().join("o.txt").display().to_string();
    let o = lsubdiv(&["curve", "fibonacci", "--steps", "1", &one, "-o", &out]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("one.txt: error: 1 control points given, at least 4 needed"),
        "{}",
        stderr(&o)
    );
}

/// A thread count beyond any machine is refused as such, by every command that takes one.
#[test]
fn thread_counts_are_bounded() {
    for args in [
        vec![
            "subdivide",
            "fibonacci",
            "--steps",
            "1",
            "in.obj",
            "-o",
            "o.obj",
            "--threads",
            "100000",
        ],
        vec!["render", "cube", "-o", "o.png", "--threads", "0"],
        vec!["bench", "--mesh", "cube", "--threads", "100000"],
    ] {
        let o = lsubdiv(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&o).contains("expected 1 to 1024 worker threads"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// `-` is standard input for a scheme as for meshes and points: a pipe is read (bounded, as
/// every input) and its errors are placed in `/dev/stdin`.
#[test]
fn a_scheme_from_standard_input() {
    use std::io::Write;
    let run = |text: &str| {
        let mut child = Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
            .args(["inspect", "-"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
        child.wait_with_output().unwrap()
    };
    let o = run("name = \"x\"\ndegree = 3\naxiom = \"A\"\n[rules]\nA = \"AA\"\n");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("scheme x (degree 3)"));
    let o = run("name = \"x\"\ndegree = 33\naxiom = \"A\"\n[rules]\nA = \"AA\"\n");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("/dev/stdin:2:10: error:"),
        "{}",
        stderr(&o)
    );
}
