//! Open curves with interpolated end points: the odd-symmetric extension.
//!
//! An end is a line of odd symmetry. Across the end point P_0 sit phantom points 2P_0 − P_j on
//! mirrored intervals, labelled σ(a) in reverse order (σ a mirror symmetry of the L-system,
//! π(σ(a)) = σ̄(π(a)), \[G\] Proposition 4.2), and likewise across the last point. The extended
//! polygon is refined as any open curve (\[N\] §2.3) and cut back at the children of the end
//! points. For a symmetric scheme the refined extension is again the odd extension of the refined
//! real polygon (its phantom labels are σ̄ of the refined real ones), so one step after another
//! is the refinement of one odd-symmetric spline; every new point is a combination of real
//! points whose weights sum to 1 (a phantom's weight w goes as 2w to the end and −w to its twin).
//! The mask of the end point's word is its own mirror, so the end point's child is the end
//! point: the ends are interpolated (set exactly, not up to rounding).
//!
//! The control point's middle knot is the end, so this needs an odd degree: for an even degree
//! the end lies mid-interval, on a label that would have to be its own twin.
//!
//! Labels: an open polygon of m points has m − 1 labels, one per edge; the label of edge
//! (P_{i−1}, P_i) is the interval between the middle knots of the two points (for a cubic,
//! the interval the Greville abscissae of P_{i−1} and P_i bound). A step replaces each edge
//! label a by the edges π(a).

use crate::curve::{refine, Curve, CurveError, CurveScheme, CurveTables};

/// An open polygon with interpolated ends: `labels[i]` labels the edge (P_i, P_{i+1}).
#[derive(Clone, Debug, PartialEq)]
pub struct EndCurve<const D: usize> {
    /// Control points, the first and last interpolated.
    pub points: Vec<[f64; D]>,
    /// One label per edge: m − 1 for m points.
    pub labels: Vec<u8>,
}

impl<const D: usize> EndCurve<D> {
    /// A polygon with the axiom repeated on its edges.
    pub fn with_axiom(t: &CurveTables<'_>, points: Vec<[f64; D]>) -> EndCurve<D> {
        let edges = points.len().saturating_sub(1);
        let labels = t.axiom.iter().copied().cycle().take(edges).collect();
        EndCurve { points, labels }
    }

    /// Checks degree, point and label counts and symbols against the tables.
    pub fn check(&self, t: &CurveTables<'_>) -> Result<(), CurveError> {
        let d = t.degree;
        if d.is_multiple_of(2) {
            return Err(CurveError::EvenDegree(d));
        }
        // The extension mirrors (d − 1)/2 points at each end (and d edges, reflected again at
        // the far end when the polygon is shorter).
        let needed = d.div_ceil(2);
        if self.points.len() < needed {
            return Err(CurveError::TooFewPoints {
                needed,
                got: self.points.len(),
            });
        }
        if self.labels.len() + 1 != self.points.len() {
            return Err(CurveError::LabelCount {
                expected: self.points.len() - 1,
                got: self.labels.len(),
            });
        }
        match self
            .labels
            .iter()
            .find(|&&s| s as usize >= t.symbol_count())
        {
            Some(&s) => Err(CurveError::UnknownSymbol(s)),
            None => Ok(()),
        }
    }

    /// The odd-symmetric extension: (d − 1)/2 phantom points and d mirrored labels at each end,
    /// an open [`Curve`] whose refinement holds the refinement of `self` (checked first). The
    /// labels are those of the polygon unfolded by reflection at both ends (edge −1 − i is
    /// σ(edge i), edge m − 1 + i is σ(edge m − 2 − i)), so a polygon of fewer than d edges
    /// extends as its faces do on a surface between two corners.
    pub fn extended(&self, t: &CurveTables<'_>, sigma: &[u8]) -> Result<Curve<D>, CurveError> {
        self.check(t)?;
        let d = t.degree;
        let r = (d - 1) / 2;
        let (p, e, m) = (&self.points, &self.labels, self.points.len());
        let twin = |a: u8| sigma[a as usize];
        let reflect = |c: [f64; D], q: [f64; D]| std::array::from_fn(|i| 2.0 * c[i] - q[i]);
        let mut points: Vec<[f64; D]> = (1..=r).rev().map(|j| reflect(p[0], p[j])).collect();
        points.extend_from_slice(p);
        points.extend((1..=r).map(|j| reflect(p[m - 1], p[m - 1 - j])));
        // Edge i of the unfolded polygon (period 2(m − 1)), i ≥ 0.
        let unfolded = |i: usize| {
            let i = i % (2 * (m - 1));
            if i < m - 1 {
                e[i]
            } else {
                twin(e[2 * (m - 1) - 1 - i])
            }
        };
        let mut labels: Vec<u8> = (0..d).rev().map(|j| twin(unfolded(j))).collect();
        labels.extend_from_slice(e);
        labels.extend((1..=d).map(|j| unfolded(m - 2 + j)));
        Ok(Curve {
            points,
            labels,
            closed: false,
        })
    }
}

/// Refines an open polygon with interpolated ends `steps` times, `sigma` a mirror symmetry of
/// the scheme (σ(a) = `sigma[a]`).
pub fn refine_ends<S: CurveScheme, const D: usize>(
    scheme: &S,
    sigma: &[u8],
    curve: &EndCurve<D>,
    steps: usize,
) -> Result<EndCurve<D>, CurveError> {
    let t = scheme.tables();
    curve.check(&t)?;
    let d = t.degree;
    // A step holds the extension and its refinement, no other level: the coarse points are
    // dropped once extended, the refined ones cut back in place (the size guard counts so).
    let mut cur: Option<EndCurve<D>> = None;
    for _ in 0..steps {
        let coarse = cur.as_ref().unwrap_or(curve);
        let ext = coarse.extended(&t, sigma)?;
        let ends = (coarse.points[0], coarse.points[coarse.points.len() - 1]);
        let labels: Vec<u8> = coarse
            .labels
            .iter()
            .flat_map(|&a| t.rule(a))
            .copied()
            .collect();
        drop(cur.take());
        let mut points = refine(scheme, &ext, 1)?.points;
        drop(ext);
        // The child of extended point k is the new point on its middle knot (odd d): new
        // point offset(k + half) − half, offset(i) = |π(labels[..i])|, and the refined open
        // curve starts at offset(d) − d ([N] §2.3). P_0 is point r, and r + half = d, so its
        // child is refined point d − half = r; the children of the other real points follow,
        // one per refined edge.
        let first = (d - 1) / 2;
        points.truncate(first + labels.len() + 1);
        points.drain(..first);
        // The end points' children are the end points (symmetric masks); exactly.
        points[0] = ends.0;
        *points.last_mut().expect("at least two points") = ends.1;
        cur = Some(EndCurve { points, labels });
    }
    Ok(cur.unwrap_or_else(|| curve.clone()))
}
