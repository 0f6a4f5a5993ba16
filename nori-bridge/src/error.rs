//! Input errors that name where the bad value is.

use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{file}:{line}: {msg}")]
    AtLine {
        file: String,
        line: usize,
        msg: String,
    },
    #[error("{file}: {msg}")]
    InFile { file: String, msg: String },
}

pub fn at_line(file: &Path, line: usize, msg: impl Into<String>) -> InputError {
    InputError::AtLine {
        file: file.display().to_string(),
        line,
        msg: msg.into(),
    }
}

pub fn in_file(file: &Path, msg: impl Into<String>) -> InputError {
    InputError::InFile {
        file: file.display().to_string(),
        msg: msg.into(),
    }
}
