//! The optical terms every kind of medium shares: σa and σs as the user
//! gave them, the phase function, and the checks on emission. Homogeneous,
//! height-fog, VDB and interior media all build on these, so they sit below
//! the files that build each kind.

use super::description::{Color, PhaseDesc};
use super::overflow;
use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;
use crate::medium::PhaseFunction;

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
    sigma_a: Option<Color>,
    sigma_s: Option<Color>,
    sigma_t: Option<Color>,
    albedo: Option<Color>,
    field: &str,
    check: &Check,
) -> Result<(Rgb, Rgb)> {
    let f = |name: &str| format!("{field}.{name}");
    let (sigma_a, sigma_s, key) =
        split_coefficients(sigma_a, sigma_s, sigma_t, albedo, field, check)?;
    // tracking samples distances with σt = σa + σs: an infinite one never ends a free flight
    overflow::sum(check, &f(key), (sigma_a, "sigma_a"), (sigma_s, "sigma_s"))?;
    Ok((sigma_a, sigma_s))
}

/// σa and σs as [`coefficients`] reads them, with the key that set their scale.
fn split_coefficients(
    sigma_a: Option<Color>,
    sigma_s: Option<Color>,
    sigma_t: Option<Color>,
    albedo: Option<Color>,
    field: &str,
    check: &Check,
) -> Result<(Rgb, Rgb, &'static str)> {
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
            Ok((t * (Rgb::WHITE - a), t * a, "sigma_t"))
        }
        (None, Some(_)) => Err(check.error(&f("albedo"), "needs sigma_t")),
        (None, None) => {
            if sigma_a.is_none() && sigma_s.is_none() {
                return Err(check.error(
                    field,
                    "needs sigma_a and/or sigma_s, or sigma_t with albedo",
                ));
            }
            let zero = Color([0.0; 3]);
            let a = check.color(&f("sigma_a"), sigma_a.unwrap_or(zero))?;
            let s = check.color(&f("sigma_s"), sigma_s.unwrap_or(zero))?;
            let key = match a.max_channel() >= s.max_channel() {
                true => "sigma_a",
                false => "sigma_s",
            };
            Ok((a, s, key))
        }
    }
}

/// Warns that emission given to a medium that absorbs nothing (albedo 1, or
/// σa = 0) does nothing: the source term is σa·Le. Refuses a source term
/// that overflows.
pub(crate) fn check_emission(
    field: &str,
    sigma_a: Rgb,
    emission: Rgb,
    check: &Check,
) -> Result<()> {
    let key = format!("{field}.emission");
    overflow::product(check, &key, (sigma_a, "sigma_a"), (emission, "emission"))?;
    warn_inert_emission(field, sigma_a, check);
    Ok(())
}

/// Warns that emission given to a medium that absorbs nothing does nothing.
pub(crate) fn warn_inert_emission(field: &str, sigma_a: Rgb, check: &Check) {
    if sigma_a.is_black() {
        check.warn(
            &format!("{field}.emission"),
            "does nothing: the medium absorbs nothing (albedo 1 or sigma_a = 0) and emits \
             sigma_a x emission; lower the albedo or give sigma_a",
        );
    }
}
