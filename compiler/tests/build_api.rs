//! The build-script API as a user calls it (prost-build style).

use lsubdiv_compiler::Config;
use std::path::PathBuf;

fn scheme(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../schemes/{name}.toml"))
}

#[test]
fn compile_writes_items_only_and_only_when_changed() {
    let dir = tempfile::tempdir().unwrap();
    let names = Config::new()
        .out_dir(dir.path())
        .registry("registry.rs")
        .compile(&[scheme("fibonacci"), scheme("binary-ternary")])
        .unwrap();
    assert_eq!(names, ["fibonacci", "binary-ternary"]);
    let file = dir.path().join("binary_ternary.rs");
    let src = std::fs::read_to_string(&file).unwrap();
    assert!(src.starts_with("// @generated"));
    assert!(!src.contains("#!["), "include! rejects inner attributes");
    assert!(!src.contains("//!"), "include! rejects inner doc comments");
    let registry = std::fs::read_to_string(dir.path().join("registry.rs")).unwrap();
    // Relative includes: the registry works from any folder, not only OUT_DIR.
    assert!(
        registry.contains("include!(\"binary_ternary.rs\")"),
        "{registry}"
    );
    assert!(!registry.contains("OUT_DIR") && !src.contains("::lsubdiv_runtime"));
    // A second compile with unchanged inputs leaves the file untouched.
    let before = std::fs::metadata(&file).unwrap().modified().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    Config::new()
        .out_dir(dir.path())
        .compile(&[scheme("binary-ternary")])
        .unwrap();
    assert_eq!(
        std::fs::metadata(&file).unwrap().modified().unwrap(),
        before
    );
}

#[test]
fn compile_without_out_dir_is_an_error_not_a_panic() {
    std::env::remove_var("OUT_DIR");
    let e = lsubdiv_compiler::compile(&[scheme("fibonacci")]).unwrap_err();
    assert!(!e.is_internal() && e.to_string().contains("OUT_DIR"), "{e}");
}

#[test]
fn duplicate_scheme_names_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let e = Config::new()
        .out_dir(dir.path())
        .compile(&[scheme("fibonacci"), scheme("fibonacci")])
        .unwrap_err();
    assert!(e.to_string().contains("already compiled"), "{e}");
}
