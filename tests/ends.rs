//! Open curves with interpolated ends (`--ends interpolate`, `lsubdiv::runtime::ends`): for
//! uniform binary the odd-symmetric extension gives the cubic B-spline boundary rules that
//! Catmull–Clark uses on boundaries and creases (end point kept, edge midpoints, (1, 6, 1)/8);
//! for every symmetric scheme the ends stay, the interior is the ordinary refinement, counts are
//! |π^N(edges)| + 1, and refinement commutes with affine maps and with reversal.

mod common;

use common::cli::{lsubdiv, stderr, write};
use common::Lcg;
use lsubdiv::compiler::exact::symmetry::rule_mirror;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::GenericScheme;
use lsubdiv::{refine, refine_ends, Curve, CurveScheme, EndCurve};
use lsubdiv_cli::resolve;

/// The generic scheme and its mirror σ.
fn scheme(name: &str) -> (GenericScheme, Vec<u8>) {
    let r = resolve(name).expect("shipped scheme");
    let sigma = rule_mirror(&r.ls).expect("a symmetric scheme");
    let s = GenericScheme::new(Scheme::build(r.ls).expect("compiles")).expect("tabulates");
    (s, sigma)
}

/// Refines by the extension, tabulating its words first.
fn ends(s: &mut GenericScheme, sigma: &[u8], c: &EndCurve<3>, steps: usize) -> EndCurve<3> {
    s.prepare(&c.extended(&s.tables(), sigma).unwrap()).unwrap();
    refine_ends(s, sigma, c, steps).unwrap()
}

fn close(a: &[[f64; 3]], b: &[[f64; 3]], tol: f64) -> bool {
    a.len() == b.len()
        && a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| (x - y).abs() <= tol * (1.0 + x.abs()))
}

/// One step of the cubic B-spline with interpolated ends, written out (the Catmull–Clark
/// boundary curve rules of OpenSubdiv's Catmark scheme, docs "Subdivision Surfaces", boundary
/// interpolation): the ends stay, every edge gets its midpoint, an interior point becomes
/// (P_{i−1} + 6 P_i + P_{i+1})/8.
fn cubic_boundary_step(p: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let m = p.len();
    let mut out = vec![p[0]];
    for i in 1..m {
        out.push(std::array::from_fn(|k| (p[i - 1][k] + p[i][k]) / 2.0));
        if i + 1 < m {
            out.push(std::array::from_fn(|k| {
                (p[i - 1][k] + 6.0 * p[i][k] + p[i + 1][k]) / 8.0
            }));
        }
    }
    out.push(p[m - 1]);
    out
}

#[test]
fn uniform_binary_gives_the_cubic_boundary_rules() {
    let (mut s, sigma) = scheme("uniform-binary");
    let mut rng = Lcg(7);
    let points: Vec<[f64; 3]> = (0..6)
        .map(|_| std::array::from_fn(|_| rng.next()))
        .collect();
    let coarse = EndCurve::with_axiom(&s.tables(), points.clone());
    let mut expect = points;
    for steps in 1..=4 {
        expect = cubic_boundary_step(&expect);
        let fine = ends(&mut s, &sigma, &coarse, steps);
        assert!(close(&fine.points, &expect, 1e-14), "step {steps}");
        assert_eq!(fine.labels.len() + 1, fine.points.len());
    }
}

#[test]
fn every_symmetric_scheme_keeps_its_ends_and_refines_the_interior_as_usual() {
    for name in [
        "uniform-binary",
        "binary-ternary",
        "fibonacci",
        "fibonacci-alt",
        "remark-5-3",
        "low-ratio",
        "delay-queue-3",
    ] {
        let (mut s, sigma) = scheme(name);
        let t = s.tables();
        let d = t.degree;
        let mut rng = Lcg(name.len() as u64);
        let points: Vec<[f64; 3]> = (0..8)
            .map(|_| std::array::from_fn(|_| rng.next()))
            .collect();
        let n = s.scheme().ls.n() as u8;
        let labels: Vec<u8> = (0..7).map(|i| (i * 5 % n as usize) as u8).collect();
        let coarse = EndCurve {
            points: points.clone(),
            labels: labels.clone(),
        };
        let steps = 3;
        let fine = ends(&mut s, &sigma, &coarse, steps);
        // The ends stay, exactly; one label per edge, |π^N(edges)| of them.
        assert_eq!(fine.points[0], points[0], "{name}");
        assert_eq!(fine.points.last(), points.last(), "{name}");
        let count = s.tables().image_len(&labels, steps);
        assert_eq!(fine.labels.len() as u128, count, "{name}");
        assert_eq!(fine.points.len(), fine.labels.len() + 1, "{name}");
        // The size guard predicts that count exactly.
        let p = lsubdiv_cli::limits::curve_ends(&s.tables(), &labels, points.len(), 3, steps);
        assert_eq!(p.vertices, fine.points.len() as u128, "{name}");

        // The interior is the ordinary ([N] §2.3) refinement of the real points: that refined
        // polygon is a contiguous run of the interpolated one.
        let ext = coarse.extended(&s.tables(), &sigma).unwrap();
        let r = (d - 1) / 2;
        let shrink = Curve {
            points: points.clone(),
            labels: ext.labels[r..r + points.len() + d].to_vec(),
            closed: false,
        };
        let plain = refine(&s, &shrink, steps).unwrap();
        let found = (0..=fine.points.len() - plain.points.len()).any(|o| {
            close(
                &fine.points[o..o + plain.points.len()],
                &plain.points,
                1e-12,
            )
        });
        assert!(
            found,
            "{name}: the interior differs from the ordinary refinement"
        );

        // Affine maps commute with refinement.
        let map = |p: &[f64; 3]| [2.0 * p[0] - p[1] + 3.0, 0.5 * p[1] + p[2], -p[2] + 1.0];
        let moved = EndCurve {
            points: points.iter().map(map).collect(),
            labels: labels.clone(),
        };
        let fine_moved = ends(&mut s, &sigma, &moved, steps);
        let mapped: Vec<[f64; 3]> = fine.points.iter().map(map).collect();
        assert!(close(&fine_moved.points, &mapped, 1e-12), "{name}: affine");

        // Reversed, with mirrored labels, gives the reversed curve.
        let reversed = EndCurve {
            points: points.iter().rev().copied().collect(),
            labels: labels.iter().rev().map(|&a| sigma[a as usize]).collect(),
        };
        let fine_rev = ends(&mut s, &sigma, &reversed, steps);
        let back: Vec<[f64; 3]> = fine.points.iter().rev().copied().collect();
        assert!(close(&fine_rev.points, &back, 1e-12), "{name}: reversal");
    }
}

#[test]
fn the_command_line_interpolates_ends_and_refuses_what_it_cannot() {
    let dir = tempfile::tempdir().unwrap();
    let pts = write(dir.path(), "p.txt", "0 0\n1 0\n2 1\n3 0\n4 0\n");
    let out = dir.path().join("o.txt");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "curve",
            extra[0],
            "--steps",
            "2",
            &pts,
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(&extra[1..]);
        lsubdiv(&args)
    };
    let o = run(&["uniform-binary", "--ends", "interpolate"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4 * 4 + 1);
    assert_eq!((lines[0], lines[16]), ("0.0 0.0", "4.0 0.0"));
    // Labels: one per edge.
    let o = run(&["binary-ternary", "--ends", "interpolate", "--labels", "LCR"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("3 interval labels given, 4 needed"), "{e}");
    for (extra, says) in [
        (
            &["uniform-binary", "--ends", "interpolate", "--closed"][..],
            "--ends interpolate is for open polygons",
        ),
        (
            &["fibonacci-curve", "--ends", "interpolate"][..],
            "has no mirror symmetry σ",
        ),
        (
            &["uniform-binary", "--ends", "interpolate", "--degree", "2"][..],
            "interpolated ends need an odd degree",
        ),
    ] {
        let o = run(extra);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {e}");
        assert!(e.contains(says), "{extra:?}: {e}");
    }
}

#[test]
fn generated_and_generic_paths_agree_bit_for_bit() {
    for name in ["uniform-binary", "binary-ternary", "fibonacci", "low-ratio"] {
        let (mut s, sigma) = scheme(name);
        let mut rng = Lcg(11);
        let points: Vec<[f64; 3]> = (0..9)
            .map(|_| std::array::from_fn(|_| rng.next()))
            .collect();
        let coarse = EndCurve::with_axiom(&s.tables(), points);
        let generic = ends(&mut s, &sigma, &coarse, 4);
        let generated = lsubdiv::generated::refine_ends(name, &sigma, &coarse, 4)
            .expect("a shipped scheme")
            .expect("its tables hold the mirrored words of the axiom");
        let bits = |c: &EndCurve<3>| -> Vec<u64> {
            c.points.iter().flatten().map(|x| x.to_bits()).collect()
        };
        assert_eq!(bits(&generic), bits(&generated), "{name}");
        assert_eq!(generic.labels, generated.labels, "{name}");
    }
}
