//! Output safety through the command line: an interrupted render (SIGINT or
//! SIGTERM) saves exactly the passes it finished, marked as partial in the EXR
//! header; a failed render never touches an existing image nor leaves
//! temporary files; a write failure after rendering exits with code 1.

mod common;

use common::cli::{self, brume};
use common::SceneText;
use exr::meta::attribute::AttributeValue;
use std::path::{Path, PathBuf};
use std::process::{Child, Output};
use std::time::Duration;

/// A sphere on a plane; `spp` large enough that only a signal ends the render.
fn slow_scene(dir: &Path) -> PathBuf {
    let scene = dir.join("slow.toml");
    let text = SceneText::camera([0.0, 1.0, 4.0], [0.0, 0.5, 0.0], [96, 64])
        .integrator("spp = 1000000")
        .point_light([0.0, 3.0, 2.0], 20.0)
        .sphere([0.0, 0.5, 0.0], 0.5)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [10.0, 10.0]);
    std::fs::write(&scene, text.build()).unwrap();
    scene
}

/// Sends `signal` (e.g. "INT") to the child after `after`, then waits at most 30 s.
fn signal_and_wait(child: Child, signal: &str, after: Duration) -> Output {
    cli::signal_and_wait(child, signal, after, Duration::from_secs(30))
}

/// The `brume:spp` and `brume:complete` header attributes of an EXR.
fn brume_attributes(path: &Path) -> (i32, i32) {
    let meta = exr::meta::MetaData::read_from_file(path, false).unwrap();
    // Image-wide attributes are written to the header; a reader may file
    // unknown ones under either the shared or the layer's attributes.
    let header = &meta.headers[0];
    let int = |name: &str| {
        let key = exr::meta::attribute::Text::from(name);
        let value = header
            .shared_attributes
            .other
            .get(&key)
            .or_else(|| header.own_attributes.other.get(&key));
        match value {
            Some(AttributeValue::I32(v)) => *v,
            v => panic!("{name}: {v:?}"),
        }
    };
    (int("brume:spp"), int("brume:complete"))
}

/// Files whose names mark them as the writers' temporaries.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect()
}

/// Interrupts a render with `signal`; checks the saved image; returns its spp.
fn interrupted_render(signal: &str, extra: &[&str], pass: i32) -> (tempfile::TempDir, i32) {
    let dir = tempfile::tempdir().unwrap();
    let scene = slow_scene(dir.path());
    let child = brume()
        .current_dir(dir.path())
        .args(["render", "--quiet", "--threads", "2", "--adaptive", "off"])
        .args(extra)
        .arg(&scene)
        .spawn()
        .unwrap();
    let output = signal_and_wait(child, signal, Duration::from_millis(2000));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "SIG{signal}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let exr = dir.path().join("slow.exr");
    let (spp, complete) = brume_attributes(&exr);
    assert_eq!(complete, 0, "SIG{signal}: the image must be marked partial");
    assert!(spp > 0, "SIG{signal}: no pass finished in 2 s");
    assert_eq!(spp % pass, 0, "SIG{signal}: {spp} spp is not whole passes");
    assert!(
        stderr.contains(&format!("interrupted: saved the {spp} spp")),
        "SIG{signal}: {stderr}"
    );
    assert!(dir.path().join("slow.png").exists());
    assert!(temporaries(dir.path()).is_empty());
    let (_, _, pixels) = brume::film::image_io::read_exr(&exr).unwrap();
    assert!(pixels.iter().all(|p| p.is_finite()));
    assert!(pixels.iter().any(|p| p.max_channel() > 0.0));
    (dir, spp)
}

#[test]
fn sigint_saves_exactly_the_finished_passes() {
    let (dir, spp) = interrupted_render("INT", &[], 16);
    // The same render asked for `spp` samples must give the very same image:
    // the interrupted pass left no trace.
    let output = brume()
        .current_dir(dir.path())
        .args([
            "render",
            "--quiet",
            "--adaptive",
            "off",
            "slow.toml",
            "--out",
            "full.exr",
        ])
        .args(["--png", "full.png", "--spp", &spp.to_string()])
        .output()
        .unwrap();
    assert!(output.status.success());
    assert_eq!(brume_attributes(&dir.path().join("full.exr")), (spp, 1));
    let (_, _, partial) = brume::film::image_io::read_exr(&dir.path().join("slow.exr")).unwrap();
    let (_, _, full) = brume::film::image_io::read_exr(&dir.path().join("full.exr")).unwrap();
    assert!(
        partial == full,
        "the interrupted image differs from a {spp} spp render"
    );
}

#[test]
fn sigterm_during_a_timed_render_saves_its_passes() {
    interrupted_render("TERM", &["--time", "60"], 4);
}

#[test]
fn an_existing_output_survives_failed_renders() {
    let dir = tempfile::tempdir().unwrap();
    let scene = slow_scene(dir.path());
    let bad_scene = dir.path().join("bad.toml");
    std::fs::write(&bad_scene, "[camera]\nposition = [0.0, 0.0]\n").unwrap();
    let exr = dir.path().join("out.exr");
    std::fs::write(&exr, b"precious").unwrap();
    let folder = dir.path().join("a_folder.png");
    std::fs::create_dir(&folder).unwrap();
    let runs: [(&Path, &Path, &str); 3] = [
        (&bad_scene, &dir.path().join("out.png"), "camera.position"),
        (&scene, &folder, "a_folder.png"),
        (&scene, &dir.path().join("no/such/folder.png"), "folder.png"),
    ];
    for (scene, png, culprit) in runs {
        let output = brume()
            .args(["render", "--quiet", "--spp", "1"])
            .arg(scene)
            .arg("--out")
            .arg(&exr)
            .arg("--png")
            .arg(png)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains(culprit), "{culprit}: {stderr}");
        assert_eq!(std::fs::read(&exr).unwrap(), b"precious", "{stderr}");
        assert!(temporaries(dir.path()).is_empty());
    }
}

#[test]
fn a_write_failure_after_rendering_exits_1_and_keeps_the_other_output() {
    let dir = tempfile::tempdir().unwrap();
    let scene = slow_scene(dir.path());
    let gone = dir.path().join("gone");
    std::fs::create_dir(&gone).unwrap();
    let png = dir.path().join("keep.png");
    std::fs::write(&png, b"precious").unwrap();
    let child = brume()
        .args(["render", "--quiet", "--threads", "1", "--time", "60"])
        .arg(&scene)
        .arg("--out")
        .arg(gone.join("out.exr"))
        .arg("--png")
        .arg(&png)
        .spawn()
        .unwrap();
    // The output folder disappears while rendering: a runtime failure.
    std::thread::sleep(Duration::from_millis(500));
    std::fs::remove_dir(&gone).unwrap();
    let output = signal_and_wait(child, "INT", Duration::from_millis(300));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("gone/out.exr: cannot write output"),
        "{stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert_eq!(std::fs::read(&png).unwrap(), b"precious");
    assert!(temporaries(dir.path()).is_empty());
}

/// Renders `resolution` of the slow scene at 1 spp; returns (exit code, stderr, whether an EXR appeared).
fn render_at(resolution: [u32; 2]) -> (Option<i32>, String, bool) {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(slow_scene(dir.path())).unwrap();
    let huge = dir.path().join("huge.toml");
    let res = format!("[{}, {}]", resolution[0], resolution[1]);
    std::fs::write(&huge, text.replace("[96, 64]", &res)).unwrap();
    let output = brume()
        .current_dir(dir.path())
        .env("BRUME_MEMORY_LIMIT", LIMIT_GB.to_string())
        .args(["render", "--quiet", "--spp", "1", "huge.toml"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    (
        output.status.code(),
        stderr,
        dir.path().join("huge.exr").exists(),
    )
}

/// The memory limit the render tests set (GB), the same on every machine.
const LIMIT_GB: u64 = 64;

#[test]
fn an_image_over_the_memory_limit_is_refused_on_every_machine() {
    use brume::render::peak_bytes;
    let limit = LIMIT_GB * 1_000_000_000;
    // the smallest square image over the limit, and one just under it
    let over = (1..).find(|&s| peak_bytes(s, s) > limit).unwrap();
    assert!(peak_bytes(over - 1, over - 1) <= limit);
    for res in [[over, over], [32768, 32768]] {
        let (code, stderr, exr) = render_at(res);
        assert_eq!(code, Some(2), "{res:?}: {stderr}");
        let needs = format!(
            "huge.toml: camera.resolution: a {}x{} image needs {:.1} GB of memory, more than the memory limit of {LIMIT_GB}.0 GB (set by BRUME_MEMORY_LIMIT)",
            res[0],
            res[1],
            peak_bytes(res[0], res[1]) as f64 / 1e9,
        );
        assert!(stderr.contains(&needs), "{res:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(!exr, "{res:?}: an image was written");
    }
}

#[test]
fn an_absurd_thread_count_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let scene = slow_scene(dir.path());
    let output = brume()
        .args(["render", "--quiet", "--spp", "1", "--threads", "100000"])
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--threads") && stderr.contains("from 1 to 1024"),
        "{stderr}"
    );
}
