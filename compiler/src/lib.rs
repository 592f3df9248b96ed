//! The exact build-time compiler of lsubdiv: scheme file → L-system → Q(ρ) → lengths → masks →
//! transition graph → Rust source for `lsubdiv-runtime`, in the style of prost-build.
//!
//! Papers: \[N\] Nivoliers, Gérot, Ostromoukhov, Stewart 2012 (univariate);
//! \[G\] Gérot, Ivrissimtzis 2023 (bivariate).
//!
//! # Quick start
//!
//! A scheme file names an L-system and a degree:
//!
//! ```toml
//! name = "my_scheme"
//! degree = 3
//! axiom = "C"
//! [rules]
//! L = "LC"
//! C = "LCR"
//! R = "CR"
//! ```
//!
//! The build script compiles it into `OUT_DIR` (with `cargo:rerun-if-changed` for each input,
//! and a `cargo:warning` when the scheme refines curves only, naming the condition of \[G\]
//! §4.2 that fails):
//!
//! ```no_run
//! // build.rs
//! fn main() {
//!     if let Err(e) = lsubdiv_compiler::compile(&["schemes/my_scheme.toml"]) {
//!         eprintln!("{e}"); // file:line:column: error: … and a hint
//!         std::process::exit(1);
//!     }
//! }
//! ```
//!
//! and the crate includes the module, `lsubdiv_runtime::include_scheme!(my_scheme);` (or
//! `lsubdiv::include_scheme!(my_scheme);` when it depends on the facade only), then refines with
//! `lsubdiv_runtime::refine(&my_scheme::Scheme, &curve, steps)`.
//!
//! [`Config`] sets the output folder (any folder, not only `OUT_DIR`), a registry module of
//! every scheme, the path generated code names the runtime by, and whether cargo directives are
//! printed:
//!
//! ```
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let dir = tempfile::tempdir()?;
//! let file = dir.path().join("chaikin.toml");
//! std::fs::write(&file, "name = \"chaikin\"\ndegree = 2\naxiom = \"A\"\n[rules]\nA = \"AA\"\n")?;
//! let names = lsubdiv_compiler::Config::new()
//!     .out_dir(dir.path())
//!     .registry("registry.rs")
//!     .emit_rerun_directives(false)
//!     .compile(&[&file])?;
//! assert_eq!(names, ["chaikin"]);
//! let source = std::fs::read_to_string(dir.path().join("chaikin.rs"))?;
//! assert!(source.starts_with("// @generated") && source.contains("pub const TABLES"));
//! // Errors name the file, line and column.
//! std::fs::write(&file, "name = \"chaikin\"\ndegree = 0\naxiom = \"A\"\n[rules]\nA = \"AA\"\n")?;
//! let e = lsubdiv_compiler::Config::new().out_dir(dir.path()).compile(&[&file]).unwrap_err();
//! assert!(e.to_string().contains("chaikin.toml:2:"), "{e}");
//! # Ok(())
//! # }
//! ```
//!
//! # For tools
//!
//! [`exact`] is the exact pipeline behind [`Config`] (fields, L-systems, masks, graphs, the
//! surface analysis, the one [`exact::Tables`] value, code generation), for the `lsubdiv` facade,
//! the command line and the explorer. A build script needs none of it.

// The quick start shows a build script, whose `main` is the point.
#![allow(clippy::needless_doctest_main)]

mod config;
pub mod exact;

pub use config::{compile, Config};
#[doc(inline)]
pub use lsubdiv_io::{
    read_bytes, read_text, temporary_files, text, write_atomic, write_atomic_with,
    write_if_changed, Error, Kind, Location,
};
