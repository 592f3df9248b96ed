//! Curve refinement by mask diffusion (\[N\] §2.3, \[G\] §2.1.1).
//!
//! Intervals carry symbols; control point k owns the d+1 intervals k..k+d (its word). One step
//! rewrites every interval (π) and spreads each old point over the new points of its mask; the
//! driver computes that in gather form ([`crate::gather`]), summing in order of k, so that every
//! path that uses the same tables produces the same bits.

use crate::gather::{lin, CurveContexts, Stencils};
pub use crate::tables::{format_word, rewrite, CurveError, CurveTables, NO_CHILD};

/// A scheme that can refine curves: its tables (the driver builds its stencils from them,
/// [`crate::gather`]) and, in generated code, stencils specialised for the contexts known at
/// build time.
pub trait CurveScheme {
    /// The tables.
    fn tables(&self) -> CurveTables<'_>;

    /// The contexts that [`CurveScheme::gather`] specialises (none by default).
    fn contexts(&self) -> CurveContexts<'_> {
        CurveContexts::NONE
    }

    /// Hands the new points of old point k, in context `c` of [`CurveScheme::contexts`], to
    /// `emit` in order; `false` leaves them to the table-driven stencils.
    #[inline(always)]
    fn gather<const D: usize>(
        &self,
        c: u32,
        p: &[[f64; D]],
        k: usize,
        emit: &mut impl FnMut([f64; D]),
    ) -> bool {
        let _ = (c, p, k, emit);
        false
    }
}

/// A control polygon with one label per knot interval.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve<const D: usize> {
    /// Control points.
    pub points: Vec<[f64; D]>,
    /// Interval labels: m + d of them for an open polygon of m points, m for a closed one.
    pub labels: Vec<u8>,
    /// Closed (cyclic) or open.
    pub closed: bool,
}

impl<const D: usize> Curve<D> {
    /// A polygon labelled with the axiom repeated from the first interval on.
    pub fn with_axiom(t: &CurveTables<'_>, points: Vec<[f64; D]>, closed: bool) -> Curve<D> {
        let n = if closed {
            points.len()
        } else {
            points.len() + t.degree
        };
        let labels = t.axiom.iter().copied().cycle().take(n).collect();
        Curve {
            points,
            labels,
            closed,
        }
    }

    /// The (d+1)-word of point k.
    pub fn word(&self, k: usize, d: usize) -> Vec<u8> {
        let n = self.labels.len();
        (k..=k + d).map(|i| self.labels[i % n]).collect()
    }

    /// Checks label count, symbols and point count against the tables.
    pub fn check(&self, t: &CurveTables<'_>) -> Result<(), CurveError> {
        let d = t.degree;
        // Open or closed, a spline of degree d needs d + 1 control points (fewer leave no
        // knot interval on which every B-spline is defined, and nothing to refine).
        let needed = d + 1;
        let expected = if self.closed {
            self.points.len()
        } else {
            self.points.len() + d
        };
        if self.points.len() < needed {
            return Err(CurveError::TooFewPoints {
                needed,
                got: self.points.len(),
            });
        }
        if self.labels.len() != expected {
            return Err(CurveError::LabelCount {
                expected,
                got: self.labels.len(),
            });
        }
        // The largest label first (a vectorised scan), the offender only if there is one.
        let bad = |s: &&u8| **s as usize >= t.symbol_count();
        if self.labels.iter().max().is_some_and(|s| bad(&s)) {
            if let Some(&s) = self.labels.iter().find(bad) {
                return Err(CurveError::UnknownSymbol(s));
            }
        }
        Ok(())
    }
}

/// Refines a curve `steps` times.
pub fn refine<S: CurveScheme, const D: usize>(
    scheme: &S,
    curve: &Curve<D>,
    steps: usize,
) -> Result<Curve<D>, CurveError> {
    let mut r = CurveRefiner::default();
    r.refine(scheme, curve, steps)?;
    Ok(r.into_curve())
}

/// Curve refinement with reusable buffers (refine the same kind of curve again and again
/// without reallocating).
#[derive(Clone, Debug, Default)]
pub struct CurveRefiner<const D: usize> {
    cur: Curve<D>,
    next: Curve<D>,
}

impl<const D: usize> Default for Curve<D> {
    fn default() -> Self {
        Curve {
            points: Vec::new(),
            labels: Vec::new(),
            closed: false,
        }
    }
}

impl<const D: usize> CurveRefiner<D> {
    /// Refines `curve` `steps` times; the result stays in the refiner.
    pub fn refine<S: CurveScheme>(
        &mut self,
        scheme: &S,
        curve: &Curve<D>,
        steps: usize,
    ) -> Result<&Curve<D>, CurveError> {
        let t = scheme.tables();
        curve.check(&t)?;
        let (mut stencils, specialised) = Stencils::new(t, scheme.contexts());
        if steps == 0 {
            // Nothing to refine, but the words must still be known.
            let d = t.degree;
            for k in 0..curve.points.len() {
                stencils.word(&curve.word(k, d))?;
            }
            self.cur.clone_from(curve);
        }
        for i in 0..steps {
            // The first step reads the input itself (no copy).
            let src = if i == 0 { curve } else { &self.cur };
            step(scheme, specialised, &mut stencils, src, &mut self.next)?;
            std::mem::swap(&mut self.cur, &mut self.next);
        }
        Ok(&self.cur)
    }

    /// The refined curve.
    pub fn into_curve(self) -> Curve<D> {
        self.cur
    }
}

/// One refinement step into `next`, in gather form ([`crate::gather`]): the new points of
/// interval k are new indices base_k..base_{k+1}. The first `reach` intervals, whose parents
/// wrap around (closed) or are cut off (open), are summed by [`head_points`], the others by
/// [`body_points`]. Fails on a word that has no mask.
fn step<S: CurveScheme, const D: usize>(
    scheme: &S,
    specialised: u32,
    stencils: &mut Stencils<'_>,
    cur: &Curve<D>,
    next: &mut Curve<D>,
) -> Result<(), CurveError> {
    let t = stencils.tables();
    let d = t.degree;
    rewrite(&t, &cur.labels, &mut next.labels);
    let m = cur.points.len();
    let image_len = |labels: &[u8]| labels.iter().map(|&s| t.rule(s).len()).sum::<usize>();
    let total = if cur.closed {
        next.labels.len()
    } else {
        image_len(&cur.labels[..m])
    };
    // An open curve keeps the new points all of whose parents exist:
    // l ∈ [Σ_{i<d}|π(label_i)| − d, total).
    let lo = if cur.closed {
        0
    } else {
        image_len(&cur.labels[..d]) - d
    };
    next.closed = cur.closed;
    next.points.clear();
    // Room for every new point, even those below `lo` dropped at the end: `body_points`
    // writes into the spare capacity.
    next.points.reserve(total);
    let head = stencils.reach.min(m);
    let base = head_points(stencils, cur, total, head, lo, &mut next.points)?;
    if head < m {
        body_points(scheme, specialised, stencils, cur, head, &mut next.points)?;
    }
    // B-spline masks reach d + 1 intervals, so `lo` is within the head; were it not, the
    // points below it are dropped here.
    next.points.drain(..lo.saturating_sub(base));
    if !cur.closed {
        next.labels.truncate(total + d);
        next.labels.drain(..lo);
    }
    Ok(())
}

/// The new points of intervals `head..m` (every parent at k − back ≥ k − reach + 1 ≥ 0): one
/// context transition per old point, one sum per new point. Contexts below `specialised` are
/// numbered as in `scheme.contexts()`, and the scheme's own code may sum them.
fn body_points<S: CurveScheme, const D: usize>(
    scheme: &S,
    specialised: u32,
    stencils: &mut Stencils<'_>,
    cur: &Curve<D>,
    head: usize,
    out: &mut Vec<[f64; D]>,
) -> Result<(), CurveError> {
    let (d, labels) = (stencils.tables().degree, &cur.labels);
    let first = head + 1 - stencils.reach;
    // The word of point k ends at label k + d (cyclically for a closed curve).
    let start: Vec<u8> = (first..=head + d)
        .map(|i| labels[i % labels.len()])
        .collect();
    let mut c = stencils.context_of(&start)?;
    let (p, spare) = (&cur.points, out.spare_capacity_mut());
    let later = labels.iter().cycle().skip(head + d + 1);
    let mut n = 0;
    let mut emit = |v| {
        spare[n].write(v);
        n += 1;
    };
    for (k, &a) in (head..p.len()).zip(std::iter::once(&0).chain(later)) {
        if k > head {
            c = stencils.advance(c, a)?;
        }
        if c < specialised && scheme.gather(c, p, k, &mut emit) {
            continue;
        }
        for terms in stencils.segment(c) {
            emit(lin(terms, p, k));
        }
    }
    // SAFETY: the first n spare slots were written by `emit`.
    unsafe { out.set_len(out.len() + n) };
    Ok(())
}

/// The new points of the first `head` intervals, each parent found by its new index; points
/// below `lo` are skipped. For a closed curve, a parent near the end reaches new index l
/// through l + q·total (q ≥ 1, the wrap); sums run in increasing old index within each q, and
/// the q-sums are added in order of q, as in scatter form, where the wrapped part was added at
/// the end. Returns the first new index after the head.
fn head_points<const D: usize>(
    stencils: &Stencils<'_>,
    cur: &Curve<D>,
    total: usize,
    head: usize,
    lo: usize,
    out: &mut Vec<[f64; D]>,
) -> Result<usize, CurveError> {
    let (t, reach, m) = (stencils.tables(), stencils.reach, cur.points.len());
    let len = |k: usize| t.rule(cur.labels[k]).len();
    // Candidate parents (index, word, base): the head, and for a closed curve the tail, whose
    // bases are counted back from `total`.
    let word = |k: usize| stencils.word(&cur.word(k, t.degree));
    let all = cur.closed && m <= 2 * reach;
    let mut parents = Vec::new();
    let mut base = 0;
    for k in 0..if all { m } else { head } {
        parents.push((k, word(k)?, base));
        base += len(k);
    }
    let end = parents[head - 1].2 + len(head - 1);
    if cur.closed && !all {
        let mut base = total;
        let mut tail = Vec::new();
        for k in (m - reach..m).rev() {
            base -= len(k);
            tail.push((k, word(k)?, base));
        }
        parents.extend(tail.into_iter().rev());
    }
    let wraps = if cur.closed { reach / total + 1 } else { 0 };
    for l in lo..end {
        let mut point = [0.0; D];
        for q in 0..=wraps {
            let mut acc = [0.0; D];
            let mut any = false;
            for &(k, word, base) in &parents {
                let range = t.mask_range(word as usize);
                let j = (l + q * total).wrapping_sub(base);
                if j < range.len() {
                    let w = t.mask_weights[range.start + j];
                    for (a, x) in acc.iter_mut().zip(&cur.points[k]) {
                        *a += w * x;
                    }
                    any = true;
                }
            }
            if q == 0 {
                point = acc;
            } else if any {
                for (o, x) in point.iter_mut().zip(acc) {
                    *o += x;
                }
            }
        }
        out.push(point);
    }
    Ok(end)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tables with only rules (no masks).
    fn rules<'a>(offsets: &'a [u32], symbols: &'a [u8], axiom: &'a [u8]) -> CurveTables<'a> {
        CurveTables {
            name: "t",
            degree: 1,
            symbol_names: "A B C",
            rule_offsets: offsets,
            rule_symbols: symbols,
            axiom,
            words: &[],
            mask_offsets: &[0],
            mask_words: &[],
            mask_weights: &[],
            mask_children: &[],
            limit_weights: &[],
            lengths: &[],
        }
    }

    /// Lengths by rewriting, for comparison.
    fn rewritten(t: &CurveTables<'_>, word: &[u8], steps: usize) -> u128 {
        let mut w = word.to_vec();
        for _ in 0..steps {
            w = w.iter().flat_map(|&s| t.rule(s).to_vec()).collect();
        }
        w.len() as u128
    }

    #[test]
    fn image_lengths_are_exact_and_end_early() {
        // A → B, B → C, C → CC: the length stays 1 for two steps, then doubles.
        let t = rules(&[0, 1, 2, 4], &[1, 2, 2, 2], &[0]);
        for steps in 0..12 {
            assert_eq!(t.image_len(&[0], steps), rewritten(&t, &[0], steps));
            assert_eq!(
                t.image_len(&[0, 2, 1], steps),
                rewritten(&t, &[0, 2, 1], steps)
            );
        }
        // 2^(s−2) saturates u128 long before usize::MAX steps.
        assert_eq!(t.image_len(&[0], 129), 1 << 127);
        assert_eq!(t.image_len(&[0], 130), u128::MAX);
        assert_eq!(t.image_len(&[0], usize::MAX), u128::MAX);
        // A → B, B → A, C → C: lengths never change, and huge step counts return at once.
        let t = rules(&[0, 1, 2, 3], &[1, 0, 2], &[0]);
        assert_eq!(t.image_len(&[0, 2], usize::MAX), 2);
        // Symbols outside the alphabet count as nothing.
        assert_eq!(t.image_len(&[0, 7], 3), 1);
    }
}
