//! Triangles and n-gons: a mesh with faces that are not quads
//! is taken one Catmull–Clark step first (OpenSubdiv's Catmark: every n-gon becomes n quads),
//! then the scheme's steps follow. The step is checked against the independent reference of
//! `lsubdiv_testkit::catmull_clark`, bit for bit, through the library and the command line.

mod common;

use common::cli::{lsubdiv, stderr, write};
use lsubdiv::mesh::features::Features;
use lsubdiv::mesh::generators::{cube, torus};
use lsubdiv::mesh::polygon::{catmull_clark, PolyMesh};
use lsubdiv::mesh::QuadMesh;
use lsubdiv_testkit::catmull_clark::catmull_clark_polygons;

/// A pentagonal prism whose top is a fan of five triangles around an apex: a triangle, quad
/// and pentagon mesh (11 vertices, 11 faces, closed, consistently oriented).
fn mixed() -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let mut p = Vec::new();
    for z in [0.0, 1.0] {
        for i in 0..5 {
            let t = std::f64::consts::TAU * f64::from(i) / 5.0;
            p.push([t.cos(), t.sin(), z]);
        }
    }
    p.push([0.1, -0.2, 1.7]);
    let mut faces = vec![vec![4, 3, 2, 1, 0]];
    for i in 0..5u32 {
        let j = (i + 1) % 5;
        faces.push(vec![i, j, j + 5, i + 5]);
        faces.push(vec![i + 5, j + 5, 10]);
    }
    (p, faces)
}

fn tetrahedron() -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let p = vec![
        [1.0, 1.0, 1.0],
        [-1.0, -1.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, -1.0, -1.0],
    ];
    (
        p,
        vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]],
    )
}

fn poly(p: &[[f64; 3]], faces: &[Vec<u32>]) -> PolyMesh {
    let mut m = PolyMesh::new();
    m.positions = p.to_vec();
    for f in faces {
        m.push_face(f);
    }
    m
}

fn bits(m: &QuadMesh) -> Vec<u64> {
    m.positions.iter().flatten().map(|x| x.to_bits()).collect()
}

fn obj(p: &[[f64; 3]], faces: &[Vec<u32>]) -> String {
    let mut s = String::new();
    for v in p {
        s += &format!("v {:?} {:?} {:?}\n", v[0], v[1], v[2]);
    }
    for f in faces {
        let corners: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        s += &format!("f {}\n", corners.join(" "));
    }
    s
}

#[test]
fn the_split_is_the_reference_catmull_clark_step() {
    let quads = |m: QuadMesh| -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
        let f = m.faces.iter().map(|f| f.to_vec()).collect();
        (m.positions, f)
    };
    for (name, (p, faces)) in [
        ("tetrahedron", tetrahedron()),
        ("mixed", mixed()),
        ("cube", quads(cube())),
        ("torus", quads(torus(5, 7))),
    ] {
        let ours = catmull_clark(&poly(&p, &faces), &Features::default()).unwrap();
        let reference = catmull_clark_polygons(&p, &faces);
        assert_eq!(ours.mesh.faces, reference.faces, "{name}");
        assert_eq!(bits(&ours.mesh), bits(&reference), "{name}");
        // Every n-gon becomes n quads, in face order.
        let face_of: Vec<u32> = faces
            .iter()
            .enumerate()
            .flat_map(|(f, c)| std::iter::repeat_n(f as u32, c.len()))
            .collect();
        assert_eq!(ours.face_of, face_of, "{name}");
    }
}

#[test]
fn subdivide_takes_the_first_step_by_catmull_clark_then_the_scheme() {
    let dir = tempfile::tempdir().unwrap();
    let (p, faces) = mixed();
    let input = write(dir.path(), "mixed.obj", &obj(&p, &faces));
    let out = dir.path().join("out.obj");
    let run = |scheme: &str, steps: &str| {
        lsubdiv(&[
            "subdivide",
            scheme,
            "--steps",
            steps,
            &input,
            "-o",
            out.to_str().unwrap(),
        ])
    };
    let read = || lsubdiv::mesh_file::read_checked(&out, u64::MAX).unwrap();
    // One step: exactly the reference step, whatever the scheme.
    let reference = catmull_clark_polygons(&p, &faces);
    for scheme in ["uniform-binary", "binary-ternary"] {
        let o = run(scheme, "1");
        assert!(o.status.success(), "{}", stderr(&o));
        let back = read();
        assert!(!back.split);
        assert_eq!(back.mesh.faces, reference.faces, "{scheme}");
        assert_eq!(bits(&back.mesh), bits(&reference), "{scheme}");
    }
    // Then the scheme's steps on the quads: Σn quads after the split, then |π²(axiom)|² quads
    // from each after two steps (uniform binary: 4² ; binary-ternary, C → LCR → LC LCR CR: 7²),
    // closed (E = 2F).
    let split_quads = faces.iter().map(Vec::len).sum::<usize>();
    for (scheme, edge) in [("uniform-binary", 4), ("binary-ternary", 7)] {
        let o = run(scheme, "3");
        assert!(o.status.success(), "{}", stderr(&o));
        let back = read();
        assert_eq!(back.mesh.faces.len(), split_quads * edge * edge);
        assert_eq!(back.topology.edge_count(), 2 * back.topology.face_count());
    }
    // The split is counted against --max-memory before it is made.
    let o = lsubdiv(&[
        "subdivide",
        "uniform-binary",
        "--steps",
        "1",
        &input,
        "-o",
        out.to_str().unwrap(),
        "--max-memory",
        "3K",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("checking its 11 faces, split into 40 quads by the first (Catmull–Clark) step, would hold"),
        "{}",
        stderr(&o)
    );
    // No step is refused: the split is a step.
    let o = run("uniform-binary", "0");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("faces that are not quads"),
        "{}",
        stderr(&o)
    );
    // PLY triangles read as the OBJ ones do.
    let (tp, tf) = tetrahedron();
    let mut ply = String::from(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n\
         property double z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n",
    );
    for v in &tp {
        ply += &format!("{:?} {:?} {:?}\n", v[0], v[1], v[2]);
    }
    for f in &tf {
        ply += &format!("3 {} {} {}\n", f[0], f[1], f[2]);
    }
    let from_ply = lsubdiv::mesh_file::parse_checked("t.ply", ply.into_bytes()).unwrap();
    let from_obj = lsubdiv::mesh_file::parse_checked("t.obj", obj(&tp, &tf).into_bytes()).unwrap();
    assert!(from_ply.split && from_obj.split);
    assert_eq!(bits(&from_ply.mesh), bits(&from_obj.mesh));
}

#[test]
fn errors_on_polygon_meshes_name_the_files_faces() {
    let (p, mut faces) = tetrahedron();
    // An open tetrahedron (the last face removed) is an open mesh: read and split.
    faces.pop();
    let open = lsubdiv::mesh_file::parse_checked("t.obj", obj(&p, &faces).into_bytes()).unwrap();
    assert!(open.split && !open.topology.is_closed());
    // An index out of range, at its face's line.
    let e = lsubdiv::mesh_file::parse_checked(
        "t.obj",
        obj(&p, &[vec![0, 1, 2], vec![0, 1, 7]]).into_bytes(),
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("t.obj:6: error:"), "{e}");
    // A vertex twice in a face is a degenerate edge, refined as OpenSubdiv refines it.
    let repeated = obj(&p, &[vec![0, 1, 0], vec![0, 1, 2]]);
    let read = lsubdiv::mesh_file::parse_checked("t.obj", repeated.into_bytes()).unwrap();
    assert!(read.weld.is_some() && read.split);
    // Two tetrahedra sharing vertex 1 only: a non-manifold vertex, each fan on its own.
    let (mut p2, mut f2) = tetrahedron();
    let shift = p2.len() as u32 - 1;
    for v in &tetrahedron().0[1..] {
        p2.push([v[0] + 3.0, v[1], v[2]]);
    }
    for f in tetrahedron().1 {
        f2.push(
            f.iter()
                .map(|&v| if v == 0 { 1 } else { v + shift })
                .collect(),
        );
    }
    let read = lsubdiv::mesh_file::parse_checked("t.obj", obj(&p2, &f2).into_bytes()).unwrap();
    assert!(
        (read.warnings.iter()).any(|w| w.contains("1 non-manifold vertex")),
        "{:?}",
        read.warnings
    );
}

#[test]
fn the_built_in_prisms_have_polygon_caps_split_first() {
    for n in [3, 5, 7] {
        let m = lsubdiv::mesh::generators::polygon_prism(n);
        let faces: Vec<Vec<u32>> = m.faces().map(<[u32]>::to_vec).collect();
        let input = lsubdiv_cli::bench::mesh(&format!("prism:{n}"), u64::MAX, None).unwrap();
        assert!(input.split);
        let reference = catmull_clark_polygons(&m.positions, &faces);
        assert_eq!(input.mesh.faces, reference.faces, "prism:{n}");
        assert_eq!(bits(&input.mesh), bits(&reference), "prism:{n}");
    }
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("p.png");
    let o = lsubdiv(&[
        "render",
        "prism:5",
        "--scheme",
        "binary-ternary",
        "--steps",
        "2",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = lsubdiv(&["render", "prism:2", "-o", png.to_str().unwrap()]);
    assert_eq!(e.status.code(), Some(2));
    assert!(stderr(&e).contains("a prism has 3 to 10000 sides"));
}
