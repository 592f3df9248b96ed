//! Gather form of a curve step (mask diffusion, \[N\] §2.3 and \[G\] §2.1.1, read backwards).
//!
//! Old point k scatters its mask onto new points base_k + j, base_k = Σ_{i<k} |π(label_i)|. Read
//! the other way round, the new points of interval k (base_k..base_{k+1}) receive weights only
//! from old points k' ≤ k whose masks reach that far: those with Σ_{k'≤i<k} |π(label_i)| below
//! the longest mask. Which weights they are depends only on the labels k'..k + d of those
//! points: a *context*. Each context met is turned once into a stencil (per new point, its
//! terms (weight, k − k') in increasing k'), and consecutive contexts are linked by a
//! transition table indexed by the next label. A step is then one pass over the old points:
//! one table lookup per point, one sum and one store per new point, no word index stored.
//!
//! The terms are summed in increasing k', the order in which the scatter form adds them, so
//! the gather form gives the same bits.
//!
//! The contexts that occur in curves labelled by the axiom's iterates are finite and known at
//! build time ([`Stencils::reachable`]): generated code numbers them as [`CurveContexts`] and
//! specialises their stencils with constant weights ([`crate::CurveScheme::gather`]); other
//! contexts are met at run time and summed from the tables.

use crate::tables::{CurveError, CurveTables};
use std::collections::{BTreeSet, HashMap};

/// Contexts numbered at build time, in the order generated code uses.
#[derive(Clone, Copy, Debug)]
pub struct CurveContexts<'a> {
    /// Labels of context c are `labels[offsets[c]..offsets[c + 1]]`.
    pub offsets: &'a [u32],
    /// Concatenated labels.
    pub labels: &'a [u8],
    /// Context × symbol → context; [`UNKNOWN`] for a transition never met from the axiom.
    pub next: &'a [u32],
}

impl CurveContexts<'_> {
    /// No context (the table-driven path).
    pub const NONE: CurveContexts<'static> = CurveContexts {
        offsets: &[0],
        labels: &[],
        next: &[],
    };

    /// Number of contexts.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// No context at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Σ weight · p[k − back] over `terms`, in their order, from 0.0 (as the scatter form began).
#[inline(always)]
pub fn lin<const D: usize>(terms: &[(f64, u32)], p: &[[f64; D]], k: usize) -> [f64; D] {
    let mut acc = [0.0; D];
    for &(w, back) in terms {
        let q = &p[k - back as usize];
        for c in 0..D {
            acc[c] += w * q[c];
        }
    }
    acc
}

/// A transition not yet taken (in [`CurveContexts::next`]: never met from the axiom).
pub const UNKNOWN: u32 = u32::MAX;

/// The stencils of the contexts met so far, built on demand from a scheme's tables.
#[derive(Debug)]
pub struct Stencils<'t> {
    t: CurveTables<'t>,
    /// The longest mask: a context reaches back while Σ|π| stays below it.
    pub reach: usize,
    /// Word index of each tabulated (d+1)-word.
    lookup: HashMap<&'t [u8], u32>,
    ids: HashMap<Vec<u8>, u32>,
    /// Labels of each context: k'..=k + d for its oldest point k'.
    keys: Vec<Vec<u8>>,
    /// Context × symbol → context of the next point, whose last label is that symbol.
    next: Vec<u32>,
    /// Context → range of its new points in `points`.
    segments: Vec<(u32, u32)>,
    /// New points of all stencils: ranges in `terms`.
    points: Vec<(u32, u32)>,
    /// (weight, back) terms: old point k − back.
    terms: Vec<(f64, u32)>,
}

impl<'t> Stencils<'t> {
    /// The stencils of `known` (numbered as there), more to come on demand. Returns the number
    /// of contexts numbered as in `known`: all of them, or 0 if they do not match the tables
    /// (then nothing is seeded and no specialised stencil may be used).
    pub fn new(t: CurveTables<'t>, known: CurveContexts<'_>) -> (Stencils<'t>, u32) {
        let mut s = Stencils::empty(t);
        let n = known.len();
        let numbered = (0..n).all(|c| {
            let key = &known.labels[known.offsets[c] as usize..known.offsets[c + 1] as usize];
            s.context_of(key).ok() == Some(c as u32)
        });
        let next_ok = known.next.len() == n * t.symbol_count()
            && known.next.iter().all(|&c| c == UNKNOWN || (c as usize) < n);
        if !(numbered && next_ok) {
            return (Stencils::empty(t), 0);
        }
        s.next.copy_from_slice(known.next);
        (s, n as u32)
    }

    /// Every context of the curves labelled by the axiom's iterates (cyclically), and the
    /// transitions between them, numbered in order of their label windows: windows of
    /// reach + d + 1 labels of the axiom repeated, closed under π (a window of π(u) lies in
    /// π of a window of u, every rule being non-empty).
    pub fn reachable(t: CurveTables<'t>) -> Result<Stencils<'t>, CurveError> {
        let mut s = Stencils::empty(t);
        let len = s.reach + t.degree + 1;
        let cyclic = |i| t.axiom.iter().cycle().skip(i).take(len).copied().collect();
        let mut seen: BTreeSet<Vec<u8>> = (0..t.axiom.len()).map(cyclic).collect();
        let mut todo: Vec<Vec<u8>> = seen.iter().cloned().collect();
        while let Some(w) = todo.pop() {
            let image: Vec<u8> = w.iter().flat_map(|&a| t.rule(a)).copied().collect();
            for v in image.windows(len) {
                if seen.insert(v.to_vec()) {
                    todo.push(v.to_vec());
                }
            }
        }
        for w in &seen {
            let c = s.context_of(&w[..len - 1])?;
            s.advance(c, w[len - 1])?;
        }
        Ok(s)
    }

    /// The contexts interned so far: (labels of each, the transition table).
    pub fn contexts(&self) -> (&[Vec<u8>], &[u32]) {
        (&self.keys, &self.next)
    }

    /// No context yet.
    fn empty(t: CurveTables<'t>) -> Stencils<'t> {
        Stencils {
            reach: (0..t.word_count())
                .map(|w| t.mask_range(w).len())
                .max()
                .unwrap_or(0)
                .max(1),
            lookup: t.word_index(),
            t,
            ids: HashMap::new(),
            keys: Vec::new(),
            next: Vec::new(),
            segments: Vec::new(),
            points: Vec::new(),
            terms: Vec::new(),
        }
    }

    /// The tables the stencils come from.
    pub fn tables(&self) -> CurveTables<'t> {
        self.t
    }

    /// The tabulated word of the d+1 labels `w`.
    pub fn word(&self, w: &[u8]) -> Result<u32, CurveError> {
        self.lookup
            .get(w)
            .copied()
            .ok_or_else(|| CurveError::UnknownWord(self.t.word_str(w)))
    }

    /// The context of a point given the labels from `reach − 1` points before it up to its
    /// own word's last label.
    pub fn context_of(&mut self, labels: &[u8]) -> Result<u32, CurveError> {
        self.context(labels.to_vec())
    }

    /// The context of the point after one in context `c`; `a` is the last label of its word.
    #[inline(always)]
    pub fn advance(&mut self, c: u32, a: u8) -> Result<u32, CurveError> {
        let i = c as usize * self.t.symbol_count() + a as usize;
        match self.next[i] {
            UNKNOWN => self.first_advance(c, a),
            n => Ok(n),
        }
    }

    /// [`Stencils::advance`] the first time it leaves `c` by `a`.
    #[cold]
    fn first_advance(&mut self, c: u32, a: u8) -> Result<u32, CurveError> {
        let mut key = self.keys[c as usize].clone();
        key.push(a);
        let n = self.context(key)?;
        self.next[c as usize * self.t.symbol_count() + a as usize] = n;
        Ok(n)
    }

    /// The new points of context `c`, each a slice of (weight, back) terms.
    #[inline]
    pub fn segment(&self, c: u32) -> impl Iterator<Item = &[(f64, u32)]> {
        let (a, b) = self.segments[c as usize];
        self.points[a as usize..b as usize]
            .iter()
            .map(|&(s, e)| &self.terms[s as usize..e as usize])
    }

    /// Interns a context given by its labels, cut to the points that can reach.
    fn context(&mut self, mut key: Vec<u8>) -> Result<u32, CurveError> {
        let d = self.t.degree;
        let len = |s: u8| self.t.rule(s).len();
        // Points k' = k − b, b < count; label index of point k − b is count − 1 − b.
        if let Some(&s) = key.iter().find(|&&s| s as usize >= self.t.symbol_count()) {
            return Err(CurveError::UnknownSymbol(s));
        }
        let count = match key.len().checked_sub(d) {
            Some(c) if c > 0 => c,
            // Fewer labels than one word: no such context.
            _ => return Err(CurveError::UnknownWord(self.t.word_str(&key))),
        };
        let mut span = 0;
        let mut keep = 1;
        while keep < count {
            span += len(key[count - 1 - keep]);
            if span >= self.reach {
                break;
            }
            keep += 1;
        }
        key.drain(..count - keep);
        if let Some(&c) = self.ids.get(&key) {
            return Ok(c);
        }
        let words = (0..keep)
            .map(|i| self.word(&key[i..=i + d]))
            .collect::<Result<Vec<u32>, _>>()?;
        let c = self.keys.len() as u32;
        let first = self.points.len() as u32;
        // offset of point i (oldest first): new index of the segment's start, seen from it.
        let mut offset = vec![0; keep];
        for i in (0..keep - 1).rev() {
            offset[i] = offset[i + 1] + len(key[i]);
        }
        for j0 in 0..len(key[keep - 1]) {
            let start = self.terms.len() as u32;
            for (i, &w) in words.iter().enumerate() {
                let range = self.t.mask_range(w as usize);
                let j = j0 + offset[i];
                if j < range.len() {
                    let back = (keep - 1 - i) as u32;
                    self.terms
                        .push((self.t.mask_weights[range.start + j], back));
                }
            }
            self.points.push((start, self.terms.len() as u32));
        }
        self.segments.push((first, self.points.len() as u32));
        self.next
            .resize(self.next.len() + self.t.symbol_count(), UNKNOWN);
        self.ids.insert(key.clone(), c);
        self.keys.push(key);
        Ok(c)
    }
}
