//! Eigenanalysis at an extraordinary vertex and the choice of α (\[G\] §4.2.3). Numeric (f64):
//! this is the one place where floating point chooses a value.
//!
//! Around an EV of valence n in its stationary configuration, the local subdivision matrix maps
//! the old 1-ring (EV, radial neighbours R_k, diagonal neighbours D_k) to the new 1-ring (EV child,
//! r_k, d_k). It is block-circulant over the n sectors, so the discrete Fourier transform splits
//! it into a 3×3 block for Fourier index 0 (the only one where α enters) and 2×2 blocks for
//! indices i ≥ 1, all with closed-form eigenvalues. λ_i is the main eigenvalue of block i, μ_0
//! the second of block 0; α is chosen so that μ_0 = λ_1².

use std::f64::consts::TAU;
use std::fmt;

/// The stencil weights of the stationary 1-ring, from the scheme's masks (see the compiler's
/// `ev` module for their derivation). Names read "source to target". `T` is `f64` here and in
/// generated code; the compiler holds the same struct of exact weights and [`map`]s it.
///
/// [`map`]: EvCoefficients::map
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvCoefficients<T = f64> {
    /// EV → r_k: h(1)·h(0), h the second half of the radial mask.
    pub ev_to_radial: T,
    /// EV → d_k: h(1)².
    pub ev_to_diagonal: T,
    /// R_k → r_k.
    pub radial_to_radial: T,
    /// R_{k±1} → r_k (each).
    pub side_to_radial: T,
    /// D_k and D_{k−1} → r_k (each).
    pub diagonal_to_radial: T,
    /// R_k and R_{k+1} → d_k (each).
    pub radial_to_diagonal: T,
    /// D_k → d_k.
    pub diagonal_to_diagonal: T,
    /// R_k → EV child (before normalisation).
    pub radial_to_ev: T,
    /// D_k → EV child (before normalisation).
    pub diagonal_to_ev: T,
}

/// The spectrum at valence n with the chosen α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spectrum {
    /// Valence.
    pub n: usize,
    /// Central entry of the EV mask.
    pub alpha: f64,
    /// Main eigenvalue of Fourier index 1 (subdominant).
    pub lambda1: f64,
    /// Main eigenvalue of Fourier index 2.
    pub lambda2: f64,
    /// Second eigenvalue of Fourier index 0 (equals λ1² by the choice of α).
    pub mu0: f64,
    /// What the EV child is divided by: α + n·(radial_to_ev + diagonal_to_ev).
    pub normalisation: f64,
}

/// What takes a stationary 1-ring (EV P, radial neighbours R_k, diagonal neighbours D_k) to
/// the EV's limit point and limit tangents: the point `centre`·P + `radial`·Σ R_k +
/// `diagonal`·Σ D_k ([`EvCoefficients::limit_weights`]), the tangents Σ_k cos θk · R_k +
/// `tangent` · cos θ(k + ½) · D_k and the same with sines ([`EvCoefficients::tangent_weight`]).
/// Numeric (f64), as α is; tabulated per valence in generated code.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvLimit {
    /// The EV's weight.
    pub centre: f64,
    /// Each radial neighbour's weight.
    pub radial: f64,
    /// Each diagonal neighbour's weight.
    pub diagonal: f64,
    /// The diagonal neighbours' tangent weight c.
    pub tangent: f64,
}

impl EvLimit {
    /// The limit data at valence n, with α chosen by [`EvCoefficients::alpha`].
    pub fn new(ev: &EvCoefficients, n: usize) -> Result<EvLimit, EvError> {
        let [centre, radial, diagonal] = ev.limit_weights(n, ev.alpha(n)?);
        Ok(EvLimit {
            centre,
            radial,
            diagonal,
            tangent: ev.tangent_weight(n)?,
        })
    }
}

/// Why no α could be found.
#[derive(Clone, Debug, PartialEq)]
pub enum EvError {
    /// Valence below 2.
    Valence(usize),
    /// μ0(α) − λ1² does not change sign on the searched range.
    NoRoot {
        /// Valence.
        n: usize,
    },
    /// A block has complex eigenvalues where real ones are needed.
    Complex {
        /// Valence.
        n: usize,
        /// Fourier index.
        index: usize,
    },
}

impl fmt::Display for EvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EvError::Valence(n) => {
                write!(f, "valence {n}: an interior vertex has two faces at least")
            }
            EvError::NoRoot { n } => write!(f, "valence {n}: no α in [0, 64n] gives μ0 = λ1²"),
            EvError::Complex { n, index } => write!(
                f,
                "valence {n}: Fourier block {index} has complex eigenvalues"
            ),
        }
    }
}

impl std::error::Error for EvError {}

impl<T> EvCoefficients<T> {
    /// The nine weights with their field names, in declaration order.
    pub fn named(&self) -> [(&'static str, &T); 9] {
        [
            ("ev_to_radial", &self.ev_to_radial),
            ("ev_to_diagonal", &self.ev_to_diagonal),
            ("radial_to_radial", &self.radial_to_radial),
            ("side_to_radial", &self.side_to_radial),
            ("diagonal_to_radial", &self.diagonal_to_radial),
            ("radial_to_diagonal", &self.radial_to_diagonal),
            ("diagonal_to_diagonal", &self.diagonal_to_diagonal),
            ("radial_to_ev", &self.radial_to_ev),
            ("diagonal_to_ev", &self.diagonal_to_ev),
        ]
    }

    /// Each weight through `f` (exact → nearest f64, f64 → tokens).
    pub fn map<U>(&self, mut f: impl FnMut(&T) -> U) -> EvCoefficients<U> {
        EvCoefficients {
            ev_to_radial: f(&self.ev_to_radial),
            ev_to_diagonal: f(&self.ev_to_diagonal),
            radial_to_radial: f(&self.radial_to_radial),
            side_to_radial: f(&self.side_to_radial),
            diagonal_to_radial: f(&self.diagonal_to_radial),
            radial_to_diagonal: f(&self.radial_to_diagonal),
            diagonal_to_diagonal: f(&self.diagonal_to_diagonal),
            radial_to_ev: f(&self.radial_to_ev),
            diagonal_to_ev: f(&self.diagonal_to_ev),
        }
    }
}

impl EvCoefficients {
    /// Eigenvalues (larger, smaller) of the 2×2 block of Fourier index `i` ≥ 1.
    pub fn block(&self, n: usize, i: usize) -> Result<(f64, f64), EvError> {
        let c = (TAU * i as f64 / n as f64).cos();
        let a = self.radial_to_radial + 2.0 * self.side_to_radial * c;
        let b = self.diagonal_to_diagonal;
        // Off-diagonal product: A3 (1 + e^{−iθ}) · B1 (1 + e^{iθ}) = A3 B1 · 2(1 + cos θ).
        let off = self.diagonal_to_radial * self.radial_to_diagonal * 2.0 * (1.0 + c);
        let disc = ((a - b) / 2.0).powi(2) + off;
        if disc < 0.0 {
            return Err(EvError::Complex { n, index: i });
        }
        let s = disc.sqrt();
        Ok(((a + b) / 2.0 + s, (a + b) / 2.0 - s))
    }

    /// The 3×3 block of Fourier index 0 (rows and columns: EV, radial, diagonal).
    pub fn block0(&self, n: usize, alpha: f64) -> [[f64; 3]; 3] {
        let nf = n as f64;
        let norm = self.normalisation(n, alpha);
        [
            [
                alpha / norm,
                nf * self.radial_to_ev / norm,
                nf * self.diagonal_to_ev / norm,
            ],
            [
                self.ev_to_radial,
                self.radial_to_radial + 2.0 * self.side_to_radial,
                2.0 * self.diagonal_to_radial,
            ],
            [
                self.ev_to_diagonal,
                2.0 * self.radial_to_diagonal,
                self.diagonal_to_diagonal,
            ],
        ]
    }

    /// α + n·(R → EV + D → EV): the sum of the weights the EV child receives.
    pub fn normalisation(&self, n: usize, alpha: f64) -> f64 {
        alpha + n as f64 * (self.radial_to_ev + self.diagonal_to_ev)
    }

    /// μ0(α): block 0 has the eigenvalue 1 (rows sum to 1); the other two are the roots of
    /// x² − (tr − 1)x + det; μ0 is the larger.
    pub fn mu0(&self, n: usize, alpha: f64) -> Result<f64, EvError> {
        let m = self.block0(n, alpha);
        let tr = m[0][0] + m[1][1] + m[2][2];
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        let t = tr - 1.0;
        let disc = t * t - 4.0 * det;
        if disc < 0.0 {
            return Err(EvError::Complex { n, index: 0 });
        }
        Ok((t + disc.sqrt()) / 2.0)
    }

    /// α with μ0(α) = λ1², by scanning [0, 64n] for a sign change and bisecting to f64 precision.
    /// At valence 2 (two faces sharing both edges at the vertex) no α meets it: α there gives
    /// the vertex itself Catmull–Clark's weight at valence 2, 1 − 7/(4·2) = 1/8, as OpenSubdiv
    /// refines it (for uniform binary, whose ring weights are Catmull–Clark's, its rule exactly).
    pub fn alpha(&self, n: usize) -> Result<f64, EvError> {
        if n < 2 {
            return Err(EvError::Valence(n));
        }
        if n == 2 {
            return Ok(self.normalisation(2, 0.0) / 7.0);
        }
        let target = self.block(n, 1)?.0.powi(2);
        let f = |a: f64| self.mu0(n, a).map(|m| m - target);
        let hi_end = 64.0 * n as f64;
        let steps = 4096;
        let mut lo = 0.0;
        let mut flo = f(lo)?;
        for k in 1..=steps {
            let hi = hi_end * k as f64 / steps as f64;
            let fhi = f(hi)?;
            if flo == 0.0 {
                return Ok(lo);
            }
            if flo.signum() != fhi.signum() {
                let (mut a, mut b, mut fa) = (lo, hi, flo);
                for _ in 0..200 {
                    let mid = 0.5 * (a + b);
                    if mid <= a || mid >= b {
                        break;
                    }
                    let fm = f(mid)?;
                    if fm.signum() == fa.signum() {
                        a = mid;
                        fa = fm;
                    } else {
                        b = mid;
                    }
                }
                return Ok(0.5 * (a + b));
            }
            lo = hi;
            flo = fhi;
        }
        Err(EvError::NoRoot { n })
    }

    /// The weights that take a stationary 1-ring to the EV's limit point: the left
    /// eigenvector of eigenvalue 1 of the local subdivision matrix, which lies in Fourier
    /// index 0 (the limit is the same under rotation), so it is block 0's: (for the EV, for
    /// each radial neighbour, for each diagonal neighbour), summing to 1 over the 1 + 2n
    /// points. Numeric (f64), as α is.
    pub fn limit_weights(&self, n: usize, alpha: f64) -> [f64; 3] {
        let m = self.block0(n, alpha);
        // l (M − I) = 0: l is orthogonal to the columns of M − I, so the cross product of two
        // of them (block 0 has rank 2 there; the pair with the largest product is taken).
        let col = |j: usize| [0, 1, 2].map(|i| m[i][j] - f64::from(u8::from(i == j)));
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let size = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>();
        let l = [
            cross(col(0), col(1)),
            cross(col(1), col(2)),
            cross(col(0), col(2)),
        ]
        .into_iter()
        .max_by(|a, b| size(a).total_cmp(&size(b)))
        .unwrap_or_default();
        let total = l[0] + l[1] + l[2];
        let nf = n as f64;
        [l[0] / total, l[1] / (nf * total), l[2] / (nf * total)]
    }

    /// The weight c of the EV's limit tangents: the left eigenvector of λ1 (Fourier
    /// index 1) gives the two tangents Σ_k (cos θk · R_k + c cos θ(k + ½) · D_k) and the same
    /// with sines, θ = 2π/n, R_k the radial and D_k the diagonal neighbours in rotation order
    /// (D_k between R_k and R_{k+1}); the EV itself has weight 0. Refining the 1-ring scales
    /// both by λ1. Numeric (f64), as α is.
    pub fn tangent_weight(&self, n: usize) -> Result<f64, EvError> {
        // At valence 2 the diagonals' cosines cos θ(k + ½) vanish, and so does the second
        // tangent: the limit has no tangent plane there (the patch limit takes the faces' mean).
        if n == 2 {
            return Ok(0.0);
        }
        let theta = TAU / n as f64;
        let lambda = self.block(n, 1)?.0;
        let a = self.radial_to_radial + 2.0 * self.side_to_radial * theta.cos();
        // (u, v) B = λ (u, v) with u = 1: v = (λ − a) / (B1 (1 + e^{iθ})) = c e^{−iθ/2}.
        Ok((lambda - a) / (2.0 * self.radial_to_diagonal * (theta / 2.0).cos()))
    }

    /// α and the spectrum at valence n.
    pub fn spectrum(&self, n: usize) -> Result<Spectrum, EvError> {
        let alpha = self.alpha(n)?;
        Ok(Spectrum {
            n,
            alpha,
            lambda1: self.block(n, 1)?.0,
            lambda2: self.block(n, 2)?.0,
            mu0: self.mu0(n, alpha)?,
            normalisation: self.normalisation(n, alpha),
        })
    }
}
