//! The scalar of positions: f64 or f32.

use std::ops::{Add, AddAssign, Div, Mul, Sub};

/// A floating-point scalar for positions.
pub trait Real:
    Copy
    + Default
    + Send
    + Sync
    + PartialEq
    + PartialOrd
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + AddAssign
    + 'static
{
    /// Nearest value of this type (a constant for constant arguments).
    fn from_f64(x: f64) -> Self;
    /// Widening (or identity) conversion.
    fn to_f64(self) -> f64;
    /// `self · a + b` with one rounding. Only where the CPU fuses it (the FMA paths of
    /// `patch`): elsewhere it is a slow library call.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// The type's name (`f64`, `f32`), for messages.
    const NAME: &'static str;
    /// Its largest finite value.
    const MAX: f64;
}

impl Real for f64 {
    const NAME: &'static str = "f64";
    const MAX: f64 = f64::MAX;
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        f64::mul_add(self, a, b)
    }
}

impl Real for f32 {
    const NAME: &'static str = "f32";
    const MAX: f64 = f32::MAX as f64;
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        f32::mul_add(self, a, b)
    }
}

/// `dst += w · src`, element-wise (the inner loop of every pass; it vectorises).
#[inline(always)]
pub fn axpy_slab<T: Real>(dst: &mut [T], w: T, src: &[T]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d += w * *s;
    }
}
