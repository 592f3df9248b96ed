//! The exact number field Q(ρ), ρ the Perron root of an L-system's matrix (\[N\] eq. (4)).
//!
//! A field is its monic minimal polynomial over Q plus an isolating interval of ρ. An element is
//! its coordinate vector on the power basis 1, ρ, …, ρ^(d−1): canonical, so equality and hashing
//! are structural. Sign and order are decided exactly by interval evaluation, refining ρ's
//! interval by bisection until the value's interval excludes zero (it must: a nonzero element of
//! degree < d cannot vanish at ρ). No floating point is used except in [`Elem::to_f64`].

use crate::exact::poly::{refine_root, QPoly};
use crate::exact::scheme::parse_rational;
use crate::exact::work::{charge, horner, limbs, Sizes};
use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex};

/// Q(ρ) for a real algebraic ρ given by its minimal polynomial and an isolating interval.
#[derive(Debug)]
pub struct Field {
    minpoly: QPoly,
    /// Isolating interval (lo, hi] of ρ; narrowed in place as signs need more precision.
    interval: Mutex<(BigRational, BigRational)>,
}

/// A shared handle to a field.
pub type FieldRef = Arc<Field>;

impl Field {
    /// Builds Q(ρ) from an irreducible polynomial and an interval (lo, hi] holding ρ alone.
    pub fn new(minpoly: &QPoly, lo: BigRational, hi: BigRational) -> FieldRef {
        Arc::new(Field {
            minpoly: minpoly.monic(),
            interval: Mutex::new((lo, hi)),
        })
    }

    /// Degree of the field over Q.
    pub fn degree(&self) -> usize {
        self.minpoly.degree().unwrap_or(0)
    }

    /// The monic minimal polynomial of ρ.
    pub fn minpoly(&self) -> &QPoly {
        &self.minpoly
    }

    /// The minimal polynomial as primitive integers, constant term first, positive leading term.
    pub fn minpoly_integer(&self) -> Vec<BigInt> {
        self.minpoly.primitive_integer()
    }

    /// The current isolating interval of ρ.
    pub fn interval(&self) -> (BigRational, BigRational) {
        self.interval.lock().expect("field interval lock").clone()
    }

    /// Halves (at least) the width of ρ's isolating interval.
    fn refine(&self) {
        let mut iv = self.interval.lock().expect("field interval lock");
        let width = (&iv.1 - &iv.0) / BigInt::from(2);
        *iv = refine_root(&self.minpoly, &iv.0, &iv.1, &width);
    }

    /// Exact comparison of the generators of two fields (ρ of one scheme against another's): equal
    /// minimal polynomials mean the same root (each field holds its polynomial's largest real
    /// root); otherwise the isolating intervals are refined until they separate, which they do
    /// since distinct irreducible polynomials share no root.
    pub fn cmp_generator(&self, other: &Field) -> Ordering {
        if self.minpoly == other.minpoly {
            return Ordering::Equal;
        }
        loop {
            let ((alo, ahi), (blo, bhi)) = (self.interval(), other.interval());
            if ahi <= blo {
                return Ordering::Less;
            }
            if bhi <= alo {
                return Ordering::Greater;
            }
            self.refine();
            other.refine();
        }
    }

    /// The element ρ.
    pub fn rho(self: &FieldRef) -> Elem {
        if self.degree() == 1 {
            // ρ is rational: minpoly = x - r.
            let r = -self.minpoly.coeffs()[0].clone();
            return Elem::rational(self, r);
        }
        let mut c = vec![BigRational::zero(); self.degree()];
        c[1] = BigRational::one();
        Elem::from_coeffs(self, c)
    }
}

/// An element of Q(ρ), canonical coordinates on 1, ρ, …, ρ^(d−1).
#[derive(Clone)]
pub struct Elem {
    field: FieldRef,
    c: Vec<BigRational>,
}

impl PartialEq for Elem {
    fn eq(&self, o: &Self) -> bool {
        self.c == o.c
    }
}
impl Eq for Elem {}
impl Hash for Elem {
    fn hash<H: Hasher>(&self, h: &mut H) {
        self.c.hash(h)
    }
}

impl Elem {
    /// Reduces an arbitrary polynomial in ρ modulo the minimal polynomial.
    pub fn from_poly(field: &FieldRef, p: &QPoly) -> Elem {
        let r = p.rem(&field.minpoly);
        let mut c = r.coeffs().to_vec();
        c.resize(field.degree(), BigRational::zero());
        Elem {
            field: field.clone(),
            c,
        }
    }

    fn from_coeffs(field: &FieldRef, c: Vec<BigRational>) -> Elem {
        debug_assert_eq!(c.len(), field.degree());
        Elem {
            field: field.clone(),
            c,
        }
    }

    /// The rational number r as an element.
    pub fn rational(field: &FieldRef, r: BigRational) -> Elem {
        let mut c = vec![BigRational::zero(); field.degree()];
        c[0] = r;
        Elem::from_coeffs(field, c)
    }

    /// The integer n as an element.
    pub fn int(field: &FieldRef, n: i64) -> Elem {
        Elem::rational(field, BigRational::from_integer(n.into()))
    }

    /// The zero element.
    pub fn zero(field: &FieldRef) -> Elem {
        Elem::int(field, 0)
    }

    /// The unit element.
    pub fn one(field: &FieldRef) -> Elem {
        Elem::int(field, 1)
    }

    /// The field this element lives in.
    pub fn field(&self) -> &FieldRef {
        &self.field
    }

    /// Coordinates on the power basis 1, ρ, …, ρ^(d−1).
    pub fn coeffs(&self) -> &[BigRational] {
        &self.c
    }

    /// The element as a polynomial in ρ.
    pub fn to_poly(&self) -> QPoly {
        QPoly::new(self.c.clone())
    }

    /// True for the zero element (structural).
    pub fn is_zero(&self) -> bool {
        self.c.iter().all(Zero::is_zero)
    }

    /// Some(r) when the element is the rational r.
    pub fn as_rational(&self) -> Option<&BigRational> {
        self.c[1..].iter().all(Zero::is_zero).then(|| &self.c[0])
    }

    /// Sum.
    pub fn add(&self, o: &Elem) -> Elem {
        charge_sum(&self.c, &o.c);
        let c = self.c.iter().zip(&o.c).map(|(a, b)| a + b).collect();
        Elem::from_coeffs(&self.field, c)
    }

    /// Difference.
    pub fn sub(&self, o: &Elem) -> Elem {
        charge_sum(&self.c, &o.c);
        let c = self.c.iter().zip(&o.c).map(|(a, b)| a - b).collect();
        Elem::from_coeffs(&self.field, c)
    }

    /// Negation.
    pub fn neg(&self) -> Elem {
        Elem::from_coeffs(&self.field, self.c.iter().map(|a| -a).collect())
    }

    /// Product, reduced modulo the minimal polynomial.
    pub fn mul(&self, o: &Elem) -> Elem {
        Elem::from_poly(&self.field, &self.to_poly().mul(&o.to_poly()))
    }

    /// Inverse by the extended Euclidean algorithm; None for zero.
    pub fn inv(&self) -> Option<Elem> {
        if self.is_zero() {
            return None;
        }
        // s·a + t·m = 1 since m is irreducible and a ≠ 0 has lower degree.
        let (g, s, _) = self.to_poly().ext_gcd(&self.field.minpoly);
        debug_assert_eq!(g, QPoly::one());
        Some(Elem::from_poly(&self.field, &s))
    }

    /// Quotient; None when dividing by zero.
    pub fn div(&self, o: &Elem) -> Option<Elem> {
        o.inv().map(|i| self.mul(&i))
    }

    /// Integer power (negative exponents invert); None for 0^negative.
    pub fn pow(&self, e: i64) -> Option<Elem> {
        let base = if e < 0 { self.inv()? } else { self.clone() };
        let mut acc = Elem::one(&self.field);
        for _ in 0..e.unsigned_abs() {
            acc = acc.mul(&base);
        }
        Some(acc)
    }

    /// Interval containing the value, from ρ's current interval (Horner in interval arithmetic).
    fn value_interval(&self) -> (BigRational, BigRational) {
        let (lo, hi) = self.field.interval();
        let d = self.c.len() as u64;
        let l = limbs(&lo).max(limbs(&hi));
        charge(4 * horner(d, l, Sizes::rationals(&self.c).largest()));
        let mut r = (BigRational::zero(), BigRational::zero());
        for c in self.c.iter().rev() {
            let p = [&r.0 * &lo, &r.0 * &hi, &r.1 * &lo, &r.1 * &hi];
            let min = p.iter().min().expect("four products").clone();
            let max = p.iter().max().expect("four products").clone();
            r = (min + c, max + c);
        }
        r
    }

    /// Exact sign: −1, 0 or 1.
    pub fn signum(&self) -> i8 {
        if let Some(r) = self.as_rational() {
            return sign_of(r);
        }
        loop {
            let (lo, hi) = self.value_interval();
            if lo.is_positive() {
                return 1;
            }
            if hi.is_negative() {
                return -1;
            }
            self.field.refine();
        }
    }

    /// Exact comparison.
    pub fn cmp_exact(&self, o: &Elem) -> Ordering {
        self.sub(o).signum().cmp(&0)
    }

    /// Nearest f64: correctly rounded unless the interval argument stalls (value within 2^-1100
    /// of a rounding boundary), in which case within one ulp.
    pub fn to_f64(&self) -> f64 {
        if let Some(r) = self.as_rational() {
            return r.to_f64().unwrap_or(f64::NAN);
        }
        for _ in 0..1100 {
            let (lo, hi) = self.value_interval();
            let (a, b) = (lo.to_f64(), hi.to_f64());
            if a.is_some() && a == b {
                return a.unwrap_or(f64::NAN);
            }
            self.field.refine();
        }
        let (lo, hi) = self.value_interval();
        ((lo + hi) / BigInt::from(2)).to_f64().unwrap_or(f64::NAN)
    }

    /// Radical form a + b√m for a quadratic field: Some((a, b, m)) with m squarefree.
    pub fn quadratic_parts(&self) -> Option<(BigRational, BigRational, BigInt)> {
        if self.field.degree() != 2 {
            return None;
        }
        // minpoly x² + p x + q, ρ = (−p + √D)/2 (ρ is the largest real root), D = p² − 4q.
        let m = self.field.minpoly.coeffs();
        let (q, p) = (&m[0], &m[1]);
        let disc = p * p - q * BigRational::from_integer(4.into());
        // √(N/M) = √(N·M)/M = k√s / M with N·M = k²·s, s squarefree.
        let nm = disc.numer() * disc.denom();
        let (k, s) = split_square(&nm);
        let sqrt_coeff = BigRational::new(k, disc.denom().clone());
        let half = BigRational::new(1.into(), 2.into());
        let a = &self.c[0] - &self.c[1] * p * &half;
        let b = &self.c[1] * &half * sqrt_coeff;
        Some((a, b, s))
    }
}

/// Charges a coefficient-wise sum or difference ([`crate::exact::work`]).
fn charge_sum(a: &[BigRational], b: &[BigRational]) {
    charge(Sizes::rationals(a).pairwise(Sizes::rationals(b)));
}

fn sign_of(r: &BigRational) -> i8 {
    if r.is_positive() {
        1
    } else if r.is_negative() {
        -1
    } else {
        0
    }
}

/// Trial divisors of [`split_square`]: the square part of a discriminant is taken out of its
/// prime factors below this bound.
const SQUARE_TRIAL_LIMIT: u64 = 100_000;

/// n = k²·s (n > 0) with s free of squares of primes below [`SQUARE_TRIAL_LIMIT`] and not itself
/// a square (the rest of n is kept whole in s, so k√s is exact, only not always reduced).
fn split_square(n: &BigInt) -> (BigInt, BigInt) {
    let mut rest = n.clone();
    let mut k = BigInt::one();
    let mut s = BigInt::one();
    let mut f = 2u64;
    while f <= SQUARE_TRIAL_LIMIT && BigInt::from(f) * f <= rest {
        let mut e = 0u32;
        while rest.is_multiple_of(&BigInt::from(f)) {
            rest /= f;
            e += 1;
        }
        k *= BigInt::from(f).pow(e / 2);
        if e % 2 == 1 {
            s *= f;
        }
        f += 1;
    }
    let root = rest.sqrt();
    if &root * &root == rest {
        (k * root, s)
    } else {
        (k, s * rest)
    }
}

/// Formats `num/den` pieces: writes "(body)/den" or "body".
fn over(body: String, den: &BigInt, needs_parens: bool) -> String {
    if den.is_one() {
        body
    } else if needs_parens {
        format!("({body})/{den}")
    } else {
        format!("{body}/{den}")
    }
}

fn coeff_term(c: &BigInt, unit: &str) -> String {
    if unit.is_empty() {
        c.to_string()
    } else if c.is_one() {
        unit.to_string()
    } else {
        format!("{c}{unit}")
    }
}

/// Writes Σ terms (integer coefficient, unit) with the positive terms first, over a denominator.
fn signed_sum(terms: &[(BigInt, String)], den: &BigInt) -> String {
    let mut ordered: Vec<&(BigInt, String)> = terms.iter().filter(|(c, _)| !c.is_zero()).collect();
    if ordered.is_empty() {
        return "0".into();
    }
    // Lead with a positive term when there is one (reads like the papers: "5√2 - 7").
    if let Some(pos) = ordered.iter().position(|(c, _)| c.is_positive()) {
        let lead = ordered.remove(pos);
        ordered.insert(0, lead);
    }
    let mut s = String::new();
    for (i, (c, unit)) in ordered.iter().enumerate() {
        let mag = coeff_term(&c.abs(), unit);
        match (i, c.is_negative()) {
            (0, false) => s += &mag,
            (0, true) => s += &format!("-{mag}"),
            (_, false) => s += &format!(" + {mag}"),
            (_, true) => s += &format!(" - {mag}"),
        }
    }
    over(s, den, ordered.len() > 1)
}

/// Common denominator of rationals and the integer numerators over it.
fn common_den(rs: &[BigRational]) -> (Vec<BigInt>, BigInt) {
    let den = rs.iter().fold(BigInt::one(), |acc, r| acc.lcm(r.denom()));
    let nums = rs.iter().map(|r| r.numer() * (&den / r.denom())).collect();
    (nums, den)
}

impl Elem {
    /// The element as a polynomial in ρ over a common denominator, e.g. `(3ρ^2 - 2)/7`.
    pub fn to_poly_string(&self) -> String {
        let (nums, den) = common_den(&self.c);
        let terms: Vec<(BigInt, String)> = nums
            .into_iter()
            .enumerate()
            .map(|(i, n)| {
                let unit = match i {
                    0 => String::new(),
                    1 => "ρ".into(),
                    _ => format!("ρ^{i}"),
                };
                (n, unit)
            })
            .collect();
        signed_sum(&terms, &den)
    }

    /// Radical form for quadratic fields, e.g. `(5 - 3√2)/7`; None for other degrees.
    pub fn to_radical_string(&self) -> Option<String> {
        let (a, b, s) = self.quadratic_parts()?;
        let (nums, den) = common_den(&[a, b]);
        let terms = [
            (nums[0].clone(), String::new()),
            (nums[1].clone(), format!("√{s}")),
        ];
        Some(signed_sum(&terms, &den))
    }
}

impl fmt::Display for Elem {
    /// Rationals as `p/q`, quadratic fields in radical form, others as polynomials in ρ.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.to_radical_string() {
            Some(s) => f.write_str(&s),
            None => f.write_str(&self.to_poly_string()),
        }
    }
}

impl fmt::Debug for Elem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{self}")
    }
}

/// Parses an expression in ρ: numbers, `rho` (or `ρ`), `+ - * / ^` (integer exponents) and
/// parentheses, e.g. `2/rho`, `(1 + rho)/2`, `rho^2 - rho`.
pub fn parse_expr(field: &FieldRef, text: &str) -> Result<Elem, String> {
    let tokens = tokenize(text)?;
    let mut p = ExprParser {
        field,
        tokens,
        at: 0,
        depth: 0,
    };
    let v = p.sum()?;
    match p.tokens.get(p.at) {
        None => Ok(v),
        Some(t) => Err(format!("unexpected {t} in `{text}`")),
    }
}

/// Largest |exponent| after `^` (ρ^e costs |e| products).
const MAX_EXPONENT: i64 = 64;
/// Largest numerator or denominator, in bits, of any coordinate of any value an expression
/// computes (so that `[lengths]` stay small numbers: 4096 bits is some 1200 digits).
pub const MAX_EXPR_BITS: u64 = 4096;
/// Longest number written in an expression: 4096 bits hold 1233 decimal digits.
const MAX_EXPR_DIGITS: usize = 1233;
/// Deepest nesting of parentheses and unary minus.
const MAX_DEPTH: usize = 64;

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Num(n) => write!(f, "number `{n}`"),
            Tok::Rho => write!(f, "`rho`"),
            Tok::Op(c) => write!(f, "`{c}`"),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(BigRational),
    Rho,
    Op(char),
}

fn tokenize(text: &str) -> Result<Vec<Tok>, String> {
    let mut out = Vec::new();
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // Digits past what MAX_EXPR_BITS holds are refused before parsing (which is
            // quadratic in the length).
            if i - start > MAX_EXPR_DIGITS {
                return Err(format!(
                    "a number of {} digits; expressions are limited to {MAX_EXPR_BITS} bits \
                     ({MAX_EXPR_DIGITS} digits)",
                    i - start
                ));
            }
            let s: String = chars[start..i].iter().collect();
            out.push(Tok::Num(parse_rational(&s)?));
        } else if c == 'ρ' {
            out.push(Tok::Rho);
            i += 1;
        } else if chars[i..].starts_with(&['r', 'h', 'o']) {
            out.push(Tok::Rho);
            i += 3;
        } else if "+-*/^()".contains(c) {
            out.push(Tok::Op(c));
            i += 1;
        } else {
            return Err(format!("unexpected character `{c}` in `{text}`"));
        }
    }
    Ok(out)
}

/// `v`, or the error that one of its coordinates exceeds [`MAX_EXPR_BITS`].
fn small(v: Elem) -> Result<Elem, String> {
    let bits =
        v.c.iter()
            .map(|r| r.numer().bits().max(r.denom().bits()))
            .max()
            .unwrap_or(0);
    if bits > MAX_EXPR_BITS {
        return Err(format!(
            "a value has a {bits}-bit coefficient; expressions are limited to {MAX_EXPR_BITS} bits"
        ));
    }
    Ok(v)
}

struct ExprParser<'a> {
    field: &'a FieldRef,
    tokens: Vec<Tok>,
    at: usize,
    /// Current nesting (parentheses and unary minus).
    depth: usize,
}

impl ExprParser<'_> {
    fn eat(&mut self, op: char) -> bool {
        if self.tokens.get(self.at) == Some(&Tok::Op(op)) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn sum(&mut self) -> Result<Elem, String> {
        let mut v = self.product()?;
        loop {
            if self.eat('+') {
                v = small(v.add(&self.product()?))?;
            } else if self.eat('-') {
                v = small(v.sub(&self.product()?))?;
            } else {
                return Ok(v);
            }
        }
    }

    fn product(&mut self) -> Result<Elem, String> {
        let mut v = self.power()?;
        loop {
            if self.eat('*') {
                v = small(v.mul(&self.power()?))?;
            } else if self.eat('/') {
                v = small(v.div(&self.power()?).ok_or("division by zero")?)?;
            } else {
                return Ok(v);
            }
        }
    }

    fn power(&mut self) -> Result<Elem, String> {
        let base = self.atom()?;
        if !self.eat('^') {
            return Ok(base);
        }
        let neg = self.eat('-');
        match self.tokens.get(self.at) {
            Some(Tok::Num(n)) if n.is_integer() => {
                self.at += 1;
                let e = n
                    .to_integer()
                    .to_i64()
                    .filter(|e| *e <= MAX_EXPONENT)
                    .ok_or_else(|| format!("exponent {n} is larger than {MAX_EXPONENT}"))?;
                // One factor at a time, each product checked against MAX_EXPR_BITS.
                let base = if neg {
                    small(base.inv().ok_or("zero to a negative power")?)?
                } else {
                    base
                };
                (0..e).try_fold(Elem::one(self.field), |acc, _| small(acc.mul(&base)))
            }
            _ => Err("`^` needs an integer exponent".into()),
        }
    }

    fn atom(&mut self) -> Result<Elem, String> {
        if self.depth >= MAX_DEPTH {
            return Err(format!("nested more than {MAX_DEPTH} deep"));
        }
        if self.eat('-') {
            self.depth += 1;
            let v = self.atom()?.neg();
            self.depth -= 1;
            return Ok(v);
        }
        if self.eat('(') {
            self.depth += 1;
            let v = self.sum()?;
            self.depth -= 1;
            return if self.eat(')') {
                Ok(v)
            } else {
                Err("missing `)`".into())
            };
        }
        match self.tokens.get(self.at).cloned() {
            Some(Tok::Num(n)) => {
                self.at += 1;
                small(Elem::rational(self.field, n))
            }
            Some(Tok::Rho) => {
                self.at += 1;
                Ok(self.field.rho())
            }
            Some(t) => Err(format!("expected a number, `rho` or `(`, found {t}")),
            None => Err("expected a number, `rho` or `(` at the end".into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::poly::isolate_real_roots;

    fn field(coeffs: &[i64]) -> FieldRef {
        let p = QPoly::from_ints(coeffs);
        let (lo, hi) = isolate_real_roots(&p).pop().unwrap();
        Field::new(&p, lo, hi)
    }

    /// `to_f64` is correctly rounded: the exact value lies within half an ulp of the result
    /// (decided exactly, in the field).
    #[test]
    fn to_f64_is_correctly_rounded() {
        for coeffs in [
            &[-1, -1, 1][..],
            &[-1, -2, 1],
            &[-2, 0, -1, 1],
            &[-2, 0, 0, 0, 0, 0, 1],
        ] {
            let f = field(coeffs);
            let rho = f.rho();
            let mut x = Elem::one(&f);
            for k in 0..40 {
                // Varied elements: ρ^k/7 − k/3.
                let e = x
                    .div(&Elem::int(&f, 7))
                    .unwrap()
                    .sub(&Elem::rational(&f, BigRational::new(k.into(), 3.into())));
                let v = e.to_f64();
                let exact = |y: f64| Elem::rational(&f, BigRational::from_float(y).unwrap());
                let half_ulp = |y: f64| (f64::from_bits(y.to_bits() + 1) - y).abs() / 2.0;
                let below = exact(v).sub(&Elem::rational(
                    &f,
                    BigRational::from_float(half_ulp(v)).unwrap(),
                ));
                let above = exact(v).add(&Elem::rational(
                    &f,
                    BigRational::from_float(half_ulp(v)).unwrap(),
                ));
                assert!(
                    e.cmp_exact(&below).is_ge() && e.cmp_exact(&above).is_le(),
                    "{e} -> {v}"
                );
                x = x.mul(&rho);
            }
        }
    }

    #[test]
    fn arithmetic_signs_and_display() {
        let f = field(&[-1, -2, 1]); // ρ = 1 + √2
        let rho = f.rho();
        let sqrt2 = rho.sub(&Elem::one(&f));
        assert_eq!(sqrt2.mul(&sqrt2), Elem::int(&f, 2));
        let x = Elem::int(&f, 5)
            .sub(&Elem::int(&f, 3).mul(&sqrt2))
            .div(&Elem::int(&f, 7))
            .unwrap();
        assert_eq!(x.to_string(), "(5 - 3√2)/7");
        assert_eq!(
            Elem::int(&f, 5)
                .mul(&sqrt2)
                .sub(&Elem::int(&f, 7))
                .to_string(),
            "5√2 - 7"
        );
        assert_eq!(x.signum(), 1); // 5 > 3√2 ≈ 4.243
        assert_eq!(
            Elem::int(&f, 99)
                .sub(&Elem::int(&f, 70).mul(&sqrt2))
                .signum(),
            1
        ); // 99 − 70√2 ≈ 0.00505
        assert_eq!(
            Elem::int(&f, 70)
                .mul(&sqrt2)
                .sub(&Elem::int(&f, 99))
                .signum(),
            -1
        );
        assert_eq!(x.mul(&x.inv().unwrap()), Elem::one(&f));
        assert!(Elem::zero(&f).inv().is_none());
        let c = field(&[-2, 0, -1, 1]);
        let r = c.rho();
        assert_eq!(r.mul(&r).mul(&r), r.mul(&r).add(&Elem::int(&c, 2)));
        assert_eq!(
            parse_expr(&c, "rho^2 - rho").unwrap().to_string(),
            "ρ^2 - ρ"
        );
        assert_eq!(parse_expr(&c, "(1 + rho)/2 * 2 - 1").unwrap(), r);
        assert_eq!(
            parse_expr(&c, "2/rho").unwrap(),
            Elem::int(&c, 2).div(&r).unwrap()
        );
        assert!(parse_expr(&c, "rho +").is_err());
        assert!(parse_expr(&c, "1/0").is_err());
        assert!(parse_expr(&c, "x").is_err());
    }
}
