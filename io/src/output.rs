//! Outputs written whole or not at all: a temporary file beside the output, then a rename.
//! Outputs that are not regular files (devices, FIFOs, `-` for standard output) are written
//! directly, never renamed over; a symbolic link is followed, and its target replaced.

use crate::error::Error;
use std::ffi::{OsStr, OsString};
use std::fs;
use std::io::{self, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Bytes of the output's name kept in a temporary name: `.NAME.PID.N.tmp` must fit the
/// 255-byte name limit of common file systems (PID and N take at most 31 bytes).
const MAX_TEMP_STEM: usize = 200;

/// `.NAME.PID.`, NAME cut to [`MAX_TEMP_STEM`] bytes: the start of this process's temporary
/// names for an output called `name`.
fn temp_prefix(name: &OsStr) -> OsString {
    let mut prefix = OsString::from(".");
    if name.len() <= MAX_TEMP_STEM {
        prefix.push(name);
    } else {
        let lossy = name.to_string_lossy();
        let mut cut = MAX_TEMP_STEM.min(lossy.len());
        while !lossy.is_char_boundary(cut) {
            cut -= 1;
        }
        prefix.push(&lossy[..cut]);
    }
    prefix.push(format!(".{}.", std::process::id()));
    prefix
}

/// The folder an output lives in (`.` for a bare name).
fn folder(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Writes bytes to `path` whole or not at all.
///
/// - `-` is standard output; an existing path that is not a regular file or a folder (a
///   device such as `/dev/null` or `/dev/full`, a FIFO, a socket) is opened and written
///   directly: it is never replaced. A full device fails with the system's error.
/// - A symbolic link is followed: its target is replaced, the link stays.
/// - Otherwise the bytes go to a temporary file `.NAME.PID.N.tmp` in the same folder
///   (synced), which is then renamed over `path`; on error the temporary file is removed and a
///   previous file at `path` is intact. The permissions of a previous file are kept. A program
///   interrupted by a signal removes its own temporary files ([`temporary_files`]).
///
/// The error names the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    write_atomic_with(path, |out| out.write_all(bytes))
}

/// [`write_atomic`] of what `content` writes, streamed through a buffer: the output is never
/// held whole in memory. `content` should fail only on I/O (check what can be refused
/// before), so that a device or pipe gets all of it or nothing.
pub fn write_atomic_with(
    path: &Path,
    content: impl FnOnce(&mut dyn io::Write) -> io::Result<()>,
) -> Result<(), Error> {
    write(path, content).map_err(|e| Error::io(path, &e))
}

/// Bytes buffered between `content` and the output.
const BUFFER: usize = 64 << 10;

/// [`write_atomic_with`] before its error is placed.
fn write(
    path: &Path,
    content: impl FnOnce(&mut dyn io::Write) -> io::Result<()>,
) -> io::Result<()> {
    let buffered = |out: &mut dyn io::Write| {
        let mut out = io::BufWriter::with_capacity(BUFFER, out);
        content(&mut out)?;
        out.flush()
    };
    match destination(path)? {
        Some(file) => replace(&file, buffered),
        None if path.as_os_str() == "-" => buffered(&mut io::stdout().lock()),
        None => buffered(&mut fs::OpenOptions::new().write(true).open(path)?),
    }
}

/// Symbolic links followed from an output to the file it names, as Linux's `MAXSYMLINKS`: a
/// chain this long is a loop, or too long for the system to open.
const MAX_LINKS: usize = 40;

/// The regular file that writing `path` replaces: `path` itself, or the end of its chain of
/// symbolic links (each relative to its link's folder; a dangling end names the file to
/// create); `None` for `-` and for what is written directly (devices, FIFOs, sockets). A
/// loop, or a chain past [`MAX_LINKS`], is an error.
fn destination(path: &Path) -> io::Result<Option<PathBuf>> {
    if path.as_os_str() == "-" || fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        return Ok(None);
    }
    let mut end = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&end) {
            Ok(m) if m.file_type().is_symlink() => end = folder(&end).join(fs::read_link(&end)?),
            _ => return Ok(Some(end)),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("more than {MAX_LINKS} symbolic links from here: a loop, or a chain too long"),
    ))
}

/// Writes `text` to `path` unless it already holds exactly that (so that cargo sees no change
/// and rebuilds nothing), then whole or not at all ([`write_atomic`]).
pub fn write_if_changed(path: &Path, text: &str) -> Result<(), Error> {
    if fs::read_to_string(path).is_ok_and(|old| old == text) {
        return Ok(());
    }
    write_atomic(path, text.as_bytes())
}

/// Writes a regular file by a temporary file and a rename (see [`write_atomic`]).
fn replace(
    path: &Path,
    content: impl FnOnce(&mut dyn io::Write) -> io::Result<()>,
) -> io::Result<()> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        )
    })?;
    let dir = folder(path);
    let prefix = temp_prefix(name);
    let mut attempt = 0;
    let (tmp, mut file) = loop {
        let mut tmp_name = prefix.clone();
        tmp_name.push(format!(
            "{}.tmp",
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
    let result = content(&mut file)
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
    let Ok(Some(file)) = destination(path) else {
        return Vec::new();
    };
    let Some(name) = file.file_name() else {
        return Vec::new();
    };
    let prefix = temp_prefix(name).to_string_lossy().into_owned();
    fs::read_dir(folder(&file))
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
    fn a_streamed_write_failing_midway_keeps_the_previous_file() {
        let dir = scratch_dir("stream");
        let path = dir.join("mesh.obj");
        fs::write(&path, b"previous").unwrap();
        // More than the buffer holds goes out before the failure.
        let failing = |out: &mut dyn io::Write| {
            out.write_all(&vec![b'v'; 3 * BUFFER])?;
            Err(io::Error::other("the content failed"))
        };
        let e = write_atomic_with(&path, failing).unwrap_err();
        assert!(e.to_string().contains("the content failed"), "{e}");
        assert_eq!(fs::read(&path).unwrap(), b"previous");
        assert_eq!(entries(&dir), vec!["mesh.obj"]);
        // Streamed in pieces, it is the file.
        write_atomic_with(&path, |out| (0..1000).try_for_each(|i| write!(out, "{i} "))).unwrap();
        let want: String = (0..1000).map(|i| format!("{i} ")).collect();
        assert_eq!(fs::read_to_string(&path).unwrap(), want);
        assert_eq!(entries(&dir), vec!["mesh.obj"]);
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

    #[test]
    fn a_symbolic_link_keeps_pointing_at_its_replaced_target() {
        let dir = scratch_dir("link");
        let (real, link) = (dir.join("real.obj"), dir.join("link.obj"));
        fs::write(&real, b"old").unwrap();
        std::os::unix::fs::symlink("real.obj", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(&real).unwrap(), b"new");
        // A dangling link: its target is created, the link stays.
        let dangling = dir.join("dangling.obj");
        std::os::unix::fs::symlink("made.obj", &dangling).unwrap();
        write_atomic(&dangling, b"made").unwrap();
        assert!(fs::symlink_metadata(&dangling)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(dir.join("made.obj")).unwrap(), b"made");
        assert_eq!(
            entries(&dir),
            vec!["dangling.obj", "link.obj", "made.obj", "real.obj"]
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_fifo_is_written_not_replaced() {
        let dir = scratch_dir("fifo");
        let fifo = dir.join("out.pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("no mkfifo here: skipped");
            return;
        }
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || fs::read(fifo).unwrap())
        };
        write_atomic(&fifo, b"through the pipe").unwrap();
        assert_eq!(reader.join().unwrap(), b"through the pipe");
        use std::os::unix::fs::FileTypeExt as _;
        assert!(fs::metadata(&fifo).unwrap().file_type().is_fifo());
        assert_eq!(entries(&dir), vec!["out.pipe"]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_long_name_gets_a_temporary_name_within_the_limit() {
        let dir = scratch_dir("long");
        let path = dir.join(format!("{}.obj", "é".repeat(123))); // 250 bytes
        write_atomic(&path, b"long").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"long");
        let tmp = temp_prefix(path.file_name().unwrap());
        assert!(tmp.len() + 24 <= 255, "{}", tmp.len());
        assert_eq!(entries(&dir).len(), 1);
        fs::remove_dir_all(&dir).unwrap();
    }
}
