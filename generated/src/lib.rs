//! The schemes of lsubdiv's `schemes/` folder, compiled exactly at build time by
//! `lsubdiv-compiler` into const mask tables and specialised mask-diffusion kernels.
//!
//! Each scheme is a module (`fibonacci`, `binary_ternary`, …) holding `Scheme`, which implements
//! [`lsubdiv_runtime::CurveScheme`], and its `TABLES`. [`NAMES`] lists them and
//! [`refine_curve`] dispatches by name. Generated code must compile warning-free.
#![deny(warnings)]

include!(concat!(env!("OUT_DIR"), "/registry.rs"));
