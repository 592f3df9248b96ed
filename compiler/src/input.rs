//! Text inputs (scheme, mesh and point files) as every reader of lsubdiv takes them.

use crate::error::Error;
use std::path::Path;

/// Reads a text file: a UTF-8 byte-order mark is dropped (it would hide the first line's first
/// token), and bytes that are not UTF-8 (a Latin-1 comment) become U+FFFD, so that a comment
/// passes and a number containing one is refused at its line by the parser.
pub fn read_text(path: &Path) -> Result<String, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, &e))?;
    let mut text = String::from_utf8(bytes)
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
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
        assert_eq!(read_text(&p).unwrap(), "1 2\n# caf\u{fffd}\n");
        std::fs::write(&p, b"1 2\n").unwrap();
        assert_eq!(read_text(&p).unwrap(), "1 2\n");
        let e = read_text(&dir.join("missing.txt")).unwrap_err();
        assert!(e.to_string().contains("missing.txt: error:"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
