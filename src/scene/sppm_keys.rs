//! The keys of `[integrator] type = "sppm"`: photons per pass, first
//! radius and radius-reduction exponent (a warning on the other integrators).

use super::description::IntegratorDesc;
use super::validate::Check;
use crate::error::Error;
use crate::integrator::sppm::{SppmSettings, DEFAULT_ALPHA, DEFAULT_PHOTONS, MAX_PHOTONS};

/// Smallest first gather radius (scene units): 1 / (π r²) per photon stays far from overflow.
const MIN_RADIUS: f32 = 1e-9;

/// Largest first gather radius (scene units): r² stays finite.
const MAX_RADIUS: f32 = 1e18;

/// The photon settings of `integ`, validated (defaults where not given).
pub(super) fn build(integ: &IntegratorDesc, check: &Check) -> Result<SppmSettings, Error> {
    if integ.kind != "sppm" {
        for (key, given) in [
            ("photons", integ.photons.is_some()),
            ("radius", integ.radius.is_some()),
            ("alpha", integ.alpha.is_some()),
        ] {
            // A warning, not an error: switching a photon-mapping scene to
            // another integrator (`--set integrator.type=bdpt`) keeps its keys.
            if given {
                check.warn(
                    &format!("integrator.{key}"),
                    format!(
                        "is a photon-mapping setting, ignored by type = \"{}\" (only \"sppm\" uses it)",
                        integ.kind
                    ),
                );
            }
        }
        return Ok(SppmSettings::default());
    }
    let photons = integ.photons.unwrap_or(DEFAULT_PHOTONS);
    if photons == 0 || photons > MAX_PHOTONS {
        return Err(check.error(
            "integrator.photons",
            format!("must be between 1 and {MAX_PHOTONS} light paths per pass, got {photons}"),
        ));
    }
    let radius = match integ.radius {
        // r² and the kernel 1 / (π r² M) must stay finite, nonzero single-precision numbers.
        Some(r) => Some(check.range("integrator.radius", r, MIN_RADIUS, MAX_RADIUS, true)?),
        None => None,
    };
    let alpha = match integ.alpha {
        Some(a) => check.range("integrator.alpha", a, 0.0, 1.0, false)?,
        None => DEFAULT_ALPHA,
    };
    Ok(SppmSettings {
        photons,
        radius,
        alpha,
    })
}
