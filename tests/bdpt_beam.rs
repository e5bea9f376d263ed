//! A spotlight reflected by a mirror into homogeneous fog: the reflected
//! beam is light the path tracer cannot sample (a point light seen only
//! through a Dirac BSDF), which bidirectional path tracing finds by light
//! tracing. Its in-beam radiance matches a quadrature of single scattering
//! of the spot's mirror image: a spot at the reflected position, aimed along
//! the reflected axis, dimmed by the mirror's reflectance, whose light
//! travels the same distances as the real light through the mirror.
//!
//! The fog fills a box beside the spot that its direct cone does not
//! reach, and paths have at most two scattering events (the mirror and one
//! in the fog), so single scattering of the reflected beam is the whole
//! image. (`max_scatter_depth = 1` would not do: the path tracer allows no
//! surface event after its last medium event, counted from the camera.)

mod bdpt_support;
mod beam_support;

use bdpt_support::*;
use beam_support::*;

/// The reflected beam: BDPT (light tracing alone can sample it) matches the
/// quadrature; the path tracer sees nothing there.
#[test]
fn mirrored_spot_beam_matches_quadrature() {
    let (coarse, fine) = (pixel(8, 2), pixel(16, 4));
    assert!(
        (coarse - fine).abs() <= 1e-7 * fine,
        "quadrature: {coarse} vs {fine}"
    );
    let expected = INTENSITY.map(|i| i * fine);
    let scene = scene_from_str(&scene(""));
    let bdpt = bdpt_pixels(&scene, 1_000_000);
    eprintln!(
        "bdpt {:?} ± {:?}, quadrature {expected:?}",
        bdpt[0].mean, bdpt[0].std_error
    );
    assert_estimate(&bdpt[0], expected, "reflected beam");
    let path = estimate_pixels(&scene, 20_000);
    assert_eq!(
        path[0].mean, [0.0; 3],
        "the path tracer cannot sample a point light in a mirror"
    );
}
