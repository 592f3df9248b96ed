//! Compiles every scheme file of the workspace's `schemes/` folder, exactly as a user's build
//! script would, plus a registry module listing them.

use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../schemes");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("schemes/ folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    if let Err(e) = lsubdiv_compiler::Config::new()
        .registry("registry.rs")
        .compile(&files)
    {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
