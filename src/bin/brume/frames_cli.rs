//! `brume render --frames LIST`: a frame sequence, one scene build per frame.
//!
//! Each frame's scene (and so its volumes) is built, rendered, written and
//! dropped before the next one is loaded. Inputs whose path does not depend
//! on the frame are kept between frames while unchanged (`scene::InputCache`:
//! a slab file is read once, each input hashed once per sequence). A stop request (Ctrl-C) saves the
//! frame in progress as a partial image and ends the sequence; the frames
//! already written stay. `--skip-existing` skips frames whose EXR exists and
//! is marked complete, so an interrupted sequence resumes where it stopped.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use brume::error::Result;
use brume::film::image_io;
use brume::scene::animation::{has_pattern, substitute};

use super::interrupt::{self, EXIT_INTERRUPTED};
use super::render_args::{
    apply_overrides, argument, check_render_args, warn_extensions, RenderArgs,
};
use super::render_job::{render_and_write, Job};

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
    let frames = args.frames.as_ref().map_or(&[][..], |f| &f.0[..]);
    check_render_args(args)?;
    if args.debug_pixel.is_some() {
        return Err(argument(
            "--debug-pixel",
            "renders one still image, not --frames",
        ));
    }
    let (exr_pattern, png_pattern) = output_patterns(args, frames.len())?;
    check_sequence_outputs(args, frames, &exr_pattern, &png_pattern)?;
    let cache = brume::scene::InputCache::new();
    let job = Job {
        args,
        show: !args.quiet && std::io::stderr().is_terminal(),
        cancel: interrupt::flag(),
        cache: &cache,
    };
    for (i, &frame) in frames.iter().enumerate() {
        if interrupt::requested() {
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
        let code = render_frame(&job, frame, &exr, &png)?;
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
fn render_frame(job: &Job, frame: i64, exr: &Path, png: &Path) -> Result<i32> {
    let args = job.args;
    // Loading has nothing to save: a stop request while it runs exits at once.
    interrupt::saving(false);
    let loaded = brume::scene::load_frame_cached(&args.scene, Some(frame), &args.set, job.cache)?;
    for w in &loaded.warnings {
        eprintln!("warning: frame {frame}: {w}");
    }
    let mut scene = loaded.scene;
    apply_overrides(&mut scene, args)?;
    let code = render_and_write(job, (&scene, Some(frame)), exr, png);
    // What this frame did not use (the files of a frame pattern) is not kept.
    job.cache.end_frame();
    code
}

/// The output-safety rule over the whole sequence, before frame 1: no
/// frame's output may be an input of any frame (or a frame of an input
/// sequence), and no two outputs of the sequence may be one file.
fn check_sequence_outputs(
    args: &RenderArgs,
    frames: &[i64],
    exr_pattern: &Path,
    png_pattern: &Path,
) -> Result<()> {
    let mut plan = brume::film::output_safety::Plan::new("render");
    brume::scene::inputs::add_to_plan(&mut plan, &args.scene, &args.set)?;
    plan.image_output_frames("--out", exr_pattern, frames);
    plan.image_output_frames("--png", png_pattern, frames);
    plan.check()?;
    warn_extensions(exr_pattern, png_pattern);
    Ok(())
}
