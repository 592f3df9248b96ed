//! A step's points as a linear map of the points before (OpenSubdiv's stencil table).
//!
//! The reference driver's step (`surface`, \[G\] §2.2) scatters each old vertex's mask over
//! the new points: the weights depend on the labels and the connectivity only, never on the
//! positions. Recorded once as a table — per new point its old points and weights, in the
//! order the scatter adds them, and the divisor its sum takes afterwards — the step on new
//! positions is only that table's sums (`Refiner` keeps it across `refine` calls). Summed in
//! the scatter's order and divided the same way, the table gives the scatter's bits.

use crate::real::Real;

/// Per new point, its weights on old points and the divisor of their sum.
#[derive(Clone, Debug, Default)]
pub(crate) struct Stencil {
    /// Per new point, its first entry (one more at the end).
    rows: Vec<usize>,
    /// Per entry, the old point.
    sources: Vec<u32>,
    /// Per entry, its weight.
    weights: Vec<f64>,
    /// Per new point, what its weighted sum is divided by (1 leaves it exactly).
    norms: Vec<f64>,
}

/// A step's weights in the order its scatter makes them: old point after old point (0, 1, …),
/// each its run of (new point, weight).
#[derive(Debug, Default)]
pub(crate) struct Scatter {
    /// Per old point, the end of its run.
    ends: Vec<usize>,
    targets: Vec<u32>,
    weights: Vec<f64>,
}

impl Scatter {
    /// Room for `points` old points' runs of `weights` weights in all.
    pub(crate) fn with_capacity(points: usize, weights: usize) -> Scatter {
        Scatter {
            ends: Vec::with_capacity(points),
            targets: Vec::with_capacity(weights),
            weights: Vec::with_capacity(weights),
        }
    }

    /// Weight `w` of the current old point on new point `i`.
    pub(crate) fn add(&mut self, i: u32, w: f64) {
        self.targets.push(i);
        self.weights.push(w);
    }

    /// Ends the current old point's run (the next old point's starts).
    pub(crate) fn close(&mut self) {
        self.ends.push(self.targets.len());
    }
}

impl Stencil {
    /// The table of `points` new points from a scatter in runs of old points (in order: the
    /// first run's old points first), each new point keeping its weights' order; each
    /// point's divisor `divisor(point, sum of its weights)`, the sum taken in that order.
    pub(crate) fn from_scatter(
        runs: Vec<Scatter>,
        points: usize,
        mut divisor: impl FnMut(usize, f64) -> f64,
    ) -> Stencil {
        let mut rows = vec![0usize; points + 1];
        for &i in runs.iter().flat_map(|r| &r.targets) {
            rows[i as usize + 1] += 1;
        }
        for i in 1..rows.len() {
            rows[i] += rows[i - 1];
        }
        let mut next = rows.clone();
        let entries = rows[points];
        let (mut sources, mut weights) = (vec![0u32; entries], vec![0.0; entries]);
        let mut v = 0u32;
        for run in runs {
            let starts = std::iter::once(0).chain(run.ends.iter().copied());
            for (lo, &hi) in starts.zip(&run.ends) {
                for (&i, &w) in run.targets[lo..hi].iter().zip(&run.weights[lo..hi]) {
                    let at = &mut next[i as usize];
                    (sources[*at], weights[*at]) = (v, w);
                    *at += 1;
                }
                v += 1;
            }
        }
        let norms = rows
            .windows(2)
            .enumerate()
            .map(|(i, r)| divisor(i, weights[r[0]..r[1]].iter().fold(0.0, |s, &w| s + w)))
            .collect();
        Stencil {
            rows,
            sources,
            weights,
            norms,
        }
    }

    /// New points.
    pub(crate) fn len(&self) -> usize {
        self.norms.len()
    }

    /// The table of the rows `rows`, in that order (a level renumbered); `u32::MAX` gives a
    /// row of no weights (its point is zero, for the caller to set).
    pub(crate) fn pick(&self, rows: &[u32]) -> Stencil {
        let span = |r: u32| match self.rows.get(r as usize..r as usize + 2) {
            Some(&[lo, hi]) => lo..hi,
            _ => 0..0,
        };
        let weights = rows.iter().map(|&r| span(r).len()).sum();
        let mut out = Stencil {
            rows: Vec::with_capacity(rows.len() + 1),
            sources: Vec::with_capacity(weights),
            weights: Vec::with_capacity(weights),
            norms: Vec::with_capacity(rows.len()),
        };
        out.rows.push(0);
        for &r in rows {
            out.sources.extend_from_slice(&self.sources[span(r)]);
            out.weights.extend_from_slice(&self.weights[span(r)]);
            out.rows.push(out.sources.len());
            out.norms
                .push(self.norms.get(r as usize).copied().unwrap_or(1.0));
        }
        out
    }

    /// The new points from the old ones, rounded to `T` at the end (`new` takes one per row).
    /// Old points a table reads must be in `old` (the level it was built for).
    pub(crate) fn apply<T: Real>(&self, old: &[[f64; 3]], new: &mut Vec<[T; 3]>) {
        new.clear();
        new.resize(self.len(), [T::default(); 3]);
        self.apply_rows(0, old, new);
    }

    /// [`Stencil::apply`] of the rows `first..first + new.len()` only, into `new` (rows apart
    /// go to threads apart, each point the same bits).
    pub(crate) fn apply_rows<T: Real>(&self, first: usize, old: &[[f64; 3]], new: &mut [[T; 3]]) {
        let rows = &self.rows[first..=first + new.len()];
        for ((out, r), &norm) in new
            .iter_mut()
            .zip(rows.windows(2))
            .zip(&self.norms[first..])
        {
            let mut p = [0.0f64; 3];
            for (&v, &w) in self.sources[r[0]..r[1]]
                .iter()
                .zip(&self.weights[r[0]..r[1]])
            {
                let q = old[v as usize];
                for (o, x) in p.iter_mut().zip(q) {
                    *o += w * x;
                }
            }
            *out = p.map(|x| T::from_f64(x / norm));
        }
    }

    /// Bytes the table holds.
    pub(crate) fn bytes(&self) -> usize {
        self.rows.capacity() * size_of::<usize>()
            + self.sources.capacity() * size_of::<u32>()
            + (self.weights.capacity() + self.norms.capacity()) * size_of::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_keep_the_scatters_order_and_divisor() {
        // Point 1 gets 0.5·p0, 0.5·p1 and 0.25·p2, divided by 1.25; point 0 gets p2.
        let mut scatter = Scatter::default();
        for run in [&[(1, 0.5)][..], &[(1, 0.5)], &[(0, 1.0), (1, 0.25)]] {
            for &(i, w) in run {
                scatter.add(i, w);
            }
            scatter.close();
        }
        // In the scatter's order: p0's weight, then p1's, then p2's.
        let s = Stencil::from_scatter(
            vec![scatter],
            3,
            |_, sum| if sum == 0.0 { 1.0 } else { sum },
        );
        let old = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 4.0]];
        let mut new: Vec<[f64; 3]> = Vec::new();
        s.apply(&old, &mut new);
        let by_hand = [(0.5 * 1.0) / 1.25, (0.5 * 2.0) / 1.25, (0.25 * 4.0) / 1.25];
        assert_eq!(new, vec![[0.0, 0.0, 4.0], by_hand, [0.0; 3]]);
        assert_eq!(s.len(), 3);
        // Renumbered: point 1 first, then a point left to the caller, then point 0.
        let mut picked: Vec<[f64; 3]> = Vec::new();
        s.pick(&[1, u32::MAX, 0]).apply(&old, &mut picked);
        assert_eq!(picked, vec![by_hand, [0.0; 3], [0.0, 0.0, 4.0]]);
    }
}
