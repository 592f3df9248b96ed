//! Limit masks of curves (`compiler::exact::limit`): for every reachable word of
//! every shipped cubic scheme, the exact weights agree with an independent evaluation of the
//! non-uniform B-spline (de Boor, `lsubdiv_testkit::spline`) at the point's middle knot, and
//! the tangent weights with its derivative there.

mod common;

use lsubdiv::compiler::exact::Scheme;
use lsubdiv_testkit::spline::de_boor;

/// The shipped schemes of degree 3.
const CUBIC: [&str; 8] = [
    "uniform-binary",
    "fibonacci",
    "fibonacci-alt",
    "binary-ternary",
    "found-cubic",
    "low-ratio",
    "remark-5-3",
    "delay-queue-3",
];

#[test]
fn limit_masks_are_the_b_spline_at_the_middle_knot() {
    for name in CUBIC {
        let s = Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls).unwrap();
        assert_eq!(s.ls.degree, 3, "{name}");
        lsubdiv_testkit::spline::check_limit_masks(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

/// Uniform binary's limit masks are the cubic B-spline's known ones: position (1, 4, 1)/6,
/// tangent (−1, 0, 1)/2 per unit interval.
#[test]
fn uniform_binary_has_the_cubic_b_spline_limit_masks() {
    let s = Scheme::build(lsubdiv_cli::resolve("uniform-binary").unwrap().ls).unwrap();
    for m in &s.limits {
        let p: Vec<f64> = m.position.iter().map(|w| w.to_f64()).collect();
        let t: Vec<f64> = m.tangent.iter().map(|w| w.to_f64()).collect();
        assert_eq!(p, vec![1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0]);
        assert_eq!(t, vec![-0.5, 0.0, 0.5]);
    }
}

/// The limit points of a refined closed curve lie on the coarse spline: each equals de Boor's
/// evaluation of the coarse curve at the refined point's middle knot, and its tangent the
/// derivative there (the mask's parameter has the refined level's lengths: × ρ^s).
#[test]
fn limit_points_of_refined_curves_are_on_the_coarse_spline() {
    use lsubdiv::generic::GenericScheme;
    use lsubdiv::{curve_limit, refine, Curve, CurveScheme};
    use lsubdiv_testkit::spline::knots_and_points;
    for name in CUBIC {
        let mut g =
            GenericScheme::new(Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls).unwrap())
                .unwrap();
        let pts: Vec<[f64; 2]> = (0..9)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 9.0;
                [a.cos() * (1.0 + 0.3 * (3.0 * a).sin()), a.sin()]
            })
            .collect();
        let coarse = Curve::with_axiom(&g.tables(), pts, true);
        let steps = 3;
        g.prepare(&coarse).unwrap();
        let fine = refine(&g, &coarse, steps).unwrap();
        g.prepare(&fine).unwrap();
        let lim = curve_limit(&g, &fine).unwrap();
        let lengths: Vec<f64> = g.scheme().lengths.iter().map(|l| l.to_f64()).collect();
        let rho = g.scheme().analysis.rho.to_f64();
        let (t0, p0) = knots_and_points(&coarse, &lengths, 1.0, 0.0, 3);
        let (t1, _) = knots_and_points(&fine, &lengths, rho.powi(-(steps as i32)), 0.0, 3);
        let period = t0[coarse.points.len()];
        let on = |x: f64| {
            // Into the coarse domain [t0[3], t0[3] + period).
            let x = t0[3] + (x - t0[3]).rem_euclid(period);
            de_boor(&t0, &p0, 3, x)
        };
        let mut worst = (0.0f64, 0.0f64);
        for (k, (p, tan)) in lim.positions.iter().zip(&lim.tangents).enumerate() {
            let x = t1[k + 2];
            let want = on(x);
            let h = 1e-6;
            let (a, b) = (on(x - h), on(x + h));
            for c in 0..2 {
                worst.0 = worst.0.max((p[c] - want[c]).abs());
                let slope = (b[c] - a[c]) / (2.0 * h);
                worst.1 = worst.1.max((tan[c] * rho.powi(steps as i32) - slope).abs());
            }
        }
        assert!(
            worst.0 < 1e-12,
            "{name}: limit points off the spline by {:e}",
            worst.0
        );
        assert!(worst.1 < 1e-5, "{name}: tangents off by {:e}", worst.1);
    }
}

/// `lsubdiv curve --limit [--tangents]`: the limit points (and derivatives as extra columns)
/// of the refined polygon; with interpolated ends the end points are their own limit points;
/// degrees without limit masks are refused.
#[test]
fn the_command_line_writes_limit_points_and_tangents() {
    use common::cli::{lsubdiv, stderr, write};
    let dir = tempfile::tempdir().unwrap();
    let square = write(dir.path(), "sq.txt", "0 0\n1 0\n1 1\n0 1\n");
    let run = |args: &[&str]| {
        let o = lsubdiv(args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let rows: Vec<Vec<f64>> = String::from_utf8(o.stdout)
            .unwrap()
            .lines()
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect();
        rows
    };
    // Uniform binary, no step: (1, 4, 1)/6 and (−1, 0, 1)/2 around each corner.
    let rows = run(&[
        "curve",
        "uniform-binary",
        "--steps",
        "0",
        "--closed",
        &square,
        "-o",
        "-",
        "--limit",
        "--tangents",
    ]);
    assert_eq!(rows[0], vec![1.0 / 6.0, 1.0 / 6.0, 0.5, -0.5]);
    assert_eq!(rows.len(), 4);
    // Interpolated ends: the end points are on the limit curve.
    let rows = run(&[
        "curve",
        "fibonacci",
        "--steps",
        "2",
        "--ends",
        "interpolate",
        &square,
        "-o",
        "-",
        "--limit",
    ]);
    assert_eq!(rows.first().unwrap(), &vec![0.0, 0.0]);
    assert_eq!(rows.last().unwrap(), &vec![0.0, 1.0]);
    // Degree 2 has no limit masks.
    let o = lsubdiv(&[
        "curve",
        "fibonacci-curve",
        "--steps",
        "1",
        "--closed",
        &square,
        "-o",
        "-",
        "--limit",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("no limit masks for degree 2"),
        "{}",
        stderr(&o)
    );
}

/// The size guard counts the limit pass (its positions and derivatives beside the refined
/// points; with interpolated ends the extension its masks read): a budget that the refinement
/// fits is refused for `--limit` with the prediction, before anything is written, and met with
/// a larger one. The points are streamed to the file, so the refinement alone fits in less
/// than its text.
#[test]
fn the_size_guard_counts_the_limit_pass() {
    use common::cli::{lsubdiv, stderr, write};
    let dir = tempfile::tempdir().unwrap();
    let circle: String = (0..200)
        .map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / 200.0;
            format!("{} {}\n", t.cos(), t.sin())
        })
        .collect();
    let input = write(dir.path(), "circle.txt", &circle);
    let out = dir.path().join("out.txt");
    let out = out.to_str().unwrap();
    // 9 steps of uniform binary: 102,400 points, ~4 MB of text; two levels of 2D points and
    // labels ~2.7 MB; the limit pass adds ~3.3 MB, the extension ~1.7 MB more.
    let run = |max: &str, extra: &[&str]| {
        let mut args = vec!["curve", "uniform-binary", "--steps", "9", &input, "-o", out];
        args.extend_from_slice(&["--max-memory", max]);
        args.extend_from_slice(extra);
        lsubdiv(&args)
    };
    for ends in [&["--closed"][..], &["--ends", "interpolate"]] {
        let plain = run("3M", ends);
        assert!(plain.status.success(), "{ends:?}: {}", stderr(&plain));
        let text = std::fs::read_to_string(out).unwrap();
        assert!(text.len() > 3 << 20, "{ends:?}: {} bytes", text.len());
        std::fs::remove_file(out).unwrap();
        let limit = [ends, &["--limit", "--tangents"]].concat();
        let refused = run("3M", &limit);
        assert_eq!(refused.status.code(), Some(2), "{ends:?}");
        let e = stderr(&refused);
        assert!(
            e.contains("would make") && e.contains("--max-memory is ~3.0 MiB"),
            "{e}"
        );
        assert!(
            !std::path::Path::new(out).exists(),
            "{ends:?}: written anyway"
        );
        let fits = run("9M", &limit);
        assert!(fits.status.success(), "{ends:?}: {}", stderr(&fits));
        let rows = std::fs::read_to_string(out).unwrap();
        assert!(rows.lines().all(|l| l.split(' ').count() == 4), "{ends:?}");
        std::fs::remove_file(out).unwrap();
    }
}

/// The compiled surface scheme `name`.
fn surface(name: &str) -> lsubdiv::generic::GenericSurface {
    let s = Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls).unwrap();
    lsubdiv::generic::GenericSurface::new(s).unwrap()
}

/// The surface schemes whose EV limits are checked on the cube.
const EV_SCHEMES: [&str; 4] = [
    "uniform-binary",
    "fibonacci",
    "binary-ternary",
    "found-cubic",
];

/// A vertex and its 1-ring: (radial, diagonal) per wedge.
type OneRing = ([f64; 3], Vec<([f64; 3], [f64; 3])>);

/// The cube (vertex 5 moved: nothing is symmetric about vertex 0) refined `steps` times by the
/// reference driver: vertex 0, an EV of valence 3 (base vertices keep their index), and its
/// 1-ring in rotation order, (radial R_k, diagonal D_k) per wedge, D_k between R_k and
/// R_{k+1}.
fn cube_one_ring(s: &lsubdiv::generic::GenericSurface, steps: usize) -> OneRing {
    use lsubdiv::mesh::surface::{refine_surface, LabelledMesh};
    use lsubdiv::mesh::topology::Topology;
    use lsubdiv::CurveScheme;
    let mut cube = lsubdiv::mesh::generators::cube();
    cube.positions[5] = [1.3, -0.8, 1.1];
    let lm = LabelledMesh::with_axiom(&s.tables(), cube).unwrap();
    let (fine, _) = refine_surface(s, &lm, steps).unwrap();
    let topo = Topology::build(&fine.mesh).unwrap();
    let at = |v: u32| fine.mesh.positions[v as usize];
    let ring = topo
        .rotation(0)
        .iter()
        .map(|w| {
            let prev = if w.next_is_plus {
                (w.corner + 3) % 4
            } else {
                (w.corner + 1) % 4
            };
            (
                at(topo.vertex(w.face, prev)),
                at(topo.vertex(w.face, (w.corner + 2) % 4)),
            )
        })
        .collect();
    (at(0), ring)
}

/// The EV's limit point from its stationary 1-ring (`EvCoefficients::limit_weights`, the left
/// eigenvector of eigenvalue 1): fixed under refinement (the limit of the 1-ring after one
/// more step is the same point), and at valence 4 the tensor product of the curve's limit
/// mask (uniform binary: 4/9, 1/9 per edge neighbour, 1/36 per diagonal one).
#[test]
fn ev_limit_points_are_fixed_under_refinement() {
    use lsubdiv::mesh::surface::SurfaceScheme;
    let ub = surface("uniform-binary");
    let st = ub.surface();
    let w = st.ev.limit_weights(4, st.alpha(4).unwrap());
    let want = [4.0 / 9.0, 1.0 / 9.0, 1.0 / 36.0];
    assert!((0..3).all(|i| (w[i] - want[i]).abs() < 1e-12), "{w:?}");
    for name in EV_SCHEMES {
        let diff = ev_limit_moves(&surface(name), 4);
        assert!(
            diff < 1e-12,
            "{name}: the EV limit moves by {diff:e} under refinement"
        );
    }
}

/// How far the cube's EV limit point, from its 1-ring after `steps` steps, moves with one
/// more step.
fn ev_limit_moves(s: &lsubdiv::generic::GenericSurface, steps: usize) -> f64 {
    use lsubdiv::mesh::surface::SurfaceScheme;
    let st = s.surface();
    let weights = st.ev.limit_weights(3, st.alpha(3).unwrap());
    let limit = |steps: usize| {
        let (centre, ring) = cube_one_ring(s, steps);
        let mut p = centre.map(|x| weights[0] * x);
        for (r, d) in ring {
            for (i, x) in p.iter_mut().enumerate() {
                *x += weights[1] * r[i] + weights[2] * d[i];
            }
        }
        p
    };
    let (a, b) = (limit(steps), limit(steps + 1));
    (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

/// The EV's limit tangents from the stationary 1-ring (`EvCoefficients::tangent_weight`, the
/// left eigenvector of λ1): refining the 1-ring one more step scales them by λ1 exactly, and at
/// valence 4 they are the regular tensor product of the curve's tangent and position masks
/// (uniform binary: diagonals a quarter of the edge neighbours, c = √2/4).
#[test]
fn ev_limit_tangents_scale_by_lambda1() {
    use lsubdiv::mesh::surface::SurfaceScheme;
    let c = surface("uniform-binary")
        .surface()
        .ev
        .tangent_weight(4)
        .unwrap();
    assert!((c - 2f64.sqrt() / 4.0).abs() < 1e-12, "{c}");
    for name in EV_SCHEMES {
        let (off, size) = ev_tangents_off(&surface(name), 4);
        assert!(
            off < 1e-10 * size,
            "{name}: tangents off λ1 scaling by {off:e} (size {size:e})"
        );
    }
}

/// How far the cube's EV limit tangents, from its 1-ring after `steps` steps, are from λ1
/// times themselves after one more step, and their size.
fn ev_tangents_off(s: &lsubdiv::generic::GenericSurface, steps: usize) -> (f64, f64) {
    use lsubdiv::mesh::surface::SurfaceScheme;
    let st = s.surface();
    let n = 3;
    let (c, lambda) = (
        st.ev.tangent_weight(n).unwrap(),
        st.ev.block(n, 1).unwrap().0,
    );
    let theta = std::f64::consts::TAU / n as f64;
    let tangents = |steps: usize| {
        let (mut e1, mut e2) = ([0.0f64; 3], [0.0f64; 3]);
        for (k, (r, d)) in cube_one_ring(s, steps).1.into_iter().enumerate() {
            let (ar, ad) = (theta * k as f64, theta * (k as f64 + 0.5));
            for i in 0..3 {
                e1[i] += ar.cos() * r[i] + c * ad.cos() * d[i];
                e2[i] += ar.sin() * r[i] + c * ad.sin() * d[i];
            }
        }
        (e1, e2)
    };
    let ((a1, a2), (b1, b2)) = (tangents(steps), tangents(steps + 1));
    let size = a1.iter().chain(&a2).fold(0.0f64, |m, x| m.max(x.abs()));
    let off = (0..3)
        .map(|i| {
            (b1[i] - lambda * a1[i])
                .abs()
                .max((b2[i] - lambda * a2[i]).abs())
        })
        .fold(0.0, f64::max);
    (off, size)
}

/// The shipped cubic schemes that refine surfaces, by name.
fn surface_schemes() -> Vec<(&'static str, lsubdiv::generic::GenericSurface)> {
    CUBIC
        .into_iter()
        .filter_map(|name| {
            let s = Scheme::build(lsubdiv_cli::resolve(name).unwrap().ls).unwrap();
            Some((name, lsubdiv::generic::GenericSurface::new(s).ok()?))
        })
        .collect()
}

/// The uniform cubic B-spline's four weights and their derivatives at parameter t, for the
/// points centred at knots ⌊t⌋ − 1 ..= ⌊t⌋ + 2 (unit intervals): the independent reference.
fn uniform_cubic(t: f64) -> (i64, [f64; 4], [f64; 4]) {
    let k = t.floor();
    let s = t - k;
    let value = [
        (1.0 - s).powi(3) / 6.0,
        (3.0 * s.powi(3) - 6.0 * s * s + 4.0) / 6.0,
        (-3.0 * s.powi(3) + 3.0 * s * s + 3.0 * s + 1.0) / 6.0,
        s.powi(3) / 6.0,
    ];
    let slope = [
        -(1.0 - s).powi(2) / 2.0,
        1.5 * s * s - 2.0 * s,
        -1.5 * s * s + s + 0.5,
        s * s / 2.0,
    ];
    (k as i64 - 1, value, slope)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The angle between two vectors, in radians.
fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = cross(a, b);
    let sin = c.iter().map(|x| x * x).sum::<f64>().sqrt();
    let cos: f64 = (0..3).map(|i| a[i] * b[i]).sum();
    sin.atan2(cos)
}

/// On the torus (every vertex of valence 4, every edge labelled by the axiom) the limit
/// surface is the uniform bicubic B-spline of the control mesh, in the parameter where each
/// base edge is one unit: knot insertion keeps the spline. Every refined vertex (x, y) of
/// base face (i, j) sits at the knots (i + K_x / K_N, j + K_y / K_N), K the prefix sums of
/// the exact lengths of W_s. The limit positions equal the spline there to 1e-12 and the
/// limit normals its ∂u × ∂v to an angle of 1e-9, for every surface scheme.
#[test]
fn limit_on_the_torus_is_the_tensor_b_spline_at_the_knots() {
    for (name, s) in surface_schemes() {
        torus_limit_is_the_tensor_b_spline(name, &s, 3);
    }
}

/// [`limit_on_the_torus_is_the_tensor_b_spline_at_the_knots`] for one scheme and `steps`.
fn torus_limit_is_the_tensor_b_spline(
    name: &str,
    s: &lsubdiv::generic::GenericSurface,
    steps: usize,
) {
    use lsubdiv::mesh::features::Features;
    use lsubdiv::mesh::patch::limit_with;
    use lsubdiv::mesh::topology::Topology;
    let (rows, cols) = (5, 7);
    let torus = lsubdiv::mesh::generators::torus(rows, cols);
    let topo = Topology::build(&torus).unwrap();
    let lim = limit_with::<_, f64>(s, &torus, &topo, &Features::default(), steps, 2).unwrap();
    assert!(lim.approximate.is_empty(), "{name}");
    // W_s's knots, in base-edge units.
    let knots = common::knots(s, steps);
    let n = knots.len() - 1;
    let total = knots[n];
    let at = |a: i64, b: i64| {
        let id = a.rem_euclid(rows as i64) as usize * cols + b.rem_euclid(cols as i64) as usize;
        torus.positions[id]
    };
    let (mut worst_p, mut worst_n) = (0.0f64, 0.0f64);
    for (q, face) in lim.mesh.faces.iter().enumerate() {
        let (f, cell) = (q / (n * n), q % (n * n));
        let (x, y) = (cell % n, cell / n);
        let u = (f / cols) as f64 + knots[x] / total;
        let v = (f % cols) as f64 + knots[y] / total;
        let (ku, wu, du) = uniform_cubic(u);
        let (kv, wv, dv) = uniform_cubic(v);
        let (mut p, mut su, mut sv) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for a in 0..4 {
            for b in 0..4 {
                let c = at(ku + a as i64, kv + b as i64);
                for i in 0..3 {
                    p[i] += wu[a] * wv[b] * c[i];
                    su[i] += du[a] * wv[b] * c[i];
                    sv[i] += wu[a] * dv[b] * c[i];
                }
            }
        }
        let vtx = face[0] as usize;
        let got = lim.mesh.positions[vtx];
        worst_p = worst_p.max((0..3).map(|i| (got[i] - p[i]).abs()).fold(0.0, f64::max));
        worst_n = worst_n.max(angle(lim.normals[vtx], cross(su, sv)));
    }
    assert!(
        worst_p < 1e-12,
        "{name}: limit positions off by {worst_p:e}"
    );
    assert!(
        worst_n < 1e-9,
        "{name}: limit normals off by {worst_n:e} rad"
    );
    // In f32, the same to f32 precision.
    let lim32 = limit_with::<_, f32>(s, &torus, &topo, &Features::default(), steps, 2).unwrap();
    assert_eq!(lim32.mesh.faces, lim.mesh.faces, "{name}");
    for (a, b) in lim32.mesh.positions.iter().zip(&lim.mesh.positions) {
        assert!(
            (0..3).all(|i| (f64::from(a[i]) - b[i]).abs() < 1e-5),
            "{name}"
        );
    }
}

proptest::proptest! {
    // Each case compiles a scheme exactly (small systems: milliseconds).
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 32, ..Default::default() })]

    /// Random symmetric surface schemes (`common::surface_systems`): the limit on the torus is
    /// the tensor bicubic B-spline at the knots of W_s, for as many steps as keep it small.
    #[test]
    fn random_schemes_limit_on_the_torus_is_the_tensor_b_spline(
        sys in common::surface_systems()
    ) {
        use lsubdiv::CurveScheme;
        let Some((text, _, s)) = common::drawn_surface(&sys) else {
            return Ok(());
        };
        for steps in 1..=3 {
            if s.tables().image_len(s.tables().axiom, steps) > 24 {
                break;
            }
            torus_limit_is_the_tensor_b_spline(&text, &s, steps);
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 32, ..Default::default() })]

    /// Random symmetric surface schemes (`common::surface_systems`), once the labels around
    /// the cube's EVs are stationary (\[G\] Lemma 4.6): the EV limit point from the 1-ring does
    /// not move with one more step, and the limit tangents scale by λ1.
    #[test]
    fn random_schemes_ev_limits_hold_under_refinement(sys in common::surface_systems()) {
        use lsubdiv::mesh::surface::SurfaceScheme;
        use lsubdiv::CurveScheme;
        let Some((text, _, s)) = common::drawn_surface(&sys) else {
            return Ok(());
        };
        let steps = s.surface().stationary_from() + 1;
        if s.tables().image_len(s.tables().axiom, steps + 1) > 48 {
            return Ok(());
        }
        let diff = ev_limit_moves(&s, steps);
        proptest::prop_assert!(diff < 1e-12, "EV limit moves by {diff:e}\n{text}");
        let (off, size) = ev_tangents_off(&s, steps);
        proptest::prop_assert!(off < 1e-10 * size, "tangents off by {off:e} of {size:e}\n{text}");
    }
}

/// Uniform binary is Catmull–Clark on quads: its limit points are Catmull–Clark's known limit
/// masks, (16 P + 4 Σ edge neighbours + Σ diagonal neighbours) / 36 at regular interior
/// vertices, (P₋ + 4 P + P₊) / 6 along a boundary, and the corner itself at a corner, on an
/// open grid after two steps (read off the refined mesh's own connectivity).
#[test]
fn uniform_binary_limit_is_catmull_clark_on_regular_regions_and_boundaries() {
    use lsubdiv::mesh::features::Features;
    use lsubdiv::mesh::patch::limit_with;
    use lsubdiv::mesh::topology::Topology;
    let mut grid = lsubdiv::mesh::generators::open_grid(3, 4);
    for (i, p) in grid.positions.iter_mut().enumerate() {
        p[2] = (i as f64 * 0.7).sin();
    }
    let topo = Topology::build(&grid).unwrap();
    let s = surface("uniform-binary");
    let steps = 2;
    let fine = lsubdiv::mesh::patch::subdivide_with::<_, f64>(
        &s,
        &grid,
        &topo,
        &Features::default(),
        steps,
        1,
    )
    .unwrap();
    let lim = limit_with::<_, f64>(&s, &grid, &topo, &Features::default(), steps, 1).unwrap();
    let ft = Topology::build(&fine).unwrap();
    let p = |v: u32| fine.positions[v as usize];
    let mut checked = [0usize; 3];
    for v in 0..ft.vertex_count() as u32 {
        let rot = ft.rotation(v);
        let spokes: Vec<u32> = ft
            .spokes(v)
            .map(|e| {
                let [a, b] = ft.edge_vertices(e);
                a + b - v
            })
            .collect();
        let want: [f64; 3] = if !ft.is_boundary(v) && rot.len() == 4 {
            checked[0] += 1;
            let diag = rot.iter().map(|w| ft.vertex(w.face, (w.corner + 2) % 4));
            std::array::from_fn(|i| {
                (16.0 * p(v)[i]
                    + 4.0 * spokes.iter().map(|&u| p(u)[i]).sum::<f64>()
                    + diag.clone().map(|u| p(u)[i]).sum::<f64>())
                    / 36.0
            })
        } else if rot.len() == 1 {
            checked[2] += 1;
            p(v)
        } else {
            checked[1] += 1;
            let (a, b) = (spokes[0], spokes[spokes.len() - 1]);
            std::array::from_fn(|i| (p(a)[i] + 4.0 * p(v)[i] + p(b)[i]) / 6.0)
        };
        let got = lim.mesh.positions[v as usize];
        let off = (0..3).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max);
        assert!(off < 1e-14, "vertex {v}: {got:?} vs {want:?}");
    }
    assert!(checked.iter().all(|&c| c > 0), "{checked:?}");
}

/// At the cube's EVs: the limit point is fixed under refinement (the limit after one more
/// step is the same point, 1e-12; so is every other point's, and its normal), and the normals of the refined 1-ring faces converge to
/// the limit normal as steps grow (the angle shrinks step by step; the sequence is printed).
#[test]
fn ev_limit_is_fixed_and_the_one_ring_normals_converge_to_it() {
    use lsubdiv::mesh::features::Features;
    use lsubdiv::mesh::patch::limit_with;
    use lsubdiv::mesh::topology::Topology;
    use lsubdiv::CurveScheme;
    let mut cube = lsubdiv::mesh::generators::cube();
    cube.positions[5] = [1.3, -0.8, 1.1];
    let topo = Topology::build(&cube).unwrap();
    for name in EV_SCHEMES {
        let s = surface(name);
        let limit =
            |steps| limit_with::<_, f64>(&s, &cube, &topo, &Features::default(), steps, 2).unwrap();
        let (a, b) = (limit(4), limit(5));
        let off = (0..3)
            .map(|i| (a.mesh.positions[0][i] - b.mesh.positions[0][i]).abs())
            .fold(0.0, f64::max);
        assert!(off < 1e-12, "{name}: the EV's limit moves by {off:e}");
        assert!(angle(a.normals[0], b.normals[0]) < 1e-12, "{name}");
        // Every point of level 4, EVs' neighbours included, keeps its limit at level 5: point
        // (x, y) of a base face is corner 0 of its cell (x, y), and old knot x is new knot
        // Off(x) = Σ_{i<x} |π(W_4[i])|.
        let t = s.tables();
        let word = t.iterate(t.axiom, 4);
        let mut off = vec![0usize];
        for &a in &word {
            off.push(off[off.len() - 1] + t.rule(a).len());
        }
        let (n, m) = (word.len(), off[word.len()]);
        let mut worst = (0.0f64, 0.0f64);
        for f in 0..cube.faces.len() {
            for y in 0..n {
                for x in 0..n {
                    let va = a.mesh.faces[f * n * n + y * n + x][0] as usize;
                    let vb = b.mesh.faces[f * m * m + off[y] * m + off[x]][0] as usize;
                    let (p, q) = (a.mesh.positions[va], b.mesh.positions[vb]);
                    let d = (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f64::max);
                    worst.0 = worst.0.max(d);
                    worst.1 = worst.1.max(angle(a.normals[va], b.normals[vb]));
                }
            }
        }
        assert!(
            worst.0 < 1e-12,
            "{name}: a limit point moves by {:e}",
            worst.0
        );
        assert!(
            worst.1 < 1e-9,
            "{name}: a limit normal turns by {:e}",
            worst.1
        );
        let mut angles = Vec::new();
        for steps in 2..=7 {
            let fine = lsubdiv::mesh::patch::subdivide_with::<_, f64>(
                &s,
                &cube,
                &topo,
                &Features::default(),
                steps,
                2,
            )
            .unwrap();
            let ft = Topology::build(&fine).unwrap();
            let p = |v: u32| fine.positions[v as usize];
            let mut mean = [0.0; 3];
            for w in ft.rotation(0) {
                let f = fine.faces[w.face as usize];
                let c = w.corner as usize;
                let d = |j: usize| {
                    let q = p(f[(c + j) % 4]);
                    [0, 1, 2].map(|i| q[i] - p(0)[i])
                };
                let n = cross(d(1), d(3));
                let len = n.iter().map(|x| x * x).sum::<f64>().sqrt();
                for i in 0..3 {
                    mean[i] += n[i] / len;
                }
            }
            angles.push(angle(mean, a.normals[0]));
        }
        eprintln!("{name}: 1-ring face normals vs the limit normal, steps 2..=7: {angles:?}");
        assert!(
            angles.windows(2).all(|w| w[1] < w[0]),
            "{name}: not converging: {angles:?}"
        );
        assert!(angles[angles.len() - 1] < 1e-3, "{name}: {angles:?}");
    }
}

/// The creased cube (every edge infinitely sharp, every vertex a corner with three one-face
/// sectors) is its own limit surface: limit points on the cube, the normal of each face's
/// inner points that face's, on an edge the bisector of its two faces', at a corner the mean
/// of its three; nothing approximate.
#[test]
fn the_creased_cube_is_its_own_limit() {
    use lsubdiv::mesh::patch::limit_with;
    use lsubdiv::mesh::topology::Topology;
    let (cube, features) = lsubdiv::mesh::generators::creased_cube();
    let topo = Topology::build(&cube).unwrap();
    for name in EV_SCHEMES {
        let s = surface(name);
        let lim = limit_with::<_, f64>(&s, &cube, &topo, &features, 2, 1).unwrap();
        assert!(lim.approximate.is_empty(), "{name}");
        for (p, n) in lim.mesh.positions.iter().zip(&lim.normals) {
            // On the cube [-1, 1]³: at least one coordinate is ±1, the others inside.
            let on: Vec<usize> = (0..3)
                .filter(|&i| (p[i].abs() - 1.0).abs() < 1e-12)
                .collect();
            assert!(
                !on.is_empty() && p.iter().all(|x| x.abs() <= 1.0 + 1e-12),
                "{p:?}"
            );
            let k = (on.len() as f64).sqrt();
            let want: [f64; 3] = std::array::from_fn(|i| {
                if on.contains(&i) {
                    p[i].signum() / k
                } else {
                    0.0
                }
            });
            assert!(
                angle(*n, want) < 1e-9,
                "{name}: normal {n:?} at {p:?}, want {want:?}"
            );
        }
    }
}

/// `lsubdiv subdivide --limit` writes one `vn` per `v` and faces `a//a` (OBJ), or vertex
/// properties nx ny nz (PLY), the positions those of the library's `limit_with`; a
/// semi-sharp crease outlasting the steps is refused (exit 2), naming the reason.
#[test]
fn subdivide_writes_limit_positions_and_normals() {
    use common::cli::{lsubdiv, stderr, write};
    let dir = tempfile::tempdir().unwrap();
    let cube =
        "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
                f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    let input = write(dir.path(), "cube.obj", cube);
    let out = dir.path().join("out.obj");
    let limit = |input: &str, out: &std::path::Path| {
        let args = [
            "subdivide",
            "fibonacci",
            input,
            "--steps",
            "3",
            "--limit",
            "-o",
        ];
        let mut args = args.to_vec();
        args.push(out.to_str().unwrap());
        lsubdiv(&args)
    };
    let o = limit(&input, &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let count = |p: &str| text.lines().filter(|l| l.starts_with(p)).count();
    assert_eq!(count("v "), count("vn "));
    assert!(count("vn ") > 8);
    let face = text.lines().find(|l| l.starts_with("f ")).unwrap();
    assert!(
        face.split_whitespace().skip(1).all(|c| {
            let (a, b) = c.split_once("//").unwrap();
            a == b
        }),
        "{face}"
    );
    // The positions are the library's limit.
    let mesh = lsubdiv::mesh_file::parse_checked("cube.obj", cube.as_bytes().to_vec()).unwrap();
    let s = surface("fibonacci");
    let lim = lsubdiv::mesh::patch::limit_with::<_, f64>(
        &s,
        &mesh.mesh,
        &mesh.topology,
        &mesh.features,
        3,
        1,
    )
    .unwrap();
    let first: Vec<f64> = text.lines().find(|l| l.starts_with("v ")).unwrap()[2..]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(first, lim.mesh.positions[0].to_vec());
    // PLY: nx ny nz after x y z.
    let ply = dir.path().join("out.ply");
    let o = limit(&input, &ply);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&ply).unwrap();
    assert!(text.contains("property double x\nproperty double y\nproperty double z\nproperty double nx\nproperty double ny\nproperty double nz\n"), "{text:.400}");
    // A crease of sharpness 4 is still sharp after 3 steps.
    let creased = write(
        dir.path(),
        "creased.obj",
        &format!("{cube}t crease 2/1/0 0 1 4\n"),
    );
    let o = limit(&creased, &out);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("still sharp"), "{}", stderr(&o));
}

/// The limit pass's result does not depend on how it runs: every SIMD path this CPU has, one to
/// three threads, bit for bit (from the same refined points), on meshes with more faces than a worker takes at once (EVs of
/// valence 3, a hole and an open boundary, infinitely and semi-sharp creases).
#[test]
fn the_limit_is_the_same_on_every_path_and_thread_count() {
    use lsubdiv::mesh::features::{Features, Sharpness};
    use lsubdiv::mesh::generators::{cube_with_creased_top, grid_cube, grid_with_hole};
    use lsubdiv::mesh::patch::{Refiner, Simd};
    use lsubdiv::mesh::surface::SurfaceScheme;
    use lsubdiv::mesh::topology::Topology;
    let (top, top_features) = cube_with_creased_top(Sharpness::steps(1));
    let meshes = [
        ("grid cube", grid_cube(10), Features::default()),
        (
            "grid with a hole",
            grid_with_hole(25).0,
            grid_with_hole(25).1,
        ),
        ("cube with a semi-sharp top", top, top_features),
    ];
    for name in EV_SCHEMES {
        let s = surface(name);
        let steps = s.surface().stationary_from().max(2);
        for (label, mesh, features) in &meshes {
            let topo = Topology::build(mesh).unwrap();
            // Refined on the baseline path (the FMA paths refine to other bits), the limit
            // taken on each.
            let refined = |threads: usize| {
                let mut r =
                    Refiner::<_, f64>::with_features(&s, &topo, features, steps, threads).unwrap();
                r.set_simd(Simd::Baseline);
                r.refine(&mesh.positions).unwrap();
                r
            };
            let one = refined(1).limit().unwrap();
            assert!(
                topo.face_count() > 512 || label.starts_with("cube"),
                "{label}"
            );
            for threads in 1..=3 {
                let mut r = refined(threads);
                for simd in Simd::available() {
                    r.set_simd(simd);
                    assert!(
                        r.limit().unwrap() == one,
                        "{name} on the {label}: {} on {threads} threads",
                        simd.name()
                    );
                }
            }
        }
    }
}
