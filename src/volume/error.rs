//! Errors of the volume module: every message names the file, the grid where
//! there is one, and the reason.

use std::path::PathBuf;

/// Why a VDB file or one of its grids could not be read.
#[derive(Debug, thiserror::Error)]
pub enum VolumeError {
    /// The file could not be read from disk at all.
    #[error("{path}: cannot read file: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The file is not an OpenVDB file, or its header or grid list is damaged.
    #[error("{path}: not a readable OpenVDB file: {reason}")]
    BadFile {
        /// The file.
        path: PathBuf,
        /// What was wrong, with the byte offset where it was found.
        reason: String,
    },
    /// No grid of that name is in the file.
    #[error("{path}: no grid named '{grid}' (grids in the file: {available})")]
    GridNotFound {
        /// The file.
        path: PathBuf,
        /// The requested name.
        grid: String,
        /// The names that are present, comma separated.
        available: String,
    },
    /// The grid exists but uses something brume does not read (value type, map, codec).
    #[error("{path}: grid '{grid}': unsupported: {reason}")]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The grid.
        grid: String,
        /// What is unsupported.
        reason: String,
    },
    /// The grid's bytes are damaged or truncated.
    #[error("{path}: grid '{grid}': corrupt data: {reason}")]
    CorruptGrid {
        /// The file.
        path: PathBuf,
        /// The grid.
        grid: String,
        /// What was wrong, with the byte offset where it was found.
        reason: String,
    },
}

impl From<VolumeError> for crate::error::Error {
    fn from(e: VolumeError) -> Self {
        crate::error::Error::Volume(e.to_string())
    }
}

/// A parse failure before the file and grid names are attached.
#[derive(Debug, Clone)]
pub(crate) enum FormatError {
    /// Damaged, truncated or inconsistent bytes.
    Corrupt(String),
    /// Well-formed, but a feature brume does not read.
    Unsupported(String),
}

impl FormatError {
    /// A corruption error found at byte `offset`.
    pub(crate) fn corrupt(offset: usize, reason: impl std::fmt::Display) -> Self {
        FormatError::Corrupt(format!("{reason} (at byte {offset})"))
    }

    /// Attaches the file and grid names.
    pub(crate) fn for_grid(self, path: &std::path::Path, grid: &str) -> VolumeError {
        match self {
            FormatError::Corrupt(reason) => VolumeError::CorruptGrid {
                path: path.to_path_buf(),
                grid: grid.to_string(),
                reason,
            },
            FormatError::Unsupported(reason) => VolumeError::Unsupported {
                path: path.to_path_buf(),
                grid: grid.to_string(),
                reason,
            },
        }
    }

    /// Attaches the file name, for errors in the header or grid list.
    pub(crate) fn for_file(self, path: &std::path::Path) -> VolumeError {
        let reason = match self {
            FormatError::Corrupt(r) => r,
            FormatError::Unsupported(r) => format!("unsupported: {r}"),
        };
        VolumeError::BadFile {
            path: path.to_path_buf(),
            reason,
        }
    }
}

/// Result of the internal parsers.
pub(crate) type FResult<T> = Result<T, FormatError>;
