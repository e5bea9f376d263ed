//! `brume render --debug-pixel X,Y`: one pixel's samples replayed.

use brume::error::Result;

use crate::render_args::argument;

/// `--debug-pixel X,Y`: the samples of one pixel, exactly as a full render takes them.
pub(crate) fn debug_pixel(scene: &brume::integrator::Scene, (x, y): (u32, u32)) -> Result<i32> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    if x >= w || y >= h {
        return Err(argument(
            "--debug-pixel",
            &format!("{x},{y} is outside the {w}x{h} image: X must be below {w} and Y below {h}"),
        ));
    }
    if scene.settings.integrator != brume::integrator::IntegratorKind::Path {
        // A bidirectional pixel also gathers other pixels' light-tracing splats: its samples are not its value.
        return Err(argument(
            "--debug-pixel",
            "replays the path tracer's samples only; this scene's [integrator] type is not \"path\"",
        ));
    }
    if scene.settings.guiding {
        // The guide is trained over the whole image first: one pixel alone would replay other samples.
        return Err(argument(
            "--debug-pixel",
            "cannot replay a guided pixel (the guide is learned from the whole image before it); add --set integrator.guiding=false",
        ));
    }
    let spp = scene.settings.spp;
    let Stats {
        finite,
        nonfinite,
        mean,
        std_error,
        brightest,
    } = replay(scene, (x, y), spp);
    println!(
        "pixel {x},{y}: {spp} samples ({nonfinite} non-finite), seed {}",
        scene.settings.seed
    );
    println!(
        "mean radiance  {:.6} {:.6} {:.6}",
        mean[0], mean[1], mean[2]
    );
    println!(
        "standard error {:.6} {:.6} {:.6}",
        std_error[0], std_error[1], std_error[2]
    );
    if finite > 0 {
        println!(
            "brightest sample {} (luminance {:.6})",
            brightest.0, brightest.1
        );
    }
    Ok(0)
}

/// What the replayed samples of one pixel add up to.
struct Stats {
    finite: u32,
    nonfinite: u32,
    mean: [f64; 3],
    std_error: [f64; 3],
    brightest: (u32, f32),
}

/// Takes the `spp` samples of pixel (x, y), printing each non-finite one.
fn replay(scene: &brume::integrator::Scene, (x, y): (u32, u32), spp: u32) -> Stats {
    let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
    let (mut finite, mut nonfinite) = (0u32, 0u32);
    let mut brightest = (0u32, f32::NEG_INFINITY);
    for s in 0..spp {
        let l = brume::render::pixel_sample(scene, x, y, s);
        if !l.is_finite() {
            nonfinite += 1;
            println!("sample {s}: non-finite radiance {:?}", l.to_array());
            continue;
        }
        finite += 1;
        for c in 0..3 {
            sum[c] += l[c] as f64;
            sum2[c] += (l[c] as f64).powi(2);
        }
        if l.luminance() > brightest.1 {
            brightest = (s, l.luminance());
        }
    }
    let n = finite.max(1) as f64;
    let mean = sum.map(|v| v / n);
    let mut std_error = [0.0; 3];
    for c in 0..3 {
        std_error[c] = ((sum2[c] / n - mean[c] * mean[c]).max(0.0) / n).sqrt();
    }
    Stats {
        finite,
        nonfinite,
        mean,
        std_error,
        brightest,
    }
}
