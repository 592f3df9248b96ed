//! The coordinate range of refinement: the masks are affine combinations (weights summing to 1),
//! so refining commutes with scaling, and a mesh or polygon whose coordinates are huge (or tiny)
//! is refined scaled by a power of two to magnitude 1 and scaled back. A power of two scales
//! every f64 operation exactly, so the result is the one of an f64 with unbounded exponent: no
//! intermediate sum overflows (the rule of a valence-200 vertex adds 200 neighbours) and no
//! subnormal loses digits. Only a result itself beyond the f64 range (masks have negative
//! weights, so a refined point may lie outside the control points' box) is refused.
//!
//! Inputs whose largest |coordinate| lies in [2^-500, 2^500] are refined as they are, so their
//! outputs are bit for bit those of the unscaled computation.

use lsubdiv_io::Error;
use lsubdiv_mesh::real::Real;

/// Largest |coordinate| refined unscaled is below 2^`UNSCALED`, smallest above 2^-`UNSCALED`.
const UNSCALED: i32 = 500;

/// 2^e for e in −1022..=1023 (normal f64).
fn pow2(e: i32) -> f64 {
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// `x · 2^e`, exact whenever the result is a normal f64 (two factors, each normal).
fn ldexp(x: f64, e: i32) -> f64 {
    let half = e / 2;
    x * pow2(half) * pow2(e - half)
}

/// Largest |coordinate| of `points` (0 for none).
pub fn largest<const D: usize, T: Real>(points: &[[T; D]]) -> f64 {
    points
        .iter()
        .flatten()
        .fold(0.0, |m: f64, x| m.max(x.to_f64().abs()))
}

/// The binary exponent that brings a largest |coordinate| `max` to [1, 2), or 0 when `max` is
/// within the unscaled range (or zero).
fn exponent(max: f64) -> i32 {
    if max == 0.0 || (pow2(-UNSCALED)..pow2(UNSCALED)).contains(&max) {
        return 0;
    }
    // log2 of a subnormal is still exact enough to pick the binade.
    max.log2().floor() as i32
}

/// Bytes of the scaled copy [`refine_scaled`] makes of `points` and of `with` more bytes (a
/// mesh's faces, a curve's labels): none when they are refined as they are.
pub fn copy_bytes<const D: usize>(points: &[[f64; D]], with: u128) -> u128 {
    if exponent(largest(points)) == 0 {
        0
    } else {
        points.len() as u128 * 8 * D as u128 + with
    }
}

/// Refines `points` by `refine`, which is given the points scaled to magnitude 1 when they are
/// outside the unscaled range (`None`: refine them as they are) and refines them into `T` (f64
/// or f32); refuses (naming `what`, the input's scale and `T`'s limit) a result that is not
/// finite once scaled back.
pub fn refine_scaled<const D: usize, R, T: Real>(
    what: &str,
    points: &[[f64; D]],
    refine: impl FnOnce(Option<Vec<[f64; D]>>) -> Result<(R, Vec<[T; D]>), Error>,
) -> Result<(R, Vec<[T; D]>), Error> {
    let max = largest(points);
    let e = exponent(max);
    let (rest, mut out) = if e == 0 {
        refine(None)?
    } else {
        refine(Some(
            points.iter().map(|p| p.map(|x| ldexp(x, -e))).collect(),
        ))?
    };
    let reached = largest(&out);
    if e != 0 {
        out.iter_mut().for_each(|p| {
            p.iter_mut()
                .for_each(|x| *x = T::from_f64(ldexp(x.to_f64(), e)))
        });
    }
    if out.iter().flatten().all(|x| x.to_f64().is_finite()) {
        return Ok((rest, out));
    }
    // `reached` is the scaled result's magnitude: finite unless the refinement itself failed.
    let magnitude = if reached.is_finite() {
        // log10 of the magnitude, split so that neither part overflows.
        let log = reached.log10() + f64::from(e) * std::f64::consts::LOG10_2;
        let exponent = log.floor();
        format!("reaches ~{:.2}e{exponent}", 10f64.powf(log - exponent))
    } else {
        "is not finite".to_string()
    };
    Err(Error::input(format!(
        "{what}: the refined result {magnitude}, beyond the largest {} ({:e}); the input's largest |coordinate| is {max:e}; scale the input down",
        T::NAME,
        T::MAX
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_by_powers_of_two_is_exact_and_round_trips() {
        for x in [1.0f64, -3.75, 1e300, 1.7e308, 5e-324, 1e-310, 0.1] {
            let e = exponent(x.abs());
            let y = ldexp(ldexp(x, -e), e);
            assert_eq!(y, x, "{x}");
            if e != 0 {
                assert!((1.0..2.0).contains(&ldexp(x, -e).abs()), "{x}");
            }
        }
        assert_eq!(exponent(1e100), 0);
        assert_eq!(exponent(1e-100), 0);
        // The size guard counts the copy only when there is one.
        assert_eq!(copy_bytes(&[[1.0, 2.0, 3.0]; 10], 160), 0);
        assert_eq!(copy_bytes(&[[1e300, 2.0, 3.0]; 10], 160), 10 * 24 + 160);
    }

    #[test]
    fn sums_that_overflow_unscaled_are_finite_scaled_and_real_overflow_is_refused() {
        // The mean of 200 points at 2^1020: the sum overflows unscaled.
        let big = 2f64.powi(1020);
        let points = vec![[big, -big]; 200];
        let mean = |p: &[[f64; 2]]| -> Result<((), Vec<[f64; 2]>), Error> {
            let s = p.iter().fold([0.0; 2], |s, q| [s[0] + q[0], s[1] + q[1]]);
            Ok(((), vec![s.map(|x| x / p.len() as f64)]))
        };
        assert!(mean(&points).unwrap().1[0][0].is_infinite());
        let scaled = |q: Option<Vec<[f64; 2]>>| mean(q.as_deref().unwrap_or(&points));
        let ((), out) = refine_scaled("t", &points, scaled).unwrap();
        assert_eq!(out, vec![[big, -big]]);
        // 2a − b with a = 1e308, b = −1e308 is 3e308: beyond f64.
        let extrapolate = |q: Option<Vec<[f64; 1]>>| {
            let p = q.unwrap_or_else(|| vec![[1e308], [-1e308]]);
            Ok(((), vec![[2.0 * p[0][0] - p[1][0]]]))
        };
        let e = refine_scaled("t", &[[1e308], [-1e308]], extrapolate).unwrap_err();
        assert!(
            e.message.contains("reaches ~3.00e308") && e.message.contains("1e308"),
            "{}",
            e.message
        );
    }
}
