//! Outputs written whole or not at all: a temporary file beside the output, then a rename.

use std::ffi::OsString;
use std::fs;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes bytes to `path` atomically: a temporary file `.NAME.PID.N.tmp` in the same directory
/// (synced), then rename; on error the temporary file is removed and a previous file at `path`
/// is intact. The permissions of a previous file are kept. A program interrupted by a signal
/// removes its own `.NAME.PID.*.tmp` files ([`temporary_files`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        )
    })?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut attempt = 0;
    let (tmp, mut file) = loop {
        let mut tmp_name = OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(
            ".{}.{}.tmp",
            std::process::id(),
            TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let tmp = dir.join(tmp_name);
        match fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => {
                break (tmp, file);
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempt < 100 => attempt += 1,
            Err(e) => return Err(e),
        }
    };
    let result = file
        .write_all(bytes)
        .and_then(|()| file.sync_all())
        .and_then(|()| {
            drop(file);
            if let Ok(meta) = fs::metadata(path) {
                if meta.is_file() {
                    fs::set_permissions(&tmp, meta.permissions())?;
                }
            }
            fs::rename(&tmp, path)
        });
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result?;
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(dir) {
        // Best effort: make the rename durable.
        let _ = d.sync_all();
    }
    Ok(())
}

/// The temporary files this process may have left beside `path` (`.NAME.PID.*.tmp`): what a
/// signal handler removes before exiting, so that an interrupted run leaves no partial file.
pub fn temporary_files(path: &Path) -> Vec<PathBuf> {
    let (Some(name), dir) = (path.file_name(), path.parent()) else {
        return Vec::new();
    };
    let dir = match dir {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut prefix = OsString::from(".");
    prefix.push(name);
    prefix.push(format!(".{}.", std::process::id()));
    let prefix = prefix.to_string_lossy().into_owned();
    fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .map(|n| n.to_string_lossy())
                .is_some_and(|n| n.starts_with(&prefix) && n.ends_with(".tmp"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "lsubdiv-mesh-{tag}-{}-{}",
            std::process::id(),
            TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn write_atomic_replaces_and_leaves_no_temp_file() {
        let dir = scratch_dir("ok");
        let path = dir.join("mesh.obj");
        write_atomic(&path, b"first").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"first");
        write_atomic(&path, b"second, longer").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"second, longer");
        write_atomic(&path, b"").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"");
        assert_eq!(entries(&dir), vec!["mesh.obj"]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn write_atomic_failure_keeps_previous_state() {
        let dir = scratch_dir("fail");
        // Target is a (non-empty) directory: the rename fails, the directory is intact.
        let target = dir.join("out.obj");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("keep"), b"kept").unwrap();
        fs::write(dir.join("previous.obj"), b"previous").unwrap();
        assert!(write_atomic(&target, b"new").is_err());
        assert!(target.is_dir());
        assert_eq!(fs::read(target.join("keep")).unwrap(), b"kept");
        assert_eq!(entries(&dir), vec!["out.obj", "previous.obj"]);
        // Missing parent directory: error, nothing created.
        assert!(write_atomic(&dir.join("missing").join("x.obj"), b"new").is_err());
        assert_eq!(entries(&dir), vec!["out.obj", "previous.obj"]);
        // No file name.
        assert!(write_atomic(Path::new("/"), b"new").is_err());
        assert_eq!(fs::read(dir.join("previous.obj")).unwrap(), b"previous");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn temporary_files_names_only_this_process() {
        let dir = scratch_dir("tmp");
        let path = dir.join("out.obj");
        let mine = dir.join(format!(".out.obj.{}.7.tmp", std::process::id()));
        fs::write(&mine, b"partial").unwrap();
        fs::write(dir.join(".out.obj.1.7.tmp"), b"another process").unwrap();
        assert_eq!(temporary_files(&path), vec![mine]);
        fs::remove_dir_all(&dir).unwrap();
    }
}
