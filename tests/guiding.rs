//! Path guiding (`integrator::guiding`, issue 35): the learned directional
//! distribution is a density that its sampler follows, the mixture with the
//! phase function keeps its pdf, guided renders keep the closed forms of the
//! furnaces and agree with unguided ones on a lit VDB scene, and a guided
//! render is the same image on 1 and 2 threads.

mod common;

use brume::integrator::guiding::dtree::{square_to_dir, DTree};
use brume::integrator::guiding::{
    bsdf_fraction, mixture_pdf, phase_fraction, sample_bsdf, sample_phase, GuidedPathTracer,
};
use brume::integrator::Scene;
use brume::material::{Material, Shading};
use brume::math::color::Rgb;
use brume::math::{Vec2, Vec3};
use brume::medium::PhaseFunction;
use brume::render::{render, train_guide, RenderOptions};
use brume::sampling::chi2::{Chi2Result, SphereChi2};
use brume::sampling::Sampler;
use common::scene_text::{vdb_box_medium, SceneText, VDB_BOX_FURNACES};
use common::*;
use std::sync::atomic::AtomicBool;

const ALPHA: f64 = 0.01;
/// The quadtree alone and its mixture with a phase function.
const CHI2_TEST_COUNT: usize = 2;

/// A quadtree trained like the guide's leaves (three rounds of deposit and
/// refinement) on directions from HG(0.7) about a tilted axis plus a
/// uniform floor: a density ∝ that mixture, piecewise constant.
fn trained_tree() -> DTree {
    let axis = Vec3::new(0.3, -0.6, 0.7).normalize();
    let hg = PhaseFunction::HenyeyGreenstein { g: 0.7 };
    let mut sampler = Sampler::from_seed(17);
    let mut tree = DTree::default();
    for round in 0..3 {
        let mut building = tree.refined(10_000);
        if round == 0 {
            building = DTree::default();
        }
        for _ in 0..20_000 {
            let d = hg.sample(axis, sampler.next_2d()).unwrap().direction;
            building.deposit(d, 1.0);
            let u = square_to_dir(sampler.next_2d());
            building.deposit(u, 0.2);
        }
        tree = building;
    }
    tree
}

fn assert_passes(name: &str, result: &Chi2Result) {
    assert!(result.passes(ALPHA, CHI2_TEST_COUNT), "{name}: {result}");
    assert_eq!(result.invalid_count, 0, "{name}: {result}");
}

/// The quadtree's pdf integrates to 1 over the sphere (exactly: a grid of
/// cell centres finer than its deepest level) and its sampler follows it (χ²).
#[test]
fn quadtree_pdf_integrates_to_one_and_matches_its_sampling() {
    let tree = trained_tree();
    assert!(
        tree.node_count() > 20,
        "a refined tree: {}",
        tree.node_count()
    );
    let n = 4096;
    let mut integral = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let p = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            integral += tree.pdf(square_to_dir(p)) as f64;
        }
    }
    integral *= 4.0 * std::f64::consts::PI / (n * n) as f64;
    assert!((integral - 1.0).abs() < 1e-4, "∫ pdf = {integral}");
    let result = SphereChi2::new(200_000, 3).run(|u| tree.sample(u), |d| tree.pdf(d));
    assert_passes("quadtree", &result);
}

/// The one-sample mixture of the quadtree and HG(0.5): directions follow the
/// mixture pdf α·p_guide + (1 − α)·p_phase, which integrates to 1, and the
/// weight is phase/mixture pdf.
#[test]
fn phase_mixture_follows_its_pdf() {
    let tree = trained_tree();
    let phase = PhaseFunction::HenyeyGreenstein { g: 0.5 };
    let alpha = phase_fraction(&phase);
    assert_eq!(alpha, 0.25);
    let dir_in = Vec3::new(-0.2, 0.9, 0.1).normalize();
    let mut select = Sampler::from_seed(99);
    let result = SphereChi2::new(200_000, 5).run(
        |u| {
            let s = sample_phase(&tree, &phase, dir_in, select.next_1d(), u)?;
            let expected = phase.eval(dir_in, s.dir)
                / mixture_pdf(&tree, alpha, s.dir, phase.pdf(dir_in, s.dir));
            assert!((s.weight.r - expected).abs() <= 1e-5 * expected, "weight");
            Some(s.dir)
        },
        |d| mixture_pdf(&tree, alpha, d, phase.pdf(dir_in, d)),
    );
    assert_passes("phase mixture", &result);
}

/// At a diffuse surface the mixture's weight is f·cos over the mixture pdf,
/// and directions under the surface end the path (f = 0) instead of counting.
#[test]
fn bsdf_mixture_weight_is_value_over_mixture_pdf() {
    let tree = trained_tree();
    let material = Material::Diffuse {
        albedo: Rgb::new(0.8, 0.5, 0.2),
    };
    let n = Vec3::new(0.0, 0.0, 1.0);
    let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
    let shading = Shading::facing(n, wo);
    let alpha = bsdf_fraction(&material);
    let mut sampler = Sampler::from_seed(4);
    let (mut some, mut none) = (0, 0);
    for _ in 0..2000 {
        let numbers = (sampler.next_1d(), sampler.next_2d(), sampler.next_1d());
        match sample_bsdf(&tree, &material, &shading, wo, numbers) {
            Some(s) => {
                some += 1;
                let pdf = mixture_pdf(&tree, alpha, s.dir, material.pdf(&shading, wo, s.dir));
                let f = material.eval(&shading, wo, s.dir);
                assert!((s.pdf - pdf).abs() <= 1e-6 * pdf);
                assert!((s.weight.g - f.g / pdf).abs() <= 1e-5 * s.weight.g);
                assert!(s.dir.dot(n) > 0.0);
            }
            None => none += 1,
        }
    }
    assert!(
        some > 1000 && none > 0,
        "{some} kept, {none} under the surface"
    );
}

/// Per-pixel estimates of a guided render: the guide trained as a render trains it.
fn guided_pixels(scene: &Scene, spp: u32) -> Vec<Estimate> {
    let guide = train_guide(scene, &AtomicBool::new(false)).expect("not cancelled");
    assert!(guide.iterations() > 0 && guide.size().1 > 0);
    let tracer = GuidedPathTracer { guide: &guide };
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let mut acc = Accumulator::default();
            for s in 0..spp {
                acc.add(tracer.pixel_sample(scene, x, y, s));
            }
            out.push(acc.estimate());
        }
    }
    out
}

/// Albedo-1 media (thick isotropic, HG 0.8) and VDB boxes in an environment
/// of 1: every guided pixel is still 1 (the mixture's weights and pdfs).
#[test]
fn guided_white_furnaces_stay_at_one() {
    for phase in ["{ type = \"isotropic\" }", "{ type = \"hg\", g = 0.8 }"] {
        let medium = format!(
            "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 4.0\nalbedo = 1.0\nphase = {phase}\nbounds = {{ type = \"sphere\", radius = 1.0 }}\n"
        );
        let scene = scene_from_str(&furnace_scene(&medium, 1.0));
        let pixels = guided_pixels(&scene, 512);
        assert_pixels_equal(&pixels, [1.0; 3], &format!("guided white furnace {phase}"));
    }
    let scene = scene_from_str(&furnace_scene(&vdb_box_medium(VDB_BOX_FURNACES[0]), 1.0));
    let pixels = guided_pixels(&scene, 512);
    assert_pixels_equal(&pixels, [1.0; 3], "guided white furnace vdb");
}

/// A closed room of emissive walls (radiance 1) around a white diffuse
/// sphere and a white medium, lit also by two small emitters of 1: every
/// guided pixel is 1. Pins the mixture pdf in the MIS weights of both
/// emitter hits and next-event estimation.
#[test]
fn guided_emissive_room_furnace_is_one() {
    let wall = |c: [f32; 3], n: [f32; 3]| {
        format!("[[shape]]\ntype = \"quad\"\ncenter = {c:?}\nnormal = {n:?}\nsize = [6.0, 6.0]\nemission = 1.0\nmaterial = {{ type = \"diffuse\", albedo = 0.0 }}\n")
    };
    let mut text = SceneText::camera([0.0, 0.0, 2.5], [0.0; 3], [6, 6])
        .fov(60.0)
        .depths(1000, 1000)
        .build();
    for (c, n) in [
        ([3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([0.0, 3.0, 0.0], [0.0, -1.0, 0.0]),
        ([0.0, -3.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, 3.0], [0.0, 0.0, -1.0]),
        ([0.0, 0.0, -3.0], [0.0, 0.0, 1.0]),
    ] {
        text += &wall(c, n);
    }
    text += "[[shape]]\ntype = \"sphere\"\ncenter = [0.0, -0.3, 0.0]\nradius = 0.8\nmaterial = { type = \"diffuse\", albedo = 1.0 }\n";
    text += "[[shape]]\ntype = \"sphere\"\ncenter = [1.5, 1.5, -1.0]\nradius = 0.2\nemission = 1.0\nmaterial = { type = \"diffuse\", albedo = 0.0 }\n";
    text += "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 0.7\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.5 }\nbounds = { type = \"box\", min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }\n";
    let scene = scene_from_str(&text);
    let pixels = guided_pixels(&scene, 256);
    assert_pixels_equal(&pixels, [1.0; 3], "guided emissive room");
}

/// A sunlit VDB box over a diffuse ground, seen from the side: the guided
/// image equals the unguided one, pixel by pixel and pooled, within their
/// standard errors (light from one side: the guide is far from uniform).
#[test]
fn guided_and_unguided_agree_on_a_sunlit_vdb_box() {
    let text = SceneText::camera([0.5, 0.6, 3.5], [0.0, 0.0, 0.0], [8, 8])
        .fov(45.0)
        .depths(64, 8)
        .sun([-0.6, -0.5, -0.3], 3.0)
        .environment([0.05, 0.07, 0.1])
        .quad([0.0, -0.9, 0.0], [0.0, 1.0, 0.0], [8.0, 8.0])
        .raw(&vdb_box_medium(
            "density_scale = 3.0\nalbedo = 0.95\nphase = { type = \"hg\", g = 0.6 }",
        ))
        .build();
    let scene = scene_from_str(&text);
    let guided = guided_pixels(&scene, 384);
    let plain = estimate_pixels(&scene, 384);
    let means: Vec<[f64; 3]> = plain.iter().map(|e| e.mean).collect();
    let ses: Vec<[f64; 3]> = plain.iter().map(|e| e.std_error).collect();
    assert!(means.iter().any(|m| m[0] > 0.05), "a lit image");
    assert_pixels(&guided, &means, &ses, "guided vs unguided sunlit vdb");
}

/// A guided render (training and image) is bit-identical on 1 and 2 threads.
#[test]
fn guided_image_is_independent_of_thread_count() {
    let text = SceneText::camera([0.5, 0.6, 3.5], [0.0, 0.0, 0.0], [24, 16])
        .depths(32, 4)
        .sun([-0.6, -0.5, -0.3], 3.0)
        .quad([0.0, -0.9, 0.0], [0.0, 1.0, 0.0], [8.0, 8.0])
        .raw(&vdb_box_medium("density_scale = 3.0\nalbedo = 0.9"))
        .build();
    let mut scene = scene_from_str(&text);
    scene.settings.guiding = true;
    let render_with = |scene: &Scene, threads| {
        let options = RenderOptions {
            spp: 4,
            time_budget: None,
            spp_is_cap: false,
            threads: Some(threads),
            progress: false,
        };
        render(scene, &options, &AtomicBool::new(false))
            .image
            .pixels
    };
    let (one, two) = (render_with(&scene, 1), render_with(&scene, 2));
    assert!(one.iter().any(|p| p.max_channel() > 0.0));
    let bits = |v: &[Rgb]| -> Vec<[u32; 3]> {
        v.iter()
            .map(|p| [p.r.to_bits(), p.g.to_bits(), p.b.to_bits()])
            .collect()
    };
    assert_eq!(bits(&one), bits(&two));
    scene.settings.guiding = false;
    assert_ne!(
        bits(&one),
        bits(&render_with(&scene, 2)),
        "guiding changes the samples"
    );
}

/// A diffuse ground and a thin medium under a small emissive sphere (an
/// area light 20× brighter than a dim sky): the guide learns the sphere's
/// direction, far from the BSDF's and phase's densities, so MIS weights
/// that used the BSDF/phase density instead of the mixture's (for next-event
/// estimation or for hits of the sphere) would show. Guided pixels equal
/// unguided ones within their standard errors. Without the sky the unguided
/// render samples the sphere by forced in-scattering (its default there),
/// which a guided path must not: its continuation's density is the mixture's.
#[test]
fn guided_and_unguided_agree_under_a_small_area_light() {
    for sky in [true, false] {
        guided_and_unguided_agree_under_an_area_light(sky);
    }
}

fn guided_and_unguided_agree_under_an_area_light(sky: bool) {
    let mut text = SceneText::camera([0.0, 1.2, 3.0], [0.0, 0.0, 0.0], [8, 8])
        .fov(50.0)
        .depths(8, 4);
    if sky {
        text = text.environment([0.05, 0.05, 0.05]);
    }
    let text = text
        .quad([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [6.0, 6.0])
        .with("material = { type = \"diffuse\", albedo = 0.8 }")
        .sphere([0.6, 1.2, -0.4], 0.25)
        .with("emission = 1.0\nmaterial = { type = \"diffuse\", albedo = 0.0 }")
        .medium("type = \"homogeneous\"\nsigma_t = 0.3\nalbedo = 0.9\nbounds = { type = \"box\", min = [-3.0, 0.0, -3.0], max = [3.0, 0.8, 3.0] }")
        .build();
    let scene = scene_from_str(&text);
    assert_eq!(scene.settings.forced_scattering, !sky);
    let guided = guided_pixels(&scene, 512);
    let plain = estimate_pixels(&scene, 512);
    let means: Vec<[f64; 3]> = plain.iter().map(|e| e.mean).collect();
    let ses: Vec<[f64; 3]> = plain.iter().map(|e| e.std_error).collect();
    assert!(means.iter().any(|m| m[0] > 0.01), "a lit image");
    assert_pixels(
        &guided,
        &means,
        &ses,
        &format!("guided vs unguided under an area light, sky {sky}"),
    );
}

/// `--debug-pixel` replays one pixel's samples alone, which a guided render
/// never takes (its guide is learned from the whole image first): refused in
/// one line naming the flag and the way past it, exit 2.
#[test]
fn debug_pixel_refuses_a_guided_scene() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene = dir.path().join("g.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nresolution = [4, 4]\n\
         [integrator]\nguiding = true\n[[light]]\ntype = \"environment\"\nradiance = 1.0\n",
    )
    .expect("write scene");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_brume"))
        .arg("render")
        .arg(&scene)
        .args(["--debug-pixel", "1,1"])
        .output()
        .expect("run brume");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--debug-pixel") && err.contains("integrator.guiding=false"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
