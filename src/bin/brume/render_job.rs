//! One image of `brume render`: render (with the live display and
//! checkpoints), then write the EXR and PNG and report, shared by a still and
//! each frame of a sequence.

use brume::error::{Error, Result};
use brume::film::image_io;
use brume::render::{render_part, RenderOptions};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use crate::interrupt::{self, EXIT_INTERRUPTED};
use crate::render_args::RenderArgs;

/// How long a finished render waits for tev to take its final image.
const DISPLAY_FINAL_WAIT: Duration = Duration::from_secs(10);

/// What a render takes beside the scene: the same for every frame of a sequence.
pub(crate) struct Job<'a> {
    pub(crate) args: &'a RenderArgs,
    pub(crate) show: bool,
    pub(crate) cancel: &'a AtomicBool,
    /// Inputs kept between the scene build and the scene hash, and between
    /// the frames of a sequence.
    pub(crate) cache: &'a brume::scene::InputCache,
}

/// Renders one image of `scene` (a still, or the given frame) and writes its
/// EXR and PNG (paths already checked by the output-safety plan); returns the exit code.
pub(crate) fn render_and_write(
    job: &Job,
    (scene, frame): (&brume::integrator::Scene, Option<i64>),
    exr_path: &Path,
    png_path: &Path,
) -> Result<i32> {
    let args = job.args;
    let (w, h) = (scene.camera.width(), scene.camera.height());
    super::mlt_cli::check(scene, args)?;
    let part =
        brume::render::split::resolve_part(w, h, scene.settings.spp, &args.split.request()?)?;
    let scene_hash = brume::render::provenance::frame_scene_hash_cached(
        &args.scene,
        &scene.settings,
        (frame, &args.set),
        job.cache,
    )?;
    check_memory(scene, &args.scene)?;
    let options = RenderOptions {
        spp: scene.settings.spp,
        time_budget: args.time,
        spp_is_cap: args.spp.is_some(),
        threads: args.threads,
        progress: job.show,
    };
    let mut checkpoint = checkpoint(args, exr_path, png_path);
    let mut display = connect_display(args)?;
    // From here a stop request saves the finished passes instead of exiting at once.
    interrupt::saving(true);
    let mut out = render_live(
        scene,
        &options,
        &part,
        job.cancel,
        &mut display,
        checkpoint.as_mut(),
    );
    let refused = out.refused.as_ref().map(|r| Error::Scene {
        file: args.scene.clone(),
        field: r.key.into(),
        message: r.message.clone(),
    });
    if out.image.spp == 0 {
        return nothing_to_save(refused, exr_path, png_path);
    }
    out.film.provenance.scene_hash = scene_hash;
    let code = save(job, &out, (exr_path, png_path), checkpoint.as_mut())?;
    if let Some(error) = refused {
        // The passes before the refused one were saved (said by `save`).
        return Err(error);
    }
    if let Some(warning) = display.and_then(|d| d.finish(job.cancel, DISPLAY_FINAL_WAIT)) {
        eprintln!("warning: --display: {warning}");
    }
    Ok(code)
}

/// Ends a render that finished no pass: an image of 0 samples is black,
/// and must not replace an earlier render. A refused first pass is its
/// error; else a stop came before the first pass finished.
fn nothing_to_save(refused: Option<Error>, exr_path: &Path, png_path: &Path) -> Result<i32> {
    if let Some(error) = refused {
        return Err(error);
    }
    eprintln!(
        "interrupted before the first pass finished: nothing written, {} and {} left as they were",
        exr_path.display(),
        png_path.display()
    );
    Ok(EXIT_INTERRUPTED)
}

/// The checkpoint writer of `--checkpoint SECONDS`, over the render's own outputs.
fn checkpoint(
    args: &RenderArgs,
    exr_path: &Path,
    png_path: &Path,
) -> Option<brume::render::checkpoint::Checkpoint> {
    args.checkpoint.map(|every| {
        brume::render::checkpoint::Checkpoint::new(
            every,
            exr_path.to_path_buf(),
            png_path.to_path_buf(),
            args.exposure,
            args.tonemap,
        )
    })
}

/// The tev connection of `--display`, named after the scene file.
fn connect_display(args: &RenderArgs) -> Result<Option<brume::render::display::Display>> {
    let Some(address) = &args.display else {
        return Ok(None);
    };
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "render".into());
    brume::render::display::Display::connect(address, &name).map(Some)
}

/// Writes a finished or stopped render: a stopped one as a partial image,
/// beside a better one if need be (`output_safety::place_partial`); returns the exit code.
fn save(
    job: &Job,
    out: &brume::render::RenderOutput,
    (exr_path, png_path): (&Path, &Path),
    checkpoint: Option<&mut brume::render::checkpoint::Checkpoint>,
) -> Result<i32> {
    use brume::film::output_safety::{place_partial, Placement};
    let place = match out.image.partial {
        true => place_partial(exr_path, Some(png_path), out.image.spp),
        false => Placement::requested(exr_path, Some(png_path)),
    };
    if let (Some(exr), Some(png)) = (&place.exr, &place.png) {
        write_images(job, out, exr, png)?;
        if !job.args.quiet {
            report(out, exr, png);
        }
    }
    if !out.image.partial {
        if let Some(c) = checkpoint {
            c.remove_stale();
        }
        if interrupt::requested() {
            // The stop came after the last pass: the image is complete, but the caller asked to stop.
            eprintln!(
                "interrupted after the render finished: the complete image is in {} and {}",
                exr_path.display(),
                png_path.display()
            );
            return Ok(EXIT_INTERRUPTED);
        }
        return Ok(0);
    }
    // Said even with --quiet: the caller must know the image is not the full render.
    let (why, stop) = match out.refused.is_some() {
        true => ("stopped by the error below", "the error"),
        false => ("interrupted", "the stop"),
    };
    match (&place.exr, &place.png) {
        (Some(exr), Some(png)) => eprintln!(
            "{why}: saved the {} spp finished before {stop} to {} and {}",
            out.image.spp,
            exr.display(),
            png.display()
        ),
        _ => eprintln!(
            "{why}: the {} spp finished before {stop} were not saved",
            out.image.spp
        ),
    }
    if let Some(note) = place.note() {
        eprintln!("note: {note}");
    }
    Ok(EXIT_INTERRUPTED)
}

/// Writes the EXR (with the AOV and denoised layers), then the PNG preview,
/// encoding the PNG while the EXR is written: after a stop request the writes
/// are all that stands between the request and the exit. The PNG is put in
/// place only once the EXR is, so a failed EXR leaves both files as they were.
fn write_images(
    job: &Job,
    out: &brume::render::RenderOutput,
    exr_path: &Path,
    png_path: &Path,
) -> Result<()> {
    let args = job.args;
    let write_exr = || {
        let denoised = match args.denoise && !args.split.is_piece() {
            true => {
                brume::film::denoise::denoise_film(&out.film).map_err(|message| Error::Output {
                    path: exr_path.to_path_buf(),
                    message,
                })?
            }
            false => Vec::new(),
        };
        image_io::write_film_exr_beauty(exr_path, &out.film, &out.image, &denoised)
    };
    let (exr, png) = std::thread::scope(|s| {
        let exr = s.spawn(write_exr);
        let png = image_io::encode_png_tonemapped(&out.image, args.exposure, args.tonemap);
        (exr.join(), png)
    });
    // A panic in the EXR writer is a bug: let it end the process as it would have.
    exr.unwrap_or_else(|p| std::panic::resume_unwind(p))?;
    if args.denoise && args.split.is_piece() && !args.quiet {
        eprintln!(
            "note: {} holds the albedo and normal for denoising after the merge: \
             brume merge --denoise",
            exr_path.display()
        );
    }
    let png = png.map_err(|message| Error::Output {
        path: png_path.to_path_buf(),
        message,
    })?;
    image_io::write_encoded_png(png_path, &png)
}

/// Renders, sending each finished pass to tev and to the checkpoint writer.
/// A viewer that goes away or a failed checkpoint is reported once; the render goes on.
fn render_live(
    scene: &brume::integrator::Scene,
    options: &RenderOptions,
    part: &brume::render::Part,
    cancel: &AtomicBool,
    display: &mut Option<brume::render::display::Display>,
    mut checkpoint: Option<&mut brume::render::checkpoint::Checkpoint>,
) -> brume::render::RenderOutput {
    if display.is_none() && checkpoint.is_none() {
        return render_part(scene, options, part, cancel, None);
    }
    let mut on_pass = |image: &image_io::Image| {
        let lost = display.as_mut().and_then(|d| d.show(image).err());
        if let Some(e) = lost {
            eprintln!("warning: --display: lost the connection to tev ({e}); rendering on");
            *display = None;
        }
        if let Some(c) = &mut checkpoint {
            if let Err(e) = c.pass_done(image) {
                eprintln!("warning: --checkpoint: {e}; no more checkpoints");
                checkpoint = None;
            }
        }
    };
    render_part(scene, options, part, cancel, Some(&mut on_pass))
}

/// Refuses an image over the memory limit (or more than this machine can
/// give) before rendering: a failed allocation mid-render would abort the
/// process instead of giving an error.
fn check_memory(scene: &brume::integrator::Scene, file: &Path) -> Result<()> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let splats = super::mlt_cli::splats(scene);
    let bytes = brume::render::film_peak_bytes(w, h, &scene.aovs, splats);
    brume::error::limits::check(bytes as u128).map_err(|refusal| Error::Scene {
        file: file.to_path_buf(),
        field: "camera.resolution".into(),
        message: format!(
            "a {w}x{h} image needs {} of memory, {refusal}",
            brume::error::limits::format_bytes(bytes as u128)
        ),
    })
}

/// The render's summary lines on stderr: rate, tracking statistics, warnings.
fn report(out: &brume::render::RenderOutput, exr: &Path, png: &Path) {
    let secs = out.elapsed.as_secs_f64();
    eprintln!(
        "{} {}x{} at {} spp in {:.2} s ({:.2} M samples/s) -> {} , {}",
        if out.image.partial {
            "stopped early:"
        } else {
            "rendered"
        },
        out.image.width,
        out.image.height,
        out.image.spp,
        secs,
        out.samples as f64 / secs.max(1e-9) / 1e6,
        exr.display(),
        png.display()
    );
    if out.tracking.lookups() > 0 {
        let per_sample = |n: u64| n as f64 / out.samples.max(1) as f64;
        eprintln!(
            "tracking: {:.2} tentative collisions per sample, null fraction {:.3}, {:.2} exact voxel steps per sample",
            per_sample(out.tracking.collisions),
            out.tracking.null_fraction(),
            per_sample(out.tracking.voxel_steps)
        );
    }
    super::mlt_cli::report(out);
    report_auto(out);
    report_noise(out);
    warn_dropped_work(out);
}

/// What the automatic choice made of its pilot.
fn report_auto(out: &brume::render::RenderOutput) {
    let Some(a) = &out.auto else { return };
    let gain = brume::render::adaptive::AUTO_GAIN;
    let full = brume::render::adaptive::FULL_GAIN;
    match a.spread {
        true => eprintln!(
            "adaptive (automatic): the pilot predicts {:.2}x the efficiency (1 / (error² × \
             cost), each pixel's squared error over its luminance) from spreading the samples (from \
             {gain}x it spreads them, in full from {full}x; --adaptive off keeps them even)",
            a.gain
        ),
        false => eprintln!(
            "uniform (automatic): the pilot of {} spp (the image's first) predicts {:.2}x the \
             efficiency (1 / (error² × cost), each pixel's squared error over its luminance) from spreading \
             the samples, below {gain}x; --adaptive on spreads them anyway",
            a.pilot_spp, a.gain
        ),
    }
}

/// A piloted render's counts and estimated error; a warning when the noise target was missed.
fn report_noise(out: &brume::render::RenderOutput) {
    let Some(r) = &out.noise else { return };
    let target = r
        .target
        .map(|t| format!(" (target {t})"))
        .unwrap_or_default();
    eprintln!(
        "{}: pilot {} spp (the image's first), image {}-{} spp per pixel (mean {:.1}), \
         estimated relative error {:.4}{target}",
        if r.adaptive { "adaptive" } else { "uniform" },
        r.pilot_spp,
        r.min_spp,
        r.max_spp,
        r.mean_spp,
        r.error
    );
    if r.target_missed() && !out.image.partial {
        eprintln!(
            "warning: the noise target {} was not reached (estimated {:.4}): the spp cap or \
             the time budget came first; raise --spp or --time",
            r.target.unwrap_or_default(),
            r.error
        );
    }
}

/// Warnings for samples, splats, rays and crossings the render left out.
fn warn_dropped_work(out: &brume::render::RenderOutput) {
    if out.nonfinite_samples > 0 {
        eprintln!(
            "warning: {} NaN/infinite samples were left out of the image",
            out.nonfinite_samples
        );
    }
    if let Some(dropped) = out
        .film
        .splats
        .as_ref()
        .map(|s| s.dropped)
        .filter(|&d| d > 0)
    {
        eprintln!(
            "warning: {dropped} splats were NaN, infinite or off the image and were left out"
        );
    }
    if out.tracking.capped_rays > 0 {
        eprintln!(
            "warning: {} rays reached the cap of {} tentative collisions and were ended \
             (the image is biased dark there; a tighter majorant, majorant = \"grid\", avoids it)",
            out.tracking.capped_rays,
            brume::integrator::tracking::MAX_TENTATIVE_COLLISIONS
        );
    }
    if out.truncated_interiors > 0 {
        eprintln!(
            "warning: {} rays crossed a shape with an interior more than {} times; past the last \
             kept crossing the medium was taken as absent (the image is biased there)",
            out.truncated_interiors,
            brume::geometry::closed::MAX_CROSSINGS
        );
    }
}
