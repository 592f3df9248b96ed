//! Test support shared by integration tests (`mod common;`).
#![allow(dead_code)]
pub mod catmull_clark;
pub mod cli;
pub mod spline;
