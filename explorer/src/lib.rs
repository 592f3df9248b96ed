//! The scheme explorer (\[G\] §5.2, Appendix B): the L-systems of the four families of §5.2
//! computed exactly, and a search over symmetric rule sets for the Pareto front of
//! (ratio ρ, number of masks).
//!
//! Counting rule (\[G\] §5.2): the masks of a degree-d scheme are the (d+1)-words in F_s for some
//! s, F_0 being the (d+1)-factors of the axiom repeated ([`lsubdiv_compiler::exact::graph`]); a word and its mirror
//! σ̄(w) count once ("we count as one each pair of symmetric words"). `words` is the raw count.
//!
//! # Quick start
//!
//! The family of eq. (44), L→LC, C→w, R→CR, holds the Binary-Ternary scheme (w = LCR, ρ = 1 + √2):
//!
//! ```
//! use lsubdiv_explorer::{enumerate, Enumeration, Family};
//!
//! let opts = Enumeration { max_word_len: 3, unconstrained: false, include_integer: false, degree: 3 };
//! let rows = enumerate(Family::Lcr, opts)?;
//! let bt = rows.iter().find(|r| r.pi_c == "LCR").expect("Binary-Ternary is in the family");
//! assert_eq!(bt.rho_text, "1 + √2");
//! assert!(bt.valid.is_ok() && bt.surface.is_ok()); // a surface scheme ([G] §4.2)
//! # Ok::<(), lsubdiv_compiler::Error>(())
//! ```

use lsubdiv_compiler::exact::ev;
use lsubdiv_compiler::exact::field::FieldRef;
use lsubdiv_compiler::exact::graph::reach;
use lsubdiv_compiler::exact::lsystem::{LSystem, Source, Sym, Word};
use lsubdiv_compiler::exact::pipeline::Scheme;
use lsubdiv_compiler::exact::symmetry::involutions;
use lsubdiv_compiler::exact::validity::analyse;
use lsubdiv_compiler::Error;
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

/// Every word of 1 ..= k letters over `letters`, shortest first.
fn words_up_to(letters: &[Sym], k: usize) -> Vec<Word> {
    let mut all = Vec::new();
    let mut layer: Vec<Word> = vec![Vec::new()];
    for _ in 0..k {
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
        all.extend(layer.iter().cloned());
    }
    all
}

/// The number of masks: reachable words with w and σ̄(w) counted once (every word alone
/// without σ).
fn mask_count(
    ls: &LSystem,
    graph: &lsubdiv_compiler::exact::graph::Reach,
    sigma: Option<&[Sym]>,
) -> usize {
    match sigma {
        Some(s) => graph
            .words
            .iter()
            .map(|w| w.word.clone().min(ls.mirror(s, &w.word)))
            .collect::<BTreeSet<Word>>()
            .len(),
        None => graph.words.len(),
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
    let masks = mask_count(&ls, &graph, family_sigma.or(sigma.as_deref()));
    let surface = match (&valid, &sigma) {
        (Err(r), _) => Err(format!("invalid L-system: {r}")),
        (_, None) => Err("not symmetric under any involution ([G] Prop. 4.2)".into()),
        (Ok(()), Some(s)) => {
            ls.symmetry = Some(s.clone());
            Scheme::build(ls.clone())
                .and_then(|scheme| ev::analyse(&scheme))
                .map(|a| (a.stationary_from, a.contained_from))
                .map_err(|e| e.message)
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
    let candidates: Vec<Word> = words_up_to(&letters, opts.max_word_len)
        .into_iter()
        .filter(|w| opts.unconstrained || family.allows(w))
        .collect();
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

/// What to search (\[G\] §5 beyond its families): symmetric L-systems on `symbols` letters with
/// a one-letter symmetric axiom and rules of 1 ..= `max_word_len` letters (with `asymmetric`,
/// also every rule set with a one-letter axiom).
#[derive(Clone, Debug)]
pub struct Search {
    /// Alphabet size, 2 ..= 6.
    pub symbols: usize,
    /// Longest rule, 1 ..= 4.
    pub max_word_len: usize,
    /// ρ bounds (exact rationals), inclusive.
    pub rho_min: Option<num_rational::BigRational>,
    /// Upper ρ bound.
    pub rho_max: Option<num_rational::BigRational>,
    /// Most masks (mirror pairs once).
    pub max_masks: Option<usize>,
    /// Keep only systems that pass \[G\] §4.2 (stationary, contained): surface schemes.
    pub require_surface: bool,
    /// Keep integer ratios.
    pub include_integer: bool,
    /// Also examine rule sets without an involution (curves; they cannot drive surfaces).
    pub asymmetric: bool,
    /// Most rule sets examined: the whole space when it is smaller, else a seeded sample.
    pub limit: u64,
    /// Spline degree.
    pub degree: usize,
}

/// Outcome of a search.
#[derive(Debug)]
pub struct Found {
    /// The Pareto front of (ρ, masks), by increasing ρ.
    pub front: Vec<Row>,
    /// Rule sets in the space, and how many were examined (all, or a sample).
    pub space: u128,
    /// Rule sets examined.
    pub examined: u64,
    /// Distinct systems (up to renaming) that passed every filter before the front.
    pub candidates: usize,
}

/// Letter names: fixed symbols first (the axiom S), then twin pairs.
const FIXED: [&str; 6] = ["S", "C", "E", "G", "H", "K"];
const PAIRS: [(&str, &str); 3] = [("L", "R"), ("A", "B"), ("D", "F")];

/// One shape of involution: `fixed` symmetric letters (≥ 1, the first is the axiom) and `pairs`
/// twin pairs; the choices for each rule of a fixed letter (symmetric words) and of the first of
/// each pair (any word; its twin's rule is the mirror). A `free` shape has no involution: every
/// rule is any word.
struct Shape {
    symbols: Vec<String>,
    sigma: Vec<Sym>,
    free: bool,
    fixed: usize,
    pairs: usize,
    symmetric_words: Vec<Word>,
    any_words: Vec<Word>,
}

impl Shape {
    fn new(fixed: usize, pairs: usize, k: usize) -> Shape {
        let mut symbols: Vec<String> = FIXED[..fixed].iter().map(|s| s.to_string()).collect();
        let mut sigma: Vec<Sym> = (0..fixed as Sym).collect();
        for (i, (a, b)) in PAIRS[..pairs].iter().enumerate() {
            symbols.push(a.to_string());
            symbols.push(b.to_string());
            let at = (fixed + 2 * i) as Sym;
            sigma.extend([at + 1, at]);
        }
        let letters: Vec<Sym> = (0..symbols.len() as Sym).collect();
        let any_words = words_up_to(&letters, k);
        let mirror = |w: &Word| -> Word { w.iter().rev().map(|&s| sigma[s as usize]).collect() };
        let symmetric_words = any_words
            .iter()
            .filter(|w| mirror(w) == **w)
            .cloned()
            .collect();
        Shape {
            symbols,
            sigma,
            free: false,
            fixed,
            pairs,
            symmetric_words,
            any_words,
        }
    }

    /// The shape without involution on n letters (S, A, B, …; S the axiom).
    fn free(n: usize, k: usize) -> Shape {
        let mut shape = Shape::new(n, 0, k);
        shape.free = true;
        shape.symbols = ["S", "A", "B", "C", "D", "E"][..n]
            .iter()
            .map(|s| s.to_string())
            .collect();
        shape
    }

    /// The words a fixed (or, in a free shape, any) letter's rule is chosen from.
    fn fixed_words(&self) -> &[Word] {
        if self.free {
            &self.any_words
        } else {
            &self.symmetric_words
        }
    }

    /// Number of rule sets of this shape.
    fn size(&self) -> u128 {
        (self.fixed_words().len() as u128).pow(self.fixed as u32)
            * (self.any_words.len() as u128).pow(self.pairs as u32)
    }

    /// The i-th rule set (mixed radix over the rule choices).
    fn system(&self, mut i: u128, degree: usize) -> LSystem {
        let n = self.symbols.len();
        let mut rules = vec![Word::new(); n];
        for rule in rules.iter_mut().take(self.fixed) {
            let c = self.fixed_words().len() as u128;
            *rule = self.fixed_words()[(i % c) as usize].clone();
            i /= c;
        }
        for p in 0..self.pairs {
            let c = self.any_words.len() as u128;
            let w = self.any_words[(i % c) as usize].clone();
            i /= c;
            let a = self.fixed + 2 * p;
            rules[a + 1] = w.iter().rev().map(|&s| self.sigma[s as usize]).collect();
            rules[a] = w;
        }
        LSystem {
            name: String::new(),
            degree,
            symbols: self.symbols.clone(),
            rules,
            axiom: vec![0],
            symmetry: (!self.free).then(|| self.sigma.clone()),
            lengths: None,
            source: Source::default(),
        }
    }
}

/// Every symbol is reachable from the axiom (otherwise the system is a smaller one).
fn all_reachable(ls: &LSystem) -> bool {
    let mut seen = vec![false; ls.n()];
    let mut stack = ls.axiom.clone();
    while let Some(a) = stack.pop() {
        if !std::mem::replace(&mut seen[a as usize], true) {
            stack.extend(ls.rules[a as usize].iter().copied());
        }
    }
    seen.into_iter().all(|s| s)
}

/// A form equal for systems equal up to renaming: symbols renumbered in order of first
/// appearance, reading the axiom and then each symbol's rule in that order.
fn canonical(ls: &LSystem) -> Vec<Word> {
    let mut order: Vec<Sym> = Vec::new();
    let mut new = vec![Sym::MAX; ls.n()];
    let mut visit = |a: Sym, order: &mut Vec<Sym>| {
        if new[a as usize] == Sym::MAX {
            new[a as usize] = order.len() as Sym;
            order.push(a);
        }
    };
    for &a in &ls.axiom {
        visit(a, &mut order);
    }
    let mut i = 0;
    while i < order.len() {
        for &b in &ls.rules[order[i] as usize] {
            visit(b, &mut order);
        }
        i += 1;
    }
    let mut key: Vec<Word> = vec![ls.axiom.iter().map(|&a| new[a as usize]).collect()];
    key.extend(order.iter().map(|&a| {
        ls.rules[a as usize]
            .iter()
            .map(|&b| new[b as usize])
            .collect()
    }));
    key
}

/// The rules written `A→w` and joined by spaces.
fn rules_text(ls: &LSystem) -> String {
    (0..ls.n())
        .map(|a| format!("{}→{}", ls.symbols[a], ls.word_str(&ls.rules[a])))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Searches the symmetric L-systems of `opts` and returns the Pareto front of (ρ, masks): no
/// listed system has another with ρ ≤ and fewer masks, or ρ < and as few. `progress` is called
/// with the number of rule sets examined so far and the number to examine.
pub fn search(opts: &Search, progress: &(dyn Fn(u64, u64) + Sync)) -> Result<Found, Error> {
    let n = opts.symbols;
    let mut shapes: Vec<Shape> = (0..=n / 2)
        .filter(|&p| n - 2 * p >= 1)
        .map(|p| Shape::new(n - 2 * p, p, opts.max_word_len))
        .collect();
    if opts.asymmetric {
        shapes.push(Shape::free(n, opts.max_word_len));
    }
    let space: u128 = shapes.iter().map(Shape::size).sum();
    let examined = u64::try_from(space.min(u128::from(opts.limit))).unwrap_or(opts.limit);
    // Index j of the examined rule sets: all of them, or a sample spread evenly over the space
    // with a fixed multiplicative scramble (deterministic: the same run gives the same front).
    let pick = |j: u64| -> u128 {
        if space <= u128::from(opts.limit) {
            u128::from(j)
        } else {
            (u128::from(j) * 0x9E37_79B9_7F4A_7C15u128 + 0x2545_F491) % space
        }
    };
    let done = std::sync::atomic::AtomicU64::new(0);
    // Phase 1 (cheap, combinatorial): reachability, canonical form, mask count.
    let mut survivors: Vec<(Vec<Word>, LSystem, usize)> = (0..examined)
        .into_par_iter()
        .filter_map(|j| {
            let c = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            if c & 4095 == 0 {
                progress(c, examined);
            }
            let mut i = pick(j);
            let shape = shapes.iter().find(|s| {
                let fits = i < s.size();
                if !fits {
                    i -= s.size();
                }
                fits
            })?;
            let ls = shape.system(i, opts.degree);
            if !all_reachable(&ls) {
                return None;
            }
            let g = reach(&ls, ls.degree + 1);
            // Pair mirror words with the shape's σ, or with the system's own symmetry if a
            // free rule set happens to have one (as `describe` does).
            let sigma = ls
                .symmetry
                .clone()
                .or_else(|| involutions(&ls).into_iter().next());
            let masks = mask_count(&ls, &g, sigma.as_deref());
            if opts.max_masks.is_some_and(|m| masks > m) {
                return None;
            }
            Some((canonical(&ls), ls, masks))
        })
        .collect();
    progress(examined, examined);
    survivors.sort_by(|a, b| a.0.cmp(&b.0));
    survivors.dedup_by(|a, b| a.0 == b.0);
    // Phase 2 (exact): ρ, validity, bounds.
    let exact: Vec<(LSystem, usize, FieldRef)> = survivors
        .into_par_iter()
        .filter_map(|(_, ls, masks)| {
            let a = analyse(&ls).ok()?;
            let rho = &a.rho;
            let integer = rho
                .as_rational()
                .is_some_and(num_rational::BigRational::is_integer);
            let bound = |r: &num_rational::BigRational| {
                lsubdiv_compiler::exact::field::Elem::rational(&a.field, r.clone())
            };
            let below = matches!(&opts.rho_min, Some(m) if rho.cmp_exact(&bound(m)).is_lt());
            let above = matches!(&opts.rho_max, Some(m) if rho.cmp_exact(&bound(m)).is_gt());
            let keep = a.valid && (opts.include_integer || !integer) && !below && !above;
            keep.then(|| (ls, masks, a.field.clone()))
        })
        .collect();
    let candidates = exact.len();
    // Phase 3: sweep by increasing ρ (exact), then masks; a system is on the front when it has
    // fewer masks than every system before it (checking the surface verdict only there).
    let mut order: Vec<usize> = (0..exact.len()).collect();
    order.sort_by(|&i, &j| {
        exact[i]
            .2
            .cmp_generator(&exact[j].2)
            .then(exact[i].1.cmp(&exact[j].1))
    });
    let mut front: Vec<Row> = Vec::new();
    for i in order {
        let (ls, masks, _) = &exact[i];
        if front.last().is_some_and(|r| r.masks <= *masks) {
            continue;
        }
        let mut ls = ls.clone();
        ls.name = format!("search-{}", front.len() + 1);
        let text = rules_text(&ls);
        // Count with the σ the sweep used (a system may have several, Remark 4.5).
        let sigma = ls.symmetry.clone();
        let row = describe("search", ls, text, Vec::new(), sigma.as_deref())?;
        if opts.require_surface && row.surface.is_err() {
            continue;
        }
        front.push(row);
    }
    Ok(Found {
        front,
        space,
        examined,
        candidates,
    })
}

/// A scheme file for the row's L-system, accepted by the rest of the toolkit.
pub fn scheme_toml(row: &Row) -> String {
    let ls = LSystem {
        symmetry: row.sigma.clone(),
        ..row.ls.clone()
    };
    format!(
        "# Found by `lsubdiv {}`: rho ~ {:.6} (minimal polynomial {}, constant term first), {} masks.\n{}",
        if row.family == "search" { "search" } else { "enumerate" },
        row.rho_f64(),
        row.minimal_polynomial().join(", "),
        row.masks,
        lsubdiv_compiler::exact::scheme::to_toml(&ls)
    )
}
