//! Curve refinement beyond the tables: the refined polygon is the control polygon of the same
//! spline on the refined knots (checked by independent de Boor evaluation), it converges to the
//! spline, and the generic and generated paths agree bit for bit.

mod common;

use common::Lcg;
use lsubdiv::compiler::exact::Scheme;
use lsubdiv::generic::GenericScheme;
use lsubdiv::{generated, Curve, CurveError, CurveScheme};
use lsubdiv_cli::resolve;
use lsubdiv_testkit::spline::{de_boor, knots_and_points, max_dist, spline_distance};

fn generic(name: &str, degree: Option<usize>) -> GenericScheme {
    let mut r = resolve(name).expect("shipped scheme");
    if let Some(d) = degree {
        r.ls.degree = d;
    }
    GenericScheme::new(Scheme::build(r.ls).expect("compiles")).expect("tabulates")
}

/// Checks that `fine` (after `steps` steps of `coarse`) is the same spline, at 401 parameters.
fn assert_same_spline<const D: usize>(
    s: &GenericScheme,
    coarse: &Curve<D>,
    fine: &Curve<D>,
    steps: usize,
) {
    let (err, x) = spline_distance(s, coarse, fine, steps);
    assert!(err < 1e-12, "{}: x = {x}: {err:e}", s.scheme().ls.name);
}

fn check_scheme(name: &str, degree: Option<usize>, seed: u64) {
    let s = generic(name, degree);
    let mut rng = Lcg(seed);
    for closed in [false, true] {
        let m = 9 + (seed as usize % 5);
        let coarse = Curve::with_axiom(&s.tables(), rng.points::<3>(m), closed);
        for steps in 1..=3 {
            let fine = lsubdiv::refine(&s, &coarse, steps).expect("refines");
            assert_same_spline(&s, &coarse, &fine, steps);
            // Counts: m + d intervals (open) or m (closed) after every step.
            let d = s.scheme().ls.degree;
            let extra = if closed { 0 } else { d };
            assert_eq!(fine.labels.len(), fine.points.len() + extra);
        }
    }
}

#[test]
fn refined_polygon_is_the_same_spline_for_every_shipped_scheme() {
    for (i, name) in generated::NAMES.iter().enumerate() {
        check_scheme(name, None, 17 + i as u64);
    }
}

#[test]
fn refined_polygon_is_the_same_spline_at_other_degrees() {
    for d in 1..=6 {
        check_scheme("fibonacci-curve", Some(d), 100 + d as u64);
        check_scheme("binary-ternary", Some(d), 200 + d as u64);
    }
}

#[test]
fn polygons_converge_to_the_spline() {
    // Distance of each control point to the curve at its Greville abscissa shrinks with the
    // knot spacing ([N] Theorem 3.2).
    let s = generic("fibonacci", None);
    let d = 3;
    let lengths: Vec<f64> = s.scheme().lengths.iter().map(|l| l.to_f64()).collect();
    let rho = s.scheme().analysis.rho.to_f64();
    let coarse = Curve::with_axiom(&s.tables(), Lcg(5).points::<2>(8), true);
    let mut errors = Vec::new();
    for steps in 0..=8i32 {
        let c = lsubdiv::refine(&s, &coarse, steps as usize).unwrap();
        let (t, p) = knots_and_points(&c, &lengths, rho.powi(-steps), 0.0, d);
        // Unrolled points d−1..=m have their Greville abscissae inside the period [t_d, t_{m+d}].
        let err = (d - 1..=c.points.len())
            .map(|k| {
                let g = t[k + 1..=k + d].iter().sum::<f64>() / d as f64;
                max_dist(&p[k], &de_boor(&t, &p, d, g))
            })
            .fold(0.0, f64::max);
        errors.push(err);
    }
    for w in errors.windows(2).skip(1) {
        assert!(w[1] < w[0], "not decreasing: {errors:?}");
    }
    // Quadratic in the spacing: about ρ^-2 per step.
    assert!(errors[8] < errors[2] * rho.powi(-2 * 6) * 4.0, "{errors:?}");
}

fn bits<const D: usize>(c: &Curve<D>) -> Vec<u64> {
    c.points.iter().flatten().map(|x| x.to_bits()).collect()
}

#[test]
fn generic_and_generated_paths_agree_bit_for_bit() {
    for (i, name) in generated::NAMES.iter().enumerate() {
        let s = generic(name, None);
        let mut rng = Lcg(1000 + i as u64);
        for closed in [false, true] {
            let c2 = Curve::with_axiom(&s.tables(), rng.points::<2>(11), closed);
            let c3 = Curve::with_axiom(&s.tables(), rng.points::<3>(11), closed);
            let a2 = lsubdiv::refine(&s, &c2, 4).unwrap();
            let b2 = generated::refine_curve(name, &c2, 4).unwrap().unwrap();
            let a3 = lsubdiv::refine(&s, &c3, 4).unwrap();
            let b3 = generated::refine_curve(name, &c3, 4).unwrap().unwrap();
            assert_eq!(bits(&a2), bits(&b2), "{name} 2D closed={closed}");
            assert_eq!(bits(&a3), bits(&b3), "{name} 3D closed={closed}");
            assert_eq!(a3.labels, b3.labels);
        }
    }
}

#[test]
fn user_labels_outside_the_tables_use_masks_computed_on_demand() {
    // "SS" never occurs in Fibonacci words, so no table has SSS: the generated path refuses,
    // the generic path computes the masks exactly and refines the same spline.
    let mut s = generic("fibonacci-curve", None);
    let points = Lcg(9).points::<2>(6);
    let labels = s.scheme().ls.parse_word("SSLSSLSS").unwrap(); // m + d = 8
    let curve = Curve {
        points,
        labels,
        closed: false,
    };
    match generated::refine_curve("fibonacci-curve", &curve, 2).unwrap() {
        Err(CurveError::UnknownWord(w)) => assert_eq!(w, "SSL"),
        other => panic!("expected UnknownWord, got {other:?}"),
    }
    assert!(matches!(
        lsubdiv::refine(&s, &curve, 2),
        Err(CurveError::UnknownWord(_))
    ));
    s.prepare(&curve).unwrap();
    let fine = lsubdiv::refine(&s, &curve, 3).unwrap();
    assert_same_spline(&s, &curve, &fine, 3);
}

#[test]
fn bad_curves_are_refused() {
    let s = generic("binary-ternary", None);
    let t = s.tables();
    let mut c = Curve::with_axiom(&t, Lcg(1).points::<2>(5), false);
    c.labels.pop();
    assert_eq!(
        lsubdiv::refine(&s, &c, 1),
        Err(CurveError::LabelCount {
            expected: 8,
            got: 7
        })
    );
    c.labels.push(9);
    assert_eq!(
        lsubdiv::refine(&s, &c, 1),
        Err(CurveError::UnknownSymbol(9))
    );
    for closed in [true, false] {
        // Degree 3 needs 4 points, open or closed (an open curve of 3 used to panic).
        let c = Curve::with_axiom(&t, Lcg(1).points::<2>(3), closed);
        assert_eq!(
            lsubdiv::refine(&s, &c, 1),
            Err(CurveError::TooFewPoints { needed: 4, got: 3 })
        );
    }
}

/// Every context met on a closed curve labelled by π^s(axiom) (cyclically) is one that the
/// generated code specialises: `Stencils::reachable`, which the code generator numbers, is
/// closed under π.
#[test]
fn build_time_contexts_cover_the_axioms_iterates() {
    use lsubdiv::runtime::gather::Stencils;
    use lsubdiv::runtime::CurveContexts;
    for name in generated::NAMES {
        let s = generic(name, None);
        let t = s.tables();
        let known = Stencils::reachable(t).unwrap();
        let (keys, next) = known.contexts();
        let mut offsets = vec![0u32];
        let labels: Vec<u8> = keys.iter().flatten().copied().collect();
        for k in keys {
            offsets.push(offsets.last().unwrap() + k.len() as u32);
        }
        let contexts = CurveContexts {
            offsets: &offsets,
            labels: &labels,
            next,
        };
        let (mut st, specialised) = Stencils::new(t, contexts);
        assert_eq!(specialised as usize, keys.len(), "{name}");
        let mut word = t.axiom.to_vec();
        for s in 0..6 {
            let n = word.len();
            let at = |i: usize| word[i % n];
            let start: Vec<u8> = (0..st.reach + t.degree).map(at).collect();
            let mut c = st.context_of(&start).unwrap();
            for i in st.reach + t.degree..st.reach + t.degree + n {
                assert!(c < specialised, "{name}: step {s}, label {i}");
                c = st.advance(c, at(i)).unwrap();
            }
            word = word.iter().flat_map(|&a| t.rule(a)).copied().collect();
        }
    }
    // Contexts that do not match the tables seed nothing (the tables then serve every point).
    let t = generic("fibonacci", None);
    let bogus = CurveContexts {
        offsets: &[0, 2],
        labels: &[0, 0],
        next: &[7; 5],
    };
    assert_eq!(Stencils::new(t.tables(), bogus).1, 0);
    let bad_symbol = CurveContexts {
        offsets: &[0, 5],
        labels: &[9; 5],
        next: &[0; 5],
    };
    assert_eq!(Stencils::new(t.tables(), bad_symbol).1, 0);
    // The generated code numbers the same contexts.
    let fib = generic("fibonacci", None);
    let known = Stencils::reachable(fib.tables()).unwrap();
    assert_eq!(
        generated::fibonacci::CONTEXTS.len(),
        known.contexts().0.len()
    );
}
