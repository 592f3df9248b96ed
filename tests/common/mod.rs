//! Test support shared by integration tests (`mod common;`).
#![allow(dead_code)]
pub mod cli;
