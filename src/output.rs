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
    write_atomic_with(path, |out| out.write_all(bytes))
}

/// Writes what `content` writes to `path` whole or not at all, streamed
/// ([`lsubdiv::write_atomic_with`]); the error names the path.
pub fn write_atomic_with(
    path: &Path,
    content: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), Error> {
    registered(path, || lsubdiv::write_atomic_with(path, content))
}

/// Runs `write`, a write of `path` whole or not at all (such as `lsubdiv::obj::write_with`),
/// with `path` known to [`remove_partial_files`] meanwhile.
pub fn registered<R>(path: &Path, write: impl FnOnce() -> R) -> R {
    writing().push(path.to_path_buf());
    let result = write();
    writing().retain(|p| p != path);
    result
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

/// `path`'s extension, in lower case.
pub fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// The format that `path`'s extension names (any case) among `formats` (extension without the
/// dot, format); the first one for a name without an extension (`-`, `/dev/null`, `out`).
/// `what` names the kind of file in the error (`picture`, `image`).
pub fn format_by_extension<F: Copy>(
    path: &Path,
    what: &str,
    formats: &[(&str, F)],
) -> Result<F, Error> {
    let ext = extension(path);
    if let Some(&(_, f)) = formats.iter().find(|(e, _)| Some(*e) == ext.as_deref()) {
        return Ok(f);
    }
    if let (None, Some(&(_, first))) = (&ext, formats.first()) {
        return Ok(first);
    }
    let names: Vec<String> = formats.iter().map(|(e, _)| format!(".{e}")).collect();
    let expected = match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    };
    Err(Error::in_file(
        path.display(),
        format!(
            "unknown {what} format `.{}`; the file name must end in {expected}",
            ext.unwrap_or_default()
        ),
    )
    .with_hint(format!(
        "name the output {expected}, or give it no extension for {}",
        names[0]
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_come_from_the_extension_in_any_case() {
        let formats = [("svg", 1), ("png", 2)];
        let of = |p: &str| format_by_extension(Path::new(p), "picture", &formats);
        assert_eq!(of("a/b.SVG"), Ok(1));
        assert_eq!(of("b.png"), Ok(2));
        assert_eq!(
            of("b.jpg").unwrap_err().to_string(),
            "b.jpg: error: unknown picture format `.jpg`; the file name must end in .svg or .png\n  \
             hint: name the output .svg or .png, or give it no extension for .svg"
        );
        assert_eq!(of("b"), Ok(1));
        assert_eq!(of("-"), Ok(1));
        assert_eq!(of("/dev/null"), Ok(1));
    }
}
