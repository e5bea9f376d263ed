//! Scene files: parsing TOML into a `SceneDesc`, validating it with errors
//! that name the file and field, and building the runtime `Scene`.

mod adaptive_keys;
pub mod animation;
mod build_shapes;
mod camera;
mod coefficients;
pub mod description;
mod envmap;
mod files;
mod fog;
pub mod input_cache;
pub mod inputs;
mod interfaces;
mod interior;
mod keyframes;
mod lights;
mod materials;
mod media;
mod messages;
pub mod mitsuba;
mod mlt_keys;
mod overflow;
mod overrides;
mod ply;
mod shapes;
mod slab_keys;
mod sppm_keys;
mod textures;
mod validate;
pub use input_cache::InputCache;
pub use overrides::Override;
pub use slab_keys::{SlabSpec, DEFAULT_ANGULAR, DEFAULT_SPATIAL};
pub mod vdb;
mod vdb_emission;
mod vdb_grids;
mod vol;

use crate::error::{Error, Result};
use crate::integrator::sun_lobe::{self, SunLobe};
use crate::integrator::tracking::MAX_OVERLAPPING_MEDIA;
use crate::integrator::{IntegratorKind, Scene, Settings, TransmittanceEstimator};
use crate::light::{Light, LightPick};
use crate::sampling::SamplerKind;
use adaptive_keys::build_adaptive;
use camera::build_camera;
use description::SceneDesc;
use lights::{build_lights, light_powers, nee_pick, sky_control, smooth_sky_beside_others};
use mlt_keys::{build_mlt, warn_mlt_keys};
use std::path::{Path, PathBuf};
use validate::Check;

/// Reads, validates and builds the scene in `path`.
pub fn load(path: &Path) -> Result<Scene> {
    load_with_inputs(path).map(|loaded| loaded.scene)
}

/// A loaded scene with what the command line needs around it.
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// Every file the scene reads: the scene file, its OBJ, texture, environment map and VDB files.
    pub inputs: Vec<PathBuf>,
    /// Warnings, each `FILE: FIELD: message`: valid values that probably are not what was meant.
    pub warnings: Vec<String>,
    /// The box and grid of `[slab]`, for `brume slab bake`.
    pub slab: Option<SlabSpec>,
}

/// [`load`], with the scene's input files and warnings.
pub fn load_with_inputs(path: &Path) -> Result<Loaded> {
    load_frame_with_inputs(path, None)
}

/// [`load_frame`], with the frame's input files and warnings.
pub fn load_frame_with_inputs(path: &Path, frame: Option<i64>) -> Result<Loaded> {
    load_frame_with_overrides(path, frame, &[])
}

/// [`load_frame_with_inputs`] with `--set` values; an error in a value they
/// set says so, naming the `--set` that set it.
pub fn load_frame_with_overrides(
    path: &Path,
    frame: Option<i64>,
    overrides: &[Override],
) -> Result<Loaded> {
    load_frame_cached(path, frame, overrides, &InputCache::new())
}

/// [`load_frame_with_overrides`] taking unchanged inputs (slab files) from
/// `cache`, and keeping what it reads there: the frames of a sequence share one.
pub fn load_frame_cached(
    path: &Path,
    frame: Option<i64>,
    overrides: &[Override],
    cache: &InputCache,
) -> Result<Loaded> {
    load_overridden(path, frame, overrides, cache)
        .map_err(|e| overrides::name_the_set(e, overrides))
}

/// [`load_frame_cached`] before errors are attributed.
fn load_overridden(
    path: &Path,
    frame: Option<i64>,
    overrides: &[Override],
    cache: &InputCache,
) -> Result<Loaded> {
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    if mitsuba::is_mitsuba(path) {
        return load_mitsuba(path, &base, frame, overrides);
    }
    let text = read_scene_text(path)?;
    let desc = parse_with_overrides(&text, path, overrides)?;
    let (scene, warnings) = build_frame_cached(&desc, path, &base, frame, cache)?;
    let slab = slab_keys::build_slab_table(&desc, &Check::new(path))?;
    let inputs = inputs::files_read(&desc, path, frame)
        .into_iter()
        .map(|f| f.path)
        .collect();
    Ok(Loaded {
        scene,
        inputs,
        warnings,
        slab,
    })
}

/// A Mitsuba 3 XML scene: imported into a description, then built as TOML
/// scenes are; `--set name=value` overrides its `<default name>`.
fn load_mitsuba(
    path: &Path,
    base: &Path,
    frame: Option<i64>,
    overrides: &[Override],
) -> Result<Loaded> {
    let imported = mitsuba::import(path, mitsuba_defaults(overrides))?;
    let (scene, mut warnings) =
        build_frame(&imported.desc, path, base, frame).map_err(|e| imported.locate(e))?;
    let mut inputs: Vec<PathBuf> = imported.files.clone();
    inputs.extend(
        inputs::files_read(&imported.desc, path, frame)
            .into_iter()
            .skip(1)
            .map(|f| f.path),
    );
    warnings.splice(0..0, imported.warnings);
    // Mitsuba has no light-slab table: an imported scene cannot be baked.
    Ok(Loaded {
        scene,
        inputs,
        warnings,
        slab: None,
    })
}

/// `brume info scene.xml`: what each element of a Mitsuba scene became,
/// after the scene has been built (so a scene brume cannot build is an error).
pub fn mitsuba_info(path: &Path) -> Result<String> {
    let imported = mitsuba::import(path, Vec::new())?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let (_, warnings) =
        build_frame(&imported.desc, path, &base, None).map_err(|e| imported.locate(e))?;
    let mut out = format!("{}: Mitsuba 3 scene\n", path.display());
    for file in imported.files.iter().skip(1) {
        out.push_str(&format!("included: {}\n", file.display()));
    }
    for line in &imported.summary {
        out.push_str(&format!("{line}\n"));
    }
    for w in imported.warnings.iter().chain(&warnings) {
        out.push_str(&format!("warning: {w}\n"));
    }
    Ok(out)
}

/// `--set name=value` as the `$name` of a Mitsuba scene (text as written, quotes removed).
pub fn mitsuba_defaults(overrides: &[Override]) -> Vec<(String, String)> {
    overrides
        .iter()
        .map(|o| {
            let value = match &o.value {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            (o.key.clone(), value)
        })
        .collect()
}

/// Largest scene file read (scene files are hand-written; meshes go in OBJ files).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The text of a scene file, refusing what is not a regular file of sane size.
fn read_scene_text(path: &Path) -> Result<String> {
    let input = |message: String| Error::Input {
        path: path.to_path_buf(),
        message,
    };
    if let Some(problem) = crate::error::input_file_problem(path, MAX_SCENE_BYTES) {
        return Err(input(format!("cannot read scene file: {problem}")));
    }
    std::fs::read_to_string(path).map_err(|e| input(format!("cannot read scene file: {e}")))
}

/// Parses scene TOML; errors carry the line (syntax) or the dotted path of the culprit.
pub fn parse(text: &str, file: &Path) -> Result<SceneDesc> {
    parse_with_overrides(text, file, &[])
}

/// [`parse`] with `--set` values applied to the TOML before anything reads
/// it; an error in a value they set names the `--set`.
pub fn parse_with_overrides(text: &str, file: &Path, overrides: &[Override]) -> Result<SceneDesc> {
    parse_overridden(text, file, overrides).map_err(|e| overrides::name_the_set(e, overrides))
}

/// [`parse_with_overrides`] before errors are attributed.
fn parse_overridden(text: &str, file: &Path, overrides: &[Override]) -> Result<SceneDesc> {
    let scene_error = |field: String, message: String| Error::Scene {
        file: file.to_path_buf(),
        field,
        message,
    };
    let mut table: toml::Table = toml::from_str(text).map_err(|e| {
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].lines().count().max(1))
            .unwrap_or(1);
        scene_error(
            format!("line {line}"),
            e.message().trim().replace('\n', " "),
        )
    })?;
    overrides::apply(&mut table, overrides)
        .map_err(|(field, message)| scene_error(field, message))?;
    for (key, value) in table.iter() {
        animation::reject_keyframes(value, key)
            .map_err(|(field, message)| scene_error(field, message))?;
    }
    check_table_shapes(&table).map_err(|(field, message)| scene_error(field, message))?;
    for (key, value) in table.iter_mut() {
        retag(value, key, key).map_err(|(field, message)| scene_error(field, message))?;
    }
    let media_key = match table.contains_key("media") {
        true => "media",
        false => "medium",
    };
    let desc: SceneDesc =
        serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
            let mut field = field_path(e.path());
            let message = messages::user_words(e.into_inner().message());
            // a `type` was rewritten into a variant key by `retag`: name the key the user wrote
            let last_key = field.rsplit('.').next().unwrap_or("");
            let last_key = last_key.split('[').next().unwrap_or("");
            if message.starts_with("unknown value") && TAGGED_KEYS.contains(&last_key) {
                field.push_str(".type");
            }
            scene_error(
                if field.is_empty() {
                    "scene".into()
                } else {
                    field
                },
                message,
            )
        })?;
    Ok(SceneDesc { media_key, ..desc })
}

/// What a TOML value is, in TOML's words (`a string "diffuse"`, `an array`).
fn toml_kind(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("a string \"{s}\""),
        toml::Value::Integer(i) => format!("the number {i}"),
        toml::Value::Float(f) => format!("the number {f}"),
        toml::Value::Boolean(b) => format!("{b}"),
        toml::Value::Datetime(_) => "a date".into(),
        toml::Value::Array(_) => "an array".into(),
        toml::Value::Table(_) => "a table".into(),
    }
}

/// A table written as the user would write it, for "expected ..." messages.
fn table_example(key: &str) -> &'static str {
    match key {
        "material" => "{ type = \"diffuse\", albedo = 0.5 }",
        "phase" => "{ type = \"hg\", g = 0.3 }",
        "bounds" => "{ type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }",
        "transform" => "{ translate = [0.0, 1.0, 0.0] }",
        "interior" => "{ type = \"homogeneous\", sigma_t = 1.0 }",
        _ => "{ ... }",
    }
}

/// Checks that tables are written as tables before serde sees them: its
/// messages for a string or array in their place name Rust types
/// (`expected struct CameraDesc`), not what to write.
fn check_table_shapes(top: &toml::Table) -> std::result::Result<(), (String, String)> {
    for key in ["camera", "integrator"] {
        if let Some(v) = top.get(key) {
            if !v.is_table() {
                return Err((
                    key.into(),
                    format!(
                        "expected one [{key}] table, got {} (write [{key}], not [[{key}]])",
                        toml_kind(v)
                    ),
                ));
            }
        }
    }
    for key in ["light", "shape", "medium", "media"] {
        match top.get(key) {
            None => {}
            Some(toml::Value::Array(items)) => {
                for (i, item) in items.iter().enumerate() {
                    let toml::Value::Table(t) = item else {
                        return Err((
                            format!("{key}[{i}]"),
                            format!("expected a [[{key}]] table, got {}", toml_kind(item)),
                        ));
                    };
                    for inner in ["material", "phase", "bounds", "transform"] {
                        if let Some(v) = t.get(inner).filter(|v| !v.is_table()) {
                            return Err((
                                format!("{key}[{i}].{inner}"),
                                format!(
                                    "expected a table like {}, got {}",
                                    table_example(inner),
                                    toml_kind(v)
                                ),
                            ));
                        }
                    }
                }
            }
            Some(v) => {
                return Err((
                    key.into(),
                    format!(
                        "expected [[{key}]] tables (an array of tables), got {} (write [[{key}]], not [{key}])",
                        toml_kind(v)
                    ),
                ))
            }
        }
    }
    Ok(())
}

/// Keys whose tables carry a `type` that selects an enum variant.
const TAGGED_KEYS: [&str; 7] = [
    "light", "medium", "media", "material", "phase", "bounds", "interior",
];

/// Rewrites every `{ type = "name", ... }` table under a tagged key into
/// `{ name = { ... } }`; returns (field path, message) for a missing or bad `type`.
fn retag(
    value: &mut toml::Value,
    key: &str,
    path: &str,
) -> std::result::Result<(), (String, String)> {
    let nested_tagged = TAGGED_KEYS.contains(&key) && !TOP_LEVEL_LISTS.contains(&key);
    match value {
        toml::Value::Array(_) if nested_tagged => {
            return Err((
                path.to_string(),
                format!("expected a table like {}, got an array", table_example(key)),
            ));
        }
        toml::Value::Array(items) => {
            for (i, item) in items.iter_mut().enumerate() {
                retag(item, key, &format!("{path}[{i}]"))?;
            }
        }
        toml::Value::Table(table) => retag_table(table, key, path)?,
        toml::Value::Datetime(d) => {
            // toml hands a date to serde as a table with a private key, which no message explains
            return Err((
                path.to_string(),
                format!(
                    "expected a number, a string, an array or a table, got the date or time {d} \
                     (no key takes one; quote it to make it a string)"
                ),
            ));
        }
        v if nested_tagged => {
            return Err((
                path.to_string(),
                format!(
                    "expected a table like {}, got {}",
                    table_example(key),
                    toml_kind(v)
                ),
            ));
        }
        _ => {}
    }
    Ok(())
}

/// Retags the children of `table` (at `path`), then `table` itself when `key` is a tagged key.
fn retag_table(
    table: &mut toml::map::Map<String, toml::Value>,
    key: &str,
    path: &str,
) -> std::result::Result<(), (String, String)> {
    for (child_key, child) in table.iter_mut() {
        let child_path = if path.is_empty() {
            child_key.clone()
        } else {
            format!("{path}.{child_key}")
        };
        retag(child, child_key, &child_path)?;
    }
    if TAGGED_KEYS.contains(&key) {
        let name = match table.remove("type") {
            Some(toml::Value::String(name)) => name,
            Some(v) => {
                return Err((
                    format!("{path}.type"),
                    format!("expected a type name in quotes, got {}", toml_kind(&v)),
                ))
            }
            None => return Err((path.to_string(), "missing key `type`".into())),
        };
        let inner = std::mem::take(table);
        table.insert(name, toml::Value::Table(inner));
    }
    Ok(())
}

/// Top-level keys holding arrays of tables (`check_table_shapes` checks their items).
const TOP_LEVEL_LISTS: [&str; 4] = ["light", "shape", "medium", "media"];

/// `light[0].intensity[1]` from a serde path, leaving out enum variant names.
fn field_path(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    for segment in path.iter() {
        match segment {
            Segment::Seq { index } => out.push_str(&format!("[{index}]")),
            Segment::Map { key } => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(key);
            }
            Segment::Enum { .. } | Segment::Unknown => {}
        }
    }
    out
}

/// Builds the runtime scene from a parsed description (a still: frame patterns are refused).
pub fn build(desc: &SceneDesc, file: &Path, base: &Path) -> Result<Scene> {
    build_with_warnings(desc, file, base).map(|(scene, _)| scene)
}

/// [`build`], with the warnings about values that are valid but probably not meant.
pub fn build_with_warnings(
    desc: &SceneDesc,
    file: &Path,
    base: &Path,
) -> Result<(Scene, Vec<String>)> {
    build_frame(desc, file, base, None)
}

/// Reads, validates and builds the scene in `path` for `frame` (frame patterns resolved).
pub fn load_frame(path: &Path, frame: Option<i64>) -> Result<Scene> {
    load_frame_with_inputs(path, frame).map(|loaded| loaded.scene)
}

/// Builds the runtime scene for `frame` (`None` for a still), with its warnings.
pub fn build_frame(
    desc: &SceneDesc,
    file: &Path,
    base: &Path,
    frame: Option<i64>,
) -> Result<(Scene, Vec<String>)> {
    build_frame_cached(desc, file, base, frame, &InputCache::new())
}

/// [`build_frame`] taking unchanged slab files from `cache` (and keeping
/// those it reads there).
pub fn build_frame_cached(
    desc: &SceneDesc,
    file: &Path,
    base: &Path,
    frame: Option<i64>,
    cache: &InputCache,
) -> Result<(Scene, Vec<String>)> {
    let check = Check::new(file).with_key_time_origin(key_time_origin(desc, frame));
    let camera = build_camera(desc, &check)?;
    check.positive_int("integrator.spp", desc.integrator.spp)?;
    if desc.shapes.is_empty() && desc.lights.is_empty() && desc.media.is_empty() {
        return Err(check.error("scene", "the scene is empty: no shape, light or medium"));
    }
    let timing = build_timing(desc, &check, frame)?;
    // Checked for every command, used by `brume slab bake` (see `Loaded::slab`).
    slab_keys::build_slab_table(desc, &check)?;
    let mut settings = build_settings(desc, &check, timing.shutter)?;
    let shapes = build_shapes::build_shapes(desc, &check, (base, cache), &timing)?;
    let eye = crate::math::Vec3::from_array(desc.camera.position);
    slab_keys::check_slab_use(desc, shapes.geometry.slabs(), eye, &check)?;
    let (lights, shape_lights) =
        build_lights(desc, &check, base, &shapes.geometry, shapes.emissions)?;
    let media = build_media(desc, &check, base, &timing, shapes.interiors)?;
    // A slab shape's baked light holds the sky; a `[slab]` table's bake traces lines
    // that must meet the sky itself (`integrator::li_from_inside`).
    let has_slabs = !shapes.geometry.slabs().is_empty() || desc.slab.is_some();
    let interfaces = interfaces::build(desc, &check, &mut settings)?;
    let power = light_powers(&lights, &shapes.geometry, &camera);
    let sky_control = sky_control(desc, &check, (&lights, &power), &media, has_slabs)?;
    let light_pick = LightPick::new(&power);
    let nee_pick = build_nee_pick(desc, &check, &lights, &power, sky_control.is_some())?;
    choose_strategies(desc, &check, &mut settings, (&lights, &media, &camera))?;
    let scene = Scene {
        camera,
        geometry: shapes.geometry,
        shape_materials: shapes.materials,
        shape_textures: shapes.textures,
        shape_lights,
        lights,
        light_pick,
        nee_pick,
        media,
        interfaces,
        settings,
        aovs: build_aovs(&desc.film.aovs, &check)?,
        sky_control,
    };
    Ok((scene, check.take_warnings()))
}

/// The sampling strategies that depend on the scene's lights and media:
/// equiangular sampling, forced in-scattering's default and the sun lobe.
fn choose_strategies(
    desc: &SceneDesc,
    check: &Check,
    settings: &mut Settings,
    (lights, media, camera): (&[Light], &[crate::medium::Medium], &crate::camera::Camera),
) -> Result<()> {
    // Equiangular sampling aims at point and spot lights: without any, no segment needs the search.
    settings.equiangular &= lights.iter().any(|l| l.point_position().is_some());
    if desc.integrator.forced_scattering.is_none() {
        settings.forced_scattering =
            !camera_in_a_medium(media, camera) && !lights.iter().any(|l| l.is_infinite());
    }
    settings.sun_lobe = SunLobe::choose(sun_lobe_share(desc, check)?, lights);
    Ok(())
}

/// `integrator.sun_lobe`: the sun lobe's share of the first medium
/// scatterings' continuations ([`SunLobe`]), 0 to [`sun_lobe::MAX_SHARE`].
fn sun_lobe_share(desc: &SceneDesc, check: &Check) -> Result<f32> {
    match desc.integrator.sun_lobe {
        Some(v) => check.range("integrator.sun_lobe", v, 0.0, sun_lobe::MAX_SHARE, true),
        None => Ok(sun_lobe::DEFAULT_SHARE),
    }
}

/// The path tracer's next-event pick ([`nee_pick`]) over `lights` of
/// powers `power`, with the key `integrator.environment_share` (0 where the
/// sky is a control variate), warning where the key can change nothing.
fn build_nee_pick(
    desc: &SceneDesc,
    check: &Check,
    lights: &[Light],
    power: &[f32],
    sky_controlled: bool,
) -> Result<LightPick> {
    let share = environment_share_key(desc, check)?;
    let sky = smooth_sky_beside_others(lights);
    if share.is_some() && matches!(desc.integrator.kind.as_str(), "bdpt" | "mlt") {
        let message = format!(
            "is a path-tracer setting, ignored by type = \"{}\" (its strategies pick lights by power)",
            desc.integrator.kind
        );
        check.warn("integrator.environment_share", message);
    } else if share.is_some() && sky.is_none() {
        check.warn(
            "integrator.environment_share",
            "has no effect: the scene has no constant or sky environment beside other lights",
        );
    }
    if share.is_some() && sky_controlled {
        check.warn(
            "integrator.environment_share",
            "has no effect: integrator.sky_control takes the sky out of the light samples",
        );
    }
    // Under `integrator.sky_control` the path tracer never samples the
    // environment (a map too, which otherwise keeps its share by power).
    if sky_controlled {
        let environment = lights.iter().position(Light::is_environment);
        return Ok(nee_pick(power, environment, Some(0.0)));
    }
    Ok(nee_pick(power, sky, share))
}

/// `integrator.environment_share`: a fixed probability in [0, 1) for the
/// path tracer's light samples to ask a constant or sky environment, or
/// `None` (absent) for the rule of [`crate::light::environment_share`].
fn environment_share_key(desc: &SceneDesc, check: &Check) -> Result<Option<f32>> {
    desc.integrator
        .environment_share
        .map(|v| {
            let v = check.range("integrator.environment_share", v, 0.0, 1.0, true)?;
            // 1 would leave the other lights (a delta sun) without light samples.
            match v < 1.0 {
                true => Ok(v),
                false => Err(check.error(
                    "integrator.environment_share",
                    "must be below 1: the other lights would get no light samples",
                )),
            }
        })
        .transpose()
}

/// Whether the camera sits inside a medium (at time 0). Such a medium (an
/// atmosphere, a fog layer) makes every segment of every path a medium
/// segment, where forced in-scattering's extra light sample per segment
/// measured as costing more than it saves (BENCHMARKS.md, "Forced
/// in-scattering"): its default is then off, as it is under a sun or sky,
/// whose light phase sampling finds too.
fn camera_in_a_medium(media: &[crate::medium::Medium], camera: &crate::camera::Camera) -> bool {
    let eye = camera.view_at(0.0).position;
    media.iter().any(|m| !m.sigma_t(eye).is_black())
}

/// The time keyframe times count from: the frame number for
/// `keyframe_time = "absolute"` (a still is frame 0), else 0.
fn key_time_origin(desc: &SceneDesc, frame: Option<i64>) -> f32 {
    match desc.animation.keyframe_time {
        animation::KeyframeTime::Relative => 0.0,
        animation::KeyframeTime::Absolute => frame.unwrap_or(0) as f32,
    }
}

/// The frame, shutter and frame rate that resolve frame patterns and motion.
fn build_timing(desc: &SceneDesc, check: &Check, frame: Option<i64>) -> Result<animation::Timing> {
    let fps = check.range("animation.fps", desc.animation.fps, 0.0, 1e6, false)?;
    let shutter = build_shutter(desc, check)?;
    Ok(animation::Timing {
        frame,
        shutter,
        fps,
        frame_offset: desc.animation.frame_offset,
        missing: desc.animation.missing_frames,
    })
}

/// `[integrator]`: the estimator, its sampler and its limits.
fn build_settings(desc: &SceneDesc, check: &Check, shutter: Option<[f32; 2]>) -> Result<Settings> {
    let integ = &desc.integrator;
    if integ.kind != "mlt" {
        warn_mlt_keys(integ, check);
    }
    if integ.guiding && integ.kind != "path" {
        let message = format!(
            "is a path-tracer setting, ignored by type = \"{}\"",
            integ.kind
        );
        check.warn("integrator.guiding", message);
    }
    Ok(Settings {
        integrator: match integ.kind.as_str() {
            "path" => IntegratorKind::Path,
            "bdpt" => IntegratorKind::Bdpt,
            "mlt" => IntegratorKind::Mlt(build_mlt(integ, check)?),
            "sppm" => IntegratorKind::Sppm,
            other => {
                return Err(check.error(
                    "integrator.type",
                    format!("unknown integrator `{other}`, expected path, bdpt, mlt or sppm"),
                ))
            }
        },
        spp: integ.spp,
        max_depth: integ.max_depth,
        max_scatter_depth: integ.max_scatter_depth.unwrap_or(u32::MAX),
        rr_depth: integ.rr_depth,
        seed: integ.seed,
        equiangular: integ.equiangular,
        forced_scattering: integ.forced_scattering.unwrap_or(true),
        sky_ahead: true,
        sun_lobe: None,
        shutter,
        transmittance: match integ.transmittance.as_str() {
            "auto" => TransmittanceEstimator::Auto,
            "ratio" => TransmittanceEstimator::Ratio,
            "residual_ratio" => TransmittanceEstimator::ResidualRatio,
            "delta" => TransmittanceEstimator::Delta,
            other => {
                return Err(check.error(
                    "integrator.transmittance",
                    format!(
                    "unknown estimator `{other}`, expected auto, ratio, residual_ratio or delta"
                ),
                ))
            }
        },
        sppm: sppm_keys::build(integ, check)?,
        sampler: match integ.sampler.as_str() {
            "sobol" => SamplerKind::Sobol,
            "independent" => SamplerKind::Independent,
            other => {
                return Err(check.error(
                    "integrator.sampler",
                    format!("unknown sampler `{other}`, expected sobol or independent"),
                ))
            }
        },
        adaptive: build_adaptive(integ, check)?,
        guiding: integ.guiding,
    })
}

/// The `[[medium]]` entries, then the shapes' interiors (at most
/// `MAX_OVERLAPPING_MEDIA` in all).
fn build_media(
    desc: &SceneDesc,
    check: &Check,
    base: &Path,
    timing: &animation::Timing,
    interiors: Vec<crate::medium::Medium>,
) -> Result<Vec<crate::medium::Medium>> {
    if desc.media.len() + interiors.len() > MAX_OVERLAPPING_MEDIA {
        return Err(check.error(
            "medium",
            format!(
                "at most {MAX_OVERLAPPING_MEDIA} media (with shape interiors) are supported, got {}",
                desc.media.len() + interiors.len()
            ),
        ));
    }
    let mut media = desc
        .media
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let field = format!("{}[{i}]", desc.media_key);
            let medium = media::build_medium(m, &field, check, base, timing)?;
            let eye = crate::math::Vec3::from_array(desc.camera.position);
            fog::check_at_camera(&medium, &field, eye, check)?;
            Ok(medium)
        })
        .collect::<Result<Vec<_>>>()?;
    media.extend(interiors);
    Ok(media)
}

/// `[film] aovs`: known names, each once.
fn build_aovs(names: &[String], check: &Check) -> Result<Vec<crate::integrator::aov::Aov>> {
    use crate::integrator::aov::Aov;
    let mut aovs = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let field = format!("film.aovs[{i}]");
        let Some(aov) = Aov::from_name(name) else {
            let known: Vec<_> = Aov::ALL.iter().map(|a| a.name()).collect();
            return Err(check.error(
                &field,
                format!("unknown AOV `{name}`, expected one of {}", known.join(", ")),
            ));
        };
        if aovs.contains(&aov) {
            return Err(check.error(&field, format!("`{name}` is listed twice")));
        }
        aovs.push(aov);
    }
    Ok(aovs)
}

/// `camera.shutter = [open, close]`: finite, open ≤ close, at most a frame either side.
fn build_shutter(desc: &SceneDesc, check: &Check) -> Result<Option<[f32; 2]>> {
    let Some([open, close]) = desc.camera.shutter else {
        return Ok(None);
    };
    check.range("camera.shutter[0]", open, -1.0, 1.0, true)?;
    check.range("camera.shutter[1]", close, -1.0, 1.0, true)?;
    if open > close {
        return Err(check.error("camera.shutter", "open must not be after close"));
    }
    Ok(Some([open, close]))
}

/// Resolves a path written in a scene file against the scene's folder.
pub(crate) fn resolve(base: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}
