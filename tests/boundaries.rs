//! Open meshes: a boundary is a line of odd symmetry, so an open regular grid
//! refined by any scheme with interpolated corners (edge-and-corner) is exactly the tensor
//! product of the 1D refinements of its rows and columns with interpolated ends
//! (`runtime::ends`), and a tube's boundary loops are the closed-curve refinement of the
//! boundary polygons.

mod common;

use lsubdiv::compiler::exact::symmetry::rule_mirror;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::{GenericScheme, GenericSurface};
use lsubdiv::mesh::patch::Refiner;
use lsubdiv::mesh::surface::SurfaceError;
use lsubdiv::mesh::topology::Topology;
use lsubdiv::mesh::QuadMesh;
use lsubdiv::{refine_ends, CurveScheme, EndCurve};
use lsubdiv_cli::resolve;

use common::SURFACE_SCHEMES as SCHEMES;

fn surface(name: &str) -> GenericSurface {
    let r = resolve(name).expect("shipped scheme");
    GenericSurface::new(Scheme::build(r.ls).expect("compiles")).expect("a surface scheme")
}

fn curve(name: &str) -> (GenericScheme, Vec<u8>) {
    let r = resolve(name).expect("shipped scheme");
    let sigma = rule_mirror(&r.ls).expect("symmetric");
    (
        GenericScheme::new(Scheme::build(r.ls).expect("compiles")).expect("tabulates"),
        sigma,
    )
}

/// An open grid of rows × cols quads, bumped out of its plane so that no two points agree:
/// vertex i·(cols + 1) + j at (j, i, z(i, j)); face (i, j) has corner 0 at vertex (i, j) and
/// edge 0 along j.
fn grid(rows: usize, cols: usize) -> QuadMesh {
    let id = |i: usize, j: usize| (i * (cols + 1) + j) as u32;
    let positions = (0..=rows)
        .flat_map(|i| {
            (0..=cols).map(move |j| {
                let (x, y) = (j as f64, i as f64);
                [
                    x + 0.1 * y * y,
                    y - 0.05 * x,
                    (0.7 * x).sin() + 0.3 * (1.3 * y).cos(),
                ]
            })
        })
        .collect();
    let faces = (0..rows)
        .flat_map(|i| {
            (0..cols).map(move |j| [id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)])
        })
        .collect();
    QuadMesh { positions, faces }
}

/// The refined grid by its global grid coordinates (I, J), from the refiner's faces: base face
/// (i, j) becomes N × N quads, row y, column x, corner 0 at (i·N + y, j·N + x).
fn by_grid(
    cols: usize,
    n: usize,
    faces: &[[u32; 4]],
) -> std::collections::HashMap<(usize, usize), u32> {
    let mut at = std::collections::HashMap::new();
    for (q, quad) in faces.iter().enumerate() {
        let (f, r) = (q / (n * n), q % (n * n));
        let (i, j) = (f / cols, f % cols);
        let (y, x) = (r / n, r % n);
        let (gi, gj) = (i * n + y, j * n + x);
        for (c, (di, dj)) in [(0, 0), (0, 1), (1, 1), (1, 0)].into_iter().enumerate() {
            let old = at.insert((gi + di, gj + dj), quad[c]);
            assert!(
                old.is_none() || old == Some(quad[c]),
                "one vertex per grid point"
            );
        }
    }
    at
}

/// Rows, then columns, refined as open curves with interpolated ends.
fn tensor(
    s: &mut GenericScheme,
    sigma: &[u8],
    p: &[Vec<[f64; 3]>],
    steps: usize,
) -> Vec<Vec<[f64; 3]>> {
    let mut one = |points: Vec<[f64; 3]>| {
        let c = EndCurve::with_axiom(&s.tables(), points);
        s.prepare(&c.extended(&s.tables(), sigma).unwrap()).unwrap();
        refine_ends(s, sigma, &c, steps).unwrap().points
    };
    let rows: Vec<Vec<[f64; 3]>> = p.iter().map(|r| one(r.clone())).collect();
    let cols: Vec<Vec<[f64; 3]>> = (0..rows[0].len())
        .map(|j| one(rows.iter().map(|r| r[j]).collect()))
        .collect();
    (0..cols[0].len())
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect()
}

#[test]
fn an_open_grid_is_the_tensor_product_of_its_rows_and_columns() {
    for name in SCHEMES {
        let s = surface(name);
        let (mut c, sigma) = curve(name);
        for steps in 1..=3 {
            let worst = grid_against_tensor(&s, &mut c, &sigma, steps);
            assert!(worst < 1e-12, "{name} steps={steps}: off by {worst:e}");
        }
    }
}

/// How far a 3 × 4 open grid refined by `s` (edge-and-corner, two threads) is from the tensor
/// product of its rows and columns refined by `c` with interpolated ends.
fn grid_against_tensor(
    s: &GenericSurface,
    c: &mut GenericScheme,
    sigma: &[u8],
    steps: usize,
) -> f64 {
    let (rows, cols) = (3, 4);
    let mesh = grid(rows, cols);
    let topo = Topology::build(&mesh).unwrap();
    let p: Vec<Vec<[f64; 3]>> = (0..=rows)
        .map(|i| {
            (0..=cols)
                .map(|j| mesh.positions[i * (cols + 1) + j])
                .collect()
        })
        .collect();
    let mut r = Refiner::<_, f64>::new(s, &topo, steps, 2).unwrap_or_else(|e| panic!("{e}"));
    let out = r.refine(&mesh.positions).unwrap().to_vec();
    let faces = r.faces();
    let n = s.tables().image_len(s.tables().axiom, steps) as usize;
    let at = by_grid(cols, n, &faces);
    let want = tensor(c, sigma, &p, steps);
    assert_eq!(want.len(), rows * n + 1);
    assert_eq!(at.len(), out.len(), "every output vertex on the grid");
    let mut worst = 0.0f64;
    for (&(i, j), &v) in &at {
        for k in 0..3 {
            worst = worst.max((out[v as usize][k] - want[i][j][k]).abs());
        }
    }
    worst
}

proptest::proptest! {
    // Each case compiles a scheme exactly (small systems: milliseconds).
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 48, ..Default::default() })]

    /// Random symmetric surface schemes (`common::surface_systems`): [`open_meshes_are_curves`].
    #[test]
    fn random_schemes_refine_open_meshes_as_their_curves(
        sys in common::surface_systems()
    ) {
        if let Some((text, scheme, s)) = common::drawn_surface(&sys) {
            open_meshes_are_curves(&text, scheme, &s, true).map_err(proptest::test_runner::TestCaseError::fail)?;
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 32, ..Default::default() })]

    /// Random symmetric surface schemes: [`alike_by_every_path`].
    #[test]
    fn random_schemes_refine_an_open_creased_triangle_mesh_alike_by_every_path(
        sys in common::surface_systems()
    ) {
        if let Some((text, _, s)) = common::drawn_surface(&sys) {
            alike_by_every_path(&text, &s, true).map_err(proptest::test_runner::TestCaseError::fail)?;
        }
    }
}

/// Schemes whose masks are contained only after two or three steps take that many reference
/// steps on a mesh with features, each on its level cut open along its sharp edges: the open
/// grid, the boundary loops and a crease are the scheme's curves, and every path agrees.
#[test]
fn schemes_needing_several_reference_steps_refine_features_as_their_curves() {
    for text in common::DELAYED {
        let (text, scheme, s) = common::text_surface(text.into()).expect("a surface scheme");
        open_meshes_are_curves(&text, scheme, &s, false).unwrap_or_else(|e| panic!("{e}"));
        alike_by_every_path(&text, &s, false).unwrap_or_else(|e| panic!("{e}"));
    }
}

/// As many steps as keep the grid small: the open grid refined by `s` is the tensor product
/// of its rows and columns, the boundary loops of meshes with EVs are the scheme's curves, and
/// so is a crease from boundary to boundary past EVs of valence 3 and 6. Where `may_refuse`,
/// a refusal of the refiner is not a failure (nothing to compare).
fn open_meshes_are_curves(
    text: &str,
    scheme: Scheme,
    s: &GenericSurface,
    may_refuse: bool,
) -> Result<(), String> {
    let sigma = rule_mirror(&scheme.ls).expect("σ is declared");
    let mut c = GenericScheme::new(scheme).unwrap();
    let refused = |e: SurfaceError| match e {
        SurfaceError::Unsupported(_) if may_refuse => Ok(()),
        e => Err(format!("{e}\n{text}")),
    };
    for steps in 1..=3 {
        if s.tables().image_len(s.tables().axiom, steps) > 40 {
            break;
        }
        let worst = grid_against_tensor(s, &mut c, &sigma, steps);
        if worst >= 1e-12 {
            return Err(format!("steps={steps}: off by {worst:e}\n{text}"));
        }
        for mesh in [open_box(), pentagon(), l_shape()] {
            for boundary in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
                let what = (text, s, &mut c, &sigma[..]);
                if let Err(e) = boundaries_are_curves(what, (&mesh, boundary), steps) {
                    refused(e).map_err(|e| format!("{boundary:?}, {steps} steps: {e}"))?;
                }
            }
        }
        match hexagon_crease_off(s, (&mut c, &sigma), steps) {
            Ok(worst) if worst >= 1e-12 => {
                return Err(format!("{steps} steps: crease off by {worst:e}\n{text}"));
            }
            Ok(_) => {}
            Err(e) => refused(e)?,
        }
    }
    Ok(())
}

/// On an open, creased triangle mesh with a sharp vertex and a hole
/// ([`creased_open_triangles`]), as many steps as keep it small: its faces all at EVs run
/// their first steps level by level, the later ones in lock-step with the 1-rings handed on
/// and the last one composed; beside a torus the same faces take every step in lock-step.
/// Both give the same points to rounding, on one and two threads (the same bits), finite, and
/// a constant mesh stays constant. Where `may_refuse`, a refusal is not a failure.
fn alike_by_every_path(text: &str, s: &GenericSurface, may_refuse: bool) -> Result<(), String> {
    use lsubdiv_testkit::points::same_points;
    let (mesh, features) = creased_open_triangles(1);
    let (both, ring) = beside_a_torus(&mesh, 24);
    let (topo, topo_both) = (
        Topology::build(&mesh).unwrap(),
        Topology::build(&both).unwrap(),
    );
    let topo_ring = Topology::build(&ring).unwrap();
    for steps in 1..=4 {
        let side = s.tables().image_len(s.tables().axiom, steps);
        if both.faces.len() as u128 * side * side > 120_000 {
            break;
        }
        let refine = |topo: &Topology, positions: &[[f64; 3]], threads| {
            let closed = topo.is_closed().then(Features::default);
            let features = closed.as_ref().unwrap_or(&features);
            Refiner::<_, f64>::with_features(s, topo, features, steps, threads)
                .and_then(|mut r| Ok(r.refine(positions)?.to_vec()))
        };
        let alone = match refine(&topo, &mesh.positions, 1) {
            Ok(points) => points,
            Err(SurfaceError::Unsupported(_)) if may_refuse => break,
            Err(e) => return Err(format!("{steps} steps: {e}\n{text}")),
        };
        let fail = |what: String| Err(format!("{steps} steps: {what}\n{text}"));
        if !alone.iter().flatten().all(|x| x.is_finite()) {
            return fail("not finite".into());
        }
        if refine(&topo, &mesh.positions, 2).unwrap() != alone {
            return fail("threads changed bits".into());
        }
        let together = refine(&topo_both, &both.positions, 1).unwrap();
        let torus = refine(&topo_ring, &ring.positions, 1).unwrap();
        let moved = torus.iter().map(|p| [p[0] + 100.0, p[1], p[2]]);
        let expected: Vec<[f64; 3]> = alone.iter().copied().chain(moved).collect();
        let d = same_points(&together, &expected);
        if d >= 1e-12 {
            return fail(format!("beside a torus off by {d:e}"));
        }
        let constant = vec![[0.25, -3.0, 7.5]; mesh.positions.len()];
        let c = refine(&topo, &constant, 1).unwrap();
        let worst = c
            .iter()
            .flat_map(|p| [p[0] - 0.25, p[1] + 3.0, p[2] - 7.5])
            .fold(0.0f64, |m, d| m.max(d.abs()));
        if worst >= 1e-12 {
            return fail(format!("constants off by {worst:e}"));
        }
    }
    Ok(())
}

/// The boundary loops of a mesh as vertex sequences (each loop once, from its smallest
/// vertex, in the direction of its smaller neighbour).
fn boundary_loops(mesh: &QuadMesh) -> Vec<Vec<u32>> {
    let topo = Topology::build(mesh).unwrap();
    let mut next: std::collections::HashMap<u32, Vec<u32>> = Default::default();
    for f in 0..topo.face_count() as u32 {
        for l in 0..4 {
            if topo.is_boundary_edge(f, l) {
                let (a, b) = (topo.vertex(f, l), topo.vertex(f, (l + 1) % 4));
                next.entry(a).or_default().push(b);
                next.entry(b).or_default().push(a);
            }
        }
    }
    let mut seen = std::collections::HashSet::new();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut loops = Vec::new();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let mut lp = vec![s];
        seen.insert(s);
        let mut at = s;
        let mut prev = u32::MAX;
        loop {
            let ns = &next[&at];
            let n = if prev == u32::MAX {
                *ns.iter().min().unwrap()
            } else {
                *ns.iter().find(|&&n| n != prev).unwrap()
            };
            if n == s {
                break;
            }
            seen.insert(n);
            lp.push(n);
            prev = at;
            at = n;
        }
        loops.push(lp);
    }
    loops
}

/// Checks that every boundary loop of `mesh` refined by `name` under `boundary` is the 1D
/// refinement of the base loop: closed when it has no corner (a boundary vertex with one face
/// under edge-and-corner), else open with interpolated ends between consecutive corners.
fn boundaries_are_curves(
    (name, s, c, sigma): (&str, &GenericSurface, &mut GenericScheme, &[u8]),
    (mesh, boundary): (&QuadMesh, Boundary),
    steps: usize,
) -> Result<(), SurfaceError> {
    let topo = Topology::build(mesh).unwrap();
    let features = Features::with_boundary(boundary);
    let fine = lsubdiv::mesh::patch::subdivide_with::<_, f64>(s, mesh, &topo, &features, steps, 2)?;
    let nv = mesh.positions.len() as u32;
    let base = boundary_loops(mesh);
    let refined = boundary_loops(&fine);
    assert_eq!(
        base.len(),
        refined.len(),
        "{name}: the same number of boundary loops"
    );
    for lp in &base {
        // The refined loop through the child of lp[0] (base vertices keep their index),
        // walked the same way round.
        let r = refined
            .iter()
            .find(|r| r.contains(&lp[0]))
            .expect("loop kept");
        let k = r.iter().position(|&v| v == lp[0]).unwrap();
        let mut walk: Vec<u32> = r[k..].iter().chain(&r[..k]).copied().collect();
        let bases: Vec<u32> = walk.iter().copied().filter(|&v| v < nv).collect();
        if bases.get(1) != lp.get(1) {
            walk[1..].reverse();
        }
        let bases: Vec<u32> = walk.iter().copied().filter(|&v| v < nv).collect();
        assert_eq!(&bases, lp, "{name}: base vertices in order along the loop");
        let corner = |v: u32| boundary == Boundary::EdgeAndCorner && topo.valence(v) == 1;
        let corners: Vec<usize> = (0..lp.len()).filter(|&i| corner(lp[i])).collect();
        let point = |v: u32| fine.positions[v as usize];
        let mut worst = 0.0f64;
        let mut compare = |want: &[[f64; 3]], got: &[u32]| {
            assert_eq!(want.len(), got.len(), "{name}: points along the boundary");
            for (w, &g) in want.iter().zip(got) {
                for (a, b) in w.iter().zip(point(g)) {
                    worst = worst.max((a - b).abs());
                }
            }
        };
        if corners.is_empty() {
            let pts: Vec<[f64; 3]> = lp.iter().map(|&v| mesh.positions[v as usize]).collect();
            let coarse = lsubdiv::Curve::with_axiom(&c.tables(), pts, true);
            // A refined closed curve starts at another point of the loop: the shift that
            // puts the child of lp[0] first.
            let want = lsubdiv::refine(&*c, &coarse, steps).unwrap().points;
            let p0 = point(lp[0]);
            let d = |q: &[f64; 3]| (0..3).map(|k| (q[k] - p0[k]).abs()).fold(0.0, f64::max);
            let shift = (0..want.len())
                .min_by(|&a, &b| d(&want[a]).total_cmp(&d(&want[b])))
                .unwrap();
            let want: Vec<[f64; 3]> = want[shift..]
                .iter()
                .chain(&want[..shift])
                .copied()
                .collect();
            compare(&want, &walk);
        } else {
            // Rotate so that the loop starts at a corner, then each piece corner to corner.
            let first = corners[0];
            let rot_base: Vec<u32> = lp[first..]
                .iter()
                .chain(&lp[..first])
                .copied()
                .chain([lp[first]])
                .collect();
            let k = walk.iter().position(|&v| v == lp[first]).unwrap();
            let rot_walk: Vec<u32> = walk[k..]
                .iter()
                .chain(&walk[..k])
                .copied()
                .chain([lp[first]])
                .collect();
            let is_corner = |v: u32| v < nv && corner(v);
            let (mut i, mut j) = (0, 0);
            while i + 1 < rot_base.len() {
                let i2 = i
                    + 1
                    + rot_base[i + 1..]
                        .iter()
                        .position(|&v| is_corner(v))
                        .unwrap();
                let j2 = j
                    + 1
                    + rot_walk[j + 1..]
                        .iter()
                        .position(|&v| is_corner(v))
                        .unwrap();
                let pts: Vec<[f64; 3]> = rot_base[i..=i2]
                    .iter()
                    .map(|&v| mesh.positions[v as usize])
                    .collect();
                let piece = EndCurve::with_axiom(&c.tables(), pts);
                let extended = piece.extended(&c.tables(), sigma).unwrap();
                c.prepare(&extended).unwrap();
                let want = refine_ends(&*c, sigma, &piece, steps).unwrap();
                compare(&want.points, &rot_walk[j..=j2]);
                (i, j) = (i2, j2);
            }
        }
        assert!(
            worst < 1e-12,
            "{name} steps={steps}: boundary off by {worst:e}"
        );
    }
    Ok(())
}

/// One pentagon split into five quads (a topological Catmull–Clark split): an interior EV of
/// valence 5, five corners with one face and five boundary vertices with two.
fn pentagon() -> QuadMesh {
    let p: Vec<[f64; 3]> = (0..5)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 5.0;
            [t.cos(), t.sin(), 0.2 * (2.0 * t).sin()]
        })
        .collect();
    lsubdiv::mesh::generators::quad_split(&p, &[vec![0, 1, 2, 3, 4]])
}

/// The cube without its top face: a square rim of boundary vertices with two faces each
/// (a closed boundary loop) and four interior EVs of valence 3.
fn open_box() -> QuadMesh {
    let mut m = lsubdiv::mesh::generators::cube();
    m.faces.pop();
    m
}

/// Three quads around a boundary vertex (vertex 4 of a 3 × 3 point grid without its last
/// quad): that vertex has three faces (a boundary EV), five boundary vertices have one.
fn l_shape() -> QuadMesh {
    let mut m = grid(2, 2);
    m.faces.pop();
    m.positions.pop();
    m
}

#[test]
fn boundary_loops_are_the_schemes_curves() {
    for name in SCHEMES {
        let s = surface(name);
        let (mut c, sigma) = curve(name);
        for steps in 1..=3 {
            // The larger grid's corner faces step in lock-step (`Refiner::fan_faces`), the
            // small one's level by level (`patch/direct.rs`).
            let grids = [
                ("grid", grid(2, 3)),
                ("larger grid", grid(6, 7)),
                ("strip", grid(1, 4)),
            ];
            let meshes = grids.into_iter().chain([("open box", open_box())]);
            let meshes = meshes
                .into_iter()
                .chain([("pentagon", pentagon()), ("L", l_shape())]);
            for (mesh_name, mesh) in meshes {
                for boundary in [Boundary::EdgeAndCorner, Boundary::EdgeOnly] {
                    let what = format!("{name}, {mesh_name}, {boundary:?}");
                    boundaries_are_curves((&what, &s, &mut c, &sigma), (&mesh, boundary), steps)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                }
            }
        }
    }
}

mod cli {
    //! The command line on open, creased and holed meshes: OBJ `t` tags and `--boundary`
    //! reach the refiner, and what it cannot refine is refused with the reason.

    use super::common::cli::{lsubdiv, stderr, write};
    use lsubdiv::mesh::features::{Boundary, Features, Sharpness};
    use lsubdiv::mesh::generators::open_grid;
    use lsubdiv::mesh::patch::subdivide_with;
    use lsubdiv::mesh::topology::Topology;

    /// A 3 × 3 open grid as OBJ, with `tags` appended.
    fn grid_obj(tags: &str) -> String {
        let m = open_grid(3, 3);
        let mut s = String::new();
        for p in &m.positions {
            s += &format!("v {:?} {:?} {:?}\n", p[0], p[1], p[2]);
        }
        for f in &m.faces {
            s += &format!("f {} {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1, f[3] + 1);
        }
        s + tags
    }

    #[test]
    fn tags_and_boundary_rule_reach_the_refiner() {
        let dir = tempfile::tempdir().unwrap();
        // A crease across the grid (vertices 4..7 on row 1), sharpness 2, and a hole.
        let tags =
            "t crease 2/1/0 4 5 2\nt crease 2/1/0 5 6 2\nt crease 2/1/0 6 7 2\nt hole 1/0/0 4\n";
        let input = write(dir.path(), "grid.obj", &grid_obj(tags));
        let out = dir.path().join("fine.obj");
        let o = lsubdiv(&[
            "subdivide",
            "fibonacci",
            "--steps",
            "3",
            "--boundary",
            "edge-only",
            &input,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let got = lsubdiv::mesh_file::read_checked(&out, u64::MAX)
            .unwrap()
            .mesh;
        let r = lsubdiv_cli::resolve("fibonacci").unwrap();
        let s = lsubdiv::generic::GenericSurface::new(
            lsubdiv::compiler::exact::Scheme::build(r.ls).unwrap(),
        )
        .unwrap();
        let mesh = open_grid(3, 3);
        let mut features = Features::with_boundary(Boundary::EdgeOnly);
        for e in [[4, 5], [5, 6], [6, 7]] {
            features.creases.push((e, Sharpness::steps(2)));
        }
        features.holes.push(4);
        let topo = Topology::build(&mesh).unwrap();
        let want: lsubdiv::mesh::QuadMesh =
            subdivide_with(&s, &mesh, &topo, &features, 3, 1).unwrap();
        assert_eq!(got.faces, want.faces);
        let worst = got
            .positions
            .iter()
            .flatten()
            .zip(want.positions.iter().flatten())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // The OBJ writer prints shortest round-trip decimals: the same numbers.
        assert_eq!(worst, 0.0);
        // Without the tags the result differs: they were not ignored.
        let plain = write(dir.path(), "plain.obj", &grid_obj(""));
        let out2 = dir.path().join("plain-fine.obj");
        let o = lsubdiv(&[
            "subdivide",
            "fibonacci",
            "--steps",
            "3",
            &plain,
            "-o",
            out2.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_ne!(
            lsubdiv::mesh_file::read_checked(&out2, u64::MAX)
                .unwrap()
                .mesh,
            got
        );
    }

    #[test]
    fn darts_refine_and_bad_tags_are_refused_at_their_line() {
        let dir = tempfile::tempdir().unwrap();
        // Binary-Ternary's first step is not contained near EVs ([G] Prop. 4.8): the
        // reference driver takes it on the mesh cut open along its sharp edges (a dart at both
        // ends of this one) with ghost layers; the result is a convex combination as always.
        let input = write(
            dir.path(),
            "dart.obj",
            &grid_obj("t crease 2/1/0 5 6 inf\n"),
        );
        let out = dir.path().join("out.obj");
        let o = lsubdiv(&[
            "subdivide",
            "binary-ternary",
            "--steps",
            "2",
            &input,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        // A crease between vertices that share no edge names its line.
        let input = write(dir.path(), "bad.obj", &grid_obj("t crease 2/1/0 0 5 inf\n"));
        let o = lsubdiv(&[
            "subdivide",
            "fibonacci",
            "--steps",
            "1",
            &input,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2));
        assert!(stderr(&o).contains("bad.obj:26:"), "{}", stderr(&o));
    }
}

/// Meshes with every kind of feature and their features: an open grid in both modes, an L
/// with a boundary EV, a grid with a hole and a crease, a creased cube.
fn featured() -> Vec<(&'static str, QuadMesh, Features)> {
    use lsubdiv::mesh::generators::{creased_cube, grid_with_hole};
    let (hole, mut crease) = grid_with_hole(3);
    crease.creases.push(([4, 5], Sharpness::INFINITE));
    crease.creases.push(([5, 6], Sharpness::steps(1)));
    vec![
        ("grid", grid(3, 3), Features::default()),
        (
            "grid edge-only",
            grid(3, 3),
            Features::with_boundary(Boundary::EdgeOnly),
        ),
        ("L", l_shape(), Features::default()),
        ("hole and crease", hole, crease),
        ("creased cube", creased_cube().0, creased_cube().1),
        ("open box", open_box(), Features::default()),
        ("darts", grid(3, 3), {
            let mut f = Features::default();
            f.creases.push(([5, 6], Sharpness::INFINITE));
            f.creases.push(([9, 13], Sharpness::steps(2)));
            f
        }),
        ("pentagon", pentagon(), Features::default()),
        {
            let (m, f, _) = creased_hexagon_grid();
            ("creased hexagon grid", m, f)
        },
    ]
}

use lsubdiv::mesh::features::{Boundary, Features, Sharpness};

fn refine_with(s: &GenericSurface, mesh: &QuadMesh, f: &Features, steps: usize) -> QuadMesh {
    let topo = Topology::build(mesh).unwrap();
    lsubdiv::mesh::patch::subdivide_with(s, mesh, &topo, f, steps, 2).unwrap()
}

/// Every new point is an affine combination of the old ones (refining is affine invariant),
/// with non-negative weights for these schemes, whose masks are non-negative: refined
/// impulses (one old vertex at 1, the others at 0, three at a time in x, y, z) give each new
/// point's weights, which sum to 1. Corners (boundary vertices with one face in
/// edge-and-corner mode, vertices with three sharp edges) stay where they are, and a planar
/// mesh stays planar.
#[test]
fn new_points_are_convex_combinations_and_corners_stay() {
    for name in SCHEMES {
        let s = surface(name);
        for (what, mesh, features) in featured() {
            let steps = 2;
            let nv = mesh.positions.len();
            let fine = refine_with(&s, &mesh, &features, steps);
            let mut sum = vec![0.0f64; fine.positions.len()];
            for first in (0..nv).step_by(3) {
                let mut impulse = mesh.clone();
                for (v, p) in impulse.positions.iter_mut().enumerate() {
                    *p = std::array::from_fn(|k| f64::from(u8::from(v == first + k)));
                }
                let w = refine_with(&s, &impulse, &features, steps);
                for (i, p) in w.positions.iter().enumerate() {
                    for (k, &x) in p.iter().enumerate() {
                        if first + k < nv {
                            assert!(
                                x >= -1e-12,
                                "{name} {what}: weight {x:e} of vertex {}",
                                first + k
                            );
                            sum[i] += x;
                        }
                    }
                }
            }
            for s in &sum {
                assert!((s - 1.0).abs() < 1e-12, "{name} {what}: weights sum to {s}");
            }
            // Affine invariance: an affine map commutes with refining.
            let map = |p: &[f64; 3]| {
                [
                    2.0 * p[0] - p[1] + 3.0,
                    0.5 * p[1] + p[2] - 1.0,
                    p[0] + 0.25 * p[2],
                ]
            };
            let mut moved = mesh.clone();
            moved.positions.iter_mut().for_each(|p| *p = map(p));
            let fine_moved = refine_with(&s, &moved, &features, steps);
            for (a, b) in fine_moved.positions.iter().zip(&fine.positions) {
                let b = map(b);
                assert!(
                    (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12),
                    "{name} {what}: affine"
                );
            }
            // Corners stay (base vertices keep their index; no holes drop one here).
            let topo = Topology::build(&mesh).unwrap();
            let r = lsubdiv::mesh::features::Resolved::new(&topo, &features).unwrap();
            for v in 0..nv as u32 {
                if r.vertex_rule(&topo, v, 0) == lsubdiv::mesh::features::VertexRule::Corner {
                    assert_eq!(
                        fine.positions[v as usize], mesh.positions[v as usize],
                        "{name} {what}: corner {v}"
                    );
                }
            }
            // Closed stays closed, and an open mesh keeps its number of boundary loops (holes
            // aside: their faces are not written, so each is a loop more).
            if features.holes.is_empty() {
                let (a, b) = (
                    Topology::build(&mesh).unwrap(),
                    Topology::build(&fine).unwrap(),
                );
                assert_eq!(a.is_closed(), b.is_closed(), "{name} {what}");
                assert_eq!(
                    boundary_loops(&mesh).len(),
                    boundary_loops(&fine).len(),
                    "{name} {what}: boundary loops"
                );
            }
            // Planar input stays planar.
            let mut flat = mesh.clone();
            flat.positions.iter_mut().for_each(|p| p[2] = 0.0);
            let fine_flat = refine_with(&s, &flat, &features, steps);
            assert!(
                fine_flat.positions.iter().all(|p| p[2].abs() < 1e-12),
                "{name} {what}: planar"
            );
        }
    }
}

/// The generated kernels and the generic path, and any number of threads, refine open,
/// creased and holed meshes to the same bits, and take them to the same limit.
#[test]
fn generated_and_generic_agree_bit_for_bit_on_featured_meshes() {
    use lsubdiv::mesh::patch::Subdivide;
    use lsubdiv::mesh::surface::SurfaceVisitor;
    for name in ["uniform-binary", "fibonacci", "found-cubic"] {
        let s = surface(name);
        for (what, mesh, features) in featured() {
            let topo = Topology::build(&mesh).unwrap();
            let job = Subdivide {
                mesh: &mesh,
                topology: &topo,
                features: &features,
                steps: 3,
                threads: 2,
                limit: false,
            };
            // The refined meshes, and their limits (positions and normals).
            for job in [job, Subdivide { limit: true, ..job }] {
                let generated = lsubdiv::generated::visit_surface(name, job)
                    .expect("a generated surface scheme")
                    .unwrap();
                let generic = job.visit(&s).unwrap();
                assert_eq!(generated, generic, "{name} {what}");
                // Threads never change a bit.
                for threads in [1, 3] {
                    let other = Subdivide { threads, ..job }.visit(&s).unwrap();
                    assert_eq!(other, generic, "{name} {what}: {threads} threads");
                }
            }
        }
    }
}

/// A 4 × 4 open grid whose faces (1, 1) and (1, 2) are one hexagon, with an infinitely sharp
/// crease along grid row 3, taken one Catmull–Clark step: the split has EVs of valence 3 and 6
/// (the hexagon) and a crease from boundary to boundary, ending in corners; returned with the
/// crease's vertices in order along it.
fn creased_hexagon_grid() -> (QuadMesh, Features, Vec<u32>) {
    use lsubdiv::mesh::polygon::{catmull_clark, PolyMesh};
    let g = grid(4, 4);
    let id = |i: u32, j: u32| i * 5 + j;
    let mut poly = PolyMesh::new();
    poly.positions = g.positions.clone();
    for i in 0..4 {
        for j in 0..4 {
            match (i, j) {
                (1, 1) => {
                    poly.push_face(&[id(1, 1), id(1, 2), id(1, 3), id(2, 3), id(2, 2), id(2, 1)])
                }
                (1, 2) => {}
                _ => poly.push_face(&[id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]),
            }
        }
    }
    let mut f = Features::default();
    for j in 0..4 {
        f.creases
            .push(([id(3, j), id(3, j + 1)], Sharpness::INFINITE));
    }
    let split = catmull_clark(&poly, &f).unwrap();
    // Along the crease: each input edge's point sits between its ends.
    let mut line = vec![id(3, 0)];
    for j in 0..4 {
        let key = [id(3, j), id(3, j + 1)];
        let e = split.edges.iter().position(|&k| k == key).unwrap() as u32;
        line.extend([poly.positions.len() as u32 + e, id(3, j + 1)]);
    }
    (split.mesh, split.features, line)
}

/// A crease is refined as the scheme's curve between its corners (interpolated ends), on a
/// mesh with EVs: for Binary-Ternary the reference driver takes the first step on the mesh cut
/// open along the crease, with ghost layers on both sides.
#[test]
fn creases_are_the_schemes_curves_between_their_corners() {
    for name in SCHEMES {
        let s = surface(name);
        let (mut c, sigma) = curve(name);
        for steps in 1..=3 {
            let worst = hexagon_crease_off(&s, (&mut c, &sigma), steps)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(
                worst < 1e-12,
                "{name} steps={steps}: crease off by {worst:e}"
            );
        }
    }
}

/// How far the crease of [`creased_hexagon_grid`] refined by `s` is from its curve by `c`
/// between its corners (the refiner's error if it refuses the mesh).
fn hexagon_crease_off(
    s: &GenericSurface,
    c: (&mut GenericScheme, &[u8]),
    steps: usize,
) -> Result<f64, SurfaceError> {
    let (mesh, features, line) = creased_hexagon_grid();
    let topo = Topology::build(&mesh).unwrap();
    Refiner::<_, f64>::with_features(s, &topo, &features, steps, 1)?;
    let crease = Crease {
        mesh: &mesh,
        topo: &topo,
        features: &features,
        line: &line,
    };
    Ok(crease.against_curve(s, c, steps).1)
}

/// A crease line of a featured mesh, to compare with the scheme's curve.
struct Crease<'m> {
    mesh: &'m QuadMesh,
    topo: &'m Topology,
    features: &'m Features,
    /// The crease's vertices in order, from corner to corner.
    line: &'m [u32],
}

impl Crease<'_> {
    /// Refines the mesh `steps` times and the crease's polygon as an open curve with
    /// interpolated ends: that curve, and the largest distance between its points and the
    /// refined points along the crease (each edge's numbered from its smaller vertex).
    fn against_curve(
        &self,
        s: &GenericSurface,
        (c, sigma): (&mut GenericScheme, &[u8]),
        steps: usize,
    ) -> (EndCurve<3>, f64) {
        let (mesh, line) = (self.mesh, self.line);
        let fine = refine_with(s, mesh, self.features, steps);
        let n = s.tables().image_len(s.tables().axiom, steps) as usize;
        let nv = mesh.positions.len();
        let mut walk = vec![line[0]];
        for w in line.windows(2) {
            let e = self.topo.edge_between(w[0], w[1]).unwrap() as usize;
            let inner: Vec<u32> = (0..n - 1).map(|t| (nv + e * (n - 1) + t) as u32).collect();
            if w[0] < w[1] {
                walk.extend(&inner);
            } else {
                walk.extend(inner.iter().rev());
            }
            walk.push(w[1]);
        }
        let pts: Vec<[f64; 3]> = line.iter().map(|&v| mesh.positions[v as usize]).collect();
        let piece = EndCurve::with_axiom(&c.tables(), pts);
        let extended = piece.extended(&c.tables(), sigma).unwrap();
        c.prepare(&extended).unwrap();
        let want = refine_ends(c, sigma, &piece, steps).unwrap();
        assert_eq!(want.points.len(), walk.len());
        let got = &fine.positions;
        let worst = (want.points.iter().zip(&walk))
            .flat_map(|(w, &g)| (0..3).map(move |k| (w[k] - got[g as usize][k]).abs()))
            .fold(0.0, f64::max);
        (want, worst)
    }
}

/// Random open meshes with random features — a 5 × 5 grid with some faces removed (what stays
/// a 2-manifold), random creases of random sharpness, corner tags and holes, both boundary
/// modes — refine without panicking, for every scheme, to finite points that reproduce
/// constants (a constant mesh stays constant: every new point an affine combination).
#[test]
fn random_featured_meshes_refine_to_affine_combinations() {
    let mut rng = common::Lcg(0x15);
    let mut pick = |n: usize| ((rng.next() + 1.0) * 0.5 * n as f64) as usize % n;
    let schemes: Vec<_> = SCHEMES.iter().map(|&n| (n, surface(n))).collect();
    let mut refined = 0;
    for round in 0..80 {
        let full = grid(5, 5);
        let mut mesh = full.clone();
        for _ in 0..pick(6) {
            let f = pick(mesh.faces.len());
            mesh.faces.remove(f);
        }
        // Drop vertices no face uses, renumbering.
        let mut map = vec![u32::MAX; mesh.positions.len()];
        let mut positions = Vec::new();
        for f in &mut mesh.faces {
            for v in f.iter_mut() {
                if map[*v as usize] == u32::MAX {
                    map[*v as usize] = positions.len() as u32;
                    positions.push(mesh.positions[*v as usize]);
                }
                *v = map[*v as usize];
            }
        }
        mesh.positions = positions;
        let Ok(topo) = Topology::build(&mesh) else {
            continue; // removing faces can leave a non-manifold vertex
        };
        let mode = if round % 2 == 0 {
            Boundary::EdgeAndCorner
        } else {
            Boundary::EdgeOnly
        };
        let mut features = Features::with_boundary(mode);
        let edges: Vec<[u32; 2]> = (0..topo.edge_count() as u32)
            .map(|e| topo.edge_vertices(e))
            .collect();
        for _ in 0..pick(8) {
            let e = edges[pick(edges.len())];
            if !features.creases.iter().any(|&(c, _)| c == e) {
                features
                    .creases
                    .push((e, Sharpness::steps(pick(12) as u32)));
            }
        }
        if pick(3) == 0 {
            features
                .corners
                .push((pick(mesh.positions.len()) as u32, Sharpness::INFINITE));
        }
        if pick(3) == 0 {
            features.holes.push(pick(mesh.faces.len()) as u32);
        }
        for (name, s) in &schemes {
            let steps = 1 + pick(3);
            let fine = lsubdiv::mesh::patch::subdivide_with::<_, f64>(
                s, &mesh, &topo, &features, steps, 2,
            )
            .unwrap_or_else(|e| panic!("{name} round {round}: {e}"));
            assert!(fine.positions.iter().flatten().all(|x| x.is_finite()));
            let mut constant = mesh.clone();
            constant
                .positions
                .iter_mut()
                .for_each(|p| *p = [0.25, -3.0, 7.5]);
            let c = lsubdiv::mesh::patch::subdivide_with::<_, f64>(
                s, &constant, &topo, &features, steps, 1,
            )
            .unwrap();
            let worst = c
                .positions
                .iter()
                .flat_map(|p| [p[0] - 0.25, p[1] + 3.0, p[2] - 7.5])
                .fold(0.0f64, |m, d| m.max(d.abs()));
            assert!(
                worst < 1e-12,
                "{name} round {round}: constants off by {worst:e}"
            );
            refined += 1;
        }
    }
    assert!(refined > 200, "only {refined} refinements");
}

/// The limit of every featured mesh: finite positions, unit normals, one of each
/// per refined vertex; the vertices without a derived limit are exactly the darts, the
/// creases with a sector other than two faces and the corners with a sector of more than one
/// face (here: the darts mesh's two darts, and none on the creased cube, whose corners have
/// three one-face sectors).
#[test]
fn limits_of_featured_meshes_are_finite_unit_and_listed() {
    use lsubdiv::mesh::patch::limit_with;
    let s = surface("fibonacci");
    for (what, mesh, features) in featured() {
        let topo = Topology::build(&mesh).unwrap();
        let fine = refine_with(&s, &mesh, &features, 3);
        let lim = limit_with::<_, f64>(&s, &mesh, &topo, &features, 3, 2).unwrap();
        assert_eq!(lim.mesh.faces, fine.faces, "{what}");
        assert_eq!(lim.normals.len(), fine.positions.len(), "{what}");
        for (p, n) in lim.mesh.positions.iter().zip(&lim.normals) {
            assert!(p.iter().all(|x| x.is_finite()), "{what}: {p:?}");
            let len = n.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!((len - 1.0).abs() < 1e-12, "{what}: normal {n:?}");
        }
        match what {
            "darts" => assert_eq!(lim.approximate.len(), 2, "{what}"),
            "creased cube" | "grid" | "open box" => {
                assert!(lim.approximate.is_empty(), "{what}: {:?}", lim.approximate)
            }
            _ => {}
        }
    }
}

/// A `Refiner` kept across calls (its output buffer reused, not cleared) gives for new
/// positions exactly what a fresh one gives, on every featured mesh (holes included: their
/// faces are refined, so every output point is written each call).
#[test]
fn a_reused_refiner_equals_a_fresh_one() {
    let s = surface("binary-ternary");
    for (what, mesh, features) in featured() {
        let topo = Topology::build(&mesh).unwrap();
        let mut kept = Refiner::<_, f64>::with_features(&s, &topo, &features, 2, 2).unwrap();
        kept.refine(&mesh.positions).unwrap();
        let moved: Vec<[f64; 3]> = (mesh.positions.iter().enumerate())
            .map(|(i, p)| [p[0] + 0.1 * (i as f64).sin(), p[1] * 1.5, p[2] - 0.2])
            .collect();
        let again = kept.refine(&moved).unwrap().to_vec();
        let mut fresh = Refiner::<_, f64>::with_features(&s, &topo, &features, 2, 1).unwrap();
        assert_eq!(again, fresh.refine(&moved).unwrap(), "{what}");
    }
}

/// A crease that turns at an interior vertex (sectors of one and three faces: its child is
/// set by the curve rule) is still the scheme's curve between its corners, for every scheme;
/// and the limit point there is the curve's (`end_limit` of the refined crease), while its
/// normal is listed as not derived.
#[test]
fn a_crease_turning_at_an_interior_vertex_is_the_schemes_curve() {
    use lsubdiv::mesh::patch::limit_with;
    let mesh = grid(4, 4);
    // Along row 2 to the centre, then up column 2: vertex 12 has two adjacent sharp edges.
    let line: Vec<u32> = vec![10, 11, 12, 17, 22];
    let mut features = Features::default();
    for w in line.windows(2) {
        features.creases.push(([w[0], w[1]], Sharpness::INFINITE));
    }
    let topo = Topology::build(&mesh).unwrap();
    for name in SCHEMES {
        let s = surface(name);
        let (mut c, sigma) = curve(name);
        for steps in 1..=3 {
            let crease = Crease {
                mesh: &mesh,
                topo: &topo,
                features: &features,
                line: &line,
            };
            let (want, worst) = crease.against_curve(&s, (&mut c, &sigma), steps);
            assert!(
                worst < 1e-12,
                "{name} steps={steps}: off the curve by {worst:e}"
            );
            let n = s.tables().image_len(s.tables().axiom, steps) as usize;
            // The limit at the turning vertex: the refined crease's limit there.
            let extended = want.extended(&c.tables(), &sigma).unwrap();
            c.prepare(&extended).unwrap();
            let curve_limit = lsubdiv::end_limit(&c, &sigma, &want).unwrap();
            let lim = limit_with::<_, f64>(&s, &mesh, &topo, &features, steps, 1).unwrap();
            let (p, q) = (lim.mesh.positions[12], curve_limit.positions[2 * n]);
            let off = (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max);
            assert!(
                off < 1e-12,
                "{name} steps={steps}: limit off the curve's by {off:e}"
            );
            assert!(lim.approximate.contains(&12), "{name}");
        }
    }
}

/// Every instruction set this CPU has, the non-temporal writer forced on or off, one or two
/// threads, wide or one-point strips, and ordinary faces refined alone or in stacks give the
/// same points: the kernels run the same operations in the same order on every path
/// ([`lsubdiv::mesh::patch::Simd`]); the fused multiply-adds of AVX2 and AVX-512 give those
/// two the same bits, within 1e-14 of the baseline's (relative to the mesh's size); in f64 and
/// f32 (the latter within f32 rounding of the former); on closed meshes (ordinary faces and
/// fans), open ones and every featured mesh, for every shipped surface scheme.
#[test]
fn every_simd_path_and_writer_gives_the_same_points() {
    use lsubdiv::generated;
    use lsubdiv::mesh::generators::{grid_cube, star, torus};
    use lsubdiv::mesh::patch::Simd;
    let mut meshes = featured();
    meshes.push(("torus", torus(6, 5), Features::default()));
    // The same torus with its faces' y against their order (chains taken downward), as
    // `lsubdiv bench --mesh torus:R:C:x` makes it.
    let mut against = torus(6, 5);
    for f in &mut against.faces {
        f.rotate_left(1);
    }
    meshes.push(("torus, faces along x", against, Features::default()));
    meshes.push(("star", star(), Features::default()));
    // Ordinary faces beside EVs: with Binary-Ternary they wait for the EVs' masks to be
    // contained and start the composed kernel after the first step (start side m > 4).
    meshes.push(("grid cube", grid_cube(4), Features::default()));
    for name in generated::SURFACE_NAMES {
        let s = surface(name);
        let steps = if *name == "binary-ternary" { 2 } else { 3 };
        for (what, mesh, features) in &meshes {
            let topo = Topology::build(mesh).unwrap();
            // Strips of 1 byte: every fan row in one-point strips, each continuing the last.
            // Stacks of one face: each ordinary face refined alone; of two: rows of faces
            // split into stacks that end anywhere.
            let refiner = |simd, stream, threads, strips, stack| {
                let mut r = Refiner::<_, f64>::with_features(&s, &topo, features, steps, threads)
                    .unwrap_or_else(|e| panic!("{name} {what}: {e}"));
                assert_eq!(
                    r.set_simd(simd),
                    simd,
                    "{name} {what}: {simd:?} is available"
                );
                r.set_stream_bytes(stream);
                r.set_strip_bytes(strips);
                r.set_stack(stack);
                r.refine(&mesh.positions).unwrap().to_vec()
            };
            let (wide, most) = (512 << 10, usize::MAX);
            let baseline = refiner(Simd::Baseline, usize::MAX, 1, wide, most);
            assert!(baseline.iter().flatten().all(|x| x.is_finite()));
            let size = baseline
                .iter()
                .flatten()
                .fold(1.0f64, |m, x| m.max(x.abs()));
            let mut fused = None;
            for simd in Simd::available() {
                let first = refiner(simd, usize::MAX, 1, wide, most);
                let runs = [
                    (0, 1, wide, most),
                    (0, 2, wide, most),
                    (usize::MAX, 2, 1, most),
                    (0, 1, 1, most),
                    (usize::MAX, 1, wide, 1),
                    (0, 2, wide, 2),
                ];
                for (stream, threads, strips, stack) in runs {
                    let other = refiner(simd, stream, threads, strips, stack);
                    assert!(
                        other == first,
                        "{name} {what}: {simd:?}, stream from {stream} bytes, {threads} threads, \
                         strips of {strips} bytes, stacks of {stack} faces"
                    );
                }
                let d = first
                    .iter()
                    .flatten()
                    .zip(baseline.iter().flatten())
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(d <= 1e-14 * size, "{name} {what}: {simd:?} off by {d:e}");
                if simd != Simd::Baseline {
                    let fused = fused.get_or_insert_with(|| first.clone());
                    assert!(*fused == first, "{name} {what}: {simd:?} against AVX2");
                }
                // f32 (16 values to a cache line): the writer and the threads change no bit.
                let single = |stream, threads| {
                    let mut r =
                        Refiner::<_, f32>::with_features(&s, &topo, features, steps, threads)
                            .unwrap();
                    r.set_simd(simd);
                    r.set_stream_bytes(stream);
                    r.refine(&mesh.positions).unwrap().to_vec()
                };
                let plain = single(usize::MAX, 1);
                assert!(single(0, 2) == plain, "{name} {what}: {simd:?} f32");
                let d = plain
                    .iter()
                    .flatten()
                    .zip(first.iter().flatten())
                    .fold(0.0f64, |m, (&a, b)| m.max((f64::from(a) - b).abs()));
                assert!(d <= 1e-5 * size, "{name} {what}: {simd:?} f32 off by {d:e}");
            }
        }
    }
}

/// The icosphere of `level` without its cap above z = 0.6, with a crease along two edges of
/// one triangle (one of them semi-sharp, 2 steps), a sharp vertex on another and a hole,
/// split into quads: every face at an EV (the triangles' centres).
fn creased_open_triangles(level: usize) -> (QuadMesh, Features) {
    use lsubdiv::mesh::generators::icosphere;
    use lsubdiv::mesh::polygon::catmull_clark;
    let open = lsubdiv_testkit::meshes::capless(&icosphere(level), 0.6);
    let count = open.faces().count();
    let t = open.faces().nth(7 % count).unwrap().to_vec();
    let mut features = Features::default();
    features.creases.push(([t[0], t[1]], Sharpness::INFINITE));
    features.creases.push(([t[1], t[2]], Sharpness::steps(2)));
    let corner = open.faces().nth(40 % count).unwrap()[0];
    features.corners.push((corner, Sharpness::INFINITE));
    // A hole (refined like every face, its points left out of the output mesh).
    features.holes.push((60 % count) as u32);
    let split = catmull_clark(&open, &features).unwrap();
    (split.mesh, split.features)
}

/// `mesh` with a torus of `rows` × `rows` faces beside it (a separate component, far along
/// x, numbered after it), which makes the refiner compose the steps it would take level by
/// level on the mesh alone.
fn beside_a_torus(mesh: &QuadMesh, rows: usize) -> (QuadMesh, QuadMesh) {
    use lsubdiv::mesh::generators::torus;
    let ring = torus(rows, rows);
    let nv = mesh.positions.len() as u32;
    let mut both = mesh.clone();
    both.positions
        .extend(ring.positions.iter().map(|p| [p[0] + 100.0, p[1], p[2]]));
    both.faces
        .extend(ring.faces.iter().map(|f| f.map(|v| v + nv)));
    assert!(both.faces.len() > 2 * mesh.faces.len());
    (both, ring)
}

/// An open triangle mesh with a sharp and a semi-sharp crease, a sharp vertex and a hole
/// ([`creased_open_triangles`]): its first steps run level by level, phantoms and vertex
/// rules included (`patch/direct.rs`). Beside a torus with more faces than it has, no step
/// runs level by level, and the two refinements give the same points to rounding, on one
/// and two threads.
#[test]
fn an_open_creased_triangle_mesh_starts_level_by_level() {
    use lsubdiv_testkit::points::same_points;
    let (mesh, features) = creased_open_triangles(2);
    let (both, ring) = beside_a_torus(&mesh, 40);
    let (topo, topo_both) = (
        Topology::build(&mesh).unwrap(),
        Topology::build(&both).unwrap(),
    );
    let topo_torus = Topology::build(&ring).unwrap();
    for name in ["uniform-binary", "fibonacci", "binary-ternary"] {
        let s = surface(name);
        for steps in 1..=3 {
            for threads in [1, 2] {
                let refine = |topo: &Topology, mesh: &QuadMesh, features: &Features| {
                    let mut r =
                        Refiner::<_, f64>::with_features(&s, topo, features, steps, threads)
                            .unwrap();
                    let points = r.refine(&mesh.positions).unwrap().to_vec();
                    (r.level_steps(), points)
                };
                let (lead, alone) = refine(&topo, &mesh, &features);
                let (none, together) = refine(&topo_both, &both, &features);
                // A refinement to side 2 runs level by level on any mesh (`patch/direct.rs`);
                // past it the mesh with the torus beside it composes its steps.
                if s.tables().image_len(s.tables().axiom, steps) > 2 {
                    assert_eq!(none, 0, "{name}, {steps} steps");
                }
                if name == "uniform-binary" {
                    assert!(lead >= steps.min(2), "{name}, {steps} steps: {lead}");
                }
                let closed = Features::default();
                let torus = refine(&topo_torus, &ring, &closed).1;
                let moved = torus.iter().map(|p| [p[0] + 100.0, p[1], p[2]]);
                let expected: Vec<[f64; 3]> = alone.iter().copied().chain(moved).collect();
                let d = same_points(&together, &expected);
                assert!(d < 1e-12, "{name}, {steps} steps, {threads} threads: {d:e}");
            }
        }
    }
}
