//! The exact build-time compiler of lsubdiv: scheme file → L-system → Q(ρ) → lengths → masks →
//! transition graph → Rust source.
//!
//! Papers: \[N\] Nivoliers, Gérot, Ostromoukhov, Stewart 2012 (univariate);
//! \[G\] Gérot, Ivrissimtzis 2023 (bivariate).

mod config;
mod error;
pub mod exact;
mod output;

pub use config::{compile, Config};
pub use error::{Error, Kind, Location};
pub use output::{temporary_files, write_atomic};
