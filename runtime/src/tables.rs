//! The tables of a curve scheme (CSR, as OpenSubdiv's stencil tables): the one contract between
//! build time and run time, which generated code emits and every driver reads; their
//! rewriting (π) and the errors of a refinement they cannot carry.

use std::collections::HashMap;
use std::fmt;

/// `mask_children` entry of a word whose mask has no child (even degrees).
pub const NO_CHILD: u32 = u32::MAX;

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
    /// Entry index (within its mask) of the child of each word, for odd degrees; [`NO_CHILD`]
    /// for even degrees.
    pub mask_children: &'a [u32],
    /// Per word, its limit mask: the weights of the points −(d−1)/2..=(d−1)/2 around a point
    /// with that word for the point of the limit curve it converges to, then for the curve's
    /// derivative there (2d values a word, nearest f64 of the exact ones); empty for degrees
    /// without one (`lsubdiv_compiler::exact::limit`: degrees 1 and 3 have them).
    pub limit_weights: &'a [f64],
    /// The interval length of each symbol (the Perron eigenvector, smallest 1: exact in the
    /// compiler, nearest f64 here): where knots lie, for face-varying data
    /// (`lsubdiv_mesh::facevarying`).
    pub lengths: &'a [f64],
}

impl<'a> CurveTables<'a> {
    /// The index of every tabulated word.
    pub fn word_index(&self) -> HashMap<&'a [u8], u32> {
        self.words.chunks_exact(self.degree + 1).zip(0..).collect()
    }

    /// π^steps(word).
    pub fn iterate(&self, word: &[u8], steps: usize) -> Vec<u8> {
        let (mut word, mut next) = (word.to_vec(), Vec::new());
        for _ in 0..steps {
            rewrite(self, &word, &mut next);
            std::mem::swap(&mut word, &mut next);
        }
        word
    }

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

    /// The limit mask of word i ([`CurveTables::limit_weights`]): the position weights and
    /// the tangent weights, if the tables have them.
    pub fn limit_mask(&self, i: usize) -> Option<(&'a [f64], &'a [f64])> {
        let d = self.degree;
        let all = self.limit_weights.get(2 * d * i..2 * d * (i + 1))?;
        Some(all.split_at(d))
    }

    /// Number of symbols.
    pub fn symbol_count(&self) -> usize {
        self.rule_offsets.len() - 1
    }

    /// |π^steps(word)|, exactly, from symbol counts (counts · M per step) without rewriting;
    /// `u128::MAX` when it does not fit. Symbols outside the alphabet count as nothing.
    pub fn image_len(&self, word: &[u8], steps: usize) -> u128 {
        let mut counts = vec![0u128; self.symbol_count()];
        for &s in word {
            if let Some(c) = counts.get_mut(s as usize) {
                *c += 1;
            }
        }
        let total = |c: &[u128]| c.iter().fold(0u128, |a, &x| a.saturating_add(x));
        let mut len = total(&counts);
        // Rules are never empty, so lengths never grow smaller. While the length stays, every
        // symbol present rewrites to one symbol; if it stays for more steps than there are
        // symbols, each orbit has closed among such symbols and it stays for ever. So the loop
        // ends early for huge `steps`, as it does once the length saturates.
        let mut flat = 0;
        for _ in 0..steps {
            if len == u128::MAX || flat > counts.len() {
                break;
            }
            let mut next = vec![0u128; counts.len()];
            for (a, &c) in counts.iter().enumerate() {
                for &b in self.rule(a as u8) {
                    next[b as usize] = next[b as usize].saturating_add(c);
                }
            }
            counts = next;
            let next_len = total(&counts);
            flat = if next_len == len { flat + 1 } else { 0 };
            len = next_len;
        }
        len
    }

    /// A word for messages ([`format_word`]).
    pub fn word_str(&self, w: &[u8]) -> String {
        let names: Vec<&str> = self.symbol_names.split(' ').collect();
        format_word(&names, w)
    }
}

/// A word written with the symbol names: `LCR`, or `A1 A2` when some symbol name is longer
/// than one character.
pub fn format_word(names: &[impl AsRef<str>], w: &[u8]) -> String {
    let compact = names.iter().all(|s| s.as_ref().chars().count() == 1);
    let parts: Vec<&str> = w.iter().map(|&s| names[s as usize].as_ref()).collect();
    parts.join(if compact { "" } else { " " })
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
    /// Interpolated ends need an odd degree ([`crate::ends`]).
    EvenDegree(usize),
    /// The tables have no limit masks for this degree ([`crate::limit`]).
    NoLimit(usize),
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
            CurveError::EvenDegree(d) => write!(
                f,
                "interpolated ends need an odd degree (the end point on a knot); this scheme has degree {d}"
            ),
            CurveError::NoLimit(d) => write!(
                f,
                "no limit masks for degree {d}: they are derived for degrees 1 and 3 (a point of the limit curve of another degree depends on more intervals than its word)"
            ),
        }
    }
}

impl std::error::Error for CurveError {}

/// π applied to every label of `labels`, into `out` (cleared first). Rules of up to 8 symbols
/// are written as one 8-byte store each (into a buffer sized from the symbol counts), longer
/// ones appended.
pub fn rewrite(t: &CurveTables<'_>, labels: &[u8], out: &mut Vec<u8>) {
    const WIDE: usize = 8;
    out.clear();
    let rules: Vec<&[u8]> = (0..t.symbol_count()).map(|a| t.rule(a as u8)).collect();
    if rules.iter().any(|r| r.len() > WIDE) {
        for &s in labels {
            out.extend_from_slice(rules[s as usize]);
        }
        return;
    }
    // One vectorised count per symbol.
    let total: usize = rules
        .iter()
        .enumerate()
        .map(|(a, r)| labels.iter().filter(|&&s| s as usize == a).count() * r.len())
        .sum();
    let padded: Vec<(u64, usize)> = rules
        .iter()
        .map(|r| {
            let bytes: [u8; WIDE] = std::array::from_fn(|i| r.get(i).copied().unwrap_or(0));
            (u64::from_le_bytes(bytes), r.len())
        })
        .collect();
    out.resize(total + WIDE, 0);
    let mut at = 0;
    for &s in labels {
        let (bytes, len) = padded[s as usize];
        out[at..at + WIDE].copy_from_slice(&bytes.to_le_bytes());
        at += len;
    }
    out.truncate(total);
}
