//! A partial image (an interrupted render, a checkpoint, a merge of
//! interrupted pieces) never replaces a complete image or one of more
//! samples: it goes beside it as `NAME.partial.exr` / `.png`, and a later
//! complete render still writes the requested path.

mod common;

use assert_cmd::cargo::CommandCargoExt;
use brume::film::image_io::{brume_header, BrumeHeader};
use brume::film::{Film, Provenance, Rect, SampleRange};
use common::cli::run_brume;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const DEADLINE: Duration = Duration::from_secs(60);

const SCENE: &str = r#"
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
resolution = [16, 12]
[integrator]
spp = 64
adaptive = false   # every pixel at 64 spp: the header's spp below
[[light]]
type = "point"
position = [0.0, 3.0, 2.0]
intensity = 20.0
[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [4.0, 4.0]
[[medium]]
type = "homogeneous"
sigma_t = 0.3
albedo = 0.8
bounds = { type = "box", min = [-2.0, 0.0, -2.0], max = [2.0, 2.0, 2.0] }
"#;

fn args(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

fn header(path: &Path) -> BrumeHeader {
    brume_header(path).unwrap_or_else(|| panic!("{} is not a brume image", path.display()))
}

/// Renders `s.toml` completely at 64 spp into `r.exr` / `r.png`; returns their bytes.
fn complete_render(dir: &Path) -> (Vec<u8>, Vec<u8>) {
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    let line = "render s.toml --out r.exr --png r.png --quiet";
    let run = run_brume(dir, &args(&line.split(' ').collect::<Vec<_>>()), DEADLINE);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(
        header(&dir.join("r.exr")),
        BrumeHeader {
            complete: true,
            spp: 64
        }
    );
    let read = |n: &str| std::fs::read(dir.join(n)).unwrap();
    (read("r.exr"), read("r.png"))
}

#[test]
fn an_interrupted_rerender_writes_beside_the_complete_image_and_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (exr, png) = complete_render(d);
    // A render far too long to finish, checkpointing after every pass.
    let mut child = Command::cargo_bin("brume")
        .unwrap()
        .current_dir(d)
        .args(["render", "s.toml", "--out", "r.exr", "--png", "r.png"])
        .args([
            "--spp",
            "100000000",
            "--checkpoint",
            "0.001",
            "--threads",
            "1",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The first checkpoint is on disk (beside r.exr) once a pass has finished.
    let start = Instant::now();
    while !d.join("r.partial.exr").exists() {
        if child.try_wait().unwrap().is_some() {
            panic!("brume ended before its first checkpoint");
        }
        if start.elapsed() > DEADLINE {
            // Never leave a render of 10^8 spp running behind a failed test.
            child.kill().unwrap();
            panic!("no checkpoint beside r.exr after {DEADLINE:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    // SAFETY: kill(2) on the pid of a child this test started and has not reaped.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert_eq!(
        std::fs::read(d.join("r.exr")).unwrap(),
        exr,
        "r.exr replaced"
    );
    assert_eq!(
        std::fs::read(d.join("r.png")).unwrap(),
        png,
        "r.png replaced"
    );
    let partial = header(&d.join("r.partial.exr"));
    assert!(!partial.complete && partial.spp > 0, "{partial:?}");
    assert!(d.join("r.partial.png").is_file());
    assert!(
        stderr.contains("to r.partial.exr and r.partial.png")
            && stderr.contains("r.exr (a complete image of 64 spp) kept"),
        "{stderr}"
    );
    let names: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert!(names.iter().all(|n| !n.contains(".tmp-")), "{names:?}");

    // A later complete render writes the requested path.
    let line = "render s.toml --out r.exr --png r.png --spp 32 --quiet";
    let run = run_brume(d, &args(&line.split(' ').collect::<Vec<_>>()), DEADLINE);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let now = header(&d.join("r.exr"));
    assert_eq!(
        now,
        BrumeHeader {
            complete: true,
            spp: 32
        }
    );
}

#[test]
fn checkpoints_beside_a_complete_image_are_removed_once_the_render_completes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    complete_render(d);
    let line = "render s.toml --out r.exr --png r.png --spp 48 --checkpoint 0.000001";
    let run = run_brume(d, &args(&line.split(' ').collect::<Vec<_>>()), DEADLINE);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("note: --checkpoint: r.exr (a complete image of 64 spp) kept"),
        "{}",
        run.stderr
    );
    assert!(!d.join("r.partial.exr").exists() && !d.join("r.partial.png").exists());
    assert_eq!(
        header(&d.join("r.exr")),
        BrumeHeader {
            complete: true,
            spp: 48
        }
    );
}

/// A 4x2 piece of `held` samples (of `requested`) of a 2 spp render, every sample 0.5.
fn piece(held: u32) -> Film {
    let provenance = Provenance {
        seed: 1,
        scene_hash: 2,
        spp_total: 2,
        requested: vec![SampleRange::new(0, 2)],
        held: vec![SampleRange::new(0, held)],
    };
    let mut film = Film::new((4, 2), Rect::full(4, 2), provenance);
    film.counts.fill(held);
    film.layers[0].sums.fill(0.5 * held as f64);
    film
}

#[test]
fn a_merge_of_interrupted_pieces_goes_beside_a_complete_merge() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    brume::film::image_io::write_film_exr(&d.join("whole.exr"), &piece(2)).unwrap();
    brume::film::image_io::write_film_exr(&d.join("cut.exr"), &piece(1)).unwrap();
    let merge = |piece: &str| {
        let line = format!("merge {piece} -o m.exr --png m.png");
        run_brume(d, &args(&line.split(' ').collect::<Vec<_>>()), DEADLINE)
    };
    let run = merge("whole.exr");
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let kept = std::fs::read(d.join("m.exr")).unwrap();
    let run = merge("cut.exr");
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(std::fs::read(d.join("m.exr")).unwrap(), kept);
    assert_eq!(
        header(&d.join("m.partial.exr")),
        BrumeHeader {
            complete: false,
            spp: 1
        }
    );
    assert!(d.join("m.partial.png").is_file());
    assert!(
        run.stderr.contains("-> m.partial.exr")
            && run
                .stderr
                .contains("m.exr (a complete image of 2 spp) kept"),
        "{}",
        run.stderr
    );
}
