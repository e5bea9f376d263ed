//! `--display` against a loopback tev server written here, and `--checkpoint`.

mod common;

use common::SceneText;
use std::io::Read;
use std::net::TcpListener;
use std::path::Path;

/// A small scene: a diffuse sphere under an environment, 24×16 pixels.
fn scene() -> String {
    SceneText::camera([0.0, 0.0, 4.0], [0.0; 3], [24, 16])
        .fov(40.0)
        .integrator("spp = 48")
        .environment([0.8, 0.9, 1.0])
        .sphere([0.0; 3], 1.0)
        .with("material = { type = \"diffuse\", albedo = [0.7, 0.5, 0.3] }")
        .build()
}

/// `brume render SCENE --out EXR --png` (the PNG beside the EXR), for more arguments.
fn render_ball(scene: &Path, exr: &Path) -> std::process::Command {
    let mut cmd = common::cli::brume();
    cmd.arg("render")
        .arg(scene)
        .arg("--out")
        .arg(exr)
        .arg("--png")
        .arg(exr.with_extension("png"))
        // The passes of a uniform render: an adaptive one sends its own.
        .args(["--adaptive", "off"]);
    cmd
}

fn write_scene(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("ball.toml");
    std::fs::write(&path, scene()).unwrap();
    path
}

/// One decoded tev packet: its type and payload (after the type byte).
struct Packet {
    kind: u8,
    body: Vec<u8>,
}

fn read_packets(mut stream: std::net::TcpStream) -> Vec<Packet> {
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).unwrap();
    let mut packets = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let len = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert!(len >= 5 && at + len <= bytes.len(), "bad framing at {at}");
        packets.push(Packet {
            kind: bytes[at + 4],
            body: bytes[at + 5..at + len].to_vec(),
        });
        at += len;
    }
    packets
}

/// Reads a NUL-terminated string at `*at`.
fn string(body: &[u8], at: &mut usize) -> String {
    let end = body[*at..].iter().position(|&b| b == 0).unwrap() + *at;
    let s = String::from_utf8(body[*at..end].to_vec()).unwrap();
    *at = end + 1;
    s
}

fn i32_at(body: &[u8], at: &mut usize) -> i32 {
    let v = i32::from_le_bytes(body[*at..*at + 4].try_into().unwrap());
    *at += 4;
    v
}

/// An update packet: (y, height, pixels as interleaved RGB).
fn decode_update(body: &[u8]) -> (usize, usize, Vec<f32>) {
    let mut at = 1;
    assert_eq!(string(body, &mut at), "ball");
    assert_eq!(i32_at(body, &mut at), 3);
    let names: Vec<String> = (0..3).map(|_| string(body, &mut at)).collect();
    assert_eq!(names, ["R", "G", "B"]);
    let (x, y, w, h) = (
        i32_at(body, &mut at),
        i32_at(body, &mut at),
        i32_at(body, &mut at),
        i32_at(body, &mut at),
    );
    assert_eq!((x, w), (0, 24));
    let longs: Vec<i64> = body[at..at + 48]
        .chunks(8)
        .map(|b| i64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(longs, [0, 1, 2, 3, 3, 3], "offsets and strides");
    at += 48;
    let data: Vec<f32> = body[at..]
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(data.len(), (w * h * 3) as usize);
    (y as usize, h as usize, data)
}

#[test]
fn display_streams_every_pass_to_a_tev_server() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let server = std::thread::spawn(move || read_packets(listener.accept().unwrap().0));
    let exr = dir.path().join("ball.exr");
    let output = render_ball(&scene, &exr)
        .args(["--quiet", "--display", &format!("127.0.0.1:{port}")])
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    let packets = server.join().unwrap();
    // CreateImage first: focus, name, 24×16, three channels R, G, B.
    assert_eq!(packets[0].kind, 4);
    let body = &packets[0].body;
    let mut at = 1;
    assert_eq!(string(body, &mut at), "ball");
    assert_eq!(
        (
            i32_at(body, &mut at),
            i32_at(body, &mut at),
            i32_at(body, &mut at)
        ),
        (24, 16, 3)
    );
    // 48 spp in passes of 16: three updates of the whole (small) image.
    let updates: Vec<_> = packets[1..]
        .iter()
        .map(|p| (p.kind, decode_update(&p.body)))
        .collect();
    assert_eq!(updates.len(), 3);
    for (kind, (y, h, _)) in &updates {
        assert_eq!((*kind, *y, *h), (6, 0, 16));
    }
    // The last pass is the final image, bit for bit.
    let (w, h, pixels) = brume::film::image_io::read_exr(&exr).unwrap();
    assert_eq!((w, h), (24, 16));
    let last = &updates[2].1 .2;
    let expected: Vec<f32> = pixels.iter().flat_map(|c| [c.r, c.g, c.b]).collect();
    assert_eq!(last, &expected);
    // Earlier passes are noisier estimates of the same image, not copies of it.
    assert_ne!(&updates[0].1 .2, last);
}

#[test]
fn display_refuses_an_address_nobody_listens_on() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    // Bind then drop: the port is free, so nothing listens there.
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let out = assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .arg("render")
        .arg(&scene)
        .args(["--quiet", "--display", &format!("127.0.0.1:{port}")])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--display") && stderr.contains("cannot connect"),
        "{stderr}"
    );
    assert!(!dir.path().join("ball.exr").exists());
}

fn complete_flag(path: &Path) -> Option<i32> {
    use exr::meta::attribute::{AttributeValue, Text};
    let meta = exr::meta::MetaData::read_from_file(path, false).ok()?;
    let key = Text::from("brume:complete");
    // The exr crate reads attributes it does not know into the layer's own set.
    let header = &meta.headers[0];
    let value = header
        .own_attributes
        .other
        .get(&key)
        .or_else(|| header.shared_attributes.other.get(&key));
    match value {
        Some(AttributeValue::I32(v)) => Some(*v),
        _ => None,
    }
}

/// While a 4-second timed render runs, a checkpoint appears marked incomplete;
/// after it, the file is the complete render.
#[test]
fn checkpoints_are_written_during_the_render_and_marked_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let exr = dir.path().join("ball.exr");
    let mut child = render_ball(&scene, &exr)
        .args([
            "--quiet",
            "--time",
            "4",
            "--checkpoint",
            "0.2",
            "--threads",
            "1",
        ])
        // Nobody reads a pipe while it runs: let its output through.
        .stdout(std::process::Stdio::inherit())
        .stderr(std::process::Stdio::inherit())
        .spawn()
        .unwrap();
    let mut seen_incomplete = false;
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() && start.elapsed().as_secs() < 60 {
        if exr.exists() && complete_flag(&exr) == Some(0) {
            seen_incomplete = true;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(child.wait().unwrap().success());
    assert!(
        seen_incomplete,
        "no incomplete checkpoint seen during the render"
    );
    assert_eq!(complete_flag(&exr), Some(1));
    // Only the final files remain: no temporary file was left behind.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");
}

#[test]
fn bad_checkpoint_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    for v in ["0", "-1", "nan"] {
        assert_cmd::Command::cargo_bin("brume")
            .unwrap()
            .current_dir(dir.path())
            .arg("render")
            .arg(&scene)
            .args(["--quiet", "--checkpoint", v])
            .assert()
            .code(2);
    }
}
