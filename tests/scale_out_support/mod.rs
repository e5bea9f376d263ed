//! Helpers shared by the scale-out tests: a small smoke scene, running brume,
//! reading films and comparing them.
#![allow(dead_code)]

use assert_cmd::cargo::CommandCargoExt;
use brume::film::Film;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The brume binary with no standard input and captured output.
pub fn brume() -> Command {
    let mut cmd = Command::cargo_bin("brume").unwrap();
    cmd.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    cmd
}

/// `dir/scene.toml`: the repository's smoke plume (copied to `dir/plume.vdb`)
/// over a ground plane, 32×24 pixels, 64 spp, with smoke albedo `albedo`.
pub fn plume_scene(dir: &Path, albedo: f32) -> PathBuf {
    let vdb = Path::new(env!("CARGO_MANIFEST_DIR")).join("volumes/smoke_plume.vdb");
    std::fs::copy(vdb, dir.join("plume.vdb")).unwrap();
    let text = format!(
        r#"
[camera]
position = [0.0, 1.1, 4.6]
look_at = [0.0, 0.85, 0.0]
fov = 40.0
resolution = [32, 24]

[integrator]
spp = 64
max_depth = 8

[[light]]
type = "sun"
direction = [-1.0, -1.1, -0.7]
irradiance = [3.0, 2.85, 2.6]

[[light]]
type = "sky"
zenith = [0.25, 0.4, 0.8]
horizon = [0.6, 0.7, 0.8]
ground = [0.1, 0.1, 0.1]

[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [40.0, 40.0]

[[medium]]
type = "vdb"
file = "plume.vdb"
grid = "density"
density_scale = 20.0
albedo = {albedo}
transform = {{ translate = [-1.02, 0.0, -1.0] }}
"#
    );
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    scene
}

/// Renders `scene` with `args` to `NAME.exr` beside it; returns the EXR path.
pub fn render(scene: &Path, args: &[&str], name: &str) -> PathBuf {
    let dir = scene.parent().unwrap();
    let out = dir.join(format!("{name}.exr"));
    let output = brume()
        .env_remove("JOB_COMPLETION_INDEX")
        .args(["render", "--quiet", "--threads", "2"])
        .arg(scene)
        .args(args)
        .arg("--out")
        .arg(&out)
        .arg("--png")
        .arg(dir.join(format!("{name}.png")))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "render {args:?}: {stderr}");
    out
}

/// Sends SIGINT to `child` after `after`, then waits for it at most 60 s.
pub fn interrupt_after(mut child: Child, after: Duration) -> Output {
    std::thread::sleep(after);
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success(), "kill -INT failed");
    let deadline = Instant::now() + Duration::from_secs(60);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            child.kill().unwrap();
            panic!("brume did not stop within 60 s of SIGINT");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Merges `pieces` into `dir/merged.exr` with `brume merge`; returns its path.
pub fn merge(dir: &Path, pieces: &[PathBuf]) -> PathBuf {
    let out = dir.join("merged.exr");
    let output = brume()
        .arg("merge")
        .args(pieces)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "merge: {stderr}");
    out
}

/// The film in an EXR written by brume.
pub fn film(path: &Path) -> Film {
    brume::film::image_io::read_film_exr(path).unwrap()
}

/// Every beauty channel mean of `film` as f32, in pixel order.
pub fn beauty_means(film: &Film) -> Vec<f32> {
    let beauty = &film.layers[0];
    (0..film.window.area())
        .flat_map(|i| (0..3).map(move |c| (i, c)))
        .map(|(i, c)| film.mean(beauty, i, c))
        .collect()
}

/// Distance in units in the last place between two finite f32 values.
pub fn ulps(a: f32, b: f32) -> u32 {
    // Map the floats onto the integers in order (negative values mirrored).
    let key = |v: f32| {
        let bits = v.to_bits() as i32;
        if bits < 0 {
            i32::MIN - bits
        } else {
            bits
        }
    };
    (key(a) as i64 - key(b) as i64).unsigned_abs() as u32
}

/// The largest per-channel ulp distance between two images of the same size.
pub fn max_ulps(a: &[f32], b: &[f32]) -> u32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| ulps(*x, *y))
        .max()
        .unwrap_or(0)
}

/// Asserts two films hold the same windows, counts and the same f64 sums bit for bit.
pub fn assert_bit_identical(single: &Film, merged: &Film) {
    assert_eq!(
        (merged.display, merged.window),
        (single.display, single.window)
    );
    assert_eq!(merged.counts, single.counts);
    assert_eq!(merged.nonfinite, single.nonfinite);
    assert_eq!(merged.provenance, single.provenance);
    let bits = |f: &Film| -> Vec<u64> { f.layers[0].sums.iter().map(|s| s.to_bits()).collect() };
    assert!(
        bits(merged) == bits(single),
        "the merged sums differ from the full render's"
    );
    let mean_bits =
        |f: &Film| -> Vec<u32> { beauty_means(f).iter().map(|v| v.to_bits()).collect() };
    assert!(mean_bits(merged) == mean_bits(single));
}
