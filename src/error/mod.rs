//! The one error type of brume, with the exit code each kind maps to.

pub mod limits;

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
    /// A Mitsuba 3 XML scene holds what brume cannot import (or a mistake).
    #[error("{}:{line}: {element}: {message}", file.display())]
    Import {
        /// The XML file holding the element (an included file if there).
        file: PathBuf,
        /// Line of the element in that file.
        line: u32,
        /// The element as written, e.g. `<bsdf type="plastic">`.
        element: String,
        /// What is wrong.
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
    /// An OpenVDB file or grid cannot be used: the volume reader's message,
    /// which names the file and grid (converted in `volume`, so that this
    /// leaf every room uses imports none of them).
    #[error("{0}")]
    Volume(String),
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

/// Why `path` cannot be read as an input file, if it cannot: missing, a
/// folder, not a regular file (a FIFO or device such as /dev/zero, which
/// would block or never end) or larger than `max_bytes`.
pub fn input_file_problem(path: &std::path::Path, max_bytes: u64) -> Option<String> {
    let meta = match regular_file(path) {
        Ok(m) => m,
        Err(problem) => return Some(problem),
    };
    if meta.len() > max_bytes {
        return Some(format!(
            "is {:.1} MB, more than the {:.0} MB brume reads for this kind of file",
            meta.len() as f64 / 1e6,
            max_bytes as f64 / 1e6
        ));
    }
    None
}

/// The one check every reader of a file makes before opening it: the path
/// (after symbolic links) is an existing regular file. Only `stat` is used,
/// so a FIFO (whose `open` would block until a writer comes), a device or a
/// socket is refused without ever being opened. The error says what the path is.
pub fn regular_file(path: &std::path::Path) -> std::result::Result<std::fs::Metadata, String> {
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err("no such file".into()),
        Err(e) => return Err(e.to_string()),
    };
    if meta.is_dir() {
        return Err("is a directory, not a file".into());
    }
    if !meta.is_file() {
        return Err(format!(
            "is not a regular file ({}); brume reads only regular files",
            file_kind(&meta)
        ));
    }
    Ok(meta)
}

/// What a non-regular file is, in words.
fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
    }
    let _ = meta;
    "a FIFO, socket or device"
}

/// Result with brume's error.
pub type Result<T> = std::result::Result<T, Error>;
