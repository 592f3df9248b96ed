//! Hostile and unlucky command lines: standard output closed early, every form an output path
//! takes (symbolic link, chain, loop, dangling link, folder, device, FIFO, read-only folder, full
//! disk) for every command that writes, output formats by flag, extension or input, two inputs
//! on standard input, the size guard on the first polygon step and on a smooth texture layout
//! (peak memory measured by `wait4`), a `--limit` refusal before refining, and a hint on every
//! refusal.

mod common;

use common::cli::{lsubdiv, stderr, write};
use std::io::Read as _;
use std::os::unix::fs::FileTypeExt as _;
use std::os::unix::process::ExitStatusExt as _;
use std::path::Path;
use std::process::{Child, Command, Stdio};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
}

/// `lsubdiv args` started with standard output `stdout` and standard error piped.
fn spawn(args: &[&str], stdout: Stdio) -> Child {
    (bin().args(args).stdout(stdout).stderr(Stdio::piped()))
        .spawn()
        .expect("runs")
}

/// All of `child`'s standard error.
fn read_stderr(child: &mut Child) -> String {
    let mut err = String::new();
    let mut stderr = child.stderr.take().unwrap();
    stderr.read_to_string(&mut err).unwrap();
    err
}

/// How a run ended, its standard error and its peak resident memory in bytes (`wait4`'s
/// `ru_maxrss`), standard output discarded.
struct Run {
    code: Option<i32>,
    stderr: String,
    peak: u64,
}

// The child is reaped by `wait4`, which also gives its peak memory.
#[allow(clippy::zombie_processes)]
fn run_measured(args: &[&str]) -> Run {
    let mut child = spawn(args, Stdio::null());
    let err = read_stderr(&mut child);
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: `rusage` is plain data; `wait4` reaps our own child, which `child` never waits for.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let reaped = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    assert_eq!(reaped, pid, "wait4");
    Run {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        stderr: err,
        peak: usage.ru_maxrss as u64 * 1024,
    }
}

/// A closed cylinder of `n` quads round with two `n`-gon caps.
fn capped_cylinder(n: usize) -> String {
    let mut t = String::new();
    for z in 0..2 {
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            t += &format!("v {} {} {z}\n", a.cos(), a.sin());
        }
    }
    for i in 0..n {
        let j = (i + 1) % n;
        t += &format!("f {} {} {} {}\n", i + 1, j + 1, n + j + 1, n + i + 1);
    }
    let cap = |range: Vec<usize>| {
        let v: Vec<String> = range.iter().map(|v| v.to_string()).collect();
        format!("f {}\n", v.join(" "))
    };
    t += &cap((1..=n).rev().collect());
    t += &cap((n + 1..=2 * n).collect());
    t
}

/// A torus of `m` × `m` quads, each quad cut into two triangles.
fn triangle_torus(m: usize) -> String {
    let mut t = String::new();
    for i in 0..m {
        for j in 0..m {
            let (a, b) = (
                std::f64::consts::TAU * i as f64 / m as f64,
                std::f64::consts::TAU * j as f64 / m as f64,
            );
            let r = 2.0 + b.cos();
            t += &format!("v {} {} {}\n", r * a.cos(), r * a.sin(), b.sin());
        }
    }
    let id = |i: usize, j: usize| (i % m) * m + (j % m) + 1;
    for i in 0..m {
        for j in 0..m {
            let (p, q, r, s) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t += &format!("f {p} {q} {r}\nf {p} {r} {s}\n");
        }
    }
    t
}

/// The cube as OBJ in `dir`.
fn cube(dir: &Path) -> String {
    let path = dir.join("cube.obj");
    lsubdiv::obj::write(&path, &lsubdiv::mesh::generators::cube()).unwrap();
    path.display().to_string()
}

/// Runs `args` with standard output a pipe closed after its first byte: the run ends quietly,
/// by SIGPIPE or successfully (when it wrote everything first), never by a panic or an error.
fn closed_pipe(args: &[&str]) {
    let mut child = spawn(args, Stdio::piped());
    let mut first = [0u8; 1];
    let _ = child.stdout.as_mut().unwrap().read(&mut first);
    drop(child.stdout.take());
    ends_quietly(child, &format!("{args:?}"));
}

/// Waits for `child` (`what`), whose output was closed early: it ends by SIGPIPE or
/// successfully (when it wrote everything first), never by a panic or an error.
fn ends_quietly(mut child: Child, what: &str) {
    let err = read_stderr(&mut child);
    let status = child.wait().unwrap();
    assert!(
        status.success() || status.signal() == Some(libc::SIGPIPE),
        "{what}: {status:?}: {err}"
    );
    for bad in ["panicked", "Broken pipe", "error"] {
        assert!(!err.contains(bad), "{what}: {err}");
    }
}

#[test]
fn every_command_ends_quietly_on_a_closed_pipe() {
    let dir = tempfile::tempdir().unwrap();
    let cube = cube(dir.path());
    let square = write(dir.path(), "sq.txt", "0 0\n1 0\n1 1\n0 1\n");
    // Command lines as words (the temporary folder's paths have no spaces).
    let commands = [
        String::new(),
        "schemes".into(),
        "ev binary-ternary --valence 3..3000".into(),
        "inspect fibonacci --json".into(),
        "inspect fibonacci".into(),
        "graph fibonacci --svg".into(),
        "graph fibonacci --dot".into(),
        "codegen fibonacci -o -".into(),
        format!("subdivide uniform-binary {cube} --steps 5 -o -"),
        format!("subdivide uniform-binary {cube} --steps 5 -o - --format ply --binary"),
        format!("curve fibonacci {square} --closed --steps 12 -o -"),
        "plot fibonacci -o -".into(),
        "render cube --size 400x300 -o -".into(),
        "ev binary-ternary --characteristic-map --valence 5 -o -".into(),
        "enumerate --family lcr --max-word-len 4".into(),
        "search --symbols 3 --max-word-len 2 --limit 3000".into(),
        "bench --mesh cube --steps 2".into(),
    ];
    for command in &commands {
        closed_pipe(&command.split_whitespace().collect::<Vec<_>>());
    }
}

/// An output path's symbolic links are followed to the end of their chain (the end replaced or
/// made, every link kept); a loop is refused, and nothing is written.
#[test]
fn symbolic_link_chains_are_followed_and_loops_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cube = cube(dir.path());
    let subdivide = |out: &Path| {
        lsubdiv(&[
            "subdivide",
            "uniform-binary",
            &cube,
            "--steps",
            "1",
            "-o",
            out.to_str().unwrap(),
        ])
    };
    let d = dir.path();
    let is_link =
        |p: &str| std::fs::symlink_metadata(d.join(p)).is_ok_and(|m| m.file_type().is_symlink());
    // a → b → a.
    std::os::unix::fs::symlink("b.obj", d.join("a.obj")).unwrap();
    std::os::unix::fs::symlink("a.obj", d.join("b.obj")).unwrap();
    let o = subdivide(&d.join("a.obj"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("symbolic links"), "{}", stderr(&o));
    assert!(stderr(&o).contains("hint:"), "{}", stderr(&o));
    assert!(
        is_link("a.obj") && is_link("b.obj"),
        "the loop is left as it was"
    );
    // c → d → e: e is made (missing), then replaced (a file); c and d stay links.
    std::os::unix::fs::symlink("d.obj", d.join("c.obj")).unwrap();
    std::os::unix::fs::symlink("e.obj", d.join("d.obj")).unwrap();
    for before in [None, Some("old")] {
        if let Some(text) = before {
            std::fs::write(d.join("e.obj"), text).unwrap();
        }
        let o = subdivide(&d.join("c.obj"));
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(is_link("c.obj") && is_link("d.obj"));
        let written = std::fs::read_to_string(d.join("e.obj")).unwrap();
        assert!(written.contains("\nf "), "{before:?}");
    }
    // A chain of 41 links is past what the system follows.
    for i in 0..41 {
        std::os::unix::fs::symlink(format!("l{}.obj", i + 1), d.join(format!("l{i}.obj"))).unwrap();
    }
    let o = subdivide(&d.join("l0.obj"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!d.join("l41.obj").exists());
}

/// `subdivide`'s output format: `--format`, else the extension (another one refused), else the
/// input's; a device is written, never replaced.
#[test]
fn output_formats_come_from_the_flag_the_name_or_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = cube(d);
    let sub = |input: &str, out: &str, more: &[&str]| {
        let mut args = vec![
            "subdivide",
            "uniform-binary",
            input,
            "--steps",
            "1",
            "-o",
            out,
        ];
        args.extend_from_slice(more);
        lsubdiv(&args)
    };
    // A device: written, still a device.
    let o = sub(&cube, "/dev/null", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // No extension: the input's format (OBJ, then PLY).
    let plain = d.join("fine");
    let o = sub(&cube, plain.to_str().unwrap(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&plain).unwrap().contains("\nv "));
    let ply = d.join("cube.ply");
    let o = sub(&cube, ply.to_str().unwrap(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = sub(ply.to_str().unwrap(), plain.to_str().unwrap(), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&plain).unwrap().starts_with(b"ply\n"));
    // `-` is standard output in the input's format, or the flag's.
    let o = sub(ply.to_str().unwrap(), "-", &[]);
    assert!(o.stdout.starts_with(b"ply\n"), "{}", stderr(&o));
    let o = sub(&cube, "-", &["--format", "ply", "--binary"]);
    assert!(
        o.stdout.starts_with(b"ply\nformat binary_little_endian"),
        "{}",
        stderr(&o)
    );
    // The flag wins over the extension.
    let named = d.join("named.ply");
    let o = sub(&cube, named.to_str().unwrap(), &["--format", "obj"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&named).unwrap().contains("\nv "));
    // Another extension is refused, with what to do; so is --binary for OBJ, before reading.
    let o = sub(&cube, d.join("fine.stl").to_str().unwrap(), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("hint: add --format"), "{}", stderr(&o));
    let o = sub(
        "missing.obj",
        d.join("x.obj").to_str().unwrap(),
        &["--binary"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--binary: the output is OBJ"),
        "{}",
        stderr(&o)
    );
    // Pictures without an extension: their first format.
    let svg = d.join("plot");
    let o = lsubdiv(&["plot", "uniform-binary", "-o", svg.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

#[test]
fn two_inputs_on_standard_input_are_refused() {
    for args in [
        &["subdivide", "-", "--steps", "1", "-", "-o", "out.obj"][..],
        &["curve", "-", "--steps", "1", "-", "-o", "out.txt"],
        &[
            "render", "-", "--scheme", "-", "--steps", "1", "-o", "out.png",
        ],
        &["plot", "-", "-", "-o", "out.svg"],
        &["bench", "--mesh", "-", "--scheme", "-"],
    ] {
        let o = lsubdiv(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&o).contains("are both `-`: standard input can be read only once"),
            "{args:?}: {}",
            stderr(&o)
        );
        for out in ["out.obj", "out.txt", "out.png", "out.svg"] {
            assert!(!Path::new(out).exists(), "{args:?} wrote {out}");
        }
    }
}

/// The size guard's refusal counts a polygon mesh's first step apart, as `--steps` does.
#[test]
fn the_size_guard_says_the_first_polygon_step_is_counted_apart() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write(dir.path(), "t.obj", &triangle_torus(8));
    let out = dir.path().join("o.obj");
    let o = lsubdiv(&[
        "subdivide",
        "binary-ternary",
        &mesh,
        "--steps",
        "3",
        "--max-memory",
        "1M",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("2 steps of binary-ternary after the first, Catmull–Clark step (--steps 3)"),
        "{e}"
    );
    assert!(e.contains("hint: use fewer steps"), "{e}");
}

/// A `--limit` that the steps cannot give is refused before refining: the refusal holds a
/// fraction of what the refinement holds.
#[test]
fn a_limit_refusal_comes_before_refining() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write(dir.path(), "t.obj", &triangle_torus(40));
    let out = dir.path().join("o.obj");
    let args = |limit: bool| {
        let mut a = vec![
            "subdivide",
            "binary-ternary",
            &mesh,
            "--steps",
            "2",
            "-o",
            out.to_str().unwrap(),
        ];
        if limit {
            a.push("--limit");
        }
        a
    };
    let refused = run_measured(&args(true));
    assert_eq!(refused.code, Some(2), "{}", refused.stderr);
    assert!(
        refused.stderr.contains("stationary from step 2"),
        "{}",
        refused.stderr
    );
    assert!(refused.stderr.contains("hint:"), "{}", refused.stderr);
    let refined = run_measured(&args(false));
    assert_eq!(refined.code, Some(0), "{}", refined.stderr);
    assert!(
        refused.peak * 2 < refined.peak,
        "refused at {} bytes, refined in {}",
        refused.peak,
        refined.peak
    );
}

/// What a run holds beside its allocations: the program's own pages.
fn baseline() -> u64 {
    let r = run_measured(&["schemes"]);
    assert_eq!(r.code, Some(0));
    r.peak
}

/// `--max-memory` bounds the reading of a mesh with two 20000-gon caps (its first polygon
/// step and its topology): refused before it is made, within the limit.
#[test]
fn the_size_guard_bounds_the_first_polygon_step() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write(dir.path(), "caps.obj", &capped_cylinder(20_000));
    let base = baseline();
    for max in [16u64, 40] {
        let r = guarded(&[&mesh, "--steps", "2"], max, base);
        assert_eq!(r.code, Some(2), "{}", r.stderr);
    }
}

/// `subdivide uniform-binary ARGS --max-memory MAXM -o FILE`, whose peak memory, refused or
/// not, is within the limit beside the program's own pages (`base`).
fn guarded(args: &[&str], max: u64, base: u64) -> Run {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.obj");
    let limit = format!("{max}M");
    let mut all = vec!["subdivide", "uniform-binary"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--max-memory", &limit, "-o", out.to_str().unwrap()]);
    let r = run_measured(&all);
    assert!(r.code == Some(0) || r.code == Some(2), "{}", r.stderr);
    assert!(
        r.peak <= (max << 20) + base,
        "{limit}: peak {} bytes, the program alone {base}: {}",
        r.peak,
        r.stderr
    );
    r
}

/// `--max-memory` bounds the refinement of a smooth texture layout (a mesh of its own, here
/// every edge a seam, so that it holds more than the positions' refinement): a run is refused
/// or stays within the limit.
#[test]
fn the_size_guard_bounds_a_smooth_texture_layout() {
    let dir = tempfile::tempdir().unwrap();
    let m = 120;
    let mut text = String::from("vt 0 0\nvt 1 0\n");
    for i in 0..m {
        for j in 0..m {
            text += &format!("v {i} {j} {}\n", (i * j) % 3);
        }
    }
    let id = |i: usize, j: usize| (i % m) * m + (j % m) + 1;
    for i in 0..m {
        for j in 0..m {
            text += &format!(
                "f {}/1 {}/2 {}/1 {}/2\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            );
        }
    }
    let mesh = write(dir.path(), "seams.obj", &text);
    let base = baseline();
    let mut refused = 0;
    for max in [12u64, 20, 24, 64] {
        let r = guarded(&[&mesh, "--steps", "0", "--uv", "smooth"], max, base);
        refused += usize::from(r.code == Some(2));
    }
    assert!((1..4).contains(&refused), "{refused} of 4 refused");
}

/// Texture layouts whose values repeat in a face, are shared by faces that meet only at a
/// point, or are left unused, refine by every smooth rule wherever the mesh does.
#[test]
fn odd_texture_layouts_refine_by_every_rule() {
    let dir = tempfile::tempdir().unwrap();
    let grid = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 2 2 0\n";
    let layouts = [
        "vt 9 9\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/2 2/3 3/4 4/2\nf 2/3 5/3 6/4 3/4\n",
        "vt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3 4/1\nf 2/1 5/2 6/3 3/1\nf 3/3 6/1 7/2\n",
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/1 3/1 4/1\nf 2/2 5/2 6/2 3/2\n",
    ];
    for (k, layout) in layouts.iter().enumerate() {
        let mesh = write(dir.path(), &format!("l{k}.obj"), &format!("{grid}{layout}"));
        for scheme in ["uniform-binary", "binary-ternary", "fibonacci"] {
            for rule in [
                "smooth",
                "corners-only",
                "corners-plus1",
                "corners-plus2",
                "boundaries",
            ] {
                let out = dir.path().join("o.obj");
                let o = lsubdiv(&[
                    "subdivide",
                    scheme,
                    &mesh,
                    "--steps",
                    "2",
                    "--uv",
                    rule,
                    "-o",
                    out.to_str().unwrap(),
                ]);
                assert!(
                    o.status.success(),
                    "layout {k}, {scheme}, {rule}: {}",
                    stderr(&o)
                );
                assert!(std::fs::read_to_string(&out).unwrap().contains("\nvt "));
            }
        }
    }
}

/// Every refusal ends with a hint.
#[test]
fn every_refusal_has_a_hint() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = cube(d);
    let out = d.join("o.obj");
    let out = out.to_str().unwrap();
    let text = std::fs::read_to_string(&cube).unwrap();
    let tagged = |name: &str, tags: &str| write(d, name, &format!("{text}{tags}"));
    let bad_tag = tagged("tag.obj", "t crease 2/1/0 0 6 1\n");
    let twice = tagged("twice.obj", "t crease 2/1/0 0 1 1\nt crease 2/1/0 1 0 2\n");
    let bad_face = write(d, "face.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n");
    let points = write(d, "p.txt", "0 0\n1\n");
    // Command lines as words (the temporary folder's paths have no spaces).
    let sub = |rest: String| format!("subdivide {rest} -o {out}");
    let cases = [
        sub(format!("no-such-scheme {cube} --steps 1")),
        sub("uniform-binary missing.obj --steps 1".into()),
        sub(format!("uniform-binary {bad_tag} --steps 1")),
        sub(format!("uniform-binary {twice} --steps 1")),
        sub(format!("uniform-binary {bad_face} --steps 1")),
        sub(format!("binary-ternary {cube} --steps 1 --limit")),
        sub(format!("uniform-binary {cube} --steps 9 --max-memory 1M")),
        format!("subdivide uniform-binary {cube} --steps 1 -o /dev/full"),
        format!("subdivide uniform-binary {cube} --steps 1 -o /no/such/dir/o.obj"),
        sub("- --steps 1 -".into()),
        format!("curve uniform-binary {points} --steps 1 -o p.out"),
        "plot uniform-binary -o x.gif".into(),
        "render cube --size 3x3 -o x.png".into(),
        "ev uniform-binary --valence x".into(),
        "inspect missing.toml".into(),
        "enumerate --family lcr --emit-scheme /dev/null".into(),
        format!("codegen uniform-binary -o {}", d.display()),
    ];
    for case in &cases {
        let args: Vec<&str> = case.split_whitespace().collect();
        let o = lsubdiv(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("\n  hint: "),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// Every command that writes a file, at every form its output path takes: nothing panics, a
/// device or FIFO is written and stays what it was, a folder or a loop is refused and left as
/// it was, a full disk refused with nothing left behind, links followed.
#[test]
fn every_writer_at_every_kind_of_output_path() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = cube(d);
    let square = write(d, "sq.txt", "0 0\n1 0\n1 1\n0 1\n");
    let writers: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["subdivide", "uniform-binary", &cube, "--steps", "1"],
            "obj",
        ),
        (
            vec![
                "curve",
                "uniform-binary",
                &square,
                "--closed",
                "--steps",
                "1",
            ],
            "txt",
        ),
        (vec!["plot", "uniform-binary"], "svg"),
        (vec!["graph", "uniform-binary", "--dot"], "dot"),
        (vec!["codegen", "uniform-binary"], "rs"),
        (vec!["render", "cube", "--size", "64x48"], "png"),
        (
            vec![
                "ev",
                "uniform-binary",
                "--characteristic-map",
                "--valence",
                "5",
            ],
            "svg",
        ),
    ];
    let root = unsafe { libc::geteuid() } == 0;
    for (k, (args, ext)) in writers.iter().enumerate() {
        let here = d.join(format!("w{k}"));
        std::fs::create_dir(&here).unwrap();
        let run = |out: &Path| {
            let mut a = args.clone();
            a.extend_from_slice(&["-o", out.to_str().unwrap()]);
            lsubdiv(&a)
        };
        let ok = |o: &std::process::Output, what: &str| {
            assert!(o.status.success(), "{args:?} {what}: {}", stderr(o));
        };
        let refused = |o: &std::process::Output, what: &str| {
            assert_eq!(o.status.code(), Some(2), "{args:?} {what}: {}", stderr(o));
            assert!(
                stderr(o).contains("hint:"),
                "{args:?} {what}: {}",
                stderr(o)
            );
        };
        let file = here.join(format!("out.{ext}"));
        // A link, a chain and a dangling link: their ends written.
        std::fs::write(&file, "old").unwrap();
        std::os::unix::fs::symlink(&file, here.join(format!("link.{ext}"))).unwrap();
        std::os::unix::fs::symlink(format!("link.{ext}"), here.join(format!("chain.{ext}")))
            .unwrap();
        for name in ["link", "chain"] {
            std::fs::write(&file, "old").unwrap();
            ok(&run(&here.join(format!("{name}.{ext}"))), name);
            assert_ne!(std::fs::read(&file).unwrap(), b"old", "{args:?} {name}");
        }
        std::os::unix::fs::symlink(format!("made.{ext}"), here.join(format!("dangling.{ext}")))
            .unwrap();
        ok(&run(&here.join(format!("dangling.{ext}"))), "dangling");
        assert!(here.join(format!("made.{ext}")).is_file());
        // A loop and a folder: refused, left as they were.
        std::os::unix::fs::symlink(format!("loop2.{ext}"), here.join(format!("loop1.{ext}")))
            .unwrap();
        std::os::unix::fs::symlink(format!("loop1.{ext}"), here.join(format!("loop2.{ext}")))
            .unwrap();
        refused(&run(&here.join(format!("loop1.{ext}"))), "loop");
        let folder = here.join(format!("folder.{ext}"));
        std::fs::create_dir(&folder).unwrap();
        refused(&run(&folder), "folder");
        assert!(folder.is_dir());
        // A device, a full one, a FIFO.
        ok(&run(Path::new("/dev/null")), "/dev/null");
        refused(&run(Path::new("/dev/full")), "/dev/full");
        let fifo = here.join(format!("fifo.{ext}"));
        assert!(Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success());
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(fifo).unwrap())
        };
        ok(&run(&fifo), "fifo");
        assert!(!reader.join().unwrap().is_empty());
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        // A read-only folder (unless this runs as root, whom permissions do not stop).
        let ro = here.join("ro");
        std::fs::create_dir(&ro).unwrap();
        let mut perms = std::fs::metadata(&ro).unwrap().permissions();
        std::os::unix::fs::PermissionsExt::set_mode(&mut perms, 0o555);
        std::fs::set_permissions(&ro, perms).unwrap();
        let o = run(&ro.join(format!("x.{ext}")));
        if !root {
            refused(&o, "read-only folder");
        }
        let left: Vec<_> = std::fs::read_dir(&ro).unwrap().collect();
        assert!(root || left.is_empty(), "{args:?}: {left:?}");
        // Nothing temporary left anywhere.
        for e in std::fs::read_dir(&here).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.ends_with(".tmp"), "{args:?} left {name}");
        }
    }
    // Writing to a FIFO whose reader went away ends quietly too.
    let fifo = d.join("gone.obj");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let fifo_name = fifo.to_str().unwrap();
    let args = [
        "subdivide",
        "uniform-binary",
        &cube,
        "--steps",
        "5",
        "-o",
        fifo_name,
    ];
    let child = spawn(&args, Stdio::null());
    let mut f = std::fs::File::open(&fifo).unwrap();
    let mut byte = [0u8; 1];
    let _ = f.read(&mut byte);
    drop(f);
    ends_quietly(child, "a FIFO whose reader went away");
}
