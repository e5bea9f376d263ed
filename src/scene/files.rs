//! The files a scene names (environment maps, textures, OBJ meshes, VDB
//! volumes): refused before they are read, with what the path is instead
//! of what the key needs (a folder, a device, an empty file, a PNG where an
//! EXR belongs), under the key that named it.

use super::validate::Check;
use crate::error::Result;
use std::io::Read;
use std::path::Path;

/// The kinds of file a scene key can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Format {
    /// OpenEXR image.
    Exr,
    /// PNG image.
    Png,
    /// Radiance RGBE image (`.hdr`).
    Hdr,
    /// JPEG image.
    Jpeg,
    /// OpenVDB volume.
    Vdb,
    /// Wavefront OBJ mesh (text).
    Obj,
    /// Stanford PLY mesh (a text header, then text or binary data).
    Ply,
}

const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
const PNG_MAGIC: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
/// The two signatures Radiance writers start a file with.
const HDR_MAGICS: [&[u8]; 2] = [b"#?RADIANCE", b"#?RGBE"];
/// A JPEG's start-of-image marker and the first marker after it.
const JPEG_MAGIC: [u8; 3] = [0xff, 0xd8, 0xff];
/// The OpenVDB magic number 0x56444220, little-endian.
const VDB_MAGIC: [u8; 4] = [0x20, 0x42, 0x44, 0x56];

impl Format {
    fn name(self) -> &'static str {
        match self {
            Format::Exr => "an EXR image",
            Format::Png => "a PNG image",
            Format::Hdr => "a Radiance HDR image",
            Format::Jpeg => "a JPEG image",
            Format::Vdb => "an OpenVDB file",
            Format::Obj => "a Wavefront OBJ file (text)",
            Format::Ply => "a PLY mesh (starting with `ply`)",
        }
    }

    /// The format whose signature `head` (a file's first bytes) starts with.
    fn of(head: &[u8]) -> Option<Format> {
        if head.starts_with(&EXR_MAGIC) {
            Some(Format::Exr)
        } else if head.starts_with(&PNG_MAGIC) {
            Some(Format::Png)
        } else if head.starts_with(&VDB_MAGIC) {
            Some(Format::Vdb)
        } else if HDR_MAGICS.iter().any(|m| head.starts_with(m)) {
            Some(Format::Hdr)
        } else if head.starts_with(&JPEG_MAGIC) {
            Some(Format::Jpeg)
        } else {
            None
        }
    }

    /// Whether a file starting with `head` can be of this format.
    fn accepts(self, head: &[u8]) -> bool {
        match self {
            // OBJ has no signature: any text that is not one of the binary formats
            Format::Obj => !head.is_empty() && Format::of(head).is_none() && !head.contains(&0),
            Format::Ply => head.starts_with(b"ply"),
            binary => Format::of(head) == Some(binary),
        }
    }
}

/// What a file starting with `head` is, for messages.
fn describe(head: &[u8]) -> String {
    if head.is_empty() {
        return "empty (0 bytes)".into();
    }
    if let Some(format) = Format::of(head) {
        return format.name().into();
    }
    if std::str::from_utf8(head).is_ok() && !head.contains(&0) {
        return "text".into();
    }
    let bytes: Vec<String> = head.iter().take(8).map(|b| format!("{b:02x}")).collect();
    format!(
        "data of an unknown kind (its first bytes are {})",
        bytes.join(" ")
    )
}

/// The message of a reader's error, without the path (the caller names it).
pub(super) fn input_message(e: crate::error::Error) -> String {
    match e {
        crate::error::Error::Input { message, .. } => message,
        other => other.to_string(),
    }
}

/// Refuses `path`, named by key `field` as a `what` ("environment map"),
/// unless it is a regular file of at most `max_bytes` that starts like `format`.
pub(super) fn check_input(
    check: &Check,
    field: &str,
    what: &str,
    path: &Path,
    format: Format,
    max_bytes: u64,
) -> Result<()> {
    let refuse = |problem: String| {
        Err(check.error(
            field,
            format!("cannot read {what} {}: {problem}", path.display()),
        ))
    };
    if let Some(problem) = crate::error::input_file_problem(path, max_bytes) {
        return refuse(problem);
    }
    let mut head = Vec::with_capacity(16);
    let read = std::fs::File::open(path).and_then(|f| f.take(16).read_to_end(&mut head));
    if let Err(e) = read {
        return refuse(e.to_string());
    }
    if !format.accepts(&head) {
        return refuse(format!("it is {}, not {}", describe(&head), format.name()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_format_knows_its_signature_and_no_other() {
        let heads: [(&[u8], Option<Format>); 5] = [
            (&[0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0], Some(Format::Exr)),
            (&PNG_MAGIC, Some(Format::Png)),
            (&[0x20, 0x42, 0x44, 0x56, 0, 0, 0, 0], Some(Format::Vdb)),
            (b"v 0 0 0\nf 1 2 3\n", None),
            (b"", None),
        ];
        for (head, format) in heads {
            assert_eq!(Format::of(head), format, "{head:?}");
            for f in [Format::Exr, Format::Png, Format::Vdb] {
                assert_eq!(f.accepts(head), format == Some(f), "{f:?} of {head:?}");
            }
        }
        assert!(Format::Obj.accepts(b"v 0 0 0\n"));
        assert!(!Format::Obj.accepts(&PNG_MAGIC));
        assert!(!Format::Obj.accepts(&[b'v', 0, 1]));
        assert!(!Format::Obj.accepts(b""));
    }

    #[test]
    fn a_file_is_described_by_what_it_holds() {
        assert_eq!(describe(b""), "empty (0 bytes)");
        assert_eq!(describe(&PNG_MAGIC), "a PNG image");
        assert_eq!(describe(b"hello"), "text");
        assert_eq!(
            describe(&[0, 0xff, 1]),
            "data of an unknown kind (its first bytes are 00 ff 01)"
        );
    }
}
