//! The output-safety rule: brume never overwrites a file the run reads, never
//! writes two outputs of one run to the same file, and never lets a partial
//! image replace a better one.
//!
//! Every command that writes (render, render --frames, merge, compare --diff,
//! airlight, checkpoints) lists what it reads and what it may write in a
//! [`Plan`] and calls [`Plan::check`] before any work. Files are compared by
//! identity, not by spelling: an existing file by device and inode (so `./x`,
//! an absolute path, a symbolic link and a hard link are all the same file),
//! a file still to be created by its canonical path (folders and links
//! resolved). A later writer (a slab bake, an integrator's debug image) does
//! the same: `Plan::new("bake")`, `.input(..)` for each file read,
//! `.output(..)` (or `.image_output(..)` for an image that may be partial)
//! for each file written, then `.check()?`.
//!
//! Partial images (an interrupted render, a checkpoint, a merge of
//! interrupted pieces) go through [`place_partial`], which keeps a complete
//! image or one of more samples and writes the partial beside it.

mod partial;
mod writable;

pub use partial::{partial_path, place_partial, Placement};
pub use writable::{canonical, destination};

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// What a file is, whatever the spelling of its path.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Identity {
    /// An existing file (after symbolic links): its device and inode.
    File {
        /// Device number.
        dev: u64,
        /// Inode number.
        ino: u64,
    },
    /// A file not yet there: its absolute path, folders and links resolved.
    Path(PathBuf),
}

/// The identity of the file `path` names (following symbolic links).
pub fn identity(path: &Path) -> Identity {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(m) = std::fs::metadata(path) {
            return Identity::File {
                dev: m.dev(),
                ino: m.ino(),
            };
        }
    }
    Identity::Path(canonical(path))
}

/// A file of the run, with how the user named it.
#[derive(Clone, Debug)]
struct Entry {
    /// The flag (`--out`) or key (`medium[0].file`) that names it.
    who: String,
    /// The path as the user (or the scene) wrote it.
    path: PathBuf,
    /// Which frame, or why brume may write it (` (frame 3)`), with its leading space.
    context: String,
}

impl Entry {
    fn show(&self) -> String {
        format!("{}{}", self.path.display(), self.context)
    }
}

/// Every file one run reads and may write, checked together by [`Plan::check`].
#[derive(Debug)]
pub struct Plan {
    run: String,
    inputs: Vec<Entry>,
    sequences: Vec<Entry>,
    outputs: Vec<Entry>,
}

impl Plan {
    /// An empty plan for a run of `run` ("render", "merge", ...), as messages name it.
    pub fn new(run: &str) -> Plan {
        Plan {
            run: run.into(),
            inputs: Vec::new(),
            sequences: Vec::new(),
            outputs: Vec::new(),
        }
    }

    /// A file the run reads: `what` names it (`piece`, `medium[0].file of frame 5`).
    pub fn input(&mut self, what: &str, path: &Path) -> &mut Plan {
        self.inputs.push(Entry {
            who: what.into(),
            path: path.to_path_buf(),
            context: String::new(),
        });
        self
    }

    /// A frame pattern (`smoke.####.vdb`) the run reads from: no output may add a file to it.
    pub fn input_sequence(&mut self, what: &str, pattern: &Path) -> &mut Plan {
        if !self.sequences.iter().any(|e| e.path == pattern) {
            self.sequences.push(Entry {
                who: what.into(),
                path: pattern.to_path_buf(),
                context: String::new(),
            });
        }
        self
    }

    /// A file the run may write, named by `flag`; `context` is shown after
    /// the path in messages (e.g. `frame 3`).
    pub fn output(&mut self, flag: &str, path: &Path, context: Option<&str>) -> &mut Plan {
        self.outputs.push(Entry {
            who: flag.into(),
            path: path.to_path_buf(),
            context: context.map(|c| format!(" ({c})")).unwrap_or_default(),
        });
        self
    }

    /// An image the run may write partial: the file, and the one beside it
    /// ([`partial_path`]) where a partial image goes when the file holds a better one.
    pub fn image_output(&mut self, flag: &str, path: &Path, context: Option<&str>) -> &mut Plan {
        self.output(flag, path, context);
        let beside = match context {
            Some(c) => format!("{c}, where a partial image of it may go"),
            None => "where a partial image of it may go".to_string(),
        };
        self.output(flag, &partial_path(path), Some(&beside))
    }

    /// Refuses the run (exit code 2, one line naming the flag and both
    /// paths) if an output cannot be written, is an input, would add a file
    /// to an input sequence, or is the same file as another output.
    pub fn check(&self) -> Result<()> {
        let mut probed = std::collections::HashSet::new();
        for out in &self.outputs {
            writable::check(&out.path, &mut probed)
                .map_err(|problem| refuse(out, format!("{}: {problem}", out.show())))?;
        }
        let ids: Vec<Identity> = self.outputs.iter().map(|o| identity(&o.path)).collect();
        let mut inputs = HashMap::new();
        for input in &self.inputs {
            inputs.entry(identity(&input.path)).or_insert(input);
        }
        for (out, id) in self.outputs.iter().zip(&ids) {
            if let Some(input) = inputs.get(id) {
                return Err(refuse(
                    out,
                    format!(
                        "{} is an input of the {} ({}: {}); brume never overwrites its inputs",
                        out.show(),
                        self.run,
                        input.who,
                        input.path.display()
                    ),
                ));
            }
        }
        self.check_sequences()?;
        let mut seen: HashMap<&Identity, &Entry> = HashMap::new();
        for (out, id) in self.outputs.iter().zip(&ids) {
            if let Some(first) = seen.insert(id, out) {
                return Err(refuse(
                    out,
                    format!(
                        "{} is the same file as {} {}; give each output its own file",
                        out.show(),
                        first.who,
                        first.show()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Refuses an output whose name is a frame of an input sequence.
    fn check_sequences(&self) -> Result<()> {
        for seq in &self.sequences {
            let Some(folder) = seq.path.parent().map(canonical_folder) else {
                continue;
            };
            for out in &self.outputs {
                let dest = canonical(&out.path);
                let in_folder = dest.parent() == Some(folder.as_path());
                let name = dest.file_name().map(|n| n.to_string_lossy().to_string());
                if in_folder && name.is_some_and(|n| frame_of(&seq.path, &n)) {
                    return Err(refuse(
                        out,
                        format!(
                            "{} would be a frame of the sequence {} that {} reads; \
                             brume never writes into its input sequences",
                            out.show(),
                            seq.path.display(),
                            seq.who
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The absolute form of a folder (`.` for an empty one).
fn canonical_folder(folder: &Path) -> PathBuf {
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    folder
        .canonicalize()
        .unwrap_or_else(|_| folder.to_path_buf())
}

/// Whether the file name `name` is a frame of `pattern`'s sequence: the
/// pattern's file name with its `#` run replaced by digits (and a sign), as
/// `missing_frames` finds the frames on disk.
fn frame_of(pattern: &Path, name: &str) -> bool {
    let Some(pattern_name) = pattern.file_name().and_then(|n| n.to_str()) else {
        return false;
    };
    let Some(start) = pattern_name.find('#') else {
        return false;
    };
    let width = pattern_name[start..]
        .chars()
        .take_while(|&c| c == '#')
        .count();
    let (prefix, suffix) = (&pattern_name[..start], &pattern_name[start + width..]);
    let digits = name
        .strip_prefix(prefix)
        .and_then(|rest| rest.strip_suffix(suffix));
    digits.is_some_and(|d| {
        let d = d.strip_prefix('-').unwrap_or(d);
        !d.is_empty() && d.chars().all(|c| c.is_ascii_digit())
    })
}

fn refuse(out: &Entry, message: String) -> Error {
    Error::Argument {
        argument: out.who.clone(),
        message,
    }
}

#[cfg(test)]
mod tests;
