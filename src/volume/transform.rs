//! Index↔world transforms read from OpenVDB linear maps.

use glam::{DMat4, DVec3};

use super::bytes::Reader;
use super::error::{FResult, FormatError};

/// An affine index→world map: world = M · [i, j, k, 1], voxel centres at integer ijk.
#[derive(Debug, Clone, PartialEq)]
pub struct GridTransform {
    map_type: String,
    forward: DMat4,
    inverse: DMat4,
    /// Set for axis-aligned maps: world→index as OpenVDB computes it,
    /// (p - translation) * inverse scale, so indices round the same way.
    scale_translate: Option<(DVec3, DVec3)>,
}

impl GridTransform {
    /// A transform from an index→world matrix; fails if it is not invertible or not finite.
    pub fn from_matrix(map_type: &str, forward: DMat4) -> Option<GridTransform> {
        let det = forward.determinant();
        if !forward.is_finite() || !det.is_finite() || det.abs() < 1e-300 {
            return None;
        }
        let inverse = forward.inverse();
        inverse.is_finite().then(|| GridTransform {
            map_type: map_type.to_string(),
            forward,
            inverse,
            scale_translate: None,
        })
    }

    /// An axis-aligned scale followed by a translation.
    pub fn scale_translate(map_type: &str, scale: DVec3, translation: DVec3) -> Option<Self> {
        let m = DMat4::from_scale(scale);
        let m = DMat4::from_translation(translation) * m;
        let mut t = GridTransform::from_matrix(map_type, m)?;
        t.scale_translate = Some((translation, DVec3::ONE / scale));
        Some(t)
    }

    /// The OpenVDB map type name this came from (e.g. `UniformScaleMap`, `AffineMap`).
    pub fn map_type(&self) -> &str {
        &self.map_type
    }

    /// Index space → world space.
    pub fn index_to_world(&self, p: DVec3) -> DVec3 {
        self.forward.transform_point3(p)
    }

    /// World space → index space.
    pub fn world_to_index(&self, p: DVec3) -> DVec3 {
        match self.scale_translate {
            Some((t, inv_scale)) => (p - t) * inv_scale,
            None => self.inverse.transform_point3(p),
        }
    }

    /// World → index map of this grid placed in the world by `to_world`: the
    /// inverse of (to_world ∘ index → world), inverted in f64.
    pub fn world_to_index_placed(&self, to_world: &glam::Affine3A) -> glam::Affine3A {
        let m = glam::Mat4::from(*to_world).as_dmat4() * self.index_to_world_matrix();
        let inv: DMat4 = m.inverse();
        glam::Affine3A::from_mat4(inv.as_mat4())
    }

    /// The index→world matrix M with world = M · [i, j, k, 1].
    pub fn index_to_world_matrix(&self) -> DMat4 {
        self.forward
    }

    /// World size of a voxel along each index axis (lengths of M's columns).
    pub fn voxel_size(&self) -> DVec3 {
        DVec3::new(
            self.forward.x_axis.truncate().length(),
            self.forward.y_axis.truncate().length(),
            self.forward.z_axis.truncate().length(),
        )
    }
}

/// Reads an OpenVDB `Transform`: the map type name, then the map's own fields.
pub(crate) fn read_transform(r: &mut Reader) -> FResult<GridTransform> {
    let at = r.pos();
    let map_type = r.string()?;
    let bad = |what: &str| FormatError::corrupt(at, format!("{map_type}: {what}"));
    let t = match map_type.as_str() {
        // scale, voxel size, inverse scale, inverse scale², 1/(2·scale)
        "UniformScaleMap" | "ScaleMap" => {
            let scale = DVec3::from(r.vec3d()?);
            r.take(4 * 24)?;
            GridTransform::scale_translate(&map_type, scale, DVec3::ZERO)
        }
        // translation, then the scale map's fields
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let translation = DVec3::from(r.vec3d()?);
            let scale = DVec3::from(r.vec3d()?);
            r.take(4 * 24)?;
            GridTransform::scale_translate(&map_type, scale, translation)
        }
        "TranslationMap" => {
            let translation = DVec3::from(r.vec3d()?);
            GridTransform::scale_translate(&map_type, DVec3::ONE, translation)
        }
        // a 4x4 matrix for row vectors, [i j k 1] · M, i.e. the transpose of ours
        "AffineMap" | "UnitaryMap" => {
            let mut m = [0.0f64; 16];
            for v in &mut m {
                *v = r.f64()?;
            }
            let forward = DMat4::from_cols_array(&m);
            let last_col = forward.row(3);
            if (last_col - glam::DVec4::W).abs().max_element() > 1e-12 {
                return Err(bad("matrix is not affine"));
            }
            GridTransform::from_matrix(&map_type, forward)
        }
        _ => {
            return Err(FormatError::Unsupported(format!(
                "transform map '{map_type}' (brume reads linear maps: scale, translation, affine)"
            )))
        }
    };
    t.ok_or_else(|| bad("map is singular or not finite"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_translate_round_trip() {
        let t = GridTransform::scale_translate(
            "ScaleTranslateMap",
            DVec3::new(0.5, 2.0, 0.25),
            DVec3::new(1.0, -2.0, 3.0),
        )
        .unwrap();
        let p = DVec3::new(3.0, 4.0, -5.0);
        let w = t.index_to_world(p);
        assert_eq!(w, DVec3::new(2.5, 6.0, 1.75));
        assert!((t.world_to_index(w) - p).length() < 1e-12);
        assert_eq!(t.voxel_size(), DVec3::new(0.5, 2.0, 0.25));
    }

    #[test]
    fn singular_matrix_is_rejected() {
        assert!(GridTransform::from_matrix("AffineMap", DMat4::ZERO).is_none());
    }
}
