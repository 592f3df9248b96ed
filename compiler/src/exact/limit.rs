//! Limit masks of curves (\[N\] §2: the limit of the scheme is the B-spline of the knot
//! intervals): for a control point with (d+1)-word w, the exact weights in Q(ρ) that take it
//! and its neighbours to the point of the limit curve it converges to — the curve at its
//! middle knot — and to the first derivative there.
//!
//! For the cubic (d = 3) a point's word holds every knot that matters: with w = (a, b, c, e)
//! (interval lengths; the point's middle knot between b and c), the three B-splines nonzero at
//! that knot take there the values (de Boor 1978; the curve's own knots)
//!
//! ```text
//! N₋ = c² / ((b + c)(a + b + c)),   N₊ = b² / ((b + c)(b + c + e)),   N₀ = 1 − N₋ − N₊,
//! ```
//!
//! and the derivative, a quadratic B-spline with control points 3(P_j − P_{j−1}) / (its
//! B-spline's support), is
//!
//! ```text
//! C' = 3 / (b + c) · ( c / (a + b + c) · (P₀ − P₋) + b / (b + c + e) · (P₊ − P₀) ).
//! ```
//!
//! The derivative is with respect to the parameter in which the intervals have the tabulated
//! lengths (those of the refined level: at level s multiply by ρ^s for the coarse parameter).
//! For d = 1 the limit point is the control point itself (the derivative jumps there). For
//! other degrees the value at a knot involves 2d − 2 intervals, more than a point's word:
//! no limit mask is derived (`None`).

use crate::exact::field::Elem;
use crate::exact::lsystem::{LSystem, Sym, Word};

/// The limit mask of the control point with word `word`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LimitMask {
    /// The point's (d+1)-word.
    pub word: Word,
    /// Weights of the points −(d−1)/2 ..= (d−1)/2 around it (itself in the middle) for its
    /// limit position: they sum to exactly 1.
    pub position: Vec<Elem>,
    /// Weights of the same points for the limit curve's derivative there: they sum to exactly
    /// 0.
    pub tangent: Vec<Elem>,
}

/// The limit mask of the (d+1)-word `w` (see the module documentation), or none where the
/// degree has no mask from one word.
pub fn limit_mask(ls: &LSystem, lengths: &[Elem], w: &[Sym]) -> Option<LimitMask> {
    let field = lengths[0].field();
    let len = |s: Sym| lengths[s as usize].clone();
    let (position, tangent) = match (ls.degree, w) {
        (1, _) => (vec![Elem::one(field)], vec![Elem::zero(field)]),
        (3, &[a, b, c, e]) => {
            let (a, b, c, e) = (len(a), len(b), len(c), len(e));
            let bc = b.add(&c);
            let left = bc.add(&a); // a + b + c
            let right = bc.add(&e); // b + c + e
                                    // Interval lengths are positive, so the denominators are not zero.
            let ratio = |n: &Elem, d: &Elem| n.div(d).expect("a positive length");
            let n_minus = ratio(&c.mul(&c), &bc.mul(&left));
            let n_plus = ratio(&b.mul(&b), &bc.mul(&right));
            let n_zero = Elem::one(field).sub(&n_minus).sub(&n_plus);
            let three = Elem::int(field, 3);
            let t_minus = ratio(&three.mul(&c), &bc.mul(&left)).neg();
            let t_plus = ratio(&three.mul(&b), &bc.mul(&right));
            let t_zero = t_minus.add(&t_plus).neg();
            (vec![n_minus, n_zero, n_plus], vec![t_minus, t_zero, t_plus])
        }
        _ => return None,
    };
    Some(LimitMask {
        word: w.to_vec(),
        position,
        tangent,
    })
}

/// What is wrong with a limit mask, if anything: its position weights must sum to exactly 1,
/// its tangent weights to exactly 0, and for a symmetric scheme the mask of σ̄(w) must be the
/// reversed mask of w (the tangent negated).
pub fn certify(ls: &LSystem, lengths: &[Elem], m: &LimitMask) -> Result<(), String> {
    let sum = |v: &[Elem]| {
        v.iter()
            .fold(Elem::zero(lengths[0].field()), |acc, x| acc.add(x))
    };
    let word = ls.word_str(&m.word);
    if sum(&m.position) != Elem::one(lengths[0].field()) {
        return Err(format!("limit position weights of {word} do not sum to 1"));
    }
    if !sum(&m.tangent).is_zero() {
        return Err(format!("limit tangent weights of {word} do not sum to 0"));
    }
    if let Some(sigma) = &ls.symmetry {
        let mirrored: Vec<Sym> = m.word.iter().rev().map(|&s| sigma[s as usize]).collect();
        let twin = limit_mask(ls, lengths, &mirrored).ok_or("no mirrored limit mask")?;
        let reversed: Vec<Elem> = m.position.iter().rev().cloned().collect();
        let negated: Vec<Elem> = m.tangent.iter().rev().map(Elem::neg).collect();
        if twin.position != reversed || twin.tangent != negated {
            return Err(format!(
                "the limit mask of {} is not the mirror of that of {word}",
                ls.word_str(&mirrored)
            ));
        }
    }
    Ok(())
}
