//! Mesh inputs as a user gives them: PLY (ASCII, binary of both byte orders,
//! any case of extension, on a pipe) refines exactly as the same OBJ does, what `subdivide`
//! writes as PLY reads back, bad PLY files are refused at their place with exit 2, pipes and
//! devices are read only up to `--max-memory`, OBJ lines continued by a `\` are read, and
//! texture coordinates (OBJ `vt`, PLY `u v` or `texcoord`) are read back as written and do not
//! change the refinement.

mod common;

use common::cli::{json, lsubdiv, stderr};
use lsubdiv::mesh::generators::{cube, star, torus};
use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Runs `lsubdiv` with `args`, `input` on its standard input.
fn lsubdiv_piped(args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let mut stdin = child.stdin.take().expect("stdin");
    // The reader may refuse before reading everything: a broken pipe is fine.
    let _ = stdin.write_all(input);
    drop(stdin);
    child.wait_with_output().expect("finishes")
}

/// Runs `subdivide uniform-binary --steps 1 INPUT -o OUT EXTRA…`, `stdin` on its standard input.
fn one_step(input: &str, out: &Path, extra: &[&str], stdin: &[u8]) -> Output {
    let out = out.display().to_string();
    let mut args = vec![
        "subdivide",
        "uniform-binary",
        "--steps",
        "1",
        input,
        "-o",
        &out,
    ];
    args.extend(extra);
    lsubdiv_piped(&args, stdin)
}

/// [`one_step`] that must succeed, and the output's bytes.
fn subdivide(input: &str, out: &Path) -> Vec<u8> {
    let o = one_step(input, out, &[], b"");
    assert!(o.status.success(), "{input}: {}", stderr(&o));
    std::fs::read(out).unwrap()
}

#[test]
fn ply_of_every_encoding_refines_as_the_same_obj() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let m = star();
    let obj = d.join("star.obj");
    std::fs::write(&obj, lsubdiv::obj::format(&m).unwrap()).unwrap();
    let expected = subdivide(&obj.display().to_string(), &d.join("expected.obj"));
    let inputs: [(&str, Vec<u8>); 5] = [
        ("star.ply", lsubdiv::ply::format(&m).unwrap().into_bytes()),
        ("star-le.PLY", lsubdiv::ply::binary(&m, false).unwrap()),
        ("star-be.Ply", lsubdiv::ply::binary(&m, true).unwrap()),
        // Content decides: a PLY file without the extension, an OBJ named `.obj` in capitals.
        (
            "star-ply-without-extension",
            lsubdiv::ply::binary(&m, true).unwrap(),
        ),
        ("STAR.OBJ", lsubdiv::obj::format(&m).unwrap().into_bytes()),
    ];
    for (name, bytes) in inputs {
        let input = d.join(name);
        std::fs::write(&input, &bytes).unwrap();
        let got = subdivide(&input.display().to_string(), &d.join("got.obj"));
        assert!(got == expected, "{name} refines differently from the OBJ");
        // On a pipe, as `-` and as /dev/stdin.
        for arg in ["-", "/dev/stdin"] {
            let out = d.join("piped.obj");
            let o = one_step(arg, &out, &[], &bytes);
            assert!(o.status.success(), "{name} on {arg}: {}", stderr(&o));
            assert!(std::fs::read(&out).unwrap() == expected, "{name} on {arg}");
        }
    }
    // `render` and `bench` read the same way.
    let ply = d.join("star-le.PLY").display().to_string();
    let png = |input: &str, out: &str| {
        let out = d.join(out);
        let o = lsubdiv(&[
            "render",
            input,
            "--size",
            "64x48",
            "-o",
            &out.display().to_string(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    assert!(png(&ply, "ply.png") == png(&obj.display().to_string(), "obj.png"));
    let v = json(&[
        "bench",
        "--json",
        "--mesh",
        &ply,
        "--scheme",
        "uniform-binary",
        "--steps",
        "1",
        "--runs",
        "1",
    ]);
    let (nv, nf) = (m.positions.len(), m.faces.len());
    // One binary step: V + E + F vertices, E = 2F.
    assert_eq!(v["output_vertices"], nv + 3 * nf);
}

#[test]
fn what_subdivide_writes_as_ply_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = d.join("cube.obj");
    std::fs::write(&input, lsubdiv::obj::format(&cube()).unwrap()).unwrap();
    let input = input.display().to_string();
    for steps in ["1", "3"] {
        let (obj, ply, bin) = (d.join("fine.obj"), d.join("fine.ply"), d.join("bin.ply"));
        for (out, binary) in [(&obj, None), (&ply, None), (&bin, Some("--binary"))] {
            let out = out.display().to_string();
            let mut args = vec![
                "subdivide",
                "binary-ternary",
                "--steps",
                steps,
                &input,
                "-o",
                &out,
            ];
            args.extend(binary);
            let o = lsubdiv(&args);
            assert!(o.status.success(), "{}", stderr(&o));
        }
        let from_obj = lsubdiv::mesh_file::read_checked(&obj, u64::MAX).unwrap();
        let from_ply = lsubdiv::mesh_file::read_checked(&ply, u64::MAX).unwrap();
        assert!(from_ply.warnings.is_empty(), "{:?}", from_ply.warnings);
        assert_eq!(from_ply.mesh, from_obj.mesh, "{steps} steps");
        // `--binary`: a binary PLY of the same mesh, bit for bit: 24 bytes a vertex, 17 a quad.
        assert!(std::fs::read(&bin)
            .unwrap()
            .starts_with(b"ply\nformat binary_little_endian 1.0\n"));
        let from_bin = lsubdiv::mesh_file::read_checked(&bin, u64::MAX).unwrap();
        assert!(from_bin.warnings.is_empty(), "{:?}", from_bin.warnings);
        assert_eq!(from_bin.mesh, from_ply.mesh, "{steps} steps");
        let bytes = std::fs::read(&bin).unwrap();
        let m = &from_bin.mesh;
        assert_eq!(
            bytes.len(),
            body_start(&bytes) + 24 * m.positions.len() + 17 * m.faces.len()
        );
        // And once more through the command line: the PLY refines as the OBJ.
        let a = subdivide(&obj.display().to_string(), &d.join("a.obj"));
        let b = subdivide(&ply.display().to_string(), &d.join("b.obj"));
        assert!(a == b, "{steps} steps");
    }
}

/// `--binary` writes PLY only: asked of an OBJ output (by extension or `-`), it is refused
/// before anything is read, and nothing is written.
#[test]
fn binary_output_is_ply_only() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cube.obj");
    std::fs::write(&input, lsubdiv::obj::format(&cube()).unwrap()).unwrap();
    let out = dir.path().join("fine.obj");
    for target in [out.display().to_string(), "-".to_string()] {
        let input = input.display().to_string();
        let o = lsubdiv(&[
            "subdivide",
            "uniform-binary",
            "--steps",
            "1",
            &input,
            "-o",
            &target,
            "--binary",
        ]);
        assert_eq!(o.status.code(), Some(2), "{target}");
        assert!(
            stderr(&o).contains("--binary: ") && stderr(&o).contains("name a `.ply` output"),
            "{}",
            stderr(&o)
        );
        assert!(o.stdout.is_empty());
    }
    assert!(!out.exists());
}

/// Where the data of a PLY file begins: after its `end_header` line.
fn body_start(bytes: &[u8]) -> usize {
    let end = b"end_header\n";
    bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len()
}

/// The cube as binary little-endian PLY, and where its data begins.
fn cube_le() -> (Vec<u8>, usize) {
    let bytes = lsubdiv::ply::binary(&cube(), false).unwrap();
    let h = body_start(&bytes);
    (bytes, h)
}

/// One row per kind of bad PLY file: exit 2, the place and a fragment of the message, the
/// output untouched.
#[test]
fn bad_ply_files_are_refused_at_their_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let ascii = lsubdiv::ply::format(&cube()).unwrap(); // header 1–10, vertices 11–18, faces 19–24
    let (le, h) = cube_le();
    let mut truncated = le.clone();
    truncated.truncate(le.len() - 2);
    let mut far = le.clone();
    let index = h + 8 * 24 + 17 + 1; // face 1, first index
    far[index..index + 4].copy_from_slice(&8u32.to_le_bytes());
    let mut inf = le.clone();
    inf[h + 5 * 24..h + 5 * 24 + 8].copy_from_slice(&f64::INFINITY.to_le_bytes());
    let tiny_huge = b"ply\nformat binary_big_endian 1.0\nelement vertex 4000000000\n\
        property float x\nproperty float y\nproperty float z\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n\0\0\0\0"
        .to_vec();
    let lines: Vec<&str> = ascii.lines().collect();
    let replace_line = |n: usize, new: &str| {
        let mut l = lines.clone();
        l[n - 1] = new;
        (l.join("\n") + "\n").into_bytes()
    };
    let cases: Vec<(&str, Vec<u8>, String, String)> = vec![
        (
            "magic.ply",
            ascii.replacen("ply", "PLY", 1).into_bytes(),
            ":1:1".into(),
            "not a PLY file: the first line must be `ply`".into(),
        ),
        (
            "format.ply",
            ascii.replace("ascii 1.0", "utf8 1.0").into_bytes(),
            ":2:8".into(),
            "unknown format `utf8`".into(),
        ),
        (
            "noend.ply",
            ascii.replace("end_header\n", "").into_bytes(),
            ":10:1".into(),
            "unknown header line `-1.0`".into(),
        ),
        (
            "cut.ply",
            ascii.split("end_header").next().unwrap().into(),
            ":9".into(),
            "the header ends without an `end_header` line".into(),
        ),
        (
            "truncated.ply",
            truncated,
            "".into(),
            format!(
                "face 5, property `vertex_indices`, byte {}: the file ends inside this element",
                h + 8 * 24 + 5 * 17 + 13
            ),
        ),
        (
            "index.ply",
            replace_line(21, "4 0 1 2 8"),
            ":21".into(),
            "vertex index 8 out of range (the file has 8 vertices)".into(),
        ),
        (
            "index-le.ply",
            far,
            "".into(),
            format!(
                "face 1, byte {}: vertex index 8 out of range (the file has 8 vertices)",
                h + 8 * 24 + 17
            ),
        ),
        (
            "nan.ply",
            replace_line(15, "1 NaN 1"),
            ":15:3".into(),
            "vertex 4, property `y`: coordinate `NaN` is not finite".into(),
        ),
        (
            "inf.ply",
            inf,
            "".into(),
            format!(
                "vertex 5, property `x`, byte {}: coordinate inf is not finite",
                h + 5 * 24
            ),
        ),
        (
            "number.ply",
            replace_line(12, "1 1 1x"),
            ":12:5".into(),
            "vertex 1, property `z`: `1x` is not a double".into(),
        ),
        (
            "huge.ply",
            tiny_huge,
            ":3".into(),
            "4000000000 `vertex` elements of at least 12 bytes each do not fit in the 4 bytes left"
                .into(),
        ),
        (
            "count.ply",
            ascii
                .replace("face 6", "face 123456789012345678901234567890")
                .into_bytes(),
            ":8:14".into(),
            "does not fit 64 bits".into(),
        ),
        (
            "type.ply",
            ascii.replace("double z", "quad z").into_bytes(),
            ":7:10".into(),
            "unknown type `quad`".into(),
        ),
    ];
    let out = d.join("out.obj");
    std::fs::write(&out, "previous").unwrap();
    for (name, bytes, at, fragment) in cases {
        let input = d.join(name);
        std::fs::write(&input, &bytes).unwrap();
        let input = input.display().to_string();
        let start = std::time::Instant::now();
        let o = one_step(&input, &out, &[], b"");
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {e}");
        assert!(
            e.starts_with(&format!("{input}{at}: error: ")),
            "{name}: {e}"
        );
        assert!(e.contains(&fragment), "{name}: {e}\nexpected {fragment}");
        assert!(
            start.elapsed().as_secs() < 10,
            "{name} took {:?}",
            start.elapsed()
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous");
    }
}

#[test]
fn pipes_and_devices_are_read_only_up_to_the_memory_limit() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.obj");
    let run = |input: &str, stdin: &[u8]| one_step(input, &out, &["--max-memory", "1M"], stdin);
    // 1 MiB / 5 = 209715 bytes read at most.
    for (o, name) in [
        (run("/dev/zero", b""), "/dev/zero"),
        (run("-", &vec![b' '; 300_000]), "/dev/stdin"),
    ] {
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(
            e.starts_with(&format!(
                "{name}: error: the input has more than 209715 bytes"
            )),
            "{e}"
        );
        assert!(e.contains("--max-memory is ~1.0 MiB"), "{e}");
        assert!(!out.exists());
    }
    // Under the limit, the same pipe is read.
    let o = run("-", lsubdiv::ply::format(&cube()).unwrap().as_bytes());
    assert!(o.status.success(), "{}", stderr(&o));
    // A PLY file is refused before parsing when its data could exceed the limit.
    let big = dir.path().join("big.ply");
    std::fs::write(&big, lsubdiv::ply::binary(&torus(60, 60), false).unwrap()).unwrap();
    let big = big.display().to_string();
    let o = run(&big, b"");
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.starts_with(&format!("{big}: error: the file has")), "{e}");
    assert!(e.contains("--max-memory is ~1.0 MiB"), "{e}");
}

#[test]
fn obj_lines_continued_by_a_backslash() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plain = lsubdiv::obj::format(&cube()).unwrap();
    let expected = {
        let p = d.join("plain.obj");
        std::fs::write(&p, &plain).unwrap();
        subdivide(&p.display().to_string(), &d.join("expected.obj"))
    };
    // Every face split after its second corner: LF, CRLF, spaces after the `\`.
    for (name, sep, eol) in [
        ("lf.obj", " \\\n", "\n"),
        ("crlf.obj", " \\\r\n", "\r\n"),
        ("spaces.obj", "\\   \n  ", "\n"),
    ] {
        let text: String = plain
            .lines()
            .map(|l| match l.strip_prefix("f ") {
                Some(rest) => {
                    let c: Vec<&str> = rest.split(' ').collect();
                    format!("f {} {}{sep}{} {}{eol}", c[0], c[1], c[2], c[3])
                }
                None => format!("{l}{eol}"),
            })
            .collect();
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        let got = subdivide(&p.display().to_string(), &d.join("got.obj"));
        assert!(got == expected, "{name}");
    }
    // A `\` on the last line ends the file; an error after a continuation names its own line.
    let p = d.join("last.obj");
    std::fs::write(&p, format!("{}\\", plain.trim_end())).unwrap();
    assert!(subdivide(&p.display().to_string(), &d.join("got.obj")) == expected);
    let first = plain.lines().find(|l| l.starts_with("f ")).unwrap();
    let c: Vec<&str> = first.split(' ').collect();
    let bad = plain.replacen(first, &format!("f {} {} \\\n\\\n{} x", c[1], c[2], c[3]), 1);
    let p = d.join("bad.obj");
    std::fs::write(&p, &bad).unwrap();
    let line = bad.lines().position(|l| l.ends_with(" x")).unwrap() + 1;
    let o = one_step(&p.display().to_string(), &d.join("bad-out.obj"), &[], b"");
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.starts_with(&format!(
            "{}:{line}: error: `x` is not a face corner",
            p.display()
        )),
        "{e}"
    );
}

/// A textured OBJ or PLY (per vertex or per corner) refines to the plain file's mesh, now with
/// its refined texture coordinates.
#[test]
fn textured_files_refine_as_the_plain_ones_with_their_uvs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let m = star();
    let plain = d.join("plain.obj");
    std::fs::write(&plain, lsubdiv::obj::format(&m).unwrap()).unwrap();
    let expected = subdivide(&plain.display().to_string(), &d.join("expected.obj"));
    // Per vertex (seamless) and per corner (a seam at every vertex): OBJ and PLY.
    let per_vertex = lsubdiv::mesh::facevarying::QuadUv {
        values: m.positions.iter().map(|p| [p[0], p[2]]).collect(),
        faces: m.faces.clone(),
    };
    let per_corner = lsubdiv::mesh::facevarying::QuadUv {
        values: (0..4 * m.faces.len()).map(|k| [k as f64, 0.5]).collect(),
        faces: (0..m.faces.len() as u32)
            .map(|f| [4 * f, 4 * f + 1, 4 * f + 2, 4 * f + 3])
            .collect(),
    };
    for (k, uv) in [per_vertex, per_corner].iter().enumerate() {
        let extras = lsubdiv::mesh_file::Extras {
            normals: None,
            uv: Some(uv),
        };
        for (name, text) in [
            ("t.obj", lsubdiv::obj::format_with(&m, extras).unwrap()),
            ("t.ply", lsubdiv::ply::format_with(&m, extras).unwrap()),
        ] {
            let p = d.join(format!("{k}-{name}"));
            std::fs::write(&p, &text).unwrap();
            // The same mesh, now with its refined texture coordinates (`vt`, `v/vt`).
            let got = subdivide(&p.display().to_string(), &d.join("got.obj"));
            let got = String::from_utf8(got).unwrap();
            assert!(got.lines().any(|l| l.starts_with("vt ")), "{k}-{name}");
            let without_uv: String = (got.lines())
                .filter(|l| !l.starts_with("vt "))
                .map(|l| {
                    let words = l.split_whitespace();
                    let words: Vec<&str> = words.map(|w| w.split('/').next().unwrap()).collect();
                    words.join(" ") + "\n"
                })
                .collect();
            assert!(without_uv.as_bytes() == expected, "{k}-{name}");
            let read = lsubdiv::mesh_file::parse_checked(name, text.into_bytes()).unwrap();
            let back = read.uv.expect("texture coordinates");
            let at = |uv: &lsubdiv::mesh::facevarying::QuadUv| -> Vec<[f64; 2]> {
                uv.faces
                    .iter()
                    .flatten()
                    .map(|&i| uv.values[i as usize])
                    .collect()
            };
            assert_eq!(at(&back), at(uv), "{k}-{name}");
        }
    }
    // Faces with and without texture indices are refused at the first face that differs.
    let mixed = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nvt 0 0\n\
                 f 1/1 2/1 3/1 4/1\nf 2 5 3\n";
    let p = d.join("mixed.obj");
    std::fs::write(&p, mixed).unwrap();
    let o = one_step(&p.display().to_string(), &d.join("mixed-out.obj"), &[], b"");
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.starts_with(&format!(
            "{}:8: error: this face has no texture indices, but the face at line 7 has them",
            p.display()
        )),
        "{e}"
    );
}
