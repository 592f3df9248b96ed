//! Points on the limit curve: each control point taken to the point of the limit
//! curve it converges to, with the derivative there, by the exact limit masks the compiler
//! derives (`lsubdiv_compiler::exact::limit`, [`crate::CurveTables::limit_weights`]).

use crate::curve::{Curve, CurveError, CurveScheme};
use crate::ends::EndCurve;
use std::collections::HashMap;

/// Limit positions and derivatives of a curve's control points, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveLimit<const D: usize> {
    /// The limit point of each control point.
    pub positions: Vec<[f64; D]>,
    /// The limit curve's derivative there, with respect to the parameter in which the
    /// curve's intervals have the tabulated lengths.
    pub tangents: Vec<[f64; D]>,
}

/// The limit of every control point whose neighbours the mask needs exist: all of a closed
/// curve's, the points (d−1)/2 ..= m − 1 − (d−1)/2 of an open one (its ends have no limit
/// point of their own, as they have no full mask: \[N\] §2.3).
pub fn curve_limit<S: CurveScheme, const D: usize>(
    scheme: &S,
    curve: &Curve<D>,
) -> Result<CurveLimit<D>, CurveError> {
    let t = scheme.tables();
    curve.check(&t)?;
    let d = t.degree;
    if t.limit_mask(0).is_none() {
        return Err(CurveError::NoLimit(d));
    }
    let index: HashMap<&[u8], u32> = t.word_index();
    let (m, r) = (curve.points.len(), (d - 1) / 2);
    let ks = if curve.closed {
        0..m
    } else {
        r..m.saturating_sub(r)
    };
    let mut out = CurveLimit {
        positions: Vec::with_capacity(ks.len()),
        tangents: Vec::with_capacity(ks.len()),
    };
    let n = curve.labels.len();
    let mut word = Vec::with_capacity(d + 1);
    for k in ks {
        // Point k owns intervals k..=k+d (cyclically when closed).
        word.clear();
        word.extend((k..=k + d).map(|i| curve.labels[i % n]));
        let i = *index
            .get(word.as_slice())
            .ok_or_else(|| CurveError::UnknownWord(t.word_str(&word)))?;
        let (position, tangent) = t.limit_mask(i as usize).ok_or(CurveError::NoLimit(d))?;
        let point = |j: usize| curve.points[(k + m + j - r) % m];
        let combine = |w: &[f64]| -> [f64; D] {
            let mut p = [0.0; D];
            for (j, &wj) in w.iter().enumerate() {
                for (o, x) in p.iter_mut().zip(point(j)) {
                    *o += wj * x;
                }
            }
            p
        };
        out.positions.push(combine(position));
        out.tangents.push(combine(tangent));
    }
    Ok(out)
}

/// The limit of every point of an open curve with interpolated ends ([`crate::ends`]): by the
/// odd-symmetric extension, the end points' too (each its own limit point).
pub fn end_limit<S: CurveScheme, const D: usize>(
    scheme: &S,
    sigma: &[u8],
    curve: &EndCurve<D>,
) -> Result<CurveLimit<D>, CurveError> {
    // The extension adds (d − 1)/2 phantoms at each end, exactly the neighbours the open
    // curve's limit needs: its limit points are those of the real points.
    let extended = curve.extended(&scheme.tables(), sigma)?;
    curve_limit(scheme, &extended)
}
