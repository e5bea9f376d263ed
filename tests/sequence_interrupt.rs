//! A real SIGINT in the middle of `brume render --frames`: the frames
//! finished before it stay complete, the frame in progress is saved as a
//! partial image marked incomplete (or, stopped before its first pass, not
//! written), nothing temporary is left, the exit code is 130, and
//! `--skip-existing` then resumes: it keeps the complete frames byte for
//! byte and renders the rest.

mod common;

use assert_cmd::cargo::CommandCargoExt;
use brume::film::image_io::exr_is_complete;
use common::SceneText;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const FRAMES: usize = 6;

/// A still scene slow enough (about a second a frame) to be stopped mid-sequence.
fn scene() -> String {
    SceneText::camera([0.0, 1.0, 4.0], [0.0, 0.5, 0.0], [64, 64])
        .integrator("spp = 256")
        .point_light([0.0, 3.0, 2.0], 20.0)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [4.0, 4.0])
        .medium(
            "type = \"homogeneous\"\nsigma_t = 0.3\nalbedo = 0.8\n\
             bounds = { type = \"box\", min = [-2.0, 0.0, -2.0], max = [2.0, 2.0, 2.0] }",
        )
        .build()
}

fn exr(dir: &Path, f: usize) -> std::path::PathBuf {
    dir.join(format!("seq.{f:04}.exr"))
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    v.sort();
    v
}

#[test]
fn sigint_mid_sequence_keeps_finished_frames_and_skip_existing_resumes() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("seq.toml"), scene()).unwrap();
    let frames = format!("1-{FRAMES}");
    let mut child = Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args(["render", "seq.toml", "--frames", &frames, "--threads", "1"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Stop soon after the first frame is on disk.
    let start = Instant::now();
    while !exr(dir.path(), 1).exists() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "frame 1 never appeared"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "brume ended before frame 1"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(200));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the sequence must still be running"
    );
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("resume with --skip-existing") || stderr.contains("interrupted"),
        "{stderr}"
    );

    // Frames 1..=k complete, frame k+1 partial (incomplete) or absent, none after it.
    let complete: Vec<bool> = (1..=FRAMES)
        .map(|f| exr_is_complete(&exr(dir.path(), f)))
        .collect();
    let k = complete.iter().take_while(|&&c| c).count();
    assert!((1..FRAMES).contains(&k), "{k} complete frames: {stderr}");
    assert!(complete[k..].iter().all(|&c| !c), "{complete:?}");
    if exr(dir.path(), k + 1).exists() {
        assert!(
            stderr.contains("interrupted in"),
            "a partial frame is reported: {stderr}"
        );
    }
    for f in k + 2..=FRAMES {
        assert!(!exr(dir.path(), f).exists(), "frame {f} after the stop");
    }
    let listed = names(dir.path());
    assert!(
        listed.iter().all(|n| !n.contains(".tmp")),
        "temporary files left: {listed:?}"
    );
    let kept: Vec<Vec<u8>> = (1..=k)
        .map(|f| std::fs::read(exr(dir.path(), f)).unwrap())
        .collect();

    // Resume: complete frames are skipped (and untouched), the rest rendered.
    let out = Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args([
            "render",
            "seq.toml",
            "--frames",
            &frames,
            "--skip-existing",
            "--threads",
            "1",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{stderr}");
    assert_eq!(stderr.matches("skipped").count(), k, "{stderr}");
    for f in 1..=FRAMES {
        assert!(
            exr_is_complete(&exr(dir.path(), f)),
            "frame {f} after resuming"
        );
    }
    for (f, bytes) in (1..=k).zip(&kept) {
        assert_eq!(
            &std::fs::read(exr(dir.path(), f)).unwrap(),
            bytes,
            "frame {f} rewritten"
        );
    }
    assert!(names(dir.path()).iter().all(|n| !n.contains(".tmp")));
}
