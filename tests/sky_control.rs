//! The sky as a control variate (`integrator.sky_control`): the same
//! expectation as the plain path tracer for every depth limit, material and
//! medium, under a constant sky, a gradient sky and a smooth map; exactly
//! the sky in a lossless furnace; lower error in a bright fog layer; its
//! key, default and refusals.

mod common;

use brume::math::{Ray, Vec3};
use common::*;
use std::path::Path;

/// An absorbing HG ball (albedo 0.7) over a diffuse ground beside a glass
/// ball and a mirror, under a sun and a blue sky, with `integrator` lines.
fn scene_text(integrator: &str) -> String {
    scene_under(
        integrator,
        "type = \"environment\"\nradiance = [0.3, 0.4, 0.6]",
    )
}

/// [`scene_text`] under the environment light of `environment` lines.
fn scene_under(integrator: &str, environment: &str) -> String {
    SceneText::view([0.0, 1.0, 6.0], [0.0, 1.0, 0.0])
        .integrator(integrator)
        .sun([0.3, -0.8, -0.4], 3.0)
        .light(environment)
        .quad([0.0; 3], [0.0, 1.0, 0.0], [20.0, 20.0])
        .with("material = { type = \"diffuse\", albedo = 0.45 }")
        .sphere([-1.3, 0.8, 0.0], 0.6)
        .with("material = { type = \"dielectric\", ior = 1.5 }")
        .sphere([1.4, 0.7, -0.5], 0.5)
        .with("material = { type = \"mirror\", reflectance = 0.8 }")
        .medium(
            "type = \"homogeneous\"\nsigma_t = 2.0\nalbedo = 0.7\n\
             phase = { type = \"hg\", g = 0.4 }\n\
             bounds = { type = \"sphere\", center = [0.0, 1.2, 0.0], radius = 0.9 }",
        )
        .build()
}

/// `text` without its `[[light]]` of type "sun" (the sky alone).
fn without_the_sun(text: &str) -> String {
    let start = text.find("[[light]]\ntype = \"sun\"").expect("a sun");
    let end = text[start + 1..]
        .find("[[")
        .map_or(text.len(), |i| start + 1 + i);
    format!("{}{}", &text[..start], &text[end..])
}

/// `medium` under a uniform sky of `radiance` alone, seen from z = 4, with `integrator` lines.
fn under_a_sky_alone(integrator: &str, radiance: impl std::fmt::Debug, medium: &str) -> String {
    SceneText::view([0.0, 0.0, 4.0], [0.0; 3])
        .integrator(integrator)
        .environment(radiance)
        .medium(medium)
        .build()
}

/// R(a) = (1 − s)/(1 + s), s = √(1 − a): the share of a light-sampled sky
/// the control books over media of least albedo a (the light a deep medium
/// of albedo a returns).
fn returned_share(a: f32) -> f32 {
    (1.0 - (1.0 - a).sqrt()) / (1.0 + (1.0 - a).sqrt())
}

/// `a` and `b` have the same expectation along the ray from `eye` toward
/// each of `targets`, `n` paths each with seeds `seeds`; `what` names the case.
fn assert_same_toward(
    (a, b): (&brume::integrator::Scene, &brume::integrator::Scene),
    eye: Vec3,
    targets: &[Vec3],
    (n, seeds): (usize, (u64, u64)),
    what: &str,
) {
    for &target in targets {
        let ray = Ray::new(eye, (target - eye).normalize());
        let x = estimate_ray(a, ray, n, seeds.0);
        let y = estimate_ray(b, ray, n, seeds.1);
        assert_same(&x, &y, &format!("{what}, toward {target:?}"));
    }
}

/// The same expectation with the control variate on and off, along rays
/// through the ball, the glass, the mirror and the ground, at the depth
/// limits 0 (emission only), 1, 2 and 64 with roulette from the first
/// event, under the sun and the sky (the sky booked whole) and under the sky
/// alone (a share of it booked, escapes meeting the rest): every throughput change but roulette's is booked as it happens
/// (seen failing by tens of σ with the booking of a path's end left out,
/// and with roulette's changes booked).
#[test]
fn the_control_variate_leaves_the_expectation_at_every_depth() {
    let eye = Vec3::new(0.0, 1.0, 6.0);
    let targets = [
        Vec3::new(0.0, 1.2, 0.0),
        Vec3::new(-1.3, 0.8, 0.0),
        Vec3::new(1.4, 0.7, -0.5),
        Vec3::new(0.5, 0.0, 1.0),
    ];
    for (max_depth, sun) in [0, 1, 2, 64]
        .into_iter()
        .flat_map(|d| [(d, true), (d, false)])
    {
        let lines = format!("max_depth = {max_depth}\nrr_depth = 1");
        let text = |key: &str| {
            let t = scene_text(&format!("{lines}\n{key}"));
            match sun {
                true => t,
                false => without_the_sun(&t),
            }
        };
        let on = scene_from_str(&text("sky_control = true"));
        let off = scene_from_str(&text("sky_control = false"));
        // Under a sky alone the control books less than the sky: escapes meet the rest.
        let booked = on.sky_control.expect("on").r;
        assert!(off.sky_control.is_none());
        assert_eq!(booked < 0.3, !sun, "booked {booked}");
        let what = format!("max_depth {max_depth}, sun {sun}");
        assert_same_toward((&off, &on), eye, &targets, (40_000, (1, 2)), &what);
    }
}

/// A lossless furnace: a white HG ball in a uniform sky of radiance 0.8 is
/// exactly 0.8 along every path with the control variate, every sample
/// (no throughput changes but roulette's, which books nothing).
#[test]
fn a_white_ball_in_a_uniform_sky_is_the_sky_in_every_sample() {
    let text = SceneText::view([0.0, 0.0, 4.0], [0.0; 3])
        .integrator("max_depth = 1000\nrr_depth = 2\nsky_control = true")
        .environment(0.8)
        .medium(
            "type = \"homogeneous\"\nsigma_t = 3.0\nalbedo = 1.0\n\
             phase = { type = \"hg\", g = 0.6 }\n\
             bounds = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }",
        )
        .build();
    let scene = scene_from_str(&text);
    assert!(scene.sky_control.is_some());
    let ray = Ray::new(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::new(0.1, 0.05, -1.0).normalize(),
    );
    let e = estimate_ray(&scene, ray, 2_000, 7);
    for c in 0..3 {
        assert!((e.mean[c] - 0.8).abs() < 1e-5, "channel {c}: {:?}", e.mean);
        assert!(e.std_error[c] < 1e-6, "channel {c}: {:?}", e.std_error);
    }
}

/// In a bright fog layer over a ground (albedo 1, the camera inside, sun
/// and sky: the airlight bench scene's kind), roulette's variance in the sky
/// light is what the control variate takes out: the standard error falls
/// by more than a tenth (0.84× measured along this ray).
#[test]
fn the_control_variate_lowers_the_error_in_a_bright_fog_layer() {
    let text = |on: bool| {
        SceneText::view([0.0, 1.0, 0.0], [0.0, 1.0, -10.0])
            .integrator(&format!("max_depth = 63\nrr_depth = 5\nsky_control = {on}"))
            .sun([0.4, -0.7, -0.6], 2.5)
            .environment([0.35, 0.5, 0.8])
            .quad([0.0; 3], [0.0, 1.0, 0.0], [300.0, 300.0])
            .with("material = { type = \"diffuse\", albedo = 0.4 }")
            .medium(
                "type = \"homogeneous\"\nsigma_t = 0.03\nalbedo = 1.0\n\
                 phase = { type = \"isotropic\" }\n\
                 bounds = { type = \"box\", min = [-150, -1, -150], max = [150, 25, 150] }",
            )
            .build()
    };
    let ray = Ray::new(
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.2, 0.02, -1.0).normalize(),
    );
    let off = estimate_ray(&scene_from_str(&text(false)), ray, 40_000, 3);
    let on = estimate_ray(&scene_from_str(&text(true)), ray, 40_000, 4);
    assert_same(&off, &on, "fog layer");
    assert_lower_error(&on, &off, 0.9, "fog layer");
}

/// Fog over a diffuse ground and a red box, seen from z = 6 under a sun
/// and a blue sky (or the sky alone), with `integrator` lines.
fn fog_over_ground(integrator: &str, medium: &str, sun: bool) -> String {
    let text = SceneText::view([0.0, 1.0, 6.0], [0.0, 0.5, 0.0])
        .integrator(integrator)
        .sun([0.3, -0.8, -0.4], 3.0)
        .environment([0.3, 0.4, 0.6])
        .quad([0.0; 3], [0.0, 1.0, 0.0], [20.0, 20.0])
        .with("material = { type = \"diffuse\", albedo = [0.3, 0.6, 0.45] }")
        .shape(
            "type = \"box\"\ncenter = [1.0, 0.4, -1.0]\nsize = [0.8, 0.8, 0.8]\n\
             material = { type = \"diffuse\", albedo = [0.8, 0.2, 0.2] }",
        )
        .medium(medium)
        .build();
    match sun {
        true => text,
        false => without_the_sun(&text),
    }
}

/// Booking ahead (`integrator::book_surface_ahead`): where a segment aims at
/// a diffuse surface through media of closed-form transmittance, the sky's
/// change there is booked by its expectation before the flight. The same
/// expectation as booking it on arrival, along rays to the ground near and
/// far, to the box and into the fog, at the depth limits 1, 2 and 64 with
/// roulette from the first event, under a sun and a sky and under the sky
/// alone, through a chromatic fog box (spectral tracking changes the
/// throughput on the way: its arrival is booked apart) and a height fog.
/// Seen failing by tens of σ with the arrival's booking left out, with ρ
/// booked in place of ρ − 1, and with a missed surface kept booked.
#[test]
fn booking_the_surface_ahead_keeps_the_expectation() {
    let media = [
        "type = \"homogeneous\"\nsigma_t = [0.5, 0.8, 1.2]\nalbedo = [0.9, 0.7, 0.95]\n\
         phase = { type = \"hg\", g = 0.3 }\n\
         bounds = { type = \"box\", min = [-3.0, -0.5, -3.0], max = [3.0, 2.0, 3.0] }",
        "type = \"height_fog\"\nvisibility = 5.0\nheight = 0.0\nscale_height = 1.5\n\
         albedo = 0.9\nphase = { type = \"isotropic\" }",
    ];
    let eye = Vec3::new(0.0, 1.0, 6.0);
    let targets = [
        Vec3::new(0.5, 0.0, 1.0),
        Vec3::new(-1.0, 0.0, -2.5),
        Vec3::new(1.0, 0.4, -1.0),
        Vec3::new(0.0, 1.5, 0.0),
    ];
    for medium in media {
        for (max_depth, sun) in [1, 2, 64].into_iter().flat_map(|d| [(d, true), (d, false)]) {
            let lines = format!("max_depth = {max_depth}\nrr_depth = 1\nsky_control = true");
            let ahead = scene_from_str(&fog_over_ground(&lines, medium, sun));
            let mut on_arrival = scene_from_str(&fog_over_ground(&lines, medium, sun));
            assert!(ahead.settings.sky_ahead);
            on_arrival.settings.sky_ahead = false;
            let what = format!("{medium:.20}, max_depth {max_depth}, sun {sun}");
            let scenes = (&on_arrival, &ahead);
            assert_same_toward(scenes, eye, &targets, (30_000, (5, 6)), &what);
        }
    }
}

/// In the bright fog layer over a ground (the airlight bench scene's kind),
/// booking the ground's deficit ahead takes the coin of reaching it out of
/// the sky light: along a ray to the ground 40 units away the standard
/// error falls by more than a tenth (0.82× measured).
#[test]
fn booking_the_ground_ahead_lowers_the_error_in_a_fog_layer() {
    let text = SceneText::view([0.0, 1.0, 0.0], [0.0, 1.0, -10.0])
        .integrator("max_depth = 63\nrr_depth = 5")
        .sun([0.4, -0.7, -0.6], 2.5)
        .environment([0.35, 0.5, 0.8])
        .quad([0.0; 3], [0.0, 1.0, 0.0], [300.0, 300.0])
        .with("material = { type = \"diffuse\", albedo = 0.4 }")
        .medium(
            "type = \"homogeneous\"\nsigma_t = 0.03\nalbedo = 1.0\n\
             phase = { type = \"isotropic\" }\n\
             bounds = { type = \"box\", min = [-150, -1, -150], max = [150, 25, 150] }",
        )
        .build();
    let ahead = scene_from_str(&text);
    let mut on_arrival = scene_from_str(&text);
    assert!(ahead.sky_control.is_some() && ahead.settings.sky_ahead);
    on_arrival.settings.sky_ahead = false;
    let ray = Ray::new(
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.1, -1.0, -40.0).normalize(),
    );
    let off = estimate_ray(&on_arrival, ray, 40_000, 7);
    let on = estimate_ray(&ahead, ray, 40_000, 8);
    assert_same(&off, &on, "fog layer's ground");
    assert_lower_error(&on, &off, 0.9, "fog layer's ground");
}

/// A bright cloud-like ball (albedo 0.99, HG 0.8) under a sky alone: the
/// default takes the sky as a control although light samples would ask it,
/// the expectation is the light samples' and the standard error along a
/// ray through the ball falls by more than half (0.09× measured).
#[test]
fn a_bright_ball_under_a_sky_alone_takes_the_control_by_default() {
    let text = |key: &str| {
        under_a_sky_alone(
            &format!("max_depth = 1000\nrr_depth = 5\n{key}"),
            [0.6, 0.7, 0.9],
            "type = \"homogeneous\"\nsigma_t = 4.0\nalbedo = 0.99\n\
             phase = { type = \"hg\", g = 0.8 }\n\
             bounds = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }",
        )
    };
    let auto = scene_from_str(&text(""));
    let off = scene_from_str(&text("sky_control = false"));
    assert!(auto.sky_control.is_some(), "the default");
    let ray = Ray::new(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::new(0.1, 0.05, -1.0).normalize(),
    );
    let sampled = estimate_ray(&off, ray, 20_000, 5);
    let controlled = estimate_ray(&auto, ray, 20_000, 6);
    assert_same(&sampled, &controlled, "bright ball");
    assert_lower_error(&controlled, &sampled, 0.5, "bright ball");
}

/// The albedo the rule reads: per channel σs/σt, 1 where a channel has no
/// extinction; a VDB medium's constant albedo under a sky alone gives the
/// booked share R per channel; a medium that scatters nothing (R = 0) keeps
/// the sky's light samples.
#[test]
fn the_rule_reads_each_mediums_albedo_per_channel() {
    let sky_alone = |medium: &str| under_a_sky_alone("", 0.5, medium);
    let homogeneous = scene_from_str(&sky_alone(
        "type = \"homogeneous\"\nsigma_a = [0.1, 0.0, 1.2]\nsigma_s = [0.9, 0.0, 2.8]\n\
         bounds = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }",
    ));
    let albedo = homogeneous.media[0].constant_albedo().expect("constant");
    assert_eq!([albedo.r, albedo.g, albedo.b], [0.9, 1.0, 0.7]);
    let vdb = scene_from_str(&sky_alone(
        "type = \"vdb\"\nfile = \"volumes/smoke_plume.vdb\"\ndensity_scale = 4.0\n\
         albedo = [0.8, 0.9, 0.99]",
    ));
    let booked = vdb.sky_control.expect("a VDB medium under a sky alone");
    for (b, a) in [(booked.r, 0.8), (booked.g, 0.9), (booked.b, 0.99)] {
        assert!((b - 0.5 * returned_share(a)).abs() < 1e-6, "{booked:?}");
    }
    let absorber = scene_from_str(&sky_alone(
        "type = \"homogeneous\"\nsigma_t = 1.0\nalbedo = 0.0\n\
         bounds = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }",
    ));
    assert!(absorber.sky_control.is_none(), "an absorber");
}

/// The default: on for the path tracer with a constant sky and a medium,
/// booking the sky whole under a brighter sun and the share a deep medium
/// of the least albedo returns where light samples would ask the sky (a
/// sky alone or brighter); off without a medium, with guiding, with
/// `environment_share` or a gradient sky over a black ground; `true` where
/// it cannot apply is refused naming the key.
#[test]
fn the_key_defaults_and_refusals() {
    let fog = "type = \"homogeneous\"\nsigma_t = 0.1\nalbedo = 0.9\n\
               bounds = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }";
    let base = |integrator: &str, env: &str, medium: bool| {
        let t = SceneText::view([0.0, 0.0, 4.0], [0.0; 3])
            .integrator(integrator)
            .sun([0.0, -1.0, 0.0], 10.0)
            .light(env);
        match medium {
            true => t.medium(fog).build(),
            false => t.sphere([0.0; 3], 1.0).build(),
        }
    };
    let constant = "type = \"environment\"\nradiance = 0.25";
    let on = scene_from_str(&base("", constant, true));
    assert_eq!(on.sky_control.map(|s| s.r), Some(0.25));
    let sky_alone = |albedo: f32| {
        let medium = fog.replace("albedo = 0.9", &format!("albedo = {albedo}"));
        under_a_sky_alone("", 0.25, &medium)
    };
    for (what, text, booked) in [
        ("a sky alone", sky_alone(0.9), 0.25 * returned_share(0.9)),
        ("a white medium under a sky alone", sky_alone(1.0), 0.25),
        (
            "a sky brighter than the sun",
            base("", "type = \"environment\"\nradiance = 20.0", true)
                .replace("albedo = 0.9", "albedo = [0.99, 0.97, 0.95]"),
            20.0 * returned_share(0.95),
        ),
    ] {
        let control = scene_from_str(&text).sky_control;
        let least = control.map(|c| c.min_channel());
        assert!(
            least.is_some_and(|b| (b - booked).abs() < 1e-5),
            "{what}: {control:?}"
        );
    }
    for (what, text) in [
        ("no medium", base("", constant, false)),
        ("guiding", base("guiding = true", constant, true)),
        (
            "environment_share",
            base("environment_share = 0.2", constant, true),
        ),
        (
            "a gradient sky",
            base("", "type = \"sky\"\nzenith = 0.5\nhorizon = 0.8", true),
        ),
        ("off", base("sky_control = false", constant, true)),
    ] {
        assert!(scene_from_str(&text).sky_control.is_none(), "{what}");
    }
    for (what, text) in [
        (
            "bdpt",
            base("type = \"bdpt\"\nsky_control = true", constant, true),
        ),
        (
            "a gradient sky",
            base(
                "sky_control = true",
                "type = \"sky\"\nzenith = 0.5\nhorizon = 0.8",
                true,
            ),
        ),
        (
            "guiding",
            base("guiding = true\nsky_control = true", constant, true),
        ),
    ] {
        let err = build_error_from_str(&text, what);
        assert!(err.contains("integrator.sky_control"), "{what}: {err}");
    }
}

/// A gradient sky with a ground (floor 0.1 in red and green, 0.15 in blue).
const GRADIENT: &str = "type = \"sky\"\nzenith = [0.2, 0.3, 0.7]\nhorizon = [0.5, 0.55, 0.6]\nground = [0.1, 0.1, 0.15]";

/// The light lines of `scenes/sky.exr`, a smooth HDR sky (its peak 10 times its average).
fn smooth_map() -> String {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sky.exr");
    format!(
        "type = \"environment_map\"\nfile = {:?}",
        file.display().to_string()
    )
}

/// The light lines of a 32 × 16 map of radiance 0.5 with a sun: one texel
/// of radiance 5000, written into `dir`.
fn map_with_a_sun(dir: &Path) -> String {
    let file = dir.join("sun.exr");
    exr::prelude::write_rgb_file(&file, 32, 16, |x, y| {
        let v = if (x, y) == (8, 4) { 5000.0f32 } else { 0.5 };
        (v, v, v)
    })
    .expect("write the map");
    format!(
        "type = \"environment_map\"\nfile = {:?}",
        file.display().to_string()
    )
}

/// Under a gradient sky and under a smooth map the control keeps the
/// light samples' expectation, booking at most the environment's floor
/// (escapes meet L(ω) − U′ ≥ 0), at depth limits 1, 2 and 64 with roulette
/// from the first event, with and without the sun.
#[test]
fn the_control_keeps_the_expectation_under_a_gradient_sky_and_a_map() {
    let eye = Vec3::new(0.0, 1.0, 6.0);
    let targets = [Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.5, 0.0, 1.0)];
    for environment in [GRADIENT.to_string(), smooth_map()] {
        for (max_depth, sun) in [1, 2, 64].into_iter().flat_map(|d| [(d, true), (d, false)]) {
            let text = |key: &str| {
                let t = scene_under(
                    &format!("max_depth = {max_depth}\nrr_depth = 1\n{key}"),
                    &environment,
                );
                match sun {
                    true => t,
                    false => without_the_sun(&t),
                }
            };
            let on = scene_from_str(&text(""));
            let off = scene_from_str(&text("sky_control = false"));
            let booked = on.sky_control.expect("on by default");
            let light = on
                .lights
                .iter()
                .find(|l| l.is_environment())
                .expect("an environment");
            let (floor, _) = light
                .smooth_environment()
                .expect("environment")
                .expect("smooth");
            assert!(
                (floor - booked).min_channel() >= 0.0,
                "booked {booked:?} above the floor {floor:?}"
            );
            let what = format!("{environment}: max_depth {max_depth}, sun {sun}");
            assert_same_toward((&off, &on), eye, &targets, (40_000, (1, 2)), &what);
        }
    }
}

/// What the control books under a gradient sky and a map: the floor (the
/// least radiance of any direction) under a brighter sun, the least of the
/// floor and R(a)·average under the environment alone; the environment's
/// light samples go (a map's too, which otherwise keeps its share by
/// power); a floor below a fifth of the average (a black ground), a map
/// with a sun in it (its peak over its average, whatever its scale) keep
/// their light samples, and `true` is refused there saying why.
#[test]
fn the_rule_books_the_floor_of_a_gradient_sky_or_a_smooth_map() {
    let fog = "type = \"homogeneous\"\nsigma_t = 0.1\nalbedo = 0.9\n\
               bounds = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }";
    let scene = |integrator: &str, environment: &str, sun: bool| {
        let t = SceneText::view([0.0, 0.0, 4.0], [0.0; 3]).integrator(integrator);
        let t = match sun {
            true => t.sun([0.0, -1.0, 0.0], 20.0),
            false => t,
        };
        t.light(environment).medium(fog).build()
    };
    let under_the_sun = scene_from_str(&scene("", GRADIENT, true));
    let booked = under_the_sun
        .sky_control
        .expect("a gradient sky under a sun");
    assert_eq!([booked.r, booked.g, booked.b], [0.1, 0.1, 0.15]);
    let alone = scene_from_str(&scene("", GRADIENT, false));
    let booked = alone.sky_control.expect("a gradient sky alone");
    let env = brume::light::Environment::Sky {
        zenith: brume::math::color::Rgb::new(0.2, 0.3, 0.7),
        horizon: brume::math::color::Rgb::new(0.5, 0.55, 0.6),
        ground: brume::math::color::Rgb::new(0.1, 0.1, 0.15),
        up: Vec3::Y,
    };
    let average = env.average() * returned_share(0.9);
    let expected = [
        0.1f32.min(average.r),
        0.1f32.min(average.g),
        0.15f32.min(average.b),
    ];
    assert_eq!(
        [booked.r, booked.g, booked.b],
        expected,
        "average {average:?}"
    );
    let map = scene_from_str(&scene("", &smooth_map(), true));
    let index = map
        .lights
        .iter()
        .position(|l| l.is_environment())
        .expect("the map");
    assert!(map.sky_control.is_some(), "a smooth map");
    assert_eq!(map.nee_pick.pmf(index), 0.0, "the map's light samples");
    // Smoothness is the peak over the average: a bright smooth map is as smooth.
    let bright = format!("{}\nscale = 100.0", smooth_map());
    assert!(
        scene_from_str(&scene("", &bright, false))
            .sky_control
            .is_some(),
        "a bright smooth map"
    );
    let dir = tempfile::tempdir().expect("temporary folder");
    let black_ground = GRADIENT.replace("ground = [0.1, 0.1, 0.15]", "ground = 0.0");
    for (what, environment, why) in [
        ("a black ground", black_ground, "least radiance"),
        (
            "a sun in the map",
            map_with_a_sun(dir.path()),
            "brightest texel",
        ),
    ] {
        assert!(
            scene_from_str(&scene("", &environment, false))
                .sky_control
                .is_none(),
            "{what}"
        );
        let err = build_error_from_str(&scene("sky_control = true", &environment, false), what);
        assert!(
            err.contains("integrator.sky_control") && err.contains(why),
            "{what}: {err}"
        );
    }
}
