//! The library's front door and the command line are one refinement: `Scheme`, `Mesh::read`,
//! `Refiner` and `Refined::write` give the bytes `lsubdiv subdivide` writes, steps counted
//! alike (a polygon mesh's first Catmull–Clark step is one of them), with creases, texture
//! coordinates and the limit; and what the library refuses, it refuses as an error a program
//! can match.

mod common;

use common::cli::{lsubdiv, stderr, write};
use lsubdiv::{Error, Mesh, Refiner, Scheme, UvRule};

/// A pyramid over a square (four triangles and a quad) with a crease along two base edges, a
/// corner, and a texture layout with a seam.
const PYRAMID: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n\
    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvt 0.5 0\n\
    f 1/1 2/2 5/5\nf 2/2 3/3 5/5\nf 3/3 4/4 5/5\nf 4/4 1/6 5/5\nf 4/4 3/3 2/2 1/1\n\
    t crease 2/1/0 0 1 2.5\nt crease 2/1/0 1 2 10\nt corner 1/1/0 3 10\n";

#[test]
fn the_library_writes_what_subdivide_writes() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "pyramid.obj", PYRAMID);
    let mesh = Mesh::read(&input).unwrap();
    for (scheme, steps, limit, uv) in [
        ("uniform-binary", 3, false, "linear"),
        ("fibonacci", 4, true, "smooth"),
        ("binary-ternary", 3, true, "corners-only"),
    ] {
        let cli = dir.path().join(format!("{scheme}-cli.obj"));
        let o = lsubdiv(
            &[
                "subdivide",
                scheme,
                &input,
                "--steps",
                &steps.to_string(),
                "--uv",
                uv,
                "-o",
                cli.to_str().unwrap(),
            ]
            .into_iter()
            .chain(limit.then_some("--limit"))
            .collect::<Vec<_>>(),
        );
        assert!(o.status.success(), "{scheme}: {}", stderr(&o));
        let rule = match uv {
            "linear" => UvRule::Linear,
            "smooth" => UvRule::Smooth,
            _ => UvRule::CornersOnly,
        };
        let shipped = Scheme::shipped(scheme).unwrap();
        let plan = Refiner::new(&shipped, &mesh)
            .steps(steps)
            .limit(limit)
            .uv_rule(rule)
            .build()
            .unwrap();
        let fine = plan.refine().unwrap();
        assert_eq!(fine.normals.is_some(), limit, "{scheme}");
        assert!(fine.uv.is_some(), "{scheme}");
        let library = dir.path().join(format!("{scheme}-library.obj"));
        fine.write(&library).unwrap();
        assert_eq!(
            std::fs::read(&library).unwrap(),
            std::fs::read(&cli).unwrap(),
            "{scheme}, {steps} steps, limit {limit}, --uv {uv}"
        );
        // A plan refines again alike.
        assert_eq!(plan.refine().unwrap(), fine, "{scheme}");
    }
}

#[test]
fn refusals_are_errors_a_program_can_match() {
    let mesh = Mesh::parse("pyramid.obj", PYRAMID.as_bytes().to_vec()).unwrap();
    let fibonacci = Scheme::shipped("fibonacci").unwrap();
    // A polygon mesh takes its first step as a Catmull–Clark step: zero steps is refused.
    let e = Refiner::new(&fibonacci, &mesh)
        .steps(0)
        .build()
        .unwrap_err();
    assert!(
        matches!(&e, Error::NoSteps { mesh } if mesh == "pyramid.obj"),
        "{e}"
    );
    // Fibonacci's EV limit holds from its third step: 1 + 2 steps is too few.
    let e = (Refiner::new(&fibonacci, &mesh).steps(3).limit(true).build()).unwrap_err();
    assert!(matches!(&e, Error::NoLimit { .. }), "{e}");
    assert!(e.to_string().starts_with("pyramid.obj: "), "{e}");
    assert!(!e.to_string().contains("error:"), "{e}");
    // A curves-only scheme, and a name that is no scheme.
    let curve = Scheme::shipped("fibonacci-curve").unwrap();
    let e = Refiner::new(&curve, &mesh).build().unwrap_err();
    assert!(matches!(&e, Error::CurvesOnly { scheme, .. } if scheme == "fibonacci-curve"));
    assert!(matches!(
        Scheme::shipped("fibonaci"),
        Err(Error::UnknownScheme { .. })
    ));
    // A bad file: its line.
    let e = Mesh::parse("bad.obj", b"v 0 0 0\nf 1 2\n".to_vec()).unwrap_err();
    match &e {
        Error::File(d) => assert_eq!(d.at.as_ref().and_then(|at| at.line), Some(2), "{e}"),
        e => panic!("{e}"),
    }
}

#[test]
fn a_scheme_file_refines_like_the_shipped_scheme_of_the_same_rules() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string("schemes/fibonacci.toml").unwrap();
    let path = write(dir.path(), "fib.toml", &text);
    let file = Scheme::from_file(&path).unwrap();
    let shipped = Scheme::shipped("fibonacci").unwrap();
    let mesh = Mesh::parse("pyramid.obj", PYRAMID.as_bytes().to_vec()).unwrap();
    let refine = |s: &Scheme| {
        let plan = Refiner::new(s, &mesh).steps(4).limit(true).build().unwrap();
        plan.refine().unwrap()
    };
    assert_eq!(refine(&file), refine(&shipped));
}

/// `text` with every `v` line's position moved by `f` (the k-th vertex, its position).
fn moved(text: &str, f: impl Fn(usize, [f64; 3]) -> [f64; 3]) -> (String, Vec<[f64; 3]>) {
    let mut k = 0;
    let mut positions = Vec::new();
    let lines: Vec<String> = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let p: Vec<f64> = rest.split(' ').map(|x| x.parse().unwrap()).collect();
                let q = f(k, [p[0], p[1], p[2]]);
                k += 1;
                positions.push(q);
                format!("v {:?} {:?} {:?}", q[0], q[1], q[2])
            }
            None => line.to_string(),
        })
        .collect();
    (lines.join("\n") + "\n", positions)
}

#[test]
fn frames_refine_new_positions_as_a_plan_of_the_moved_mesh_does() {
    // Two cubes sharing a vertex (a non-manifold vertex: copies joined again), and the
    // pyramid (its first step a Catmull–Clark step).
    let bowtie = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        v 2 1 1\nv 2 2 1\nv 1 2 1\nv 1 1 2\nv 2 1 2\nv 2 2 2\nv 1 2 2\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n\
        f 7 11 10 9\nf 12 13 14 15\nf 7 9 13 12\nf 9 10 14 13\nf 10 11 15 14\nf 11 7 12 15\n";
    // Two pyramids apex to apex: triangles (a Catmull–Clark step first) at a non-manifold
    // vertex (separated, then joined).
    let twins = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nv 0 0 2\nv 1 0 2\nv 1 1 2\n\
        v 0 1 2\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nf 4 3 2 1\n\
        f 7 6 5\nf 8 7 5\nf 9 8 5\nf 6 9 5\nf 6 7 8 9\n";
    let shipped = Scheme::shipped("binary-ternary").unwrap();
    for (name, text, limit) in [
        ("bowtie.obj", bowtie, false),
        ("bowtie.obj", bowtie, true),
        ("pyramid.obj", PYRAMID, false),
        ("pyramid.obj", PYRAMID, true),
        ("twins.obj", twins, false),
        ("twins.obj", twins, true),
    ] {
        let mesh = Mesh::parse(name, text.as_bytes().to_vec()).unwrap();
        let plan = (Refiner::new(&shipped, &mesh).steps(3).limit(limit))
            .build()
            .unwrap();
        let input = plan.input();
        assert_eq!(input.split, name != "bowtie.obj", "{name}");
        assert_eq!(input.weld.is_some(), name != "pyramid.obj", "{name}");
        let mut frames = plan.frames().unwrap();
        // The positions as read: the plan's own refinement.
        let fine = plan.refine().unwrap();
        let first = frames.refine(mesh.positions()).unwrap();
        assert_eq!(first.positions, fine.mesh.positions, "{name}");
        assert_eq!(first.normals, fine.normals, "{name}");
        assert_eq!(frames.faces(), &fine.mesh.faces[..], "{name}");
        assert_eq!(frames.uv(), fine.uv.as_ref(), "{name}");
        // A frame that bends the mesh: what a plan of the bent mesh gives.
        let (text2, bent) = moved(text, |k, p| {
            [p[0] + 0.1 * p[2] * p[2], p[1], p[2] + 0.01 * k as f64]
        });
        let mesh2 = Mesh::parse(name, text2.into_bytes()).unwrap();
        let plan2 = (Refiner::new(&shipped, &mesh2).steps(3).limit(limit))
            .build()
            .unwrap();
        let want = plan2.refine().unwrap();
        let got = frames.refine(&bent).unwrap();
        assert_eq!(got.positions, want.mesh.positions, "{name}, limit {limit}");
        assert_eq!(got.normals, want.normals, "{name}, limit {limit}");
        assert_eq!(got.approximate, want.approximate, "{name}, limit {limit}");
        // A frame of the wrong size is refused, naming both counts.
        let e = frames.refine(&bent[1..]).unwrap_err();
        assert!(e.to_string().contains("positions for a mesh of"), "{e}");
    }
}

#[test]
fn frames_refine_into_f32_as_the_mesh_refiner_does() {
    use lsubdiv::mesh::patch::subdivide_with;
    use lsubdiv::Frames;
    let cube = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\n\
        v -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n\
        t crease 2/1/0 0 1 1.5\n";
    let mesh = Mesh::parse("cube.obj", cube.as_bytes().to_vec()).unwrap();
    let shipped = Scheme::shipped("fibonacci").unwrap();
    let plan = Refiner::new(&shipped, &mesh).steps(3).build().unwrap();
    let mut frames: Frames<'_, '_, f32> = plan.frames_in().unwrap();
    let in_f64 = plan.refine().unwrap().mesh.positions;
    for scale in [1.0, 1e30] {
        let positions: Vec<[f64; 3]> = mesh
            .positions()
            .iter()
            .map(|p| p.map(|x| scale * x))
            .collect();
        let frame = frames.refine(&positions).unwrap();
        // The f32 path of the mesh refiner, on the checked mesh, unscaled input.
        if scale == 1.0 {
            let input = plan.input();
            let fib = lsubdiv::generated::AnySurface::Fibonacci;
            let direct =
                subdivide_with::<_, f32>(&fib, &input.mesh, &input.topology, &input.features, 3, 1)
                    .unwrap();
            assert_eq!(frame.positions, direct.positions);
        }
        // Huge coordinates are refined scaled to magnitude 1 and come back finite.
        for (p, q) in frame.positions.iter().zip(&in_f64) {
            for (a, b) in p.iter().zip(q) {
                let (a, b) = (f64::from(*a) / scale, *b);
                assert!((a - b).abs() < 1e-5, "{scale}: {a} against {b}");
            }
        }
    }
}

/// Per-vertex values of any dimension go through the plan as positions do: three values are
/// the positions' bits; values that are an affine function of the positions refine to the same
/// function of the refined positions (the masks sum to one), with the limit too; each further
/// coordinate is refined on its own.
#[test]
fn frames_refine_values_of_any_dimension() {
    let shipped = Scheme::shipped("binary-ternary").unwrap();
    let mesh = Mesh::parse("pyramid.obj", PYRAMID.as_bytes().to_vec()).unwrap();
    for limit in [false, true] {
        let plan = (Refiner::new(&shipped, &mesh).steps(3).limit(limit))
            .build()
            .unwrap();
        let mut frames = plan.frames().unwrap();
        let positions = frames.refine(mesh.positions()).unwrap().positions;
        assert_eq!(frames.refine_values(mesh.positions()).unwrap(), positions);
        let affine = |p: &[f64; 3]| [2.0 * p[0] - p[2] + 1.0, 0.5 * p[1], -3.0, p[0] + p[1]];
        let values: Vec<[f64; 4]> = mesh.positions().iter().map(affine).collect();
        let refined = frames.refine_values(&values).unwrap();
        assert_eq!(refined.len(), positions.len());
        for (got, p) in refined.iter().zip(&positions) {
            for (a, b) in got.iter().zip(affine(p)) {
                assert!(
                    (a - b).abs() < 1e-12,
                    "limit {limit}: {got:?} against {p:?}"
                );
            }
        }
        let one: Vec<[f64; 1]> = values.iter().map(|v| [v[3]]).collect();
        let alone = frames.refine_values(&one).unwrap();
        assert!(alone.iter().zip(&refined).all(|(a, b)| a[0] == b[3]));
        let none: Vec<[f64; 0]> = vec![[]; values.len()];
        assert_eq!(frames.refine_values(&none).unwrap().len(), positions.len());
    }
}
