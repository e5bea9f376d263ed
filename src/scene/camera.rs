//! The `[camera]` table: lens, frame, placement and its range checks.

use super::description::SceneDesc;
use super::keyframes;
use super::validate::Check;
use crate::camera::{Camera, FovAxis, PixelFilter};
use crate::error::Result;

/// Position, look_at and up of the camera at rest, and the keyframes that move it.
type CameraRest = (
    crate::math::Vec3,
    crate::math::Vec3,
    crate::math::Vec3,
    Option<crate::math::keyframes::Keyframes>,
);

pub(super) fn build_camera(desc: &SceneDesc, check: &Check) -> Result<Camera> {
    let c = &desc.camera;
    let position = check.vec3("camera.position", c.position)?;
    let look_at = check.vec3("camera.look_at", c.look_at)?;
    let up = check.vec3("camera.up", c.up)?;
    check.range("camera.fov", c.fov, 0.0, 180.0, false)?;
    let [w, h] = c.resolution;
    check.positive_int("camera.resolution[0]", w)?;
    check.positive_int("camera.resolution[1]", h)?;
    if w > 32768 || h > 32768 {
        return Err(check.error("camera.resolution", "at most 32768 pixels a side"));
    }
    let (position, look_at, up, motion) = camera_placement(desc, position, look_at, up, check)?;
    // In f64: a look_at 1e30 away overflows the f32 length and is not a parallel up.
    let view = look_at.as_dvec3() - position.as_dvec3();
    if view.length() == 0.0 {
        return Err(check.error("camera.look_at", "equals camera.position"));
    }
    check_camera_range(position, check)?;
    // A step the f32 position can resolve: 1 m, or a thousandth of a huge position.
    let step = position.length().max(1.0) * 1e-3 + 1.0;
    let aim = position + (view / view.length()).as_vec3() * step;
    let camera = Camera::new(position, aim, up, c.fov, w, h)
        .ok_or_else(|| check.error("camera.up", "is parallel to the viewing direction"))?;
    let camera = match motion {
        Some(keys) => camera.with_motion(keys),
        None => camera,
    };
    let axis = match c.fov_axis.as_deref() {
        None | Some("y" | "vertical") => FovAxis::Vertical,
        Some("x" | "horizontal") => FovAxis::Horizontal,
        Some(other) => {
            return Err(check.error(
                "camera.fov_axis",
                format!("unknown axis `{other}`, expected \"y\" (vertical) or \"x\" (horizontal)"),
            ))
        }
    };
    let aperture = match c.aperture_radius {
        Some(a) if check.finite("camera.aperture_radius", a)? < 0.0 => {
            return Err(check.error(
                "camera.aperture_radius",
                format!("must be 0 or more, got {a}"),
            ))
        }
        Some(a) => a,
        None => 0.0,
    };
    let focus = match c.focus_distance {
        Some(f) => check.positive("camera.focus_distance", f)?,
        None => view.length() as f32,
    };
    Ok(camera
        .with_fov_axis(axis)
        .with_lens(aperture, focus)
        .with_filter(pixel_filter(desc, check)?))
}

/// `camera.pixel_filter`: box, or a Gaussian of `stddev` pixels (path tracer only).
fn pixel_filter(desc: &SceneDesc, check: &Check) -> Result<PixelFilter> {
    let Some(f) = &desc.camera.pixel_filter else {
        return Ok(PixelFilter::Box);
    };
    match (f.kind.as_str(), f.stddev) {
        ("box", None) => Ok(PixelFilter::Box),
        ("box", Some(_)) => {
            Err(check.error("camera.pixel_filter.stddev", "a box filter has no stddev"))
        }
        ("gaussian", _) if desc.integrator.kind != "path" => Err(check.error(
            "camera.pixel_filter",
            format!(
                "a gaussian pixel filter is supported by the path tracer only, not `{}`",
                desc.integrator.kind
            ),
        )),
        ("gaussian", stddev) => {
            let stddev = check.range(
                "camera.pixel_filter.stddev",
                stddev.unwrap_or(0.5),
                0.0,
                16.0,
                false,
            )?;
            Ok(PixelFilter::gaussian(stddev))
        }
        (other, _) => Err(check.error(
            "camera.pixel_filter.type",
            format!("unknown pixel filter `{other}`, expected \"box\" or \"gaussian\""),
        )),
    }
}

/// Refuses a camera position whose f32 ray arithmetic overflows (issue 11):
/// |position|² must stay finite for the view frame and every ray it starts.
fn check_camera_range(position: crate::math::Vec3, check: &Check) -> Result<()> {
    if position.length_squared().is_finite() {
        return Ok(());
    }
    Err(check.error(
        "camera.position",
        format!(
            "is {:.3e} from the origin: too far for f32 ray arithmetic (at most about {:.1e}); \
             move the scene toward the origin",
            position.as_dvec3().length(),
            f32::MAX.sqrt()
        ),
    ))
}

/// `camera.transform`: a still placement moves position, look_at and up
/// once; keyframes move the camera rigidly at each sample's time (no scale).
fn camera_placement(
    desc: &SceneDesc,
    position: crate::math::Vec3,
    look_at: crate::math::Vec3,
    up: crate::math::Vec3,
    check: &Check,
) -> Result<CameraRest> {
    let Some(t) = desc.camera.transform.as_ref() else {
        return Ok((position, look_at, up, None));
    };
    let scales = std::iter::once(t.scale)
        .chain(t.keyframes.iter().flatten().map(|k| k.scale))
        .flatten();
    for s in scales {
        if s.0 != [1.0; 3] {
            return Err(check.error(
                "camera.transform",
                "a camera moves rigidly: translate and rotate only, no scale",
            ));
        }
    }
    Ok(
        match keyframes::build_placement(Some(t), "camera", check)? {
            keyframes::Placed::Still(m) => (
                m.transform_point3(position),
                m.transform_point3(look_at),
                m.transform_vector3(up),
                None,
            ),
            keyframes::Placed::Moving(keys) => (position, look_at, up, Some(keys)),
        },
    )
}
