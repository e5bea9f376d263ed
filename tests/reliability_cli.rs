//! Reliability through the command line, one table per class of bad input:
//! output rules, input files, grid values, messages and pathological scenes.
//! Every case runs under a 10 s timeout and must exit with its code, print
//! one `error:` line naming the culprit (for failures), never panic, and
//! leave every file that existed before (scene, inputs, an earlier image)
//! byte for byte as it was.

mod common;

use assert_cmd::cargo::CommandCargoExt;
use common::cli::{run_brume, snapshot};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const TIMEOUT: Duration = Duration::from_secs(10);

/// A small scene: a lit quad, optionally with more TOML appended.
fn scene(extra: &str) -> String {
    format!(
        r#"
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
resolution = [8, 6]

[integrator]
spp = 2

[[light]]
type = "point"
position = [0.0, 3.0, 2.0]
intensity = 20.0

{extra}
"#
    )
}

const QUAD: &str = r#"
[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [4.0, 4.0]
"#;

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend((s.len() as u32).to_le_bytes());
    out.extend(s.as_bytes());
}

/// A one-grid VDB (format 224, uncompressed) holding one active root tile of `value`.
fn tile_vdb(value: f32) -> Vec<u8> {
    tile_vdb_grids(&[("density", value)])
}

/// A VDB (format 224, uncompressed) of grids, each one active root tile of its value.
fn tile_vdb_grids(grids: &[(&str, f32)]) -> Vec<u8> {
    let mut f = Vec::new();
    f.extend(0x5644_4220u64.to_le_bytes());
    f.extend(224u32.to_le_bytes());
    f.extend([10u32.to_le_bytes(), 0u32.to_le_bytes()].concat());
    f.push(1);
    f.extend(b"00000000-0000-0000-0000-000000000000");
    f.extend(0u32.to_le_bytes());
    f.extend((grids.len() as i32).to_le_bytes());
    for &(name, value) in grids {
        string(&mut f, name);
        string(&mut f, "Tree_float_5_4_3");
        string(&mut f, "");
        let offsets_at = f.len();
        f.extend([0u8; 24]);
        let grid_pos = f.len();
        f.extend(0u32.to_le_bytes());
        f.extend(0u32.to_le_bytes());
        string(&mut f, "UniformScaleMap");
        for v in [
            0.5f64, 0.5, 0.5, 0.5, 0.5, 0.5, 2.0, 2.0, 2.0, 4.0, 4.0, 4.0, 1.0, 1.0, 1.0,
        ] {
            f.extend(v.to_le_bytes());
        }
        f.extend(1i32.to_le_bytes());
        f.extend(0f32.to_le_bytes());
        f.extend(1u32.to_le_bytes());
        f.extend(0u32.to_le_bytes());
        for c in [0i32, 0, 0] {
            f.extend(c.to_le_bytes());
        }
        f.extend(value.to_le_bytes());
        f.push(1);
        let end = f.len() as i64;
        for (i, o) in [grid_pos as i64, end, end].iter().enumerate() {
            f[offsets_at + 8 * i..offsets_at + 8 * i + 8].copy_from_slice(&o.to_le_bytes());
        }
    }
    f
}

fn vdb_medium(file: &str, extra: &str) -> String {
    format!("[[medium]]\ntype = \"vdb\"\nfile = \"{file}\"\n{extra}\n")
}

fn smoke() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("volumes/smoke_plume.vdb")
        .display()
        .to_string()
}

/// Sets up a case's folder: `s.toml`, an earlier image `keep.exr`/`keep.png`,
/// a cube `m.obj`, one triangle 30 000 times `repeats.obj`, a folder `dir`, a FIFO `fifo` and VDBs `inf.vdb`,
/// `nan.vdb`, `big.vdb` (3e38), `neg.vdb` (-1), `one.vdb` (1) and `glow.vdb`
/// (a `density` of 1 beside an emission grid `glow` of +inf).
fn setup(dir: &Path, scene_text: &str) {
    std::fs::write(dir.join("s.toml"), scene_text).unwrap();
    std::fs::write(dir.join("keep.exr"), b"an earlier EXR image").unwrap();
    std::fs::write(dir.join("keep.png"), b"an earlier PNG image").unwrap();
    std::fs::write(dir.join("notvdb.vdb"), b"hello, not a VDB").unwrap();
    std::fs::write(dir.join("m.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    // One triangle repeated: identical boxes once made the BVH build quadratic.
    let repeats = "v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_string() + &"f 1 2 3\n".repeat(30_000);
    std::fs::write(dir.join("repeats.obj"), repeats).unwrap();
    std::fs::create_dir(dir.join("dir")).unwrap();
    let status = Command::new("mkfifo")
        .arg(dir.join("fifo"))
        .status()
        .unwrap();
    assert!(status.success());
    for (name, v) in [
        ("inf", f32::INFINITY),
        ("nan", f32::NAN),
        ("big", 3e38),
        ("neg", -1.0),
        ("one", 1.0),
    ] {
        std::fs::write(dir.join(format!("{name}.vdb")), tile_vdb(v)).unwrap();
    }
    let glow = tile_vdb_grids(&[("density", 1.0), ("glow", f32::INFINITY)]);
    std::fs::write(dir.join("glow.vdb"), glow).unwrap();
}

/// Runs brume in `dir` with `args` under [`TIMEOUT`] (a hang fails the test); returns (exit code, stderr, seconds).
fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String, f64) {
    let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    let out = run_brume(dir, &args, TIMEOUT);
    (out.code, out.stderr, out.seconds)
}

/// One case: the scene text, the command line, the exit code and what stderr must name.
struct Case {
    name: &'static str,
    scene: String,
    args: Vec<&'static str>,
    code: i32,
    culprit: &'static str,
}

fn case(
    name: &'static str,
    scene: String,
    args: &[&'static str],
    code: i32,
    culprit: &'static str,
) -> Case {
    Case {
        name,
        scene,
        args: args.to_vec(),
        code,
        culprit,
    }
}

const KEEP: [&str; 4] = ["--out", "keep.exr", "--png", "keep.png"];

/// A render of `s.toml` into the earlier image, plus `more` arguments.
fn render(more: &[&'static str]) -> Vec<&'static str> {
    let mut a = vec!["render", "s.toml"];
    a.extend(more);
    if !more.contains(&"--out") {
        a.extend(&KEEP[..2]);
    }
    if !more.contains(&"--png") {
        a.extend(&KEEP[2..]);
    }
    a
}

fn check(c: &Case) {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path(), &c.scene);
    if c.name == "output is a symlink to the scene" {
        std::os::unix::fs::symlink("s.toml", dir.path().join("link.exr")).unwrap();
    }
    let before = snapshot(dir.path());
    let (code, stderr, secs) = run(dir.path(), &c.args);
    let what = format!("{} ({:?})", c.name, c.args);
    assert!(!stderr.contains("panicked"), "{what}: panicked: {stderr}");
    assert_eq!(code, Some(c.code), "{what}: exit code; stderr: {stderr}");
    assert!(secs < TIMEOUT.as_secs_f64(), "{what}: took {secs:.1} s");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    if c.code == 0 {
        assert!(errors.is_empty(), "{what}: {stderr}");
    } else {
        assert_eq!(errors.len(), 1, "{what}: one error line expected: {stderr}");
    }
    assert!(
        stderr.contains(c.culprit),
        "{what}: '{}' not named: {stderr}",
        c.culprit
    );
    let after = snapshot(dir.path());
    for (path, bytes) in &before {
        let written = c.code == 0 && path.ends_with("keep.exr") || path.ends_with("keep.png");
        if c.code != 0 || !written {
            assert_eq!(
                after.get(path),
                Some(bytes),
                "{what}: {} changed",
                path.display()
            );
        }
    }
    // No temporary file is left behind.
    assert!(
        !after.keys().any(|p| p.to_string_lossy().contains(".tmp-")),
        "{what}: temporary file left: {:?}",
        after.keys()
    );
}

fn output_cases() -> Vec<Case> {
    let s = || scene(QUAD);
    let obj = scene("[[shape]]\ntype = \"mesh\"\nfile = \"m.obj\"\n");
    let vdb = scene(&vdb_medium("one.vdb", ""));
    vec![
        case(
            "output is the scene",
            s(),
            &render(&["--out", "s.toml"]),
            2,
            "is an input",
        ),
        case(
            "png is the scene",
            s(),
            &render(&["--png", "s.toml"]),
            2,
            "is an input",
        ),
        case(
            "output is the scene via ./",
            s(),
            &render(&["--out", "./s.toml"]),
            2,
            "is an input",
        ),
        case(
            "output is the OBJ",
            obj,
            &render(&["--out", "m.obj"]),
            2,
            "is an input",
        ),
        case(
            "output is the VDB",
            vdb.clone(),
            &render(&["--png", "one.vdb"]),
            2,
            "is an input",
        ),
        case(
            "both outputs one file",
            s(),
            &render(&["--out", "x.exr", "--png", "x.exr"]),
            2,
            "same file",
        ),
        case(
            "both outputs the earlier image",
            s(),
            &render(&["--png", "keep.exr"]),
            2,
            "same file",
        ),
        case(
            "output is a device",
            s(),
            &render(&["--out", "/dev/null"]),
            2,
            "not a regular file",
        ),
        case(
            "output is a FIFO",
            s(),
            &render(&["--png", "fifo"]),
            2,
            "not a regular file",
        ),
        case(
            "output folder does not exist",
            s(),
            &render(&["--out", "newdir/"]),
            2,
            "folder that does not exist",
        ),
        case(
            "output names an existing folder/",
            s(),
            &render(&["--out", "dir/"]),
            2,
            "is a folder",
        ),
        case(
            "output is a folder",
            s(),
            &render(&["--out", "dir"]),
            2,
            "is a directory",
        ),
        case(
            "output in a missing folder",
            s(),
            &render(&["--out", "missing/x.exr"]),
            2,
            "does not exist",
        ),
        case(
            "output is a symlink to the scene",
            s(),
            &render(&["--out", "link.exr"]),
            2,
            "is an input",
        ),
        case(
            "--time 1e20",
            s(),
            &render(&["--time", "1e20"]),
            2,
            "--time",
        ),
        case("--time 0", s(), &render(&["--time", "0"]), 2, "--time"),
        case("--time -1", s(), &render(&["--time", "-1"]), 2, "--time"),
        case("--time NaN", s(), &render(&["--time", "NaN"]), 2, "--time"),
        case("--time inf", s(), &render(&["--time", "inf"]), 2, "--time"),
        case("--spp 0", s(), &render(&["--spp", "0"]), 2, "--spp"),
        case(
            "--threads 0",
            s(),
            &render(&["--threads", "0"]),
            2,
            "--threads",
        ),
        case(
            "--exposure inf",
            s(),
            &render(&["--exposure", "inf"]),
            2,
            "--exposure",
        ),
        case(
            "wrong extension warns",
            s(),
            &render(&["--out", "x.png", "--png", "y.png"]),
            0,
            "does not end in .exr",
        ),
    ]
}

fn input_cases() -> Vec<Case> {
    let s = || scene(QUAD);
    vec![
        case(
            "scene is a FIFO",
            s(),
            &["render", "fifo", "--out", "keep.exr", "--png", "keep.png"],
            2,
            "not a regular file",
        ),
        case(
            "scene is /dev/zero",
            s(),
            &[
                "render",
                "/dev/zero",
                "--out",
                "keep.exr",
                "--png",
                "keep.png",
            ],
            2,
            "not a regular file",
        ),
        case(
            "scene is a folder",
            s(),
            &["render", "dir", "--out", "keep.exr", "--png", "keep.png"],
            2,
            "is a directory",
        ),
        case(
            "scene is missing",
            s(),
            &[
                "render",
                "nope.toml",
                "--out",
                "keep.exr",
                "--png",
                "keep.png",
            ],
            2,
            "no such file",
        ),
        case(
            "info on /dev/zero",
            s(),
            &["info", "/dev/zero"],
            2,
            "not a regular file",
        ),
        case(
            "info on a FIFO",
            s(),
            &["info", "fifo"],
            2,
            "not a regular file",
        ),
        case(
            "info on a folder",
            s(),
            &["info", "dir"],
            2,
            "is a directory",
        ),
        case(
            "VDB is /dev/zero",
            scene(&vdb_medium("/dev/zero", "")),
            &render(&[]),
            2,
            "medium[0].file",
        ),
        case(
            "VDB is a folder",
            scene(&vdb_medium("dir", "")),
            &render(&[]),
            2,
            "is a directory",
        ),
        case(
            "VDB is a FIFO",
            scene(&vdb_medium("fifo", "")),
            &render(&[]),
            2,
            "not a regular file",
        ),
        case(
            "VDB is not a VDB",
            scene(&vdb_medium("notvdb.vdb", "")),
            &render(&[]),
            2,
            "medium[0].file: ",
        ),
        case(
            "OBJ is a folder",
            scene("[[shape]]\ntype = \"mesh\"\nfile = \"dir\"\n"),
            &render(&[]),
            2,
            "shape[0].file",
        ),
        case(
            "OBJ is /dev/zero",
            scene("[[shape]]\ntype = \"mesh\"\nfile = \"/dev/zero\"\n"),
            &render(&[]),
            2,
            "not a regular file",
        ),
        case(
            "OBJ is a FIFO",
            scene("[[shape]]\ntype = \"mesh\"\nfile = \"fifo\"\n"),
            &render(&[]),
            2,
            "not a regular file",
        ),
    ]
}

fn grid_cases() -> Vec<Case> {
    vec![
        case(
            "+inf density tile",
            scene(&vdb_medium("inf.vdb", "")),
            &render(&[]),
            2,
            "medium[0].grid: grid 'density' holds 1 non-finite values (0 NaN, 1 +inf",
        ),
        case(
            "NaN density tile",
            scene(&vdb_medium("nan.vdb", "")),
            &render(&[]),
            2,
            "1 NaN",
        ),
        case(
            "3e38 x 20 overflows",
            scene(&vdb_medium("big.vdb", "density_scale = 20.0")),
            &render(&[]),
            2,
            "medium[0].density_scale",
        ),
        case(
            "3e38 x sigma_t_scale overflows",
            scene(&vdb_medium("big.vdb", "sigma_t_scale = [1.0, 2.0, 1.0]")),
            &render(&[]),
            2,
            "overflows",
        ),
        case(
            "negative density",
            scene(&vdb_medium("neg.vdb", "")),
            &render(&[]),
            2,
            "no positive value",
        ),
        case(
            "emission grid overflows",
            scene(&vdb_medium(
                "big.vdb",
                "albedo = 0.5\nemission_grid = \"density\"\nemission_scale = 1e38",
            )),
            &render(&[]),
            2,
            "medium[0].emission_scale",
        ),
        case(
            "+inf emission grid",
            scene(&vdb_medium(
                "glow.vdb",
                "albedo = 0.5\nemission_grid = \"glow\"",
            )),
            &render(&[]),
            2,
            "medium[0].emission_grid: grid 'glow' holds 1 non-finite values (0 NaN, 1 +inf",
        ),
        case(
            "finite emission grid beside it",
            scene(&vdb_medium(
                "glow.vdb",
                "albedo = 0.5\nemission_grid = \"density\"",
            )),
            &render(&["--out", "o.exr", "--png", "o.png"]),
            0,
            "",
        ),
    ]
}

fn message_cases() -> Vec<Case> {
    let quad_with = |m: &str| scene(&format!("{QUAD}{m}\n"));
    let fog = |m: &str| {
        scene(&format!(
            "{QUAD}[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.1\nglobal = true\n{m}\n"
        ))
    };
    let spot = |m: &str| {
        scene(&format!(
            "{QUAD}[[light]]\ntype = \"spot\"\nposition = [0.0, 2.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nintensity = 5.0\n{m}\n"
        ))
    };
    vec![
        case("material as a string", quad_with("material = \"diffuse\""), &render(&[]), 2, "shape[0].material: expected a table like { type = \"diffuse\", albedo = 0.5 }, got a string \"diffuse\""),
        case("phase as a string", fog("phase = \"hg\""), &render(&[]), 2, "medium[0].phase: expected a table like { type = \"hg\""),
        case("bounds as an array", scene("[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.1\nbounds = [0.0, 1.0]\n"), &render(&[]), 2, "medium[0].bounds: expected a table like { type = \"box\""),
        case("[[camera]]", scene(QUAD).replace("[camera]", "[[camera]]"), &render(&[]), 2, "camera: expected one [camera] table"),
        case("[light] instead of [[light]]", scene(QUAD).replace("[[light]]", "[light]"), &render(&[]), 2, "light: expected [[light]] tables"),
        case("double_hg weight", fog("phase = { type = \"double_hg\", g_forward = 0.5, g_back = -0.3, weight = 2.0 }"), &render(&[]), 2, "medium[0].phase.weight"),
        case("g rounds to 1", fog("phase = { type = \"hg\", g = 0.99999999 }"), &render(&[]), 2, "medium[0].phase.g: 0.99999999 rounds to 1"),
        case("g = 1", fog("phase = { type = \"hg\", g = 1.0 }"), &render(&[]), 2, "medium[0].phase.g: must be in (-1, 1)"),
        case("narrow spot with the default falloff", spot("cone_angle = 3.0"), &render(&["--out", "o.exr", "--png", "o.png"]), 0, ""),
        case("falloff wider than the cone", spot("cone_angle = 3.0\ncone_falloff = 5.0"), &render(&[]), 2, "light[1].cone_falloff"),
        case("up parallel to the view", scene(QUAD).replace("[integrator]", "up = [0.0, 0.0, 1.0]\nlook_at = [0.0, 1.0, 0.0]\n[integrator]").replace("look_at = [0.0, 0.5, 0.0]\n", ""), &render(&[]), 2, "camera.up"),
        case("camera 1e30 from the origin", scene(QUAD).replace("position = [0.0, 1.0, 4.0]", "position = [1e30, 1e30, 1e30]"), &render(&[]), 2, "camera.position: is 1.732e30 from the origin: too far for f32 ray arithmetic"),
        case("keys out of order", quad_with("transform = { keyframes = [{ time = 0.5 }, { time = 0.1, translate = [1.0, 0.0, 0.0] }] }"), &render(&[]), 2, "shape[0].transform.keyframes[1].time: keys must be in increasing time: 0.1 follows 0.5"),
        case("keys beside a translate", quad_with("transform = { translate = [1.0, 0.0, 0.0], keyframes = [{ time = 0.0 }] }"), &render(&[]), 2, "shape[0].transform: give either keyframes or translate/rotate/scale"),
        case("a scaling camera", scene(QUAD).replace("[integrator]", "transform = { keyframes = [{ time = 0.0 }, { time = 0.5, scale = 2.0 }] }\n[integrator]"), &render(&[]), 2, "camera.transform: a camera moves rigidly"),
        case("emission on an albedo-1 medium", scene(&vdb_medium("one.vdb", "emission = 2.0")), &render(&["--out", "o.exr", "--png", "o.png"]), 0, "medium[0].emission: does nothing"),
    ]
}

fn pathological_cases() -> Vec<Case> {
    let fog = |p: &str| {
        scene(&format!(
            "{QUAD}[[medium]]\ntype = \"height_fog\"\nvisibility = 100.0\n{p}\n"
        ))
    };
    let out = || render(&["--out", "o.exr", "--png", "o.png"]);
    vec![
        case(
            "fog scale_height 1e-30",
            fog("scale_height = 1e-30"),
            &out(),
            0,
            "",
        ),
        case(
            "fog scale_height 1e-10",
            fog("scale_height = 1e-10"),
            &out(),
            0,
            "",
        ),
        case(
            "fog height -1e30",
            fog("scale_height = 10.0\nheight = -1e30"),
            &out(),
            0,
            "",
        ),
        case(
            "fog height 1e30",
            fog("scale_height = 1e-30\nheight = 1e30"),
            &out(),
            0,
            "",
        ),
        case(
            "mesh of 30000 copies of one triangle",
            scene("[[shape]]\ntype = \"mesh\"\nfile = \"repeats.obj\"\n"),
            &out(),
            0,
            "",
        ),
        case(
            "VDB density_scale 1e6",
            scene(&vdb_medium(&smoke(), "density_scale = 1e6\nalbedo = 1.0")),
            &out(),
            0,
            "",
        ),
        case(
            "VDB density_scale 1e6, global majorant",
            scene(&vdb_medium(
                &smoke(),
                "density_scale = 1e6\nalbedo = 1.0\nmajorant = \"global\"",
            ))
            .replace("spp = 2", "spp = 1"),
            &out(),
            0,
            "",
        ),
    ]
}

#[test]
fn output_rules() {
    output_cases().iter().for_each(check);
}

#[test]
fn input_files() {
    input_cases().iter().for_each(check);
}

#[test]
fn grid_values() {
    grid_cases().iter().for_each(check);
}

#[test]
fn messages_in_the_users_words() {
    message_cases().iter().for_each(check);
}

#[test]
fn pathological_scenes_finish() {
    pathological_cases().iter().for_each(check);
}

#[test]
fn at_least_forty_cases() {
    let n = output_cases().len()
        + input_cases().len()
        + grid_cases().len()
        + message_cases().len()
        + pathological_cases().len();
    assert!(n >= 40, "{n} cases");
}

/// `info` counts NaN and infinite values and prints "inf", not JSON's null.
#[test]
fn info_reports_nonfinite_values() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path(), &scene(QUAD));
    for (file, expect) in [("inf.vdb", "infinite: 1"), ("nan.vdb", "NaN: 1")] {
        let out = Command::cargo_bin("brume")
            .unwrap()
            .current_dir(dir.path())
            .args(["info", file])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains(expect), "{file}: {text}");
        let json = Command::cargo_bin("brume")
            .unwrap()
            .current_dir(dir.path())
            .args(["info", "--json", file])
            .output()
            .unwrap();
        let json = String::from_utf8_lossy(&json.stdout);
        assert!(!json.contains("null"), "{file}: {json}");
    }
}

/// `--time 1e-300` renders one pass and marks nothing it did not do.
#[test]
fn tiny_time_budget_renders_one_pass() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path(), &scene(QUAD));
    let (code, stderr, _) = run(
        dir.path(),
        &[
            "render", "s.toml", "--time", "1e-300", "--out", "o.exr", "--png", "o.png",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let meta = exr::meta::MetaData::read_from_file(dir.path().join("o.exr"), false).unwrap();
    let spp = meta.headers[0]
        .own_attributes
        .other
        .get(&exr::meta::attribute::Text::from("brume:spp"))
        .cloned()
        .or_else(|| {
            meta.headers[0]
                .shared_attributes
                .other
                .get(&exr::meta::attribute::Text::from("brume:spp"))
                .cloned()
        });
    assert!(
        matches!(spp, Some(exr::meta::attribute::AttributeValue::I32(n)) if n >= 1),
        "{spp:?}"
    );
}

/// SIGINT to a render stuck in a pathological scene (a dense VDB under a
/// global majorant, where every ray walks to the tracking cap) ends it within
/// 2 s; with no pass finished it exits 130 and leaves the earlier image alone.
/// Uniform (`--adaptive off`): the automatic choice's 4-spp pilot would
/// finish within the 1.5 s and, being the image's first samples, be kept
/// as a partial image.
#[test]
fn sigint_stops_a_stuck_render_within_two_seconds() {
    let dir = tempfile::tempdir().unwrap();
    let text = scene(&vdb_medium(
        &smoke(),
        "density_scale = 1e6\nalbedo = 1.0\nmajorant = \"global\"",
    ))
    .replace("resolution = [8, 6]", "resolution = [256, 256]")
    .replace("spp = 2", "spp = 64");
    setup(dir.path(), &text);
    let before = snapshot(dir.path());
    let mut child = Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args(["render", "s.toml", "--out", "keep.exr", "--png", "keep.png"])
        .args(["--adaptive", "off"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the render must still be running"
    );
    let sent = Instant::now();
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    while child.try_wait().unwrap().is_none() {
        if sent.elapsed() > Duration::from_secs(10) {
            child.kill().unwrap();
            panic!("brume did not stop within 10 s of SIGINT");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let stopped = sent.elapsed();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stopped < Duration::from_secs(2),
        "stopped after {stopped:?}"
    );
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("nothing written"), "{stderr}");
    assert_eq!(
        snapshot(dir.path()),
        before,
        "the earlier image must survive"
    );
}

#[test]
fn a_closed_stdout_pipe_ends_quietly() {
    use std::os::unix::process::ExitStatusExt;
    // The reader is closed before brume starts, so its first print meets a
    // broken pipe for certain (a reader closed after spawning could race it).
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let volume =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/volumes/homogeneous_box.vdb");
    let out = Command::cargo_bin("brume")
        .unwrap()
        .arg("info")
        .arg(&volume)
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        out.status.signal(),
        Some(libc::SIGPIPE),
        "{:?}: {stderr}",
        out.status
    );
}
