//! Bad input as a user meets it on the command line: every diagnostic names its place, says
//! what is wrong and how to fix it, and exits with status 2; nothing panics.

mod common;

use common::cli::{lsubdiv, stderr, write};
use std::path::Path;
use std::process::Command;

const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

/// Which command reads the scheme file: `inspect` (curve conditions) or `subdivide` (also the
/// surface conditions of [G] §4.2).
#[derive(Clone, Copy)]
enum Run {
    Inspect,
    Subdivide,
}

/// One row per scheme diagnostic: the file, the command, `line:column`, a fragment of the
/// message and one of the hint.
const SCHEMES: &[(&str, Run, &str, &str, &str)] = &[
    // TOML syntax.
    (
        "name = \"x\ndegree = 3\n",
        Run::Inspect,
        "1:10",
        "invalid basic string",
        "scheme files are TOML",
    ),
    // A key twice, a rule twice.
    (
        "name = \"x\"\nname = \"y\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "2:1",
        "duplicate key `name`",
        "delete or merge the repeated line",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\nL = \"L\"\n",
        Run::Inspect,
        "6:1",
        "duplicate key `L` in table `rules`",
        "one rule per symbol",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\nfoo = 1\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "4:1",
        "unknown key `foo`",
        "known keys: name, degree, axiom",
    ),
    // Missing keys: top-level keys belong at the top of the file.
    (
        "degree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "1:1",
        "missing key `name`",
        "add `name = \"my-scheme\"` at the top of the file",
    ),
    (
        "name = \"x\"\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "1:1",
        "missing key `degree`",
        "add `degree = 3`",
    ),
    (
        "name = \"x\"\ndegree = 3\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "1:1",
        "missing key `axiom`",
        "add `axiom = \"C\"`",
    ),
    // A missing `[rules]` table goes at the end of the file.
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n",
        Run::Inspect,
        "4:1",
        "missing `[rules]` table",
        "add `[rules]` at the end of the file",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\n",
        Run::Inspect,
        "4:2",
        "`[rules]` is empty",
        "one `SYMBOL = \"WORD\"` line per symbol",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\nrules = 4\n",
        Run::Inspect,
        "4:9",
        "`rules` must be a table",
        "write `[rules]` on a line of its own",
    ),
    (
        "name = \"x y\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "1:8",
        "scheme name `x y` is not a slug",
        "letters, digits",
    ),
    // Degree 0, absurd, not an integer.
    (
        "name = \"x\"\ndegree = 0\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "2:10",
        "degree 0 is out of range",
        "use a degree from 1 to 15",
    ),
    (
        "name = \"x\"\ndegree = 16\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "2:10",
        "degree 16 is out of range",
        "use a degree from 1 to 15",
    ),
    (
        "name = \"x\"\ndegree = \"3\"\naxiom = \"L\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "2:10",
        "the value of `degree` must be an integer",
        "without quotes",
    ),
    // Words: a rule that is not a string, empty words, symbols without a rule (pointing at
    // the symbol itself).
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = 3\n",
        Run::Inspect,
        "5:5",
        "the value of `L` must be a string",
        "write it in double quotes",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"\"\n",
        Run::Inspect,
        "5:5",
        "rule for `L`: empty word",
        "at least one interval",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"  \"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "3:9",
        "axiom: empty word",
        "write one or more symbols",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LCX\"\nC = \"L\"\n",
        Run::Inspect,
        "5:8",
        "rule for `L`: symbol `X` has no rule",
        "add a rule `X = \"...\"` under `[rules]`, or use a symbol that has one: L, C",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"A1\"\n[rules]\nA1 = \"A1 A2\"\nA2 = \"A1\"\nB = \"A1A2\"\n",
        Run::Inspect,
        "7:6",
        "rule for `B`: symbol `A` has no rule",
        "separate symbols longer than one character with spaces",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L Q\"\n[rules]\nL = \"LL\"\n",
        Run::Inspect,
        "3:12",
        "axiom: symbol `Q` has no rule",
        "add a rule `Q = \"...\"`",
    ),
    // [symmetry].
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n[symmetry]\nQ = \"L\"\n",
        Run::Inspect,
        "7:1",
        "`[symmetry]` names `Q`, which has no rule",
        "pairs twin symbols",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n[symmetry]\nL = \"Q\"\n",
        Run::Inspect,
        "7:5",
        "`[symmetry]` maps `L` to `Q`, which has no rule",
        "pairs twin symbols",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"C\"\n[rules]\nL = \"LC\"\nC = \"LCR\"\nR = \"CR\"\n[symmetry]\nL = \"R\"\nR = \"C\"\n",
        Run::Inspect,
        "10:5",
        "`[symmetry]` is not an involution: `R` is paired with both `L` and `C`",
        "list each twin pair once",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"C\"\n[rules]\nL = \"LC\"\nR = \"RC\"\nC = \"LCR\"\n[symmetry]\nL = \"R\"\n",
        Run::Inspect,
        "8:2",
        "the declared σ is not a symmetry ([G] eq. (14)): π(σ(L)) = RC but σ̄(π(L)) = CR",
        "the rule of `R` must be the rule of `L` read backwards",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LR\"\nR = \"LR\"\n[symmetry]\nL = \"R\"\n",
        Run::Inspect,
        "7:2",
        "the axiom L is not symmetric",
        "read the same backwards",
    ),
    // Validity: which condition of [N] Definition 3.1 fails.
    (
        "name = \"x\"\ndegree = 3\naxiom = \"A\"\n[rules]\nA = \"B\"\nB = \"A\"\n",
        Run::Inspect,
        "4:2",
        "L-system `x` is not valid: [N] Definition 3.1 asks for a real eigenvalue ρ > 1 of M, but the spectral radius ρ(M) = 1 is not greater than 1",
        "several intervals that lead back to it",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"A\"\n[rules]\nA = \"AAB\"\nB = \"B\"\n",
        Run::Inspect,
        "4:2",
        "[N] Definition 3.1 asks for a positive eigenvector of M for ρ > 1, but there is no positive eigenvector for ρ(M) = 2",
        "[N] Theorem 3.7",
    ),
    // Lengths: not free, not satisfying eq. (3), incomplete, unknown, malformed, not positive,
    // and missing where they are not unique (`subdivide` needs them; `inspect` reports).
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n[lengths]\nL = \"1\"\n",
        Run::Inspect,
        "7:5",
        "`[lengths]` given, but the eigenvector of ρ is unique: lengths are not free",
        "remove `[lengths]`",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"LR\"\nL = \"LC\"\nC = \"L\"\nD = \"R\"\nR = \"DR\"\n[lengths]\nS = \"1\"\nL = \"1\"\nC = \"rho - 1\"\nD = \"rho - 1\"\nR = \"1\"\n",
        Run::Inspect,
        "11:5",
        "`[lengths]` do not satisfy [N] eq. (3) for `S`",
        "ρ·a must equal the sum of the lengths of π(A)",
    ),
    (
        // Eq. (3) holds (A and B each double), but σ swaps A and B of different lengths.
        "name = \"x\"\ndegree = 2\naxiom = \"AB\"\n[rules]\nA = \"AA\"\nB = \"BB\"\n[symmetry]\nA = \"B\"\n[lengths]\nA = \"1\"\nB = \"2\"\n",
        Run::Inspect,
        "10:5",
        "`[lengths]` are not σ-invariant: `A` has length 1 but its twin `B` has 2",
        "needs twins of equal length",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"LR\"\nL = \"LC\"\nC = \"L\"\nD = \"R\"\nR = \"DR\"\n[lengths]\nS = \"1\"\n",
        Run::Inspect,
        "10:2",
        "`[lengths]` has no entry for symbol `L`",
        "give every symbol a length",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LL\"\n[lengths]\nQ = \"1\"\n",
        Run::Inspect,
        "7:1",
        "`[lengths]` names `Q`, which has no rule",
        "one entry per symbol of `[rules]`: L",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"LR\"\nL = \"LC\"\nC = \"L\"\nD = \"R\"\nR = \"DR\"\n[lengths]\nS = \"2\"\nL = \"rho^99999999\"\nC = \"rho - 1\"\nD = \"rho - 1\"\nR = \"1\"\n",
        Run::Inspect,
        "12:5",
        "`[lengths]` entry for `L`: exponent 99999999 is larger than 64",
        "expressions in `rho`",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"LR\"\nL = \"LC\"\nC = \"L\"\nD = \"R\"\nR = \"DR\"\n[lengths]\nS = \"-2\"\nL = \"1\"\nC = \"rho - 1\"\nD = \"rho - 1\"\nR = \"1\"\n",
        Run::Inspect,
        "11:5",
        "`[lengths]` entry for `S` is -2, not positive",
        "greater than 0",
    ),
    (
        "name = \"x\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"LR\"\nL = \"LC\"\nC = \"L\"\nD = \"R\"\nR = \"DR\"\n",
        Run::Subdivide,
        "4:2",
        "lengths are not unique: the eigenspace of ρ has dimension 2",
        "declare `[lengths]`",
    ),
    // Surfaces ([G] §4.2): degree, axiom, symmetry, stationarity, containment.
    (
        "name = \"t\"\ndegree = 2\naxiom = \"A\"\n[rules]\nA = \"AA\"\n",
        Run::Subdivide,
        "2:10",
        "surfaces need degree 3",
        "set `degree = 3` for surfaces",
    ),
    (
        "name = \"t\"\ndegree = 3\naxiom = \"CC\"\n[rules]\nL = \"LC\"\nC = \"LCR\"\nR = \"CR\"\n[symmetry]\nL = \"R\"\n",
        Run::Subdivide,
        "3:9",
        "the axiom, which must be one symbol; it is CC",
        "one-symbol axiom",
    ),
    (
        "name = \"t\"\ndegree = 3\naxiom = \"C\"\n[rules]\nL = \"LC\"\nR = \"RC\"\nC = \"LCR\"\n",
        Run::Subdivide,
        "4:2",
        "not symmetric: no involution σ",
        "symmetric L-system ([G] §4.1)",
    ),
    (
        "name = \"t\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"LR\"\nL = \"RR\"\nR = \"LL\"\n[symmetry]\nL = \"R\"\n",
        Run::Subdivide,
        "4:2",
        "never become stationary: the ray prefix cycles with period 2",
        "must settle",
    ),
    (
        "name = \"t\"\ndegree = 3\naxiom = \"C\"\n[rules]\nL = \"LCC\"\nC = \"LCR\"\nR = \"CCR\"\n[symmetry]\nL = \"R\"\n",
        Run::Subdivide,
        "5:5",
        "the label L of edges leaving an EV must rewrite as L X",
        "e.g. `L = \"LC\"`",
    ),
];

#[test]
fn every_scheme_diagnostic_names_file_line_column_and_hint() {
    let dir = tempfile::tempdir().unwrap();
    let cube = write(dir.path(), "cube.obj", CUBE);
    let out = dir.path().join("out.obj").display().to_string();
    for (i, &(text, run, at, message, hint)) in SCHEMES.iter().enumerate() {
        let name = format!("bad{i}.toml");
        let f = write(dir.path(), &name, text);
        let o = match run {
            Run::Inspect => lsubdiv(&["inspect", &f]),
            Run::Subdivide => lsubdiv(&["subdivide", &f, "--steps", "1", &cube, "-o", &out]),
        };
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "row {i}: {e}");
        assert!(
            e.contains(&format!("{name}:{at}: error: ")),
            "row {i}: wrong place (expected {at}): {e}"
        );
        assert!(e.contains(message), "row {i}: wrong message: {e}");
        let hint_line = e.lines().find(|l| l.starts_with("  hint: "));
        assert!(
            hint_line.is_some_and(|h| h.contains(hint)),
            "row {i}: wrong or missing hint: {e}"
        );
        assert!(!e.contains("panicked"), "row {i}: {e}");
    }
    assert!(
        !dir.path().join("out.obj").exists(),
        "no output from a refused scheme"
    );
}

/// The compiled generic tables of a shipped scheme.
fn generic(name: &str) -> lsubdiv::generic::GenericScheme {
    let r = lsubdiv_cli::resolve(name).unwrap();
    lsubdiv::generic::GenericScheme::new(lsubdiv::compiler::exact::Scheme::build(r.ls).unwrap())
        .unwrap()
}

#[test]
fn predicted_curve_sizes_are_exact() {
    use lsubdiv::{Curve, CurveScheme};
    let square: Vec<[f64; 2]> = (0..6).map(|i| [f64::from(i), f64::from(i * i)]).collect();
    let mut cases = Vec::new();
    for name in [
        "fibonacci",
        "binary-ternary",
        "delay-queue-3",
        "uniform-binary",
    ] {
        for closed in [false, true] {
            let s = generic(name);
            let c = Curve::with_axiom(&s.tables(), square.clone(), closed);
            cases.push((s, c));
        }
    }
    // Labels other than the axiom, open: the interior labels grow, the ends stay.
    let mut s = generic("fibonacci-curve");
    let labels = s.scheme().ls.parse_word("SSLSSLSS").unwrap();
    let c = Curve {
        points: square,
        labels,
        closed: false,
    };
    s.prepare(&c).unwrap();
    cases.push((s, c));
    for (s, c) in &cases {
        let t = s.tables();
        for steps in 0..7 {
            let fine = lsubdiv::refine(s, c, steps).unwrap();
            let p = lsubdiv_cli::limits::curve(&t, &c.labels, c.closed, c.points.len(), 2, steps);
            assert_eq!(
                p.vertices,
                fine.points.len() as u128,
                "{} closed={} steps={steps}",
                t.name,
                c.closed
            );
        }
    }
}

#[test]
fn predicted_surface_sizes_are_exact() {
    use lsubdiv::mesh::features::Features;
    use lsubdiv::mesh::generators::{
        creased_cube, cube, grid_with_hole, open_grid, star, torus, tube,
    };
    use lsubdiv::mesh::surface::SurfaceScheme;
    use lsubdiv::CurveScheme;
    for name in ["binary-ternary", "fibonacci", "uniform-binary"] {
        let s = lsubdiv::generic::GenericSurface::new(
            lsubdiv::compiler::exact::Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls)
                .unwrap(),
        )
        .unwrap();
        let plain = |m| (m, Features::default());
        let meshes = [
            plain(cube()),
            plain(star()),
            plain(torus(3, 4)),
            plain(open_grid(3, 2)),
            plain(tube(2, 5)),
            grid_with_hole(3),
            creased_cube(),
        ];
        for (mesh, features) in &meshes {
            for steps in 0..4 {
                let topo = lsubdiv::mesh::topology::Topology::build(mesh).unwrap();
                let fine = lsubdiv::mesh::patch::subdivide_with::<_, f64>(
                    &s, mesh, &topo, features, steps, 1,
                )
                .unwrap();
                let t = s.tables();
                let p = lsubdiv_cli::limits::surface(
                    &t,
                    s.surface().contained_from,
                    &topo,
                    features,
                    steps,
                    8,
                    1,
                );
                assert_eq!(
                    (p.vertices, p.quads),
                    (fine.positions.len() as u128, Some(fine.faces.len() as u128)),
                    "{name} steps={steps}"
                );
            }
        }
    }
}

#[test]
fn too_large_requests_are_refused_before_refining() {
    let dir = tempfile::tempdir().unwrap();
    let cube = write(dir.path(), "cube.obj", CUBE);
    let square = write(dir.path(), "square.txt", "0 0\n1 0\n1 1\n0 1\n");
    let out = dir.path().join("out.obj");
    let out_s = out.display().to_string();
    let started = std::time::Instant::now();
    for (args, expect) in [
        (
            vec!["subdivide", "binary-ternary", "--steps", "40", &cube, "-o", &out_s],
            "40 steps of binary-ternary on",
        ),
        (
            vec!["subdivide", "binary-ternary", "--steps", "18446744073709551615", &cube, "-o", &out_s],
            "more than 10^38 vertices, more than 10^38 quads",
        ),
        (
            // ~1 TiB of points and labels: over half of any machine's memory (the default).
            vec!["curve", "fibonacci", "--steps", "50", &square, "-o", &out_s],
            "would make 40 730 022 151 points",
        ),
        (
            // 4 steps of binary-ternary on the cube: |π⁴(C)| = 41, so 6·41² quads, fine under
            // the default but not under 1 MiB.
            vec!["subdivide", "binary-ternary", "--steps", "4", "--max-memory", "1M", &cube, "-o", &out_s],
            "would make 10 088 vertices, 10 086 quads, ~1.2 MiB; --max-memory is ~1.0 MiB\n  hint: use fewer steps or raise --max-memory",
        ),
        (
            vec!["bench", "--mesh", "cube", "--scheme", "uniform-binary", "--steps", "40"],
            "40 steps of uniform-binary on cube would make",
        ),
        // Inputs too large to read under the limit are refused unread (5 bytes held per byte).
        (
            vec!["subdivide", "binary-ternary", "--steps", "1", "--max-memory", "500", &cube, "-o", &out_s],
            "cube.obj: error: the file has 136 bytes, and reading it may hold 680 bytes; --max-memory is 500 bytes",
        ),
        (
            vec!["curve", "fibonacci", "--steps", "1", "--max-memory", "50", &square, "-o", &out_s],
            "square.txt: error: the file has 16 bytes, and reading it may hold 80 bytes; --max-memory is 50 bytes",
        ),
    ] {
        let o = lsubdiv(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(expect), "{args:?}: {}", stderr(&o));
        assert!(!out.exists(), "{args:?}: no output");
    }
    assert!(
        started.elapsed().as_secs() < 20,
        "refused quickly: {:?}",
        started.elapsed()
    );
    let o = lsubdiv(&[
        "subdivide",
        "binary-ternary",
        "--steps",
        "1",
        "--max-memory",
        "4X",
        &cube,
        "-o",
        &out_s,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("`4X` is not a size"), "{}", stderr(&o));
}

/// Two cubes; the second's vertices listed in `shared` (1-based) are the first's. Vertex lines
/// first (8, then the second cube's new ones), then the twelve faces.
fn two_cubes(shared: &[u32]) -> String {
    let faces: Vec<&str> = CUBE.lines().filter(|l| l.starts_with("f ")).collect();
    let verts: Vec<&str> = CUBE.lines().filter(|l| l.starts_with("v ")).collect();
    let mut text: String = verts.iter().map(|v| format!("{v}\n")).collect();
    let mut map = [0u32; 9];
    let mut next = 9;
    for i in 1..=8u32 {
        if shared.contains(&i) {
            map[i as usize] = i;
        } else {
            map[i as usize] = next;
            next += 1;
            let xyz: Vec<f64> = verts[i as usize - 1][2..]
                .split(' ')
                .map(|t| t.parse().unwrap())
                .collect();
            text += &format!("v {} {} {}\n", xyz[0] + 3.0, xyz[1], xyz[2]);
        }
    }
    for f in &faces {
        text += &format!("{f}\n");
    }
    for f in &faces {
        let idx: Vec<String> = f[2..]
            .split(' ')
            .map(|t| map[t.parse::<usize>().unwrap()].to_string())
            .collect();
        text += &format!("f {}\n", idx.join(" "));
    }
    text
}

#[test]
fn every_mesh_error_names_its_line_or_element() {
    let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
    let fin = format!("{CUBE}v 0 -2 -1\nv 0 -2 0\nf 1 2 10 9\n");
    let isolated = format!("{CUBE}v 5 5 5\n");
    let duplicate = format!("{CUBE}f 2 1 4 3\n");
    let cube_lines: Vec<&str> = CUBE.lines().collect();
    let repeated = format!("{}\nf 1 4 4 2\n", cube_lines[..14].join("\n"));
    // A vertex added on the cube's edge 1–2, and the two pentagons it makes split into quads
    // (one Catmull–Clark topology step): the new vertex has valence 2. `obj::format` writes a
    // comment line first, so vertex 9 is on line 10.
    let valence_two = {
        let c = lsubdiv::mesh::generators::cube();
        let mut polys: Vec<Vec<u32>> = c.faces.iter().map(|f| f.to_vec()).collect();
        for p in &mut polys {
            if let Some(i) = (0..4).find(|&i| {
                let (a, b) = (p[i], p[(i + 1) % 4]);
                (a, b) == (0, 1) || (a, b) == (1, 0)
            }) {
                p.insert(i + 1, 8);
            }
        }
        let mut positions = c.positions.clone();
        positions.push([0.0, -1.0, -1.0]);
        let m = lsubdiv::mesh::generators::quad_split(&positions, &polys);
        lsubdiv::obj::format(&m).unwrap()
    };
    let accepted: Vec<(&str, String, Option<&str>)> = vec![
        (
            "fin.obj",
            fin,
            Some("not a 2-manifold: 2 non-manifold vertices and 1 non-manifold edge"),
        ),
        (
            "edge.obj",
            two_cubes(&[1, 2]),
            Some("not a 2-manifold: 2 non-manifold vertices and 1 non-manifold edge"),
        ),
        (
            "vertex.obj",
            two_cubes(&[1]),
            Some("not a 2-manifold: 1 non-manifold vertex and 0 non-manifold edges"),
        ),
        (
            "isolated.obj",
            isolated,
            Some("1 vertex used by no face: dropped"),
        ),
        (
            "duplicate.obj",
            duplicate,
            Some("not a 2-manifold: 4 non-manifold vertices and 4 non-manifold edges"),
        ),
        ("repeated.obj", repeated, Some("not a 2-manifold")),
        ("valence.obj", valence_two, None),
    ];
    let rows: Vec<(&str, String, &str)> = vec![
        (
            "number.obj",
            format!("{square}v 0 x 0\n"),
            ":5: error: `x` is not a number",
        ),
        (
            "count.obj",
            "v 0 0\n".into(),
            ":1: error: vertex has 2 values",
        ),
        (
            "nan.obj",
            "v 0 nan 0\n".into(),
            ":1: error: coordinate `nan` is not finite",
        ),
        (
            "inf.obj",
            "v 0 0 -inf\n".into(),
            ":1: error: coordinate `-inf` is not finite",
        ),
        (
            "corner.obj",
            format!("{square}f 1 2 3 4/x\n"),
            ":5: error: `4/x` is not a face corner",
        ),
        (
            "zero.obj",
            format!("{square}f 0 1 2 3\n"),
            ":5: error: vertex index 0 is invalid (OBJ indices start at 1)",
        ),
        (
            "range.obj",
            format!("{square}f 1 2 3 9\n"),
            ":5: error: vertex index 9 out of range (the file has 4 vertices)",
        ),
        (
            "huge.obj",
            format!("{square}f 1 2 3 99999999999999999999999\n"),
            ":5: error: vertex index 99999999999999999999999 out of range",
        ),
        (
            "relative.obj",
            format!("f -1 -2 -3 -4\n{square}"),
            ":1: error: vertex index -1 out of range (only 0 vertices precede this line)",
        ),
        (
            "tri.obj",
            format!("{square}f 1 2\n"),
            ":5: error: face has 2 vertices; a face has at least 3",
        ),
        ("empty.obj", String::new(), ": error: empty mesh: no faces"),
        (
            "comments.obj",
            "# a comment\n\n# another\n".into(),
            ": error: empty mesh: no faces",
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    let out_s = out.display().to_string();
    // The two commands that read a mesh, on file f.
    let commands = |f: &str| -> [Vec<String>; 2] {
        let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        [
            words(&[
                "subdivide",
                "uniform-binary",
                "--steps",
                "1",
                f,
                "-o",
                &out_s,
            ]),
            words(&["bench", "--mesh", f, "--steps", "1", "--runs", "1"]),
        ]
    };
    let run = |args: &[String]| lsubdiv(&args.iter().map(String::as_str).collect::<Vec<_>>());
    for (name, text, expect) in &rows {
        let f = write(dir.path(), name, text);
        for args in commands(&f) {
            let o = run(&args);
            let e = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{name} {}: {e}", args[0]);
            assert!(
                e.contains(&format!("{name}{expect}")),
                "{name} {}: {e}",
                args[0]
            );
            assert!(!e.contains("panicked"), "{name}: {e}");
        }
    }
    assert!(!out.exists(), "no output from a refused mesh");
    // What OpenSubdiv refines is refined, with a warning saying what was done.
    for (name, text, warning) in &accepted {
        let f = write(dir.path(), name, text);
        for args in commands(&f) {
            let o = run(&args);
            let e = stderr(&o);
            assert!(o.status.success(), "{name} {}: {e}", args[0]);
            if let (Some(w), "subdivide") = (warning, args[0].as_str()) {
                assert!(e.contains(&format!("{name}: warning: {w}")), "{name}: {e}");
            }
        }
    }
}

/// The names in a directory, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn failed_runs_leave_previous_outputs_and_no_temporary_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = write(d, "cube.obj", CUBE);
    let broken = write(
        d,
        "broken.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 5\n",
    );
    let square = write(d, "square.txt", "0 0\n1 0\n1 1\n0 1\n");
    let bad_scheme = write(
        d,
        "bad.toml",
        "name = \"x\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"LX\"\n",
    );
    let (mesh, points, code) = (d.join("mesh.obj"), d.join("points.txt"), d.join("code.rs"));
    let s = |p: &Path| p.display().to_string();
    for (args, out) in [
        (
            vec![
                "subdivide",
                "binary-ternary",
                "--steps",
                "1",
                &cube,
                "-o",
                &s(&mesh),
            ],
            &mesh,
        ),
        (
            vec![
                "curve",
                "fibonacci",
                "--steps",
                "2",
                &square,
                "-o",
                &s(&points),
            ],
            &points,
        ),
        (vec!["codegen", "fibonacci", "-o", &s(&code)], &code),
    ] {
        assert!(lsubdiv(&args).status.success(), "{args:?}");
        assert!(out.exists());
    }
    let before: Vec<Vec<u8>> = [&mesh, &points, &code]
        .map(|p| std::fs::read(p).unwrap())
        .to_vec();
    let listing = entries(d);
    // Failures in reading, in refining (too large) and in writing (the output is a directory:
    // the rename fails after the whole file was written next to it).
    let target_dir = d.join("taken.obj");
    std::fs::create_dir(&target_dir).unwrap();
    for args in [
        vec![
            "subdivide",
            "binary-ternary",
            "--steps",
            "1",
            &broken,
            "-o",
            &s(&mesh),
        ],
        vec![
            "subdivide",
            &bad_scheme,
            "--steps",
            "1",
            &cube,
            "-o",
            &s(&mesh),
        ],
        vec![
            "subdivide",
            "binary-ternary",
            "--steps",
            "5",
            "--max-memory",
            "1K",
            &cube,
            "-o",
            &s(&mesh),
        ],
        vec![
            "curve",
            "fibonacci",
            "--steps",
            "2",
            "--labels",
            "LLQ",
            &square,
            "-o",
            &s(&points),
        ],
        vec![
            "curve",
            "fibonacci",
            "--steps",
            "40",
            "--max-memory",
            "1M",
            &square,
            "-o",
            &s(&points),
        ],
        vec!["codegen", &bad_scheme, "-o", &s(&code)],
        vec![
            "subdivide",
            "binary-ternary",
            "--steps",
            "1",
            &cube,
            "-o",
            &s(&target_dir),
        ],
        vec![
            "curve",
            "fibonacci",
            "--steps",
            "1",
            &square,
            "-o",
            &s(&target_dir),
        ],
    ] {
        let o = lsubdiv(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    }
    let after: Vec<Vec<u8>> = [&mesh, &points, &code]
        .map(|p| std::fs::read(p).unwrap())
        .to_vec();
    assert!(before == after, "previous outputs changed");
    let mut expected = listing;
    expected.push("taken.obj".into());
    expected.sort();
    assert_eq!(entries(d), expected, "no temporary or partial file left");
    assert!(entries(&target_dir).is_empty());
}

/// Ctrl-C while the output is being written: the temporary file is removed, the previous
/// output stays, the exit status is 130.
#[cfg(unix)]
#[test]
fn an_interrupted_run_leaves_the_previous_output_and_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let square = write(d, "square.txt", "0 0\n1 0\n1 1\n0 1\n");
    let out = d.join("points.txt");
    // 28 Fibonacci steps: 39 MB of text, written and synced while we watch. Should the run
    // finish before the signal lands (a loaded machine), try again.
    for attempt in 0..3 {
        std::fs::write(&out, "previous\n").unwrap();
        let mut child = Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
            .args(["curve", "fibonacci", "--steps", "28", &square, "-o"])
            .arg(&out)
            .spawn()
            .unwrap();
        let seen = loop {
            if entries(d).iter().any(|n| n.ends_with(".tmp")) {
                let kill = Command::new("kill")
                    .args(["-INT", &child.id().to_string()])
                    .status()
                    .unwrap();
                assert!(kill.success());
                break true;
            }
            if child.try_wait().unwrap().is_some() {
                break false;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        };
        let status = child.wait().unwrap();
        if !seen || status.success() {
            eprintln!("attempt {attempt}: finished before the signal");
            continue;
        }
        assert_eq!(status.code(), Some(130));
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous\n");
        assert_eq!(entries(d), vec!["points.txt", "square.txt"]);
        return;
    }
    panic!("could not interrupt a run while it wrote its output");
}

/// `n` symbols `A0 …`, rule i given by `rule(i)`: large alphabets.
fn alphabet(n: usize, rule: impl Fn(usize) -> String) -> String {
    let rules: String = (0..n)
        .map(|i| format!("A{i} = \"{}\"\n", rule(i)))
        .collect();
    format!("name = \"big\"\ndegree = 3\naxiom = \"A0\"\n[rules]\n{rules}")
}

/// Small scheme files whose exact compilation would take minutes or not end: each is refused,
/// quickly, with the limit it passes named at its place (docs/schemes.md, "Limits"); a long rule
/// that used to take minutes (quadratic mask copies) compiles.
#[test]
fn exact_work_is_bounded_with_located_errors() {
    let dir = tempfile::tempdir().unwrap();
    let free = |b: &str| {
        format!(
            "name = \"x\"\ndegree = 3\naxiom = \"AB\"\n[rules]\nA = \"AA\"\nB = \"BB\"\n[lengths]\nA = \"1\"\nB = \"{b}\"\n"
        )
    };
    let n = 255;
    let rows: Vec<(String, &str, &str, &str)> = vec![
        // ρ = 2^(1/255): degree 255 over Q.
        (
            alphabet(n, |i| {
                if i + 1 < n {
                    format!("A{}", i + 1)
                } else {
                    "A0 A0".into()
                }
            }),
            "4:2",
            "ρ has degree 255 over Q (its minimal polynomial x^255 - 2); at most 64 is supported",
            "use fewer symbols",
        ),
        // ρ = 2 over Q, but 255 symbols in one class: the analysis runs out of work.
        (
            alphabet(n, |i| format!("A{} A{}", (i + 1) % n, (i * 7 + 3) % n)),
            "4:2",
            "the analysis ([N] §3) of `big` needs more exact work than the limit",
            "use fewer symbols, shorter rules or smaller numbers",
        ),
        // [lengths] with numbers far too large.
        (
            free("(123456789012345678901234567890^64)^64"),
            "9:5",
            "`[lengths]` entry for `B`: a value has a",
            "expressions in `rho`",
        ),
        (
            free(&"7".repeat(2000)),
            "9:5",
            "`[lengths]` entry for `B`: a number of 2000 digits; expressions are limited to 4096 bits",
            "expressions in `rho`",
        ),
    ];
    for (i, (text, at, message, hint)) in rows.iter().enumerate() {
        let name = format!("work{i}.toml");
        let f = write(dir.path(), &name, text);
        let o = lsubdiv(&["inspect", &f]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "row {i}: {e}");
        assert!(e.contains(&format!("{name}:{at}: error: ")), "row {i}: {e}");
        assert!(e.contains(message), "row {i}: {e}");
        assert!(e.contains(hint), "row {i}: {e}");
    }
    // A rule 2000 letters long compiles (its masks are 8000 long).
    let long = format!(
        "name = \"long\"\ndegree = 3\naxiom = \"L\"\n[rules]\nL = \"{}{}\"\nR = \"LR\"\n",
        "L".repeat(1000),
        "R".repeat(1000)
    );
    let f = write(dir.path(), "long.toml", &long);
    let o = lsubdiv(&["inspect", &f]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
