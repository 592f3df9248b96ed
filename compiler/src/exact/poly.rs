//! Exact univariate polynomials over Q.
//!
//! Arithmetic, characteristic polynomials (Faddeev–LeVerrier over Z), complete
//! factorisation over Q (Yun square-free decomposition + Zassenhaus: Berlekamp
//! modulo a small prime, Hensel lifting, exhaustive recombination), Sturm
//! sequences and exact real-root isolation/refinement by bisection.
//!
//! Everything is exact (`BigInt` / `BigRational`); no floating point is used.

use std::cmp::Ordering;
use std::fmt;

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

use crate::exact::work::{charge, horner, int_limbs, limbs, Sizes};

/// Dense polynomial over Q, coefficients constant term first, never trailing zeros
/// (zero polynomial = empty vec).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct QPoly(Vec<BigRational>);

fn rat(n: BigInt) -> BigRational {
    BigRational::from_integer(n)
}

impl QPoly {
    /// Builds a polynomial from coefficients (constant term first), trimming trailing zeros.
    pub fn new(mut coeffs: Vec<BigRational>) -> Self {
        while coeffs.last().is_some_and(Zero::is_zero) {
            coeffs.pop();
        }
        QPoly(coeffs)
    }

    /// Builds a polynomial from machine-integer coefficients (constant term first).
    pub fn from_ints(coeffs: &[i64]) -> Self {
        Self::new(coeffs.iter().map(|&c| rat(BigInt::from(c))).collect())
    }

    /// Builds a polynomial from integer coefficients (constant term first).
    pub fn from_bigints(coeffs: &[BigInt]) -> Self {
        Self::new(coeffs.iter().cloned().map(rat).collect())
    }

    /// The zero polynomial.
    pub fn zero() -> Self {
        QPoly(Vec::new())
    }

    /// The constant polynomial 1.
    pub fn one() -> Self {
        QPoly(vec![BigRational::one()])
    }

    /// The polynomial x.
    pub fn x() -> Self {
        QPoly(vec![BigRational::zero(), BigRational::one()])
    }

    /// Coefficients, constant term first, no trailing zeros.
    pub fn coeffs(&self) -> &[BigRational] {
        &self.0
    }

    /// Degree, `None` for the zero polynomial.
    pub fn degree(&self) -> Option<usize> {
        self.0.len().checked_sub(1)
    }

    /// True for the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    /// Leading coefficient, `None` for the zero polynomial.
    pub fn leading(&self) -> Option<&BigRational> {
        self.0.last()
    }

    /// Sum.
    pub fn add(&self, o: &Self) -> Self {
        let z = BigRational::zero();
        let n = self.0.len().max(o.0.len());
        charge(Sizes::rationals(&self.0).pairwise(Sizes::rationals(&o.0)));
        Self::new(
            (0..n)
                .map(|i| self.0.get(i).unwrap_or(&z) + o.0.get(i).unwrap_or(&z))
                .collect(),
        )
    }

    /// Difference `self - o`.
    pub fn sub(&self, o: &Self) -> Self {
        let z = BigRational::zero();
        let n = self.0.len().max(o.0.len());
        charge(Sizes::rationals(&self.0).pairwise(Sizes::rationals(&o.0)));
        Self::new(
            (0..n)
                .map(|i| self.0.get(i).unwrap_or(&z) - o.0.get(i).unwrap_or(&z))
                .collect(),
        )
    }

    /// Product.
    pub fn mul(&self, o: &Self) -> Self {
        if self.is_zero() || o.is_zero() {
            return Self::zero();
        }
        charge(Sizes::rationals(&self.0).all_pairs(Sizes::rationals(&o.0)));
        let mut v = vec![BigRational::zero(); self.0.len() + o.0.len() - 1];
        for (i, a) in self.0.iter().enumerate() {
            if a.is_zero() {
                continue;
            }
            for (j, b) in o.0.iter().enumerate() {
                v[i + j] += a * b;
            }
        }
        Self::new(v)
    }

    /// Negation.
    pub fn neg(&self) -> Self {
        QPoly(self.0.iter().map(|c| -c).collect())
    }

    /// Multiplication by the constant `c`.
    pub fn scale(&self, c: &BigRational) -> Self {
        if c.is_zero() {
            return Self::zero();
        }
        charge(Sizes::rationals(&self.0).each_with(limbs(c), 1));
        QPoly(self.0.iter().map(|a| a * c).collect())
    }

    /// Euclidean division: `(q, r)` with `self = q*d + r`, `deg r < deg d`.
    ///
    /// # Panics
    /// Panics if `d` is the zero polynomial.
    pub fn div_rem(&self, d: &Self) -> (Self, Self) {
        let dl = d
            .leading()
            .expect("QPoly::div_rem: division by the zero polynomial");
        let m = d.0.len() - 1;
        if self.0.len() < d.0.len() {
            return (Self::zero(), self.clone());
        }
        let inv = dl.recip();
        let mut r = self.0.clone();
        let mut q = vec![BigRational::zero(); r.len() - m];
        charge(
            Sizes::rationals(&d.0).each_with(Sizes::rationals(&self.0).largest(), q.len() as u64),
        );
        for i in (0..q.len()).rev() {
            let c = &r[i + m] * &inv;
            if !c.is_zero() {
                for j in 0..m {
                    let t = &c * &d.0[j];
                    r[i + j] -= t;
                }
            }
            q[i] = c;
        }
        r.truncate(m);
        (Self::new(q), Self::new(r))
    }

    /// Remainder of the Euclidean division by `d`.
    ///
    /// # Panics
    /// Panics if `d` is the zero polynomial.
    pub fn rem(&self, d: &Self) -> Self {
        self.div_rem(d).1
    }

    /// Monic greatest common divisor (zero if both are zero). Computed by a primitive
    /// pseudo-remainder sequence over Z, which avoids rational coefficient blow-up.
    pub fn gcd(&self, o: &Self) -> Self {
        if self.is_zero() || o.is_zero() {
            return self.add(o).monic();
        }
        let (mut a, mut b) = (self.primitive_integer(), o.primitive_integer());
        if a.len() < b.len() {
            std::mem::swap(&mut a, &mut b);
        }
        while !b.is_empty() {
            let r = zp_primitive(zp_prem_positive(&a, &b));
            a = std::mem::replace(&mut b, r);
        }
        QPoly::from_bigints(&a).monic()
    }

    /// Extended Euclid: returns (g, s, t) with s*self + t*o = g, g monic gcd.
    /// Both zero gives (0, 0, 0).
    pub fn ext_gcd(&self, o: &Self) -> (Self, Self, Self) {
        let (mut r0, mut s0, mut t0) = (self.clone(), Self::one(), Self::zero());
        let (mut r1, mut s1, mut t1) = (o.clone(), Self::zero(), Self::one());
        while !r1.is_zero() {
            let (q, r) = r0.div_rem(&r1);
            let mut s = s0.sub(&q.mul(&s1));
            let mut t = t0.sub(&q.mul(&t1));
            let mut r = r;
            if let Some(l) = r.leading() {
                let c = l.recip();
                r = r.scale(&c);
                s = s.scale(&c);
                t = t.scale(&c);
            }
            r0 = std::mem::replace(&mut r1, r);
            s0 = std::mem::replace(&mut s1, s);
            t0 = std::mem::replace(&mut t1, t);
        }
        match r0.leading() {
            None => (Self::zero(), Self::zero(), Self::zero()),
            Some(l) => {
                let c = l.recip();
                (r0.scale(&c), s0.scale(&c), t0.scale(&c))
            }
        }
    }

    /// Formal derivative.
    pub fn derivative(&self) -> Self {
        Self::new(
            self.0
                .iter()
                .enumerate()
                .skip(1)
                .map(|(i, c)| c * rat(BigInt::from(i)))
                .collect(),
        )
    }

    /// The monic associate (zero stays zero).
    pub fn monic(&self) -> Self {
        match self.leading() {
            None => Self::zero(),
            Some(l) if l.is_one() => self.clone(),
            Some(l) => self.scale(&l.recip()),
        }
    }

    /// Value at `x` (Horner).
    pub fn eval(&self, x: &BigRational) -> BigRational {
        let n = self.0.len() as u64;
        charge(horner(n, limbs(x), Sizes::rationals(&self.0).largest()));
        let mut acc = BigRational::zero();
        for c in self.0.iter().rev() {
            acc = acc * x + c;
        }
        acc
    }

    /// Sign of self at x: -1, 0, 1.
    pub fn sign_at(&self, x: &BigRational) -> i8 {
        if self.is_zero() {
            return 0;
        }
        zp_sign_at(&zp_positive_multiple(self), x)
    }

    /// The primitive integer polynomial with positive leading coefficient proportional to self
    /// (content removed), constant term first.
    ///
    /// # Panics
    /// Panics on the zero polynomial.
    pub fn primitive_integer(&self) -> Vec<BigInt> {
        assert!(!self.is_zero(), "QPoly::primitive_integer: zero polynomial");
        let mut v = zp_positive_multiple(self);
        if v.last().is_some_and(Signed::is_negative) {
            for c in &mut v {
                *c = -&*c;
            }
        }
        v
    }

    /// Square-free part (monic): self / gcd(self, self'). Zero stays zero.
    pub fn square_free(&self) -> Self {
        if self.is_zero() {
            return Self::zero();
        }
        let g = self.gcd(&self.derivative());
        self.div_rem(&g).0.monic()
    }
}

impl fmt::Display for QPoly {
    /// Highest degree first, e.g. `x^3 - x^2 - 2` or `1/2 x + 3`; zero is `0`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_zero() {
            return write!(f, "0");
        }
        let mut first = true;
        for (k, c) in self.0.iter().enumerate().rev() {
            if c.is_zero() {
                continue;
            }
            let neg = c.is_negative();
            let a = c.abs();
            if first {
                if neg {
                    write!(f, "-")?;
                }
            } else {
                write!(f, " {} ", if neg { '-' } else { '+' })?;
            }
            let mono = match k {
                0 => String::new(),
                1 => "x".to_string(),
                _ => format!("x^{k}"),
            };
            if k == 0 {
                write!(f, "{a}")?;
            } else if a.is_one() {
                write!(f, "{mono}")?;
            } else {
                write!(f, "{a} {mono}")?;
            }
            first = false;
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// Integer polynomials (Vec<BigInt>, constant term first, trimmed).
// ---------------------------------------------------------------------------

fn zp_trim(v: &mut Vec<BigInt>) {
    while v.last().is_some_and(Zero::is_zero) {
        v.pop();
    }
}

/// Non-negative gcd of the coefficients.
fn zp_content(v: &[BigInt]) -> BigInt {
    v.iter().fold(BigInt::zero(), |g, c| g.gcd(c))
}

/// Content removed, leading coefficient made positive.
fn zp_primitive(mut v: Vec<BigInt>) -> Vec<BigInt> {
    zp_trim(&mut v);
    let c = zp_content(&v);
    if c.is_zero() {
        return v;
    }
    let c = if v.last().is_some_and(Signed::is_negative) {
        -c
    } else {
        c
    };
    v.iter().map(|a| a / &c).collect()
}

/// Primitive integer polynomial equal to a *positive* multiple of `q` (sign preserved).
fn zp_positive_multiple(q: &QPoly) -> Vec<BigInt> {
    let l = q.0.iter().fold(BigInt::one(), |acc, c| acc.lcm(c.denom()));
    let v: Vec<BigInt> = q.0.iter().map(|c| c.numer() * (&l / c.denom())).collect();
    let g = zp_content(&v);
    if g.is_zero() {
        return v;
    }
    v.iter().map(|a| a / &g).collect()
}

/// A positive integer multiple of the remainder of `a` by `b` (`b` nonzero): pseudo-division
/// using the multiplier |lc(b)| at each step.
fn zp_prem_positive(a: &[BigInt], b: &[BigInt]) -> Vec<BigInt> {
    let lb = b.last().expect("zp_prem_positive: zero divisor");
    let (alb, sb) = (lb.abs(), lb.signum());
    let m = b.len() - 1;
    let mut r = a.to_vec();
    zp_trim(&mut r);
    while r.len() > m {
        charge(
            Sizes::integers(&r).each_with(int_limbs(&alb), 1)
                + Sizes::integers(b).each_with(Sizes::integers(&r).largest(), 1),
        );
        let k = r.len() - 1 - m;
        let lr = r.pop().expect("nonempty") * &sb;
        for c in &mut r {
            *c *= &alb;
        }
        for j in 0..m {
            r[k + j] -= &lr * &b[j];
        }
        zp_trim(&mut r);
    }
    r
}

fn zp_mul(a: &[BigInt], b: &[BigInt]) -> Vec<BigInt> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    charge(Sizes::integers(a).all_pairs(Sizes::integers(b)));
    let mut v = vec![BigInt::zero(); a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        if x.is_zero() {
            continue;
        }
        for (j, y) in b.iter().enumerate() {
            v[i + j] += x * y;
        }
    }
    zp_trim(&mut v);
    v
}

/// `Some(a / b)` if `b` divides `a` exactly in Z[x], else `None`. `b` must be nonzero.
fn zp_div_exact(a: &[BigInt], b: &[BigInt]) -> Option<Vec<BigInt>> {
    let lb = b.last().expect("zp_div_exact: zero divisor");
    if a.is_empty() {
        return Some(Vec::new());
    }
    if a.len() < b.len() {
        return None;
    }
    let m = b.len() - 1;
    let mut r = a.to_vec();
    let mut q = vec![BigInt::zero(); a.len() - m];
    charge(Sizes::integers(b).each_with(Sizes::integers(a).largest(), q.len() as u64));
    for i in (0..q.len()).rev() {
        let (c, rem) = r[i + m].div_rem(lb);
        if !rem.is_zero() {
            return None;
        }
        if !c.is_zero() {
            for j in 0..m {
                let t = &c * &b[j];
                r[i + j] -= t;
            }
        }
        q[i] = c;
    }
    if r[..m].iter().all(Zero::is_zero) {
        Some(q)
    } else {
        None
    }
}

/// Sign of the integer polynomial `a` at the rational `x` (homogeneous Horner, no fractions).
fn zp_sign_at(a: &[BigInt], x: &BigRational) -> i8 {
    let Some(top) = a.last() else {
        return 0;
    };
    let (num, den) = (x.numer(), x.denom()); // den > 0
    let n = a.len() as u64;
    charge(horner(n, limbs(x), Sizes::integers(a).largest()));
    let mut s = top.clone();
    let mut dpow = BigInt::one();
    for c in a.iter().rev().skip(1) {
        dpow *= den;
        s = s * num + c * &dpow;
    }
    if s.is_positive() {
        1
    } else if s.is_negative() {
        -1
    } else {
        0
    }
}

fn cmp_qpoly(a: &QPoly, b: &QPoly) -> Ordering {
    a.degree().cmp(&b.degree()).then_with(|| a.0.cmp(&b.0))
}

// ---------------------------------------------------------------------------
// Characteristic polynomial.
// ---------------------------------------------------------------------------

/// Characteristic polynomial det(xI - M) of a square integer matrix, exact
/// (Faddeev–LeVerrier over Z, all divisions exact). Monic of degree n; 1 for n = 0.
///
/// # Panics
/// Panics if `m` is not square.
pub fn char_poly(m: &[Vec<i64>]) -> QPoly {
    let n = m.len();
    assert!(
        m.iter().all(|r| r.len() == n),
        "char_poly: matrix must be square"
    );
    let a: Vec<Vec<BigInt>> = m
        .iter()
        .map(|r| r.iter().map(|&x| BigInt::from(x)).collect())
        .collect();
    let mut c = vec![BigInt::zero(); n + 1];
    c[n] = BigInt::one();
    // am = A * M_{k-1}; M_k = am + c_{n-k+1} I; c_{n-k} = -tr(A M_k) / k.
    let mut am = vec![vec![BigInt::zero(); n]; n];
    for k in 1..=n {
        let mut mk = am;
        for (i, row) in mk.iter_mut().enumerate() {
            row[i] += &c[n - k + 1];
        }
        am = mat_mul(&a, &mk);
        let tr: BigInt = (0..n).map(|i| &am[i][i]).sum();
        let (q, r) = tr.div_rem(&BigInt::from(k));
        debug_assert!(r.is_zero());
        c[n - k] = -q;
    }
    QPoly::from_bigints(&c)
}

fn mat_mul(a: &[Vec<BigInt>], b: &[Vec<BigInt>]) -> Vec<Vec<BigInt>> {
    let n = a.len();
    // Each entry a_ik meets the n entries of row k of b: all pairs over n.
    charge(
        Sizes::integers(a.iter().flatten()).all_pairs(Sizes::integers(b.iter().flatten()))
            / n as u64,
    );
    let mut out = vec![vec![BigInt::zero(); n]; n];
    for i in 0..n {
        for k in 0..n {
            if a[i][k].is_zero() {
                continue;
            }
            for j in 0..n {
                out[i][j] += &a[i][k] * &b[k][j];
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------
// Polynomials over F_p (Vec<u64>, constant term first, trimmed, p < 2^31).
// ---------------------------------------------------------------------------

fn fp_trim(mut v: Vec<u64>) -> Vec<u64> {
    while v.last() == Some(&0) {
        v.pop();
    }
    v
}

fn fp_pow(mut b: u64, mut e: u64, p: u64) -> u64 {
    let mut r = 1 % p;
    b %= p;
    while e > 0 {
        if e & 1 == 1 {
            r = r * b % p;
        }
        b = b * b % p;
        e >>= 1;
    }
    r
}

fn fp_inv(a: u64, p: u64) -> u64 {
    debug_assert!(!Integer::is_multiple_of(&a, &p));
    fp_pow(a, p - 2, p)
}

fn fp_from_z(a: &[BigInt], p: u64) -> Vec<u64> {
    let pb = BigInt::from(p);
    fp_trim(
        a.iter()
            .map(|c| c.mod_floor(&pb).to_u64().expect("residue fits u64"))
            .collect(),
    )
}

fn fp_add(a: &[u64], b: &[u64], p: u64) -> Vec<u64> {
    let n = a.len().max(b.len());
    fp_trim(
        (0..n)
            .map(|i| (a.get(i).unwrap_or(&0) + b.get(i).unwrap_or(&0)) % p)
            .collect(),
    )
}

fn fp_sub(a: &[u64], b: &[u64], p: u64) -> Vec<u64> {
    let n = a.len().max(b.len());
    fp_trim(
        (0..n)
            .map(|i| (a.get(i).unwrap_or(&0) + p - b.get(i).unwrap_or(&0)) % p)
            .collect(),
    )
}

fn fp_mul(a: &[u64], b: &[u64], p: u64) -> Vec<u64> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut v = vec![0u64; a.len() + b.len() - 1];
    for (i, &x) in a.iter().enumerate() {
        if x == 0 {
            continue;
        }
        for (j, &y) in b.iter().enumerate() {
            v[i + j] = (v[i + j] + x * y) % p;
        }
    }
    fp_trim(v)
}

fn fp_scale(a: &[u64], c: u64, p: u64) -> Vec<u64> {
    fp_trim(a.iter().map(|&x| x * c % p).collect())
}

fn fp_monic(a: &[u64], p: u64) -> Vec<u64> {
    match a.last() {
        None => Vec::new(),
        Some(&l) => fp_scale(a, fp_inv(l, p), p),
    }
}

/// Euclidean division over F_p; `b` nonzero.
fn fp_divrem(a: &[u64], b: &[u64], p: u64) -> (Vec<u64>, Vec<u64>) {
    let lb = *b.last().expect("fp_divrem: zero divisor");
    if a.len() < b.len() {
        return (Vec::new(), a.to_vec());
    }
    let inv = fp_inv(lb, p);
    let m = b.len() - 1;
    let mut r = a.to_vec();
    let mut q = vec![0u64; a.len() - m];
    for i in (0..q.len()).rev() {
        let c = r[i + m] * inv % p;
        if c != 0 {
            for j in 0..m {
                r[i + j] = (r[i + j] + p - c * b[j] % p) % p;
            }
        }
        q[i] = c;
    }
    r.truncate(m);
    (fp_trim(q), fp_trim(r))
}

fn fp_rem(a: &[u64], b: &[u64], p: u64) -> Vec<u64> {
    fp_divrem(a, b, p).1
}

/// Monic gcd over F_p.
fn fp_gcd(a: &[u64], b: &[u64], p: u64) -> Vec<u64> {
    let (mut a, mut b) = (fp_monic(a, p), fp_monic(b, p));
    while !b.is_empty() {
        let r = fp_monic(&fp_rem(&a, &b, p), p);
        a = std::mem::replace(&mut b, r);
    }
    a
}

/// Extended Euclid over F_p: (g, s, t) with s*a + t*b = g monic.
fn fp_ext_gcd(a: &[u64], b: &[u64], p: u64) -> (Vec<u64>, Vec<u64>, Vec<u64>) {
    let (mut r0, mut s0, mut t0) = (a.to_vec(), vec![1u64], Vec::new());
    let (mut r1, mut s1, mut t1) = (b.to_vec(), Vec::new(), vec![1u64]);
    while !r1.is_empty() {
        let (q, r) = fp_divrem(&r0, &r1, p);
        let s = fp_sub(&s0, &fp_mul(&q, &s1, p), p);
        let t = fp_sub(&t0, &fp_mul(&q, &t1, p), p);
        r0 = std::mem::replace(&mut r1, r);
        s0 = std::mem::replace(&mut s1, s);
        t0 = std::mem::replace(&mut t1, t);
    }
    let inv = fp_inv(*r0.last().expect("fp_ext_gcd: both zero"), p);
    (
        fp_scale(&r0, inv, p),
        fp_scale(&s0, inv, p),
        fp_scale(&t0, inv, p),
    )
}

fn fp_deriv(a: &[u64], p: u64) -> Vec<u64> {
    fp_trim(
        a.iter()
            .enumerate()
            .skip(1)
            .map(|(i, &c)| (i as u64 % p) * c % p)
            .collect(),
    )
}

/// x^e mod f over F_p.
fn fp_x_pow_mod(mut e: u64, f: &[u64], p: u64) -> Vec<u64> {
    let mut r = fp_rem(&[1], f, p);
    let mut b = fp_rem(&[0, 1], f, p);
    while e > 0 {
        if e & 1 == 1 {
            r = fp_rem(&fp_mul(&r, &b, p), f, p);
        }
        b = fp_rem(&fp_mul(&b, &b, p), f, p);
        e >>= 1;
    }
    r
}

/// Kernel basis of the matrix `t` (rows) over F_p.
fn fp_nullspace(mut t: Vec<Vec<u64>>, p: u64) -> Vec<Vec<u64>> {
    let rows = t.len();
    let cols = t.first().map_or(0, Vec::len);
    let mut pivots: Vec<usize> = Vec::new();
    let mut r = 0;
    for c in 0..cols {
        if r == rows {
            break;
        }
        let Some(i) = (r..rows).find(|&i| t[i][c] != 0) else {
            continue;
        };
        t.swap(i, r);
        let inv = fp_inv(t[r][c], p);
        for x in &mut t[r] {
            *x = *x * inv % p;
        }
        let pivot_row = t[r].clone();
        for (i2, row) in t.iter_mut().enumerate() {
            if i2 != r && row[c] != 0 {
                let f = row[c];
                for (x, &y) in row.iter_mut().zip(&pivot_row) {
                    *x = (*x + p - f * y % p) % p;
                }
            }
        }
        pivots.push(c);
        r += 1;
    }
    let mut basis = Vec::new();
    for free in (0..cols).filter(|c| !pivots.contains(c)) {
        let mut v = vec![0u64; cols];
        v[free] = 1;
        for (k, &pc) in pivots.iter().enumerate() {
            v[pc] = (p - t[k][free]) % p;
        }
        basis.push(v);
    }
    basis
}

/// Berlekamp subalgebra basis {v : v^p = v mod f} of a monic square-free `f` over F_p,
/// as polynomials; its size is the number of irreducible factors of `f`.
fn berlekamp_basis(f: &[u64], p: u64) -> Vec<Vec<u64>> {
    let n = f.len() - 1;
    let xp = fp_x_pow_mod(p, f, p);
    // rows[i] = x^{ip} mod f - x^i
    let mut rows: Vec<Vec<u64>> = Vec::with_capacity(n);
    let mut cur = vec![1u64];
    for i in 0..n {
        let mut row = cur.clone();
        row.resize(n, 0);
        row[i] = (row[i] + p - 1) % p;
        rows.push(row);
        if i + 1 < n {
            cur = fp_rem(&fp_mul(&cur, &xp, p), f, p);
        }
    }
    // v is in the kernel iff sum_i v_i rows[i] = 0, i.e. rows^T v = 0.
    let t: Vec<Vec<u64>> = (0..n)
        .map(|j| (0..n).map(|i| rows[i][j]).collect())
        .collect();
    fp_nullspace(t, p).into_iter().map(fp_trim).collect()
}

/// Splits a monic square-free `f` into its monic irreducible factors over F_p (Berlekamp,
/// deterministic: every basis vector is tried against every constant s in F_p).
fn berlekamp_split(f: &[u64], basis: &[Vec<u64>], p: u64) -> Vec<Vec<u64>> {
    let r = basis.len();
    let mut facs = vec![f.to_vec()];
    for v in basis.iter().filter(|v| v.len() >= 2) {
        if facs.len() >= r {
            break;
        }
        let mut next = Vec::new();
        for u in facs {
            let mut rest = u;
            for s in 0..p {
                if rest.len() <= 2 {
                    break;
                }
                let mut w = v.clone();
                w[0] = (w[0] + p - s) % p;
                let g = fp_gcd(&rest, &w, p);
                if g.len() == rest.len() {
                    break;
                }
                if g.len() > 1 {
                    rest = fp_divrem(&rest, &g, p).0;
                    next.push(g);
                }
            }
            next.push(rest);
        }
        facs = next;
    }
    facs.sort_by(|a, b| a.len().cmp(&b.len()).then_with(|| a.cmp(b)));
    facs
}

fn is_small_prime(n: u64) -> bool {
    if n < 2 {
        return false;
    }
    let mut d = 2;
    while d * d <= n {
        if Integer::is_multiple_of(&n, &d) {
            return false;
        }
        d += 1;
    }
    true
}

// ---------------------------------------------------------------------------
// Zassenhaus factorisation over Z.
// ---------------------------------------------------------------------------

/// Number of admissible primes whose Berlekamp factor counts are compared.
const PRIMES_TO_COMPARE: usize = 5;
/// Largest prime tried before giving up.
const MAX_PRIME: u64 = 1 << 30;
/// Maximal number of recombination candidates tried before giving up.
const MAX_RECOMBINATION_TRIALS: u64 = 2_000_000;

/// Lifts `f ≡ g0*h0 (mod p)` (f monic with coefficients mod p^k, g0, h0 monic coprime mod p)
/// to monic `g, h` with coefficients in [0, p^k) and `f ≡ g*h (mod p^k)` (linear Hensel lifting).
fn hensel_lift_two(
    f: &[BigInt],
    g0: &[u64],
    h0: &[u64],
    p: u64,
    k: u32,
) -> (Vec<BigInt>, Vec<BigInt>) {
    let (one, s, t) = fp_ext_gcd(g0, h0, p);
    debug_assert_eq!(one, vec![1]);
    let to_z = |v: &[u64]| v.iter().map(|&c| BigInt::from(c)).collect::<Vec<_>>();
    let (mut g, mut h) = (to_z(g0), to_z(h0));
    let pb = BigInt::from(p);
    let mut pj = pb.clone();
    for _ in 1..k {
        let gh = zp_mul(&g, &h);
        let n = f.len().max(gh.len());
        let z = BigInt::zero();
        let e: Vec<u64> = fp_trim(
            (0..n)
                .map(|i| {
                    let d = f.get(i).unwrap_or(&z) - gh.get(i).unwrap_or(&z);
                    debug_assert!((&d % &pj).is_zero());
                    (d / &pj).mod_floor(&pb).to_u64().expect("residue fits u64")
                })
                .collect(),
        );
        if !e.is_empty() {
            let (q, dg) = fp_divrem(&fp_mul(&e, &t, p), g0, p);
            let dh = fp_add(&fp_mul(&e, &s, p), &fp_mul(&q, h0, p), p);
            for (i, c) in dg.iter().enumerate() {
                g[i] += &pj * c;
            }
            for (i, c) in dh.iter().enumerate() {
                h[i] += &pj * c;
            }
        }
        pj *= &pb;
    }
    (g, h)
}

/// Multifactor Hensel lifting by balanced binary splitting of `facs` (monic, pairwise coprime
/// mod p, product ≡ f mod p). Returns the lifts, in the order of `facs`.
fn hensel_lift_all(f: &[BigInt], facs: &[Vec<u64>], p: u64, k: u32) -> Vec<Vec<BigInt>> {
    if facs.len() == 1 {
        return vec![f.to_vec()];
    }
    let mid = facs.len() / 2;
    let prod = |fs: &[Vec<u64>]| fs.iter().fold(vec![1u64], |a, b| fp_mul(&a, b, p));
    let (g, h) = hensel_lift_two(f, &prod(&facs[..mid]), &prod(&facs[mid..]), p, k);
    let mut out = hensel_lift_all(&g, &facs[..mid], p, k);
    out.extend(hensel_lift_all(&h, &facs[mid..], p, k));
    out
}

/// Advances `comb` (strictly increasing indices < n) to the next combination; false at the end.
fn next_combination(comb: &mut [usize], n: usize) -> bool {
    let s = comb.len();
    for i in (0..s).rev() {
        if comb[i] < n - s + i {
            comb[i] += 1;
            for j in i + 1..s {
                comb[j] = comb[j - 1] + 1;
            }
            return true;
        }
    }
    false
}

/// Irreducible factors over Z of a primitive square-free `g` (positive leading coefficient).
fn zassenhaus(g: &[BigInt]) -> Result<Vec<Vec<BigInt>>, String> {
    let n = g.len() - 1;
    if n <= 1 {
        return Ok(vec![g.to_vec()]);
    }
    let lc = g[n].clone();

    // Choose the admissible prime with the fewest modular factors.
    let mut best: Option<(u64, Vec<u64>, Vec<Vec<u64>>)> = None;
    let mut good = 0;
    let mut p = 3u64;
    while good < PRIMES_TO_COMPARE {
        if p > MAX_PRIME {
            if best.is_some() {
                break;
            }
            return Err(format!(
                "factor: no admissible prime below {MAX_PRIME} for a polynomial of degree {n}"
            ));
        }
        if is_small_prime(p) && !(&lc % p).is_zero() {
            let gp = fp_monic(&fp_from_z(g, p), p);
            if fp_gcd(&gp, &fp_deriv(&gp, p), p).len() == 1 {
                let basis = berlekamp_basis(&gp, p);
                if basis.len() == 1 {
                    return Ok(vec![g.to_vec()]);
                }
                let better = match &best {
                    None => true,
                    Some(b) => basis.len() < b.2.len(),
                };
                if better {
                    best = Some((p, gp, basis));
                }
                good += 1;
            }
        }
        p += 2;
    }
    let (p, gp, basis) = best.expect("an admissible prime was found");
    let modular = berlekamp_split(&gp, &basis, p);

    // Coefficients of lc(g)/lc(h) * h for any factor h of g are below
    // |lc| * 2^n * ||g||_2 (Mignotte); lift until p^k exceeds twice that.
    let norm2: BigInt = g.iter().map(|c| c * c).sum();
    let bound = BigInt::from(2) * lc.abs() * (BigInt::one() << n) * (norm2.sqrt() + 1);
    let pb = BigInt::from(p);
    let (mut pk, mut k) = (pb.clone(), 1u32);
    while pk <= bound {
        pk *= &pb;
        k += 1;
    }
    let lc_inv = lc.mod_floor(&pk).modinv(&pk).expect("lc is a unit mod p^k");
    let f: Vec<BigInt> = g.iter().map(|c| (c * &lc_inv).mod_floor(&pk)).collect();
    let mut remaining = hensel_lift_all(&f, &modular, p, k);

    // Recombination: subsets in increasing size, exact trial division over Z.
    let half = &pk >> 1;
    let mut g = g.to_vec();
    let mut out = Vec::new();
    let mut trials = 0u64;
    let mut s = 1;
    while 2 * s <= remaining.len() {
        let lcg = g.last().expect("nonzero").mod_floor(&pk);
        let mut comb: Vec<usize> = (0..s).collect();
        let mut found = false;
        loop {
            trials += 1;
            if trials > MAX_RECOMBINATION_TRIALS {
                return Err(format!(
                    "factor: recombination of {} modular factors (degree {n}) exceeds {MAX_RECOMBINATION_TRIALS} trials",
                    remaining.len() + out.len()
                ));
            }
            let mut cand = vec![lcg.clone()];
            for &i in &comb {
                cand = zp_mul(&cand, &remaining[i])
                    .into_iter()
                    .map(|c| c.mod_floor(&pk))
                    .collect();
            }
            for c in &mut cand {
                if *c > half {
                    *c -= &pk;
                }
            }
            let cand = zp_primitive(cand);
            if let Some(q) = zp_div_exact(&g, &cand) {
                out.push(cand);
                g = q;
                for &i in comb.iter().rev() {
                    remaining.remove(i);
                }
                found = true;
                break;
            }
            if !next_combination(&mut comb, remaining.len()) {
                break;
            }
        }
        if !found {
            s += 1;
        }
    }
    out.push(zp_primitive(g));
    Ok(out)
}

/// True if `g mod p` is square-free of full degree for one of the first few odd primes
/// (a sufficient condition for `g` to be square-free over Q).
fn is_square_free_mod_small_prime(g: &[BigInt]) -> bool {
    let lc = g.last().expect("nonzero");
    (3u64..200).filter(|&p| is_small_prime(p)).any(|p| {
        if (lc % p).is_zero() {
            return false;
        }
        let gp = fp_monic(&fp_from_z(g, p), p);
        fp_gcd(&gp, &fp_deriv(&gp, p), p).len() == 1
    })
}

/// Yun's square-free decomposition of a nonzero polynomial: pairwise coprime monic
/// square-free `a_i` of positive degree with `f = c * prod a_i^i`.
fn yun(f: &QPoly) -> Vec<(QPoly, usize)> {
    let df = f.derivative();
    let a0 = f.gcd(&df);
    let mut b = f.div_rem(&a0).0;
    let mut d = df.div_rem(&a0).0.sub(&b.derivative());
    let mut i = 1;
    let mut out = Vec::new();
    while b.degree().unwrap_or(0) > 0 {
        let a = b.gcd(&d);
        b = b.div_rem(&a).0;
        d = d.div_rem(&a).0.sub(&b.derivative());
        if a.degree().unwrap_or(0) > 0 {
            out.push((a, i));
        }
        i += 1;
    }
    out
}

/// Complete factorisation over Q into distinct irreducible factors, each returned as a
/// primitive integer polynomial (positive leading coefficient), with multiplicity.
/// Product of factor^mult equals `p` up to a rational constant (a nonzero constant gives
/// an empty list). Sorted by degree, then by coefficient vector (constant term first).
///
/// Algorithm: Yun square-free decomposition, then Zassenhaus on each part (Berlekamp
/// modulo the best of several small primes, Hensel lifting above the Mignotte bound,
/// recombination by subset size with exact trial division). Deterministic.
///
/// Errors on the zero polynomial, or (never in practice for degrees ≲ 40) if recombination
/// exceeds its trial budget.
pub fn factor(p: &QPoly) -> Result<Vec<(QPoly, usize)>, String> {
    if p.is_zero() {
        return Err("factor: the zero polynomial has no factorisation".to_string());
    }
    if p.degree() == Some(0) {
        return Ok(Vec::new());
    }
    let z = p.primitive_integer();
    // Fast path: square-free modulo a small prime not dividing lc implies square-free.
    let parts = if is_square_free_mod_small_prime(&z) {
        vec![(QPoly::from_bigints(&z), 1)]
    } else {
        yun(&p.monic())
    };
    let mut out = Vec::new();
    for (a, mult) in parts {
        for fac in zassenhaus(&a.primitive_integer())? {
            out.push((QPoly::from_bigints(&fac), mult));
        }
    }
    out.sort_by(|a, b| cmp_qpoly(&a.0, &b.0));
    Ok(out)
}

// ---------------------------------------------------------------------------
// Sturm sequences and real roots.
// ---------------------------------------------------------------------------

/// Sturm sequence of the square-free part of a polynomial, for counting distinct real roots.
#[derive(Clone, Debug)]
pub struct Sturm {
    /// Positive integer multiples of the Sturm chain p0 = sqfree(p), p1 = p0', ...
    chain: Vec<Vec<BigInt>>,
}

impl Sturm {
    /// Builds the chain of `p`'s square-free part (so any nonzero `p` is accepted;
    /// zero gives an empty chain counting no roots).
    pub fn new(p: &QPoly) -> Self {
        if p.is_zero() {
            return Sturm { chain: Vec::new() };
        }
        let q = p.square_free();
        let mut chain = vec![zp_positive_multiple(&q)];
        let d = q.derivative();
        if !d.is_zero() {
            chain.push(zp_positive_multiple(&d));
        }
        while chain.len() >= 2 {
            let n = chain.len();
            let r = zp_prem_positive(&chain[n - 2], &chain[n - 1]);
            if r.is_empty() {
                break;
            }
            let r: Vec<BigInt> = r.iter().map(|c| -c).collect();
            chain.push(zp_positive_multiple(&QPoly::from_bigints(&r)));
        }
        Sturm { chain }
    }

    fn variations(&self, x: &BigRational) -> usize {
        let mut last = 0i8;
        let mut v = 0;
        for s in self.chain.iter().map(|c| zp_sign_at(c, x)) {
            if s != 0 {
                if last != 0 && s != last {
                    v += 1;
                }
                last = s;
            }
        }
        v
    }

    /// Number of distinct real roots in the half-open interval (lo, hi] (0 if lo >= hi).
    pub fn count_roots(&self, lo: &BigRational, hi: &BigRational) -> usize {
        if lo >= hi {
            return 0;
        }
        self.variations(lo).saturating_sub(self.variations(hi))
    }
}

/// A rational bound B with all real roots in (-B, B) (Cauchy bound 1 + max|a_i/a_n|),
/// for nonzero p of degree ≥ 1 (a nonzero constant gives 1).
///
/// # Panics
/// Panics on the zero polynomial.
pub fn root_bound(p: &QPoly) -> BigRational {
    let l = p.leading().expect("root_bound: zero polynomial").abs();
    let m = p.0[..p.0.len() - 1]
        .iter()
        .map(|c| c.abs() / &l)
        .max()
        .unwrap_or_else(BigRational::zero);
    m + BigRational::one()
}

/// Smallest power of two (exponent ≥ 0) that is ≥ `b`.
fn pow2_at_least(b: &BigRational) -> BigRational {
    let mut r = BigRational::one();
    while &r < b {
        r *= BigRational::from_integer(BigInt::from(2));
    }
    r
}

/// Disjoint isolating intervals (lo, hi], lo < hi, sorted increasingly, each containing exactly
/// one real root of p (p need not be square-free: its square-free part is used). Exact, by
/// Sturm + bisection of (-2^e, 2^e] ⊇ the Cauchy interval, so endpoints are dyadic.
/// Zero or constant p gives no intervals.
pub fn isolate_real_roots(p: &QPoly) -> Vec<(BigRational, BigRational)> {
    if p.degree().unwrap_or(0) == 0 {
        return Vec::new();
    }
    let q = p.square_free();
    let st = Sturm::new(&q);
    let b = pow2_at_least(&root_bound(&q));
    let lo = -b.clone();
    let total = st.count_roots(&lo, &b);
    let two = BigRational::from_integer(BigInt::from(2));
    let mut out = Vec::new();
    let mut stack = vec![(lo, b, total)];
    while let Some((lo, hi, cnt)) = stack.pop() {
        match cnt {
            0 => {}
            1 => out.push((lo, hi)),
            _ => {
                let mid = (&lo + &hi) / &two;
                let left = st.count_roots(&lo, &mid);
                stack.push((mid.clone(), hi, cnt - left));
                stack.push((lo, mid, left));
            }
        }
    }
    out
}

/// Given p with exactly one root in (lo, hi] and a sign change or a root at hi, bisect until
/// hi - lo <= width; returns the new interval (lo', hi'] ⊆ (lo, hi] still containing the root.
///
/// Uses sign evaluation when p(lo), p(hi) have opposite signs (always the case for an
/// irreducible p of degree ≥ 2); a root hit exactly at hi or a midpoint r gives
/// (max(lo, r - width/2), r]. Otherwise falls back to Sturm bisection.
///
/// # Panics
/// Panics if p is zero, lo >= hi or width <= 0.
pub fn refine_root(
    p: &QPoly,
    lo: &BigRational,
    hi: &BigRational,
    width: &BigRational,
) -> (BigRational, BigRational) {
    assert!(!p.is_zero(), "refine_root: zero polynomial");
    assert!(lo < hi, "refine_root: empty interval");
    assert!(width.is_positive(), "refine_root: width must be positive");
    let (mut lo, mut hi) = (lo.clone(), hi.clone());
    if &hi - &lo <= *width {
        return (lo, hi);
    }
    let two = BigRational::from_integer(BigInt::from(2));
    let half_w = width / &two;
    let z = zp_positive_multiple(p);
    let s_hi = zp_sign_at(&z, &hi);
    if s_hi == 0 {
        let l = (&hi - &half_w).max(lo);
        return (l, hi);
    }
    let s_lo = zp_sign_at(&z, &lo);
    if s_lo == -s_hi {
        while &hi - &lo > *width {
            let mid = (&lo + &hi) / &two;
            let s = zp_sign_at(&z, &mid);
            if s == 0 {
                // hi - lo > width, so mid - width/2 > lo.
                return (&mid - &half_w, mid);
            }
            if s == s_lo {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    } else {
        let st = Sturm::new(p);
        while &hi - &lo > *width {
            let mid = (&lo + &hi) / &two;
            if st.count_roots(&lo, &mid) >= 1 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> BigRational {
        BigRational::new(BigInt::from(n), BigInt::from(d))
    }

    fn ints(c: &[i64]) -> QPoly {
        QPoly::from_ints(c)
    }

    fn pow(p: &QPoly, e: usize) -> QPoly {
        (0..e).fold(QPoly::one(), |a, _| a.mul(p))
    }

    /// Deterministic 64-bit LCG.
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            self.0 >> 33
        }
        fn range(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % (hi - lo + 1) as u64) as i64
        }
    }

    /// p(M) over Z by Horner.
    fn eval_at_matrix(p: &QPoly, m: &[Vec<i64>]) -> Vec<Vec<BigInt>> {
        let n = m.len();
        let a: Vec<Vec<BigInt>> = m
            .iter()
            .map(|r| r.iter().map(|&x| BigInt::from(x)).collect())
            .collect();
        let mut acc = vec![vec![BigInt::zero(); n]; n];
        for c in p.coeffs().iter().rev() {
            assert!(c.is_integer());
            acc = mat_mul(&acc, &a);
            for (i, row) in acc.iter_mut().enumerate() {
                row[i] += c.to_integer();
            }
        }
        acc
    }

    /// det by fraction-free Bareiss elimination (independent of Faddeev–LeVerrier).
    fn det_bareiss(mut a: Vec<Vec<BigInt>>) -> BigInt {
        let n = a.len();
        let mut sign = BigInt::one();
        let mut prev = BigInt::one();
        for k in 0..n {
            if a[k][k].is_zero() {
                match (k + 1..n).find(|&i| !a[i][k].is_zero()) {
                    Some(i) => {
                        a.swap(i, k);
                        sign = -sign;
                    }
                    None => return BigInt::zero(),
                }
            }
            for i in k + 1..n {
                for j in k + 1..n {
                    a[i][j] = (&a[i][j] * &a[k][k] - &a[i][k] * &a[k][j]) / &prev;
                }
            }
            prev = a[k][k].clone();
        }
        if n == 0 {
            return BigInt::one();
        }
        sign * &a[n - 1][n - 1]
    }

    fn check_factorisation(p: &QPoly, facs: &[(QPoly, usize)]) {
        let prod = facs
            .iter()
            .fold(QPoly::one(), |acc, (f, m)| acc.mul(&pow(f, *m)));
        assert_eq!(prod.monic(), p.monic(), "product of factors");
        for (f, _) in facs {
            assert!(f.leading().unwrap().is_positive());
            assert_eq!(QPoly::from_bigints(&f.primitive_integer()), *f);
        }
        for w in facs.windows(2) {
            assert_eq!(cmp_qpoly(&w[0].0, &w[1].0), Ordering::Less, "sorted");
        }
    }

    fn assert_factors(p: &QPoly, expected: &[(&[i64], usize)]) {
        let facs = factor(p).unwrap();
        check_factorisation(p, &facs);
        let exp: Vec<(QPoly, usize)> = expected.iter().map(|(c, m)| (ints(c), *m)).collect();
        assert_eq!(facs, exp, "factorisation of {p}");
    }

    fn assert_irreducible(p: &QPoly) {
        let f = QPoly::from_bigints(&p.primitive_integer());
        assert_eq!(
            factor(p).unwrap(),
            vec![(f, 1)],
            "{p} should be irreducible"
        );
    }

    #[test]
    fn arithmetic_and_display() {
        let a = ints(&[-2, 0, -1, 1]);
        assert_eq!(a.to_string(), "x^3 - x^2 - 2");
        assert_eq!(QPoly::new(vec![q(3, 1), q(1, 2)]).to_string(), "1/2 x + 3");
        assert_eq!(ints(&[0, -3, 0, -1]).to_string(), "-x^3 - 3 x");
        assert_eq!(QPoly::zero().to_string(), "0");
        assert_eq!(QPoly::new(vec![q(1, 1), q(0, 1)]), QPoly::one());
        assert_eq!(QPoly::x().degree(), Some(1));
        assert_eq!(QPoly::zero().degree(), None);
        let b = ints(&[1, 2, 3]);
        let (qq, r) = a.div_rem(&b);
        assert_eq!(qq.mul(&b).add(&r), a);
        assert!(r.degree().unwrap() < 2);
        assert_eq!(a.sub(&a), QPoly::zero());
        assert_eq!(a.add(&a.neg()), QPoly::zero());
        assert_eq!(a.scale(&q(2, 1)), a.add(&a));
        assert_eq!(a.eval(&q(2, 1)), q(2, 1));
        assert_eq!(a.sign_at(&q(3, 2)), -1);
        assert_eq!(ints(&[-1, 1]).sign_at(&q(1, 1)), 0);
        assert_eq!(a.derivative(), ints(&[0, -2, 3]));
        // gcd / ext_gcd
        let g = ints(&[-1, 1]).mul(&ints(&[1, 0, 1]));
        let u = g.mul(&ints(&[5, 7, 1])).scale(&q(3, 4));
        let v = g.mul(&ints(&[2, -1]));
        assert_eq!(u.gcd(&v), g);
        let (gg, s, t) = u.ext_gcd(&v);
        assert_eq!(gg, g);
        assert_eq!(s.mul(&u).add(&t.mul(&v)), g);
        assert_eq!(QPoly::zero().gcd(&QPoly::zero()), QPoly::zero());
        let (g0, s0, t0) = QPoly::zero().ext_gcd(&ints(&[2, 4]));
        assert_eq!(g0, ints(&[1, 2]).monic());
        assert_eq!(s0.mul(&QPoly::zero()).add(&t0.mul(&ints(&[2, 4]))), g0);
        // primitive integer and square-free part
        let h = QPoly::new(vec![q(-1, 2), q(0, 1), q(-3, 4)]);
        assert_eq!(
            h.primitive_integer(),
            vec![BigInt::from(2), BigInt::zero(), BigInt::from(3)]
        );
        let sq = pow(&ints(&[-1, 1]), 3).mul(&ints(&[2, 1]));
        assert_eq!(sq.square_free(), ints(&[-2, 1, 1]));
    }

    #[test]
    fn char_poly_fibonacci() {
        assert_eq!(char_poly(&[vec![1, 1], vec![1, 0]]), ints(&[-1, -1, 1]));
        assert_eq!(char_poly(&[]), QPoly::one());
        assert_eq!(char_poly(&[vec![5]]), ints(&[-5, 1]));
    }

    #[test]
    fn char_poly_lsystem_5x5() {
        // Symbols S, L, C, D, R. Column S is zero, so det(xI - M) = x * det(xI - M'),
        // M' on (L, C, D, R) = [[1,1,0,0],[0,0,0,1],[1,0,0,0],[0,0,1,1]]. Expanding
        // det(xI - M') along its rows gives x^4 - 2x^3 + x^2 - 1 = (x^2-x-1)(x^2-x+1),
        // hence x^5 - 2x^4 + x^3 - x.
        let m = vec![
            vec![0, 1, 0, 0, 1],
            vec![0, 1, 1, 0, 0],
            vec![0, 0, 0, 0, 1],
            vec![0, 1, 0, 0, 0],
            vec![0, 0, 0, 1, 1],
        ];
        let p = char_poly(&m);
        assert_eq!(p, ints(&[0, -1, 0, 1, -2, 1]));
        // Independent check: det(tI - M) by Bareiss at several integer points.
        for t in -4..=4i64 {
            let a: Vec<Vec<BigInt>> = (0..5)
                .map(|i| {
                    (0..5)
                        .map(|j| BigInt::from(if i == j { t } else { 0 } - m[i][j]))
                        .collect()
                })
                .collect();
            assert_eq!(rat(det_bareiss(a)), p.eval(&rat(BigInt::from(t))));
        }
        // Cayley–Hamilton.
        assert!(eval_at_matrix(&p, &m).iter().flatten().all(Zero::is_zero));
        let facs = factor(&p).unwrap();
        check_factorisation(&p, &facs);
        assert!(facs.contains(&(ints(&[-1, -1, 1]), 1)));
        assert_factors(&p, &[(&[0, 1], 1), (&[-1, -1, 1], 1), (&[1, -1, 1], 1)]);
    }

    #[test]
    fn cayley_hamilton_random() {
        let mut rng = Lcg(12345);
        for n in 1..=9 {
            for round in 0..3 {
                let (lo, hi) = if round == 0 { (-3, 3) } else { (0, 4) };
                let m: Vec<Vec<i64>> = (0..n)
                    .map(|_| (0..n).map(|_| rng.range(lo, hi)).collect())
                    .collect();
                let p = char_poly(&m);
                assert_eq!(p.degree(), Some(n));
                assert!(p.leading().unwrap().is_one());
                let tr: i64 = (0..n).map(|i| m[i][i]).sum();
                assert_eq!(p.coeffs()[n - 1], rat(BigInt::from(-tr)));
                assert!(eval_at_matrix(&p, &m).iter().flatten().all(Zero::is_zero));
                let a: Vec<Vec<BigInt>> = m
                    .iter()
                    .map(|r| r.iter().map(|&x| BigInt::from(-x)).collect())
                    .collect();
                assert_eq!(
                    rat(det_bareiss(a)),
                    p.coeffs().first().cloned().unwrap_or_default()
                );
            }
        }
    }

    #[test]
    fn factor_x_n_minus_2_irreducible() {
        for n in 2..=7 {
            let mut c = vec![0i64; n + 1];
            c[0] = -2;
            c[n] = 1;
            assert_irreducible(&ints(&c));
        }
    }

    #[test]
    fn factor_cubics_irreducible() {
        assert_irreducible(&ints(&[-2, 0, -1, 1]));
        assert_irreducible(&ints(&[-1, 0, -1, 1]));
        // Swinnerton-Dyer polynomials: reducible modulo every prime.
        assert_irreducible(&ints(&[1, 0, -10, 0, 1]));
        assert_irreducible(&ints(&[576, 0, -960, 0, 352, 0, -40, 0, 1]));
    }

    #[test]
    fn factor_small_cases() {
        assert_factors(&ints(&[3, -4, 1]), &[(&[-3, 1], 1), (&[-1, 1], 1)]);
        assert_factors(
            &ints(&[-1, 0, 0, 0, 1]),
            &[(&[-1, 1], 1), (&[1, 1], 1), (&[1, 0, 1], 1)],
        );
        // (1/2 x + 1/3)(x^2 + 1) * 5/7
        let p = QPoly::new(vec![q(1, 3), q(1, 2)])
            .mul(&ints(&[1, 0, 1]))
            .scale(&q(5, 7));
        assert_factors(&p, &[(&[2, 3], 1), (&[1, 0, 1], 1)]);
        assert!(factor(&QPoly::zero()).is_err());
        assert_eq!(factor(&ints(&[-7])).unwrap(), vec![]);
        assert_factors(&ints(&[0, 0, 0, 2]), &[(&[0, 1], 3)]);
    }

    #[test]
    fn factor_multiplicities() {
        let p = pow(&ints(&[-2, 0, 1]), 2).mul(&ints(&[-1, -1, 1]));
        assert_factors(&p, &[(&[-2, 0, 1], 2), (&[-1, -1, 1], 1)]);
        let p = p
            .mul(&pow(&ints(&[1, 1]), 3))
            .mul(&pow(&ints(&[-2, 0, -1, 1]), 4))
            .scale(&q(-3, 5));
        assert_factors(
            &p,
            &[
                (&[1, 1], 3),
                (&[-2, 0, 1], 2),
                (&[-1, -1, 1], 1),
                (&[-2, 0, -1, 1], 4),
            ],
        );
    }

    #[test]
    fn factor_product_of_quartics() {
        // Eisenstein at 3 and at 5 respectively, hence irreducible.
        let a: &[i64] = &[3 * 1001, 3 * 8191, -3 * 4567, 3 * 1237, 7];
        let b: &[i64] = &[5 * 2718, -5 * 31415, 5 * 777, -5 * 2345, 11];
        let p = ints(a).mul(&ints(b));
        assert_factors(&p, &[(a, 1), (b, 1)]);
    }

    #[test]
    fn factor_degree_12() {
        let fs: [&[i64]; 4] = [
            &[-1, -1, 1],       // x^2 - x - 1
            &[-2, 0, 0, 1],     // x^3 - 2 (Eisenstein)
            &[-2, 0, -1, 1],    // x^3 - x^2 - 2 (no rational root)
            &[14, 7, 0, 21, 5], // Eisenstein at 7
        ];
        let p = fs.iter().fold(QPoly::one(), |acc, f| acc.mul(&ints(f)));
        assert_eq!(p.degree(), Some(12));
        let facs = factor(&p).unwrap();
        check_factorisation(&p, &facs);
        assert_eq!(facs.len(), 4);
        for f in fs {
            assert!(facs.contains(&(ints(f), 1)));
        }
    }

    #[test]
    fn factor_degree_16_large_coefficients() {
        // Four quartics, Eisenstein at 2, 3, 5, 7; coefficients up to ~10^6.
        let fs: [&[i64]; 4] = [
            &[2 * 499_999, 2 * 123_457, -2 * 98_765, 2 * 31_337, 999_983],
            &[
                3 * 333_331,
                -3 * 271_828,
                3 * 141_421,
                3 * 173_205,
                1_000_003,
            ],
            &[5 * 199_999, 5 * 161_803, -5 * 57_721, -5 * 66_743, 999_979],
            &[
                7 * 142_857,
                -7 * 111_111,
                7 * 123_456,
                7 * 100_001,
                1_000_033,
            ],
        ];
        let p = fs.iter().fold(QPoly::one(), |acc, f| acc.mul(&ints(f)));
        let facs = factor(&p).unwrap();
        check_factorisation(&p, &facs);
        assert_eq!(facs.len(), 4);
        for f in fs {
            assert!(facs.contains(&(ints(f), 1)), "missing {}", ints(f));
        }
    }

    #[test]
    fn factor_random_products_consistent() {
        let mut rng = Lcg(2024);
        for _ in 0..12 {
            let k = rng.range(2, 4) as usize;
            let mut p = QPoly::one();
            let mut parts = Vec::new();
            for _ in 0..k {
                let d = rng.range(1, 4) as usize;
                let mut c: Vec<i64> = (0..d).map(|_| rng.range(-9, 9)).collect();
                c.push(rng.range(1, 6));
                let m = rng.range(1, 2) as usize;
                let f = ints(&c);
                p = p.mul(&pow(&f, m));
                parts.push((f, m));
            }
            let facs = factor(&p).unwrap();
            check_factorisation(&p, &facs);
            // Every factor of every part appears with at least the expected multiplicity.
            for (f, m) in &parts {
                for (g, e) in factor(f).unwrap() {
                    let found = facs.iter().find(|(h, _)| *h == g).expect("factor present");
                    assert!(found.1 >= e * m);
                }
            }
            // Returned factors are irreducible (stable under re-factorisation).
            for (g, _) in &facs {
                assert_eq!(factor(g).unwrap(), vec![(g.clone(), 1)]);
            }
        }
        // Non-monic linear factors and a Swinnerton-Dyer factor.
        let p = ints(&[-1, 2])
            .mul(&ints(&[5, 3]))
            .mul(&ints(&[-11, 7]))
            .mul(&ints(&[1, 0, -10, 0, 1]));
        assert_factors(
            &p,
            &[
                (&[-11, 7], 1),
                (&[-1, 2], 1),
                (&[5, 3], 1),
                (&[1, 0, -10, 0, 1], 1),
            ],
        );
    }

    #[test]
    fn sturm_close_roots() {
        // (x - 1/1000)(x - 2/1000)(x - 1)
        let p = QPoly::new(vec![q(-1, 1000), q(1, 1)])
            .mul(&QPoly::new(vec![q(-2, 1000), q(1, 1)]))
            .mul(&ints(&[-1, 1]));
        let st = Sturm::new(&p);
        assert_eq!(st.count_roots(&q(-10, 1), &q(10, 1)), 3);
        assert_eq!(st.count_roots(&q(0, 1), &q(15, 10000)), 1);
        assert_eq!(st.count_roots(&q(1, 1000), &q(2, 1000)), 1); // (a, b] includes b only
        assert_eq!(st.count_roots(&q(0, 1), &q(1, 1000)), 1);
        assert_eq!(st.count_roots(&q(1, 1000), &q(1, 1)), 2);
        assert_eq!(st.count_roots(&q(1, 1), &q(5, 1)), 0);
        assert_eq!(st.count_roots(&q(3, 1), &q(-3, 1)), 0);
        let iv = isolate_real_roots(&p);
        let roots = [q(1, 1000), q(2, 1000), q(1, 1)];
        assert_eq!(iv.len(), 3);
        for (i, (lo, hi)) in iv.iter().enumerate() {
            assert!(lo < hi);
            assert!(*lo < roots[i] && roots[i] <= *hi);
            assert_eq!(st.count_roots(lo, hi), 1);
            if i > 0 {
                assert!(iv[i - 1].1 <= *lo);
            }
        }
        // Multiple roots: (x-1)^3 (x+2)^2 has two distinct real roots.
        let m = pow(&ints(&[-1, 1]), 3).mul(&pow(&ints(&[2, 1]), 2));
        let iv = isolate_real_roots(&m);
        assert_eq!(iv.len(), 2);
        assert!(iv[0].0 < q(-2, 1) && q(-2, 1) <= iv[0].1);
        assert!(iv[1].0 < q(1, 1) && q(1, 1) <= iv[1].1);
        assert!(isolate_real_roots(&ints(&[1, 0, 1])).is_empty());
        assert!(isolate_real_roots(&ints(&[3])).is_empty());
    }

    #[test]
    fn root_bound_is_cauchy() {
        let p = ints(&[-2, 0, -1, 1]);
        assert_eq!(root_bound(&p), q(3, 1));
        let p = ints(&[6, -5, 1]).scale(&q(1, 2)); // roots 2, 3
        let b = root_bound(&p);
        assert!(b > q(3, 1));
    }

    #[test]
    fn largest_root_of_cubic() {
        let p = ints(&[-2, 0, -1, 1]); // x^3 - x^2 - 2, real root ~ 1.6956207696
        let iv = isolate_real_roots(&p);
        assert_eq!(iv.len(), 1);
        let (lo, hi) = refine_root(&p, &iv[0].0, &iv[0].1, &q(1, 1_000_000));
        assert!(&hi - &lo <= q(1, 1_000_000));
        assert!(q(16956, 10000) < lo && hi < q(16957, 10000));
        assert_eq!(p.sign_at(&q(16956, 10000)), -1);
        assert_eq!(p.sign_at(&q(16957, 10000)), 1);
    }

    #[test]
    fn refine_root_below_2_pow_minus_80() {
        let w = BigRational::new(BigInt::one(), BigInt::one() << 80);
        for p in [
            ints(&[-2, 0, 1]),
            ints(&[-1, -1, 1]),
            ints(&[-2, 0, -1, 1]),
            ints(&[0, -1, 0, 1, -2, 1]),
        ] {
            let st = Sturm::new(&p);
            for (lo, hi) in isolate_real_roots(&p) {
                let (l, h) = refine_root(&p, &lo, &hi, &w);
                assert!(l < h && &h - &l <= w);
                assert!(lo <= l && h <= hi);
                assert_eq!(st.count_roots(&l, &h), 1);
            }
        }
        // Rational roots: exactly at a midpoint, at hi, and off-dyadic.
        let p = ints(&[-1, 2]); // root 1/2
        let (l, h) = refine_root(&p, &q(0, 1), &q(1, 1), &w);
        assert_eq!(h, q(1, 2));
        assert!(l < h && &h - &l <= w);
        let (l, h) = refine_root(&p, &q(0, 1), &q(1, 2), &w);
        assert!(l < q(1, 2) && h == q(1, 2) && &h - &l <= w);
        let p = ints(&[-1, 3]); // root 1/3
        let (l, h) = refine_root(&p, &q(0, 1), &q(1, 1), &w);
        assert!(l < q(1, 3) && q(1, 3) <= h && &h - &l <= w);
        // Double root (no sign change): Sturm fallback.
        let p = pow(&ints(&[-1, 3]), 2);
        let (l, h) = refine_root(&p, &q(0, 1), &q(1, 1), &w);
        assert!(l < q(1, 3) && q(1, 3) <= h && &h - &l <= w);
    }
}
