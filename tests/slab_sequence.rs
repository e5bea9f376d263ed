//! A slab viewed along a camera orbit in one `brume render --frames`
//! process: the sequence keeps the slab file between frames
//! (`scene::InputCache`), and must render exactly what separate processes
//! render; `animation.keyframe_time = "absolute"` moves the camera across
//! frames.

mod common;

use brume::geometry::slab::{Grid, LightSlab, Param, SlabHeader};
use brume::math::color::Rgb;
use brume::math::{Bounds3, Vec3};
use common::cli::brume;
use std::path::Path;

/// A slab over the unit box whose radiance varies with the line (so a view
/// changes as the camera turns) and whose transmittance is one half.
fn write_slab(path: &Path) {
    let header = SlabHeader {
        bounds: Bounds3::new(Vec3::splat(-0.5), Vec3::splat(0.5)),
        grid: Grid {
            spatial: 6,
            angular: 3,
        },
        spp: 1,
        seed: 0,
    };
    let param = Param::new(header.bounds, header.grid);
    let (slab, _) = LightSlab::from_records(header, |i| {
        let (p, d) = param.line(i);
        let l = Rgb::new(0.5 + 0.4 * d.x, 0.5 + 0.3 * p.y, 0.4 + 0.2 * d.z);
        (l, Rgb::splat(0.5))
    });
    let mut f = std::fs::File::create(path).unwrap();
    slab.write_to(&mut f).unwrap();
}

/// A camera orbiting the slab: a quarter turn about +y over frames 0 to 4,
/// key times counted as frame numbers.
const ORBIT: &str = "[camera]\nposition = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\
    resolution = [24, 24]\n\
    transform = { keyframes = [{ time = 0.0 }, { time = 4.0, rotate = [0.0, 90.0, 0.0] }] }\n\
    [animation]\nkeyframe_time = \"absolute\"\n\
    [integrator]\nspp = 2\n[[light]]\ntype = \"environment\"\nradiance = 0.25\n\
    [[shape]]\ntype = \"slab\"\nfile = \"orbit.slab\"\n";

fn render(dir: &Path, args: &[&str]) {
    let out = brume()
        .current_dir(dir)
        .args(["render", "--quiet", "orbit.toml"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The film of `name` in `dir`: pixel bits and the scene hash.
fn film(dir: &Path, name: &str) -> (Vec<[u32; 3]>, u64) {
    let path = dir.join(name);
    let (_, _, px) = brume::film::image_io::read_exr(&path).unwrap();
    let bits = px
        .iter()
        .map(|c| [c.r.to_bits(), c.g.to_bits(), c.b.to_bits()])
        .collect();
    let hash = brume::film::image_io::read_film_exr(&path)
        .unwrap()
        .provenance
        .scene_hash;
    (bits, hash)
}

/// Frames 1 and 2 rendered in one process (the slab read once, its digest
/// computed once) are bit for bit the frames rendered by two processes,
/// with the same scene hashes; the orbit moves, so the two frames differ.
#[test]
fn a_sequence_renders_what_separate_processes_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_slab(&d.join("orbit.slab"));
    std::fs::write(d.join("orbit.toml"), ORBIT).unwrap();
    render(
        d,
        &[
            "--frames",
            "1-2",
            "--out",
            "seq.####.exr",
            "--png",
            "seq.####.png",
        ],
    );
    for f in ["1", "2"] {
        let out = format!("one.{f}.exr");
        render(
            d,
            &[
                "--frames",
                f,
                "--out",
                &out,
                "--png",
                &format!("one.{f}.png"),
            ],
        );
    }
    let (seq1, seq2) = (film(d, "seq.0001.exr"), film(d, "seq.0002.exr"));
    assert!(
        seq1 == film(d, "one.1.exr"),
        "frame 1 differs from its own process"
    );
    assert!(
        seq2 == film(d, "one.2.exr"),
        "frame 2 differs from its own process"
    );
    assert_ne!(seq1.0, seq2.0, "the camera did not move between frames");
}

/// Frame 2 of the orbit (an eighth of a turn) is the still view from the
/// camera position turned by 45°, up to f32 rounding of the rotation; frame 0
/// is the unturned view.
#[test]
fn absolute_keyframe_times_are_frame_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_slab(&d.join("orbit.slab"));
    std::fs::write(d.join("orbit.toml"), ORBIT).unwrap();
    render(d, &["--frames", "2", "--out", "f2.exr", "--png", "f2.png"]);
    let s = std::f32::consts::FRAC_1_SQRT_2 * 3.0;
    let still = ORBIT
        .replace("position = [0.0, 0.6, 3.0]", &format!("position = [{s}, 0.6, {s}]"))
        .replace("transform = { keyframes = [{ time = 0.0 }, { time = 4.0, rotate = [0.0, 90.0, 0.0] }] }\n", "");
    assert_ne!(still, ORBIT);
    std::fs::write(d.join("still.toml"), still).unwrap();
    let out = brume()
        .current_dir(d)
        .args([
            "render",
            "--quiet",
            "still.toml",
            "--out",
            "still.exr",
            "--png",
            "still.png",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let read = |n: &str| brume::film::image_io::read_exr(&d.join(n)).unwrap().2;
    let (f2, still) = (read("f2.exr"), read("still.exr"));
    let max_diff = |a: &[Rgb], b: &[Rgb]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| {
                (x.r - y.r)
                    .abs()
                    .max((x.g - y.g).abs())
                    .max((x.b - y.b).abs())
            })
            .fold(0.0f32, f32::max)
    };
    let turned = max_diff(&f2, &still);
    assert!(
        turned < 1e-3,
        "frame 2 vs the still at 45°: max difference {turned}"
    );
    render(d, &["--frames", "0", "--out", "f0.exr", "--png", "f0.png"]);
    let unturned = max_diff(&read("f0.exr"), &still);
    assert!(
        unturned > 0.05,
        "frame 0 vs the still at 45°: max difference {unturned}"
    );
}
