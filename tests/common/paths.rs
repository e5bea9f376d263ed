//! Random spellings of a test folder's files for the output-safety
//! properties: plain, `./`, `sub/..`, absolute, a symbolic link, a hard link,
//! or through a link to the folder.

use proptest::prelude::*;
use std::path::Path;

/// How a test spells a path to a file of its folder.
#[derive(Clone, Copy, Debug)]
pub enum Spelling {
    /// `name`
    Plain,
    /// `./name`
    Dot,
    /// `sub/../name`
    Up,
    /// `/tmp/.../name`
    Absolute,
    /// `linkN`, a symbolic link to `name`
    Symlink,
    /// `linkN`, a hard link to `name` (a symbolic link if `name` is not there yet)
    HardLink,
    /// `alias/name`, where `alias` links to the folder itself
    LinkedFolder,
}

/// Any spelling.
pub fn spelling() -> impl Strategy<Value = Spelling> {
    use Spelling::*;
    prop_oneof![
        Just(Plain),
        Just(Dot),
        Just(Up),
        Just(Absolute),
        Just(Symlink),
        Just(HardLink),
        Just(LinkedFolder),
    ]
}

/// One case's folder, holding `sub/` and `alias` (a link to the folder itself).
pub struct Folder {
    dir: tempfile::TempDir,
    links: usize,
}

impl Folder {
    /// A new empty folder (with `sub/` and `alias`).
    pub fn new() -> Folder {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        std::os::unix::fs::symlink(".", dir.path().join("alias")).unwrap();
        Folder { dir, links: 0 }
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// `name` (a file of the folder, existing or not) spelled as `how`; a
    /// hard link to a file not yet there is a symbolic link instead.
    pub fn spell(&mut self, name: &str, how: Spelling) -> String {
        let d = self.path().to_path_buf();
        self.links += 1;
        let link = format!("link{}", self.links);
        match how {
            Spelling::Plain => name.into(),
            Spelling::Dot => format!("./{name}"),
            Spelling::Up => format!("sub/../{name}"),
            Spelling::Absolute => d.join(name).display().to_string(),
            Spelling::LinkedFolder => format!("alias/{name}"),
            Spelling::HardLink if d.join(name).exists() => {
                std::fs::hard_link(d.join(name), d.join(&link)).unwrap();
                link
            }
            Spelling::Symlink | Spelling::HardLink => {
                std::os::unix::fs::symlink(name, d.join(&link)).unwrap();
                link
            }
        }
    }
}
