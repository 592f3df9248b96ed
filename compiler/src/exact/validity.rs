//! Validity of an L-system as an interval subdivision descriptor (\[N\] §3).
//!
//! ρ is the spectral radius of M, the largest real root of det(xI − M) (Perron–Frobenius for
//! non-negative matrices). Definition 3.1 asks for ρ > 1 and a positive eigenvector. Whether a
//! positive eigenvector exists is decided exactly on the classes (strongly connected components)
//! of G(M): it exists iff the *basic* classes (spectral radius ρ) are exactly the *final* classes
//! (no edge leaving them) — Berman & Plemmons, Nonnegative Matrices, Thm 2.3.10.

use crate::exact::field::{parse_expr, Elem, Field, FieldRef};
use crate::exact::linalg::{null_space, shifted, transpose};
use crate::exact::lsystem::{LSystem, Part};
use crate::exact::poly::{char_poly, factor, isolate_real_roots, QPoly, Sturm};
use crate::exact::work;
use crate::Error;
use petgraph::algo::tarjan_scc;
use petgraph::graph::DiGraph;

/// A class of G(M): a strongly connected set of symbols.
#[derive(Clone, Debug)]
pub struct Class {
    /// Symbols of the class.
    pub symbols: Vec<usize>,
    /// Its spectral radius equals ρ(M).
    pub basic: bool,
    /// No edge leaves it.
    pub is_final: bool,
}

/// How the interval lengths were obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LengthSource {
    /// The eigenspace of ρ has dimension 1.
    Unique,
    /// Given in the scheme file and checked against \[N\] eq. (3).
    Declared,
    /// The σ-invariant eigenvector of \[G\] Proposition 5.1.
    SymmetryInvariant,
}

/// Everything \[N\] §3 says about an L-system.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// M of \[N\] eq. (4).
    pub matrix: Vec<Vec<i64>>,
    /// det(xI − M).
    pub char_poly: QPoly,
    /// Q(ρ).
    pub field: FieldRef,
    /// ρ = ρ(M).
    pub rho: Elem,
    /// Definition 3.1 holds.
    pub valid: bool,
    /// Why not, when invalid.
    pub reason: Option<String>,
    /// Classes of G(M).
    pub classes: Vec<Class>,
    /// G(M) is strongly connected (M irreducible).
    pub strongly_connected: bool,
    /// The sufficient condition of Theorem 3.7: strongly connected and a row sum ≥ 2.
    pub theorem_3_7: bool,
    /// Dimension of the eigenspace of ρ.
    pub eigenspace_dim: usize,
    /// Positive lengths a (smallest entry 1), when valid and determined.
    pub lengths: Option<(Vec<Elem>, LengthSource)>,
    /// Why lengths are not determined, when they are not.
    pub lengths_problem: Option<String>,
    /// Left eigenvectors s (s^T M = ρ s^T, \[N\] eq. (6)); one normalised to sum 1 when unique.
    pub left: Vec<Vec<Elem>>,
}

impl Analysis {
    /// The error for an L-system that fails \[N\] Definition 3.1, naming the condition.
    pub fn invalid_error(&self, ls: &LSystem) -> Option<Error> {
        let reason = self.reason.as_ref()?;
        let hint = if self.rho.cmp_exact(&Elem::one(&self.field)).is_le() {
            "some symbol must rewrite, step after step, into several intervals that lead back to it, e.g. `A = \"AB\"`, `B = \"A\"`"
        } else {
            "a sufficient condition ([N] Theorem 3.7): every symbol's rewriting eventually produces every symbol, and some rule has two or more symbols"
        };
        Some(ls.error(
            Part::Rules,
            format!("L-system `{}` is not valid: {reason}", ls.name),
            Some(hint.into()),
        ))
    }

    /// The lengths, or an error explaining why there are none (for stages that need them).
    pub fn require_lengths(&self, ls: &LSystem) -> Result<&[Elem], Error> {
        if let Some(e) = self.invalid_error(ls) {
            return Err(e);
        }
        match (&self.lengths, &self.lengths_problem) {
            (Some((l, _)), _) => Ok(l),
            (None, p) => Err(ls.error(
                Part::Rules,
                p.clone().unwrap_or_else(|| "lengths undetermined".into()),
                Some("declare `[lengths]` (expressions in `rho`) satisfying [N] eq. (3)".into()),
            )),
        }
    }
}

/// The Perron root as a field: the irreducible factor of the characteristic polynomial that has
/// the largest real root, with that root's isolating interval.
fn perron_field(cp: &QPoly) -> Result<FieldRef, String> {
    let roots = isolate_real_roots(cp);
    let (lo, hi) = roots
        .last()
        .cloned()
        .ok_or("the characteristic polynomial has no real root")?;
    let factors = factor(cp)?;
    let (f, _) = factors
        .iter()
        .find(|(f, _)| Sturm::new(f).count_roots(&lo, &hi) > 0)
        .ok_or("no irreducible factor holds the largest real root")?;
    Ok(Field::new(f, lo, hi))
}

/// The largest degree of Q(ρ) over Q compiled: an element holds that many rationals, and a
/// matrix of them n² times as many.
pub const MAX_FIELD_DEGREE: usize = 64;

/// Analyses an L-system, within the work bound of [`crate::exact::work`].
pub fn analyse(ls: &LSystem) -> Result<Analysis, Error> {
    work::stage(ls, "the analysis ([N] §3)", || analyse_unbounded(ls))
}

fn analyse_unbounded(ls: &LSystem) -> Result<Analysis, Error> {
    let m = ls.matrix();
    let n = ls.n();
    let cp = char_poly(&m);
    let field = perron_field(&cp).map_err(|e| {
        Error::internal(
            Some(ls.locate(Part::Rules)),
            format!("the Perron root of M: {e}"),
        )
    })?;
    if field.degree() > MAX_FIELD_DEGREE {
        return Err(ls.error(
            Part::Rules,
            format!(
                "ρ has degree {} over Q (its minimal polynomial {}); at most {MAX_FIELD_DEGREE} \
                 is supported",
                field.degree(),
                field.minpoly()
            ),
            Some("ρ's degree is at most the number of symbols of its class: use fewer symbols in the cycles of the rules".into()),
        ));
    }
    let rho = field.rho();
    let one = Elem::one(&field);

    let classes = classes(&m, &field);
    let strongly_connected = classes.len() == 1 && (n > 1 || m[0][0] != 0);
    let theorem_3_7 = strongly_connected && m.iter().any(|r| r.iter().sum::<i64>() >= 2);

    let eigen = null_space(&field, &shifted(&field, &m, &rho), n);
    let eigenspace_dim = eigen.len();

    // A positive eigenvector of a non-negative matrix belongs to its spectral radius, so the
    // two conditions of Definition 3.1 are decided on ρ(M) alone.
    let reason = if rho.cmp_exact(&one).is_le() {
        Some(format!(
            "[N] Definition 3.1 asks for a real eigenvalue ρ > 1 of M, but the spectral radius ρ(M) = {rho} is not greater than 1, so intervals never shrink"
        ))
    } else if classes.iter().any(|c| c.basic != c.is_final) {
        let names = |pick: fn(&Class) -> bool| -> String {
            classes
                .iter()
                .filter(|c| pick(c))
                .map(|c| {
                    let s: Vec<&str> = c.symbols.iter().map(|&i| ls.symbols[i].as_str()).collect();
                    format!("{{{}}}", s.join(", "))
                })
                .collect::<Vec<_>>()
                .join(" ")
        };
        Some(format!(
            "[N] Definition 3.1 asks for a positive eigenvector of M for ρ > 1, but there is no positive eigenvector for ρ(M) = {rho}: the classes of G(M) with spectral radius ρ ({}) are not exactly the classes no rule leaves ({})",
            names(|c| c.basic),
            names(|c| c.is_final)
        ))
    } else {
        None
    };
    let valid = reason.is_none();

    let mut lengths = None;
    let mut lengths_problem = None;
    if valid {
        match lengths_for(ls, &field, &m, &rho, &eigen)? {
            Ok(l) => lengths = Some(l),
            Err(p) => lengths_problem = Some(p),
        }
    } else if ls.lengths.is_some() {
        lengths_problem = Some("lengths are declared but the L-system is invalid".into());
    }

    let mut left = null_space(&field, &shifted(&field, &transpose(&m), &rho), n);
    if let [s] = left.as_mut_slice() {
        let sum = s.iter().fold(Elem::zero(&field), |a, x| a.add(x));
        if !sum.is_zero() {
            *s = s
                .iter()
                .map(|x| x.div(&sum).expect("nonzero sum"))
                .collect();
        }
    }

    Ok(Analysis {
        matrix: m,
        char_poly: cp,
        field,
        rho,
        valid,
        reason,
        classes,
        strongly_connected,
        theorem_3_7,
        eigenspace_dim,
        lengths,
        lengths_problem,
        left,
    })
}

/// Classes of G(M) with their basic/final flags.
fn classes(m: &[Vec<i64>], field: &FieldRef) -> Vec<Class> {
    let n = m.len();
    let mut g = DiGraph::<usize, ()>::new();
    let nodes: Vec<_> = (0..n).map(|i| g.add_node(i)).collect();
    for i in 0..n {
        for j in 0..n {
            if m[i][j] != 0 {
                g.add_edge(nodes[i], nodes[j], ());
            }
        }
    }
    let mut out: Vec<Class> = tarjan_scc(&g)
        .into_iter()
        .map(|scc| {
            let mut symbols: Vec<usize> = scc.iter().map(|&v| g[v]).collect();
            symbols.sort_unstable();
            let sub: Vec<Vec<i64>> = symbols
                .iter()
                .map(|&i| symbols.iter().map(|&j| m[i][j]).collect())
                .collect();
            // Basic iff ρ is a root of the class's characteristic polynomial (its spectral
            // radius never exceeds ρ(M)).
            let basic = Elem::from_poly(field, &char_poly(&sub)).is_zero();
            let is_final = symbols
                .iter()
                .all(|&i| (0..n).all(|j| m[i][j] == 0 || symbols.contains(&j)));
            Class {
                symbols,
                basic,
                is_final,
            }
        })
        .collect();
    out.sort_by_key(|c| c.symbols[0]);
    out
}

/// Positive lengths: the unique eigenvector, the declared one, or the σ-invariant one.
/// Outer `Err` for a declared `[lengths]` that is wrong; inner `Err` when undetermined.
#[allow(clippy::type_complexity)]
fn lengths_for(
    ls: &LSystem,
    field: &FieldRef,
    m: &[Vec<i64>],
    rho: &Elem,
    eigen: &[Vec<Elem>],
) -> Result<Result<(Vec<Elem>, LengthSource), String>, Error> {
    let n = ls.n();
    if let Some(decl) = &ls.lengths {
        if eigen.len() == 1 {
            return Err(ls.error(
                Part::Length(0),
                "`[lengths]` given, but the eigenvector of ρ is unique: lengths are not free"
                    .into(),
                Some("remove `[lengths]`; the compiler derives them ([N] eq. (4))".into()),
            ));
        }
        let mut a = Vec::with_capacity(n);
        for (i, (s, text)) in ls.symbols.iter().zip(decl).enumerate() {
            let v = parse_expr(field, text).map_err(|e| {
                ls.error(
                    Part::Length(i),
                    format!("`[lengths]` entry for `{s}`: {e}"),
                    Some("lengths are expressions in `rho`: numbers, `rho`, `+ - * / ^` and parentheses, e.g. `(1 + rho)/2`".into()),
                )
            })?;
            if v.signum() <= 0 {
                return Err(ls.error(
                    Part::Length(i),
                    format!("`[lengths]` entry for `{s}` is {v}, not positive"),
                    Some("[N] Definition 3.1 asks for positive lengths: every entry must be greater than 0".into()),
                ));
            }
            a.push(v);
        }
        for (i, row) in m.iter().enumerate() {
            let ma = row.iter().zip(&a).fold(Elem::zero(field), |acc, (&k, x)| {
                acc.add(&Elem::int(field, k).mul(x))
            });
            if ma != rho.mul(&a[i]) {
                return Err(ls.error(
                    Part::Length(i),
                    format!(
                        "`[lengths]` do not satisfy [N] eq. (3) for `{}`: ρ·a = {} but the lengths of π({}) sum to {}",
                        ls.symbols[i],
                        rho.mul(&a[i]),
                        ls.symbols[i],
                        ma
                    ),
                    Some("ρ·a must equal the sum of the lengths of π(A) for every symbol A: take an eigenvector of M for ρ (`lsubdiv inspect` prints M and ρ)".into()),
                ));
            }
        }
        // [G] §4.1: a symmetric system's knot intervals must mirror, a_σ(A) = a_A (Prop. 5.1).
        if let Some(sigma) = &ls.symmetry {
            if let Some(i) = (0..n).find(|&i| a[i] != a[sigma[i] as usize]) {
                let t = sigma[i] as usize;
                return Err(ls.error(
                    Part::Length(i),
                    format!(
                        "`[lengths]` are not σ-invariant: `{}` has length {} but its twin `{}` has {}",
                        ls.symbols[i], a[i], ls.symbols[t], a[t]
                    ),
                    Some(format!(
                        "a symmetric L-system ([G] §4.1, Prop. 5.1) needs twins of equal length: give `{}` and `{}` the same length",
                        ls.symbols[i], ls.symbols[t]
                    )),
                ));
            }
        }
        return Ok(Ok((normalise(a), LengthSource::Declared)));
    }
    let (basis, source) = if eigen.len() == 1 {
        (eigen.to_vec(), LengthSource::Unique)
    } else if let Some(sigma) = &ls.symmetry {
        // [G] Prop. 5.1: restrict to a = P a.
        let mut rows = shifted(field, m, rho);
        for (i, &s) in sigma.iter().enumerate() {
            if s as usize != i {
                let mut r = vec![Elem::zero(field); n];
                r[i] = Elem::one(field);
                r[s as usize] = Elem::int(field, -1);
                rows.push(r);
            }
        }
        (null_space(field, &rows, n), LengthSource::SymmetryInvariant)
    } else {
        (eigen.to_vec(), LengthSource::Unique)
    };
    if basis.len() != 1 {
        return Ok(Err(format!(
            "lengths are not unique: the eigenspace of ρ has dimension {}{}",
            basis.len(),
            if source == LengthSource::SymmetryInvariant {
                " even restricted to σ-invariant vectors"
            } else {
                ""
            }
        )));
    }
    let v = &basis[0];
    let signs: Vec<i8> = v.iter().map(Elem::signum).collect();
    let a = if signs.iter().all(|&s| s > 0) {
        v.clone()
    } else if signs.iter().all(|&s| s < 0) {
        v.iter().map(Elem::neg).collect()
    } else {
        return Ok(Err("the eigenvector of ρ is not positive".into()));
    };
    Ok(Ok((normalise(a), source)))
}

/// Scales a positive vector so that its smallest entry is 1.
fn normalise(a: Vec<Elem>) -> Vec<Elem> {
    let min = a
        .iter()
        .min_by(|x, y| x.cmp_exact(y))
        .expect("non-empty alphabet")
        .clone();
    a.iter().map(|x| x.div(&min).expect("positive")).collect()
}
