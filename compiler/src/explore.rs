//! The scheme explorer (\[G\] §5.2, Appendix B): the L-systems of the four families of §5.2
//! computed exactly, and a search over symmetric rule sets for the Pareto front of
//! (ratio ρ, number of masks).
//!
//! Counting rule (\[G\] §5.2): the masks of a degree-d scheme are the (d+1)-words in F_s for some
//! s, F_0 being the (d+1)-factors of the axiom repeated ([`crate::graph`]); a word and its mirror
//! σ̄(w) count once ("we count as one each pair of symmetric words"). `words` is the raw count.

use crate::error::Error;
use crate::ev;
use crate::field::FieldRef;
use crate::graph::reach;
use crate::lsystem::{LSystem, Source, Sym, Word};
use crate::pipeline::Scheme;
use crate::symmetry::involutions;
use crate::validity::analyse;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BTreeSet;

/// One L-system described as in \[G\] Appendix B, plus the verdicts of \[N\] §3 and \[G\] §4.
#[derive(Clone, Debug)]
pub struct Row {
    /// Family name (`lcr`, `slcr`, `lcdr`, `slcdr`) or `search`.
    pub family: String,
    /// The L-system.
    pub ls: LSystem,
    /// π(C) for the families; the rules, `A→w` joined by spaces, for search results.
    pub pi_c: String,
    /// M\[C; Σ\] for the families (empty for search results).
    pub m_row: Vec<i64>,
    /// Q(ρ): ρ exactly, with its minimal polynomial.
    pub field: FieldRef,
    /// ρ in radical or polynomial form.
    pub rho_text: String,
    /// ρ is an integer (Remark 5.5 excludes these by default).
    pub integer: bool,
    /// \[N\] Definition 3.1 holds; else why not.
    pub valid: Result<(), String>,
    /// The involution that makes the system symmetric (\[G\] Prop. 4.2), when there is one.
    pub sigma: Option<Vec<Sym>>,
    /// Masks, mirror pairs counted once.
    pub masks: usize,
    /// Reachable (d+1)-words.
    pub words: usize,
    /// \[G\] §4.2: the steps from which the EV configuration is stationary and the masks are
    /// contained, or why the system cannot drive a surface.
    pub surface: Result<(usize, usize), String>,
}

impl Row {
    /// ρ as f64 (display only).
    pub fn rho_f64(&self) -> f64 {
        self.field.rho().to_f64()
    }

    /// The minimal polynomial of ρ, primitive integers, constant term first.
    pub fn minimal_polynomial(&self) -> Vec<String> {
        self.field
            .minpoly_integer()
            .iter()
            .map(ToString::to_string)
            .collect()
    }

    /// σ written as its twin pairs and fixed symbols, e.g. `L↔R C↔D S`.
    pub fn involution(&self) -> Option<String> {
        let s = self.sigma.as_ref()?;
        let names = &self.ls.symbols;
        let parts: Vec<String> = (0..s.len())
            .filter(|&a| s[a] as usize >= a)
            .map(|a| match s[a] as usize {
                b if b == a => names[a].clone(),
                b => format!("{}↔{}", names[a], names[b]),
            })
            .collect();
        Some(parts.join(" "))
    }

    /// The paper's order: by ρ (exactly), then by number of masks, then by π(C).
    pub fn cmp_paper(&self, o: &Row) -> Ordering {
        self.field
            .cmp_generator(&o.field)
            .then(self.masks.cmp(&o.masks))
            .then_with(|| self.pi_c.cmp(&o.pi_c))
    }
}

/// Describes one L-system. `family_sigma` (a family's σ, \[G\] §5.2) pairs mirror words for the
/// count even when the axiom is not symmetric (the masks of w and σ̄(w) are reverses of each
/// other as soon as twin lengths are equal); without it the system's own symmetry pairs them,
/// and with none every word counts alone.
pub fn describe(
    family: &str,
    mut ls: LSystem,
    pi_c: String,
    m_row: Vec<i64>,
    family_sigma: Option<&[Sym]>,
) -> Result<Row, Error> {
    let analysis = analyse(&ls)?;
    let field = analysis.field.clone();
    let rho = analysis.rho.clone();
    let integer = rho
        .as_rational()
        .is_some_and(num_rational::BigRational::is_integer);
    let valid = match (&analysis.valid, &analysis.reason) {
        (true, _) => Ok(()),
        (false, r) => Err(r.clone().unwrap_or_else(|| "invalid".into())),
    };
    let all = involutions(&ls);
    let sigma = family_sigma
        .filter(|p| all.iter().any(|s| s == p))
        .map(<[Sym]>::to_vec)
        .or_else(|| all.first().cloned());
    let graph = reach(&ls, ls.degree + 1);
    let words = graph.words.len();
    let pairing = family_sigma.map(<[Sym]>::to_vec).or_else(|| sigma.clone());
    let masks = match &pairing {
        Some(s) => graph
            .words
            .iter()
            .map(|w| w.word.clone().min(ls.mirror(s, &w.word)))
            .collect::<BTreeSet<Word>>()
            .len(),
        None => words,
    };
    let surface = match (&valid, &sigma) {
        (Err(r), _) => Err(format!("invalid L-system: {r}")),
        (_, None) => Err("not symmetric under any involution ([G] Prop. 4.2)".into()),
        (Ok(()), Some(s)) => {
            ls.symmetry = Some(s.clone());
            Scheme::build(ls.clone())
                .and_then(|scheme| ev::analyse(&scheme))
                .map(|a| (a.stationary_from, a.contained_from))
                .map_err(|e| e.message())
        }
    };
    Ok(Row {
        family: family.into(),
        rho_text: rho.to_string(),
        ls,
        pi_c,
        m_row,
        field,
        integer,
        valid,
        sigma,
        masks,
        words,
        surface,
    })
}

/// The four families of \[G\] §5.2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Eq. (44): {L, C, R}, axiom C; L→LC, C→w, R→CR; w symmetric, from L to R.
    Lcr,
    /// Eq. (45): {S, L, C, R}, axiom S; S→LR, L→LC, C→w, R→CR; w symmetric.
    Slcr,
    /// Eq. (46): {L, C, D, R}, axiom C; L→LC, C→w, D→σ̄(w), R→DR; w from L to R.
    Lcdr,
    /// Eq. (47): {S, L, C, D, R}, axiom S; S→LR, L→LC, C→w, D→σ̄(w), R→DR.
    Slcdr,
}

impl Family {
    /// Every family, in the paper's order.
    pub const ALL: [Family; 4] = [Family::Lcr, Family::Slcr, Family::Lcdr, Family::Slcdr];

    /// The family's command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Lcr => "lcr",
            Family::Slcr => "slcr",
            Family::Lcdr => "lcdr",
            Family::Slcdr => "slcdr",
        }
    }

    /// Parses a family name.
    pub fn parse(name: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The alphabet, in the column order of the paper's M\[C; Σ\].
    fn symbols(self) -> &'static [&'static str] {
        match self {
            Family::Lcr => &["L", "C", "R"],
            Family::Slcr => &["S", "L", "C", "R"],
            Family::Lcdr => &["L", "C", "D", "R"],
            Family::Slcdr => &["S", "L", "C", "D", "R"],
        }
    }

    fn index(self, name: &str) -> Sym {
        self.symbols()
            .iter()
            .position(|s| *s == name)
            .expect("family symbol") as Sym
    }

    /// The family's involution: L↔R, and C↔D when D exists (S and C fixed otherwise).
    fn sigma(self) -> Vec<Sym> {
        let twin = |s: &'static str| match s {
            "L" => "R",
            "R" => "L",
            "C" if self.has_d() => "D",
            "D" => "C",
            other => other,
        };
        self.symbols().iter().map(|s| self.index(twin(s))).collect()
    }

    fn has_d(self) -> bool {
        matches!(self, Family::Lcdr | Family::Slcdr)
    }

    /// The letters w is written with: every symbol but S (`unconstrained`: every symbol).
    fn letters(self, unconstrained: bool) -> Vec<Sym> {
        (0..self.symbols().len() as Sym)
            .filter(|&s| unconstrained || self.symbols()[s as usize] != "S")
            .collect()
    }

    /// The paper's constraints on w: symmetric for (44)–(45), from L to R for (44) and (46).
    fn allows(self, w: &[Sym]) -> bool {
        let sigma = self.sigma();
        let mirror: Word = w.iter().rev().map(|&s| sigma[s as usize]).collect();
        let symmetric = mirror == w;
        let l_to_r = w.first() == Some(&self.index("L")) && w.last() == Some(&self.index("R"));
        match self {
            Family::Lcr => symmetric && l_to_r,
            Family::Slcr => symmetric,
            Family::Lcdr => l_to_r,
            Family::Slcdr => true,
        }
    }

    /// The L-system with π(C) = w.
    pub fn system(self, w: &[Sym], degree: usize) -> LSystem {
        let sigma = self.sigma();
        let sym = |s: &str| self.index(s);
        let word = |text: &str| -> Word { text.chars().map(|c| sym(&c.to_string())).collect() };
        let rules = self
            .symbols()
            .iter()
            .map(|&s| match s {
                "S" => word("LR"),
                "L" => word("LC"),
                "C" => w.to_vec(),
                "D" => w.iter().rev().map(|&a| sigma[a as usize]).collect(),
                _ if self.has_d() => word("DR"),
                _ => word("CR"),
            })
            .collect();
        let axiom = if self.symbols().contains(&"S") {
            "S"
        } else {
            "C"
        };
        LSystem {
            name: format!("{}-{}", self.name(), self.word_text(w).to_lowercase()),
            degree,
            symbols: self.symbols().iter().map(|s| s.to_string()).collect(),
            rules,
            axiom: vec![sym(axiom)],
            symmetry: None,
            lengths: None,
            source: Source::default(),
        }
    }

    fn word_text(self, w: &[Sym]) -> String {
        w.iter().map(|&s| self.symbols()[s as usize]).collect()
    }
}

/// What to enumerate.
#[derive(Clone, Copy, Debug)]
pub struct Enumeration {
    /// Longest π(C).
    pub max_word_len: usize,
    /// Lift the paper's constraints on w (symmetry, first/last letter; S allowed in w).
    pub unconstrained: bool,
    /// Keep integer ratios (Remark 5.5 leaves them out).
    pub include_integer: bool,
    /// Spline degree (the paper's lists use 3).
    pub degree: usize,
}

impl Default for Enumeration {
    fn default() -> Self {
        Enumeration {
            max_word_len: 3,
            unconstrained: false,
            include_integer: false,
            degree: 3,
        }
    }
}

/// Every L-system of `family` with |π(C)| ≤ K, described and sorted as in Appendix B.
pub fn enumerate(family: Family, opts: Enumeration) -> Result<Vec<Row>, Error> {
    let letters = family.letters(opts.unconstrained);
    let mut candidates: Vec<Word> = Vec::new();
    let mut layer: Vec<Word> = vec![Vec::new()];
    for _ in 0..opts.max_word_len {
        layer = layer
            .iter()
            .flat_map(|w| {
                letters.iter().map(move |&a| {
                    let mut v = w.clone();
                    v.push(a);
                    v
                })
            })
            .collect();
        candidates.extend(
            layer
                .iter()
                .filter(|w| opts.unconstrained || family.allows(w))
                .cloned(),
        );
    }
    let sigma = family.sigma();
    let rows: Vec<Result<Row, Error>> = candidates
        .par_iter()
        .map(|w| {
            let ls = family.system(w, opts.degree);
            let c = family.index("C") as usize;
            let m_row = ls.matrix()[c].clone();
            describe(family.name(), ls, family.word_text(w), m_row, Some(&sigma))
        })
        .collect();
    let mut rows: Vec<Row> = rows
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .filter(|r| opts.include_integer || !r.integer)
        .collect();
    rows.sort_by(Row::cmp_paper);
    Ok(rows)
}
