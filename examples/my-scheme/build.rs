// build.rs: compile the scheme exactly into OUT_DIR (with a cargo:rerun-if-changed line).
fn main() {
    if let Err(e) = lsubdiv_compiler::compile(&["schemes/my_scheme.toml"]) {
        eprintln!("{e}"); // file:line:column: error: … and a hint
        std::process::exit(1);
    }
}
