//! The path tracer's light samples ask a constant or sky environment beside
//! brighter lights less than its power says (`integrator.environment_share`,
//! `brume::light::environment_share`): the sky is then gathered by the
//! continuation rays alone, with MIS weight 1, and the image's expectation
//! is unchanged.

mod common;

use std::path::Path;

use brume::integrator::Scene;
use brume::math::{Ray, Vec3};
use common::*;

/// Sun (delta, irradiance 4) and a uniform sky (radiance 0.1) over a grey
/// diffuse ground, with an optional medium and `integrator` lines.
fn sunlit_text(integrator: &str, medium: Option<&str>) -> String {
    let text = SceneText::view([0.0, 2.0, 5.0], [0.0, 0.5, 0.0])
        .integrator(&format!("max_depth = 1000\n{integrator}"))
        .sun([-0.5, -0.8, -0.3], 4.0)
        .with("angular_radius = 0.0")
        .environment(0.1)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [400.0, 400.0])
        .with("material = { type = \"diffuse\", albedo = 0.5 }");
    match medium {
        Some(m) => text.medium(m).build(),
        None => text.build(),
    }
}

/// The HG 0.3 smoke-like ball the medium cases use.
const BALL: &str = "type = \"homogeneous\"\nsigma_t = 2.0\nalbedo = 0.9\n\
                    phase = { type = \"hg\", g = 0.3 }\n\
                    bounds = { type = \"sphere\", center = [0.0, 1.0, 0.0], radius = 0.8 }";

/// The scene, its warnings, or its error, for TOML `text`.
fn build(text: &str) -> brume::error::Result<(Scene, Vec<String>)> {
    let file = Path::new("sky.toml");
    let desc = brume::scene::parse(text, file).expect("parse");
    brume::scene::build_with_warnings(&desc, file, Path::new("."))
}

/// A ground lit by a delta sun and a uniform sky has the closed form
/// ρ/π (E cos θ + π L). With the sky left to the BSDF's cosine samples
/// (the default here) every sample is that value exactly: the sun is asked
/// every time and the escaping continuation carries the whole sky. The
/// escapes' MIS weight must count on the sky never being asked (with the
/// pick by power's 0.116 it would lose 1.3 % of the sky). Asking the sky
/// half or 0.9 of the time gives the same mean, with noise.
#[test]
fn a_sunlit_ground_under_a_sky_is_exact_with_the_sky_left_to_the_bsdf() {
    let to_sun = -Vec3::new(-0.5, -0.8, -0.3).normalize();
    let expected = (0.5 / std::f64::consts::PI) * (4.0 * to_sun.y as f64) + 0.5 * 0.1;
    let eye = Vec3::new(0.0, 2.0, 5.0);
    for (target, seed) in [
        (Vec3::new(0.3, 0.0, 1.0), 1),
        (Vec3::new(-2.0, 0.0, -3.0), 2),
    ] {
        let ray = Ray::new(eye, (target - eye).normalize());
        let default = scene_from_str(&sunlit_text("", None));
        let exact = estimate_ray(&default, ray, 20_000, seed);
        assert_estimate(
            &exact,
            [expected; 3],
            &format!("default, toward {target:?}"),
        );
        assert!(
            exact.std_error.iter().all(|&se| se < 1e-6 * expected),
            "the default's samples vary: standard error {:?}",
            exact.std_error
        );
        for share in [0.5, 0.9] {
            let scene = scene_from_str(&sunlit_text(&format!("environment_share = {share}"), None));
            let est = estimate_ray(&scene, ray, 200_000, seed + 10);
            assert_estimate(
                &est,
                [expected; 3],
                &format!("share {share}, toward {target:?}"),
            );
        }
    }
}

/// In a scattering ball over the ground (light samples from medium vertices
/// asking the sky uniformly over the sphere, phase-sampled escapes), the
/// default (the sky never asked), half and 0.9 give the same mean along
/// a ray through the ball's middle, one through its rim and one to the
/// ground in its shadow.
#[test]
fn a_scattering_ball_keeps_its_mean_whatever_the_sky_is_asked() {
    let eye = Vec3::new(0.0, 2.0, 5.0);
    let targets = [
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.6, 1.5, 0.0),
        Vec3::new(0.8, 0.0, 0.5),
    ];
    for (k, target) in targets.into_iter().enumerate() {
        let ray = Ray::new(eye, (target - eye).normalize());
        let seed = 100 + 10 * k as u64;
        let default = estimate_ray(
            &scene_from_str(&sunlit_text("", Some(BALL))),
            ray,
            100_000,
            seed,
        );
        for (j, share) in [0.5, 0.9].into_iter().enumerate() {
            let text = sunlit_text(&format!("environment_share = {share}"), Some(BALL));
            let est = estimate_ray(&scene_from_str(&text), ray, 100_000, seed + 1 + j as u64);
            assert_same(&default, &est, &format!("toward {target:?}, share {share}"));
        }
    }
}

/// The pick itself: a sun brighter than the sky takes every light sample; a
/// sky alone takes them all; a sky far brighter than a small lamp keeps
/// all but the lamp's uniform share; an image map keeps its pick by power; the key fixes the
/// share; bidirectional strategies keep the pick by power.
#[test]
fn the_sky_is_asked_by_the_rule_or_the_key() {
    let sunlit = scene_from_str(&sunlit_text("", None));
    assert_eq!((sunlit.nee_pick.pmf(0), sunlit.nee_pick.pmf(1)), (1.0, 0.0));
    assert!(sunlit.light_pick.pmf(1) > 0.1, "bdpt's pick changed");
    let sky_only = SceneText::view([0.0, 2.0, 5.0], [0.0, 0.5, 0.0])
        .environment(0.1)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [4.0, 4.0])
        .build();
    assert_eq!(scene_from_str(&sky_only).nee_pick.pmf(0), 1.0);
    let lamp = SceneText::view([0.0, 2.0, 5.0], [0.0, 0.5, 0.0])
        .environment(1.0)
        .point_light([0.0, 1.0, 0.0], 0.01)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [4.0, 4.0])
        .build();
    let lamp = scene_from_str(&lamp);
    let sky = lamp.nee_pick.pmf(0);
    assert_eq!(
        sky,
        brume::light::MAX_ENVIRONMENT_SHARE,
        "a sky beside a faint lamp"
    );
    assert!((sky + lamp.nee_pick.pmf(1) - 1.0).abs() < 1e-6);
    let map = sunlit_text("", None).replace(
        "type = \"environment\"\nradiance = 0.1",
        "type = \"environment_map\"\nfile = \"scenes/sky.exr\"",
    );
    assert!(map.contains("environment_map"), "the sky's table moved");
    let map = scene_from_str(&map);
    for i in 0..2 {
        assert_eq!(map.nee_pick.pmf(i), map.light_pick.pmf(i), "light {i}");
    }
    let fixed = scene_from_str(&sunlit_text("environment_share = 0.3", None));
    assert!((fixed.nee_pick.pmf(1) - 0.3).abs() < 1e-6);
    assert!((fixed.nee_pick.pmf(0) - 0.7).abs() < 1e-6);
}

/// The scene `text` builds with a warning about `integrator.environment_share` that says `needle`.
fn assert_key_warns(text: &str, needle: &str, what: &str) {
    let (_, warnings) = build(text).expect("build");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("integrator.environment_share") && w.contains(needle)),
        "{what}: no warning saying {needle:?} in {warnings:?}"
    );
}

/// Out-of-range shares are refused naming the key; a share that can change
/// nothing (no sky; a sky alone; a bidirectional integrator) warns.
#[test]
fn the_key_is_checked_and_warns_where_it_does_nothing() {
    for bad in [
        "environment_share = 1",
        "environment_share = 1.5",
        "environment_share = -0.1",
        "environment_share = nan",
    ] {
        let error = build(&sunlit_text(bad, None))
            .err()
            .unwrap_or_else(|| panic!("{bad} accepted"));
        let message = error.to_string();
        assert!(
            message.contains("integrator.environment_share"),
            "{bad}: {message}"
        );
        assert!(message.contains("sky.toml"), "{bad}: {message}");
    }
    let (_, quiet) = build(&sunlit_text("environment_share = 0.2", None)).expect("build");
    assert!(quiet.is_empty(), "{quiet:?}");
    let sun_only = sunlit_text("environment_share = 0.2", None).replace(
        "type = \"environment\"\nradiance = 0.1",
        "type = \"point\"\nposition = [0, 3, 0]\nintensity = 1",
    );
    assert!(
        !sun_only.contains("\"environment\""),
        "the sky's table moved"
    );
    assert_key_warns(&sun_only, "no effect", "sun_only");
    let sky_alone = SceneText::view([0.0, 2.0, 5.0], [0.0, 0.5, 0.0])
        .integrator("environment_share = 0.2")
        .environment(0.1)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [4.0, 4.0])
        .build();
    assert_key_warns(&sky_alone, "no effect", "sky_alone");
    let bdpt = sunlit_text("type = \"bdpt\"\nenvironment_share = 0.2", None);
    assert_key_warns(&bdpt, "bdpt", "bdpt");
}
