//! The fuzz corpora as tests, on stable Rust without cargo-fuzz: every kept input of each target
//! of `fuzz/` (`tests/fuzz_corpus/<target>/`, crash inputs under `regressions/`) goes through
//! the same check as the target ([`lsubdiv_testkit::fuzzing`]) and must not panic: it is processed
//! (its invariants hold) or refused with an error.

use lsubdiv_testkit::fuzzing::{check_obj, check_pipeline, check_ply, check_scheme, Outcome};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// The files of a folder, sorted (none if it does not exist).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| rd.map(|e| e.expect("directory entry").path()).collect())
        .unwrap_or_default();
    out.retain(|p| p.is_file());
    out.sort();
    out
}

/// Runs `check` on the corpus and the regressions of `target`; returns (processed, refused).
fn run(target: &str, check: fn(&[u8]) -> Outcome) -> (usize, usize) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_corpus")
        .join(target);
    let mut all = files(&dir);
    all.extend(files(&dir.join("regressions")));
    assert!(!all.is_empty(), "no corpus in {}", dir.display());
    let (mut ok, mut refused, mut panicked) = (0, 0, Vec::new());
    for f in &all {
        let data = std::fs::read(f).expect("readable");
        match catch_unwind(AssertUnwindSafe(|| check(&data))) {
            Ok(Ok(())) => ok += 1,
            Ok(Err(_)) => refused += 1,
            Err(_) => panicked.push(f.display().to_string()),
        }
    }
    assert!(panicked.is_empty(), "{target}: panicked on {panicked:#?}");
    eprintln!("{target}: {ok} processed, {refused} refused");
    (ok, refused)
}

#[test]
fn scheme_parser_corpus() {
    let (ok, refused) = run("scheme_parser", check_scheme);
    assert!(ok > 0 && refused > 0, "the corpus reaches both outcomes");
}

#[test]
fn obj_reader_corpus() {
    let (ok, refused) = run("obj_reader", check_obj);
    assert!(ok > 0 && refused > 0, "the corpus reaches both outcomes");
}

#[test]
fn ply_reader_corpus() {
    let (ok, refused) = run("ply_reader", check_ply);
    assert!(ok > 0 && refused > 0, "the corpus reaches both outcomes");
}

#[test]
fn pipeline_corpus() {
    let (ok, refused) = run("pipeline", check_pipeline);
    assert!(ok > 0 && refused > 0, "the corpus reaches both outcomes");
}

/// The shipped schemes are in the scheme corpus and pass the check.
#[test]
fn shipped_schemes_pass_the_scheme_check() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("schemes");
    for f in files(&dir) {
        let data = std::fs::read(&f).expect("readable");
        assert_eq!(check_scheme(&data), Ok(()), "{}", f.display());
    }
}
