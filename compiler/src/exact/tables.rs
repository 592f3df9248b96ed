//! The one tables value: the certified [`Scheme`] flattened once into the runtime's layout
//! (rules, words and masks in CSR form, each weight's nearest f64 beside its exact value), with
//! the surface data when the scheme passes \[G\] §4.2. Code generation emits it
//! ([`crate::exact::codegen`]); the dynamic path holds it and appends the masks of words the
//! axiom never makes ([`Tables::add_reachable`]). It lends the runtime's views,
//! [`CurveTables`] and [`SurfaceTables`].
//!
//! f64 appears here only as the nearest double of exact values, and in the runtime's α solver.

use crate::exact::ev::{self, SurfaceAnalysis};
use crate::exact::field::Elem;
use crate::exact::graph::reach_from;
use crate::exact::lsystem::{Part, Word};
use crate::exact::pipeline::Scheme;
use crate::exact::work;
use crate::Error;
use lsubdiv_runtime::curve::NO_CHILD;
use lsubdiv_runtime::ev::{EvCoefficients, EvLimit};
use lsubdiv_runtime::surface::SurfaceTables;
use lsubdiv_runtime::CurveTables;
use std::collections::HashMap;

/// Largest valence whose α is tabulated; the runtime computes larger ones with the same solver.
pub const MAX_TABULATED_VALENCE: usize = 32;

/// The tables of a compiled scheme (see the module documentation).
#[derive(Clone, Debug)]
pub struct Tables {
    scheme: Scheme,
    symbol_names: String,
    rule_offsets: Vec<u32>,
    rule_symbols: Vec<u8>,
    words: Vec<u8>,
    index: HashMap<Word, u32>,
    mask_offsets: Vec<u32>,
    mask_words: Vec<u32>,
    mask_weights: Vec<f64>,
    exact_weights: Vec<Elem>,
    mask_children: Vec<u32>,
    /// Per word, its limit mask's 2d weights (none for degrees without one).
    limit_weights: Vec<f64>,
    /// Per symbol, its interval length as f64.
    lengths: Vec<f64>,
    surface: Result<Surface, Error>,
}

/// The surface data of a scheme that passes \[G\] §4.2.
#[derive(Clone, Debug)]
struct Surface {
    analysis: SurfaceAnalysis,
    ev: EvCoefficients,
    /// α for valences 3..=[`MAX_TABULATED_VALENCE`].
    alpha: Vec<f64>,
    /// The EV's limit data for the same valences.
    ev_limits: Vec<EvLimit>,
    rings: Vec<[f64; 2]>,
    /// Per tabulated word, kept in step with the masks.
    ring_weights: Vec<f64>,
}

impl Surface {
    fn new(scheme: &Scheme, analysis: SurfaceAnalysis) -> Result<Surface, Error> {
        let ev = analysis.coefficients_f64();
        let alpha = (3..=MAX_TABULATED_VALENCE)
            .map(|n| ev.alpha(n))
            .collect::<Result<_, _>>()
            .map_err(|e| scheme.ls.error(Part::Rules, format!("no α: {e}"), None))?;
        let ev_limits = (3..=MAX_TABULATED_VALENCE)
            .map(|n| EvLimit::new(&ev, n))
            .collect::<Result<_, _>>()
            .map_err(|e| {
                scheme
                    .ls
                    .error(Part::Rules, format!("no EV limit: {e}"), None)
            })?;
        let rings = analysis
            .steps
            .iter()
            .map(|st| [st.ring.0.to_f64(), st.ring.1.to_f64()])
            .collect();
        Ok(Surface {
            analysis,
            ev,
            alpha,
            ev_limits,
            rings,
            ring_weights: Vec::new(),
        })
    }
}

impl Tables {
    /// The tables of every word reachable from the axiom, and the surface data when the scheme
    /// passes \[G\] §4.2 (else the reason, [`Tables::curves_only`]); within the work bound of
    /// [`crate::exact::work`] (the f64 weights are decided exactly, by refining ρ).
    pub fn new(scheme: Scheme) -> Result<Tables, Error> {
        let ls = scheme.ls.clone();
        work::stage(&ls, "the tables", || Ok(Tables::new_unbounded(scheme)))
    }

    fn new_unbounded(scheme: Scheme) -> Tables {
        let surface = ev::analyse(&scheme).and_then(|a| Surface::new(&scheme, a));
        let mut rule_offsets = vec![0u32];
        let mut rule_symbols = Vec::new();
        for r in &scheme.ls.rules {
            rule_symbols.extend_from_slice(r);
            rule_offsets.push(rule_symbols.len() as u32);
        }
        let words: Vec<Word> = scheme.graph.words.iter().map(|w| w.word.clone()).collect();
        let mut t = Tables {
            symbol_names: scheme.ls.symbols.join(" "),
            rule_offsets,
            rule_symbols,
            words: Vec::new(),
            index: HashMap::new(),
            mask_offsets: vec![0],
            mask_words: Vec::new(),
            mask_weights: Vec::new(),
            exact_weights: Vec::new(),
            mask_children: Vec::new(),
            limit_weights: Vec::new(),
            lengths: scheme.lengths.iter().map(Elem::to_f64).collect(),
            surface,
            scheme,
        };
        t.add_words(words);
        t
    }

    /// The exact scheme behind the tables.
    pub fn scheme(&self) -> &Scheme {
        &self.scheme
    }

    /// The curve tables, as the runtime reads them.
    pub fn curve(&self) -> CurveTables<'_> {
        CurveTables {
            name: &self.scheme.ls.name,
            degree: self.scheme.ls.degree,
            symbol_names: &self.symbol_names,
            rule_offsets: &self.rule_offsets,
            rule_symbols: &self.rule_symbols,
            axiom: &self.scheme.ls.axiom,
            words: &self.words,
            mask_offsets: &self.mask_offsets,
            mask_words: &self.mask_words,
            mask_weights: &self.mask_weights,
            mask_children: &self.mask_children,
            limit_weights: &self.limit_weights,
            lengths: &self.lengths,
        }
    }

    /// The surface tables, when the scheme passes \[G\] §4.2.
    pub fn surface(&self) -> Option<SurfaceTables<'_>> {
        let s = self.surface.as_ref().ok()?;
        Some(SurfaceTables {
            sigma: &s.analysis.sigma,
            ring_weights: &s.ring_weights,
            alpha: &s.alpha,
            ev_limits: &s.ev_limits,
            ev: s.ev,
            rings: &s.rings,
            contained_from: s.analysis.contained_from,
        })
    }

    /// The surface analysis (exact), when the scheme passes \[G\] §4.2.
    pub fn surface_analysis(&self) -> Option<&SurfaceAnalysis> {
        self.surface.as_ref().ok().map(|s| &s.analysis)
    }

    /// Why the scheme refines curves only: the condition of \[G\] §4.2 that fails, at its place
    /// in the scheme file; `None` for a surface scheme.
    pub fn curves_only(&self) -> Option<&Error> {
        self.surface.as_ref().err()
    }

    /// The exact weight of mask entry `e` (`mask_weights[e]` is its nearest f64).
    pub fn exact_weight(&self, e: usize) -> &Elem {
        &self.exact_weights[e]
    }

    /// The first step at which tabulated word `i` appears from the axiom, if it does.
    pub fn first_step(&self, i: usize) -> Option<usize> {
        let w = self.curve().word(i).to_vec();
        let g = &self.scheme.graph;
        g.index.get(&w).map(|&j| g.words[j].first_step)
    }

    /// The index of a tabulated word.
    pub fn word_index(&self, w: &[u8]) -> Option<u32> {
        self.index.get(w).copied()
    }

    /// Appends the masks of `start` and of every word reachable from them, exactly (words the
    /// axiom never makes, say from a curve's own labels); known words are skipped. Within the
    /// work bound of [`crate::exact::work`].
    pub fn add_reachable(&mut self, start: Vec<Word>) -> Result<(), Error> {
        let start: Vec<Word> = start
            .into_iter()
            .filter(|w| !self.index.contains_key(w))
            .collect();
        if start.is_empty() {
            return Ok(());
        }
        let ls = self.scheme.ls.clone();
        work::stage(&ls, "the masks of the curve's labels", || {
            let reach = reach_from(&self.scheme.ls, self.scheme.ls.degree + 1, start);
            self.add_words(reach.words.into_iter().map(|w| w.word).collect());
            Ok(())
        })
    }

    /// Tabulates the masks of `words` (closed under refinement with the words already known).
    /// Everything is computed before anything is appended, so that running out of work
    /// ([`Tables::add_reachable`]) leaves the tables as they were.
    fn add_words(&mut self, words: Vec<Word>) {
        let mut index = HashMap::new();
        let mut new = Vec::new();
        for w in words {
            if !self.index.contains_key(&w) && !index.contains_key(&w) {
                index.insert(w.clone(), (self.index.len() + new.len()) as u32);
                new.push(w);
            }
        }
        let (mut mask_words, mut mask_weights, mut exact_weights) = (vec![], vec![], vec![]);
        let (mut mask_offsets, mut mask_children, mut ring_weights) = (vec![], vec![], vec![]);
        let mut limit_weights = Vec::new();
        for w in &new {
            let (ls, lengths) = (&self.scheme.ls, &self.scheme.lengths);
            if let Some(l) = crate::exact::limit::limit_mask(ls, lengths, w) {
                limit_weights.extend(l.position.iter().chain(&l.tangent).map(Elem::to_f64));
            }
            let m = self.scheme.mask_of(w);
            for c in &m.contributions {
                let at = self.index.get(&c.word).or_else(|| index.get(&c.word));
                mask_words.push(*at.expect("reachable words are closed under refinement"));
                mask_weights.push(c.weight.to_f64());
                exact_weights.push(c.weight.clone());
            }
            mask_offsets.push((self.mask_words.len() + mask_words.len()) as u32);
            mask_children.push(m.child.map_or(NO_CHILD, |c| c as u32));
            ring_weights.push(m.child.map_or(0.0, |c| {
                ev::ring_weight(&m.contributions[c].weight).to_f64()
            }));
        }
        for w in &new {
            self.words.extend_from_slice(w);
        }
        self.index.extend(index);
        self.mask_words.extend(mask_words);
        self.mask_weights.extend(mask_weights);
        self.exact_weights.extend(exact_weights);
        self.mask_offsets.extend(mask_offsets);
        self.mask_children.extend(mask_children);
        self.limit_weights.extend(limit_weights);
        if let Ok(s) = &mut self.surface {
            s.ring_weights.extend(ring_weights);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::scheme;

    fn tables(text: &str) -> Tables {
        Tables::new(Scheme::build(scheme::parse("t.toml", text).unwrap()).unwrap()).unwrap()
    }

    /// Every view stays in step with the masks, also after words the axiom never makes.
    fn check(t: &Tables) {
        let c = t.curve();
        let n = c.word_count();
        assert_eq!(c.words.len(), n * (c.degree + 1));
        assert_eq!(c.mask_children.len(), n);
        assert!(c.limit_weights.is_empty() || c.limit_weights.len() == 2 * c.degree * n);
        assert_eq!(
            *c.mask_offsets.last().unwrap() as usize,
            c.mask_weights.len()
        );
        for (e, &w) in c.mask_weights.iter().enumerate() {
            assert_eq!(t.exact_weight(e).to_f64().to_bits(), w.to_bits());
        }
        for i in 0..n {
            let m = t.scheme().mask_of(c.word(i));
            let got: Vec<&[u8]> = c
                .mask_range(i)
                .map(|e| c.word(c.mask_words[e] as usize))
                .collect();
            let want: Vec<&[u8]> = m.contributions.iter().map(|x| &x.word[..]).collect();
            assert_eq!(got, want, "mask {i}");
            assert_eq!(t.word_index(c.word(i)), Some(i as u32));
        }
        if let Some(s) = t.surface() {
            assert_eq!(s.ring_weights.len(), n);
        }
    }

    #[test]
    fn surface_tables_grow_with_the_masks() {
        let mut t = tables("name = \"bt\"\ndegree = 3\naxiom = \"C\"\n[rules]\nL = \"LC\"\nC = \"LCR\"\nR = \"CR\"\n[symmetry]\nL = \"R\"\n");
        assert!(t.curves_only().is_none() && t.surface().is_some());
        check(&t);
        let n = t.curve().word_count();
        assert_eq!(t.first_step(0), Some(0));
        // LLLL: never made from the axiom.
        assert_eq!(t.word_index(&[0; 4]), None);
        t.add_reachable(vec![vec![0; 4]]).unwrap();
        assert!(t.curve().word_count() > n);
        assert_eq!(t.first_step(n), None);
        check(&t);
    }

    #[test]
    fn a_curve_scheme_says_why_it_has_no_surface_tables() {
        let t = tables("name = \"q\"\ndegree = 2\naxiom = \"A\"\n[rules]\nA = \"AB\"\nB = \"A\"\n");
        assert!(t.surface().is_none() && t.surface_analysis().is_none());
        let e = t.curves_only().expect("degree 2");
        assert!(e.message.contains("surfaces need degree 3"), "{e}");
        check(&t);
    }
}
