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

use crate::curve::{CurveError, CurveTables};
use std::collections::HashMap;

/// Marks a transition not yet taken.
const UNKNOWN: u32 = u32::MAX;

/// The stencils of the contexts met so far, built on demand from a scheme's tables.
#[derive(Debug)]
pub(crate) struct Stencils<'t> {
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
    /// No context yet.
    pub fn new(t: CurveTables<'t>) -> Stencils<'t> {
        Stencils {
            reach: (0..t.word_count())
                .map(|w| t.mask_range(w).len())
                .max()
                .unwrap_or(0)
                .max(1),
            lookup: t.words.chunks_exact(t.degree + 1).zip(0..).collect(),
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
    #[inline]
    pub fn advance(&mut self, c: u32, a: u8) -> Result<u32, CurveError> {
        let i = c as usize * self.t.symbol_count() + a as usize;
        match self.next[i] {
            UNKNOWN => {
                let mut key = self.keys[c as usize].clone();
                key.push(a);
                let n = self.context(key)?;
                self.next[i] = n;
                Ok(n)
            }
            n => Ok(n),
        }
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
        let count = key.len() - d;
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
