//! The shipped schemes' code is committed (`src/schemes/`, as prost-types and lalrpop commit
//! theirs), so that a program refining with them builds no compiler. This test compiles the
//! scheme files again, exactly, and fails when the committed code differs from what they give
//! today; `LSUBDIV_BLESS=1 cargo test -p lsubdiv-generated` rewrites it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Every `.rs` file of `dir` by name, with its text.
fn sources(dir: &Path) -> BTreeMap<String, String> {
    std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).expect("UTF-8 source"))
        })
        .collect()
}

#[test]
fn the_committed_code_is_what_the_scheme_files_compile_to() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let committed_dir = root.join("src/schemes");
    let fresh_dir = std::env::temp_dir().join(format!("lsubdiv-generated-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&fresh_dir);
    std::fs::create_dir_all(&fresh_dir).unwrap();
    let files = lsubdiv_compiler::exact::scheme::scheme_files(&root.join("../schemes")).unwrap();
    lsubdiv_compiler::Config::new()
        .out_dir(&fresh_dir)
        .registry("registry.rs")
        .emit_rerun_directives(false)
        .compile(&files)
        .unwrap_or_else(|e| panic!("{e}"));
    let fresh = sources(&fresh_dir);
    let committed = sources(&committed_dir);
    if std::env::var_os("LSUBDIV_BLESS").is_some() && fresh != committed {
        for name in committed.keys().filter(|n| !fresh.contains_key(*n)) {
            std::fs::remove_file(committed_dir.join(name)).unwrap();
        }
        for (name, text) in &fresh {
            std::fs::write(committed_dir.join(name), text).unwrap();
        }
        eprintln!(
            "rewrote {} files in {}",
            fresh.len(),
            committed_dir.display()
        );
    } else {
        let differ: Vec<&String> = fresh
            .keys()
            .chain(committed.keys())
            .filter(|n| fresh.get(*n) != committed.get(*n))
            .collect();
        assert!(
            differ.is_empty(),
            "generated/src/schemes is stale ({differ:?} differ from what schemes/ compiles to): \
             run `LSUBDIV_BLESS=1 cargo test -p lsubdiv-generated` and commit the result"
        );
    }
    std::fs::remove_dir_all(&fresh_dir).unwrap();
}
