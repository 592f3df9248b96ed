//! Test support shared by integration tests (`mod common;`).
#![allow(dead_code)]
pub mod cli;

/// Deterministic pseudo-random numbers in [-1, 1).
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number.
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// `m` points of `D` coordinates.
    pub fn points<const D: usize>(&mut self, m: usize) -> Vec<[f64; D]> {
        (0..m)
            .map(|_| std::array::from_fn(|_| self.next()))
            .collect()
    }
}
