#![doc = include_str!("../README.md")]
//!
//! Generated code must compile warning-free.
#![deny(warnings)]

include!("schemes/registry.rs");
