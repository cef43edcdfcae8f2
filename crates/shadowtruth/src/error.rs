//! The one error type of the library's entry points (`src/api.rs`): each module's own error
//! converts into it, so an embedder matches on one enum.

use crate::import::ImportError;
use crate::scene::SceneError;
use crate::technique::TechniqueSpecError;
use crate::trace::AreaLightError;

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A scene file that cannot be read: every problem with its file and JSON path.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A technique's parameters are out of their range.
    #[error("technique {technique}: {source}")]
    Technique { technique: String, source: TechniqueSpecError },
    /// An area-light reference of a light without a usable size.
    #[error(transparent)]
    AreaLight(#[from] AreaLightError),
    /// A visibility buffer that does not fit the G-buffer, or a value outside [0, 1].
    #[error("visibility buffer: {0}")]
    Visibility(String),
    /// An imported image (`crate::import`) that cannot be read or does not fit the view: the
    /// file, and the pixel for a bad value.
    #[error("{}: {message}", path.display())]
    Import { path: std::path::PathBuf, message: String },
    /// An argument outside its range (a shadow-map resolution, …).
    #[error("{0}")]
    Invalid(String),
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// `Result` with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// An import's error as the entry points' one: its file problems are `Error::Import`.
impl From<ImportError> for Error {
    fn from(error: ImportError) -> Self {
        match error {
            ImportError::File { path, message } => Error::Import { path, message },
            ImportError::Invalid(message) => Error::Invalid(message),
        }
    }
}
