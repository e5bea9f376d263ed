//! `brume slab bake` and `type = "slab"` shapes from the command line: the
//! file depends on the seed only, refusals name the key in the user's words,
//! and a viewed slab agrees with path tracing the same view.

mod common;

use common::cli::{assert_refused, assert_scene_refused, brume};
use std::path::Path;

/// A sphere of scattering, emitting medium under a sky and a point light, with its `[slab]` box.
const BAKE: &str = r#"
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
resolution = [8, 8]
[integrator]
spp = 4
[[light]]
type = "environment"
radiance = 0.5
[[light]]
type = "point"
position = [2, 3, 2]
intensity = 20
[[medium]]
type = "homogeneous"
sigma_a = 0.5
sigma_s = 2.0
emission = [1.0, 0.5, 0.2]
bounds = { type = "sphere", center = [0, 0, 0], radius = 1 }
[slab]
min = [-1.1, -1.1, -1.1]
max = [1.1, 1.1, 1.1]
spatial = 8
angular = 4
"#;

fn bake(dir: &Path, scene: &str, out: &str, extra: &[&str]) -> std::process::Output {
    std::fs::write(dir.join("bake.toml"), scene).unwrap();
    brume()
        .current_dir(dir)
        .args(["slab", "bake", "bake.toml", "--out", out])
        .args(extra)
        .output()
        .unwrap()
}

/// The file is the same bytes with one thread or two, differs with another
/// seed, is as long as the header says, and its size was announced first.
#[test]
fn bake_depends_on_the_seed_only() {
    let dir = tempfile::tempdir().unwrap();
    let one = bake(dir.path(), BAKE, "one.slab", &["--threads", "1"]);
    assert!(
        one.status.success(),
        "{}",
        String::from_utf8_lossy(&one.stderr)
    );
    let stderr = String::from_utf8_lossy(&one.stderr);
    let records = 6 * 8 * 8 * 4 * 4;
    assert!(stderr.contains(&format!("= {records} lines")), "{stderr}");
    let two = bake(dir.path(), BAKE, "two.slab", &["--threads", "2"]);
    assert!(two.status.success());
    let other = bake(dir.path(), BAKE, "other.slab", &["--seed", "9"]);
    assert!(other.status.success());
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("one.slab").len(), 64 + 12 * records);
    assert!(
        read("one.slab") == read("two.slab"),
        "thread count changed the file"
    );
    assert!(
        read("one.slab") != read("other.slab"),
        "the seed changed nothing"
    );
}

/// Bad `[slab]` tables, a missing one and an output that is an input are
/// refused in one line naming the key or flag; the existing file stays.
#[test]
fn bad_bakes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("keep.slab"), b"precious").unwrap();
    let cases: [(String, &[&str], &str); 4] = [
        (
            BAKE.replace("[slab]", "[unused_table]"),
            &["unused_table"],
            "unknown table",
        ),
        (
            BAKE.replace("max = [1.1, 1.1, 1.1]", "max = [1.1, -2, 1.1]"),
            &["slab.max", "y"],
            "max below min",
        ),
        (
            BAKE.replace("spatial = 8", "spatial = 1"),
            &["slab.spatial", "2 to"],
            "one node",
        ),
        (
            BAKE.replace("angular = 4", "angular = 0.5"),
            &["slab.angular"],
            "a fraction",
        ),
    ];
    for (text, culprits, what) in cases {
        let out = bake(dir.path(), &text, "keep.slab", &[]);
        assert_refused(&out, culprits, what);
    }
    let no_table: String = BAKE.split("[slab]").next().unwrap().into();
    let out = bake(dir.path(), &no_table, "keep.slab", &[]);
    assert_refused(&out, &["bake.toml", "slab", "missing"], "no [slab]");
    let out = bake(dir.path(), BAKE, "bake.toml", &[]);
    assert_refused(&out, &["--out", "is an input"], "over the scene");
    assert_eq!(
        std::fs::read(dir.path().join("keep.slab")).unwrap(),
        b"precious"
    );
}

/// A view of `slab` (a file beside it) from `position`.
fn view(position: &str, shape_extra: &str) -> String {
    format!(
        "[camera]\nposition = {position}\nlook_at = [0, 0, 0]\nresolution = [48, 48]\n\
         [integrator]\nspp = 4\n[[light]]\ntype = \"environment\"\nradiance = 0.5\n\
         [[shape]]\ntype = \"slab\"\nfile = \"a.slab\"\n{shape_extra}"
    )
}

/// A camera inside the box, a damaged file, keys a slab does not take and
/// an integrator that cannot show it are refused naming the shape's key.
#[test]
fn bad_slab_shapes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let ok = bake(dir.path(), BAKE, "a.slab", &["--quiet"]);
    assert!(ok.status.success());
    let d = dir.path();
    assert_scene_refused(
        d,
        "v.toml",
        &view("[0.2, 0, 0.5]", ""),
        &[] as &[&str],
        &["shape[0]", "inside"],
        "camera inside",
    );
    assert_scene_refused(
        d,
        "v.toml",
        &view(
            "[0, 0, 5]",
            "material = { type = \"diffuse\", albedo = 0.5 }",
        ),
        &[] as &[&str],
        &["shape[0].material"],
        "material",
    );
    assert_scene_refused(
        d,
        "v.toml",
        &view("[0, 0, 5]", "filter = \"cubic\""),
        &[] as &[&str],
        &["shape[0].filter", "nearest"],
        "filter",
    );
    let bdpt = view("[0, 0, 5]", "").replace("spp = 4", "spp = 4\ntype = \"bdpt\"");
    assert_scene_refused(
        d,
        "v.toml",
        &bdpt,
        &[] as &[&str],
        &["shape[0]", "path"],
        "bdpt",
    );
    let bytes = std::fs::read(d.join("a.slab")).unwrap();
    std::fs::write(d.join("a.slab"), &bytes[..1000]).unwrap();
    assert_scene_refused(
        d,
        "v.toml",
        &view("[0, 0, 5]", ""),
        &[] as &[&str],
        &["shape[0].file", "truncated"],
        "truncated",
    );
}

/// Root mean square difference and mean of two renders.
fn compare(a: &Path, b: &Path) -> (f64, f64, f64) {
    let (_, _, pa) = brume::film::image_io::read_exr(a).unwrap();
    let (_, _, pb) = brume::film::image_io::read_exr(b).unwrap();
    let n = pa.len() as f64;
    let sq: f64 = pa
        .iter()
        .zip(&pb)
        .map(|(x, y)| ((x.average() - y.average()) as f64).powi(2))
        .sum();
    let mean =
        |p: &[brume::math::color::Rgb]| p.iter().map(|x| x.average() as f64).sum::<f64>() / n;
    ((sq / n).sqrt(), mean(&pa), mean(&pb))
}

/// A novel outside view of the baked sphere agrees with path tracing the
/// same view (image mean within 2%), and quadrilinear lookup is closer to
/// it than the nearest record (the seed's figure 13).
#[test]
fn viewed_slab_agrees_with_path_tracing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let baked = BAKE
        .replace("spatial = 8", "spatial = 24")
        .replace("angular = 4", "angular = 8");
    assert!(bake(d, &baked, "a.slab", &["--quiet", "--spp", "16"])
        .status
        .success());
    let eye = "[1.5, 1.0, 4.5]";
    let render = |name: &str, text: &str, spp: &str| {
        std::fs::write(d.join(format!("{name}.toml")), text).unwrap();
        let out = brume()
            .current_dir(d)
            .args([
                "render",
                "--quiet",
                &format!("{name}.toml"),
                "--out",
                &format!("{name}.exr"),
                "--png",
                &format!("{name}.png"),
                "--spp",
                spp,
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let traced = BAKE
        .replace("position = [0, 0, 5]", &format!("position = {eye}"))
        .replace("resolution = [8, 8]", "resolution = [48, 48]");
    render("traced", traced.split("[slab]").next().unwrap(), "256");
    render("quad", &view(eye, ""), "4");
    render("nearest", &view(eye, "filter = \"nearest\""), "4");
    let (rmse_q, mean_q, mean_t) = compare(&d.join("quad.exr"), &d.join("traced.exr"));
    let (rmse_n, _, _) = compare(&d.join("nearest.exr"), &d.join("traced.exr"));
    eprintln!("rmse quadrilinear {rmse_q:.4}, nearest {rmse_n:.4}; mean slab {mean_q:.4}, traced {mean_t:.4}");
    assert!(
        (mean_q / mean_t - 1.0).abs() < 0.02,
        "means {mean_q} vs {mean_t}"
    );
    assert!(
        rmse_q < rmse_n,
        "quadrilinear {rmse_q} not closer than nearest {rmse_n}"
    );
}

/// A stop request (SIGINT) ends a bake within seconds, with exit code 130,
/// and leaves the existing file as it was: a slab of fewer samples is never written.
#[test]
fn a_stopped_bake_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bake.toml"), BAKE).unwrap();
    std::fs::write(dir.path().join("keep.slab"), b"precious").unwrap();
    let child = brume()
        .current_dir(dir.path())
        .args([
            "slab",
            "bake",
            "bake.toml",
            "--out",
            "keep.slab",
            "--spp",
            "100000000",
        ])
        .spawn()
        .unwrap();
    let out = common::cli::signal_and_wait(
        child,
        "INT",
        std::time::Duration::from_millis(800),
        std::time::Duration::from_secs(5),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("nothing written"), "{stderr}");
    assert_eq!(
        std::fs::read(dir.path().join("keep.slab")).unwrap(),
        b"precious"
    );
}
