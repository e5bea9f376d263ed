//! The flags of `brume render` and the checks on them that do not need the
//! scene, shared by a still and a frame sequence.

use brume::error::{Error, Result};
use brume::film::tonemap::Tonemap;
use brume::integrator::aov::Aov;
use brume::render::cli_values as values;
use std::path::{Path, PathBuf};
use std::time::Duration;

#[derive(clap::Args)]
pub(crate) struct RenderArgs {
    /// The scene file (TOML).
    pub(crate) scene: PathBuf,
    /// Set a scene value before validation, as TOML (repeatable): `--set camera.resolution=[640,360]
    /// --set integrator.spp=64 --set shape[2].material.albedo=0.5`; a bare word is a string.
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = values::set)]
    pub(crate) set: Vec<brume::scene::Override>,
    /// Samples per pixel (overrides the scene's integrator.spp).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::whole(1u32, u32::MAX))]
    pub(crate) spp: Option<u32>,
    /// Maximum path depth (overrides integrator.max_depth).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::whole(0u32, u32::MAX))]
    pub(crate) max_depth: Option<u32>,
    /// Seed of the random streams (overrides integrator.seed).
    #[arg(long, allow_negative_numbers = true, value_name = "S", value_parser = values::whole(0u64, u64::MAX))]
    pub(crate) seed: Option<u64>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::threads)]
    pub(crate) threads: Option<usize>,
    /// EXR output (default: NAME.exr in the current folder).
    #[arg(long)]
    pub(crate) out: Option<PathBuf>,
    /// PNG preview (default: NAME.png in the current folder).
    #[arg(long)]
    pub(crate) png: Option<PathBuf>,
    /// Render progressive passes until this many seconds are spent (--spp then caps it).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = values::seconds)]
    pub(crate) time: Option<Duration>,
    /// Stop once the estimated relative error of the image reaches TARGET (e.g. 0.02; README
    /// "Adaptive sampling"); --spp then caps each pixel's samples, --time the whole render.
    #[arg(long, value_name = "TARGET", allow_negative_numbers = true, value_parser = values::noise)]
    pub(crate) noise: Option<f32>,
    /// Spread the samples over the pixels by a pilot pass's error estimates: on or off
    /// (default: the scene's integrator.adaptive, else on with a noise target and, without
    /// one, on where the pilot predicts less error; README "Adaptive sampling").
    #[arg(long, value_name = "on|off", value_parser = values::on_off)]
    pub(crate) adaptive: Option<bool>,
    /// Tone curve of the PNG preview: aces (filmic, rolls highlights off) or clip.
    #[arg(long, value_enum, default_value_t = Tonemap::Aces)]
    pub(crate) tonemap: Tonemap,
    /// Exposure of the PNG preview in stops.
    #[arg(long, value_name = "STOPS", default_value = "0", allow_negative_numbers = true, value_parser = values::exposure)]
    pub(crate) exposure: f32,
    /// No progress bar and no summary.
    #[arg(long, short)]
    pub(crate) quiet: bool,
    /// AOVs written as extra EXR layers, comma-separated: alpha,depth,normal,albedo,transmittance
    /// (replaces the scene's [film] aovs; "none" for none).
    #[arg(long, value_name = "LIST", value_parser = values::aovs)]
    pub(crate) aovs: Option<values::Aovs>,
    /// Denoise the beauty with Intel Open Image Denoise into a `denoised` layer
    /// (adds the albedo and normal AOVs; needs a build with `--features denoise`).
    /// A piece of a split render records the albedo and normal only: denoise with `brume merge --denoise`.
    #[arg(long)]
    pub(crate) denoise: bool,
    /// Stream every finished pass to the tev image viewer listening at HOST:PORT (tev's default port is 14158).
    #[arg(long, value_name = "HOST:PORT", value_parser = values::host_port)]
    pub(crate) display: Option<String>,
    /// Rewrite the EXR and PNG (marked incomplete) every SECONDS during the render.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = values::seconds)]
    pub(crate) checkpoint: Option<Duration>,
    /// Replay one pixel X,Y (column, row from the top): print its samples' statistics, write no image.
    #[arg(long, value_name = "X,Y", value_parser = values::pixel)]
    pub(crate) debug_pixel: Option<(u32, u32)>,
    /// For a bdpt scene, also write each strategy's weighted and unweighted
    /// contribution images into DIR (s2_t1_weighted.exr, ...), retracing the render's samples.
    #[arg(long, value_name = "DIR")]
    pub(crate) debug_strategies: Option<PathBuf>,
    /// Render a frame sequence: `1-100`, `1,3,7-20:2`; outputs take the #### pattern of --out/--png
    /// (default NAME.####.exr and NAME.####.png).
    #[arg(long, value_name = "LIST", allow_hyphen_values = true, value_parser = values::frames)]
    pub(crate) frames: Option<values::Frames>,
    /// With --frames, skip frames whose EXR exists and is marked complete.
    #[arg(long, requires = "frames")]
    pub(crate) skip_existing: bool,
    #[command(flatten)]
    pub(crate) split: brume::render::split::SplitArgs,
}

/// Applies --spp, --max-depth, --seed, --aovs and --denoise to a loaded scene.
pub(crate) fn apply_overrides(
    scene: &mut brume::integrator::Scene,
    args: &RenderArgs,
) -> Result<()> {
    if let Some(spp) = args.spp {
        scene.settings.spp = spp;
    }
    if let Some(d) = args.max_depth {
        scene.settings.max_depth = d;
    }
    if let Some(seed) = args.seed {
        scene.settings.seed = seed;
    }
    apply_adaptive(scene, args)?;
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
    if !scene.aovs.is_empty() && !scene.geometry.slabs().is_empty() {
        let flag = if args.denoise { "--denoise" } else { "--aovs" };
        return Err(argument(
            flag,
            "the AOVs do not see slab shapes yet; render a scene with slabs without AOVs",
        ));
    }
    Ok(())
}

/// The automatic choice is a default, never an error: dropped where a flag
/// decides, or for a piece of a split render (a sample range from 0 looks
/// whole to the renderer, whose own guard, `Run::may_pilot`, sees the rest:
/// crops, later sample ranges, too few samples).
fn keep_auto_where_it_may_pilot(scene: &mut brume::integrator::Scene, args: &RenderArgs) {
    let a = &mut scene.settings.adaptive;
    a.auto &= args.noise.is_none() && args.adaptive.is_none() && !args.split.is_piece();
}

/// Applies --noise and --adaptive, refusing them where they cannot apply.
fn apply_adaptive(scene: &mut brume::integrator::Scene, args: &RenderArgs) -> Result<()> {
    use brume::integrator::IntegratorKind;
    let a = &mut scene.settings.adaptive;
    if let Some(noise) = args.noise {
        a.noise = Some(noise);
        a.adaptive = true;
    }
    if let Some(on) = args.adaptive {
        a.adaptive = on;
    }
    keep_auto_where_it_may_pilot(scene, args);
    let settings = scene.settings;
    if !settings.adaptive.piloted() {
        return Ok(());
    }
    // A flag is named by itself; the scene's keys were checked with the scene.
    let flag = match (args.noise, args.adaptive) {
        (Some(_), _) => "--noise",
        (None, Some(_)) => "--adaptive",
        (None, None) => "",
    };
    if !flag.is_empty() && !matches!(settings.integrator, IntegratorKind::Path) {
        return Err(argument(
            flag,
            "adaptive sampling and noise targets take the path tracer's pixel samples: \
             the scene's integrator.type must be \"path\"",
        ));
    }
    if args.split.is_piece() {
        let (name, what) = match flag {
            "" => (
                "--samples",
                "the scene's integrator.noise or integrator.adaptive",
            ),
            f => (f, "adaptive sampling and noise targets"),
        };
        return Err(argument(
            name,
            &format!(
                "a piece of a split render (--crop, --samples, --task-count) holds the same \
                 samples in every pixel, which {what} would not; render in one piece, or set \
                 --adaptive off without a noise target"
            ),
        ));
    }
    let min = brume::render::adaptive::MIN_SPP;
    if settings.spp < min {
        return Err(argument(
            if flag.is_empty() { "--spp" } else { flag },
            &format!(
                "adaptive sampling and noise targets need at least {min} samples per pixel \
                 (--spp or integrator.spp), got {}",
                settings.spp
            ),
        ));
    }
    Ok(())
}

/// Checks the combinations of flags that do not depend on the scene (each value is checked by its parser).
pub(crate) fn check_render_args(args: &RenderArgs) -> Result<()> {
    if args.split.is_piece() && args.time.is_some() {
        return Err(argument(
            "--time",
            "a piece (--crop, --samples, --task-count) renders a fixed sample range; leave out --time",
        ));
    }
    Ok(())
}

pub(crate) fn argument(name: &str, message: &str) -> Error {
    Error::Argument {
        argument: name.into(),
        message: message.into(),
    }
}

/// A wrong extension is only a warning: the format follows the flag, not the name.
pub(crate) fn warn_extensions(exr: &Path, png: &Path) {
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
