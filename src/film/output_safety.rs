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
pub use writable::destination;
use writable::Folders;

use crate::error::{Error, Result};
use crate::film::frame_pattern::substitute;
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
    Folders::default().identity(path)
}

/// A file the run reads, with how the user (or the scene) named it.
#[derive(Clone, Debug)]
struct Input {
    /// The key or role that names it (`medium[0].file`, `piece`).
    what: String,
    /// The path as written (resolved against the scene's folder).
    path: PathBuf,
}

/// Files the run may write: one, or one per frame of a pattern.
#[derive(Clone, Debug)]
enum Outputs {
    /// One file; `context` is shown after its path (`frame 3`).
    One {
        flag: String,
        path: PathBuf,
        context: Option<String>,
    },
    /// `pattern` with each of `frames` written in, and beside each the
    /// file a partial image of that frame may go to.
    Frames {
        flag: String,
        pattern: PathBuf,
        frames: Vec<i64>,
    },
}

/// One output file of the run, as messages show it.
struct Out<'a> {
    flag: &'a str,
    path: PathBuf,
    context: Option<String>,
}

impl Out<'_> {
    fn show(&self) -> String {
        match &self.context {
            Some(c) => format!("{} ({c})", self.path.display()),
            None => self.path.display().to_string(),
        }
    }
}

const BESIDE: &str = "where a partial image goes beside";

/// Every file one run reads and may write, checked together by [`Plan::check`].
#[derive(Debug)]
pub struct Plan {
    run: String,
    inputs: Vec<Input>,
    sequences: Vec<Input>,
    outputs: Vec<Outputs>,
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

    /// A file the run reads: `what` names it (`piece`, `medium[0].file`).
    /// A path given again (each frame names the scene) is kept once.
    pub fn input(&mut self, what: &str, path: &Path) -> &mut Plan {
        if !self.inputs.iter().any(|i| i.path == path) {
            self.inputs.push(Input {
                what: what.into(),
                path: path.to_path_buf(),
            });
        }
        self
    }

    /// A frame pattern (`smoke.####.vdb`) the run reads from: every file of
    /// the sequence on disk is an input (any frame may read it, through
    /// `frame_offset` or `missing_frames`), and no output may add a frame to it.
    pub fn input_sequence(&mut self, what: &str, pattern: &Path) -> &mut Plan {
        if self.sequences.iter().any(|e| e.path == pattern) {
            return self;
        }
        for file in crate::film::frame_pattern::sequence_files(pattern) {
            self.input(what, &file);
        }
        self.sequences.push(Input {
            what: what.into(),
            path: pattern.to_path_buf(),
        });
        self
    }

    /// A file the run may write, named by `flag`; `context` is shown after
    /// the path in messages (e.g. `frame 3`).
    pub fn output(&mut self, flag: &str, path: &Path, context: Option<&str>) -> &mut Plan {
        self.outputs.push(Outputs::One {
            flag: flag.into(),
            path: path.to_path_buf(),
            context: context.map(String::from),
        });
        self
    }

    /// An image the run may write partial: the file, and the one beside it
    /// ([`partial_path`]) where a partial image goes when the file holds a better one.
    pub fn image_output(&mut self, flag: &str, path: &Path, context: Option<&str>) -> &mut Plan {
        self.output(flag, path, context);
        let beside = match context {
            Some(c) => format!("{c}, {BESIDE} {}", path.display()),
            None => format!("{BESIDE} {}", path.display()),
        };
        self.output(flag, &partial_path(path), Some(&beside))
    }

    /// [`Plan::image_output`] for each of `frames` of the frame pattern
    /// `pattern`, kept as the pattern (a long sequence costs no memory per frame).
    pub fn image_output_frames(&mut self, flag: &str, pattern: &Path, frames: &[i64]) -> &mut Plan {
        self.outputs.push(Outputs::Frames {
            flag: flag.into(),
            pattern: pattern.to_path_buf(),
            frames: frames.to_vec(),
        });
        self
    }

    /// Every output of the run in order, `(group, index)` naming each.
    fn each_output(&self, mut f: impl FnMut(Out, (usize, usize)) -> Result<()>) -> Result<()> {
        for (g, outputs) in self.outputs.iter().enumerate() {
            let n = match outputs {
                Outputs::One { .. } => 1,
                Outputs::Frames { frames, .. } => 2 * frames.len(),
            };
            for k in 0..n {
                f(self.nth(g, k), (g, k))?;
            }
        }
        Ok(())
    }

    /// Output `k` of group `g`.
    fn nth(&self, g: usize, k: usize) -> Out<'_> {
        match &self.outputs[g] {
            Outputs::One {
                flag,
                path,
                context,
            } => Out {
                flag,
                path: path.clone(),
                context: context.clone(),
            },
            Outputs::Frames {
                flag,
                pattern,
                frames,
            } => {
                let frame = frames[k / 2];
                let path = substitute(pattern, frame);
                let (path, context) = match k % 2 {
                    0 => (path, format!("frame {frame}")),
                    _ => {
                        let beside = format!("frame {frame}, {BESIDE} {}", path.display());
                        (partial_path(&path), beside)
                    }
                };
                Out {
                    flag,
                    path,
                    context: Some(context),
                }
            }
        }
    }

    /// Refuses the run (exit code 2, one line naming the flag and both
    /// paths) at the first output, in order, that cannot be written, is an
    /// input, would add a frame to an input sequence, or is the same file as
    /// an earlier output. Each output costs a few `stat` calls and 16 bytes.
    pub fn check(&self) -> Result<()> {
        let mut folders = Folders::default();
        let mut inputs = HashMap::new();
        for input in &self.inputs {
            inputs.entry(folders.identity(&input.path)).or_insert(input);
        }
        let sequences: Vec<(PathBuf, &Input)> = self
            .sequences
            .iter()
            .filter_map(|s| Some((folders.canonical(folder_of(&s.path))?, s)))
            .collect();
        let mut seen: HashMap<u64, (usize, usize)> = HashMap::new();
        self.each_output(|out, at| {
            let id = folders
                .output(&out.path)
                .map_err(|problem| refuse(&out, format!("{}: {problem}", out.show())))?;
            if let Some(input) = inputs.get(&id) {
                return Err(refuse(
                    &out,
                    format!(
                        "{} is an input of the {} ({}: {}); brume never overwrites its inputs",
                        out.show(),
                        self.run,
                        input.what,
                        input.path.display()
                    ),
                ));
            }
            if !sequences.is_empty() {
                let dest = match &id {
                    Identity::Path(p) => p.clone(),
                    Identity::File { .. } => folders.file(&destination(&out.path)),
                };
                check_sequences(&out, &dest, &sequences)?;
            }
            // A fingerprint per output, the identity compared again on a match.
            let print = fingerprint(&id);
            if let Some(&(g, k)) = seen.get(&print) {
                let first = self.nth(g, k);
                if folders.output(&first.path).ok() == Some(id) {
                    return Err(refuse(
                        &out,
                        format!(
                            "{} is the same file as {} {}; give each output its own file",
                            out.show(),
                            first.flag,
                            first.show()
                        ),
                    ));
                }
            }
            seen.insert(print, at);
            Ok(())
        })
    }
}

/// Refuses an output (canonical path `dest`) whose name is a frame of an input sequence.
fn check_sequences(out: &Out, dest: &Path, sequences: &[(PathBuf, &Input)]) -> Result<()> {
    let name = dest.file_name().map(|n| n.to_string_lossy().to_string());
    for (folder, seq) in sequences {
        let named = name.as_deref().is_some_and(|n| frame_of(&seq.path, n));
        if named && dest.parent() == Some(folder.as_path()) {
            return Err(refuse(
                out,
                format!(
                    "{} would be a frame of the sequence {} that {} reads; \
                     brume never writes into its input sequences",
                    out.show(),
                    seq.path.display(),
                    seq.what
                ),
            ));
        }
    }
    Ok(())
}

fn fingerprint(id: &Identity) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    id.hash(&mut h);
    h.finish()
}

fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
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

fn refuse(out: &Out, message: String) -> Error {
    Error::Argument {
        argument: out.flag.to_string(),
        message,
    }
}

#[cfg(test)]
mod tests;
