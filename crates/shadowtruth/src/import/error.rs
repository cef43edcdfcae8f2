//! What can go wrong reading another renderer's buffers: the import's own error, which the
//! library's entry points turn into their `Error` (src/error.rs).

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// An image or sidecar that cannot be read or does not fit the view: the file, and the pixel
    /// for a bad value.
    #[error("{}: {message}", path.display())]
    File { path: PathBuf, message: String },
    /// An argument outside its range (a depth tolerance, …).
    #[error("{0}")]
    Invalid(String),
}

/// `Result` with [`ImportError`].
pub type Result<T, E = ImportError> = std::result::Result<T, E>;
