#![doc = include_str!("../README.md")]
//!
//! Generated code must compile warning-free.
#![deny(warnings)]

include!(concat!(env!("OUT_DIR"), "/registry.rs"));
