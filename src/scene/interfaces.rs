//! Mitsuba's interface rule of an imported scene (`SceneDesc::interfaces`)
//! built for the path tracer, which alone follows it: the other integrators
//! and AOVs are refused here, in one line naming the key.

use super::description::SceneDesc;
use super::validate::Check;
use crate::error::Result;
use crate::integrator::interfaces::Interfaces;
use crate::integrator::{IntegratorKind, Settings};

/// The interface rule of `desc`, if it has one; turns off equiangular
/// sampling, which brume draws over all media at once.
pub(super) fn build(
    desc: &SceneDesc,
    check: &Check,
    settings: &mut Settings,
) -> Result<Option<Interfaces>> {
    let Some(rule) = &desc.interfaces else {
        return Ok(None);
    };
    if settings.integrator != IntegratorKind::Path {
        return Err(check.error(
            "integrator.type",
            "this scene's media follow Mitsuba's interface rule (see README, \"Which medium \
             a ray is in\"), which only the path tracer follows: use type = \"path\"",
        ));
    }
    if !desc.film.aovs.is_empty() {
        return Err(check.error(
            "film.aovs",
            "AOVs are not written for a scene whose media follow Mitsuba's interface rule",
        ));
    }
    let count = desc.media.len() as u32;
    let known = |m: &Option<u32>| m.is_none_or(|m| m < count);
    let sides_known = rule.shapes.iter().flatten().flatten().all(known);
    if rule.shapes.len() != desc.shapes.len() || !sides_known || !known(&rule.camera) {
        return Err(check.error(
            "medium",
            "an interface names a medium that is not in the scene",
        ));
    }
    settings.equiangular = false;
    Ok(Some(Interfaces {
        sides: rule.shapes.clone(),
        null: desc.shapes.iter().map(|s| s.material.is_none()).collect(),
        camera: rule.camera,
    }))
}
