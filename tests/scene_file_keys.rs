//! Every file-valued key of the scene schema (found by crawling it: the keys
//! named `file`), given a path that is not a file of its kind — a folder, a
//! link to a folder, a device, a FIFO, an empty file, text, another format,
//! nothing at all — is refused through the command line with exit code 2
//! and one line that names the key and says what the path is. Never "not
//! found" for a path that exists, and never a hang on a FIFO.

#[path = "schema_support/mod.rs"]
mod schema_support;

use std::path::Path;
use std::time::Duration;

const CAMERA: &str =
    "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [4, 4]\n";
const PNG_MAGIC: &[u8] = &[0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13];
const EXR_MAGIC: &[u8] = &[0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];

/// A scene that reads `FILE` through `key`, the extension the key's loader
/// expects and a good file for it (crate-relative); `None` for a key this
/// test does not know yet (which fails the test: add it here).
fn template(key: &str) -> Option<(String, &'static str, &'static str)> {
    let texture = |material: &str| {
        format!("[[shape]]\ntype = \"sphere\"\nradius = 1.0\n{material}\n")
            .replace("TEX", "{ type = \"image\", file = \"FILE\" }")
    };
    let (body, ext, good) = match key {
        "light[0].file" => (
            "[[light]]\ntype = \"environment_map\"\nfile = \"FILE\"\n".into(),
            "exr",
            "",
        ),
        "shape[0].file" => (
            "[[shape]]\ntype = \"mesh\"\nfile = \"FILE\"\n".into(),
            "obj",
            "tests/data/meshes/cube.obj",
        ),
        "shape[0].material.albedo.file" => (
            texture("material = { type = \"diffuse\", albedo = TEX }"),
            "png",
            "tests/data/textures/checker4x2.png",
        ),
        "shape[0].material.reflectance.file" => (
            texture("material = { type = \"mirror\", reflectance = TEX }"),
            "png",
            "tests/data/textures/checker4x2.png",
        ),
        "shape[0].material.f0.file" => (
            texture("material = { type = \"conductor\", f0 = TEX }"),
            "png",
            "tests/data/textures/checker4x2.png",
        ),
        "shape[0].material.diffuse.file" => (
            texture("material = { type = \"plastic\", diffuse = TEX }"),
            "png",
            "tests/data/textures/checker4x2.png",
        ),
        "shape[0].emission.file" => (
            texture("emission = TEX"),
            "png",
            "tests/data/textures/checker4x2.png",
        ),
        "shape[0].interior.file" => (
            "[[shape]]\ntype = \"sphere\"\nradius = 1.0\ninterior = { type = \"vdb\", file = \"FILE\" }\n"
                .into(),
            "vdb",
            "tests/data/volumes/sphere_fog.vdb",
        ),
        "medium[0].file" | "media[0].file" => (
            format!("[[{}]]\ntype = \"vdb\"\nfile = \"FILE\"\n", &key[..key.find('[').unwrap()]),
            "vdb",
            "tests/data/volumes/sphere_fog.vdb",
        ),
        _ => return None,
    };
    Some((format!("{CAMERA}{body}"), ext, good))
}

/// The bad paths for a key whose files end in `.ext`: (path, what the message must say).
fn bad_paths(dir: &Path, ext: &str) -> Vec<(String, &'static str)> {
    let p = |name: &str| dir.join(format!("{name}.{ext}"));
    std::fs::create_dir(p("folder")).unwrap();
    std::os::unix::fs::symlink(p("folder"), p("link")).unwrap();
    let fifo = std::ffi::CString::new(p("fifo").to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o644) }, 0, "mkfifo");
    std::fs::write(p("empty"), b"").unwrap();
    std::fs::write(p("text"), b"just a note, no image\n").unwrap();
    // a file of another format than the key reads
    let (other, other_name) = match ext {
        "png" => (EXR_MAGIC, "an EXR image"),
        _ => (PNG_MAGIC, "a PNG image"),
    };
    std::fs::write(p("other"), other).unwrap();
    let text = match ext {
        "obj" => "holds no triangles",
        _ => "it is text",
    };
    let show = |name: &str| p(name).display().to_string();
    vec![
        (show("folder"), "is a directory"),
        (show("link"), "is a directory"),
        (
            "/dev/null".into(),
            "is not a regular file (a character device)",
        ),
        (show("fifo"), "is not a regular file (a FIFO (named pipe))"),
        (show("empty"), "is empty (0 bytes)"),
        (show("text"), text),
        (show("other"), other_name),
        (show("missing"), "no such file"),
    ]
}

/// A small grey environment map in `dir`.
fn good_map(dir: &Path) -> String {
    let path = dir.join("good.exr");
    let image = brume::film::image_io::Image {
        width: 4,
        height: 2,
        pixels: vec![brume::math::color::Rgb::splat(0.5); 8],
        spp: 1,
        partial: false,
    };
    brume::film::image_io::write_exr(&path, &image).unwrap();
    path.display().to_string()
}

/// Runs `brume render` on `scene`; (exit code, stderr).
fn render(scene: &Path) -> (Option<i32>, String) {
    let out = scene.with_file_name("out.exr");
    let output = assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .arg("render")
        .arg(scene)
        .args(["--spp", "1", "--quiet", "--out"])
        .arg(&out)
        .timeout(Duration::from_secs(20))
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into(),
    )
}

#[test]
fn every_file_key_says_what_a_bad_path_is() {
    let crawl = schema_support::crawl();
    let keys: Vec<&String> = crawl
        .leaves
        .iter()
        .filter(|k| k.ends_with(".file"))
        .collect();
    assert!(keys.len() >= 6, "the crawl found only {keys:?}");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for key in keys {
        let Some((scene, ext, good)) = template(key) else {
            panic!("{key} is a file key this test has no scene for: add one to `template`");
        };
        let dir = tempfile::tempdir().unwrap();
        // the scene reaches the file: a good one renders
        let file = match good {
            "" => good_map(dir.path()),
            good => root.join(good).display().to_string(),
        };
        let path = dir.path().join("good.toml");
        std::fs::write(&path, scene.replace("FILE", &file)).unwrap();
        let (code, stderr) = render(&path);
        assert_eq!(code, Some(0), "{key} with {file}: {stderr}");
        for (bad, says) in bad_paths(dir.path(), ext) {
            let path = dir.path().join("s.toml");
            std::fs::write(&path, scene.replace("FILE", &bad)).unwrap();
            let (code, stderr) = render(&path);
            let lines: Vec<&str> = stderr.lines().collect();
            assert_eq!(code, Some(2), "{key} = {bad}: {stderr}");
            assert_eq!(lines.len(), 1, "{key} = {bad}: {stderr}");
            let line = lines[0];
            assert!(
                line.starts_with("error: ") && line.contains(&format!("{key}: ")),
                "{key} = {bad}: the error does not name the key: {line}"
            );
            assert!(line.contains(&bad), "{key} = {bad}: {line}");
            assert!(
                line.contains(says),
                "{key} = {bad}: expected `{says}` in {line}"
            );
            if !bad.ends_with(&format!("missing.{ext}")) {
                assert!(!line.contains("not found"), "{key} = {bad}: {line}");
            }
        }
    }
}
