//! Curve refinement by mask diffusion ([N] §2.3, [G] §2.1.1).
//!
//! Intervals carry symbols; control point k owns the d+1 intervals k..k+d (its word). One step
//! rewrites every interval (π) and scatters each old point into the new points of its mask, in
//! order of k, so that every path that uses the same tables produces the same bits.

use crate::real::{axpy_slab, Real};
use std::collections::HashMap;
use std::fmt;

/// Flat tables of a curve scheme (CSR layout, as OpenSubdiv's stencil tables).
#[derive(Clone, Copy, Debug)]
pub struct CurveTables<'a> {
    /// Scheme name.
    pub name: &'a str,
    /// Spline degree d.
    pub degree: usize,
    /// Symbol names separated by single spaces, in symbol order.
    pub symbol_names: &'a str,
    /// π(A) is `rule_symbols[rule_offsets[A]..rule_offsets[A + 1]]`.
    pub rule_offsets: &'a [u32],
    /// Concatenated right-hand sides.
    pub rule_symbols: &'a [u8],
    /// The axiom.
    pub axiom: &'a [u8],
    /// Word i is `words[i * (d + 1)..(i + 1) * (d + 1)]`.
    pub words: &'a [u8],
    /// Mask of word i is entries `mask_offsets[i]..mask_offsets[i + 1]`.
    pub mask_offsets: &'a [u32],
    /// Word index of the new point of each mask entry.
    pub mask_words: &'a [u32],
    /// Weight of each mask entry (nearest f64 to the exact weight).
    pub mask_weights: &'a [f64],
    /// Entry index (within its mask) of the child of each word, for odd degrees; `u32::MAX` for
    /// even degrees (no child).
    pub mask_children: &'a [u32],
}

impl CurveTables<'_> {
    /// π(A).
    pub fn rule(&self, a: u8) -> &[u8] {
        let a = a as usize;
        &self.rule_symbols[self.rule_offsets[a] as usize..self.rule_offsets[a + 1] as usize]
    }

    /// Number of tabulated words.
    pub fn word_count(&self) -> usize {
        self.mask_offsets.len() - 1
    }

    /// Word i.
    pub fn word(&self, i: usize) -> &[u8] {
        let k = self.degree + 1;
        &self.words[i * k..(i + 1) * k]
    }

    /// Entries of the mask of word i.
    pub fn mask_range(&self, i: usize) -> std::ops::Range<usize> {
        self.mask_offsets[i] as usize..self.mask_offsets[i + 1] as usize
    }

    /// Number of symbols.
    pub fn symbol_count(&self) -> usize {
        self.rule_offsets.len() - 1
    }

    /// A word for messages (`LCR`, or `A1 A2` when a symbol name is longer than one character).
    pub fn word_str(&self, w: &[u8]) -> String {
        let all: Vec<&str> = self.symbol_names.split(' ').collect();
        let compact = all.iter().all(|s| s.chars().count() == 1);
        let names: Vec<&str> = w.iter().map(|&s| all[s as usize]).collect();
        names.join(if compact { "" } else { " " })
    }
}

/// A scheme that can refine curves: its tables plus a mask-diffusion kernel.
pub trait CurveScheme {
    /// The tables.
    fn tables(&self) -> CurveTables<'_>;

    /// Adds `weight · p` for every entry of the mask of `word` into `out[j]`, j = entry index.
    fn diffuse<const D: usize>(&self, word: u32, p: &[f64; D], out: &mut [[f64; D]]) {
        let t = self.tables();
        let range = t.mask_range(word as usize);
        for (o, &w) in out.iter_mut().zip(&t.mask_weights[range]) {
            for c in 0..D {
                o[c] += w * p[c];
            }
        }
    }

    /// Entries `keep` of the mask of `word` on slabs: for every entry j in `keep`,
    /// `dst[(j − keep.start)·len ..][..len] += w_j · src` with `len = src.len()` (whole rows of
    /// points at once).
    fn axpy_mask<T: Real>(
        &self,
        word: u32,
        keep: std::ops::Range<usize>,
        src: &[T],
        dst: &mut [T],
    ) {
        let t = self.tables();
        let n = src.len();
        let weights = &t.mask_weights[t.mask_range(word as usize)];
        for (j, &w) in weights.iter().enumerate().take(keep.end).skip(keep.start) {
            let at = (j - keep.start) * n;
            axpy_slab(&mut dst[at..at + n], T::from_f64(w), src);
        }
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

/// Why a curve cannot be refined.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CurveError {
    /// Label count does not match the point count.
    LabelCount {
        /// Expected.
        expected: usize,
        /// Given.
        got: usize,
    },
    /// A label is not a symbol of the scheme.
    UnknownSymbol(u8),
    /// Too few points for the degree.
    TooFewPoints {
        /// Needed.
        needed: usize,
        /// Given.
        got: usize,
    },
    /// A point's word has no mask in the tables (not reachable from the axiom).
    UnknownWord(String),
}

impl fmt::Display for CurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveError::LabelCount { expected, got } => {
                write!(f, "{got} interval labels given, {expected} needed")
            }
            CurveError::UnknownSymbol(s) => write!(f, "label {s} is not a symbol of the scheme"),
            CurveError::TooFewPoints { needed, got } => {
                write!(f, "{got} control points given, at least {needed} needed")
            }
            CurveError::UnknownWord(w) => write!(
                f,
                "word {w} has no tabulated mask (not reachable from the axiom); use the generic path"
            ),
        }
    }
}

impl std::error::Error for CurveError {}

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
        let (needed, expected) = if self.closed {
            (d + 1, self.points.len())
        } else {
            (1, self.points.len() + d)
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
        match self
            .labels
            .iter()
            .find(|&&s| s as usize >= t.symbol_count())
        {
            Some(&s) => Err(CurveError::UnknownSymbol(s)),
            None => Ok(()),
        }
    }
}

/// Refines a curve `steps` times.
pub fn refine<S: CurveScheme, const D: usize>(
    scheme: &S,
    curve: &Curve<D>,
    steps: usize,
) -> Result<Curve<D>, CurveError> {
    let t = scheme.tables();
    curve.check(&t)?;
    let lookup: HashMap<&[u8], u32> = (0..t.word_count()).map(|i| (t.word(i), i as u32)).collect();
    let mut words = (0..curve.points.len())
        .map(|k| {
            let w = curve.word(k, t.degree);
            lookup
                .get(w.as_slice())
                .copied()
                .ok_or_else(|| CurveError::UnknownWord(t.word_str(&w)))
        })
        .collect::<Result<Vec<u32>, _>>()?;
    let mut cur = curve.clone();
    for _ in 0..steps {
        let (next, next_words) = step(scheme, &t, &cur, &words);
        cur = next;
        words = next_words;
    }
    Ok(cur)
}

/// One refinement step; returns the new curve and the word index of each new point.
fn step<S: CurveScheme, const D: usize>(
    scheme: &S,
    t: &CurveTables<'_>,
    cur: &Curve<D>,
    words: &[u32],
) -> (Curve<D>, Vec<u32>) {
    let d = t.degree;
    let mut offsets = Vec::with_capacity(cur.labels.len() + 1);
    let mut labels = Vec::new();
    offsets.push(0usize);
    for &s in &cur.labels {
        labels.extend_from_slice(t.rule(s));
        offsets.push(labels.len());
    }
    let total = labels.len();
    let m = cur.points.len();
    // Buffer long enough for every mask without wrapping.
    let span = (0..m)
        .map(|k| offsets[k] + t.mask_range(words[k] as usize).len())
        .max()
        .unwrap_or(0)
        .max(total);
    let mut out = vec![[0.0; D]; span];
    let mut out_words = vec![0u32; span];
    for k in 0..m {
        let base = offsets[k];
        let w = words[k];
        scheme.diffuse(w, &cur.points[k], &mut out[base..]);
        let range = t.mask_range(w as usize);
        out_words[base..base + range.len()].copy_from_slice(&t.mask_words[range]);
    }
    if cur.closed {
        // New point l ≥ total is point l − total of the cycle.
        for i in total..span {
            let v = out[i];
            for c in 0..D {
                out[i - total][c] += v[c];
            }
            out_words[i - total] = out_words[i];
        }
        out.truncate(total);
        out_words.truncate(total);
        (
            Curve {
                points: out,
                labels,
                closed: true,
            },
            out_words,
        )
    } else {
        // Keep the new points all of whose parents exist: l ∈ [offsets[d] − d, offsets[m]).
        let (lo, hi) = (offsets[d] - d, offsets[m]);
        (
            Curve {
                points: out[lo..hi].to_vec(),
                labels: labels[lo..hi + d].to_vec(),
                closed: false,
            },
            out_words[lo..hi].to_vec(),
        )
    }
}
