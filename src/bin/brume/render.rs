//! `brume render scene.toml`: a still (or, with --frames, a sequence; with
//! --debug-pixel, one pixel replayed), from flags to written images.

use brume::error::Result;
use brume::film::output_safety::Plan;
use std::io::IsTerminal;
use std::path::PathBuf;

use crate::render_args::{apply_overrides, check_render_args, warn_extensions, RenderArgs};
use crate::render_job::{render_and_write, Job};
use crate::{debug_pixel::debug_pixel, debug_strategies, frames_cli, interrupt};

pub(crate) fn run_render(args: RenderArgs) -> Result<i32> {
    if let Some(dir) = &args.debug_strategies {
        debug_strategies::check_args(&args, dir)?;
    }
    if args.frames.is_some() {
        return frames_cli::run_frames(&args);
    }
    check_render_args(&args)?;
    let stem = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "render".into());
    let exr_path = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.exr")));
    let png_path = args
        .png
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.png")));
    if args.debug_pixel.is_none() {
        // Before the scene's volumes are loaded: a refused run does no work.
        let mut plan = Plan::new("render");
        brume::scene::inputs::add_to_plan(&mut plan, &args.scene, &args.set)?;
        plan.image_output("--out", &exr_path, None);
        plan.image_output("--png", &png_path, None);
        plan.check()?;
        warn_extensions(&exr_path, &png_path);
    }
    // One cache for the build and the scene hash: the slab file is read once.
    let cache = brume::scene::InputCache::new();
    let loaded = brume::scene::load_frame_cached(&args.scene, None, &args.set, &cache)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let mut scene = loaded.scene;
    apply_overrides(&mut scene, &args)?;
    if let Some(pixel) = args.debug_pixel {
        return debug_pixel(&scene, pixel);
    }
    if args.debug_strategies.is_some() {
        debug_strategies::check_scene(&scene)?;
    }
    let job = Job {
        args: &args,
        show: !args.quiet && std::io::stderr().is_terminal(),
        cancel: interrupt::flag(),
        cache: &cache,
    };
    let code = render_and_write(&job, (&scene, None), &exr_path, &png_path)?;
    if let Some(dir) = &args.debug_strategies {
        if code == 0 {
            debug_strategies::write(&args, &scene, dir, (&exr_path, &png_path))?;
        } else {
            eprintln!("note: the render was stopped: no --debug-strategies images written");
        }
    }
    Ok(code)
}
