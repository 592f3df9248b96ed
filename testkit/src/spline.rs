//! Independent B-spline evaluation (de Boor) for checking that a refined polygon is the control
//! polygon of the same spline on the refined knots (\[N\] §2.2).

use lsubdiv::generic::GenericScheme;
use lsubdiv::Curve;

/// Evaluates the spline with knots `t` (len m + d + 1) and points `p` at x ∈ [t_d, t_m] (de Boor).
pub fn de_boor<const D: usize>(t: &[f64], p: &[[f64; D]], d: usize, x: f64) -> [f64; D] {
    let m = p.len();
    let mut mu = d;
    while mu + 1 < m && t[mu + 1] <= x {
        mu += 1;
    }
    let mut q: Vec<[f64; D]> = p[mu - d..=mu].to_vec();
    for r in 1..=d {
        for j in (r..=d).rev() {
            let i = mu - d + j;
            let a = (x - t[i]) / (t[i + d + 1 - r] - t[i]);
            let prev = q[j - 1];
            for (v, pv) in q[j].iter_mut().zip(prev) {
                *v = (1.0 - a) * pv + a * *v;
            }
        }
    }
    q[d]
}

/// Knots of a curve at step s: starting at `start`, interval lengths ℓ(label)/ρ^s. A closed
/// curve is unrolled into an open one covering one period (points p_0..p_{m+d−1} cyclically).
pub fn knots_and_points<const D: usize>(
    c: &Curve<D>,
    lengths: &[f64],
    scale: f64,
    start: f64,
    d: usize,
) -> (Vec<f64>, Vec<[f64; D]>) {
    let (n_int, pts) = if c.closed {
        let m = c.points.len();
        (m + 2 * d, (0..m + d).map(|j| c.points[j % m]).collect())
    } else {
        (c.labels.len(), c.points.clone())
    };
    let mut t = vec![start];
    for j in 0..n_int {
        let l = lengths[c.labels[j % c.labels.len()] as usize] * scale;
        t.push(t[j] + l);
    }
    (t, pts)
}

/// Largest coordinate difference.
pub fn max_dist<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    (0..D).map(|c| (a[c] - b[c]).abs()).fold(0.0, f64::max)
}

/// Largest distance between the splines of `coarse` and of `fine` (after `steps` steps of
/// `coarse`) at 401 parameters of their common domain, with the parameter where it occurs.
pub fn spline_distance<const D: usize>(
    s: &GenericScheme,
    coarse: &Curve<D>,
    fine: &Curve<D>,
    steps: usize,
) -> (f64, f64) {
    let a = &s.scheme().analysis;
    let d = s.scheme().ls.degree;
    let lengths: Vec<f64> = s.scheme().lengths.iter().map(|l| l.to_f64()).collect();
    let scale = a.rho.to_f64().powi(-(steps as i32));
    let (t0, p0) = knots_and_points(coarse, &lengths, 1.0, 0.0, d);
    // Open: the domain start t_d is invariant. Closed: the first knot is.
    let start = if coarse.closed {
        0.0
    } else {
        let (u, _) = knots_and_points(fine, &lengths, scale, 0.0, d);
        t0[d] - u[d]
    };
    let (t1, p1) = knots_and_points(fine, &lengths, scale, start, d);
    let (m0, m1) = (p0.len(), p1.len());
    let lo = t0[d].max(t1[d]);
    let hi = t0[m0].min(t1[m1]);
    assert!(hi > lo, "empty common domain");
    (0..=400)
        .map(|i| {
            let x = lo + (hi - lo) * i as f64 / 400.0 * (1.0 - 1e-12);
            let err = max_dist(&de_boor(&t0, &p0, d, x), &de_boor(&t1, &p1, d, x));
            (err, x)
        })
        .fold((0.0, lo), |a, b| if b.0 > a.0 { b } else { a })
}

/// Checks every limit mask of a cubic scheme (`Scheme::limits`) against de Boor: for each
/// reachable word, the position weights against the B-splines' values at the point's middle
/// knot (to 1e-12) and the tangent weights against their central differences (to 1e-6), on a
/// knot vector of the word's exact lengths (as f64) between unit intervals.
pub fn check_limit_masks(s: &lsubdiv::compiler::exact::Scheme) -> Result<(), String> {
    if s.ls.degree != 3 {
        return Ok(());
    }
    if s.limits.len() != s.graph.words.len() {
        return Err(format!(
            "{} limit masks for {} words",
            s.limits.len(),
            s.graph.words.len()
        ));
    }
    let len = |sym: u8| s.lengths[sym as usize].to_f64();
    for m in &s.limits {
        // Knots x_0..x_8: two unit intervals, the word's four, two unit intervals; five cubic
        // B-splines, the middle one (x_2..x_6) the point's, its middle knot x_4.
        let mut x = vec![0.0];
        let intervals = [1.0, 1.0]
            .into_iter()
            .chain(m.word.iter().map(|&sym| len(sym)))
            .chain([1.0, 1.0]);
        for h in intervals {
            x.push(x[x.len() - 1] + h);
        }
        let impulses: Vec<[f64; 3]> = (0..5)
            .map(|j| std::array::from_fn(|k| f64::from(u8::from(j == k + 1))))
            .collect();
        let at = |t: f64| de_boor(&x, &impulses, 3, t);
        let (knot, h) = (x[4], 1e-5);
        let (value, before, after) = (at(knot), at(knot - h), at(knot + h));
        let word = s.ls.word_str(&m.word);
        for k in 0..3 {
            let (p, t) = (m.position[k].to_f64(), m.tangent[k].to_f64());
            let slope = (after[k] - before[k]) / (2.0 * h);
            if (p - value[k]).abs() > 1e-12 || (t - slope).abs() > 1e-6 * (1.0 + slope.abs()) {
                return Err(format!(
                    "{word}: weight {k}: position {p} vs {}, tangent {t} vs {slope}",
                    value[k]
                ));
            }
        }
    }
    Ok(())
}
