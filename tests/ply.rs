//! The PLY mesh reader: ASCII and binary (both byte orders) give the same
//! triangles as the same mesh in OBJ, and damaged files are one error line
//! naming the file, never a panic or an allocation the file cannot back.

mod common;

use common::sample_bits;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// A unit square (a quad face, fan-split) and a triangle beside it, with normals and uv.
const VERTICES: [[f32; 8]; 7] = [
    [-1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    [1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0],
    [1.0, 1.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0],
    [-1.0, 1.0, 0.0, 0.3, 0.0, 1.0, 0.0, 1.0],
    [1.2, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    [2.0, -1.0, 0.5, 0.0, 0.0, 1.0, 1.0, 0.0],
    [1.6, 1.0, 0.0, 0.0, 0.0, 1.0, 0.5, 1.0],
];
const FACES: [&[u32]; 2] = [&[0, 1, 2, 3], &[4, 5, 6]];

fn header(format: &str, extra: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment made by brume's tests\nelement vertex 7\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property float u\nproperty float v\n{extra}\
         element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    )
}

fn ascii() -> Vec<u8> {
    let mut text = header("ascii", "");
    for v in VERTICES {
        let words: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        text += &(words.join(" ") + "\n");
    }
    for f in FACES {
        let words: Vec<String> = f.iter().map(|i| i.to_string()).collect();
        text += &format!("{} {}\n", f.len(), words.join(" "));
    }
    text.into_bytes()
}

fn binary(big: bool) -> Vec<u8> {
    let order = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = header(order, "").into_bytes();
    for v in VERTICES {
        for x in v {
            out.extend(if big {
                x.to_be_bytes()
            } else {
                x.to_le_bytes()
            });
        }
    }
    for f in FACES {
        out.push(f.len() as u8);
        for &i in f {
            out.extend(if big {
                i.to_be_bytes()
            } else {
                i.to_le_bytes()
            });
        }
    }
    out
}

fn obj() -> String {
    let mut text = String::new();
    for v in VERTICES {
        text += &format!(
            "v {} {} {}\nvn {} {} {}\nvt {} {}\n",
            v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]
        );
    }
    for f in FACES {
        let words: Vec<String> = f.iter().map(|i| format!("{0}/{0}/{0}", i + 1)).collect();
        text += &format!("f {}\n", words.join(" "));
    }
    text
}

/// A scene looking at `mesh` (a file in `dir`), lit by a point light, textured by a checkerboard on its uv.
fn scene(dir: &Path, mesh: &str) -> PathBuf {
    let text = format!(
        "[camera]\nposition = [0.3, 0.2, 4.0]\nlook_at = [0.3, 0.0, 0.0]\nfov = 60.0\nresolution = [16, 12]\n\
         [integrator]\nspp = 4\nseed = 1\nmax_depth = 2\n\
         [[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 3.0]\nintensity = 10.0\n\
         [[shape]]\ntype = \"mesh\"\nfile = \"{mesh}\"\ntransform = {{ rotate = [0.0, 20.0, 0.0] }}\n\
         material = {{ type = \"diffuse\", albedo = {{ type = \"checkerboard\", a = 0.2, b = 0.8, uv_scale = 4 }} }}\n"
    );
    let path = dir.join(format!("{mesh}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn bits(scene: &Path) -> Vec<[u32; 3]> {
    let loaded = brume::scene::load_with_inputs(scene).unwrap_or_else(|e| panic!("{e}"));
    sample_bits(&loaded.scene, 4)
}

#[test]
fn ascii_and_binary_plys_render_like_the_same_obj() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.obj"), obj()).unwrap();
    let reference = bits(&scene(dir.path(), "m.obj"));
    assert!(
        reference.iter().any(|p| p[0] != 0),
        "the OBJ render is black"
    );
    for (name, bytes) in [
        ("a.ply", ascii()),
        ("le.ply", binary(false)),
        ("be.ply", binary(true)),
    ] {
        std::fs::write(dir.path().join(name), bytes).unwrap();
        assert!(
            bits(&scene(dir.path(), name)) == reference,
            "{name} renders differently from the OBJ"
        );
    }
}

/// The error of loading a scene whose mesh is the PLY `bytes`.
fn error(bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.ply"), bytes).unwrap();
    match brume::scene::load_with_inputs(&scene(dir.path(), "m.ply")) {
        Ok(_) => panic!("accepted"),
        Err(e) => {
            let message = e.to_string();
            assert!(!message.contains('\n'), "more than one line: {message}");
            assert!(
                message.contains("shape[0].file") && message.contains("m.ply"),
                "{message}"
            );
            message
        }
    }
}

#[test]
fn damaged_plys_are_refused_by_name_before_allocating() {
    let good = binary(false);
    let cut = &good[..good.len() - 1];
    assert!(error(cut).contains("truncated"), "{}", error(cut));
    let huge =
        header("binary_little_endian", "").replace("element vertex 7", "element vertex 4000000000");
    assert!(
        error(huge.as_bytes()).contains("more than its"),
        "{}",
        error(huge.as_bytes())
    );
    let ascii_text = String::from_utf8(ascii()).unwrap();
    let out_of_range = ascii_text.replace("3 4 5 6", "3 4 5 7");
    assert!(error(out_of_range.as_bytes()).contains("out of range"));
    let no_end = ascii_text.replace("end_header", "end_of_it");
    assert!(error(no_end.as_bytes()).contains("end_header"));
    assert!(error(b"solid cube\n").contains("not a PLY mesh"));
    let no_faces = ascii_text.replace("element face 2", "element face 0");
    assert!(error(no_faces.as_bytes()).contains("no faces"));
    let bad_type = ascii_text.replace("property float z", "property quad z");
    assert!(error(bad_type.as_bytes()).contains("unknown property type"));
    let nan = ascii_text.replacen("-1 -1 0", "NaN -1 0", 1);
    assert!(error(nan.as_bytes()).contains("non-finite"));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// A PLY cut or overwritten at any byte is read or refused, never a panic.
    #[test]
    fn mangled_plys_never_panic(cut in 0usize..400, at in 0usize..400, byte in any::<u8>(), big in any::<bool>()) {
        let mut bytes = if big { binary(true) } else { ascii() };
        let at = at % bytes.len();
        bytes[at] = byte;
        bytes.truncate(cut.max(1).min(bytes.len()));
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.ply"), &bytes).unwrap();
        if let Err(e) = brume::scene::load_with_inputs(&scene(dir.path(), "m.ply")) {
            prop_assert!(!e.to_string().contains('\n'));
        }
    }
}
