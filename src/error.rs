//! Errors are values: one [`Error`] enum for the whole crate.
//!
//! Caller errors (a bad SWC file, a bad parameter, an unreadable mesh file) carry
//! what a user needs to fix them: the file, the 1-based line and the reason. They
//! render as `FILE:LINE: reason`, which is what the CLI prints after `error: ` and
//! what the Python layer puts into `neuromesh_rs.SwcError`. Internal failures
//! (a broken invariant) are a separate variant that asks for a bug report.

use std::fmt;
use std::path::Path;

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// A malformed SWC input: which file (or `<arrays>`), which line, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SwcError {
    /// The file as the user named it, or `<arrays>` for in-memory input.
    pub path: String,
    /// 1-based line number in the file (row number + 1 for arrays).
    pub line: usize,
    /// What is wrong, written for the user.
    pub reason: String,
}

impl fmt::Display for SwcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.path, self.line, self.reason)
    }
}

impl std::error::Error for SwcError {}

/// Everything that can go wrong in neuromesh.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The SWC input is malformed.
    #[error("{0}")]
    Swc(SwcError),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file as the user named it.
        path: String,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// A mesh file (OBJ, PLY, STL) could not be understood.
    #[error("{}", located(path, *line, reason))]
    MeshFile {
        /// The file as the user named it.
        path: String,
        /// 1-based line for text formats, 0 when no line applies (binary formats).
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// A parameter is out of its valid range.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParam {
        /// The parameter's name, as in the CLI flag and the Python keyword.
        name: &'static str,
        /// Why the value is rejected.
        reason: String,
    },
    /// A mesh given by the caller is unusable (bad shapes, out-of-range indices).
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// A broken internal invariant: this is a bug in neuromesh.
    #[error("internal error: {0} (this is a bug; please file an issue with the input)")]
    Internal(String),
}

fn located(path: &str, line: usize, reason: &str) -> String {
    if line > 0 {
        format!("{path}:{line}: {reason}")
    } else {
        format!("{path}: {reason}")
    }
}

impl Error {
    /// Builds an [`Error::Swc`].
    pub fn swc(path: &str, line: usize, reason: impl Into<String>) -> Self {
        Error::Swc(SwcError {
            path: path.to_owned(),
            line,
            reason: reason.into(),
        })
    }

    /// Builds an [`Error::Io`] for `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Error::Io {
            path: path.display().to_string(),
            source,
        }
    }

    /// Builds an [`Error::MeshFile`].
    pub fn mesh_file(path: &Path, line: usize, reason: impl Into<String>) -> Self {
        Error::MeshFile {
            path: path.display().to_string(),
            line,
            reason: reason.into(),
        }
    }

    /// The 1-based line this error points at, if any.
    pub fn line(&self) -> Option<usize> {
        match self {
            Error::Swc(e) => Some(e.line),
            Error::MeshFile { line, .. } if *line > 0 => Some(*line),
            _ => None,
        }
    }

    /// The file this error is about, if any.
    pub fn path(&self) -> Option<&str> {
        match self {
            Error::Swc(e) => Some(&e.path),
            Error::Io { path, .. } | Error::MeshFile { path, .. } => Some(path),
            _ => None,
        }
    }
}

impl From<SwcError> for Error {
    fn from(e: SwcError) -> Self {
        Error::Swc(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swc_error_renders_file_line_reason() {
        let e = Error::swc("cell.swc", 12, "expected 7 fields, found 5");
        assert_eq!(e.to_string(), "cell.swc:12: expected 7 fields, found 5");
        assert_eq!(e.line(), Some(12));
        assert_eq!(e.path(), Some("cell.swc"));
    }

    #[test]
    fn io_error_names_the_file() {
        let e = Error::io(
            Path::new("missing.swc"),
            std::io::Error::new(std::io::ErrorKind::NotFound, "No such file"),
        );
        assert!(e.to_string().starts_with("missing.swc: "));
        assert_eq!(e.line(), None);
    }
}
