//! Velocity-grid ("Eulerian") motion blur for grid media.
//!
//! ```toml
//! [camera]
//! shutter = [-0.25, 0.25]         # frames, relative to the frame's time
//!
//! [animation]
//! fps = 24.0                      # turns velocities per second into per frame
//!
//! [[medium]]
//! type = "vdb"
//! file = "smoke.####.vdb"
//! velocity_grid = "vel"           # a vec3s grid, world units per second
//! velocity_scale = 1.0            # multiplies the velocities
//! ```
//!
//! # Model
//!
//! A camera sample's time t (frames from the frame's time) is uniform over
//! the shutter. The medium at time t is the frame's medium advected along
//! the velocity field v, to first order (semi-Lagrangian, backward):
//!
//! ```text
//! σ(x, t) = σ_frame(x − S·v(x)·t),   S = to_world linear part · velocity_scale / fps
//! ```
//!
//! with v looked up trilinearly at x in the velocity grid's own index space
//! (values in the file's world units). Emission is advected with the
//! density. With v = 0 the displaced point is x exactly (x − 0 = x in floating
//! point), so a still medium renders bit-identically with or without a shutter.
//!
//! # Unbiasedness
//!
//! The time is fixed per camera sample and carried by every ray of the path,
//! shadow rays included ([`crate::math::Ray::time`]). Conditioned on t, the
//! path therefore sees a static medium σ(·, t), tracked against a majorant
//! that bounds σ(·, t) for every t in the shutter. Delta, ratio and residual
//! ratio tracking are unbiased for any static medium under a valid majorant,
//! so each path is an unbiased estimate of the image at time t, and the
//! average over t ~ U(shutter) is an unbiased estimate of the image averaged
//! over the shutter.
//!
//! # The majorant over the shutter (dilation)
//!
//! Let `B` = (world → density-index linear map)·S, `V_j` the largest |value|
//! of velocity component j that any trilinear lookup returns (over every
//! stored voxel, tile and the background: a trilinear value is a convex
//! combination of those), and `T` = max(|open|, |close|). In density index
//! space the looked-up point is q' = q − B·v(x)·t, so for every x and every
//! t in the shutter
//!
//! ```text
//! |q'_i − q_i| ≤ r_i = T · Σ_j |B_ij| · V_j      (per axis i)
//! ```
//!
//! (padded by a relative 1e-3 and 0.01 voxel for the f32 rounding of the
//! displaced point). Take the static majorant cells (size c) over the box
//! [lo − K·c, hi + K·c], K_i = ⌈r_i / c_i⌉, where [lo, hi] is the box outside
//! which the frame's density is 0, and give each cell the max (and min) over
//! its (2K + 1)³ neighbourhood ([`MajorantGrid::dilated`]). Claim: for x in
//! cell C and any t in the shutter, min'(C) ≤ σ(x, t) ≤ max'(C).
//!
//! Proof. q' lies in the box C ⊕ [−r, r], which the neighbours of C within K
//! cells cover (r_i ≤ K_i·c_i). If q' lies in a neighbour N, the static
//! bounds of N hold at q' (they bound every trilinear lookup in N), and the
//! filtered bounds of C include N's. If q' ∉ [lo, hi], σ(x, t) = 0 ≤ max'(C);
//! and then q' lies outside the grid or in a neighbour not inside [lo, hi],
//! whose minimum the filter takes as 0, so min'(C) = 0. Points x outside the
//! tracked box [lo − K·c, hi + K·c] have q' outside [lo, hi] (|q' − q| ≤ r),
//! so nothing is lost by tracking only inside it. ∎
//!
//! Cost: wider cells' bounds mean more null collisions, and every density
//! lookup adds a velocity lookup; with no velocity grid nothing changes.

use glam::{IVec3, Mat3, Vec3};

use super::majorant_grid::MajorantGrid;
use crate::math::Affine3A;
use crate::volume::{FloatGrid, Vec3Grid};

/// What moves a grid medium over the shutter.
#[derive(Clone, Debug)]
pub struct GridMotion {
    /// Velocity in the file's world units per second.
    pub velocity: Vec3Grid,
    /// `velocity_scale / fps`: velocity × this × time in frames = displacement in the file's world units.
    pub scale: f32,
    /// The shutter `[open, close]` in frames from the frame's time that the majorant must cover.
    pub shutter: [f32; 2],
}

/// Velocity lookups of a placed grid medium.
#[derive(Clone, Debug)]
pub(crate) struct MotionLookup {
    velocity: Vec3Grid,
    /// Scene world → velocity index space.
    world_to_index: Affine3A,
    /// Velocity (file units per second) → scene-world displacement per frame.
    step: Mat3,
}

/// Relative and absolute (voxels) widening of the dilation radius for f32 rounding.
const DILATION_PAD: (f32, f32) = (1e-3, 1e-2);

impl MotionLookup {
    /// Velocity lookups for a medium placed by `to_world`, and the dilation
    /// radius `r` in `density` index voxels per axis (see the module doc).
    pub(crate) fn new(
        motion: &GridMotion,
        to_world: &Affine3A,
        density_world_to_index: &Affine3A,
    ) -> (MotionLookup, Vec3) {
        let world_to_index = motion.velocity.transform().world_to_index_placed(to_world);
        let step = Mat3::from(to_world.matrix3) * motion.scale;
        let b = Mat3::from(density_world_to_index.matrix3) * step;
        let v = motion.velocity.max_abs_lookup();
        let t = motion.shutter[0].abs().max(motion.shutter[1].abs());
        let row = |i: usize| {
            let r = b.row(i).abs().dot(v) * t;
            if r > 0.0 {
                r * (1.0 + DILATION_PAD.0) + DILATION_PAD.1
            } else {
                0.0
            }
        };
        let lookup = MotionLookup {
            velocity: motion.velocity.clone(),
            world_to_index,
            step,
        };
        (lookup, Vec3::new(row(0), row(1), row(2)))
    }

    /// Where the frame's medium is looked up for world point `p` at `time`.
    #[inline]
    pub(crate) fn displaced(&self, p: Vec3, time: f32) -> Vec3 {
        let v = self
            .velocity
            .trilinear_index(self.world_to_index.transform_point3(p));
        p - self.step * (v * time)
    }
}

/// Cells of dilation per axis for radius `r` voxels and cells of `cell` voxels.
pub(crate) fn dilation_cells(r: Vec3, cell: Vec3) -> IVec3 {
    (r / cell).ceil().as_ivec3()
}

/// The static majorant grid over the box `[lo, hi]` widened by `k` cells,
/// dilated to cover the shutter, and that widening (index units).
pub(crate) fn dilated_majorants(
    density: &FloatGrid,
    lo: Vec3,
    hi: Vec3,
    cell: Vec3,
    k: IVec3,
) -> (MajorantGrid, Vec3) {
    let pad = k.as_vec3() * cell;
    let grid = MajorantGrid::build(density, lo - pad, hi + pad, cell).dilated(k, (lo, hi));
    (grid, pad)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A medium that moves up to `r` voxels over the shutter needs its
    /// majorants widened by ⌈r / cell⌉ cells: a cell short and the bound
    /// misses density that moved in; more only costs null collisions.
    #[test]
    fn motion_widens_the_majorants_by_whole_cells_covering_the_radius() {
        let cell = Vec3::splat(4.0);
        let r = Vec3::new(5.0, 8.0, 0.5);
        assert_eq!(dilation_cells(r, cell), IVec3::new(2, 2, 1));
        assert_eq!(dilation_cells(Vec3::ZERO, cell), IVec3::ZERO);
    }
}
