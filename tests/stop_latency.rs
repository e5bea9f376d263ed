//! Stop requests are answered within a second: a tev viewer that accepts the
//! connection and never reads cannot hold up SIGTERM, Ctrl-C or the exit of
//! a finished render, and the finished passes of a large image are written
//! and brume gone within a second of SIGINT.

use std::io::Read;
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The bound on the answer to a stop request (docs/robustness.md).
const ANSWER: Duration = Duration::from_secs(1);

/// Held by each test for its whole run: they measure brume's latency, not
/// the contention of four renders started at once on a small machine.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner())
}

/// A diffuse sphere under a sky at `res`×`res`, `spp` samples.
fn write_scene(dir: &Path, res: u32, spp: u32, sphere: bool) -> PathBuf {
    let mut text = format!(
        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\
         resolution = [{res}, {res}]\n[integrator]\nspp = {spp}\n\
         [[light]]\ntype = \"environment\"\nradiance = [0.8, 0.9, 1.0]\n"
    );
    if sphere {
        text.push_str(
            "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\
             material = { type = \"diffuse\", albedo = [0.7, 0.5, 0.3] }\n",
        );
    }
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_brume"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits for `child` at most `limit` (killing it past that); returns its output and the wait.
fn wait(mut child: Child, limit: Duration) -> (Output, Duration) {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().unwrap();
            let out = child.wait_with_output().unwrap();
            panic!(
                "brume did not exit within {limit:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let waited = start.elapsed();
    (child.wait_with_output().unwrap(), waited)
}

/// Sends `signal` to `child`, then waits for it; returns its output and the time from the signal to its exit.
fn stop(child: Child, signal: i32) -> (Output, Duration) {
    // SAFETY: kill(2) on the pid of a child this test spawned and has not reaped.
    let sent = unsafe { libc::kill(child.id() as i32, signal) };
    assert_eq!(sent, 0, "kill failed");
    wait(child, Duration::from_secs(60))
}

/// A tev stand-in that accepts one connection and never reads from it.
fn deaf_viewer() -> (u16, std::thread::JoinHandle<TcpStream>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    (
        port,
        std::thread::spawn(move || listener.accept().unwrap().0),
    )
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn sigterm_is_answered_at_once_while_the_viewer_never_reads() {
    let _serial = one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    // 3 MB a pass: the socket buffers fill within a few passes, then every
    // send would block for as long as the viewer keeps not reading.
    write_scene(dir.path(), 512, 1_000_000, true);
    let (port, viewer) = deaf_viewer();
    let address = format!("127.0.0.1:{port}");
    let child = spawn(
        dir.path(),
        &["render", "s.toml", "--quiet", "--display", &address],
    );
    let connection = viewer.join().unwrap();
    std::thread::sleep(Duration::from_millis(2500));
    let (out, answered) = stop(child, libc::SIGTERM);
    drop(connection);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        answered < ANSWER,
        "SIGTERM answered after {answered:?}: {err}"
    );
    assert!(err.contains("interrupted: saved the"), "{err}");
    assert!(dir.path().join("s.exr").exists() && dir.path().join("s.png").exists());
}

/// Runs `brume render s.toml --quiet --spp 32` plus `extra` in `dir`; returns its output and run time.
fn finished_render(dir: &Path, extra: &[&str]) -> (Output, Duration) {
    let mut args = vec!["render", "s.toml", "--quiet", "--spp", "32"];
    args.extend(extra);
    wait(spawn(dir, &args), Duration::from_secs(60))
}

#[test]
fn a_finished_render_exits_soon_though_the_viewer_never_reads() {
    let _serial = one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    // Frames of 3 MB: a few fill the loopback socket buffers.
    write_scene(dir.path(), 512, 32, false);
    // The same render without a viewer, under the same load, as the yardstick.
    let (out, alone) = finished_render(dir.path(), &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let (port, viewer) = deaf_viewer();
    let address = format!("127.0.0.1:{port}");
    let child = spawn(
        dir.path(),
        &[
            "render",
            "s.toml",
            "--quiet",
            "--spp",
            "32",
            "--display",
            &address,
        ],
    );
    let connection = viewer.join().unwrap();
    let (out, took) = wait(child, Duration::from_secs(60));
    drop(connection);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    // The viewer may cost one stall window (2 s) and some slack, never a
    // wait per frame or the 10 s final wait.
    assert!(
        took < alone + Duration::from_millis(3500),
        "took {took:?}, {alone:?} without the viewer: {err}"
    );
    assert!(err.contains("tev took less than 64 KB in 2 s"), "{err}");
    let (w, h, _) = brume::film::image_io::read_exr(&dir.path().join("s.exr")).unwrap();
    assert_eq!((w, h), (512, 512));
}

#[test]
fn sigint_is_answered_at_once_while_the_viewer_reads_slowly() {
    let _serial = one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    write_scene(dir.path(), 512, 1_000_000, true);
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    // Reads about 800 KB/s: never slow enough to count as stalled (64 KB in
    // 2 s), far too slow for 3 MB frames, so frames are still queued at the
    // stop. Left running when the test ends: it would take long to read what brume queued.
    std::thread::spawn(move || {
        let (mut stream, _) = listener.accept().unwrap();
        let mut buf = vec![0u8; 16 << 10];
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    });
    let address = format!("127.0.0.1:{port}");
    let child = spawn(
        dir.path(),
        &["render", "s.toml", "--quiet", "--display", &address],
    );
    std::thread::sleep(Duration::from_millis(2500));
    let (out, answered) = stop(child, libc::SIGINT);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        answered < ANSWER,
        "SIGINT answered after {answered:?}: {err}"
    );
}

/// Starts `brume ARGS` in `dir`, sends SIGINT after `wait` and expects exit
/// 130; None (with `wait` doubled for the next try) when no pass had
/// finished, so nothing was written.
fn stop_after_a_pass(dir: &Path, args: &[&str], wait: &mut Duration) -> Option<(Output, Duration)> {
    let child = spawn(dir, args);
    std::thread::sleep(*wait);
    let (out, answered) = stop(child, libc::SIGINT);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{err}");
    if err.contains("nothing written") {
        *wait *= 2;
        return None;
    }
    Some((out, answered))
}

/// SIGINT once a pass of a 2048² render has finished: the 4 M pixels are
/// written (EXR and PNG) and brume gone within a second. Before the writes
/// were made fast and parallel this took 1.3 s at this size (2.6 s at 4096²).
/// The best of two runs is compared with the bound, so that a burst of load
/// on a shared machine measures the machine, not brume.
#[test]
fn sigint_on_a_large_image_writes_and_exits_within_a_second() {
    let _serial = one_at_a_time();
    let mut answers = Vec::new();
    let mut wait_for_pass = Duration::from_secs(3);
    for _ in 0..4 {
        let dir = tempfile::tempdir().unwrap();
        write_scene(dir.path(), 2048, 1_000_000, false);
        let args = ["render", "s.toml", "--quiet", "--time", "600"];
        // No pass finished yet: nothing to write, so nothing measured.
        let Some((out, answered)) = stop_after_a_pass(dir.path(), &args, &mut wait_for_pass) else {
            continue;
        };
        let err = stderr(&out);
        assert!(err.contains("interrupted: saved the"), "{err}");
        let (w, h, _) = brume::film::image_io::read_exr(&dir.path().join("s.exr")).unwrap();
        assert_eq!((w, h), (2048, 2048));
        assert!(dir.path().join("s.png").exists());
        answers.push(answered);
        if answers.len() == 2 {
            break;
        }
    }
    assert_eq!(
        answers.len(),
        2,
        "no pass finished in the runs: {answers:?}"
    );
    let best = answers.iter().min().unwrap();
    assert!(*best < ANSWER, "SIGINT answered after {answers:?}");
}

/// SIGINT during a Metropolis render's bootstrap (2·10⁸ independent paths,
/// minutes of work): answered within the bound, nothing written.
#[test]
fn sigint_is_answered_at_once_during_the_mlt_bootstrap() {
    let _serial = one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), 16, 4, true);
    let text = std::fs::read_to_string(&scene).unwrap();
    let text = text.replace(
        "[integrator]\n",
        "[integrator]\ntype = \"mlt\"\nbootstrap_samples = 200000000\n",
    );
    std::fs::write(&scene, text).unwrap();
    let child = spawn(dir.path(), &["render", "s.toml", "--quiet"]);
    std::thread::sleep(Duration::from_millis(1500));
    let (out, answered) = stop(child, libc::SIGINT);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        answered < ANSWER,
        "SIGINT answered after {answered:?}: {err}"
    );
    assert!(err.contains("nothing written"), "{err}");
    assert!(!dir.path().join("s.exr").exists());
}

/// A timed render asks for what it reaches, so its film is complete after a
/// stop; its image is still the stopped one and gets the fast encodings
/// (run-length EXR), as every image written on the way to the exit does.
/// It got the small, slow ZIP encoding: a stop at 4096² with five AOVs took
/// 4.4 s instead of 2.5 s.
#[test]
fn a_stopped_timed_render_is_written_with_the_fast_encoding() {
    let _serial = one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    write_scene(dir.path(), 128, 1, true);
    let mut wait_for_pass = Duration::from_millis(500);
    for _ in 0..4 {
        let args = [
            "render", "s.toml", "--quiet", "--time", "600", "--aovs", "depth",
        ];
        if stop_after_a_pass(dir.path(), &args, &mut wait_for_pass).is_none() {
            continue;
        }
        let meta = exr::meta::MetaData::read_from_file(dir.path().join("s.exr"), false).unwrap();
        assert_eq!(
            meta.headers[0].compression,
            exr::compression::Compression::RLE
        );
        return;
    }
    panic!("no pass finished before the stop in 4 runs");
}
