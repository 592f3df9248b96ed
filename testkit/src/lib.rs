//! Test support for lsubdiv (not published): independent oracles and random inputs shared by the
//! integration tests, the property tests and the fuzz targets.

pub mod catmull_clark;
pub mod fuzzing;
pub mod meshes;
pub mod points;
pub mod spline;
