//! The command line's outputs: each written whole or not at all ([`lsubdiv::write_atomic`]),
//! and the temporary files of an interrupted run removed by the signal handler.

use lsubdiv::compiler::Error;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The outputs this run is writing, for [`remove_partial_files`].
static WRITING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn writing() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    WRITING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Writes `bytes` to `path` whole or not at all; the error names the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    writing().push(path.to_path_buf());
    let result = lsubdiv::compiler::write_atomic(path, bytes);
    writing().retain(|p| p != path);
    result.map_err(|e| Error::io(path, &e))
}

/// Removes the temporary files of the writes in progress (for a signal handler, which then
/// exits): outputs are only ever replaced by a rename, so the previous ones stay intact.
pub fn remove_partial_files() {
    for p in writing().iter() {
        for tmp in lsubdiv::compiler::temporary_files(p) {
            let _ = std::fs::remove_file(tmp);
        }
    }
}
