//! Errors a user can cause: bad files, bad parameters, bad command lines.
//!
//! Every user-facing failure is one [`InputError`]: the file (or option) it concerns and a one-line
//! description of the problem. The CLI prints it as `error: <file>: <problem>` and exits with code 2.
//! Bugs are not `InputError`s; they stay panics so they are found.

use std::fmt;
use std::path::{Path, PathBuf};

/// A problem with something the user gave us, with the file it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError {
    /// The file (or `--option`) the problem is in.
    pub source: PathBuf,
    /// What is wrong, on one line.
    pub problem: String,
}

impl InputError {
    /// A problem in `source`. Newlines in `problem` are folded so the message stays on one line.
    pub fn new(source: impl AsRef<Path>, problem: impl fmt::Display) -> Self {
        let problem = problem.to_string();
        let problem = problem.split_whitespace().collect::<Vec<_>>().join(" ");
        Self {
            source: source.as_ref().to_path_buf(),
            problem,
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.source.display(), self.problem)
    }
}

impl std::error::Error for InputError {}

/// Result of anything that reads user input.
pub type InputResult<T> = Result<T, InputError>;
