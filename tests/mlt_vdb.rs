//! Metropolis light transport in a heterogeneous (VDB) medium: the smoke
//! plume under a point light, region by region (the four quadrants of the
//! image, luminance), against the bidirectional integrator. MLT's passes are
//! correlated, so its standard error comes from independent seeds (each its
//! own bootstrap and chains); BDPT's from its i.i.d. sample passes.

mod bdpt_support;

use bdpt_support::common::scene_text::SceneText;
use bdpt_support::common::{assert_within, scene_from_str};
use bdpt_support::{Accumulator, Estimate};
use brume::integrator::bdpt::{strategies, BdptArena};
use brume::math::color::Rgb;
use brume::render::{render, RenderOptions};
use std::sync::atomic::AtomicBool;

const SIZE: u32 = 8;

fn plume(integrator: &str) -> String {
    SceneText::plume_view(SIZE)
        .integrator(&format!("max_depth = 12\n{integrator}"))
        .point_light([1.2, 2.2, 1.0], [6.0, 5.0, 4.0])
        .smoke_plume_on_ground(10.0)
        .build()
}

/// Mean luminance of each quadrant of a row-major image.
fn quadrants(pixels: &[Rgb]) -> [f64; 4] {
    let mut q = [0.0; 4];
    let half = SIZE / 2;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let i = ((y >= half) as usize) * 2 + (x >= half) as usize;
            q[i] += pixels[(y * SIZE + x) as usize].luminance() as f64;
        }
    }
    q.map(|v| v / (half * half) as f64)
}

/// Mean and standard error of each quadrant over independent images.
fn estimates(images: impl Iterator<Item = [f64; 4]>) -> [Estimate; 4] {
    let mut acc = [Accumulator::default(); 4];
    for q in images {
        for (a, v) in acc.iter_mut().zip(q) {
            a.add(Rgb::splat(v as f32));
        }
    }
    acc.map(|a| a.estimate())
}

#[test]
fn plume_quadrants_match_bdpt() {
    let bdpt_scene = scene_from_str(&plume("type = \"bdpt\"\nseed = 4"));
    let mut arena = BdptArena::new();
    let mut pass = vec![Rgb::BLACK; (SIZE * SIZE) as usize];
    let bdpt = estimates((0..1024).map(|i| {
        strategies::render_pass(&bdpt_scene, i, &mut arena, &mut pass);
        quadrants(&pass)
    }));
    let mlt = estimates((0..64u64).map(|seed| {
        let text = plume(&format!(
            "type = \"mlt\"\nseed = {seed}\nbootstrap_samples = 65536\nchains = 16"
        ));
        let options = RenderOptions {
            spp: 256,
            time_budget: None,
            spp_is_cap: false,
            threads: None,
            progress: false,
        };
        let out = render(&scene_from_str(&text), &options, &AtomicBool::new(false));
        quadrants(&out.image.pixels)
    }));
    for (q, (m, b)) in mlt.iter().zip(&bdpt).enumerate() {
        let se = (m.std_error[0].powi(2) + b.std_error[0].powi(2)).sqrt();
        eprintln!(
            "quadrant {q}: mlt {} ± {}, bdpt {} ± {}",
            m.mean[0], m.std_error[0], b.mean[0], b.std_error[0]
        );
        assert_within(m.mean[0], se, b.mean[0], 4, &format!("quadrant {q}"));
    }
}
