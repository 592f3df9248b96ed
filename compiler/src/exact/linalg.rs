//! Exact linear algebra over Q(ρ): null spaces by Gauss–Jordan elimination.

use crate::exact::field::{Elem, FieldRef};
use crate::exact::work;

/// A basis of the null space of the r×c matrix `a` (rows of `Elem`), in reduced form: basis
/// vector j has a 1 at the j-th free column and 0 at the other free columns.
pub fn null_space(field: &FieldRef, a: &[Vec<Elem>], cols: usize) -> Vec<Vec<Elem>> {
    // Copying a matrix of Elems: one unit per coordinate (exact::work).
    work::charge((a.len() * cols * field.degree()) as u64);
    let mut m: Vec<Vec<Elem>> = a.to_vec();
    let mut pivots: Vec<usize> = Vec::new();
    let mut row = 0;
    for col in 0..cols {
        let Some(p) = (row..m.len()).find(|&r| !m[r][col].is_zero()) else {
            continue;
        };
        m.swap(row, p);
        let inv = m[row][col].inv().expect("pivot is nonzero");
        m[row] = m[row].iter().map(|x| x.mul(&inv)).collect();
        for r in 0..m.len() {
            if r != row && !m[r][col].is_zero() {
                let f = m[r][col].clone();
                let pivot_row = m[row].clone();
                for (x, p) in m[r].iter_mut().zip(&pivot_row) {
                    *x = x.sub(&f.mul(p));
                }
            }
        }
        pivots.push(col);
        row += 1;
        if row == m.len() {
            break;
        }
    }
    let free: Vec<usize> = (0..cols).filter(|c| !pivots.contains(c)).collect();
    free.iter()
        .map(|&f| {
            let mut v = vec![Elem::zero(field); cols];
            v[f] = Elem::one(field);
            for (r, &pc) in pivots.iter().enumerate() {
                v[pc] = m[r][f].neg();
            }
            v
        })
        .collect()
}

/// The integer matrix `m` minus `lambda`·I, over the field.
pub fn shifted(field: &FieldRef, m: &[Vec<i64>], lambda: &Elem) -> Vec<Vec<Elem>> {
    m.iter()
        .enumerate()
        .map(|(i, row)| {
            row.iter()
                .enumerate()
                .map(|(j, &x)| {
                    let e = Elem::int(field, x);
                    if i == j {
                        e.sub(lambda)
                    } else {
                        e
                    }
                })
                .collect()
        })
        .collect()
}

/// The transpose of an integer matrix.
pub fn transpose(m: &[Vec<i64>]) -> Vec<Vec<i64>> {
    let n = m.len();
    (0..n).map(|j| (0..n).map(|i| m[i][j]).collect()).collect()
}
