//! `<transform>`: `translate`, `scale`, `rotate`, `matrix` and `lookat`
//! composed in the order written (each applies after the ones above it),
//! and the split of an affine matrix into brume's scale, rotate, translate.

use super::mechanics::Node;
use super::numbers::{number, numbers, triple};
use crate::error::Result;
use crate::scene::description::{Color, TransformDesc};
use glam::{DMat3, DMat4, DQuat, DVec3, EulerRot};

/// The matrix of a `<transform>`: later operations multiply from the left.
pub(crate) fn compose(node: &Node) -> Result<DMat4> {
    let mut m = DMat4::IDENTITY;
    for op in &node.children {
        m = operation(op)? * m;
    }
    Ok(m)
}

/// One operation of a `<transform>`.
fn operation(op: &Node) -> Result<DMat4> {
    Ok(match op.tag.as_str() {
        "translate" => DMat4::from_translation(DVec3::from_array(triple(op, 0.0)?)),
        "scale" => DMat4::from_scale(scale(op)?),
        "rotate" => {
            let axis = DVec3::from_array(triple(op, 0.0)?);
            let angle = number(op, op.required("angle")?)?;
            if axis == DVec3::ZERO {
                return Err(op.error("the rotation axis is zero"));
            }
            // As written: Mitsuba does not normalize it (a longer axis also scales and shears).
            DMat4::from_mat3(rotation(axis, angle))
        }
        "matrix" => {
            let text = op.required("value")?;
            let v = numbers(op, text)?;
            match v.len() {
                16 => DMat4::from_cols_slice(&v).transpose(),
                9 => DMat4::from_mat3(DMat3::from_cols_slice(&v).transpose()),
                n => return Err(op.error(format!("expected 16 (or 9) numbers, got {n}"))),
            }
        }
        "lookat" => lookat(op)?,
        _ => {
            return Err(op.error(
                "unknown transform operation (expected translate, scale, rotate, matrix or lookat)",
            ))
        }
    })
}

/// Rotation by `degrees` about the unit `axis` (right-handed); quarter
/// turns are exact, so a rectangle turned by 90° lies exactly in its plane.
fn rotation(axis: DVec3, degrees: f64) -> DMat3 {
    let quarter = degrees / 90.0;
    let (s, c) = if quarter == quarter.round() {
        match (quarter as i64).rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        }
    } else {
        degrees.to_radians().sin_cos()
    };
    let k = DMat3::from_cols(
        DVec3::new(0.0, axis.z, -axis.y),
        DVec3::new(-axis.z, 0.0, axis.x),
        DVec3::new(axis.y, -axis.x, 0.0),
    );
    DMat3::IDENTITY * c + k * s + outer(axis) * (1.0 - c)
}

/// The outer product a aᵀ.
fn outer(a: DVec3) -> DMat3 {
    DMat3::from_cols(a * a.x, a * a.y, a * a.z)
}

/// `<scale value="s"/>` (uniform), `value="x, y, z"`, or `x`, `y`, `z` (default 1).
fn scale(op: &Node) -> Result<DVec3> {
    if let Some(text) = op.attr("value") {
        return match numbers(op, text)?.as_slice() {
            [s] => Ok(DVec3::splat(*s)),
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(op.error(format!("`{text}` is not one or three numbers"))),
        };
    }
    Ok(DVec3::from_array(triple(op, 1.0)?))
}

/// The origin, target and up of a `<transform>` that is one `<lookat>`, as written.
pub(crate) fn lone_lookat(node: &Node) -> Option<Result<[DVec3; 3]>> {
    match node.children.as_slice() {
        [op] if op.tag == "lookat" => Some(lookat_points(op)),
        _ => None,
    }
}

/// `<lookat origin target up>` as written (up defaults to +Y).
fn lookat_points(op: &Node) -> Result<[DVec3; 3]> {
    let point = |key: &str| -> Result<DVec3> {
        let text = op.required(key)?;
        match numbers(op, text)?.as_slice() {
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(op.error(format!("{key} `{text}` is not three numbers"))),
        }
    };
    let up = match op.attr("up") {
        Some(_) => point("up")?,
        None => DVec3::Y,
    };
    Ok([point("origin")?, point("target")?, up])
}

/// `<lookat origin target up>`: local +Z toward the target, +Y toward up,
/// +X = up × direction (Mitsuba's frame).
fn lookat(op: &Node) -> Result<DMat4> {
    let [origin, target, up] = lookat_points(op)?;
    let dir = (target - origin)
        .try_normalize()
        .ok_or_else(|| op.error("target equals origin"))?;
    let left = up
        .normalize_or_zero()
        .cross(dir)
        .try_normalize()
        .ok_or_else(|| op.error("up is parallel to the viewing direction"))?;
    let new_up = dir.cross(left);
    Ok(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

/// The axes of `m` (columns of its linear part) with their lengths, if `m`
/// is affine with orthogonal axes (no shear).
pub(crate) fn axes(m: &DMat4) -> Option<([DVec3; 3], DVec3)> {
    if m.row(3) != glam::DVec4::W {
        return None;
    }
    let cols = [
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    ];
    let lengths = DVec3::new(cols[0].length(), cols[1].length(), cols[2].length());
    if lengths.min_element() <= 0.0 {
        return None;
    }
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if cols[i].dot(cols[j]).abs() > 1e-6 * lengths[i] * lengths[j] {
            return None;
        }
    }
    Some((cols, lengths))
}

/// brume's `{ scale, rotate, translate }` equal to `m`, which must be a
/// rotation, a positive (per-axis) scale and a translation.
pub(crate) fn to_brume(m: &DMat4, at: &Node) -> Result<Option<TransformDesc>> {
    let Some((cols, lengths)) = axes(m) else {
        return Err(super::unsupported(
            at,
            "a to_world with shear or projection (brume places shapes by scale, rotation and translation)",
        ));
    };
    if DMat3::from_cols(cols[0], cols[1], cols[2]).determinant() < 0.0 {
        return Err(super::unsupported(
            at,
            "a mirroring to_world (negative scale)",
        ));
    }
    let rotation = DMat3::from_cols(
        cols[0] / lengths.x,
        cols[1] / lengths.y,
        cols[2] / lengths.z,
    );
    let t = m.w_axis.truncate();
    let desc = TransformDesc {
        translate: (t != DVec3::ZERO).then(|| t.as_vec3().to_array()),
        rotate: rotate_degrees(&rotation),
        scale: (lengths != DVec3::ONE).then(|| Color(lengths.as_vec3().to_array())),
        keyframes: None,
    };
    Ok(match (desc.translate, desc.rotate, &desc.scale) {
        (None, None, None) => None,
        _ => Some(desc),
    })
}

/// brume's rotate (degrees about X, then Y, then Z) of an orthonormal
/// matrix; `None` for the identity.
pub(crate) fn rotate_degrees(r: &DMat3) -> Option<[f32; 3]> {
    if *r == DMat3::IDENTITY {
        return None;
    }
    let (z, y, x) = DQuat::from_mat3(r).to_euler(EulerRot::ZYX);
    // + 0.0 turns -0 into +0, as a user would write it.
    Some([x, y, z].map(|a| a.to_degrees() as f32 + 0.0))
}
