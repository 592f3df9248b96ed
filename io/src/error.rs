//! The one diagnostic type of lsubdiv: every reader and argument check (scheme files here, meshes
//! and points in the facade, flags in the CLI) says where, what is wrong, and how to fix it; the
//! program at the edge renders it once, lalrpop-style: `file:line:col: error: message` and an
//! indented `hint:` line.

use std::fmt;
use std::path::Path;

/// A place in an input: a file, optionally a 1-based line and column (columns in characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// File name as given by the caller (or a flag such as `--labels`).
    pub file: String,
    /// 1-based line, when the problem is on one.
    pub line: Option<usize>,
    /// 1-based column, when known.
    pub column: Option<usize>,
}

impl Location {
    /// The location of byte `offset` in `text`.
    pub fn from_offset(file: &str, text: &str, offset: usize) -> Location {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        Location {
            file: file.to_string(),
            line: Some(line),
            column: Some(column),
        }
    }

    /// The start of a file (for problems that concern the whole file).
    pub fn file(file: &str) -> Location {
        Location {
            file: file.to_string(),
            line: Some(1),
            column: Some(1),
        }
    }

    /// A file as a whole (no line): for I/O failures and problems found after reading.
    pub fn whole(file: impl fmt::Display) -> Location {
        Location {
            file: file.to_string(),
            line: None,
            column: None,
        }
    }

    /// Line `line` of `file`, without a column.
    pub fn line(file: impl fmt::Display, line: usize) -> Location {
        Location {
            file: file.to_string(),
            line: Some(line),
            column: None,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        Ok(())
    }
}

/// Whose fault a diagnostic is: the input's (exit status 2) or lsubdiv's (1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Bad input: a file, a flag, an unusable L-system, a file that cannot be read or written.
    Input,
    /// An identity that must hold exactly does not: a bug in lsubdiv, not in the input.
    Internal,
}

/// A diagnostic: where (if anywhere in particular), what is wrong, and how to fix it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// Input or internal.
    pub kind: Kind,
    /// Where: a file, line and column; `None` for problems of no file (a flag's value).
    pub at: Option<Location>,
    /// What is wrong (one line, no `error:` prefix).
    pub message: String,
    /// How to fix it.
    pub hint: Option<String>,
}

impl Error {
    /// Bad input at `at`.
    pub fn at(at: Location, message: impl Into<String>) -> Error {
        Error {
            kind: Kind::Input,
            at: Some(at),
            message: message.into(),
            hint: None,
        }
    }

    /// Bad input in `file` as a whole.
    pub fn in_file(file: impl fmt::Display, message: impl Into<String>) -> Error {
        Error::at(Location::whole(file), message)
    }

    /// A file that could not be read or written.
    pub fn io(path: &Path, e: &std::io::Error) -> Error {
        use std::io::ErrorKind as K;
        let hint = match e.kind() {
            K::NotFound => {
                "check the path: a file read must exist, and so must the folder of one written"
            }
            K::PermissionDenied | K::ReadOnlyFilesystem => {
                "check the permissions of the file and of its folder"
            }
            K::StorageFull | K::QuotaExceeded | K::FileTooLarge => {
                "free some space or write elsewhere; a previous file there is intact"
            }
            K::IsADirectory => "name a file, not a folder",
            K::InvalidData => "the file must be text (UTF-8) where text is read",
            _ => "check the path, the links along it and the device it is on",
        };
        Error::in_file(path.display(), e.to_string()).with_hint(hint)
    }

    /// Bad input of no file (a flag, an option of the API).
    pub fn input(message: impl Into<String>) -> Error {
        Error {
            kind: Kind::Input,
            at: None,
            message: message.into(),
            hint: None,
        }
    }

    /// A bug in lsubdiv, placed at the input it concerns when there is one.
    pub fn internal(at: Option<Location>, message: impl Into<String>) -> Error {
        Error {
            kind: Kind::Internal,
            at,
            message: message.into(),
            hint: None,
        }
    }

    /// The same diagnostic with a hint.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Error {
        self.hint = Some(hint.into());
        self
    }

    /// The same diagnostic, with `hint` if it has none.
    pub fn or_hint(self, hint: impl Into<String>) -> Error {
        match self.hint {
            Some(_) => self,
            None => self.with_hint(hint),
        }
    }

    /// The same diagnostic with an optional hint.
    pub fn with_hint_opt(mut self, hint: Option<String>) -> Error {
        self.hint = hint;
        self
    }

    /// Whether the error is lsubdiv's (exit status 1) rather than the input's (2).
    pub fn is_internal(&self) -> bool {
        self.kind == Kind::Internal
    }

    /// What is wrong, without the location or hint (for tables and JSON fields).
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(at) = &self.at {
            write!(f, "{at}: ")?;
        }
        let what = match self.kind {
            Kind::Input => "error",
            Kind::Internal => "internal error",
        };
        write!(f, "{what}: {}", self.message)?;
        if let Some(h) = &self.hint {
            write!(f, "\n  hint: {h}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Error {}
