//! The exact build-time pipeline of lsubdiv: scheme file → L-system → Q(ρ) → lengths → masks →
//! transition graph → Rust source.
//!
//! Papers: \[N\] Nivoliers, Gérot, Ostromoukhov, Stewart 2012 (univariate);
//! \[G\] Gérot, Ivrissimtzis 2023 (bivariate).

pub mod codegen;
pub mod error;
pub mod ev;
pub mod explore;
pub mod field;
pub mod generic;
pub mod graph;
pub mod linalg;
pub mod lsystem;
pub mod masks;
pub mod pipeline;
pub mod poly;
pub mod scheme;
pub mod symmetry;
pub mod validity;

pub use codegen::{compile, Config};
pub use error::Error;
pub use pipeline::Scheme;
