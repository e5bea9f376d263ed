//! The memory limit through the command line: every file or flag that sizes
//! an allocation (environment maps, textures, merge pieces, compare inputs,
//! VDB files, velocity-dilated majorant grids, the render itself) is refused
//! with exit code 2 and one line naming the file or key, the declared size
//! and the limit; `--memory-limit` and `BRUME_MEMORY_LIMIT` set the limit.

mod limits_support;

use assert_cmd::Command;
use limits_support::{tiny_rgb_exr, tiny_rgb_png, EXR_COMPRESSIONS};
use std::path::Path;
use std::time::{Duration, Instant};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Runs brume in `dir` without a limit from the environment; (exit code, stderr, seconds).
fn brume(dir: &Path, args: &[&str], env: Option<&str>) -> (Option<i32>, String, f64) {
    let mut cmd = Command::cargo_bin("brume").unwrap();
    cmd.current_dir(dir)
        .args(args)
        .env_remove("BRUME_MEMORY_LIMIT");
    if let Some(value) = env {
        cmd.env("BRUME_MEMORY_LIMIT", value);
    }
    let started = Instant::now();
    let out = cmd.timeout(Duration::from_secs(60)).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code(), stderr, started.elapsed().as_secs_f64())
}

/// Exit code 2, one line holding every piece of `wanted`, no panic, and quickly.
fn assert_refused((code, stderr, secs): (Option<i32>, String, f64), wanted: &[&str]) {
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    for w in wanted {
        assert!(stderr.contains(w), "missing `{w}` in: {stderr}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(secs < 10.0, "took {secs} s: {stderr}");
}

const CAMERA: &str =
    "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [4, 4]\n";

#[test]
fn a_tiny_environment_map_declaring_a_huge_image_is_refused_for_every_compression() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!("{CAMERA}[[light]]\ntype = \"environment_map\"\nfile = \"sky.exr\"\n");
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    for (code, name) in EXR_COMPRESSIONS {
        let rgb = [("B", 2), ("G", 2), ("R", 2)];
        let file = limits_support::exr([0, 0, 59999, 59999], code, &rgb, &[0; 64]);
        std::fs::write(dir.path().join("sky.exr"), file).unwrap();
        let run = brume(dir.path(), &["render", "s.toml"], None);
        assert_refused(
            run,
            &[
                "s.toml: light[0].file: ",
                "sky.exr: declares 60000x60000 pixels (43.2 GB decoded) but the file is ",
                "truncated or damaged",
            ],
        );
        assert!(
            !dir.path().join("s.exr").exists(),
            "{name}: an image was written"
        );
    }
}

#[test]
fn a_tiny_texture_declaring_a_huge_image_is_refused_with_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{CAMERA}[[light]]\ntype = \"environment\"\nradiance = 1.0\n[[shape]]\ntype = \"quad\"\n\
         normal = [0.0, 0.0, 1.0]\nsize = [1.0, 1.0]\n\
         material = {{ type = \"diffuse\", albedo = {{ type = \"image\", file = \"t.png\" }} }}\n"
    );
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    std::fs::write(dir.path().join("t.png"), tiny_rgb_png(30000, 30000)).unwrap();
    assert_refused(
        brume(dir.path(), &["render", "s.toml"], None),
        &[
            "s.toml: shape[0].material.albedo.file: ",
            "t.png: declares 30000x30000 pixels (10.8 GB decoded) but the file is ",
        ],
    );
}

#[test]
fn merge_pieces_and_compare_inputs_declaring_huge_images_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("big.exr"), tiny_rgb_exr(40000, 40000)).unwrap();
    let declares = "big.exr: declares 40000x40000 pixels (";
    assert_refused(
        brume(dir.path(), &["merge", "big.exr", "-o", "m.exr"], None),
        &[declares],
    );
    assert!(!dir.path().join("m.exr").exists());
    assert_refused(
        brume(dir.path(), &["compare", "big.exr", "big.exr"], None),
        &[declares],
    );
}

/// A valid 8×8 crop of a 4000×4000 image: the merged film it declares
/// (4000² pixels × 36 bytes = 576 MB) is refused over a 500 MB limit before
/// any merging (without the check, the merge fails on the missing pixels).
#[test]
fn a_merge_whose_merged_film_is_over_the_limit_is_refused_before_merging() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{}[[light]]\ntype = \"point\"\nposition = [0.0, 3.0, 0.0]\nintensity = 5.0\n",
        CAMERA.replace("[4, 4]", "[4000, 4000]")
    );
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    let render = [
        "render", "--quiet", "s.toml", "--crop", "0,8,0,8", "--spp", "1",
    ];
    let (code, stderr, _) = brume(
        dir.path(),
        &[&render[..], &["--out", "p.exr"]].concat(),
        Some("3"),
    );
    assert_eq!(code, Some(0), "{stderr}");
    assert_refused(
        brume(dir.path(), &["merge", "p.exr", "-o", "m.exr"], Some("0.5")),
        &["cannot merge: p.exr declares a 4000x4000 image, whose merged film needs 576.0 MB, more than the memory limit of 500.0 MB"],
    );
    assert!(!dir.path().join("m.exr").exists());
}

/// A real 256×128 sky (393 kB decoded) over limits of 200 kB from the flag or the environment.
#[test]
fn the_limit_comes_from_the_flag_else_the_environment_and_names_its_source() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(root().join("scenes/sky.exr"), dir.path().join("sky.exr")).unwrap();
    let scene = format!("{CAMERA}[[light]]\ntype = \"environment_map\"\nfile = \"sky.exr\"\n");
    std::fs::write(dir.path().join("s.toml"), scene).unwrap();
    let over = "sky.exr: declares 256x128 pixels (393.2 kB decoded), more than the memory limit of 200.0 kB";
    let raise = "raise it with --memory-limit GB or BRUME_MEMORY_LIMIT=GB";
    let args = ["render", "--quiet", "--spp", "1", "s.toml"];
    let flag = ["--memory-limit", "0.0002"];
    let with_flag: Vec<&str> = args[..4]
        .iter()
        .chain(&flag)
        .chain(&args[4..])
        .copied()
        .collect();
    assert_refused(
        brume(dir.path(), &with_flag, None),
        &[over, "(set by --memory-limit)", raise],
    );
    assert_refused(
        brume(dir.path(), &args, Some("0.0002")),
        &[over, "(set by BRUME_MEMORY_LIMIT)", raise],
    );
    // The flag wins over the environment, before or after the command's name.
    let before: Vec<&str> = ["--memory-limit", "1"]
        .iter()
        .chain(&args)
        .copied()
        .collect();
    let (code, stderr, _) = brume(dir.path(), &before, Some("0.0002"));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(dir.path().join("s.exr").exists());
}

#[test]
fn a_limit_that_is_not_a_size_is_refused_in_the_users_words() {
    let dir = tempfile::tempdir().unwrap();
    let info = ["info", "x.vdb"];
    for bad in ["abc", "0", "-2", "inf", "nan", "1e300", ""] {
        assert_refused(
            brume(dir.path(), &info, Some(bad)),
            &["error: invalid argument BRUME_MEMORY_LIMIT: "],
        );
        let (code, stderr, _) = brume(dir.path(), &["info", "--memory-limit", bad, "x.vdb"], None);
        assert_eq!(code, Some(2), "{bad}: {stderr}");
        assert!(stderr.contains("--memory-limit"), "{bad}: {stderr}");
        assert!(
            !stderr.contains("f64") && !stderr.contains("panicked"),
            "{stderr}"
        );
    }
}

#[test]
fn a_vdb_file_larger_than_the_limit_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let plume = root().join("tests/data/anim/plume.0001.vdb");
    let plume = plume.to_str().unwrap();
    assert_refused(
        brume(
            dir.path(),
            &["info", "--memory-limit", "0.00001", plume],
            None,
        ),
        &[
            "plume.0001.vdb: ",
            "is 90.7 kB, more than the memory limit of 10.0 kB (set by --memory-limit)",
        ],
    );
}

#[test]
fn an_extreme_velocity_scale_is_refused_on_its_key_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let plume = root().join("tests/data/anim/plume.0001.vdb");
    for scale in ["3e4", "1e6", "1e30", "-1e38"] {
        let scene = format!(
            "{CAMERA}shutter = [-0.5, 0.5]\n[animation]\nfps = 24.0\n[[light]]\ntype = \"environment\"\n\
             radiance = 1.0\n[[medium]]\ntype = \"vdb\"\nfile = \"{}\"\nvelocity_grid = \"vel\"\n\
             velocity_scale = {scale}\n",
            plume.display()
        );
        std::fs::write(dir.path().join("m.toml"), scene).unwrap();
        assert_refused(
            brume(dir.path(), &["render", "m.toml"], Some("8")),
            &[
                "m.toml: medium[0].velocity_scale: over the shutter [-0.5, 0.5] the medium moves up to ",
                "voxels, so its majorant grid needs ",
                "a smaller velocity_scale or shutter moves it less",
            ],
        );
    }
}

#[test]
fn an_airlight_width_over_the_limit_is_refused_on_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["airlight", "--out", "air", "--spp", "1", "--width", "30000"];
    // The size is the render's peak, as for `camera.resolution`.
    let needs = brume::error::limits::format_bytes(brume::render::peak_bytes(30000, 6000) as u128);
    let wanted = format!(
        "invalid argument --width: a 30000x6000 image needs {needs} of memory, more than the memory limit of 1.0 GB"
    );
    assert_refused(brume(dir.path(), &args, Some("1")), &[&wanted]);
}
