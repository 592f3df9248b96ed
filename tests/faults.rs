//! Issue 14, kinds 2 and 3, as a demanding user meets them: finite input never gives a
//! non-finite output (coordinates at the edges of the f64 range around high-valence vertices,
//! huge curves, pictures of such data), `render` frames any scale, and `--max-memory` bounds
//! render's image buffers, pictures and point files read from pipes or devices.

mod common;

use common::cli::{lsubdiv, stderr, write};
use lsubdiv::mesh::generators::{prism, torus};
use lsubdiv::mesh::QuadMesh;
use std::path::Path;

/// `mesh` with every coordinate multiplied by `s` and shifted by `t`.
fn moved(mesh: &QuadMesh, s: f64, t: [f64; 3]) -> QuadMesh {
    QuadMesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| [0, 1, 2].map(|c| p[c] * s + t[c]))
            .collect(),
        faces: mesh.faces.clone(),
    }
}

fn write_mesh(dir: &Path, name: &str, m: &QuadMesh) -> String {
    write(dir, name, &lsubdiv::obj::format(m).unwrap())
}

/// Runs `subdivide` and reads the result back with lsubdiv's own reader.
fn subdivide(dir: &Path, input: &str, scheme: &str, steps: &str) -> QuadMesh {
    let out = dir.join("out.obj");
    let o = lsubdiv(&[
        "subdivide",
        scheme,
        input,
        "-o",
        out.to_str().unwrap(),
        "--steps",
        steps,
    ]);
    assert!(o.status.success(), "{input}: {}", stderr(&o));
    lsubdiv::mesh_file::read_checked(&out, u64::MAX)
        .unwrap_or_else(|e| panic!("{input}: lsubdiv refuses its own output: {e}"))
        .mesh
}

#[test]
fn coordinates_near_the_ends_of_f64_refine_exactly_as_at_scale_one() {
    // (valence of the two cap centres, power of two scaling the mesh, scheme, steps): the
    // masks are affine, so the result is the unit mesh's scaled by the same power of two,
    // exactly, even where the plain f64 sums overflow (200 neighbours of 2^1023).
    let rows: [(usize, i32, &str, &str); 6] = [
        (12, 1000, "binary-ternary", "2"),
        (12, 1023, "binary-ternary", "2"),
        (200, 1020, "binary-ternary", "2"),
        (200, 1023, "uniform-binary", "3"),
        (50, -1000, "binary-ternary", "2"),
        (50, 600, "fibonacci", "2"),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (n, e, scheme, steps) in rows {
        let unit = prism(n);
        let s = 2f64.powi(e);
        let base = subdivide(
            dir.path(),
            &write_mesh(dir.path(), "unit.obj", &unit),
            scheme,
            steps,
        );
        let big = subdivide(
            dir.path(),
            &write_mesh(dir.path(), "big.obj", &moved(&unit, s, [0.0; 3])),
            scheme,
            steps,
        );
        assert_eq!(big.faces, base.faces);
        for (a, b) in big.positions.iter().zip(&base.positions) {
            assert!(a.iter().all(|x| x.is_finite()), "valence {n}, 2^{e}: {a:?}");
            assert_eq!(*a, b.map(|x| x * s), "valence {n}, 2^{e}, {scheme}");
        }
    }
}

#[test]
fn huge_curves_refine_exactly_and_finite() {
    let square = [
        [1.0, 1.0],
        [-1.0, 0.75],
        [-0.5, -1.0],
        [1.0, -0.5],
        [0.25, 0.0],
    ];
    let dir = tempfile::tempdir().unwrap();
    let points = |s: f64| -> String {
        square
            .iter()
            .map(|p| format!("{:?} {:?}\n", p[0] * s, p[1] * s))
            .collect()
    };
    let refine = |name: &str, s: f64, scheme: &str, closed: bool| -> Vec<Vec<f64>> {
        let input = write(dir.path(), name, &points(s));
        let out = dir.path().join(format!("{name}.out"));
        let mut args = vec![
            "curve",
            scheme,
            &input,
            "-o",
            out.to_str().unwrap(),
            "--steps",
            "5",
        ];
        if closed {
            args.push("--closed");
        }
        let o = lsubdiv(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        std::fs::read_to_string(&out)
            .unwrap()
            .lines()
            .map(|l| l.split(' ').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    for (scheme, closed) in [("uniform-binary", true), ("fibonacci-curve", false)] {
        let unit = refine("unit.txt", 1.0, scheme, closed);
        for e in [1023, -1022] {
            let s = 2f64.powi(e);
            let big = refine("big.txt", s, scheme, closed);
            assert_eq!(big.len(), unit.len());
            for (a, b) in big.iter().zip(&unit) {
                assert!(a.iter().all(|x| x.is_finite()), "{scheme} 2^{e}: {a:?}");
                let scaled: Vec<f64> = b.iter().map(|x| x * s).collect();
                assert_eq!(*a, scaled, "{scheme} 2^{e}");
            }
        }
    }
}

#[test]
fn writers_refuse_non_finite_coordinates() {
    let mut m = torus(3, 3);
    m.positions[4][1] = f64::INFINITY;
    for e in [
        lsubdiv::obj::format(&m).unwrap_err(),
        lsubdiv::ply::format(&m).unwrap_err(),
    ] {
        assert!(e.message.contains("vertex 5 has a non-finite"), "{e}");
    }
    let e = lsubdiv::points::format(&[[0.0, 1.0], [f64::NAN, 2.0]]).unwrap_err();
    assert!(e.message.contains("point 2 has a non-finite"), "{e}");
    // Limit points with their tangents: the first line with a non-finite value in any column
    // set is named; finite ones are written side by side, at round-trip precision.
    let (p, t) = (
        [[0.5, 1.0], [2.0, 3.0], [4.0, 5.0]],
        [[0.1, 1.0], [1.0, f64::INFINITY], [f64::NAN, 0.0]],
    );
    let e = lsubdiv::points::Text::with_columns(vec![&p, &t])
        .err()
        .unwrap();
    assert!(e.message.contains("point 2 has a non-finite"), "{e}");
    let text = lsubdiv::points::Text::with_columns(vec![&p[..1], &t[..1]]).unwrap();
    assert_eq!(text.to_string(), "0.5 1.0 0.1 1.0\n");
    assert!(lsubdiv::obj::format(&torus(3, 3)).is_ok());
}

/// Decoded RGB pixels of a PNG.
fn pixels(path: &Path) -> Vec<[u8; 3]> {
    let mut reader = png::Decoder::new(std::fs::File::open(path).unwrap())
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf[..info.buffer_size()]
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect()
}

#[test]
fn render_frames_the_mesh_at_any_scale_with_finite_curvature() {
    let unit = prism(9);
    let mut flat = unit.clone();
    flat.positions.iter_mut().for_each(|p| p[2] = 0.0);
    // (name, mesh, fewest colours): tiny, huge, far from the origin, subnormal, and flat in one
    // axis (a plane: one shade, and its antialiased silhouette).
    let rows = [
        ("tiny", moved(&unit, 1e-300, [0.0; 3]), 20),
        ("huge", moved(&unit, 1e300, [0.0; 3]), 20),
        ("far", moved(&unit, 1.0, [1e15, -1e15, 1e15]), 20),
        ("subnormal", moved(&unit, 1e-310, [0.0; 3]), 20),
        ("flat", flat, 3),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (name, mesh, fewest) in rows {
        let input = write_mesh(dir.path(), &format!("{name}.obj"), &mesh);
        for shading in ["smooth", "curvature"] {
            let out = dir.path().join(format!("{name}.{shading}.png"));
            let o = lsubdiv(&[
                "render",
                &input,
                "-o",
                out.to_str().unwrap(),
                "--shading",
                shading,
                "--size",
                "240x160",
            ]);
            let err = stderr(&o);
            assert!(o.status.success(), "{name} {shading}: {err}");
            assert!(
                !err.contains("inf") && !err.contains("NaN"),
                "{name} {shading}: {err}"
            );
            let px = pixels(&out);
            let mut colours = px.clone();
            colours.sort_unstable();
            colours.dedup();
            let object = px.iter().filter(|&&p| p != [255; 3]).count();
            assert!(
                colours.len() >= fewest && object > 2000,
                "{name} {shading}: {} colours, {object} object pixels",
                colours.len()
            );
        }
    }
}

#[test]
fn image_buffers_and_streamed_point_files_are_bounded_by_max_memory() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("big.png");
    let svg_out = dir.path().join("p.png");
    let txt = dir.path().join("c.txt");
    let (png, svg_out, txt) = (
        png.to_str().unwrap(),
        svg_out.to_str().unwrap(),
        txt.to_str().unwrap(),
    );
    // (arguments, what the message says, the output that must not appear)
    let rows: [(Vec<&str>, &[&str], &str); 5] = [
        (
            vec![
                "render",
                "cube",
                "-o",
                png,
                "--size",
                "10000x10000",
                "--max-memory",
                "100M",
            ],
            &[
                "10000x10000 picture",
                "--max-memory is ~100.0 MiB",
                "--size",
            ],
            png,
        ),
        (
            vec![
                "render",
                "torus:300:300",
                "-o",
                png,
                "--size",
                "2000x2000",
                "--max-memory",
                "150M",
            ],
            &["of 90 000 quads", "--max-memory is ~150.0 MiB"],
            png,
        ),
        (
            vec![
                "plot",
                "uniform-binary",
                "-o",
                svg_out,
                "--size",
                "10000x10000",
                "--max-memory",
                "64M",
            ],
            &["10000x10000 picture", "--max-memory is ~64.0 MiB"],
            svg_out,
        ),
        (
            vec![
                "curve",
                "uniform-binary",
                "/dev/zero",
                "-o",
                txt,
                "--steps",
                "1",
                "--max-memory",
                "10M",
            ],
            &[
                "/dev/zero: error:",
                "more than 2097152 bytes",
                "--max-memory is ~10.0 MiB",
            ],
            txt,
        ),
        (
            vec![
                "plot",
                "uniform-binary",
                "/dev/zero",
                "-o",
                svg_out,
                "--max-memory",
                "10M",
            ],
            &["/dev/zero: error:", "more than 2097152 bytes"],
            svg_out,
        ),
    ];
    for (args, says, output) in rows {
        let o = lsubdiv(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        for s in says {
            assert!(err.contains(s), "{args:?}: `{s}` not in {err}");
        }
        assert!(!Path::new(output).exists(), "{args:?} wrote {output}");
    }
    // A plot's limit curve is counted as it is refined to a pixel: past what the levels and
    // the picture leave, it is refused and nothing is written; with room, drawn.
    let svg = dir.path().join("h.svg");
    let plot = |max: &str| {
        lsubdiv(&[
            "plot",
            "uniform-binary",
            "-o",
            svg.to_str().unwrap(),
            "--max-memory",
            max,
        ])
    };
    let o = plot("400K");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("drawing the limit curve to a pixel refines it to up to"),
        "{}",
        stderr(&o)
    );
    assert!(!svg.exists());
    let o = plot("2M");
    assert!(o.status.success() && svg.exists(), "{}", stderr(&o));
    // Within the limit the same render is drawn.
    let o = lsubdiv(&[
        "render",
        "cube",
        "-o",
        png,
        "--size",
        "400x300",
        "--max-memory",
        "100M",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn plots_frame_data_at_the_ends_of_f64() {
    let dir = tempfile::tempdir().unwrap();
    let square = |s: f64| format!("{s:e} {s:e}\n-{s:e} {s:e}\n-{s:e} -{s:e}\n{s:e} -{s:e}\n");
    for s in [1e-300, 1e300, 1.7e308] {
        let input = write(dir.path(), "sq.txt", &square(s));
        let out = dir.path().join("sq.svg");
        let o = lsubdiv(&[
            "plot",
            "uniform-binary",
            &input,
            "--closed",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{s}: {}", stderr(&o));
        let svg = std::fs::read_to_string(&out).unwrap();
        assert!(
            !svg.contains("NaN") && !svg.contains("inf") && !svg.contains("922337203685"),
            "{s}"
        );
    }
}
