//! The `[integrator]` keys of `type = "mlt"`, checked in the user's words.

use super::description::IntegratorDesc;
use super::validate::Check;
use crate::error::{limits, Result};
use crate::integrator::mlt::bootstrap::BYTES_PER_SAMPLE;
use crate::integrator::mlt::MltSettings;

/// Deepest `max_depth` a Metropolis render takes.
const MAX_DEPTH: u32 = 4096;

/// The Metropolis settings of `integ` (defaults for the keys left out).
pub(super) fn build_mlt(integ: &IntegratorDesc, check: &Check) -> Result<MltSettings> {
    let mut s = MltSettings::default();
    if let Some(p) = integ.large_step_probability {
        s.large_step_probability =
            check.range("integrator.large_step_probability", p, 0.0, 1.0, true)?;
    }
    if let Some(sigma) = integ.small_step_size {
        // Past ½ a wrapped Gaussian step is nearly uniform: a large step in disguise.
        s.small_step_size = check.range("integrator.small_step_size", sigma, 0.0, 0.5, false)?;
    }
    if let Some(n) = integ.chains {
        s.chains = check.positive_int("integrator.chains", n)?;
    }
    if integ.max_depth > MAX_DEPTH {
        return Err(check.error(
            "integrator.max_depth",
            format!(
                "must be at most {MAX_DEPTH} with type = \"mlt\" (the bootstrap samples every path length), got {}",
                integ.max_depth
            ),
        ));
    }
    let lengths = integ.max_depth as u64 + 1;
    if let Some(n) = integ.bootstrap_samples {
        if (n as u64) < lengths {
            return Err(check.error(
                "integrator.bootstrap_samples",
                format!(
                    "must be at least max_depth + 1 = {lengths} (one path of every length), got {n}"
                ),
            ));
        }
        s.bootstrap_samples = n;
    } else if (s.bootstrap_samples as u64) < lengths {
        // One bootstrap path of every length at least.
        s.bootstrap_samples = lengths as u32;
    }
    let bytes = u128::from(s.bootstrap_samples) * u128::from(BYTES_PER_SAMPLE);
    limits::check(bytes).map_err(|refusal| {
        check.error(
            "integrator.bootstrap_samples",
            format!(
                "{} samples need {} of memory, {refusal}",
                s.bootstrap_samples,
                limits::format_bytes(bytes)
            ),
        )
    })?;
    Ok(s)
}

/// Warns about the Metropolis keys on another integrator: switching an
/// `mlt` scene to another estimator (`--set integrator.type=bdpt`) keeps
/// them, as it keeps the photon-mapping keys.
pub(super) fn warn_mlt_keys(integ: &IntegratorDesc, check: &Check) {
    let given = [
        (
            "large_step_probability",
            integ.large_step_probability.is_some(),
        ),
        ("small_step_size", integ.small_step_size.is_some()),
        ("bootstrap_samples", integ.bootstrap_samples.is_some()),
        ("chains", integ.chains.is_some()),
    ];
    for (key, _) in given.iter().filter(|(_, set)| *set) {
        check.warn(
            &format!("integrator.{key}"),
            format!(
                "is a Metropolis setting, ignored by type = \"{}\" (only \"mlt\" uses it)",
                integ.kind
            ),
        );
    }
}
