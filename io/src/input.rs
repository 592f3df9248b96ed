//! Inputs (scheme, mesh and point files) as every reader of lsubdiv takes them: bounded, so that
//! a pipe or a device is never read without end, and text decoded one way.

use crate::error::Error;
use std::io::Read;
use std::path::Path;

/// Reads a file of at most `max` bytes. A regular file is refused unread when it is larger; a
/// pipe, a device or standard input is read only up to `max + 1` bytes, and refused if there
/// are more, so no input holds more than `max` bytes whatever it is.
pub fn read_bytes(path: &Path, max: u64) -> Result<Vec<u8>, Error> {
    let refuse = |what: String| {
        Error::in_file(
            path.display(),
            format!("{what}; at most {max} bytes are read from an input"),
        )
    };
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, &e))?;
    let meta = file.metadata().map_err(|e| Error::io(path, &e))?;
    if meta.is_file() && meta.len() > max {
        return Err(refuse(format!("the file has {} bytes", meta.len())));
    }
    let mut bytes = Vec::new();
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, &e))?;
    if bytes.len() as u64 > max {
        return Err(refuse(format!("the input has more than {max} bytes")));
    }
    Ok(bytes)
}

/// Reads a text file of at most `max` bytes ([`read_bytes`]) and decodes it by [`text`].
pub fn read_text(path: &Path, max: u64) -> Result<String, Error> {
    read_bytes(path, max).map(text)
}

/// Decodes an input's bytes: a UTF-8 byte-order mark is dropped (it would hide the first line's
/// first token), and bytes that are not UTF-8 (a Latin-1 comment) become U+FFFD, so that a
/// comment passes and a number containing one is refused at its line by the parser.
pub fn text(bytes: Vec<u8>) -> String {
    let mut text = String::from_utf8(bytes)
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_order_mark_and_latin1_bytes() {
        let dir = std::env::temp_dir().join(format!("lsubdiv-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.txt");
        std::fs::write(&p, b"\xEF\xBB\xBF1 2\n# caf\xE9\n").unwrap();
        assert_eq!(read_text(&p, 100).unwrap(), "1 2\n# caf\u{fffd}\n");
        std::fs::write(&p, b"1 2\n").unwrap();
        assert_eq!(read_text(&p, 100).unwrap(), "1 2\n");
        let e = read_text(&dir.join("missing.txt"), 100).unwrap_err();
        assert!(e.to_string().contains("missing.txt: error:"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn inputs_past_the_bound_are_refused_whatever_they_are() {
        let dir = std::env::temp_dir().join(format!("lsubdiv-bound-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.txt");
        std::fs::write(&p, b"0123456789").unwrap();
        assert_eq!(read_bytes(&p, 10).unwrap().len(), 10);
        let e = read_bytes(&p, 9).unwrap_err().to_string();
        assert!(
            e.contains("t.txt: error: the file has 10 bytes; at most 9"),
            "{e}"
        );
        // A device with no end is read only to the bound.
        let e = read_bytes(Path::new("/dev/zero"), 1000)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/dev/zero: error: the input has more than 1000 bytes"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
