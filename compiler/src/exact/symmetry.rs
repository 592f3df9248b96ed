//! Symmetric L-systems (\[G\] §4.1): involutions σ with π(σ(A)) = σ̄(π(A)) for every symbol and a
//! symmetric axiom (Proposition 4.2).

use crate::exact::lsystem::{LSystem, Part, Sym};
use crate::Error;

/// True when σ makes the L-system symmetric (Proposition 4.2).
pub fn is_symmetry(ls: &LSystem, sigma: &[Sym]) -> bool {
    check_symmetry(ls, sigma).is_ok()
}

/// \[G\] Proposition 4.2: the axiom is symmetric and π(σ(A)) = σ̄(π(A)) for every symbol.
pub fn check_symmetry(ls: &LSystem, sigma: &[Sym]) -> Result<(), Error> {
    if ls.mirror(sigma, &ls.axiom) != ls.axiom {
        return Err(ls.error(
            Part::Symmetry,
            format!(
                "the axiom {} is not symmetric under the declared σ ([G] Definition 4.1): its mirror is {}",
                ls.word_str(&ls.axiom),
                ls.word_str(&ls.mirror(sigma, &ls.axiom))
            ),
            Some("the axiom must read the same backwards with every symbol replaced by its twin, e.g. a symbol that `[symmetry]` leaves fixed".into()),
        ));
    }
    for a in 0..ls.n() {
        let lhs = &ls.rules[sigma[a] as usize];
        let rhs = ls.mirror(sigma, &ls.rules[a]);
        if *lhs != rhs {
            return Err(ls.error(
                Part::Symmetry,
                format!(
                    "the declared σ is not a symmetry ([G] eq. (14)): π(σ({})) = {} but σ̄(π({})) = {}",
                    ls.symbols[a],
                    ls.word_str(lhs),
                    ls.symbols[a],
                    ls.word_str(&rhs)
                ),
                Some(format!(
                    "the rule of `{}` must be the rule of `{}` read backwards with twins swapped: fix one of the two rules or the pairs in `[symmetry]`",
                    ls.symbols[sigma[a] as usize], ls.symbols[a]
                )),
            ));
        }
    }
    Ok(())
}

/// At most this many involutions are listed by [`involutions`]: Remark 4.5's systems have one or
/// two, but symbols with interchangeable rules (say every Xᵢ → A) give exponentially many.
pub const MAX_INVOLUTIONS: usize = 1000;

/// Every involution σ of the alphabet that makes the L-system symmetric (Remark 4.5: there may be
/// several), in a canonical order (lexicographic on σ as a table); the first
/// [`MAX_INVOLUTIONS`] of that order when there are more.
pub fn involutions(ls: &LSystem) -> Vec<Vec<Sym>> {
    let n = ls.n();
    let mut out = Vec::new();
    let mut sigma: Vec<Option<Sym>> = vec![None; n];
    // The axiom is a σ-palindrome: σ(ω_{k−1−i}) = ω_i.
    let w = &ls.axiom;
    let forced = (0..w.len()).map(|i| (w[w.len() - 1 - i] as usize, w[i] as usize));
    if assign(ls, &mut sigma, forced) {
        search(ls, &sigma, MAX_INVOLUTIONS, &is_symmetry, &mut out);
    }
    out
}

/// σ̄ maps rewriting to rewriting: π(σ(A)) = σ̄(π(A)) for every symbol (\[G\] eq. (14)), whatever
/// the axiom. What reflecting a curve across an interpolated end needs (`lsubdiv_runtime::ends`).
pub fn mirrors_rules(ls: &LSystem, sigma: &[Sym]) -> bool {
    (0..ls.n()).all(|a| ls.rules[sigma[a] as usize] == ls.mirror(sigma, &ls.rules[a]))
}

/// A mirror of the rules ([`mirrors_rules`]): the declared σ when it is one, else the first
/// involution in the canonical order that is (the identity when every rule is a palindrome).
pub fn rule_mirror(ls: &LSystem) -> Option<Vec<Sym>> {
    if let Some(s) = ls.symmetry.as_ref().filter(|s| mirrors_rules(ls, s)) {
        return Some(s.clone());
    }
    let mut out = Vec::new();
    search(ls, &vec![None; ls.n()], 1, &mirrors_rules, &mut out);
    out.pop()
}

/// Sets σ(x) = y and σ(y) = x for each given pair and everything [G] eq. (14) then forces:
/// π(y) = σ̄(π(x)), i.e. σ(π(x)_{k−1−i}) = π(y)_i. False on a contradiction (σ left partly set).
fn assign(
    ls: &LSystem,
    sigma: &mut [Option<Sym>],
    pairs: impl IntoIterator<Item = (usize, usize)>,
) -> bool {
    let mut queue: Vec<(usize, usize)> = pairs.into_iter().collect();
    while let Some((x, y)) = queue.pop() {
        for (p, q) in [(x, y), (y, x)] {
            match sigma[p] {
                Some(v) if v as usize != q => return false,
                Some(_) => {}
                None => {
                    sigma[p] = Some(q as Sym);
                    let (rp, rq) = (&ls.rules[p], &ls.rules[q]);
                    if rp.len() != rq.len() {
                        return false;
                    }
                    let k = rp.len();
                    queue.extend((0..k).map(|i| (rp[k - 1 - i] as usize, rq[i] as usize)));
                }
            }
        }
    }
    true
}

/// Backtracking over involutions in lexicographic order: the first unassigned symbol is fixed or
/// paired with a later unassigned one, and the constraints this forces are propagated
/// ([`assign`]), so a choice fixes σ on everything its rules reach and dead branches end early.
/// Collects up to `most` complete ones that `accept` takes.
fn search(
    ls: &LSystem,
    sigma: &[Option<Sym>],
    most: usize,
    accept: &dyn Fn(&LSystem, &[Sym]) -> bool,
    out: &mut Vec<Vec<Sym>>,
) {
    if out.len() >= most {
        return;
    }
    let Some(a) = sigma.iter().position(Option::is_none) else {
        let s: Vec<Sym> = sigma.iter().map(|x| x.expect("assigned")).collect();
        if accept(ls, &s) {
            out.push(s);
        }
        return;
    };
    for b in a..sigma.len() {
        if sigma[b].is_some() {
            continue;
        }
        let mut trial = sigma.to_vec();
        if assign(ls, &mut trial, [(a, b)]) {
            search(ls, &trial, most, accept, out);
        }
    }
}
