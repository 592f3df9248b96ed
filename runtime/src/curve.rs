//! Curve refinement by mask diffusion (\[N\] §2.3, \[G\] §2.1.1).
//!
//! Intervals carry symbols; control point k owns the d+1 intervals k..k+d (its word). One step
//! rewrites every interval (π) and scatters each old point into the new points of its mask, in
//! order of k, so that every path that uses the same tables produces the same bits.

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
    let mut r = CurveRefiner::default();
    r.refine(scheme, curve, steps)?;
    Ok(r.into_curve())
}

/// New points accumulated in cache before they are written out.
const WINDOW: usize = 4096;

/// Curve refinement with reusable buffers (refine the same kind of curve again and again
/// without reallocating).
#[derive(Clone, Debug, Default)]
pub struct CurveRefiner<const D: usize> {
    cur: Curve<D>,
    next: Curve<D>,
    words: Vec<u32>,
    next_words: Vec<u32>,
    window: Vec<[f64; D]>,
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
        initial_words(&t, curve, &mut self.words)?;
        if steps == 0 {
            self.cur.clone_from(curve);
        }
        for i in 0..steps {
            // The first step reads the input itself (no copy).
            let src = if i == 0 { curve } else { &self.cur };
            step(
                scheme,
                &t,
                src,
                &self.words,
                &mut self.next,
                &mut self.next_words,
                &mut self.window,
            );
            std::mem::swap(&mut self.cur, &mut self.next);
            std::mem::swap(&mut self.words, &mut self.next_words);
        }
        Ok(&self.cur)
    }

    /// The refined curve.
    pub fn into_curve(self) -> Curve<D> {
        self.cur
    }
}

/// The word index of every point, from windows over the labels (wrapped for closed curves),
/// without allocating per point; equal consecutive windows reuse the previous lookup.
fn initial_words<const D: usize>(
    t: &CurveTables<'_>,
    curve: &Curve<D>,
    words: &mut Vec<u32>,
) -> Result<(), CurveError> {
    let lookup: HashMap<&[u8], u32> = (0..t.word_count()).map(|i| (t.word(i), i as u32)).collect();
    let (d, labels) = (t.degree, &curve.labels);
    // A closed curve's last windows wrap around to its first labels: only those d windows are
    // copied, never the whole label sequence.
    let split = labels.len().saturating_sub(d);
    let tail: Vec<u8> = if curve.closed {
        labels[split..]
            .iter()
            .chain(labels.iter().cycle().take(d))
            .copied()
            .collect()
    } else {
        labels[split..].to_vec()
    };
    words.clear();
    let mut last: Option<(&[u8], u32)> = None;
    for k in 0..curve.points.len() {
        let w = if k < split {
            &labels[k..k + d + 1]
        } else {
            &tail[k - split..k - split + d + 1]
        };
        let i = match last {
            Some((prev, i)) if prev == w => i,
            _ => *lookup
                .get(w)
                .ok_or_else(|| CurveError::UnknownWord(t.word_str(w)))?,
        };
        last = Some((w, i));
        words.push(i);
    }
    Ok(())
}

/// One refinement step into `next`. New point j of old point k's mask is new point base_k + j,
/// base_k = Σ_{i<k} |π(label_i)|. Masks are accumulated in a cache-sized window; the new points
/// before base_k are final once point k is reached, and are written out once.
fn step<S: CurveScheme, const D: usize>(
    scheme: &S,
    t: &CurveTables<'_>,
    cur: &Curve<D>,
    words: &[u32],
    next: &mut Curve<D>,
    next_words: &mut Vec<u32>,
    window: &mut Vec<[f64; D]>,
) {
    let d = t.degree;
    next.labels.clear();
    for &s in &cur.labels {
        next.labels.extend_from_slice(t.rule(s));
    }
    let total = next.labels.len();
    let longest = (0..t.word_count())
        .map(|w| t.mask_range(w).len())
        .max()
        .unwrap_or(0);
    next.points.clear();
    next.points.reserve(total + longest);
    next_words.clear();
    next_words.resize(total + longest, 0);
    window.clear();
    window.resize(WINDOW + longest, [0.0; D]);
    let mut w0 = 0; // new index of window[0]
    let mut base = 0;
    let mut end = 0;
    for ((p, &w), &s) in cur.points.iter().zip(words).zip(&cur.labels) {
        let range = t.mask_range(w as usize);
        if base + range.len() > w0 + window.len() {
            // Points before `base` are final: write them, slide the window.
            let done = base - w0;
            next.points.extend_from_slice(&window[..done]);
            window.copy_within(done.., 0);
            let keep = window.len() - done;
            window[keep..].fill([0.0; D]);
            w0 = base;
        }
        scheme.diffuse(w, p, &mut window[base - w0..]);
        end = end.max(base + range.len());
        next_words[base..base + range.len()].copy_from_slice(&t.mask_words[range]);
        base += t.rule(s).len();
    }
    next.points.extend_from_slice(&window[..end - w0]);
    next_words.truncate(end);
    if cur.closed {
        // New point l ≥ total is point l − total of the cycle.
        for i in total..end {
            let v = next.points[i];
            for (o, x) in next.points[i - total].iter_mut().zip(v) {
                *o += x;
            }
            next_words[i - total] = next_words[i];
        }
        next.points.truncate(total);
        next_words.truncate(total);
        next.closed = true;
    } else {
        // Keep the new points all of whose parents exist: l ∈ [Σ_{i<d}|π(label_i)| − d, base).
        let lo = cur.labels[..d]
            .iter()
            .map(|&s| t.rule(s).len())
            .sum::<usize>()
            - d;
        next.points.truncate(base);
        next.points.drain(..lo);
        next_words.truncate(base);
        next_words.drain(..lo);
        next.labels.truncate(base + d);
        next.labels.drain(..lo);
        next.closed = false;
    }
}
