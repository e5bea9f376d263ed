//! `camera.pixel_filter`: a Gaussian pixel filter (Mitsuba's default
//! reconstruction filter, which its importer sets) against the closed form
//! of an edge, and its keys' errors.

mod common;

use common::stats::assert_estimate;
use common::{estimate_pixels, scene_from_str};

/// An 8 × 1 image, 90° wide, of an emitting quad (radiance 1) that fills
/// the image's left half exactly (from the image's left edge to the
/// boundary between pixels 3 and 4) in front of nothing.
fn edge_scene(filter: &str) -> String {
    format!(
        r#"[camera]
position = [0.0, 0.0, 1.0]
look_at = [0.0, 0.0, 0.0]
fov = 90.0
fov_axis = "x"
resolution = [8, 1]
{filter}
[integrator]
max_depth = 0
[[shape]]
type = "quad"
center = [-0.5, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
size = [1.0, 10.0]
emission = 1.0
"#
    )
}

/// The windowed Gaussian of `stddev` pixels (radius 4·stddev), f(x) =
/// exp(−x²/2σ²) − exp(−r²/2σ²), integrated over film x from `lo` to `hi`
/// (pixels from the centre), by the midpoint rule.
fn filter_integral(stddev: f64, lo: f64, hi: f64) -> f64 {
    let r = 4.0 * stddev;
    let (lo, hi) = (lo.max(-r), hi.min(r));
    if hi <= lo {
        return 0.0;
    }
    let n = 100_000;
    let h = (hi - lo) / n as f64;
    let bias = (-r * r / (2.0 * stddev * stddev)).exp();
    (0..n)
        .map(|k| {
            let x = lo + (k as f64 + 0.5) * h;
            (-x * x / (2.0 * stddev * stddev)).exp() - bias
        })
        .sum::<f64>()
        * h
}

/// Pixel x sees the filter around its centre x + ½, restricted to the image
/// [0, 8), as a film that splats uniform samples with filter weights sees
/// it: the lit share is ∫ over [0, 4) of the filter over its integral over
/// [0, 8) (film x maps linearly onto the quad's plane). Seen failing with a
/// box filter (pixel 4 black) and with the filter not restricted to the
/// image (pixel 0 at 0.84: its rays beyond the left edge see nothing).
#[test]
fn a_gaussian_filter_blurs_an_edge_as_its_closed_form() {
    for stddev in [0.5f64, 0.8] {
        let scene = scene_from_str(&edge_scene(&format!(
            "pixel_filter = {{ type = \"gaussian\", stddev = {stddev} }}"
        )));
        let pixels = estimate_pixels(&scene, 40_000);
        for (x, estimate) in pixels.iter().enumerate() {
            let c = x as f64 + 0.5;
            let lit = filter_integral(stddev, -c, 4.0 - c);
            let all = filter_integral(stddev, -c, 8.0 - c);
            let want = lit / all;
            assert_estimate(estimate, [want; 3], &format!("σ {stddev}, pixel {x}"));
        }
    }
}

/// The box filter (default) keeps each pixel to its own square.
#[test]
fn the_box_filter_keeps_an_edge_sharp() {
    let scene = scene_from_str(&edge_scene("pixel_filter = { type = \"box\" }"));
    let pixels = estimate_pixels(&scene, 1000);
    for (x, estimate) in pixels.iter().enumerate() {
        let want = if x < 4 { 1.0 } else { 0.0 };
        assert!(
            (estimate.mean[0] - want).abs() < 1e-6,
            "pixel {x}: {:?}",
            estimate.mean
        );
    }
}

/// Bad filter keys name the key, in one line.
#[test]
fn bad_pixel_filters_name_their_key() {
    for (filter, integrator, want) in [
        ("{ type = \"tent\" }", "path", "camera.pixel_filter.type"),
        (
            "{ type = \"box\", stddev = 0.5 }",
            "path",
            "camera.pixel_filter.stddev",
        ),
        (
            "{ type = \"gaussian\", stddev = -1.0 }",
            "path",
            "camera.pixel_filter.stddev",
        ),
        ("{ type = \"gaussian\", width = 2.0 }", "path", "width"),
        ("{ type = \"gaussian\" }", "bdpt", "path tracer only"),
    ] {
        let text = edge_scene(&format!("pixel_filter = {filter}")).replace(
            "max_depth = 0",
            &format!("max_depth = 2\ntype = \"{integrator}\""),
        );
        let file = std::path::Path::new("edge.toml");
        let error = match brume::scene::parse(&text, file) {
            Err(e) => e.to_string(),
            Ok(desc) => match brume::scene::build(&desc, file, std::path::Path::new(".")) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{filter} under {integrator}: accepted"),
            },
        };
        assert!(
            error.contains(want) && !error.contains('\n'),
            "{filter}: {error}"
        );
    }
}
