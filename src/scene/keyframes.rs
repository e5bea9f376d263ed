//! `transform` tables: one placement, or keyframes (`math::keyframes`).

use super::description::{KeyframeDesc, TransformDesc};
use super::validate::Check;
use crate::error::Result;
use crate::math::keyframes::{Key, Keyframes};
use crate::math::{Affine3A, Quat, Vec3};

/// Where a transform puts its object: fixed, or keyed over time.
#[derive(Clone, Debug)]
pub(crate) enum Placed {
    /// One placement (also keyframes that never change).
    Still(Affine3A),
    /// Keyframes that move the object.
    Moving(Keyframes),
}

impl Placed {
    /// The map from the frame the object is built in to world space (the
    /// identity for a moving object, built in its local frame), and the keys
    /// that move it.
    pub(crate) fn split(self) -> (Affine3A, Option<Keyframes>) {
        match self {
            Placed::Still(m) => (m, None),
            Placed::Moving(k) => (Affine3A::IDENTITY, Some(k)),
        }
    }
}

/// Scale, rotation and translation written at `prefix` (`shape[0].transform`).
fn trs(
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<super::description::Color>,
    prefix: &str,
    check: &Check,
) -> Result<(Vec3, Quat, Vec3)> {
    let scale = match scale {
        Some(s) => {
            let mut v = [0.0; 3];
            for (i, &c) in s.0.iter().enumerate() {
                v[i] = check.positive(&format!("{prefix}.scale[{i}]"), c)?;
            }
            Vec3::from_array(v)
        }
        None => Vec3::ONE,
    };
    let rotation = match rotate {
        Some(r) => {
            let r = check.vec3(&format!("{prefix}.rotate"), r)?;
            Quat::from_rotation_z(r.z.to_radians())
                * Quat::from_rotation_y(r.y.to_radians())
                * Quat::from_rotation_x(r.x.to_radians())
        }
        None => Quat::IDENTITY,
    };
    let translation = match translate {
        Some(tr) => check.vec3(&format!("{prefix}.translate"), tr)?,
        None => Vec3::ZERO,
    };
    Ok((scale, rotation, translation))
}

/// The placement of `field.transform` (identity when absent).
pub(crate) fn build_placement(
    t: Option<&TransformDesc>,
    field: &str,
    check: &Check,
) -> Result<Placed> {
    let Some(t) = t else {
        return Ok(Placed::Still(Affine3A::IDENTITY));
    };
    let prefix = format!("{field}.transform");
    let Some(keys) = &t.keyframes else {
        let (s, r, tr) = trs(t.translate, t.rotate, t.scale, &prefix, check)?;
        return Ok(Placed::Still(Affine3A::from_scale_rotation_translation(
            s, r, tr,
        )));
    };
    if t.translate.is_some() || t.rotate.is_some() || t.scale.is_some() {
        return Err(check.error(
            &prefix,
            "give either keyframes or translate/rotate/scale, not both \
             (each key has its own translate, rotate and scale)",
        ));
    }
    if keys.is_empty() {
        return Err(check.error(
            &format!("{prefix}.keyframes"),
            "needs at least one key, e.g. { time = 0.0, translate = [0.0, 0.0, 0.0] }",
        ));
    }
    let built = build_keys(keys, &prefix, check)?;
    let first = built[0];
    let same = |k: &Key| {
        (k.translate, k.rotation, k.scale) == (first.translate, first.rotation, first.scale)
    };
    if built.iter().all(same) {
        // Built as `transform = { ... }` with the first key's values: the same bits.
        return Ok(Placed::Still(Affine3A::from_scale_rotation_translation(
            first.scale,
            first.rotation,
            first.translate,
        )));
    }
    Ok(Placed::Moving(
        Keyframes::new(&built).expect("keys checked in increasing time"),
    ))
}

/// The keys of `prefix.keyframes`, each checked, in strictly increasing time.
fn build_keys(keys: &[KeyframeDesc], prefix: &str, check: &Check) -> Result<Vec<Key>> {
    let mut built = Vec::with_capacity(keys.len());
    for (i, k) in keys.iter().enumerate() {
        let key_field = format!("{prefix}.keyframes[{i}]");
        let time = check.finite(&format!("{key_field}.time"), k.time)?;
        if let Some(prev) = keys[..i].last().map(|k| k.time) {
            if time <= prev {
                return Err(check.error(
                    &format!("{key_field}.time"),
                    format!("keys must be in increasing time: {time} follows {prev}"),
                ));
            }
        }
        let (scale, rotation, translate) = trs(k.translate, k.rotate, k.scale, &key_field, check)?;
        built.push(Key {
            // Sequence keyframe times are frame numbers: this frame's time is 0.
            time: time - check.key_time_origin(),
            translate,
            rotation,
            scale,
        });
    }
    Ok(built)
}

/// The placement of `field.transform`, refusing keyframes where `what` cannot move.
pub(crate) fn build_still(
    t: Option<&TransformDesc>,
    field: &str,
    what: &str,
    check: &Check,
) -> Result<Affine3A> {
    match build_placement(t, field, check)? {
        Placed::Still(m) => Ok(m),
        Placed::Moving(_) => Err(check.error(
            &format!("{field}.transform.keyframes"),
            format!(
                "{what} cannot be keyframed; give one transform {{ translate, rotate, scale }}"
            ),
        )),
    }
}

/// The keyframes of `field.transform` when they move the object (`None`
/// for no transform, one placement, or keys that never change).
pub(crate) fn moving_keys(
    t: Option<&TransformDesc>,
    field: &str,
    check: &Check,
) -> Result<Option<Keyframes>> {
    Ok(build_placement(t, field, check)?.split().1)
}
