//! Running the `lsubdiv` binary as a user does.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `lsubdiv` with `args` and returns what it did.
pub fn lsubdiv(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
        .args(args)
        .output()
        .expect("runs")
}

/// Runs `lsubdiv` with `args`, which must succeed, and parses its standard output as JSON.
pub fn json(args: &[&str]) -> serde_json::Value {
    let o = lsubdiv(args);
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The run's standard error, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}
