//! The exact pipeline behind [`crate::Config`], for tools that need its parts (the `lsubdiv`
//! facade and CLI, the explorer): scheme file → [`lsystem::LSystem`] → Q(ρ) ([`field`]) →
//! lengths ([`validity`]) → masks ([`masks`]) → transition graph ([`graph`]) → certified
//! [`pipeline::Scheme`] → surface analysis ([`ev`]) → one [`Tables`] value ([`tables`]) → Rust
//! source ([`codegen`]) or the run-time path (the `lsubdiv` facade's `generic`).
//!
//! A build script needs none of it: [`crate::compile`] and [`crate::Config`] are the API.

pub mod codegen;
pub mod ev;
pub mod field;
pub mod graph;
pub mod limit;
pub mod linalg;
pub mod lsystem;
pub mod masks;
pub mod pipeline;
pub mod poly;
pub mod scheme;
pub mod symmetry;
pub mod tables;
pub mod validity;
pub mod work;

pub use pipeline::Scheme;
pub use tables::Tables;
