//! What the command line refuses and reports for `[integrator] type = "mlt"`.

use super::render_args::{argument, RenderArgs};
use brume::error::{Error, Result};
use brume::integrator::{IntegratorKind, Scene};

/// Deepest path a Metropolis render takes (as `scene::mlt_keys` checks the scene's).
const MAX_DEPTH: u32 = 4096;

/// Refuses what a Metropolis render cannot give: pieces of a split render
/// (chains splat over the whole frame), AOVs (no pixel owns a sample) and a
/// `--max-depth` the bootstrap cannot cover.
pub fn check(scene: &Scene, args: &RenderArgs) -> Result<()> {
    let IntegratorKind::Mlt(settings) = scene.settings.integrator else {
        return Ok(());
    };
    let why = "is not supported with [integrator] type = \"mlt\"";
    if let Some(flag) = [
        ("--crop", args.split.crop.is_some()),
        ("--samples", args.split.samples.is_some()),
        ("--task-count", args.split.task_count.is_some()),
    ]
    .iter()
    .find_map(|(f, set)| set.then_some(*f))
    {
        return Err(argument(
            flag,
            &format!("a piece of a split render {why}: its chains splat over the whole frame; render the whole image"),
        ));
    }
    if !scene.aovs.is_empty() {
        let fix = "no pixel owns a sample; render the AOVs with type = \"path\"";
        return Err(match (args.denoise, args.aovs.is_some()) {
            (true, _) => argument(
                "--denoise",
                &format!("(it needs the albedo and normal AOVs) {why}: {fix}"),
            ),
            (_, true) => argument("--aovs", &format!("{why}: {fix}")),
            _ => Error::Scene {
                file: args.scene.clone(),
                field: "film.aovs".into(),
                message: format!("{why}: {fix}"),
            },
        });
    }
    let depth = scene.settings.max_depth;
    if depth > MAX_DEPTH || (settings.bootstrap_samples as u64) < depth as u64 + 1 {
        return Err(argument(
            "--max-depth",
            &format!(
                "{depth} needs at most {MAX_DEPTH} and at least max_depth + 1 bootstrap paths with type = \"mlt\" (integrator.bootstrap_samples is {})",
                settings.bootstrap_samples
            ),
        ));
    }
    Ok(())
}

/// The render summary's Metropolis lines: the bootstrap's brightness and the acceptance per path length.
pub fn report(out: &brume::render::RenderOutput) {
    let Some(stats) = &out.mlt else {
        return;
    };
    eprintln!(
        "mlt: brightness {:.6} ± {:.6} (bootstrap), acceptance {:.3} over all chains",
        stats.brightness,
        stats.brightness_std_error,
        stats.acceptance()
    );
    let per_length: Vec<String> = stats
        .lengths
        .iter()
        .map(|l| format!("{}: {:.3} ({} chains)", l.length, l.acceptance(), l.chains))
        .collect();
    if !per_length.is_empty() {
        eprintln!(
            "mlt: acceptance by path length (segments): {}",
            per_length.join(", ")
        );
    }
}

/// Whether the film keeps splats for `scene`'s integrator.
pub fn splats(scene: &Scene) -> bool {
    matches!(
        scene.settings.integrator,
        IntegratorKind::Bdpt | IntegratorKind::Mlt(_)
    )
}
