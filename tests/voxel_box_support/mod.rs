//! The box of voxels the motion-blur tests move (tests/motion_box.rs by a
//! velocity grid, tests/motion_keyframed_media.rs by keyframes too): its
//! grids, its medium and the closed form of its trilinear profile.
#![allow(dead_code)]

use brume::math::color::Rgb;
use brume::math::{Affine3A, Ray, Vec3};
use brume::medium::{GridEmission, GridMediumParams, GridMotion, MajorantMode, PhaseFunction};
use brume::volume::{FloatGrid, GridTransform, Vec3Grid};
use glam::{DVec3, IVec3};

/// Voxel size (m).
pub const H: f32 = 0.1;
/// Frames per second.
pub const FPS: f32 = 24.0;
/// Extinction per unit density (1/m).
pub const SIGMA: f32 = 2.5;

/// Voxels of size [`H`], index space at the world origin.
pub fn transform() -> GridTransform {
    GridTransform::scale_translate("UniformScaleMap", DVec3::splat(H as f64), DVec3::ZERO).unwrap()
}

/// A grid of `dims` voxels from `origin`, every one `value`.
pub fn dense(origin: IVec3, dims: IVec3, value: f32) -> FloatGrid {
    let n = (dims.x * dims.y * dims.z) as usize;
    FloatGrid::from_dense("g", origin, dims, &vec![value; n], transform()).unwrap()
}

/// 16 × 8 × 8 voxels, dense (1) for x < 8 and light (0.1) beyond: a
/// medium moving it carries dense voxels into cells whose still bound is light.
pub fn half_dense() -> FloatGrid {
    let dims = IVec3::new(16, 8, 8);
    let values: Vec<f32> = (0..dims.x * dims.y * dims.z)
        .map(|i| if i % dims.x < 8 { 1.0 } else { 0.1 })
        .collect();
    FloatGrid::from_dense("d", IVec3::ZERO, dims, &values, transform()).unwrap()
}

/// The medium parameters: σt = [`SIGMA`] per unit density, albedo ½,
/// isotropic, majorant cells of `cell` voxels.
pub fn params(cell: i32) -> GridMediumParams {
    GridMediumParams {
        to_world: Affine3A::IDENTITY,
        density_scale: SIGMA,
        sigma_t_scale: Rgb::WHITE,
        albedo: Rgb::splat(0.5),
        phase: PhaseFunction::Isotropic,
        emission: GridEmission::None,
        majorant: MajorantMode::Grid,
        cell_size: Some(cell),
    }
}

/// The constant velocity `v` (m/s) over a region holding every point the box sweeps.
pub fn constant_velocity(v: Vec3, shutter: [f32; 2]) -> GridMotion {
    let (o, d) = (IVec3::splat(-16), IVec3::splat(40));
    let components = [dense(o, d, v.x), dense(o, d, v.y), dense(o, d, v.z)];
    GridMotion {
        velocity: Vec3Grid::from_components("vel", components).unwrap(),
        scale: 1.0 / FPS,
        shutter,
    }
}

/// The x profile of the trilinear box of voxels 0..=7: 1 on [0, 7], linear to 0 at −1 and 8.
pub fn profile(q: f64) -> f64 {
    (1.0 - (-q).max(q - 7.0).max(0.0)).clamp(0.0, 1.0)
}

/// A ray along +z through index (qx, 3.5, ·) at `time`, crossing the whole box.
pub fn ray_at(qx: f32, time: f32) -> Ray {
    Ray {
        time,
        ..Ray::new(Vec3::new(qx * H, 3.5 * H, -1.0), Vec3::Z)
    }
}
