//! Errors as values: every one names its place (file, line, column) and what is wrong.

use std::fmt;

/// A place in a source file (1-based line and column, columns counted in characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// File name as given by the caller.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
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
            line,
            column,
        }
    }

    /// The start of a file (for problems that concern the whole scheme).
    pub fn file(file: &str) -> Location {
        Location {
            file: file.to_string(),
            line: 1,
            column: 1,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// Everything that can go wrong in the compiler.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Error {
    /// A file could not be read or written.
    Io {
        /// The path.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A scheme file is malformed or describes an unusable L-system.
    Scheme {
        /// Where.
        at: Location,
        /// What is wrong.
        message: String,
        /// How to fix it.
        hint: Option<String>,
    },
    /// Input other than a scheme file (labels, polygons) is unusable.
    Input(String),
    /// An identity that must hold exactly does not: a bug in the compiler, not in the input.
    Internal(String),
}

impl Error {
    /// Whether the error is in the input (exit status 2) rather than in lsubdiv (1).
    pub fn is_internal(&self) -> bool {
        matches!(self, Error::Internal(_))
    }

    /// A scheme-level error located at the start of the file.
    pub fn scheme(file: &str, message: String, hint: Option<String>) -> Error {
        Error::Scheme {
            at: Location::file(file),
            message,
            hint,
        }
    }
}

impl Error {
    /// What is wrong, without the location or hint (for tables and JSON fields).
    pub fn message(&self) -> String {
        match self {
            Error::Io { message, .. } | Error::Scheme { message, .. } => message.clone(),
            Error::Input(m) | Error::Internal(m) => m.clone(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, message } => write!(f, "{path}: error: {message}"),
            Error::Scheme { at, message, hint } => {
                write!(f, "{at}: error: {message}")?;
                if let Some(h) = hint {
                    write!(f, "\n  hint: {h}")?;
                }
                Ok(())
            }
            Error::Input(m) => write!(f, "error: {m}"),
            Error::Internal(m) => write!(f, "internal error: {m}"),
        }
    }
}

impl std::error::Error for Error {}
