//! The airlight demo (`brume airlight`): identical dark and bright targets at
//! increasing distances in haze, measured from the rendered image and
//! compared with Koschmieder's law
//!
//! ```text
//! L(d) = L0·e^(-σt·d) + L_air·(1 - e^(-σt·d)),   V = ln(50)/σt.
//! ```
//!
//! Every target subtends the same angle (its size grows with its distance),
//! and each column holds a bright and a dark target side by side, centred on
//! the horizon. Because the two are identical but for their reflectance (or
//! emission), their difference ΔL(d) = ΔL0·e^(-σt·d) does not depend on L_air,
//! so σt is fitted by weighted least squares of ln ΔL against d.
//!
//! Two configurations:
//! - `Sky`: sun and sky over a homogeneous haze layer (multiple scattering),
//!   diffuse targets: the picture a reader expects. The sun is high so that
//!   the in-scattered light hardly depends on azimuth, and all targets share
//!   one normal so their irradiance is equal; Koschmieder then holds up to the
//!   slight height dependence of the illumination over large targets.
//! - `EmissionAbsorption`: a global absorbing medium (σs = 0) emitting Le and
//!   emissive targets. Then L(d) = L0·e^(-σa·d) + Le·(1 - e^(-σa·d)) exactly,
//!   L_air = Le, which is what the tests check the measurement against.

mod measure;
mod plot;

use measure::{csv, measure, table};
pub use measure::{fit_sigma_t, koschmieder};

use crate::error::{Error, Result};
use crate::film::image_io;
use crate::math::color::Rgb;
use crate::math::Vec2;
use crate::render::{render, RenderOptions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Target distances in metres, one column each.
pub const DISTANCES: [f32; 8] = [10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0, 2000.0];

/// Which lighting and medium the demo uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AirlightMode {
    /// Sun and sky over a scattering haze layer, diffuse targets.
    Sky,
    /// Absorbing, emitting global medium and emissive targets: Koschmieder exactly.
    EmissionAbsorption,
    /// A sun at the zenith over a scattering slab, single scattering only: on
    /// horizontal lines of sight the in-scattered source is constant, so
    /// Koschmieder holds exactly with L_air = α p E e^(-σt·SLAB_TOP).
    SingleScattering,
}

/// Settings of one demo run.
#[derive(Clone, Debug)]
pub struct AirlightOptions {
    /// Folder for the image, CSV, plot and scene (None: write nothing).
    pub out: Option<PathBuf>,
    /// Meteorological visual range V in metres (σt = ln 50 / V).
    pub visibility: f32,
    /// Samples per pixel.
    pub spp: u32,
    /// Image width in pixels (the height is a fifth of it).
    pub width: u32,
    /// Lighting and medium.
    pub mode: AirlightMode,
    /// Seed of the random streams.
    pub seed: u64,
    /// Worker threads (None = all cores).
    pub threads: Option<usize>,
    /// Show a progress bar.
    pub progress: bool,
}

impl Default for AirlightOptions {
    fn default() -> Self {
        AirlightOptions {
            out: Some(PathBuf::from("airlight")),
            visibility: 1000.0,
            spp: 64,
            width: 768,
            mode: AirlightMode::Sky,
            seed: 0,
            threads: None,
            progress: false,
        }
    }
}

/// The mean radiance of one target and its standard error.
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    /// Mean radiance over the target's fully covered pixels.
    pub mean: Rgb,
    /// Standard error of the mean luminance (pixel-to-pixel spread / √pixels).
    pub std_error: f64,
    /// Pixels used.
    pub pixels: usize,
    /// Mean hit distance of those pixels' centre rays (m).
    pub distance: f64,
}

/// One column: the bright and the dark target at one distance.
#[derive(Clone, Copy, Debug)]
pub struct TargetRow {
    /// Nominal distance (m).
    pub distance: f32,
    /// The bright target.
    pub bright: Measured,
    /// The dark target.
    pub dark: Measured,
}

/// What a demo run measured.
#[derive(Clone, Debug)]
pub struct AirlightReport {
    /// One row per distance.
    pub rows: Vec<TargetRow>,
    /// Horizon sky between the targets: L_air.
    pub horizon: Measured,
    /// The true extinction ln 50 / V.
    pub sigma_t_true: f64,
    /// σt fitted from ln(L_bright - L_dark) against distance.
    pub sigma_t_fit: f64,
    /// Standard error of the fit.
    pub sigma_t_fit_std_error: f64,
    /// Rows used in the fit (difference significant at 3 standard errors).
    pub fit_rows: usize,
    /// Exact target radiances at zero distance (bright, dark) and L_air in `EmissionAbsorption` mode.
    pub exact: Option<(f64, f64, f64)>,
    /// Render time in seconds.
    pub render_seconds: f64,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// The table printed by the CLI.
    pub table: String,
}

/// Target luminances at zero distance and the medium emission in `EmissionAbsorption` mode.
const EA_BRIGHT: f32 = 3.0;
const EA_DARK: f32 = 0.2;
const EA_EMISSION: f32 = 1.0;

/// Sun irradiance in `SingleScattering` mode.
pub const SS_IRRADIANCE: f32 = 3.0;
/// Single-scattering albedo of the haze in `SingleScattering` mode.
pub const SS_ALBEDO: f32 = 0.9;
/// Height of the haze slab's top above the eye in `SingleScattering` mode (m).
pub const SLAB_TOP: f32 = 300.0;

/// Image geometry: column pitch and target size in pixels.
struct Layout {
    width: u32,
    height: u32,
    fov: f32,
}

impl Layout {
    fn new(width: u32) -> Layout {
        let height = (width / 5).max(8);
        // 40° horizontally.
        let tan_half_v = (20f32).to_radians().tan() * height as f32 / width as f32;
        Layout {
            width,
            height,
            fov: 2.0 * tan_half_v.atan().to_degrees(),
        }
    }

    fn pitch(&self) -> f32 {
        self.width as f32 / DISTANCES.len() as f32
    }

    /// Side of a target in pixels.
    fn target_pixels(&self) -> f32 {
        0.36 * self.pitch()
    }

    /// Pixel-space centre of the bright (k = 0) or dark (k = 1) target of column i.
    fn target_center(&self, i: usize, k: usize) -> (f32, f32) {
        let x = (i as f32 + 0.5) * self.pitch() + (k as f32 - 0.5) * 0.45 * self.pitch();
        (x, self.height as f32 * 0.5)
    }
}

/// The demo scene as TOML text (also written next to the image).
pub fn scene_text(options: &AirlightOptions) -> String {
    let layout = Layout::new(options.width);
    let sigma_t = 50f64.ln() / options.visibility as f64;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# brume airlight demo ({:?}): visibility {} m, sigma_t = {sigma_t:.6} 1/m",
        options.mode, options.visibility
    );
    let _ = writeln!(
        s,
        "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nfov = {}\nresolution = [{}, {}]\n",
        layout.fov, layout.width, layout.height
    );
    s.push_str(&integrator_lights_and_air(options, sigma_t));
    s.push_str(&target_shapes(options, &layout));
    s
}

/// The `[integrator]`, lights and air of the demo: what differs between modes.
fn integrator_lights_and_air(options: &AirlightOptions, sigma_t: f64) -> String {
    match options.mode {
        AirlightMode::Sky => format!(
            "[integrator]\nspp = {}\nmax_depth = 8\nseed = {}\n\n\
             [[light]]\ntype = \"sun\"\ndirection = [0.0, -1.0, -0.25]\nirradiance = [3.0, 2.9, 2.7]\n\n\
             [[light]]\ntype = \"sky\"\nzenith = [0.12, 0.2, 0.45]\nhorizon = [0.4, 0.45, 0.55]\nground = [0.08, 0.08, 0.07]\n\n\
             # Haze in a layer 300 m deep above the eye, unbounded sideways.\n\
             [[medium]]\ntype = \"homogeneous\"\nsigma_t = {sigma_t:?}\nalbedo = 0.9\nphase = {{ type = \"hg\", g = 0.6 }}\n\
             bounds = {{ type = \"box\", min = [-1.0e5, -1.0e4, -1.0e5], max = [1.0e5, 300.0, 1.0e5] }}\n\n",
            options.spp, options.seed
        ),
        AirlightMode::SingleScattering => format!(
            "[integrator]\nspp = {}\nmax_depth = 1\nmax_scatter_depth = 1\nseed = {}\n\n\
             [[light]]\ntype = \"sun\"\ndirection = [0.0, -1.0, 0.0]\nirradiance = {SS_IRRADIANCE}\nangular_radius = 0.0\n\n\
             # Isotropic haze in a slab {SLAB_TOP} m deep above the eye, unbounded sideways.\n\
             [[medium]]\ntype = \"homogeneous\"\nsigma_t = {sigma_t:?}\nalbedo = {SS_ALBEDO}\n\
             bounds = {{ type = \"box\", min = [-1.0e6, -1.0e4, -1.0e6], max = [1.0e6, {SLAB_TOP}, 1.0e6] }}\n\n",
            options.spp, options.seed
        ),
        AirlightMode::EmissionAbsorption => format!(
            "[integrator]\nspp = {}\nmax_depth = 0\nseed = {}\n\n\
             # Absorbing, emitting air: L_air = emission exactly.\n\
             [[medium]]\ntype = \"homogeneous\"\nsigma_a = {sigma_t:?}\nemission = {EA_EMISSION}\nglobal = true\n\n",
            options.spp, options.seed
        ),
    }
}

/// The bright and dark target quads, one pair per distance, each filling
/// the same angle from the eye.
fn target_shapes(options: &AirlightOptions, layout: &Layout) -> String {
    let camera = crate::camera::Camera::new(
        crate::math::Vec3::ZERO,
        -crate::math::Vec3::Z,
        crate::math::Vec3::Y,
        layout.fov,
        layout.width,
        layout.height,
    )
    .expect("fixed camera frame");
    let side_tan =
        layout.target_pixels() * 2.0 * (layout.fov.to_radians() * 0.5).tan() / layout.height as f32;
    // One normal for all: equal sun and sky irradiance on every target.
    let n = crate::math::Vec3::new(0.0, 0.3, 1.0).normalize();
    let mut s = String::new();
    for (i, &d) in DISTANCES.iter().enumerate() {
        for k in 0..2 {
            let (x, y) = layout.target_center(i, k);
            let ray = camera.generate_ray(
                x.floor() as u32,
                y.floor() as u32,
                Vec2::new(x.fract(), y.fract()),
            );
            let c = ray.direction * d;
            let size = d * side_tan;
            let _ = writeln!(
                s,
                "# {} target at {d} m\n[[shape]]\ntype = \"quad\"\ncenter = [{}, {}, {}]\nnormal = [{}, {}, {}]\n\
                 u_axis = [1.0, 0.0, 0.0]\nsize = [{size}, {size}]\nmaterial = {}\n",
                if k == 0 { "bright" } else { "dark" },
                c.x, c.y, c.z, n.x, n.y, n.z,
                target_material(options.mode, k)
            );
        }
    }
    s
}

/// The material of the bright (k = 0) or dark target in a mode.
fn target_material(mode: AirlightMode, k: usize) -> String {
    match (mode, k) {
        (AirlightMode::Sky | AirlightMode::SingleScattering, 0) => {
            "{ type = \"diffuse\", albedo = 0.8 }".to_string()
        }
        (AirlightMode::Sky | AirlightMode::SingleScattering, _) => {
            "{ type = \"diffuse\", albedo = 0.04 }".to_string()
        }
        (AirlightMode::EmissionAbsorption, _) => {
            let l = if k == 0 { EA_BRIGHT } else { EA_DARK };
            format!("{{ type = \"diffuse\", albedo = 0.0 }}\nemission = {l}")
        }
    }
}

/// Largest `--width`: the image is width × width/5 pixels, at most 32768 a side.
const MAX_WIDTH: u32 = 32768;

/// The demo scene and its TOML, built from the options. The user never wrote it:
/// an error in it is reported under the flag that made the value.
fn demo_scene(options: &AirlightOptions) -> Result<(crate::integrator::Scene, String)> {
    let text = scene_text(options);
    let file = PathBuf::from("airlight.toml");
    crate::scene::parse(&text, &file)
        .and_then(|desc| crate::scene::build(&desc, &file, Path::new(".")))
        .map(|scene| (scene, text.clone()))
        .map_err(|e| match e {
            Error::Scene { field, message, .. } => {
                let flag = match field.split(['.', '[']).next().unwrap_or("") {
                    "camera" | "shape" => "--width",
                    "medium" => "--visibility",
                    "integrator" => "--spp",
                    _ => "--width/--visibility/--spp",
                };
                Error::Argument {
                    argument: flag.into(),
                    message: format!(
                        "the demo scene made from --width {} --visibility {:?} --spp {} is invalid: {message}",
                        options.width, options.visibility, options.spp
                    ),
                }
            }
            other => other,
        })
}

/// The files `brume airlight --out DIR` writes into DIR.
pub const OUTPUT_FILES: [&str; 5] = [
    "airlight.exr",
    "airlight.png",
    "airlight.csv",
    "airlight_plot.png",
    "airlight.toml",
];

/// Before rendering: `dir` is a folder (created if missing) and its five
/// output files pass the output-safety rule (writable, five different files).
fn prepare_outputs(dir: &Path) -> Result<()> {
    let flag = || "--out".to_string();
    if dir.exists() && !dir.is_dir() {
        return Err(Error::Argument {
            argument: flag(),
            message: format!(
                "{} exists and is not a folder; airlight writes {} files into a folder",
                dir.display(),
                OUTPUT_FILES.len()
            ),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::Argument {
        argument: flag(),
        message: format!("cannot create the folder {}: {e}", dir.display()),
    })?;
    let mut plan = crate::film::output_safety::Plan::new("airlight demo");
    for name in OUTPUT_FILES {
        plan.output("--out", &dir.join(name), None);
    }
    plan.check()
}

/// Renders the demo, measures every target, fits σt and writes the outputs.
pub fn run(options: &AirlightOptions) -> Result<AirlightReport> {
    validate(options)?;
    let (scene, text) = demo_scene(options)?;
    let (w, h) = (scene.camera.width(), scene.camera.height());
    let bytes = crate::render::peak_bytes(w, h) as u128;
    crate::error::limits::check(bytes).map_err(|refusal| {
        let needs = crate::error::limits::format_bytes(bytes);
        argument_error(
            "--width",
            &format!("a {w}x{h} image needs {needs} of memory, {refusal}"),
        )
    })?;
    let render_options = RenderOptions {
        spp: options.spp,
        time_budget: None,
        spp_is_cap: false,
        threads: options.threads,
        progress: options.progress,
    };
    if let Some(dir) = &options.out {
        prepare_outputs(dir)?;
    }
    let out = render(&scene, &render_options, &AtomicBool::new(false));
    let mut report = measure(&scene, &out.image, options);
    report.render_seconds = out.elapsed.as_secs_f64();
    report.table = table(&report);
    if let Some(dir) = &options.out {
        report.files = write_outputs(dir, &out.image, &report, &text)?;
    }
    Ok(report)
}

/// An error under the command-line flag `flag`.
fn argument_error(flag: &str, message: &str) -> Error {
    Error::Argument {
        argument: flag.into(),
        message: message.into(),
    }
}

/// The flags' values are ones the demo can be built from.
fn validate(options: &AirlightOptions) -> Result<()> {
    if !(options.visibility.is_finite() && options.visibility > 0.0) {
        return Err(argument_error(
            "--visibility",
            "must be a positive number of metres",
        ));
    }
    if options.spp == 0 {
        return Err(argument_error("--spp", "must be at least 1"));
    }
    if options.width < 64 {
        return Err(argument_error("--width", "must be at least 64 pixels"));
    }
    if options.width > MAX_WIDTH {
        return Err(argument_error(
            "--width",
            &format!("must be at most {MAX_WIDTH} pixels (brume renders at most 32768 a side)"),
        ));
    }
    // σt = ln 50 / V must be a finite single-precision number
    if 50f64.ln() / options.visibility as f64 > f32::MAX as f64 {
        return Err(argument_error(
            "--visibility",
            "must be at least 1.2e-38 metres (ln 50 / visibility must fit single precision)",
        ));
    }
    Ok(())
}

/// Writes the five output files into `dir`; returns their paths.
fn write_outputs(
    dir: &Path,
    image: &image_io::Image,
    report: &AirlightReport,
    text: &str,
) -> Result<Vec<PathBuf>> {
    let write_text = |name: &str, body: &str| -> Result<PathBuf> {
        let path = dir.join(name);
        image_io::write_text(&path, body)?;
        Ok(path)
    };
    let exr = dir.join("airlight.exr");
    image_io::write_exr(&exr, image)?;
    let png = dir.join("airlight.png");
    image_io::write_png(&png, image, 0.0)?;
    let plot_path = dir.join("airlight_plot.png");
    let pixels = plot::draw(report).map_err(|message| Error::Output {
        path: plot_path.clone(),
        message,
    })?;
    image_io::write_png_srgb8(&plot_path, plot::WIDTH, plot::HEIGHT, &pixels)?;
    Ok(vec![
        exr,
        png,
        write_text("airlight.csv", &csv(report))?,
        plot_path,
        write_text("airlight.toml", text)?,
    ])
}
