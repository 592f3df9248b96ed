//! Limit masks of curves (issue 16, `compiler::exact::limit`): for every reachable word of
//! every shipped cubic scheme, the exact weights agree with an independent evaluation of the
//! non-uniform B-spline (de Boor, `lsubdiv_testkit::spline`) at the point's middle knot, and
//! the tangent weights with its derivative there.

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
        assert_eq!(
            s.limits.len(),
            s.graph.words.len(),
            "{name}: one limit mask per word"
        );
        let len = |sym: u8| s.lengths[sym as usize].to_f64();
        for m in &s.limits {
            // Knots x_0..x_8: two unit intervals, the word's four, two unit intervals; five
            // cubic B-splines, the middle one (x_2..x_6) the point's, its middle knot x_4.
            let mut x = vec![0.0];
            let intervals = [1.0, 1.0]
                .into_iter()
                .chain(m.word.iter().map(|&sym| len(sym)))
                .chain([1.0, 1.0]);
            for h in intervals {
                x.push(x.last().unwrap() + h);
            }
            let impulses: Vec<[f64; 3]> = (0..5)
                .map(|j| std::array::from_fn(|k| f64::from(u8::from(j == k + 1))))
                .collect();
            let at = |t: f64| de_boor(&x, &impulses, 3, t);
            let (knot, h) = (x[4], 1e-5);
            let value = at(knot);
            let (before, after) = (at(knot - h), at(knot + h));
            let word = s.ls.word_str(&m.word);
            for k in 0..3 {
                let exact = m.position[k].to_f64();
                assert!(
                    (exact - value[k]).abs() < 1e-12,
                    "{name} {word}: N{k} {exact} vs {}",
                    value[k]
                );
                let slope = (after[k] - before[k]) / (2.0 * h);
                let exact = m.tangent[k].to_f64();
                assert!(
                    (exact - slope).abs() < 1e-6,
                    "{name} {word}: N'{k} {exact} vs {slope}"
                );
            }
        }
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
