//! What a surface scheme is at run time (\[G\] §4): its surface tables beyond the curve tables
//! (the involution σ, α and the EV limit data per valence, the EV rings per step) and the
//! [`SurfaceScheme`] trait that generated code implements. The mesh refiners that run such a
//! scheme are in `lsubdiv-mesh`.

use crate::curve::CurveScheme;
use crate::ev::{EvCoefficients, EvError, EvLimit};

/// Surface data of a scheme, beyond its curve tables.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceTables<'a> {
    /// The involution σ.
    pub sigma: &'a [u8],
    /// Per word: (1 − h(0)²)/4, what each sector gives an EV child whose radial word it is.
    pub ring_weights: &'a [f64],
    /// α for valences 3, 4, 5, … (entry n − 3).
    pub alpha: &'a [f64],
    /// The EV's limit data for the same valences ([`EvLimit`]).
    pub ev_limits: &'a [EvLimit],
    /// Stationary 1-ring stencils, for α beyond the table.
    pub ev: EvCoefficients,
    /// Per step (the last entry for every later step): what the EV child gets from each radial
    /// neighbour and from each diagonal neighbour.
    pub rings: &'a [[f64; 2]],
    /// First step from which masks are contained near EVs (\[G\] Prop. 4.8).
    pub contained_from: usize,
}

impl SurfaceTables<'_> {
    /// α at valence n: the table, or the same solver ([`EvCoefficients::alpha`]) beyond it.
    pub fn alpha(&self, n: usize) -> Result<f64, EvError> {
        match self.alpha.get(n.wrapping_sub(3)) {
            Some(&a) => Ok(a),
            None => self.ev.alpha(n),
        }
    }

    /// The EV's limit data at valence n: the table, or the same computation
    /// ([`EvLimit::new`]) beyond it.
    pub fn ev_limit(&self, n: usize) -> Result<EvLimit, EvError> {
        match self.ev_limits.get(n.wrapping_sub(3)) {
            Some(&l) => Ok(l),
            None => EvLimit::new(&self.ev, n),
        }
    }

    /// First step from which the EV configuration, and so its local subdivision matrix, no
    /// longer changes (\[G\] Lemma 4.6): the limit weights of [`EvLimit`] hold from there.
    pub fn stationary_from(&self) -> usize {
        self.rings.len().saturating_sub(1)
    }
}

/// A scheme that refines surfaces.
#[diagnostic::on_unimplemented(
    message = "`{Self}` does not refine surfaces",
    note = "its scheme compiles for curves only: the build printed a `cargo:warning` naming the condition of [G] §4.2 that fails, and the scheme's docs say it too"
)]
pub trait SurfaceScheme: CurveScheme {
    /// The surface tables.
    fn surface(&self) -> SurfaceTables<'_>;
}

/// Something to do with a surface scheme whose concrete type is only known by name (see the
/// generated registry's `visit_surface`).
pub trait SurfaceVisitor {
    /// The result.
    type Output;
    /// Runs with the scheme.
    fn visit<S: SurfaceScheme + Sync>(self, scheme: &S) -> Self::Output;
}
