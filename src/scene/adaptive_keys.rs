//! The `[integrator]` keys of adaptive sampling (`adaptive`, `noise`),
//! checked in the user's words.

use super::description::IntegratorDesc;
use super::validate::Check;
use crate::error::Result;
use crate::integrator::adaptive_settings::{AdaptiveSettings, MAX_NOISE, MIN_SPP};

/// `integrator.adaptive` and `integrator.noise`: adaptive by default with a
/// noise target; with neither key, the path tracer decides from its pilot.
pub(super) fn build_adaptive(integ: &IntegratorDesc, check: &Check) -> Result<AdaptiveSettings> {
    let noise = match integ.noise {
        Some(v) => Some(check.range("integrator.noise", v, 0.0, MAX_NOISE, false)?),
        None => None,
    };
    let settings = AdaptiveSettings {
        adaptive: integ.adaptive.unwrap_or(noise.is_some()),
        noise,
        auto: integ.adaptive.is_none() && noise.is_none() && integ.kind == "path",
    };
    let field = match noise {
        Some(_) => "integrator.noise",
        None => "integrator.adaptive",
    };
    if settings.piloted() && integ.kind != "path" {
        return Err(check.error(
            field,
            format!(
                "adaptive sampling and noise targets need type = \"path\" (this scene's is \"{}\"); \
                 leave the key out or set adaptive = false without noise",
                integ.kind
            ),
        ));
    }
    if settings.piloted() && integ.spp < MIN_SPP {
        return Err(check.error(
            "integrator.spp",
            format!(
                "adaptive sampling and noise targets need at least {} samples per pixel, got {}",
                MIN_SPP, integ.spp
            ),
        ));
    }
    Ok(settings)
}
