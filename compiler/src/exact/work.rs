//! The bound on exact work: every stage of the pipeline runs inside [`bounded`], and the big-number
//! kernels ([`crate::exact::poly`], [`crate::exact::field`]) [`charge`] what they do, so that no
//! scheme file, however small, keeps a build script busy without end.
//!
//! A unit is about one operation on small rationals; an operation on longer numbers costs the
//! square of their length in 64-bit limbs (`op`). Past the limit, [`charge`] unwinds to the innermost [`bounded`] (without the
//! panic hook: nothing is printed), which returns [`Exhausted`]; callers turn it into an error
//! located at the scheme's rules. The count is per thread and shared by nested scopes, so a
//! stage called from another stage spends the outer budget.

use crate::exact::lsystem::{LSystem, Part};
use crate::Error;
use num_bigint::BigInt;
use num_rational::BigRational;
use std::cell::Cell;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};

/// Work allowed to one stage: 5·10⁷ units, some 20 s of one core where it was measured (1 to
/// 6·10⁶ units/s, optimised), 300 times what the largest shipped scheme spends and 5 times what
/// a random degree-5 scheme over a quintic field does (docs/schemes.md, "Limits").
pub const MAX_WORK: u64 = 50_000_000;

/// A stage ran out of work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Exhausted {
    /// The limit that was reached.
    pub limit: u64,
}

thread_local! {
    /// (spent, limit) of the outermost open scope on this thread.
    static BUDGET: Cell<Option<(u64, u64)>> = const { Cell::new(None) };
}

/// Runs `f` with at most `limit` units of work (the enclosing scope's budget when there is one);
/// `Err` when it needed more. Panics of `f` other than exhaustion pass through.
pub fn bounded<T>(limit: u64, f: impl FnOnce() -> T) -> Result<T, Exhausted> {
    let outermost = BUDGET.get().is_none();
    if outermost {
        BUDGET.set(Some((0, limit)));
    }
    let result = catch_unwind(AssertUnwindSafe(f));
    if outermost {
        BUDGET.set(None);
    }
    result.map_err(|payload| match payload.downcast::<Exhausted>() {
        Ok(e) => *e,
        Err(other) => resume_unwind(other),
    })
}

/// Runs the stage `what` of the pipeline on `ls` within [`MAX_WORK`]; running out becomes an
/// error located at the rules that names the stage and the limit.
pub fn stage<T>(
    ls: &LSystem,
    what: &str,
    f: impl FnOnce() -> Result<T, Error>,
) -> Result<T, Error> {
    bounded(MAX_WORK, f).unwrap_or_else(|e| {
        Err(ls.error(
            Part::Rules,
            format!(
                "{what} of `{}` needs more exact work than the limit ({} units, some 20 s): the \
                 L-system is too large to compile exactly",
                ls.name, e.limit
            ),
            Some(
                "use fewer symbols, shorter rules or smaller numbers in `[lengths]` (docs/schemes.md, \
                 \"Limits\")"
                    .into(),
            ),
        ))
    })
}

/// Spends `units`; past the limit of the open scope, unwinds to it. Outside any scope (unit
/// tests of the kernels) work is not counted.
pub fn charge(units: u64) {
    if let Some((spent, limit)) = BUDGET.get() {
        let spent = spent.saturating_add(units);
        BUDGET.set(Some((spent, limit)));
        if spent > limit {
            resume_unwind(Box::new(Exhausted { limit }));
        }
    }
}

/// Work spent so far in the open scope (0 outside any).
pub fn spent() -> u64 {
    BUDGET.get().map_or(0, |(s, _)| s)
}

/// The sizes of some numbers in 64-bit limbs (a zero has none), to price
/// operations on all of them: a product of numbers of a and b limbs costs 1 + a·b (schoolbook),
/// a sum 1 + a + b; so a unit is about one operation on small numbers.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sizes {
    /// Numbers, zeros included.
    len: u64,
    /// Nonzero numbers.
    count: u64,
    sum: u64,
    squares: u64,
    largest: u64,
}

impl Sizes {
    fn of(limbs: impl Iterator<Item = u64>) -> Sizes {
        limbs.fold(Sizes::default(), |s, l| Sizes {
            len: s.len + 1,
            count: s.count + u64::from(l > 0),
            sum: s.sum.saturating_add(l),
            squares: s.squares.saturating_add(l.saturating_mul(l)),
            largest: s.largest.max(l),
        })
    }

    /// Of rationals (numerator and denominator limbs).
    pub fn rationals<'a>(rs: impl IntoIterator<Item = &'a BigRational>) -> Sizes {
        Sizes::of(rs.into_iter().map(limbs))
    }

    /// Of integers.
    pub fn integers<'a>(ns: impl IntoIterator<Item = &'a BigInt>) -> Sizes {
        Sizes::of(ns.into_iter().map(int_limbs))
    }

    /// Every number of `self` with every number of `o` (a product of polynomials or matrices):
    /// Σᵢⱼ (1 + aᵢ bⱼ) over the nonzero aᵢ (the kernels skip zero factors on the left).
    pub fn all_pairs(self, o: Sizes) -> u64 {
        self.count
            .saturating_mul(o.len)
            .saturating_add(self.sum.saturating_mul(o.sum))
    }

    /// Number by number (a sum of vectors): Σ (1 + aᵢ + bᵢ).
    pub fn pairwise(self, o: Sizes) -> u64 {
        self.len
            .max(o.len)
            .saturating_add(self.sum)
            .saturating_add(o.sum)
    }

    /// Each number `times` times with one of `b` limbs (a scaling, a division step).
    pub fn each_with(self, b: u64, times: u64) -> u64 {
        self.len
            .saturating_add(self.sum.saturating_mul(b))
            .saturating_mul(times)
    }

    /// The largest size, in limbs.
    pub fn largest(self) -> u64 {
        self.largest
    }
}

/// Horner's rule on `n` coefficients of at most `c` limbs at a point of `x` limbs: the
/// accumulator grows to n·x limbs, so about Σₖ (1 + (k x + c) x) ≤ n (1 + (n x + c) x).
pub fn horner(n: u64, x: u64, c: u64) -> u64 {
    let step = n.saturating_mul(x).saturating_add(c).saturating_mul(x);
    n.saturating_mul(step.saturating_add(1))
}

/// 64-bit limbs of an integer (0 for zero).
pub fn int_limbs(n: &BigInt) -> u64 {
    n.bits().div_ceil(64)
}

/// 64-bit limbs of a nonzero rational, numerator and denominator; 0 for zero.
pub fn limbs(r: &BigRational) -> u64 {
    match int_limbs(r.numer()) {
        0 => 0,
        n => n + int_limbs(r.denom()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_past_the_limit_unwinds_to_the_scope_and_nested_scopes_share_it() {
        assert_eq!(bounded(10, || (charge(4), charge(6), spent()).2), Ok(10));
        assert_eq!(bounded(10, || charge(11)), Err(Exhausted { limit: 10 }));
        // The inner scope spends the outer budget: 6 + 6 > 10.
        let r = bounded(10, || {
            charge(6);
            bounded(1000, || charge(6))
        });
        assert_eq!(r, Ok(Err(Exhausted { limit: 10 })));
        // Outside a scope nothing is counted, and a scope ends with its closure.
        charge(u64::MAX);
        assert_eq!(spent(), 0);
    }

    #[test]
    fn other_panics_pass_through() {
        let r = catch_unwind(|| bounded(10, || panic!("a bug")));
        assert!(r.is_err());
        assert_eq!(spent(), 0);
    }
}
