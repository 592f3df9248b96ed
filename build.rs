//! Embeds the shipped scheme files (`schemes/*.toml`) so the CLI accepts their names.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("schemes");
    println!("cargo:rerun-if-changed={}", dir.display());
    let files = lsubdiv_compiler::exact::scheme::scheme_files(&dir).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    let mut out = String::from(
        "/// Shipped schemes: (file stem, file path, TOML text).\npub const BUILTIN: &[(&str, &str, &str)] = &[\n",
    );
    for f in &files {
        println!("cargo:rerun-if-changed={}", f.display());
        let stem = f
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("UTF-8 file name");
        let _ = writeln!(
            out,
            "    ({stem:?}, \"schemes/{stem}.toml\", include_str!({:?})),",
            f.display().to_string()
        );
    }
    out.push_str("];\n");
    let dest = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR")).join("builtin.rs");
    // Rewritten only when it changes, and then whole or not at all.
    lsubdiv_compiler::write_if_changed(&dest, &out).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
}
