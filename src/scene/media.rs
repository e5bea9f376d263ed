//! Turning `[[medium]]` entries into media.

use super::description::{BoundsDesc, MediumDesc, PhaseDesc};
use super::shapes::build_transform;
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
use crate::math::Bounds3;
use crate::medium::{HomogeneousMedium, Medium, PhaseFunction, Region};
use std::path::Path;

/// The phase function of `phase = { ... }` (isotropic when absent).
pub(crate) fn build_phase(
    desc: Option<&PhaseDesc>,
    field: &str,
    check: &Check,
) -> Result<PhaseFunction> {
    let field = format!("{field}.phase");
    let g = |name: &str, g: f64| asymmetry(&format!("{field}.{name}"), g, check);
    let phase = match desc {
        None | Some(PhaseDesc::Isotropic {}) => PhaseFunction::Isotropic,
        Some(PhaseDesc::Hg { g: v }) => PhaseFunction::HenyeyGreenstein { g: g("g", *v)? },
        Some(PhaseDesc::Rayleigh {}) => PhaseFunction::Rayleigh,
        Some(PhaseDesc::DoubleHg {
            g_forward,
            g_back,
            weight,
        }) => PhaseFunction::DoubleHenyeyGreenstein {
            g_forward: g("g_forward", *g_forward)?,
            g_back: g("g_back", *g_back)?,
            weight_forward: check.range(&format!("{field}.weight"), *weight, 0.0, 1.0, true)?,
        },
    };
    // The phase module names its own parameters (weight_forward); the user wrote `weight`.
    phase
        .validate()
        .map_err(|m| check.error(&field, m.replace("weight_forward", "weight")))?;
    Ok(phase)
}

/// A Henyey–Greenstein asymmetry as written (f64), in (-1, 1) also once rounded to f32.
fn asymmetry(field: &str, g: f64, check: &Check) -> Result<f32> {
    if !(g.is_finite() && g.abs() < 1.0) {
        return Err(check.error(field, format!("must be in (-1, 1), got {g}")));
    }
    let rounded = g as f32;
    if rounded.abs() >= 1.0 {
        return Err(check.error(
            field,
            format!(
                "{g} rounds to {rounded} in single precision, where the lobe is a delta; use |g| <= 0.9999"
            ),
        ));
    }
    Ok(rounded)
}

/// σa and σs from either (sigma_a, sigma_s) or (sigma_t, albedo).
pub(crate) fn coefficients(
    sigma_a: Option<super::description::Color>,
    sigma_s: Option<super::description::Color>,
    sigma_t: Option<super::description::Color>,
    albedo: Option<super::description::Color>,
    field: &str,
    check: &Check,
) -> Result<(Rgb, Rgb)> {
    let f = |name: &str| format!("{field}.{name}");
    match (sigma_t, albedo) {
        (Some(t), a) => {
            if sigma_a.is_some() || sigma_s.is_some() {
                return Err(check.error(
                    &f("sigma_t"),
                    "give either sigma_t (with albedo) or sigma_a/sigma_s, not both",
                ));
            }
            let t = check.color(&f("sigma_t"), t)?;
            let a = match a {
                Some(a) => check.albedo(&f("albedo"), a)?,
                None => Rgb::WHITE,
            };
            Ok((t * (Rgb::WHITE - a), t * a))
        }
        (None, Some(_)) => Err(check.error(&f("albedo"), "needs sigma_t")),
        (None, None) => {
            if sigma_a.is_none() && sigma_s.is_none() {
                return Err(check.error(
                    field,
                    "needs sigma_a and/or sigma_s, or sigma_t with albedo",
                ));
            }
            let zero = super::description::Color([0.0; 3]);
            Ok((
                check.color(&f("sigma_a"), sigma_a.unwrap_or(zero))?,
                check.color(&f("sigma_s"), sigma_s.unwrap_or(zero))?,
            ))
        }
    }
}

/// Warns that emission given to a medium that absorbs nothing (albedo 1, or
/// σa = 0) does nothing: the source term is σa·Le.
pub(crate) fn warn_inert_emission(field: &str, sigma_a: Rgb, check: &Check) {
    if sigma_a.is_black() {
        check.warn(
            &format!("{field}.emission"),
            "does nothing: the medium absorbs nothing (albedo 1 or sigma_a = 0) and emits \
             sigma_a x emission; lower the albedo or give sigma_a",
        );
    }
}

/// The region of a bounded medium, or all space with `global = true`.
fn build_region(
    bounds: Option<&BoundsDesc>,
    global: bool,
    transform: Option<&super::description::TransformDesc>,
    field: &str,
    check: &Check,
) -> Result<Region> {
    match (bounds, global) {
        (Some(_), true) => {
            Err(check.error(&format!("{field}.global"), "a global medium has no bounds"))
        }
        (None, false) => Err(check.error(field, "needs bounds (box or sphere) or global = true")),
        (None, true) => {
            if transform.is_some() {
                return Err(check.error(
                    &format!("{field}.transform"),
                    "a global medium has no transform",
                ));
            }
            Ok(Region::Everywhere)
        }
        (Some(b), false) => {
            let to_world = build_transform(transform, field, check)?;
            let world_to_local = to_world.inverse();
            Ok(match b {
                BoundsDesc::Box { min, max } => {
                    let min = check.vec3(&format!("{field}.bounds.min"), *min)?;
                    let max = check.vec3(&format!("{field}.bounds.max"), *max)?;
                    if !(min.cmplt(max).all()) {
                        return Err(check.error(
                            &format!("{field}.bounds"),
                            "min must be below max on every axis",
                        ));
                    }
                    Region::Box {
                        world_to_local,
                        local: Bounds3 { min, max },
                    }
                }
                BoundsDesc::Sphere { center, radius } => Region::Sphere {
                    world_to_local,
                    center: check.vec3(&format!("{field}.bounds.center"), *center)?,
                    radius: check.positive(&format!("{field}.bounds.radius"), *radius)?,
                },
            })
        }
    }
}

/// The medium of one `[[medium]]` entry.
pub(crate) fn build_medium(
    desc: &MediumDesc,
    field: &str,
    check: &Check,
    base: &Path,
    timing: &super::animation::Timing,
) -> Result<Medium> {
    match desc {
        MediumDesc::Homogeneous {
            sigma_a,
            sigma_s,
            sigma_t,
            albedo,
            emission,
            phase,
            bounds,
            global,
            transform,
        } => {
            let (sigma_a, sigma_s) =
                coefficients(*sigma_a, *sigma_s, *sigma_t, *albedo, field, check)?;
            let emission = match emission {
                Some(e) => check.color(&format!("{field}.emission"), *e)?,
                None => Rgb::BLACK,
            };
            if !emission.is_black() {
                warn_inert_emission(field, sigma_a, check);
            }
            // Moving: the region is built in its local frame, placed per time.
            let keys = super::keyframes::moving_keys(transform.as_ref(), field, check)?;
            let region_transform = match (&keys, *global) {
                (Some(_), false) => None,
                _ => transform.as_ref(),
            };
            let medium = Medium::Homogeneous(HomogeneousMedium {
                sigma_a,
                sigma_s,
                emission,
                phase: build_phase(phase.as_ref(), field, check)?,
                region: build_region(bounds.as_ref(), *global, region_transform, field, check)?,
            });
            Ok(medium.moved_by(keys))
        }
        MediumDesc::HeightFog { .. } => super::fog::build_height_fog(desc, field, check),
        MediumDesc::Vdb(vdb) => super::vdb::build_vdb_medium(vdb, field, check, base, timing),
    }
}
