//! Turning `[[medium]] type = "height_fog"` entries into height fog.

use super::coefficients::{build_phase, check_emission, coefficients};
use super::description::{Color, MediumDesc};
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
use crate::math::Vec3;
use crate::medium::height_fog::sigma_t_from_visibility;
use crate::medium::{HeightFog, Medium};

/// The height fog of one `[[medium]]` entry (`desc` must be `MediumDesc::HeightFog`).
pub(crate) fn build_height_fog(desc: &MediumDesc, field: &str, check: &Check) -> Result<Medium> {
    let MediumDesc::HeightFog {
        sigma_a,
        sigma_s,
        sigma_t,
        visibility,
        albedo,
        emission,
        phase,
        height,
        scale_height,
        up,
    } = desc
    else {
        unreachable!("build_height_fog is only called for height fog");
    };
    let f = |name: &str| format!("{field}.{name}");
    let explicit = sigma_t.is_some() || sigma_a.is_some() || sigma_s.is_some();
    let (sigma_a, sigma_s) = match visibility {
        Some(_) if explicit => {
            return Err(check.error(
                &f("visibility"),
                "give either visibility or sigma_t (or sigma_a/sigma_s), not both",
            ))
        }
        Some(v) => visibility_coefficients(*v, *albedo, field, check)?,
        None if !explicit => {
            return Err(check.error(
                field,
                "height fog needs visibility, sigma_t (with albedo) or sigma_a/sigma_s",
            ))
        }
        None => coefficients(*sigma_a, *sigma_s, *sigma_t, *albedo, field, check)?,
    };
    let emission = match emission {
        Some(e) => check.color(&f("emission"), *e)?,
        None => Rgb::BLACK,
    };
    if !emission.is_black() {
        check_emission(field, sigma_a, emission, check)?;
    }
    Ok(Medium::HeightFog(HeightFog {
        sigma_a,
        sigma_s,
        emission,
        phase: build_phase(phase.as_ref(), field, check)?,
        up: check.direction(&f("up"), *up)?,
        height: check.finite(&f("height"), *height)?,
        scale_height: check.positive(&f("scale_height"), *scale_height)?,
    }))
}

/// (σa, σs) of a fog whose `visibility` (and `albedo`) set its extinction.
fn visibility_coefficients(
    visibility: f32,
    albedo: Option<Color>,
    field: &str,
    check: &Check,
) -> Result<(Rgb, Rgb)> {
    let key = format!("{field}.visibility");
    let v = check.positive(&key, visibility)?;
    let t = sigma_t_from_visibility(v);
    let exact = 50f64.ln() / v as f64;
    super::overflow::fits(check, &key, t, exact, || {
        format!(
            "the extinction ln 50 / visibility {}",
            super::overflow::num(v)
        )
    })?;
    coefficients(None, None, Some(Color([t; 3])), albedo, field, check)
}

/// Refuses a height fog infinitely dense where the camera is: its density
/// grows without bound below `height`, and a camera whose σt (or source
/// term σa·Le) overflows f32 would render nothing but NaN (`height = 1e30`).
pub(super) fn check_at_camera(
    medium: &Medium,
    field: &str,
    eye: Vec3,
    check: &Check,
) -> Result<()> {
    let Medium::HeightFog(fog) = medium else {
        return Ok(());
    };
    let p = fog.properties(eye);
    let sigma_t = p.sigma_a + p.sigma_s;
    if sigma_t.is_finite() && (p.sigma_a * fog.emission).is_finite() {
        return Ok(());
    }
    let below = fog.height as f64 - fog.up.dot(eye) as f64;
    Err(check.error(
        &format!("{field}.height"),
        format!(
            "the camera is {} below the fog's reference height, {:.3e} scale heights, where its \
             extinction (or emission) overflows single precision: it would sit in infinitely dense \
             fog; lower height or raise scale_height",
            super::overflow::num(below as f32),
            below / fog.scale_height as f64
        ),
    ))
}
