//! Turning `[[medium]] type = "height_fog"` entries into height fog.

use super::description::{Color, MediumDesc};
use super::media::{build_phase, coefficients};
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
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
        Some(v) => {
            let v = check.positive(&f("visibility"), *v)?;
            let t = Color([sigma_t_from_visibility(v); 3]);
            coefficients(None, None, Some(t), *albedo, field, check)?
        }
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
        super::media::warn_inert_emission(field, sigma_a, check);
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
