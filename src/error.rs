//! The one error type of brume, with the exit code each kind maps to.

use std::path::PathBuf;

/// Everything that can stop brume, each naming the file and the culprit.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file is malformed or holds an invalid value.
    #[error("{}: {field}: {message}", file.display())]
    Scene {
        /// The scene file.
        file: PathBuf,
        /// Dotted path of the offending entry, e.g. `shape[2].material.albedo`.
        field: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// An input file (scene, OBJ, VDB) cannot be read.
    #[error("{}: {message}", path.display())]
    Input {
        /// The file.
        path: PathBuf,
        /// Why it cannot be used.
        message: String,
    },
    /// An OpenVDB file or grid cannot be used.
    #[error(transparent)]
    Volume(#[from] crate::volume::VolumeError),
    /// A command-line value is invalid.
    #[error("invalid argument {argument}: {message}")]
    Argument {
        /// The flag or argument.
        argument: String,
        /// What is wrong.
        message: String,
    },
    /// Pieces of a split render that cannot be merged into one image.
    #[error("cannot merge: {message}")]
    Merge {
        /// Which piece and what is wrong with it.
        message: String,
    },
    /// An output file cannot be written.
    #[error("{}: cannot write output: {message}", path.display())]
    Output {
        /// The output file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl Error {
    /// Process exit code: 2 for bad input, 1 for failures while running.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Output { .. } => 1,
            _ => 2,
        }
    }
}

/// Result with brume's error.
pub type Result<T> = std::result::Result<T, Error>;
