//! `brume render --frames LIST`: a frame sequence, one scene build per frame.
//!
//! Each frame's scene (and so its volumes) is built, rendered, written and
//! dropped before the next one is loaded. A stop request (Ctrl-C) saves the
//! frame in progress as a partial image and ends the sequence; the frames
//! already written stay. `--skip-existing` skips frames whose EXR exists and
//! is marked complete, so an interrupted sequence resumes where it stopped.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use brume::error::Result;
use brume::image_io;
use brume::render::{render, RenderOptions};
use brume::scene::animation::{has_pattern, parse_frames, substitute};

use super::{
    apply_overrides, argument, check_memory, check_render_args, report, RenderArgs,
    EXIT_INTERRUPTED,
};

/// The EXR and PNG patterns: the user's, or NAME.####.exr / NAME.####.png.
fn output_patterns(args: &RenderArgs, frames: usize) -> Result<(PathBuf, PathBuf)> {
    let stem = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "render".into());
    let exr = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.####.exr")));
    let png = args
        .png
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}.####.png")));
    for (flag, path) in [("--out", &exr), ("--png", &png)] {
        if frames > 1 && !has_pattern(path) {
            return Err(argument(
                flag,
                &format!(
                    "{} has no #### frame pattern: every frame would overwrite it",
                    path.display()
                ),
            ));
        }
    }
    Ok((exr, png))
}

/// Renders every frame of `--frames`; returns the exit code.
pub fn run_frames(args: &RenderArgs) -> Result<i32> {
    let list = args.frames.as_deref().unwrap_or_default();
    let frames = parse_frames(list).map_err(|m| argument("--frames", &m))?;
    let time_budget = check_render_args(args)?;
    if args.debug_pixel.is_some() {
        return Err(argument(
            "--debug-pixel",
            "renders one still image, not --frames",
        ));
    }
    let (exr_pattern, png_pattern) = output_patterns(args, frames.len())?;
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(EXIT_INTERRUPTED);
        }
    });
    let show = !args.quiet && std::io::stderr().is_terminal();
    for (i, &frame) in frames.iter().enumerate() {
        if cancel.load(Ordering::SeqCst) {
            // stopped between frames: write nothing for the frames not begun
            eprintln!("interrupted before frame {frame}: earlier frames are complete");
            return Ok(EXIT_INTERRUPTED);
        }
        let exr = substitute(&exr_pattern, frame);
        let png = substitute(&png_pattern, frame);
        let position = format!("frame {frame} ({}/{})", i + 1, frames.len());
        if args.skip_existing && image_io::exr_is_complete(&exr) {
            if !args.quiet {
                eprintln!("{position}: {} is complete, skipped", exr.display());
            }
            continue;
        }
        if !args.quiet {
            eprintln!("{position}");
        }
        let code = render_frame(args, frame, &exr, &png, time_budget, show, &cancel)?;
        if code != 0 {
            eprintln!(
                "interrupted in {position}: earlier frames are complete; resume with --skip-existing"
            );
            return Ok(code);
        }
    }
    Ok(0)
}

/// Builds, renders and writes one frame; its scene and volumes are dropped on return.
fn render_frame(
    args: &RenderArgs,
    frame: i64,
    exr: &Path,
    png: &Path,
    time_budget: Option<std::time::Duration>,
    show: bool,
    cancel: &AtomicBool,
) -> Result<i32> {
    let mut scene = brume::scene::load_frame(&args.scene, Some(frame))?;
    apply_overrides(&mut scene, args)?;
    image_io::check_writable(exr)?;
    image_io::check_writable(png)?;
    check_memory(&scene, &args.scene)?;
    let options = RenderOptions {
        spp: scene.settings.spp,
        time_budget,
        spp_is_cap: args.spp.is_some(),
        threads: args.threads,
        progress: show,
    };
    let out = render(&scene, &options, cancel);
    image_io::write_exr(exr, &out.image)?;
    image_io::write_png(png, &out.image, args.exposure)?;
    if !args.quiet {
        report(&out, exr, png);
    }
    Ok(if out.image.partial {
        EXIT_INTERRUPTED
    } else {
        0
    })
}
