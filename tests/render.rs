//! `lsubdiv render` as a user runs it: every mode writes a decodable image of the requested
//! size showing the object; the curvature map is uniform on a sphere and changes sign on a fat
//! torus; bad arguments exit 2 without writing anything.

mod common;

use common::cli::{lsubdiv, stderr};
use lsubdiv::mesh::generators::{cube, torus};
use lsubdiv::mesh::QuadMesh;
use lsubdiv::obj;
use std::path::Path;

/// A decoded RGB image.
struct Picture {
    width: usize,
    height: usize,
    rgb: Vec<[u8; 3]>,
}

impl Picture {
    fn load(path: &Path) -> Picture {
        let file = std::fs::File::open(path).unwrap();
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        Picture {
            width: info.width as usize,
            height: info.height as usize,
            rgb: buf[..info.buffer_size()]
                .chunks(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect(),
        }
    }

    fn at(&self, x: usize, y: usize) -> [u8; 3] {
        self.rgb[y * self.width + x]
    }

    /// Pixels of the object: not the white background, left of the curvature legend's strip.
    fn object(&self) -> Vec<(usize, usize)> {
        (0..self.height)
            .flat_map(|y| (0..self.width - 100).map(move |x| (x, y)))
            .filter(|&(x, y)| self.at(x, y) != [255; 3])
            .collect()
    }

    /// Object pixels whose 8 neighbours are object too (no antialiased silhouette).
    fn interior(&self) -> Vec<(usize, usize)> {
        self.object()
            .into_iter()
            .filter(|&(x, y)| {
                x > 0
                    && y > 0
                    && y + 1 < self.height
                    && (0..3).all(|dy| (0..3).all(|dx| self.at(x + dx - 1, y + dy - 1) != [255; 3]))
            })
            .collect()
    }
}

fn render(dir: &Path, name: &str, args: &[&str]) -> Picture {
    let out = dir.join(name);
    let mut all = vec!["render", "-o", out.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = lsubdiv(&all);
    assert!(o.status.success(), "{all:?}: {}", stderr(&o));
    Picture::load(&out)
}

fn write_obj(dir: &Path, name: &str, m: &QuadMesh) -> String {
    let p = dir.join(name);
    std::fs::write(&p, obj::format(m).unwrap()).unwrap();
    p.display().to_string()
}

#[test]
fn every_mode_draws_the_object_at_the_requested_size() {
    let dir = tempfile::tempdir().unwrap();
    let refined = ["cube", "--scheme", "binary-ternary", "--steps", "2"];
    let mut pictures = Vec::new();
    for (name, extra) in [
        ("flat", vec!["--shading", "flat"]),
        ("wire", vec!["--shading", "flat", "--wireframe"]),
        ("smooth", vec!["--shading", "smooth"]),
        ("curvature", vec!["--shading", "curvature"]),
        ("reflection", vec!["--shading", "reflection"]),
    ] {
        let mut args = refined.to_vec();
        args.extend(["--size", "200x150"]);
        args.extend(extra);
        let p = render(dir.path(), &format!("{name}.png"), &args);
        assert_eq!((p.width, p.height), (200, 150), "{name}");
        // The fitted rounded cube covers a disc of radius ≈ 0.42 × 75 px: ~ 17 % of the image.
        let share = p.object().len() as f64 / (200.0 * 150.0);
        assert!(
            (0.08..0.35).contains(&share),
            "{name}: object share {share}"
        );
        pictures.push((name, p));
    }
    let count = |p: &Picture, pred: &dyn Fn([u8; 3]) -> bool| {
        p.interior()
            .iter()
            .filter(|&&(x, y)| pred(p.at(x, y)))
            .count()
    };
    let grey = |c: [u8; 3]| c.iter().max().unwrap() - c.iter().min().unwrap() < 40;
    let dark = |c: [u8; 3]| c.iter().all(|&v| v < 60);
    let light = |c: [u8; 3]| c.iter().all(|&v| v > 200);
    let [(_, flat), (_, wire), (_, smooth), (_, curv), (_, refl)] = &pictures[..] else {
        unreachable!()
    };
    // Flat and smooth shading are greys, smooth has a highlight, flat does not.
    for p in [flat, smooth] {
        assert_eq!(count(p, &grey), p.interior().len());
    }
    assert!(count(smooth, &light) > 20 && count(flat, &light) == 0);
    // The wireframe adds dark lines (a 2-step cube has 96 quads).
    assert!(count(wire, &dark) > count(flat, &dark) + 300);
    // Curvature is coloured (a convex surface: red to yellow, no blue).
    let warm = |c: [u8; 3]| i32::from(c[0]) > i32::from(c[2]) + 60;
    assert!(count(curv, &warm) > curv.interior().len() * 9 / 10);
    // Reflection lines: stripes, both dark and light.
    let (d, l) = (count(refl, &dark), count(refl, &light));
    assert!(d > 1000 && l > 1000, "dark {d} light {l}");
}

#[test]
fn curvature_is_uniform_on_a_sphere_and_changes_sign_on_a_fat_torus() {
    let dir = tempfile::tempdir().unwrap();
    // The cube refined three times and pushed onto the unit sphere: H = 1 everywhere.
    let r = lsubdiv::mesh::patch::subdivide::<_, f64>(
        &lsubdiv::generated::binary_ternary::Scheme,
        &cube(),
        3,
        1,
    )
    .unwrap();
    let sphere = QuadMesh {
        positions: r
            .positions
            .iter()
            .map(|p| {
                let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                p.map(|c| c / n)
            })
            .collect(),
        faces: r.faces,
    };
    let path = write_obj(dir.path(), "sphere.obj", &sphere);
    let out = dir.path().join("sphere.png");
    let o = lsubdiv(&[
        "render",
        &path,
        "-o",
        out.to_str().unwrap(),
        "--shading",
        "curvature",
        "--size",
        "200x150",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("colours span ±1.0"), "{}", stderr(&o));
    let p = Picture::load(&out);
    // Every interior pixel is the red end of the map, only shaded: green and blue stay small
    // against red.
    let pixels = p.interior();
    assert!(pixels.len() > 3000);
    for &(x, y) in &pixels {
        let [r, g, b] = p.at(x, y).map(f64::from);
        assert!(g < 0.4 * r && b < 0.4 * r, "({x}, {y}): {:?}", p.at(x, y));
    }

    // A torus with tube radius 0.7 about a circle of radius 1: H = (1 + 1.4 cos v) /
    // (1.4 (1 + 0.7 cos v)) is negative on the inner side (cos v < −1/1.4), positive outside.
    let mut fat = torus(64, 32);
    for p in &mut fat.positions {
        let rho = (p[0] * p[0] + p[1] * p[1]).sqrt();
        let k = (1.0 + 2.0 * (rho - 1.0)) / rho;
        *p = [p[0] * k, p[1] * k, 2.0 * p[2]];
    }
    let path = write_obj(dir.path(), "fat.obj", &fat);
    let p = render(
        dir.path(),
        "fat.png",
        &[
            &path,
            "--shading",
            "curvature",
            "--size",
            "300x200",
            "--camera",
            "0,90",
            "--up",
            "z",
        ],
    );
    // Along the middle row from the hole (the centre of the picture beside the legend)
    // outwards: the inner rim is blue, the outer red.
    let y = p.height / 2;
    assert_eq!(p.at((p.width - 100) / 2, y), [255; 3]);
    let row: Vec<usize> = ((p.width - 100) / 2..p.width - 100)
        .filter(|&x| p.at(x, y) != [255; 3])
        .collect();
    let (inner, outer) = (row[0] + 3, row[row.len() - 1] - 3);
    let [r, _, b] = p.at(inner, y).map(i32::from);
    assert!(b > r + 60, "inner rim {:?}", p.at(inner, y));
    let [r, _, b] = p.at(outer, y).map(i32::from);
    assert!(r > b + 60, "outer rim {:?}", p.at(outer, y));
}

#[test]
fn ppm_output_and_bad_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let ppm = dir.path().join("a.ppm");
    let o = lsubdiv(&[
        "render",
        "torus:12:8",
        "-o",
        ppm.to_str().unwrap(),
        "--size",
        "40x30",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&ppm).unwrap();
    assert!(bytes.starts_with(b"P6\n40 30\n255\n") && bytes.len() == 13 + 40 * 30 * 3);

    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();
    let bad_obj = dir.path().join("bad.obj");
    std::fs::write(&bad_obj, "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n").unwrap();
    let bad_obj = bad_obj.to_str().unwrap();
    let jpg = dir.path().join("x.jpg");
    for (args, expected) in [
        (vec!["cube", "-o", out, "--size", "800"], "--size `800`"),
        (vec!["cube", "-o", out, "--size", "0x600"], "--size `0x600`"),
        (
            vec!["cube", "-o", jpg.to_str().unwrap()],
            "x.jpg: error: unknown image format `.jpg`",
        ),
        (vec!["missing.obj", "-o", out], "missing.obj: error:"),
        (
            vec![bad_obj, "-o", out],
            "bad.obj:4: error: vertex index 9 out of range",
        ),
        (vec!["cube", "-o", out, "--camera", "30"], "--camera `30`"),
        (
            vec!["torus:100000:100000", "-o", out],
            "built-in tori have at most 16777216",
        ),
        (
            vec!["grid-cube:0", "-o", out],
            "`grid-cube:0`: a grid cube's faces are 1 × 1 to 1000 × 1000 grids",
        ),
        (
            vec!["icosphere:9", "-o", out],
            "`icosphere:9`: an icosphere's level is 0 to 8",
        ),
        (
            vec!["cube", "-o", out, "--camera", "0,120"],
            "elevation 120",
        ),
        (
            vec!["cube", "-o", out, "--eye", "0,0,0"],
            "the eye and the target are the same point",
        ),
        (
            vec!["cube", "-o", out, "--scheme", "nope", "--steps", "1"],
            "no shipped scheme",
        ),
    ] {
        let mut all = vec!["render"];
        all.extend(&args);
        let o = lsubdiv(&all);
        assert_eq!(o.status.code(), Some(2), "{all:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{all:?}: {}", stderr(&o));
        assert!(
            !Path::new(out).exists() && !jpg.exists(),
            "{all:?} wrote a file"
        );
    }
}

/// An open mesh: its boundary is drawn in its own colour (red), and the back of the surface,
/// seen from below, in the warm back material, the front, seen from above, in the cool one.
#[test]
fn open_meshes_draw_their_boundary_and_their_back() {
    let dir = tempfile::tempdir().unwrap();
    let red = |p: &[u8; 3]| p[0] > 180 && p[1] < 110 && p[2] < 80;
    let warm = |p: &[u8; 3]| u16::from(p[0]) > u16::from(p[2]) + 20;
    for (name, camera, back) in [("above.png", "30,40", false), ("below.png", "30,-40", true)] {
        let pic = render(
            dir.path(),
            name,
            &[
                "grid",
                "--scheme",
                "fibonacci",
                "--steps",
                "2",
                "--camera",
                camera,
            ],
        );
        let object = pic.object();
        let boundary = object.iter().filter(|&&(x, y)| red(&pic.at(x, y))).count();
        assert!(boundary > 100, "{name}: {boundary} boundary pixels");
        let inside = pic.interior();
        let warm_share = inside.iter().filter(|&&(x, y)| warm(&pic.at(x, y))).count() as f64
            / inside.len() as f64;
        if back {
            assert!(
                warm_share > 0.9,
                "{name}: {warm_share} of the surface in the back material"
            );
        } else {
            assert!(
                warm_share < 0.1,
                "{name}: {warm_share} of the surface in the back material"
            );
        }
    }
}

/// `--normals limit` (the default with `--scheme`) shades a coarse refinement with the limit
/// surface's normals at its limit points, `--normals mesh` with normals averaged from the refined
/// control mesh: the images differ, and the limit one's reflection lines are much closer to those
/// of the same surface refined far finer (drawn with mesh normals: nothing of the limit code).
/// A 2-step torus: 28 % of the pixels show the other stripe than the fine one's with mesh
/// normals, 12 % with limit normals (the rest is the triangles' linear interpolation).
/// Without `--scheme` there is no limit surface, and before its EVs' configuration is
/// stationary a mesh with EVs has none either: `--normals limit` is refused, the default falls
/// back to mesh normals with a note.
#[test]
fn limit_normals_draw_truer_reflection_lines_and_need_a_limit() {
    let dir = tempfile::tempdir().unwrap();
    let draw = |name: &str, steps: &str, normals: &str| {
        render(
            dir.path(),
            name,
            &[
                "torus:8:5",
                "--scheme",
                "fibonacci",
                "--steps",
                steps,
                "--normals",
                normals,
                "--shading",
                "reflection",
                "--size",
                "400x300",
            ],
        )
    };
    let mesh = draw("mesh.png", "2", "mesh");
    let limit = draw("limit.png", "2", "limit");
    let fine = draw("fine.png", "6", "mesh");
    assert!(mesh.rgb != limit.rgb, "the normals make no difference");
    // Pixels inside all three silhouettes whose stripe (light or dark) differs from the fine one.
    let light = |p: &Picture, (x, y): (usize, usize)| p.at(x, y)[0] > 128;
    let inside = |p: &Picture, x: usize, y: usize| p.at(x, y) != [255; 3];
    let common: Vec<(usize, usize)> = fine
        .interior()
        .into_iter()
        .filter(|&(x, y)| inside(&mesh, x, y) && inside(&limit, x, y))
        .collect();
    assert!(common.len() > 5000, "{} common pixels", common.len());
    let wrong = |p: &Picture| {
        common
            .iter()
            .filter(|&&q| light(p, q) != light(&fine, q))
            .count() as f64
            / common.len() as f64
    };
    let (mesh_wrong, limit_wrong) = (wrong(&mesh), wrong(&limit));
    assert!(
        limit_wrong < 0.6 * mesh_wrong,
        "stripes off the fine surface's: {mesh_wrong} with mesh normals, {limit_wrong} with limit normals"
    );

    let out = dir.path().join("x.png");
    let out = out.to_str().unwrap();
    let early = [
        "cube",
        "--scheme",
        "fibonacci",
        "--steps",
        "2",
        "--size",
        "40x30",
    ];
    let o = lsubdiv(&[&["render", "-o", out][..], &early].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: shaded with the refined mesh's normals, not the limit surface's: the limit at extraordinary vertices after 2 steps"),
        "{}",
        stderr(&o)
    );
    std::fs::remove_file(out).unwrap();
    for (args, says) in [
        (&["cube"][..], "--normals limit needs --scheme"),
        (
            &early[..],
            "error: the limit at extraordinary vertices after 2 steps",
        ),
    ] {
        let o = lsubdiv(&[&["render", "-o", out, "--normals", "limit"], args].concat());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{args:?}: {}", stderr(&o));
        assert!(!Path::new(out).exists(), "{args:?} wrote {out}");
    }
}

/// A mesh file is drawn +y up (OBJ's convention), a built-in mesh +z up; `--up` names another
/// axis. A box 4 high along y, 2 wide along x and z, seen from the side: tall by default and
/// with `--up -y`, lying with `--up z`.
#[test]
fn mesh_files_are_drawn_y_up_unless_told() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = cube();
    for p in &mut m.positions {
        p[1] *= 2.0;
    }
    let file = write_obj(dir.path(), "tall.obj", &m);
    let extent = |p: &Picture| {
        let o = p.object();
        let (xs, ys): (Vec<usize>, Vec<usize>) = o.into_iter().unzip();
        let span = |v: &[usize]| v.iter().max().unwrap() - v.iter().min().unwrap();
        (span(&xs), span(&ys))
    };
    let side = ["--camera", "0,0"];
    let (w, h) = extent(&render(dir.path(), "y.png", &[&file, side[0], side[1]]));
    assert!(h > 2 * w, "+y up: {w} × {h}");
    let (w, h) = extent(&render(
        dir.path(),
        "z.png",
        &[&file, "--up", "z", side[0], side[1]],
    ));
    assert!(w > 2 * h, "--up z: {w} × {h}");
    let (w, h) = extent(&render(
        dir.path(),
        "m.png",
        &[&file, "--up", "-y", side[0], side[1]],
    ));
    assert!(h > 2 * w, "--up -y: {w} × {h}");
    let o = lsubdiv(&["render", "cube", "--up", "w", "-o", "x.png"]);
    assert_eq!(o.status.code(), Some(2));
}
