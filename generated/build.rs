//! Compiles every scheme file of the workspace's `schemes/` folder, exactly as a user's build
//! script would, plus a registry module listing them.

use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../schemes");
    println!("cargo:rerun-if-changed={}", dir.display());
    let result = lsubdiv_compiler::exact::scheme::scheme_files(&dir).and_then(|files| {
        lsubdiv_compiler::Config::new()
            .registry("registry.rs")
            .compile(&files)
    });
    if let Err(e) = result {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
