//! `brume render --debug-strategies DIR`: each bidirectional strategy's
//! weighted and unweighted contribution images, `s{S}_t{T}_weighted.exr` and
//! `s{S}_t{T}_unweighted.exr`, for validating the estimator (as pbrt does).
//!
//! The images come from a second pass over the render's samples, after the
//! render is written, so a render without the flag pays nothing for it.

use std::path::Path;

use brume::error::{Error, Result};
use brume::film::image_io::{self, Image};
use brume::film::output_safety::Plan;
use brume::integrator::bdpt::strategies::render_strategies;
use brume::integrator::{IntegratorKind, Scene};

use super::render_args::{argument, RenderArgs};

const FLAG: &str = "--debug-strategies";

/// Refuses the flag where it cannot apply, before any work (the scene's
/// integrator is checked by [`check_scene`] once the scene is loaded).
pub fn check_args(args: &RenderArgs, dir: &Path) -> Result<()> {
    let conflict = if args.frames.is_some() {
        Some("writes the images of one render; leave out --frames")
    } else if args.split.is_piece() {
        Some("writes the images of a whole render; leave out --crop, --samples and --task-count")
    } else if args.time.is_some() {
        Some("retraces the render's samples, whose count --time leaves open; give --spp instead")
    } else if args.debug_pixel.is_some() {
        Some("writes images; leave out --debug-pixel")
    } else {
        None
    };
    if let Some(message) = conflict {
        return Err(argument(FLAG, message));
    }
    let parent = dir.parent().filter(|p| !p.as_os_str().is_empty());
    if dir.exists() && !dir.is_dir() {
        return Err(argument(
            FLAG,
            &format!("{} exists and is not a folder", dir.display()),
        ));
    }
    if !dir.exists() && parent.is_some_and(|p| !p.is_dir()) {
        return Err(argument(
            FLAG,
            &format!(
                "{}: folder {} does not exist",
                dir.display(),
                parent.unwrap_or(dir).display()
            ),
        ));
    }
    Ok(())
}

/// Refuses the flag for an integrator with no strategies to show.
pub fn check_scene(scene: &Scene) -> Result<()> {
    match scene.settings.integrator {
        IntegratorKind::Bdpt => Ok(()),
        IntegratorKind::Path | IntegratorKind::Sppm => Err(argument(
            FLAG,
            "needs [integrator] type = \"bdpt\" in the scene (path and sppm have no strategies to split)",
        )),
        IntegratorKind::Mlt(_) => Err(argument(
            FLAG,
            "needs [integrator] type = \"bdpt\" in the scene (mlt's chains do not keep the strategies apart)",
        )),
    }
}

/// Renders the strategy images of `scene` at its spp and writes them into
/// `dir` (created if missing), after checking them against the run's other
/// files (`exr`, `png`) and inputs.
pub fn write(
    args: &RenderArgs,
    scene: &Scene,
    dir: &Path,
    (exr, png): (&Path, &Path),
) -> Result<()> {
    let spp = scene.settings.spp;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .expect("thread pool");
    let images = pool.install(|| render_strategies(scene, spp));
    if !dir.is_dir() {
        std::fs::create_dir(dir).map_err(|e| Error::Output {
            path: dir.to_path_buf(),
            message: format!("cannot create the folder: {e}"),
        })?;
    }
    let name = |s: usize, t: usize, kind: &str| dir.join(format!("s{s}_t{t}_{kind}.exr"));
    let mut plan = Plan::new("render");
    brume::scene::inputs::add_to_plan(&mut plan, &args.scene, &args.set)?;
    plan.output("--out", exr, None).output("--png", png, None);
    for im in &images {
        for kind in ["weighted", "unweighted"] {
            plan.output(FLAG, &name(im.s, im.t, kind), None);
        }
    }
    plan.check()?;
    let (width, height) = (
        scene.camera.width() as usize,
        scene.camera.height() as usize,
    );
    for im in images {
        for (kind, pixels) in [("weighted", im.weighted), ("unweighted", im.unweighted)] {
            let image = Image {
                width,
                height,
                pixels,
                spp,
                partial: false,
            };
            image_io::write_exr(&name(im.s, im.t, kind), &image)?;
        }
    }
    if !args.quiet {
        eprintln!("wrote the strategy images into {}", dir.display());
    }
    Ok(())
}
