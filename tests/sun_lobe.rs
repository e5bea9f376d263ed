//! Sun-lobe sampling (`integrator.sun_lobe`): a share of the first medium
//! scatterings' continuations drawn toward the sun leaves the image's
//! expectation unchanged and, in a strongly forward medium, lowers its
//! error; its key and default.

mod common;

use brume::integrator::sun_lobe::{SunLobe, DEFAULT_SHARE};
use brume::math::{Ray, Vec3};
use common::*;

/// A forward-scattering (HG 0.8) ball, nearly white, backlit by the sun (a
/// disk of the default size) under a blue sky, over a grey ground.
fn ball_text(integrator: &str) -> String {
    SceneText::view([0.0, 0.5, 6.0], [0.0, 1.0, 0.0])
        .integrator(&format!("max_depth = 1000\n{integrator}"))
        .sun([0.2, -0.5, 0.8], 3.0)
        .environment([0.2, 0.3, 0.5])
        .quad([0.0; 3], [0.0, 1.0, 0.0], [20.0, 20.0])
        .with("material = { type = \"diffuse\", albedo = 0.4 }")
        .medium(
            "type = \"homogeneous\"\nsigma_t = 3.0\nalbedo = 0.98\n\
             phase = { type = \"hg\", g = 0.8 }\n\
             bounds = { type = \"sphere\", center = [0.0, 1.2, 0.0], radius = 1.0 }",
        )
        .build()
}

/// The same expectation with no lobe, the default share and the largest one
/// (whose bias, if the mixture's density were wrong anywhere, is largest),
/// along a ray through the ball's middle and one through its rim, under the
/// sun's disk (whose light samples and phase-sampled hits weigh each other
/// by the mixture's density) and a delta sun; the default's standard error
/// is the lower in each case.
#[test]
fn the_lobe_leaves_the_expectation_and_lowers_the_error_in_a_forward_ball() {
    let eye = Vec3::new(0.0, 0.5, 6.0);
    let cases = [Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.7, 1.8, 0.0)]
        .into_iter()
        .flat_map(|target| [(target, false), (target, true)]);
    for (target, delta) in cases {
        let ray = Ray::new(eye, (target - eye).normalize());
        let scene = |integrator: &str| {
            let text = ball_text(integrator);
            scene_from_str(&match delta {
                true => text.replace("type = \"sun\"", "type = \"sun\"\nangular_radius = 0.0"),
                false => text,
            })
        };
        let what = format!("toward {target:?}, delta sun {delta}");
        let plain = estimate_ray(&scene("sun_lobe = 0.0"), ray, 100_000, 1);
        let default = scene("");
        assert!(default.settings.sun_lobe.is_some());
        let lobe = estimate_ray(&default, ray, 100_000, 2);
        let widest = estimate_ray(&scene("sun_lobe = 0.5"), ray, 100_000, 3);
        assert_same(&plain, &lobe, &format!("{what}, default share"));
        assert_same(&plain, &widest, &format!("{what}, share 0.5"));
        assert_lower_error(&lobe, &plain, 1.0, &what);
    }
}

/// A white furnace: a non-absorbing HG 0.8 ball in a uniform sky of
/// radiance 1, with a faint sun that only aims the lobe, is exactly 1 with
/// the largest share. The sky seen through the lobe's directions is counted
/// once only if its light samples and its phase-sampled escapes weigh each
/// other by the mixture's density (seen failing by 8 σ with the light
/// samples weighed by the phase density alone).
#[test]
fn a_white_ball_in_a_uniform_sky_stays_one_with_the_widest_lobe() {
    let eye = Vec3::new(0.0, 0.5, 6.0);
    let text = SceneText::view([0.0, 0.5, 6.0], [0.0, 1.0, 0.0])
        .integrator("max_depth = 1000\nsun_lobe = 0.5")
        .sun([0.2, -0.5, 0.8], 1e-6)
        .environment(1.0)
        .medium(
            "type = \"homogeneous\"\nsigma_t = 1.0\nalbedo = 1.0\n\
             phase = { type = \"hg\", g = 0.8 }\n\
             bounds = { type = \"sphere\", center = [0.0, 1.2, 0.0], radius = 1.0 }",
        )
        .build();
    let scene = scene_from_str(&text);
    assert!(scene.settings.sun_lobe.is_some());
    for target in [Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.7, 1.8, 0.0)] {
        let ray = Ray::new(eye, (target - eye).normalize());
        let est = estimate_ray(&scene, ray, 1_000_000, 4);
        assert_estimate(&est, [1.0; 3], &format!("toward {target:?}"));
    }
}

/// On by default under a sun (with or without a disk); off without one or
/// with the key at 0; out-of-range shares are refused naming the key.
#[test]
fn the_lobe_aims_at_the_sun_by_default() {
    let with_sun = scene_from_str(&ball_text(""));
    let lobe = with_sun.settings.sun_lobe.expect("a lobe under a sun");
    assert_eq!(lobe.share, DEFAULT_SHARE);
    assert!((lobe.to_sun - Vec3::new(-0.2, 0.5, -0.8).normalize()).length() < 1e-5);
    let no_sun = SceneText::view([0.0, 0.5, 6.0], [0.0, 1.0, 0.0])
        .environment(1.0)
        .medium("type = \"homogeneous\"\nsigma_t = 1.0\nphase = { type = \"hg\", g = 0.8 }\nglobal = true")
        .build();
    assert_eq!(scene_from_str(&no_sun).settings.sun_lobe, None);
    let disk = ball_text("").replace("type = \"sun\"", "type = \"sun\"\nangular_radius = 0.5");
    assert_ne!(disk, ball_text(""), "the sun's table moved");
    assert_eq!(scene_from_str(&disk).settings.sun_lobe, Some(lobe));
    let off = scene_from_str(&ball_text("sun_lobe = 0"));
    assert_eq!(off.settings.sun_lobe, None::<SunLobe>);
    for bad in ["sun_lobe = 0.8", "sun_lobe = -0.1", "sun_lobe = nan"] {
        let text = ball_text(bad);
        let file = std::path::Path::new("ball.toml");
        let desc = brume::scene::parse(&text, file).expect("parse");
        let error = brume::scene::build(&desc, file, std::path::Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("{bad} accepted"));
        assert!(
            error.to_string().contains("integrator.sun_lobe"),
            "{bad}: {error}"
        );
    }
}
