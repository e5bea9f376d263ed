//! Every file brume reads, given as something that is not a regular file:
//! for each role a file plays (the scene, a file the scene names, a frame of
//! a VDB sequence, a merge piece, a compared image, a VDB for `info`) and
//! each kind of non-regular file (a FIFO with no writer, a device, a folder,
//! a socket), brume exits with 2 within seconds, with one `error:` line that
//! names the path (and the scene key) and says what the path is. A FIFO that
//! brume opened would block it forever: the deadline turns that into a
//! failure instead of a stuck suite.

mod common;

use common::cli::run_brume;
use std::os::unix::net::UnixListener;
use std::path::Path;
use std::time::Duration;

const DEADLINE: Duration = Duration::from_secs(20);
const PROMPT: f64 = 5.0;

/// A kind of non-regular file and the word the error must use for it.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Fifo,
    Device,
    Folder,
    Socket,
}

impl Kind {
    const ALL: [Kind; 4] = [Kind::Fifo, Kind::Device, Kind::Folder, Kind::Socket];

    fn word(self) -> &'static str {
        match self {
            Kind::Fifo => "FIFO",
            Kind::Device => "device",
            Kind::Folder => "directory",
            Kind::Socket => "socket",
        }
    }

    /// Makes one at `dir/name` (a device: a link to /dev/zero, so that the
    /// name keeps its extension); returns its path as the user would write
    /// it, and the listener that keeps a socket alive.
    fn make(self, dir: &Path, name: &str) -> (String, Option<UnixListener>) {
        let path = dir.join(name);
        match self {
            Kind::Fifo => {
                let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
                // SAFETY: a valid NUL-terminated path; mkfifo only creates the node.
                assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
                (name.into(), None)
            }
            Kind::Device => {
                std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
                (name.into(), None)
            }
            Kind::Folder => {
                std::fs::create_dir(&path).unwrap();
                (name.into(), None)
            }
            Kind::Socket => (name.into(), Some(UnixListener::bind(&path).unwrap())),
        }
    }
}

/// A role a file plays: the command line, the scene (if any), and the
/// scene key the message must name; `{}` stands for the file.
struct Role {
    name: &'static str,
    args: &'static str,
    scene: &'static str,
    key: &'static str,
}

const HEAD: &str = "[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.5, 0.0]\n\
    resolution = [4, 3]\n[integrator]\nspp = 1\n";
const LIGHT: &str = "[[light]]\ntype = \"point\"\nposition = [0.0, 3.0, 2.0]\nintensity = 20.0\n";

fn roles() -> Vec<Role> {
    let role = |name, args, scene, key| Role {
        name,
        args,
        scene,
        key,
    };
    vec![
        role("scene file", "render {} --out o.exr --png o.png", "", ""),
        role(
            "OBJ mesh",
            "render s.toml --out o.exr --png o.png",
            "[[shape]]\ntype = \"mesh\"\nfile = \"{}\"\n",
            "shape[0].file",
        ),
        role(
            "image texture",
            "render s.toml --out o.exr --png o.png",
            "[[shape]]\ntype = \"quad\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n\
             size = [4.0, 4.0]\nmaterial = { type = \"diffuse\", albedo = { type = \"image\", file = \"{}\" } }\n",
            "shape[0].material.albedo.file",
        ),
        role(
            "environment map",
            "render s.toml --out o.exr --png o.png",
            "[[light]]\ntype = \"environment_map\"\nfile = \"{}\"\n",
            "light[1].file",
        ),
        role(
            "VDB volume",
            "render s.toml --out o.exr --png o.png",
            "[[medium]]\ntype = \"vdb\"\nfile = \"{}\"\n",
            "medium[0].file",
        ),
        role(
            "interior VDB volume",
            "render s.toml --out o.exr --png o.png",
            "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.5, 0.0]\nradius = 0.5\n\
             interior = { type = \"vdb\", file = \"{}\" }\n",
            "shape[0].interior",
        ),
        role("first merge piece", "merge {} good.exr -o m.exr", "", ""),
        role("second merge piece", "merge good.exr {} -o m.exr", "", ""),
        role("compared image A", "compare {} good.exr", "", ""),
        role("reference image B", "compare good.exr {} --diff d.png", "", ""),
        role("VDB for info", "info {}", "", ""),
    ]
}

#[test]
fn every_input_that_is_not_a_regular_file_is_refused_at_once() {
    let mut cases = 0;
    for role in roles() {
        for kind in Kind::ALL {
            let dir = tempfile::tempdir().unwrap();
            let (path, _listener) = kind.make(dir.path(), "culprit.exr");
            let good = brume::film::image_io::Image {
                width: 4,
                height: 3,
                pixels: vec![brume::math::color::Rgb::new(0.5, 0.5, 0.5); 12],
                spp: 1,
                partial: false,
            };
            brume::film::image_io::write_exr(&dir.path().join("good.exr"), &good).unwrap();
            let scene = format!("{HEAD}{LIGHT}{}", role.scene.replace("{}", &path));
            std::fs::write(dir.path().join("s.toml"), scene).unwrap();
            let args: Vec<String> = role
                .args
                .split(' ')
                .map(|a| a.replace("{}", &path))
                .collect();
            let run = run_brume(dir.path(), &args, DEADLINE);
            let what = format!("{} as a {kind:?}: {}", role.name, run.stderr);
            assert_eq!(run.code, Some(2), "{what}");
            assert!(run.seconds < PROMPT, "{what}: took {:.1} s", run.seconds);
            let errors: Vec<&str> = run
                .stderr
                .lines()
                .filter(|l| l.starts_with("error:"))
                .collect();
            assert_eq!(errors.len(), 1, "{what}");
            assert!(errors[0].contains(&path), "path not named: {what}");
            assert!(errors[0].contains(role.key), "key not named: {what}");
            assert!(errors[0].contains(kind.word()), "kind not said: {what}");
            assert!(!run.stderr.contains("panicked"), "{what}");
            cases += 1;
        }
    }
    assert_eq!(cases, roles().len() * Kind::ALL.len());
}

/// A frame of a VDB sequence that is a FIFO is named as what it is (not
/// "missing"), and never opened, whatever `missing_frames` says.
#[test]
fn a_sequence_frame_that_is_a_fifo_is_refused() {
    for missing in ["error", "hold", "repeat"] {
        let dir = tempfile::tempdir().unwrap();
        let (path, _) = Kind::Fifo.make(dir.path(), "v.0001.vdb");
        let scene = format!(
            "{HEAD}{LIGHT}[[medium]]\ntype = \"vdb\"\nfile = \"v.####.vdb\"\n\
             [animation]\nmissing_frames = \"{missing}\"\n"
        );
        std::fs::write(dir.path().join("s.toml"), scene).unwrap();
        let args: Vec<String> = ["render", "s.toml", "--frames", "1"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let run = run_brume(dir.path(), &args, DEADLINE);
        let what = format!("missing_frames = {missing}: {}", run.stderr);
        assert_eq!(run.code, Some(2), "{what}");
        assert!(run.seconds < PROMPT, "{what}");
        assert!(
            run.stderr.contains(&path) && run.stderr.contains("FIFO"),
            "{what}"
        );
    }
}
