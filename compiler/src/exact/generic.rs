//! The generic path: run-time tables for any scheme file, with masks computed on demand (exactly)
//! for words the axiom never produces. It shares the driver of `lsubdiv_runtime` with the
//! generated path, and the same nearest-f64 weights, so both give the same bits.

use crate::error::Error;
use crate::exact::codegen::{alpha_table, ring_weights};
use crate::exact::ev::{self, SurfaceAnalysis};
use crate::exact::graph::reach_from;
use crate::exact::lsystem::{Part, Word};
use crate::exact::pipeline::Scheme;
use lsubdiv_runtime::ev::EvCoefficients;
use lsubdiv_runtime::surface::{SurfaceScheme, SurfaceTables};
use lsubdiv_runtime::{Curve, CurveScheme, CurveTables};
use std::collections::HashMap;

/// Owned tables built from a compiled [`Scheme`].
#[derive(Clone, Debug)]
pub struct GenericScheme {
    scheme: Scheme,
    symbol_names: String,
    rule_offsets: Vec<u32>,
    rule_symbols: Vec<u8>,
    words: Vec<u8>,
    index: HashMap<Word, u32>,
    mask_offsets: Vec<u32>,
    mask_words: Vec<u32>,
    mask_weights: Vec<f64>,
    mask_children: Vec<u32>,
}

impl GenericScheme {
    /// Tables of every word reachable from the axiom.
    pub fn new(scheme: Scheme) -> GenericScheme {
        let mut rule_offsets = vec![0u32];
        let mut rule_symbols = Vec::new();
        for r in &scheme.ls.rules {
            rule_symbols.extend_from_slice(r);
            rule_offsets.push(rule_symbols.len() as u32);
        }
        let mut g = GenericScheme {
            symbol_names: scheme.ls.symbols.join(" "),
            rule_offsets,
            rule_symbols,
            words: Vec::new(),
            index: HashMap::new(),
            mask_offsets: vec![0],
            mask_words: Vec::new(),
            mask_weights: Vec::new(),
            mask_children: Vec::new(),
            scheme,
        };
        let words: Vec<Word> = g
            .scheme
            .graph
            .words
            .iter()
            .map(|w| w.word.clone())
            .collect();
        g.add_words(words);
        g
    }

    /// The exact scheme behind the tables.
    pub fn scheme(&self) -> &Scheme {
        &self.scheme
    }

    /// Adds the masks of the curve's words and of every word reachable from them.
    pub fn prepare<const D: usize>(&mut self, curve: &Curve<D>) {
        let d = self.scheme.ls.degree;
        let n = self.scheme.ls.n();
        let start: Vec<Word> = (0..curve.points.len())
            .map(|k| curve.word(k, d))
            .filter(|w| w.iter().all(|&s| (s as usize) < n) && !self.index.contains_key(w))
            .collect();
        if start.is_empty() || curve.check(&self.tables()).is_err() {
            return;
        }
        let reach = reach_from(&self.scheme.ls, d + 1, start);
        self.add_words(reach.words.into_iter().map(|w| w.word).collect());
    }

    fn add_words(&mut self, words: Vec<Word>) {
        let new: Vec<Word> = words
            .into_iter()
            .filter(|w| !self.index.contains_key(w))
            .collect();
        for w in &new {
            self.index.insert(w.clone(), self.index.len() as u32);
            self.words.extend_from_slice(w);
        }
        for w in &new {
            let m = self.scheme.mask_of(w);
            for c in &m.contributions {
                self.mask_words.push(self.index[&c.word]);
                self.mask_weights.push(c.weight.to_f64());
            }
            self.mask_offsets.push(self.mask_words.len() as u32);
            self.mask_children
                .push(m.child.map_or(u32::MAX, |c| c as u32));
        }
    }
}

impl CurveScheme for GenericScheme {
    fn tables(&self) -> CurveTables<'_> {
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
        }
    }
}

/// The generic path for surfaces: the generic tables plus the surface data derived at run time.
#[derive(Clone, Debug)]
pub struct GenericSurface {
    generic: GenericScheme,
    analysis: SurfaceAnalysis,
    ring_weights: Vec<f64>,
    alpha: Vec<f64>,
    ev: EvCoefficients,
    rings: Vec<[f64; 2]>,
}

impl GenericSurface {
    /// Checks the surface conditions (\[G\] §4) and prepares the tables.
    pub fn new(scheme: Scheme) -> Result<GenericSurface, Error> {
        let analysis = ev::analyse(&scheme)?;
        let alpha = alpha_table(&analysis).map_err(|e| scheme.ls.error(Part::Rules, e, None))?;
        let ring_weights = ring_weights(&scheme);
        let ev = analysis.coefficients_f64();
        let rings = analysis
            .steps
            .iter()
            .map(|st| [st.ring.0.to_f64(), st.ring.1.to_f64()])
            .collect();
        Ok(GenericSurface {
            rings,
            generic: GenericScheme::new(scheme),
            analysis,
            ring_weights,
            alpha,
            ev,
        })
    }

    /// The surface analysis.
    pub fn analysis(&self) -> &SurfaceAnalysis {
        &self.analysis
    }

    /// The exact scheme.
    pub fn scheme(&self) -> &Scheme {
        self.generic.scheme()
    }
}

impl CurveScheme for GenericSurface {
    fn tables(&self) -> CurveTables<'_> {
        self.generic.tables()
    }
}

impl SurfaceScheme for GenericSurface {
    fn surface(&self) -> SurfaceTables<'_> {
        SurfaceTables {
            sigma: &self.analysis.sigma,
            ring_weights: &self.ring_weights,
            alpha: &self.alpha,
            ev: self.ev,
            rings: &self.rings,
            contained_from: self.analysis.contained_from,
        }
    }
}
