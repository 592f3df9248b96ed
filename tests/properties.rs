//! Property tests on random valid L-systems (1–5 symbols, rules of length 1–4, degree 1–5):
//! exact partition of unity, exact mirror symmetry of the masks of symmetric systems (\[G\]
//! eq. (14)), refinement keeps the spline (de Boor), affine invariance, interpolated ends.

mod common;

use lsubdiv::compiler::exact::field::Elem;
use lsubdiv::compiler::exact::lsystem::LSystem;
use lsubdiv::compiler::exact::symmetry::{check_symmetry, involutions, is_symmetry, rule_mirror};
use lsubdiv::compiler::exact::{scheme, validity, Scheme};
use lsubdiv::generic::GenericScheme;
use lsubdiv::{refine_ends, Curve, CurveScheme, EndCurve};
use lsubdiv_testkit::fuzzing::{involution, SmallSystem};
use lsubdiv_testkit::spline::spline_distance;
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{TestCaseError, TestRunner};
use std::fmt;

/// Random systems, symmetric with probability `symmetric` (in 0..=1). Half of them get a
/// cycle A → B → … → A through their rules (the last symbol of π(a) becomes a + 1), which makes
/// M irreducible, so that most are valid ([N] Theorem 3.7); the others are left as drawn.
fn systems(symmetric: f64) -> impl Strategy<Value = SmallSystem> {
    (1..=5usize, 1..=5usize)
        .prop_flat_map(move |(n, degree)| {
            let word = move |max: usize| vec(0..n as u8, 1..=max);
            (
                Just(degree),
                vec(word(4), n),
                word(3),
                any::<bool>(),
                proptest::bool::weighted(symmetric),
                vec(0..n, n),
            )
        })
        .prop_map(|(degree, mut rules, axiom, cycle, sym, picks)| {
            let n = rules.len();
            if cycle {
                for (a, r) in rules.iter_mut().enumerate() {
                    *r.last_mut().expect("non-empty") = ((a + 1) % n) as u8;
                }
            }
            let s = SmallSystem {
                degree,
                rules,
                axiom,
                sigma: None,
            };
            if sym {
                s.symmetrised(involution(n, &picks))
            } else {
                s
            }
        })
}

/// The L-system of a drawn system, when the compiler accepts it as valid with lengths.
fn valid(s: &SmallSystem) -> Option<LSystem> {
    let ls = scheme::parse("small.toml", &s.to_toml()).expect("generated text parses");
    let a = validity::analyse(&ls).expect("analyses");
    a.require_lengths(&ls).ok()?;
    Some(ls)
}

/// A valid scheme and what the properties draw for it.
struct Case {
    /// The scheme file (shown when a property fails).
    text: String,
    /// The tables (the exact scheme is `generic.scheme()`), prepared for `curve`'s words.
    generic: GenericScheme,
    /// A cyclic word over the alphabet, of length d+1..=d+6.
    word: Vec<u8>,
    /// d+1..=d+5 points in 3D, open or closed, labelled by the axiom or by drawn labels.
    curve: Curve<3>,
    /// 1..=3 refinement steps.
    steps: usize,
    /// An affine map x ↦ A x + b.
    affine: ([[f64; 3]; 3], [f64; 3]),
}

impl fmt::Debug for Case {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.curve;
        writeln!(f, "{}", self.text)?;
        writeln!(
            f,
            "word {:?}, steps {}, closed {}",
            self.word, self.steps, c.closed
        )?;
        writeln!(f, "labels {:?}\npoints {:?}", c.labels, c.points)?;
        write!(f, "affine {:?}", self.affine)
    }
}

/// Cases over valid systems, symmetric with probability `symmetric`.
fn cases(symmetric: f64) -> impl Strategy<Value = Case> {
    let matrix = proptest::array::uniform3(proptest::array::uniform3(-2.0..2.0f64));
    let shift = proptest::array::uniform3(-5.0..5.0f64);
    systems(symmetric)
        .prop_filter_map("invalid or lengths undetermined", |s| {
            valid(&s).map(|ls| (s.to_toml(), ls))
        })
        .prop_flat_map(move |(text, ls)| {
            let (n, d) = (ls.n(), ls.degree);
            (
                Just((text, ls)),
                vec(0..n as u8, d + 1..=d + 6),
                vec(proptest::array::uniform3(-1.0..1.0f64), d + 1..=d + 5),
                any::<bool>(),
                proptest::option::of(vec(0..n as u8, 2 * d + 5)),
                1..=3usize,
                (matrix.clone(), shift.clone()),
            )
        })
        .prop_map(|((text, ls), word, points, closed, drawn, steps, affine)| {
            let s = Scheme::build(ls)
                .unwrap_or_else(|e| panic!("valid but does not compile: {e}\n{text}"));
            let mut generic = GenericScheme::new(s).unwrap();
            let mut curve = Curve::with_axiom(&generic.tables(), points, closed);
            if let Some(labels) = drawn {
                curve.labels = labels[..curve.labels.len()].to_vec();
            }
            generic.prepare(&curve).unwrap();
            Case {
                text,
                generic,
                word,
                curve,
                steps,
                affine,
            }
        })
}

/// Exact partition of unity: on the closed curve labelled by the cyclic word u (any labels),
/// old point k (word u_k..u_{k+d}) gives contribution j of its mask to new point o_k + j,
/// o_k = Σ_{i<k} |π(u_i)| (cyclically); every new point's weights sum to exactly 1 in Q(ρ).
fn partition_of_unity(c: &Case) -> Result<(), TestCaseError> {
    let (s, u) = (c.generic.scheme(), &c.word);
    let (d, len) = (s.ls.degree, u.len());
    let mut offsets = vec![0];
    for &a in u {
        offsets.push(offsets[offsets.len() - 1] + s.ls.rules[a as usize].len());
    }
    let total = offsets[len];
    let field = &s.analysis.field;
    let mut sums = vec![Elem::zero(field); total];
    for (k, &start) in offsets[..len].iter().enumerate() {
        let w: Vec<u8> = (k..=k + d).map(|i| u[i % len]).collect();
        let m = s.mask_of(&w);
        let image: usize = w.iter().map(|&a| s.ls.rules[a as usize].len()).sum();
        prop_assert_eq!(m.contributions.len(), image - d);
        for (j, c) in m.contributions.iter().enumerate() {
            let l = (start + j) % total;
            sums[l] = sums[l].add(&c.weight);
        }
    }
    for (l, sum) in sums.iter().enumerate() {
        prop_assert!(
            *sum == Elem::one(field),
            "new point {}: weights sum to {}",
            l,
            sum
        );
    }
    Ok(())
}

/// Mirror symmetry ([G] eq. (14)): for every (d+1)-factor w of the cyclic word, reachable or
/// not, the mask of σ̄(w) is the mask of w reversed, each new word mirrored, weights equal
/// exactly; for odd d the child is the mirrored entry.
fn mirror_symmetry(c: &Case) -> Result<(), TestCaseError> {
    let (s, u) = (c.generic.scheme(), &c.word);
    let sigma = s.ls.symmetry.as_ref().expect("symmetric");
    let (d, len) = (s.ls.degree, u.len());
    for k in 0..len {
        let w: Vec<u8> = (k..=k + d).map(|i| u[i % len]).collect();
        let m = s.mask_of(&w);
        let r = s.mask_of(&s.ls.mirror(sigma, &w));
        let n = m.contributions.len();
        prop_assert_eq!(r.contributions.len(), n);
        for (j, c) in m.contributions.iter().enumerate() {
            let mirrored = &r.contributions[n - 1 - j];
            prop_assert_eq!(&mirrored.word, &s.ls.mirror(sigma, &c.word));
            prop_assert!(
                mirrored.weight == c.weight,
                "entry {}: {} vs {}",
                j,
                c.weight,
                mirrored.weight
            );
        }
        prop_assert_eq!(r.child, m.child.map(|c| n - 1 - c));
    }
    Ok(())
}

/// Interpolated ends (`lsubdiv::runtime::ends`, odd degrees): after the steps the end points
/// are the coarse ones exactly, there are |π^N(edges)| + 1 points (the size guard's count), and
/// the ordinary refinement (\[N\] §2.3) of the real points, labelled as in the extension, is a
/// run of them.
fn interpolated_ends(c: &mut Case) -> Result<(), TestCaseError> {
    let ls = &c.generic.scheme().ls;
    let (d, steps) = (ls.degree, c.steps);
    let Some(sigma) = rule_mirror(ls).filter(|_| d % 2 == 1) else {
        return Ok(());
    };
    let points = c.curve.points.clone();
    let m = points.len();
    let labels = c.curve.labels[..m - 1].to_vec();
    let coarse = EndCurve {
        points: points.clone(),
        labels: labels.clone(),
    };
    let ext = coarse
        .extended(&c.generic.tables(), &sigma)
        .expect("extends");
    c.generic.prepare(&ext).expect("tabulates");
    let r = (d - 1) / 2;
    let shrink = Curve {
        points: points.clone(),
        labels: ext.labels[r..r + m + d].to_vec(),
        closed: false,
    };
    c.generic.prepare(&shrink).expect("tabulates");
    let fine = refine_ends(&c.generic, &sigma, &coarse, steps).expect("refines");
    prop_assert_eq!(fine.points[0], points[0]);
    prop_assert_eq!(fine.points.last(), points.last());
    let t = c.generic.tables();
    prop_assert_eq!(fine.labels.len() as u128, t.image_len(&labels, steps));
    prop_assert_eq!(fine.points.len(), fine.labels.len() + 1);
    let guard = lsubdiv_cli::limits::curve_ends(&t, &labels, m, 3, steps);
    prop_assert_eq!(guard.vertices, fine.points.len() as u128);
    let plain = lsubdiv::refine(&c.generic, &shrink, steps).expect("refines");
    let scale = fine
        .points
        .iter()
        .flatten()
        .fold(1.0f64, |a, x| a.max(x.abs()));
    let close = |run: &[[f64; 3]]| {
        run.iter()
            .flatten()
            .zip(plain.points.iter().flatten())
            .all(|(x, y)| (x - y).abs() <= 1e-12 * scale)
    };
    let runs = fine.points.len() + 1 - plain.points.len().min(fine.points.len() + 1);
    prop_assert!(
        (0..runs).any(|o| close(&fine.points[o..o + plain.points.len()])),
        "the interior is not the ordinary refinement"
    );
    Ok(())
}

/// The exact limit masks (cubic schemes) are the B-spline at each point's middle knot.
fn limit_masks(c: &Case) -> Result<(), TestCaseError> {
    lsubdiv_testkit::spline::check_limit_masks(c.generic.scheme()).map_err(TestCaseError::fail)
}

/// The refined polygon is the control polygon of the same spline on the refined knots.
fn same_spline(c: &Case) -> Result<(), TestCaseError> {
    let fine = lsubdiv::refine(&c.generic, &c.curve, c.steps).expect("refines");
    let (err, x) = spline_distance(&c.generic, &c.curve, &fine, c.steps);
    prop_assert!(err < 1e-10, "x = {}: {:e}", x, err);
    Ok(())
}

/// refine(A·P + b) = A·refine(P) + b, to 1e-12 relative to the largest coordinate.
fn affine_invariance(c: &Case) -> Result<(), TestCaseError> {
    let (a, b) = c.affine;
    let map = |p: &[f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| a[i][j] * p[j]).sum::<f64>() + b[i])
    };
    let moved = Curve {
        points: c.curve.points.iter().map(map).collect(),
        ..c.curve.clone()
    };
    let lhs = lsubdiv::refine(&c.generic, &moved, c.steps).expect("refines");
    let rhs = lsubdiv::refine(&c.generic, &c.curve, c.steps).expect("refines");
    let rhs: Vec<[f64; 3]> = rhs.points.iter().map(map).collect();
    let scale = rhs.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
    for (p, q) in lhs.points.iter().zip(&rhs) {
        prop_assert!(
            (0..3).all(|i| (p[i] - q[i]).abs() <= 1e-12 * scale),
            "{:?} vs {:?}",
            p,
            q
        );
    }
    Ok(())
}

proptest! {
    // Each case compiles a scheme (exact, the expensive part), then checks several properties.
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn random_valid_systems(c in cases(1.0 / 3.0)) {
        partition_of_unity(&c)?;
        same_spline(&c)?;
        affine_invariance(&c)?;
        limit_masks(&c)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn random_symmetric_systems(mut c in cases(1.0)) {
        mirror_symmetry(&c)?;
        partition_of_unity(&c)?;
        interpolated_ends(&mut c)?;
    }
}

/// Every involution of 0..n (brute force, for checking the search).
fn all_involutions(n: usize) -> Vec<Vec<u8>> {
    fn extend(sigma: &mut Vec<Option<u8>>, out: &mut Vec<Vec<u8>>) {
        let Some(a) = sigma.iter().position(Option::is_none) else {
            out.push(sigma.iter().map(|s| s.expect("set")).collect());
            return;
        };
        for b in a..sigma.len() {
            if sigma[b].is_none() {
                (sigma[a], sigma[b]) = (Some(b as u8), Some(a as u8));
                extend(sigma, out);
                (sigma[a], sigma[b]) = (None, None);
            }
        }
    }
    let mut out = Vec::new();
    extend(&mut vec![None; n], &mut out);
    out.sort();
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// The involution search (constraint propagation) finds exactly the involutions that make
    /// the system symmetric, valid or not, in lexicographic order.
    #[test]
    fn involution_search_finds_every_symmetry(s in systems(0.5)) {
        let ls = scheme::parse("small.toml", &s.to_toml()).expect("generated text parses");
        let expect: Vec<Vec<u8>> = all_involutions(ls.n())
            .into_iter()
            .filter(|sigma| is_symmetry(&ls, sigma))
            .collect();
        prop_assert_eq!(involutions(&ls), expect);
    }
}

/// The generator is useful: most drawn systems are valid with lengths (so proptest rejects
/// few), the symmetric ones included.
#[test]
fn most_drawn_systems_are_valid() {
    for (symmetric, at_least) in [(1.0 / 3.0, 0.5), (1.0, 0.3)] {
        let mut runner = TestRunner::deterministic();
        let strategy = systems(symmetric);
        let draws = 500;
        let accepted = (0..draws)
            .filter(|_| valid(&strategy.new_tree(&mut runner).expect("draws").current()).is_some())
            .count();
        let rate = accepted as f64 / draws as f64;
        eprintln!(
            "symmetric with probability {symmetric:.2}: {accepted}/{draws} valid ({rate:.2})"
        );
        assert!(rate >= at_least, "only {accepted}/{draws} valid");
    }
}

/// Systems drawn symmetric satisfy [G] eq. (14) and Proposition 4.2 under their declared σ.
#[test]
fn drawn_symmetric_systems_are_symmetric() {
    let mut runner = TestRunner::deterministic();
    let strategy = systems(1.0);
    for _ in 0..200 {
        let s = strategy.new_tree(&mut runner).expect("draws").current();
        let ls = scheme::parse("small.toml", &s.to_toml()).expect("parses");
        let sigma = ls.symmetry.clone().expect("declared");
        check_symmetry(&ls, &sigma).unwrap_or_else(|e| panic!("{e}\n{}", s.to_toml()));
    }
}
