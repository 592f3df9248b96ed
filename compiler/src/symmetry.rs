//! Symmetric L-systems (\[G\] §4.1): involutions σ with π(σ(A)) = σ̄(π(A)) for every symbol and a
//! symmetric axiom (Proposition 4.2).

use crate::error::Error;
use crate::lsystem::{LSystem, Part, Sym};

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

/// Every involution σ of the alphabet that makes the L-system symmetric (Remark 4.5: there may be
/// several), in a canonical order (lexicographic on σ as a table).
pub fn involutions(ls: &LSystem) -> Vec<Vec<Sym>> {
    let n = ls.n();
    let mut out = Vec::new();
    let mut sigma: Vec<Option<Sym>> = vec![None; n];
    search(ls, &mut sigma, &mut out);
    out.sort();
    out
}

/// Backtracking over involutions: each unassigned symbol is fixed or paired with a later
/// unassigned one whose rule has the same length (|π(σ(A))| = |π(A)| is necessary).
fn search(ls: &LSystem, sigma: &mut Vec<Option<Sym>>, out: &mut Vec<Vec<Sym>>) {
    let Some(a) = sigma.iter().position(Option::is_none) else {
        let s: Vec<Sym> = sigma.iter().map(|x| x.expect("assigned")).collect();
        if is_symmetry(ls, &s) {
            out.push(s);
        }
        return;
    };
    let n = sigma.len();
    for b in a..n {
        if sigma[b].is_some() || ls.rules[a].len() != ls.rules[b].len() {
            continue;
        }
        sigma[a] = Some(b as Sym);
        sigma[b] = Some(a as Sym);
        search(ls, sigma, out);
        sigma[a] = None;
        sigma[b] = None;
    }
}
