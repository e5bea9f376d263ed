//! `<sensor>` (perspective, thinlens) with its `<film>` and `<sampler>`,
//! and the `<integrator>`.

use super::mechanics::Node;
use super::transform::axes;
use super::values::{Obj, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{CameraDesc, IntegratorDesc, PixelFilterDesc};
use glam::{DMat4, DVec3};

/// The camera, the pixel budget and the medium the camera is in.
pub(crate) struct Sensor<'a> {
    /// The `<sensor>` element.
    pub node: &'a Node,
    /// brume's camera.
    pub camera: CameraDesc,
    /// The medium around the camera (`<ref id=...>` or a nested `<medium>`).
    pub medium: Option<Obj<'a>>,
    spp: u32,
    seed: u64,
    sampler: &'static str,
}

impl Sensor<'_> {
    /// Puts the sampler's settings into the integrator's.
    pub fn settings(&self, integrator: &mut IntegratorDesc) {
        integrator.spp = self.spp;
        integrator.seed = self.seed;
        integrator.sampler = self.sampler.into();
    }

    /// One line for `brume info`.
    pub fn summary(&self, integrator: &IntegratorDesc) -> String {
        let [w, h] = self.camera.resolution;
        let axis = self.camera.fov_axis.as_deref().unwrap_or("y");
        format!(
            "line {}: {} → camera {w}×{h}, fov {:.4}° along {axis}, {} spp ({} sampler), max_depth {} (brume's count)",
            self.node.line,
            self.node.what(),
            self.camera.fov,
            self.spp,
            self.sampler,
            integrator.max_depth,
        )
    }
}

/// `<sensor type="perspective">` or `"thinlens"`.
pub(crate) fn read<'a>(ctx: &Ctx<'a>, node: &'a Node) -> Result<Sensor<'a>> {
    let kind = node.required("type")?;
    if kind != "perspective" && kind != "thinlens" {
        return Err(unsupported(
            node,
            "this sensor (perspective and thinlens only)",
        ));
    }
    let p = ctx.props(node)?;
    let to_world = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let (film, pixel_filter) = p
        .object("film", None)
        .map(|f| film(ctx, f.node))
        .transpose()?
        .unwrap_or(([768, 576], Some(mitsuba_gaussian(None))));
    let (spp, seed, sampler) = match p.object("sampler", None) {
        Some(s) => read_sampler(ctx, s.node)?,
        None => (4, 0, "independent"),
    };
    let at = p.node_of("to_world").unwrap_or(node);
    let mut camera = placement(&to_world, at)?;
    if let Some(points) = super::transform::lone_lookat(at) {
        // As written: brume builds the same frame from them, without a round trip through a matrix.
        let [origin, target, up] = points?.map(|v| v.as_vec3().to_array());
        (camera.position, camera.look_at, camera.up) = (origin, target, up);
    }
    camera.resolution = film;
    camera.pixel_filter = pixel_filter;
    fov(&p, &mut camera)?;
    if kind == "thinlens" {
        let need = |key: &str| -> Result<f32> {
            p.float(key)?.map(|v| v as f32).ok_or_else(|| {
                node.error(format!(
                    "give <float name=\"{key}\"> (brume has no default for it)"
                ))
            })
        };
        camera.aperture_radius = Some(need("aperture_radius")?);
        camera.focus_distance = Some(need("focus_distance")?);
    }
    warn_clipping(ctx, &p, node)?;
    let medium = p.object("medium", None);
    p.finish()?;
    Ok(Sensor {
        node,
        camera,
        medium,
        spp,
        seed,
        sampler,
    })
}

/// Clipping planes other than Mitsuba's defaults warn: brume does not clip camera rays.
fn warn_clipping(ctx: &Ctx, p: &Props, node: &Node) -> Result<()> {
    for (key, default) in [("near_clip", 0.01), ("far_clip", 10000.0)] {
        if let Some(v) = p.float(key)? {
            if v != default {
                ctx.warn(
                    node,
                    format!("{key} = {v}: brume does not clip camera rays"),
                );
            }
        }
    }
    Ok(())
}

/// Position, target and up of a rigid `to_world` (Mitsuba looks along local +Z).
fn placement(m: &DMat4, at: &Node) -> Result<CameraDesc> {
    let rigid = axes(m).is_some_and(|(cols, lengths)| {
        (lengths - DVec3::ONE).abs().max_element() < 1e-5
            && cols[0].cross(cols[1]).dot(cols[2]) > 0.0
    });
    if !rigid {
        return Err(unsupported(
            at,
            "a camera to_world that scales, shears or mirrors (only lookat, rotate and translate)",
        ));
    }
    let f = |v: DVec3| v.as_vec3().to_array();
    Ok(CameraDesc {
        position: f(m.transform_point3(DVec3::ZERO)),
        look_at: f(m.transform_point3(DVec3::Z)),
        up: f(m.transform_vector3(DVec3::Y)),
        fov: 40.0,
        resolution: [768, 576],
        shutter: None,
        fov_axis: None,
        aperture_radius: None,
        focus_distance: None,
        transform: None,
        pixel_filter: None,
    })
}

/// `fov` along `fov_axis` (x, y, smaller, larger, diagonal) or
/// `focal_length` (35 mm equivalent, along the diagonal; default 50mm).
fn fov(p: &Props, camera: &mut CameraDesc) -> Result<()> {
    let [w, h] = camera.resolution.map(f64::from);
    let focal = p.string("focal_length")?;
    let (degrees, axis) = match (p.float("fov")?, focal) {
        (Some(_), Some((_, at))) => {
            return Err(at.error("give either fov or focal_length, not both"))
        }
        (Some(f), None) => {
            let axis = match p.string("fov_axis")? {
                Some((a, _)) => a.to_lowercase(),
                None => "x".into(),
            };
            (f, axis)
        }
        (None, focal) => {
            let text = focal.map(|(t, _)| t).unwrap_or("50mm");
            let at = p.node_of("focal_length").unwrap_or(p.owner);
            let mm = super::numbers::number(at, text.trim().trim_end_matches("mm"))?;
            if mm <= 0.0 {
                return Err(at.error("the focal length must be positive"));
            }
            let half_diagonal = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt() / (2.0 * mm);
            (2.0 * half_diagonal.atan().to_degrees(), "diagonal".into())
        }
    };
    let at = p.node_of("fov").unwrap_or(p.owner);
    if !(degrees > 0.0 && degrees < 180.0) {
        return Err(at.error(format!("fov {degrees} must be between 0 and 180 degrees")));
    }
    let (fov, axis) = match axis.as_str() {
        "x" => (degrees, "x"),
        "y" => (degrees, "y"),
        "smaller" if w <= h => (degrees, "x"),
        "smaller" => (degrees, "y"),
        "larger" if w >= h => (degrees, "x"),
        "larger" => (degrees, "y"),
        "diagonal" => {
            let half = (degrees.to_radians() * 0.5).tan() * w / (w * w + h * h).sqrt();
            (2.0 * half.atan().to_degrees(), "x")
        }
        other => {
            let at = p.node_of("fov_axis").unwrap_or(p.owner);
            return Err(at.error(format!(
                "unknown fov_axis `{other}`, expected x, y, smaller, larger or diagonal"
            )));
        }
    };
    camera.fov = fov as f32;
    camera.fov_axis = Some(axis.into());
    Ok(())
}

/// Mitsuba's `gaussian` reconstruction filter (its default: stddev 0.5 pixels).
fn mitsuba_gaussian(stddev: Option<f64>) -> PixelFilterDesc {
    PixelFilterDesc {
        kind: "gaussian".into(),
        stddev: stddev.map(|s| s as f32),
    }
}

/// `<film type="hdrfilm">`: the size and the pixel filter; a crop must be the whole frame.
fn film(ctx: &Ctx, node: &Node) -> Result<([u32; 2], Option<PixelFilterDesc>)> {
    if node.required("type")? != "hdrfilm" {
        return Err(unsupported(node, "this film (hdrfilm only)"));
    }
    let p = ctx.props(node)?;
    let size = |key: &str, default: i64| -> Result<u32> {
        let v = p.int(key)?.unwrap_or(default);
        u32::try_from(v)
            .ok()
            .filter(|v| (1..=32768).contains(v))
            .ok_or_else(|| {
                p.node_of(key)
                    .unwrap_or(node)
                    .error(format!("{key} {v} must be 1 to 32768"))
            })
    };
    let (w, h) = (size("width", 768)?, size("height", 576)?);
    let crop = [
        p.int("crop_offset_x")?.unwrap_or(0),
        p.int("crop_offset_y")?.unwrap_or(0),
        p.int("crop_width")?.unwrap_or(w as i64),
        p.int("crop_height")?.unwrap_or(h as i64),
    ];
    if crop != [0, 0, w as i64, h as i64] {
        return Err(unsupported(node, "a crop window smaller than the film"));
    }
    // What the file holds, not what the pixels are: brume writes its own EXR and PNG.
    for key in ["pixel_format", "component_format", "file_format"] {
        p.string(key)?;
    }
    p.bool("banner")?;
    if p.bool("sample_border")? == Some(true) {
        return Err(unsupported(node, "sample_border"));
    }
    let filter = match p.object("rfilter", None) {
        Some(f) if f.node.attr("type") == Some("box") => None,
        Some(f) if f.node.attr("type") == Some("gaussian") => {
            let q = ctx.props(f.node)?;
            let stddev = q.float("stddev")?;
            q.finish()?;
            Some(mitsuba_gaussian(stddev))
        }
        Some(f) => {
            ctx.warn(
                f.node,
                "brume has box and gaussian pixel filters: this one is taken as a box",
            );
            None
        }
        // Mitsuba's default.
        None => Some(mitsuba_gaussian(None)),
    };
    p.finish()?;
    Ok(([w, h], filter))
}

/// `<sampler>`: samples per pixel, seed, and which of brume's samplers.
fn read_sampler(ctx: &Ctx, node: &Node) -> Result<(u32, u64, &'static str)> {
    let kind = match node.required("type")? {
        "independent" => "independent",
        // Stratified families: brume's scrambled Sobol' points, equally unbiased.
        "stratified" | "multijitter" | "orthogonal" | "ldsampler" => "sobol",
        _ => return Err(unsupported(node, "this sampler")),
    };
    let p = ctx.props(node)?;
    let spp = p.int("sample_count")?.unwrap_or(4);
    let spp = u32::try_from(spp).ok().filter(|&s| s > 0).ok_or_else(|| {
        p.node_of("sample_count")
            .unwrap_or(node)
            .error("must be a positive whole number")
    })?;
    let seed = p.int("seed")?.unwrap_or(0);
    let seed = u64::try_from(seed)
        .map_err(|_| p.node_of("seed").unwrap_or(node).error("must be 0 or more"))?;
    p.bool("jitter")?;
    p.finish()?;
    Ok((spp, seed, kind))
}

/// `<integrator>`: path, volpath, volpathmis or direct (inside moment/aov
/// wrappers), and the `direct` element if it is that one (it has no media).
pub(crate) fn integrator<'a>(
    ctx: &Ctx<'a>,
    node: Option<&'a Node>,
) -> Result<(IntegratorDesc, Option<&'a Node>)> {
    let mut desc = IntegratorDesc {
        max_depth: u32::MAX,
        ..IntegratorDesc::default()
    };
    let Some(mut node) = node else {
        return Ok((desc, None)); // Mitsuba's default: path, unlimited depth
    };
    while matches!(node.required("type")?, "moment" | "aov") {
        node = unwrapped(ctx, node)?;
    }
    if node.required("type")? == "direct" {
        return Ok((direct(ctx, node, desc)?, Some(node)));
    }
    if !matches!(node.required("type")?, "path" | "volpath" | "volpathmis") {
        return Err(unsupported(
            node,
            "this integrator (path, volpath, volpathmis, direct)",
        ));
    }
    let p = ctx.props(node)?;
    // Mitsuba counts path segments (1 = emitters seen directly); brume counts scattering vertices.
    if let Some(d) = p.int("max_depth")? {
        let at = p.node_of("max_depth").unwrap_or(node);
        desc.max_depth = match d {
            -1 => u32::MAX,
            0 => return Err(at.error("max_depth 0 renders nothing")),
            d if d > 0 => u32::try_from(d - 1).unwrap_or(u32::MAX),
            _ => return Err(at.error("must be -1 (unlimited) or positive")),
        };
    }
    if let Some(d) = p.int("rr_depth")? {
        desc.rr_depth = u32::try_from(d).map_err(|_| {
            p.node_of("rr_depth")
                .unwrap_or(node)
                .error("must be 0 or more")
        })?;
    }
    refuse_hidden_emitters(&p, node)?;
    p.finish()?;
    Ok((desc, None))
}

/// `hide_emitters = true` is refused: brume always shows the emitters a camera ray meets.
fn refuse_hidden_emitters(p: &Props, node: &Node) -> Result<()> {
    match p.bool("hide_emitters")? {
        Some(true) => Err(unsupported(node, "hide_emitters")),
        _ => Ok(()),
    }
}

/// The integrator a `moment` or `aov` wrapper holds (its extra outputs are not written).
fn unwrapped<'a>(ctx: &Ctx<'a>, node: &'a Node) -> Result<&'a Node> {
    let p = ctx.props(node)?;
    p.string("aovs")?;
    let inner = p.objects("integrator");
    p.finish()?;
    if inner.is_empty() {
        return Err(node.error("holds no <integrator> to render with"));
    }
    if inner.len() > 1 {
        return Err(unsupported(node, "several nested integrators"));
    }
    ctx.warn(
        node,
        "a wrapper's extra outputs are not written: brume renders the nested integrator",
    );
    Ok(inner[0].node)
}

/// `<integrator type="direct">`: emitters seen directly and light reflected
/// once, sampled by the emitters and the BSDF under MIS; the path tracer
/// with one scattering vertex has that expectation. Its sample counts
/// change only the noise: brume takes one of each per pixel sample.
fn direct(ctx: &Ctx, node: &Node, mut desc: IntegratorDesc) -> Result<IntegratorDesc> {
    let p = ctx.props(node)?;
    for key in ["shading_samples", "emitter_samples", "bsdf_samples"] {
        if let Some(n) = p.int(key)? {
            let at = p.node_of(key).unwrap_or(node);
            if n < 0 {
                return Err(at.error("must be 0 or more"));
            }
            ctx.warn(
                at,
                "brume takes one emitter and one BSDF sample per pixel sample (the same image, other noise)",
            );
        }
    }
    refuse_hidden_emitters(&p, node)?;
    p.finish()?;
    desc.max_depth = 1;
    Ok(desc)
}
