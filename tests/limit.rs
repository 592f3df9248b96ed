//! Limit masks of curves (issue 16, `compiler::exact::limit`): for every reachable word of
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
    use lsubdiv::runtime::surface::{refine_surface, LabelledMesh};
    use lsubdiv::runtime::topology::Topology;
    use lsubdiv::CurveScheme;
    let mut cube = lsubdiv::runtime::generators::cube();
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
    use lsubdiv::runtime::surface::SurfaceScheme;
    let ub = surface("uniform-binary");
    let st = ub.surface();
    let w = st.ev.limit_weights(4, st.alpha(4).unwrap());
    let want = [4.0 / 9.0, 1.0 / 9.0, 1.0 / 36.0];
    assert!((0..3).all(|i| (w[i] - want[i]).abs() < 1e-12), "{w:?}");
    for name in EV_SCHEMES {
        let s = surface(name);
        let st = s.surface();
        let weights = st.ev.limit_weights(3, st.alpha(3).unwrap());
        let limit = |steps: usize| {
            let (centre, ring) = cube_one_ring(&s, steps);
            let mut p = centre.map(|x| weights[0] * x);
            for (r, d) in ring {
                for (i, x) in p.iter_mut().enumerate() {
                    *x += weights[1] * r[i] + weights[2] * d[i];
                }
            }
            p
        };
        let (a, b) = (limit(4), limit(5));
        let diff = (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
        assert!(
            diff < 1e-12,
            "{name}: the EV limit moves by {diff:e} under refinement"
        );
    }
}

/// The EV's limit tangents from the stationary 1-ring (`EvCoefficients::tangent_weight`, the
/// left eigenvector of λ1): refining the 1-ring one more step scales them by λ1 exactly, and at
/// valence 4 they are the regular tensor product of the curve's tangent and position masks
/// (uniform binary: diagonals a quarter of the edge neighbours, c = √2/4).
#[test]
fn ev_limit_tangents_scale_by_lambda1() {
    use lsubdiv::runtime::surface::SurfaceScheme;
    let c = surface("uniform-binary")
        .surface()
        .ev
        .tangent_weight(4)
        .unwrap();
    assert!((c - 2f64.sqrt() / 4.0).abs() < 1e-12, "{c}");
    for name in EV_SCHEMES {
        let s = surface(name);
        let st = s.surface();
        let n = 3;
        let (c, lambda) = (
            st.ev.tangent_weight(n).unwrap(),
            st.ev.block(n, 1).unwrap().0,
        );
        let theta = std::f64::consts::TAU / n as f64;
        let tangents = |steps: usize| {
            let (mut e1, mut e2) = ([0.0f64; 3], [0.0f64; 3]);
            for (k, (r, d)) in cube_one_ring(&s, steps).1.into_iter().enumerate() {
                let (ar, ad) = (theta * k as f64, theta * (k as f64 + 0.5));
                for i in 0..3 {
                    e1[i] += ar.cos() * r[i] + c * ad.cos() * d[i];
                    e2[i] += ar.sin() * r[i] + c * ad.sin() * d[i];
                }
            }
            (e1, e2)
        };
        let ((a1, a2), (b1, b2)) = (tangents(4), tangents(5));
        let size = a1.iter().chain(&a2).fold(0.0f64, |m, x| m.max(x.abs()));
        let off = (0..3)
            .map(|i| {
                (b1[i] - lambda * a1[i])
                    .abs()
                    .max((b2[i] - lambda * a2[i]).abs())
            })
            .fold(0.0, f64::max);
        assert!(
            off < 1e-10 * size,
            "{name}: tangents off λ1 scaling by {off:e} (size {size:e})"
        );
    }
}
