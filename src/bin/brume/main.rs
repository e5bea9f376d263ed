//! The `brume` command line: `render`, and the tools around it.

use brume::error::{Error, Result};
use brume::film::image_io;
use brume::film::tonemap::Tonemap;
use brume::integrator::aov::Aov;
use brume::render::cli_values as values;
use brume::render::output_safety::Plan;
use brume::render::{render_part, RenderOptions};
use clap::{Parser, Subcommand};
use interrupt::EXIT_INTERRUPTED;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

mod debug_strategies;
mod frames_cli;
mod interrupt;

/// brume: a physically based renderer for participating media.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Largest image, grid or file brume allocates, in GB (default: half of
    /// this machine's memory, or BRUME_MEMORY_LIMIT); see docs/robustness.md "Limits".
    #[arg(long, global = true, value_name = "GB", allow_negative_numbers = true, value_parser = brume::error::limits::parse_gb)]
    memory_limit: Option<u64>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file to EXR (linear) and PNG (sRGB preview).
    Render(Box<RenderArgs>),
    /// Describe the grids of an OpenVDB file: types, transform, voxel counts, bounds, values, memory.
    Info(InfoArgs),
    /// Render the airlight demo: targets fading with distance in haze, compared with Koschmieder's law.
    Airlight(AirlightArgs),
    /// Merge the pieces of a split render (crops, sample ranges) into the image of the whole render.
    Merge(MergeArgs),
    /// Compare A.exr with the reference B.exr: RMSE, relative MSE, means, max difference.
    Compare(CompareArgs),
}

#[derive(clap::Args)]
struct MergeArgs {
    /// The pieces: EXR files written by `brume render` with --crop, --samples or --task-count.
    #[arg(required = true)]
    pieces: Vec<PathBuf>,
    /// The merged EXR.
    #[arg(long, short)]
    out: PathBuf,
    /// A PNG preview of the merged image.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Denoise the merged beauty into a `denoised` layer, guided by the merged albedo and normal
    /// (render the pieces with --denoise; needs a build with `--features denoise`).
    #[arg(long)]
    denoise: bool,
}

#[derive(clap::Args)]
struct CompareArgs {
    /// The image to judge (EXR).
    a: PathBuf,
    /// The reference image (EXR).
    b: PathBuf,
    /// Write a false-colour picture of the per-pixel error here (PNG).
    #[arg(long)]
    diff: Option<PathBuf>,
    /// Exit with code 1 when the RMSE is above this (or an image holds NaN or infinity).
    #[arg(long, allow_negative_numbers = true, value_name = "X", value_parser = values::rmse)]
    max_rmse: Option<f64>,
}

#[derive(clap::Args)]
struct AirlightArgs {
    /// Output folder for airlight.exr/.png, airlight.csv, airlight_plot.png and airlight.toml.
    #[arg(long, default_value = "airlight")]
    out: PathBuf,
    /// Meteorological visual range in metres (sigma_t = ln 50 / visibility).
    #[arg(long, allow_negative_numbers = true, value_name = "METRES", default_value = "1000", value_parser = visibility)]
    visibility: f32,
    /// Samples per pixel.
    #[arg(long, allow_negative_numbers = true, value_name = "N", default_value = "64", value_parser = values::whole(1u32, u32::MAX))]
    spp: u32,
    /// Image width in pixels (height = width / 5).
    #[arg(long, allow_negative_numbers = true, value_name = "PIXELS", default_value = "768", value_parser = values::whole(64u32, 32768))]
    width: u32,
    /// Emission–absorption air and emissive targets, where Koschmieder's law is exact.
    #[arg(long, conflicts_with = "single")]
    exact: bool,
    /// A zenith sun over a scattering slab with single scattering only, where Koschmieder's law is exact too.
    #[arg(long)]
    single: bool,
    /// Worker threads (default: all cores).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::threads)]
    threads: Option<usize>,
}

/// `airlight --visibility`: from a millimetre to a million kilometres, so that
/// sigma_t = ln 50 / visibility stays a normal number in the demo's scene.
fn visibility(text: &str) -> values::Parsed<f32> {
    values::decimal(1e-3, 1e9, "metres")(text).map(|v| v as f32)
}

#[derive(clap::Args)]
struct InfoArgs {
    /// The .vdb file.
    file: PathBuf,
    /// Machine-readable JSON instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
struct RenderArgs {
    /// The scene file (TOML).
    scene: PathBuf,
    /// Set a scene value before validation, as TOML (repeatable): `--set camera.resolution=[640,360]
    /// --set integrator.spp=64 --set shape[2].material.albedo=0.5`; a bare word is a string.
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = values::set)]
    set: Vec<brume::scene::Override>,
    /// Samples per pixel (overrides the scene's integrator.spp).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::whole(1u32, u32::MAX))]
    spp: Option<u32>,
    /// Maximum path depth (overrides integrator.max_depth).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::whole(0u32, u32::MAX))]
    max_depth: Option<u32>,
    /// Seed of the random streams (overrides integrator.seed).
    #[arg(long, allow_negative_numbers = true, value_name = "S", value_parser = values::whole(0u64, u64::MAX))]
    seed: Option<u64>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::threads)]
    threads: Option<usize>,
    /// EXR output (default: NAME.exr in the current folder).
    #[arg(long)]
    out: Option<PathBuf>,
    /// PNG preview (default: NAME.png in the current folder).
    #[arg(long)]
    png: Option<PathBuf>,
    /// Render progressive passes until this many seconds are spent (--spp then caps it).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = values::seconds)]
    time: Option<Duration>,
    /// Tone curve of the PNG preview: aces (filmic, rolls highlights off) or clip.
    #[arg(long, value_enum, default_value_t = Tonemap::Aces)]
    tonemap: Tonemap,
    /// Exposure of the PNG preview in stops.
    #[arg(long, value_name = "STOPS", default_value = "0", allow_negative_numbers = true, value_parser = values::exposure)]
    exposure: f32,
    /// No progress bar and no summary.
    #[arg(long, short)]
    quiet: bool,
    /// AOVs written as extra EXR layers, comma-separated: alpha,depth,normal,albedo,transmittance
    /// (replaces the scene's [film] aovs; "none" for none).
    #[arg(long, value_name = "LIST", value_parser = values::aovs)]
    aovs: Option<values::Aovs>,
    /// Denoise the beauty with Intel Open Image Denoise into a `denoised` layer
    /// (adds the albedo and normal AOVs; needs a build with `--features denoise`).
    /// A piece of a split render records the albedo and normal only: denoise with `brume merge --denoise`.
    #[arg(long)]
    denoise: bool,
    /// Stream every finished pass to the tev image viewer listening at HOST:PORT (tev's default port is 14158).
    #[arg(long, value_name = "HOST:PORT", value_parser = values::host_port)]
    display: Option<String>,
    /// Rewrite the EXR and PNG (marked incomplete) every SECONDS during the render.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = values::seconds)]
    checkpoint: Option<Duration>,
    /// Replay one pixel X,Y (column, row from the top): print its samples' statistics, write no image.
    #[arg(long, value_name = "X,Y", value_parser = values::pixel)]
    debug_pixel: Option<(u32, u32)>,
    /// For a bdpt scene, also write each strategy's weighted and unweighted
    /// contribution images into DIR (s2_t1_weighted.exr, ...), retracing the render's samples.
    #[arg(long, value_name = "DIR")]
    debug_strategies: Option<PathBuf>,
    /// Render a frame sequence: `1-100`, `1,3,7-20:2`; outputs take the #### pattern of --out/--png
    /// (default NAME.####.exr and NAME.####.png).
    #[arg(long, value_name = "LIST", allow_hyphen_values = true, value_parser = values::frames)]
    frames: Option<values::Frames>,
    /// With --frames, skip frames whose EXR exists and is marked complete.
    #[arg(long, requires = "frames")]
    skip_existing: bool,
    #[command(flatten)]
    split: brume::render::split::SplitArgs,
}

fn main() {
    restore_default_sigpipe();
    interrupt::install();
    let cli = parse_command_line();
    let result = match cli.memory_limit {
        Some(bytes) => {
            brume::error::limits::set_memory_limit(bytes);
            Ok(())
        }
        None => brume::error::limits::check_setting().map(|_| ()),
    };
    let result = result.and_then(|()| match cli.command {
        Command::Render(args) => run_render(*args),
        Command::Info(args) => run_info(args),
        Command::Airlight(args) => run_airlight(args),
        Command::Merge(args) => run_merge(args),
        Command::Compare(args) => run_compare(args),
    });
    match result {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(e.exit_code());
        }
    }
}

/// The command line, or exit: help and version as clap prints them; a bad
/// flag value as one line naming the flag and what it expects, exit code 2.
fn parse_command_line() -> Cli {
    use clap::error::ErrorKind;
    let e = match Cli::try_parse() {
        Ok(cli) => return cli,
        Err(e) => e,
    };
    match e.kind() {
        ErrorKind::ValueValidation | ErrorKind::InvalidValue => {
            // clap's first paragraph says it (with the possible values of a
            // choice on a line of their own); the rest points to --help.
            let text = e.render().to_string();
            let first: Vec<&str> = text
                .lines()
                .take_while(|l| !l.is_empty())
                .map(str::trim)
                .collect();
            eprintln!("{}", first.join(" "));
            std::process::exit(2);
        }
        _ => e.exit(),
    }
}

/// Lets a closed pipe end the process silently, as it ends `cat` or `grep`.
///
/// Rust ignores SIGPIPE, so `println!` into a reader that has gone away (`brume
/// compare a b | head -1`) panics. Every file brume writes is written before its
/// report is printed (and atomically, through a temporary), so dying at a print
/// never leaves a half-written image.
fn restore_default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a
    // valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// How long a finished render waits for tev to take its final image.
const DISPLAY_FINAL_WAIT: Duration = Duration::from_secs(10);

fn run_info(args: InfoArgs) -> Result<i32> {
    let report = brume::volume::info_report(&args.file, args.json)?;
    print!("{report}");
    if !report.ends_with('\n') {
        println!();
    }
    // The report lists damaged grids beside the good ones; scripts still need a
    // failing exit code for a damaged file (an unsupported grid type is fine).
    let file = brume::volume::VdbFile::open(&args.file)?;
    for name in file.grid_names() {
        if let Err(e @ brume::volume::VolumeError::CorruptGrid { .. }) = file.load_grid(&name) {
            return Err(e.into());
        }
    }
    Ok(0)
}

fn run_airlight(args: AirlightArgs) -> Result<i32> {
    use brume::airlight::{AirlightMode, AirlightOptions};
    let report = brume::airlight::run(&AirlightOptions {
        out: Some(args.out),
        visibility: args.visibility,
        spp: args.spp,
        width: args.width,
        mode: if args.exact {
            AirlightMode::EmissionAbsorption
        } else if args.single {
            AirlightMode::SingleScattering
        } else {
            AirlightMode::Sky
        },
        seed: 0,
        threads: args.threads,
        progress: std::io::stderr().is_terminal(),
    })?;
    print!("{}", report.table);
    println!("rendered in {:.2} s", report.render_seconds);
    for f in &report.files {
        println!("wrote {}", f.display());
    }
    Ok(0)
}

fn run_compare(args: CompareArgs) -> Result<i32> {
    if let Some(diff) = &args.diff {
        Plan::new("comparison")
            .input("image A", &args.a)
            .input("reference B", &args.b)
            .output("--diff", diff, None)
            .check()?;
    }
    let (c, a, b) = brume::film::compare::compare_files(&args.a, &args.b)?;
    print!("{}", c.report());
    if let Some(diff) = &args.diff {
        let scale = brume::film::compare::diff_scale(&a, &b);
        let rgb = brume::film::compare::false_colour(&a, &b, scale);
        let (w, h) = c.size;
        image_io::write_png_srgb8(diff, w as u32, h as u32, &rgb)?;
        println!(
            "wrote {} (saturates at a mean |A-B| of {scale:.4e})",
            diff.display()
        );
    }
    match args.max_rmse {
        Some(_) if c.nonfinite > 0 => {
            println!("FAIL: {} non-finite channel values", c.nonfinite);
            Ok(1)
        }
        Some(m) if c.rmse > m => {
            println!("FAIL: rmse {:.6e} above --max-rmse {m:e}", c.rmse);
            Ok(1)
        }
        _ => Ok(0),
    }
}

fn argument(name: &str, message: &str) -> Error {
    Error::Argument {
        argument: name.into(),
        message: message.into(),
    }
}

fn run_render(args: RenderArgs) -> Result<i32> {
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
    let loaded = brume::scene::load_frame_with_overrides(&args.scene, None, &args.set)?;
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

/// Applies --spp, --max-depth, --seed, --aovs and --denoise to a loaded scene.
fn apply_overrides(scene: &mut brume::integrator::Scene, args: &RenderArgs) -> Result<()> {
    if let Some(spp) = args.spp {
        scene.settings.spp = spp;
    }
    if let Some(d) = args.max_depth {
        scene.settings.max_depth = d;
    }
    if let Some(seed) = args.seed {
        scene.settings.seed = seed;
    }
    if let Some(aovs) = &args.aovs {
        scene.aovs = aovs.0.clone();
    }
    if args.denoise {
        if !brume::film::denoise::AVAILABLE {
            return Err(argument("--denoise", brume::film::denoise::UNAVAILABLE));
        }
        for aov in [Aov::Albedo, Aov::Normal] {
            if !scene.aovs.contains(&aov) {
                scene.aovs.push(aov);
            }
        }
    }
    Ok(())
}

/// Checks the combinations of flags that do not depend on the scene (each value is checked by its parser).
fn check_render_args(args: &RenderArgs) -> Result<()> {
    if args.split.is_piece() && args.time.is_some() {
        return Err(argument(
            "--time",
            "a piece (--crop, --samples, --task-count) renders a fixed sample range; leave out --time",
        ));
    }
    Ok(())
}

/// What a render takes beside the scene: the same for every frame of a sequence.
struct Job<'a> {
    args: &'a RenderArgs,
    show: bool,
    cancel: &'a AtomicBool,
}

/// Renders one image of `scene` (a still, or the given frame) and writes its
/// EXR and PNG (paths already checked by the output-safety plan); returns the exit code.
fn render_and_write(
    job: &Job,
    (scene, frame): (&brume::integrator::Scene, Option<i64>),
    exr_path: &Path,
    png_path: &Path,
) -> Result<i32> {
    let args = job.args;
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let part =
        brume::render::split::resolve_part(w, h, scene.settings.spp, &args.split.request()?)?;
    let scene_hash = brume::render::provenance::frame_scene_hash(
        &args.scene,
        &scene.settings,
        frame,
        &args.set,
    )?;
    check_memory(scene, &args.scene)?;
    let options = RenderOptions {
        spp: scene.settings.spp,
        time_budget: args.time,
        spp_is_cap: args.spp.is_some(),
        threads: args.threads,
        progress: job.show,
    };
    let mut checkpoint = args.checkpoint.map(|every| {
        brume::render::checkpoint::Checkpoint::new(
            every,
            exr_path.to_path_buf(),
            png_path.to_path_buf(),
            args.exposure,
            args.tonemap,
        )
    });
    let mut display = match &args.display {
        Some(address) => {
            let name = args
                .scene
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_else(|| "render".into());
            Some(brume::render::display::Display::connect(address, &name)?)
        }
        None => None,
    };
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
    if out.image.spp == 0 {
        // Only a stop before the first pass finished gets here: an image of
        // 0 samples is black, and must not replace an earlier render.
        eprintln!(
            "interrupted before the first pass finished: nothing written, {} and {} left as they were",
            exr_path.display(),
            png_path.display()
        );
        return Ok(EXIT_INTERRUPTED);
    }
    out.film.provenance.scene_hash = scene_hash;
    let code = save(job, &out, (exr_path, png_path), checkpoint.as_mut())?;
    if let Some(warning) = display.and_then(|d| d.finish(job.cancel, DISPLAY_FINAL_WAIT)) {
        eprintln!("warning: --display: {warning}");
    }
    Ok(code)
}

/// Writes a finished or stopped render: a stopped one as a partial image,
/// beside a better one if need be (`output_safety::place_partial`); returns the exit code.
fn save(
    job: &Job,
    out: &brume::render::RenderOutput,
    (exr_path, png_path): (&Path, &Path),
    checkpoint: Option<&mut brume::render::checkpoint::Checkpoint>,
) -> Result<i32> {
    use brume::render::output_safety::{place_partial, Placement};
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
    match (&place.exr, &place.png) {
        (Some(exr), Some(png)) => eprintln!(
            "interrupted: saved the {} spp finished before the stop to {} and {}",
            out.image.spp,
            exr.display(),
            png.display()
        ),
        _ => eprintln!(
            "interrupted: the {} spp finished before the stop were not saved",
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

fn run_merge(args: MergeArgs) -> Result<i32> {
    let merged = brume::render::merge_pieces::merge_files(
        &args.pieces,
        &args.out,
        args.png.as_deref(),
        args.denoise,
    )?;
    for note in &merged.notes {
        eprintln!("{note}");
    }
    let p = &merged.film.provenance;
    let (w, h) = merged.film.display;
    let written = match &merged.written {
        Some(path) => path.display().to_string(),
        None => "not written".into(),
    };
    eprintln!(
        "merged {} pieces into {w}x{h} at {} spp{} -> {written}",
        args.pieces.len(),
        p.spp_held(),
        if p.complete() {
            ""
        } else {
            " (incomplete: some pieces were interrupted)"
        },
    );
    // Nothing saved (both files hold better images, said in a note above): not a success.
    Ok(if merged.written.is_some() { 0 } else { 1 })
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

/// `--debug-pixel X,Y`: the samples of one pixel, exactly as a full render takes them.
fn debug_pixel(scene: &brume::integrator::Scene, (x, y): (u32, u32)) -> Result<i32> {
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
            "replays the path tracer's samples only; this scene's [integrator] type is \"bdpt\"",
        ));
    }
    let spp = scene.settings.spp;
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

/// A wrong extension is only a warning: the format follows the flag, not the name.
fn warn_extensions(exr: &Path, png: &Path) {
    for (flag, out, ext) in [("--out", exr, "exr"), ("--png", png, "png")] {
        let matches = out
            .extension()
            .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case(ext));
        if !matches {
            eprintln!(
                "warning: {flag} {}: the file is written as {} but its name does not end in .{ext}",
                out.display(),
                ext.to_uppercase()
            );
        }
    }
}

/// Refuses an image over the memory limit (or more than this machine can
/// give) before rendering: a failed allocation mid-render would abort the
/// process instead of giving an error.
fn check_memory(scene: &brume::integrator::Scene, file: &Path) -> Result<()> {
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let splats = scene.settings.integrator == brume::integrator::IntegratorKind::Bdpt;
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
