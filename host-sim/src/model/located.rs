//! An error in an input file: where (`file`, `line`) and what (`kind`), the
//! one shape of [`crate::model::mechanism_toml::MechanismError`] and
//! [`crate::data::run::RunError`].

use std::fmt;

/// An error at `file:line`: displayed as `file:line: kind` (`file: kind`
/// without a line), `kind` saying what was wrong and what was expected.
#[derive(Debug)]
pub struct Located<K> {
    /// The file, as given (a path or a name for text read from memory).
    pub file: String,
    /// 1-based line, when the error is about one.
    pub line: Option<usize>,
    /// What was wrong.
    pub kind: K,
}

impl<K> Located<K> {
    /// An error at `line` (if known) of `file`.
    pub fn new(file: &str, line: Option<usize>, kind: K) -> Self {
        Located {
            file: file.to_string(),
            line,
            kind,
        }
    }

    /// The 1-based line the error points at, when there is one.
    pub fn line(&self) -> Option<usize> {
        self.line
    }
}

impl<K: fmt::Display> fmt::Display for Located<K> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{l}: {}", self.file, self.kind),
            None => write!(f, "{}: {}", self.file, self.kind),
        }
    }
}

impl<K: std::error::Error> std::error::Error for Located<K> {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.kind.source()
    }
}
