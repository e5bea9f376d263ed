//! The `[integrator]` keys of `type = "mlt"`, checked in the user's words.

use super::description::IntegratorDesc;
use super::validate::Check;
use crate::error::Result;
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
    Ok(s)
}

/// Refuses the Metropolis keys in a scene whose integrator is not mlt: they would do nothing.
pub(super) fn refuse_mlt_keys(integ: &IntegratorDesc, check: &Check) -> Result<()> {
    let given = [
        (
            "large_step_probability",
            integ.large_step_probability.is_some(),
        ),
        ("small_step_size", integ.small_step_size.is_some()),
        ("bootstrap_samples", integ.bootstrap_samples.is_some()),
        ("chains", integ.chains.is_some()),
    ];
    match given.iter().find(|(_, set)| *set) {
        Some((key, _)) => Err(check.error(
            &format!("integrator.{key}"),
            format!(
                "applies to type = \"mlt\" only; this scene's type is \"{}\"",
                integ.kind
            ),
        )),
        None => Ok(()),
    }
}
