//! Compiles every scheme file of the package's `schemes/` folder (the workspace's `schemes/`,
//! through a symbolic link that `cargo package` follows), exactly as a user's build script
//! would, plus a registry module listing them.

use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("schemes");
    println!("cargo:rerun-if-changed={}", dir.display());
    let result = lsubdiv_compiler::exact::scheme::scheme_files(&dir).and_then(|files| {
        // The folder's curve-only schemes are meant so: no warning for them (the directive on
        // the folder above covers every file).
        lsubdiv_compiler::Config::new()
            .emit_rerun_directives(false)
            .registry("registry.rs")
            .compile(&files)
    });
    if let Err(e) = result {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
