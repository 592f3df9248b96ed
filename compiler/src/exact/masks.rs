//! Subdivision masks by knot insertion (\[N\] §2.2, \[G\] §2.1.1).
//!
//! The old control point labelled by the (d+1)-word w owns the B-spline B whose knots bound the
//! intervals of w. Rewriting gives the refined intervals π(w); B is a combination of the refined
//! B-splines whose supports lie in its own, one per (d+1)-factor of π(w), and those coefficients
//! are the mask. They are computed exactly with Boehm's single-knot insertion, inserting the new
//! knots one by one into B's local knot vector (which only ever reads knots inside B's support).
//! Lengths are those of the refined level (ℓ, not ℓ/ρ): by \[N\] eq. (3) the old knots are exactly
//! the refined knots at rule boundaries, so ρ never appears and nothing depends on the step.

use crate::exact::field::Elem;
use crate::exact::lsystem::{LSystem, Sym, Word};

/// The weight an old point gives to one new point.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contribution {
    /// The (d+1)-word of the new point.
    pub word: Word,
    /// Its weight, exact.
    pub weight: Elem,
}

/// The mask of an old point: its contributions in order along π(w).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    /// The old point's (d+1)-word.
    pub word: Word,
    /// Contribution j goes to the new point whose support starts at refined interval j of π(w).
    pub contributions: Vec<Contribution>,
    /// For odd d, the index of the child: the new point on the old point's middle knot.
    pub child: Option<usize>,
}

/// The mask of the (d+1)-word `w`, exact, for any degree `ls.degree`.
pub fn mask(ls: &LSystem, lengths: &[Elem], w: &[Sym]) -> Mask {
    let d = ls.degree;
    debug_assert_eq!(w.len(), d + 1);
    let field = lengths[0].field();
    let refined = ls.rewrite(w);
    // Refined knots u_0 = 0 < u_1 < … < u_M; old knots are u at the rule boundaries.
    let mut u = vec![Elem::zero(field)];
    for &s in &refined {
        let next = u.last().expect("non-empty").add(&lengths[s as usize]);
        u.push(next);
    }
    let mut boundaries = vec![0usize];
    for &s in w {
        boundaries.push(boundaries.last().expect("non-empty") + ls.rules[s as usize].len());
    }
    // Local knot vector as indices into u, and B's coefficients on its B-splines.
    let mut knots = boundaries.clone();
    let mut coeffs = vec![Elem::one(field)];
    for x in 1..refined.len() {
        if boundaries.contains(&x) {
            continue;
        }
        let mu = knots.iter().rposition(|&k| k < x).expect("u_0 < x");
        boehm(&u, &mut knots, &mut coeffs, d, mu, x);
    }
    debug_assert_eq!(coeffs.len(), refined.len() - d);
    let contributions = coeffs
        .into_iter()
        .enumerate()
        .map(|(j, weight)| Contribution {
            word: refined[j..j + d + 1].to_vec(),
            weight,
        })
        .collect();
    // The new point whose middle knot u_{j+(d+1)/2} is the old middle knot.
    let half = d.div_ceil(2);
    let child = (d % 2 == 1).then(|| boundaries[half] - half);
    Mask {
        word: w.to_vec(),
        contributions,
        child,
    }
}

/// One knot insertion (Boehm 1980), in place: the knot u[x] enters between knots[mu] and
/// knots[mu+1], and the coefficients become those on the refined B-splines,
/// c'_j = β_j c_j + (1 − β_j) c_{j−1} with β_j = (x − t_j)/(t_{j+d} − t_j) for μ−d < j ≤ μ,
/// c_j before and c_{j−1} after: only d coefficients are computed, so a mask costs O(d) field
/// operations per new knot whatever the length of π(w).
fn boehm(u: &[Elem], knots: &mut Vec<usize>, c: &mut Vec<Elem>, d: usize, mu: usize, x: usize) {
    let field = u[0].field();
    let zero = Elem::zero(field);
    // c'_j for j ≤ μ−d is c_j, for j > μ it is c_{j−1}; between, it is new (j ≤ |c|, the
    // last index of c'). So c' = c[..first] ++ new ++ c[last..], one longer than c.
    let first = (mu + 1).saturating_sub(d);
    let last = mu.min(c.len());
    let new: Vec<Elem> = (first..=last)
        .map(|j| {
            let (tj, tjd) = (&u[knots[j]], &u[knots[j + d]]);
            let beta = u[x].sub(tj).div(&tjd.sub(tj)).expect("distinct knots");
            let one_minus = Elem::one(field).sub(&beta);
            let prev = if j == 0 {
                &zero
            } else {
                c.get(j - 1).unwrap_or(&zero)
            };
            beta.mul(c.get(j).unwrap_or(&zero))
                .add(&one_minus.mul(prev))
        })
        .collect();
    c.splice(first..last, new);
    knots.insert(mu + 1, x);
}
