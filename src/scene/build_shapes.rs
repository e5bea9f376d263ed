//! The `[[shape]]` entries built into the scene's geometry, with each
//! shape's material, texture, emission and interior medium.

use super::animation::Timing;
use super::description::{self, MaterialDesc, SceneDesc, ShapeDesc};
use super::validate::Check;
use super::{interior, materials, resolve, shapes, textures};
use crate::error::Result;
use crate::geometry::{Geometry, MovingShape, Primitive, BARYCENTRIC_UV};
use crate::material::texture::Texture;
use crate::material::Material;
use crate::math::color::Rgb;
use crate::math::Vec2;
use crate::medium::Medium;
use std::path::Path;

/// The shapes of a scene, built: geometry and what each shape carries.
pub(super) struct Shapes {
    /// All primitives (surfaces and moving shapes) with their texture coordinates.
    pub geometry: Geometry,
    /// The material of each shape.
    pub materials: Vec<Material>,
    /// The texture of each shape's material.
    pub textures: Vec<Option<Texture>>,
    /// The emitted radiance of each shape, if it glows.
    pub emissions: Vec<Option<Texture>>,
    /// The media inside closed shapes.
    pub interiors: Vec<Medium>,
}

/// Builds every `[[shape]]`: primitives, materials, emissions, interiors.
pub(super) fn build_shapes(
    desc: &SceneDesc,
    check: &Check,
    (base, cache): (&Path, &super::InputCache),
    timing: &Timing,
) -> Result<Shapes> {
    let mut surfaces = Surfaces::default();
    let mut moving = Vec::new();
    let mut carried = Carried::default();
    let mut images = textures::ImageCache::default();
    let mut interiors = Vec::new();
    let mut slabs = Vec::new();
    for (i, shape) in desc.shapes.iter().enumerate() {
        let field = format!("shape[{i}]");
        if shape.kind == description::ShapeType::Slab {
            slabs.push(super::slab_keys::build_slab_shape(
                shape,
                (i as u32, &field),
                check,
                (base, cache),
            )?);
            // Indexed like the shapes; a slab has no surface to use them.
            let material = build_material(None, &field, check, base, &mut images)?;
            carried.push(material, None, None);
            continue;
        }
        let mut built = shapes::build_shape(shape, &field, check, base)?;
        require_uv(shape, &field, built.texcoords.is_some(), check, base)?;
        let keys = check_moving_shape(shape, built.keys.take(), &field, check)?;
        let axes = still_sphere_axes(&built, keys.is_some(), &field, check)?;
        let surface = add_interior(shape, &built, &field, (check, base, timing), &mut interiors)?;
        match keys {
            Some(keys) => moving.push(MovingShape::new(i as u32, built.primitives, keys)),
            None if surface => surfaces.add(built, i as u32),
            None => {}
        }
        let material = build_material(shape.material.as_ref(), &field, check, base, &mut images)?;
        super::materials::path_tracer_only(&material.0, &desc.integrator.kind, &field, check)?;
        let emission = build_emission(shape, &field, check, base, &mut images)?;
        carried.push(material, emission, axes);
    }
    Ok(Shapes {
        geometry: surfaces
            .into_geometry()
            .with_moving(moving)
            .with_slabs(slabs)
            .with_sphere_axes(carried.sphere_axes),
        materials: carried.materials,
        textures: carried.textures,
        emissions: carried.emissions,
        interiors,
    })
}

/// What each shape carries besides its primitives, indexed like the shapes.
#[derive(Default)]
struct Carried {
    materials: Vec<Material>,
    textures: Vec<Option<Texture>>,
    emissions: Vec<Option<Texture>>,
    sphere_axes: Vec<Option<[crate::math::Vec3; 3]>>,
}

impl Carried {
    /// The next shape's material with its texture, emission and sphere axes.
    fn push(
        &mut self,
        (material, texture): (Material, Option<Texture>),
        emission: Option<Texture>,
        sphere_axes: Option<[crate::math::Vec3; 3]>,
    ) {
        self.materials.push(material);
        self.textures.push(texture);
        self.emissions.push(emission);
        self.sphere_axes.push(sphere_axes);
    }
}

/// A sphere's texture axes, refused on a moving sphere (they would stay
/// fixed in the world while it turns).
fn still_sphere_axes(
    built: &shapes::BuiltShape,
    moving: bool,
    field: &str,
    check: &Check,
) -> Result<Option<[crate::math::Vec3; 3]>> {
    if moving && built.uv_axes.is_some() {
        return Err(check.error(
            &format!("{field}.uv_axes"),
            "not supported on a moving sphere (its texture axes would stay fixed in the world)",
        ));
    }
    Ok(built.uv_axes)
}

/// The primitives of the static surfaces, each with its shape index and
/// texture coordinates (indexed like the primitives: only surfaces get both).
#[derive(Default)]
struct Surfaces {
    items: Vec<(Primitive, u32)>,
    texcoords: Vec<[Vec2; 3]>,
    any_vt: bool,
}

impl Surfaces {
    /// Adds the primitives of shape `i`.
    fn add(&mut self, built: shapes::BuiltShape, i: u32) {
        let n = built.primitives.len();
        self.items
            .extend(built.primitives.into_iter().map(|p| (p, i)));
        self.any_vt |= built.texcoords.is_some();
        match built.texcoords {
            Some(t) => self.texcoords.extend(t),
            None => self
                .texcoords
                .extend(std::iter::repeat_n(BARYCENTRIC_UV, n)),
        }
    }

    /// The geometry of the surfaces (moving shapes and slabs are added after).
    fn into_geometry(self) -> Geometry {
        // Only OBJ corners carry coordinates of their own: keep no table without them.
        let texcoords = match self.any_vt {
            true => self.texcoords,
            false => Vec::new(),
        };
        Geometry::with_texcoords(self.items, texcoords)
    }
}

/// Builds the medium inside `shape`, if it has one; returns whether the shape
/// is still a surface (a dielectric boundary) or only bounds its medium.
fn add_interior(
    shape: &ShapeDesc,
    built: &shapes::BuiltShape,
    field: &str,
    (check, base, timing): (&Check, &Path, &Timing),
    interiors: &mut Vec<Medium>,
) -> Result<bool> {
    if shape.interior.is_none() {
        return Ok(true);
    }
    let surface = interior::boundary(shape, field, check)? == interior::Boundary::Dielectric;
    interiors.extend(interior::build_interior(
        shape,
        &built.primitives,
        field,
        check,
        base,
        timing,
    )?);
    Ok(surface)
}

/// The emitted radiance of `shape`, a colour or a texture, if it glows.
fn build_emission(
    shape: &ShapeDesc,
    field: &str,
    check: &Check,
    base: &Path,
    images: &mut textures::ImageCache,
) -> Result<Option<Texture>> {
    let Some(e) = &shape.emission else {
        return Ok(None);
    };
    let key = format!("{field}.emission");
    textures::build(check, &key, e, textures::Range::Radiance, base, images).map(Some)
}

/// The keyframes `keys` of a shape, refused where the shape cannot move:
/// with an interior or a texture, or emissive and not scaled uniformly (`light::moving`).
fn check_moving_shape(
    shape: &description::ShapeDesc,
    keys: Option<crate::math::keyframes::Keyframes>,
    field: &str,
    check: &Check,
) -> Result<Option<crate::math::keyframes::Keyframes>> {
    let Some(keys) = keys else {
        return Ok(None);
    };
    if shape.interior.is_some() {
        return Err(check.error(
            &format!("{field}.transform.keyframes"),
            "a shape with an `interior` cannot move yet: keyframe the medium instead, or leave the shape still",
        ));
    }
    if let Some((key, _)) = shape
        .colors()
        .into_iter()
        .find(|(_, c)| matches!(c, description::ColorOrTexture::Texture(_)))
    {
        return Err(check.error(
            &format!("{field}.{key}"),
            "a textured shape cannot move yet (keyframed shapes take constant colours)",
        ));
    }
    let emits = shape
        .emission
        .as_ref()
        .is_some_and(|e| !matches!(e, description::ColorOrTexture::Color(c) if c.0 == [0.0; 3]));
    if emits && !keys.is_uniform_scale() {
        return Err(check.error(
            &format!("{field}.transform.keyframes"),
            "an emissive shape that moves must scale alike on all three axes in every key",
        ));
    }
    Ok(Some(keys))
}

/// Refuses a texture that needs texture coordinates on a mesh whose OBJ file has none.
fn require_uv(
    shape: &ShapeDesc,
    field: &str,
    has_vt: bool,
    check: &Check,
    base: &Path,
) -> Result<()> {
    let (Some(file), false) = (&shape.file, has_vt) else {
        return Ok(());
    };
    let textured = shape
        .colors()
        .into_iter()
        .find(|(_, c)| matches!(c, description::ColorOrTexture::Texture(_)));
    match textured {
        Some((key, _)) => Err(check.error(
            &format!("{field}.{key}"),
            format!(
                "a texture needs texture coordinates, but OBJ file {} has no `vt` lines (in every model)",
                resolve(base, file).display()
            ),
        )),
        None => Ok(()),
    }
}

/// The material of a shape and the texture of its colour parameter, if it has one.
fn build_material(
    desc: Option<&MaterialDesc>,
    field: &str,
    check: &Check,
    base: &Path,
    images: &mut textures::ImageCache,
) -> Result<(Material, Option<Texture>)> {
    let field = format!("{field}.material");
    // A constant stays in the material; a texture replaces it at every hit.
    let mut texture = None;
    let mut color = |key: &str, value: &description::ColorOrTexture| -> Result<Rgb> {
        let t = textures::build(
            check,
            &format!("{field}.{key}"),
            value,
            textures::Range::Albedo,
            base,
            images,
        )?;
        Ok(match t.constant() {
            Some(c) => c,
            None => {
                texture = Some(t);
                Rgb::WHITE
            }
        })
    };
    let material = match desc {
        None => Material::Diffuse {
            albedo: Rgb::splat(0.5),
        },
        Some(desc) => materials::material(desc, check, &field, &mut color)?,
    };
    Ok((material, texture))
}
