//! A heterogeneous medium over a sparse density grid (OpenVDB).
//!
//! ```toml
//! [[medium]]
//! type = "vdb"
//! file = "../volumes/smoke_plume.vdb"
//! grid = "density"
//! density_scale = 20.0
//! albedo = [0.9, 0.9, 0.9]
//! phase = { type = "hg", g = 0.3 }
//! ```
//!
//! σt(x) = density(x) · `density_scale` · `sigma_t_scale` (per channel, per
//! unit of world length), σs = albedo·σt, σa = (1 - albedo)·σt, where
//! density(x) is the trilinear (OpenVDB BoxSampler) lookup at the index-space
//! point of x, clamped to ≥ 0, and zero outside the active bounding box
//! widened by one voxel. World → index is the inverse of (scene transform ∘
//! the file's index → world map). Rays keep their parameter t in index
//! space (the direction is mapped, not renormalized), so the majorant
//! segments found there apply to the world ray unchanged.

use glam::IVec3;

use super::blackbody::BlackbodyTable;
use super::channels::ChannelGrids;
use super::majorant_grid::{Dda, MajorantGrid};
use super::motion::{GridMotion, MotionLookup};
use super::voxel::VoxelWalk;
use super::{MajorantSegment, MediumProperties, PhaseFunction};
use crate::math::color::Rgb;
use crate::math::{Affine3A, Bounds3, Ray, Vec3};
use crate::volume::FloatGrid;

mod majorants;
use majorants::{build_majorants, choose_cell_size};
pub use majorants::{default_cell_size, MajorantTooLarge};

/// How tracking bounds the density along a ray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MajorantMode {
    /// A coarse grid of per-cell bounds walked by a DDA.
    #[default]
    Grid,
    /// One bound for the whole volume (for comparison).
    Global,
}

/// Where tracking integrates the trilinear density exactly, voxel cell by
/// voxel cell (`medium::voxel`), instead of taking null collisions.
///
/// Both are unbiased; the choice is one of cost. A majorant segment costs
/// σ̄ tentative collisions per unit length under null-collision tracking and
/// about ‖d‖₁ voxel steps (d: the index-space direction) under the exact walk.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ExactVoxels {
    /// Exact in majorant segments with at least [`EXACT_VOXEL_DEPTH`] expected
    /// tentative collisions per voxel step (dense cells), null collisions elsewhere.
    #[default]
    Auto,
    /// Exact everywhere (for tests).
    Always,
    /// Null collisions everywhere (for tests and comparisons).
    Never,
}

/// Expected tentative collisions per voxel step above which a majorant
/// segment is walked voxel by voxel with exact optical depths (see [`ExactVoxels`]).
pub const EXACT_VOXEL_DEPTH: f32 = 1.0;

/// Where the emitted radiance Le of a grid medium comes from (the source term is σa·Le).
#[derive(Clone, Debug, Default)]
pub enum GridEmission {
    /// No emission.
    #[default]
    None,
    /// The same Le everywhere.
    Constant(Rgb),
    /// Le = `emission_scale` · blackbody(temperature · `temperature_scale` K) (see `blackbody`).
    Blackbody {
        /// The temperature grid.
        temperature: FloatGrid,
        /// Kelvin per unit of grid value.
        temperature_scale: f32,
        /// Multiplies the blackbody radiance.
        emission_scale: Rgb,
    },
    /// Le = `emission_scale` · emission grid value.
    Grid {
        /// The emission grid.
        grid: FloatGrid,
        /// Multiplies the grid value.
        emission_scale: Rgb,
    },
}

/// Everything but the density grid that defines a grid medium.
#[derive(Clone, Debug)]
pub struct GridMediumParams {
    /// Scene placement, applied after the file's index → world map.
    pub to_world: Affine3A,
    /// Extinction per unit density.
    pub density_scale: f32,
    /// Per-channel factor on `density_scale` (chromatic extinction).
    pub sigma_t_scale: Rgb,
    /// Single-scattering albedo σs/σt.
    pub albedo: Rgb,
    /// Phase function.
    pub phase: PhaseFunction,
    /// Emission.
    pub emission: GridEmission,
    /// Majorant grid or one global majorant.
    pub majorant: MajorantMode,
    /// Majorant cell size in voxels (default: chosen from the volume's extent).
    pub cell_size: Option<i32>,
}

/// Emission ready for lookups: grid, its world → index map, and the factors.
#[derive(Clone, Debug)]
enum EmissionSource {
    None,
    Constant(Rgb),
    Blackbody {
        temperature: FloatGrid,
        world_to_index: Affine3A,
        temperature_scale: f32,
        emission_scale: Rgb,
        table: BlackbodyTable,
    },
    Grid {
        grid: FloatGrid,
        world_to_index: Affine3A,
        emission_scale: Rgb,
    },
}

/// A medium whose density comes from a sparse grid.
#[derive(Clone, Debug)]
pub struct GridMedium {
    density: FloatGrid,
    world_to_index: Affine3A,
    /// Index-space box outside which the density is zero.
    bounds: Bounds3,
    sigma_t_unit: Rgb,
    albedo: Rgb,
    phase: PhaseFunction,
    emission: EmissionSource,
    majorants: MajorantGrid,
    /// Velocity motion blur (see `motion`), if the medium moves.
    motion: Option<MotionLookup>,
    /// Index-space box tracked by the DDA: `bounds`, dilated by the motion over the shutter.
    track_bounds: Bounds3,
    /// Where tracking integrates voxels exactly.
    exact: ExactVoxels,
    /// Whether some stored value (or the background) is negative, so that the lookup's clamp to 0 can act.
    may_clamp: bool,
    /// The largest majorant of any cell (per unit ray parameter).
    peak_majorant: f32,
    /// Per-channel σt and albedo grids (`.vol` media), if any; `density` is then the largest σt channel.
    channels: Option<Box<ChannelGrids>>,
    /// Factor on a majorant cell's minimum giving its control extinction.
    control_unit: Rgb,
}

/// World → index map of a grid placed by `to_world`, as the inverse of (to_world ∘ index → world) in f64.
fn index_map(grid: &FloatGrid, to_world: &Affine3A) -> Affine3A {
    grid.transform().world_to_index_placed(to_world)
}

/// The emission lookups of a grid medium placed by `to_world`.
fn emission_source(emission: GridEmission, to_world: &Affine3A) -> EmissionSource {
    match emission {
        GridEmission::None => EmissionSource::None,
        GridEmission::Constant(le) => EmissionSource::Constant(le),
        GridEmission::Blackbody {
            temperature,
            temperature_scale,
            emission_scale,
        } => {
            let t_max = temperature.value_range().1.max(temperature.background());
            EmissionSource::Blackbody {
                world_to_index: index_map(&temperature, to_world),
                table: BlackbodyTable::new(t_max * temperature_scale),
                temperature,
                temperature_scale,
                emission_scale,
            }
        }
        GridEmission::Grid {
            grid,
            emission_scale,
        } => EmissionSource::Grid {
            world_to_index: index_map(&grid, to_world),
            grid,
            emission_scale,
        },
    }
}

impl GridMedium {
    /// A medium over `density` (any origin: a VDB file's grid or one built in code).
    ///
    /// Panics when its majorant grid is over the memory limit (see [`GridMedium::try_new_moving`]).
    pub fn new(density: FloatGrid, params: GridMediumParams) -> GridMedium {
        GridMedium::new_moving(density, params, None)
    }

    /// A medium over `density`, advected by `motion` over the shutter (module `motion`).
    ///
    /// Panics when its majorant grid is over the memory limit: scene loading
    /// uses [`GridMedium::try_new_moving`], which reports it.
    pub fn new_moving(
        density: FloatGrid,
        params: GridMediumParams,
        motion: Option<GridMotion>,
    ) -> GridMedium {
        GridMedium::try_new_moving(density, params, motion)
            .unwrap_or_else(|e| panic!("majorant grid of {}", e.grid))
    }

    /// [`GridMedium::new_moving`], or the majorant grid it would need when
    /// that is over the memory limit (extreme velocities, a sparse grid
    /// spanning a huge box with a small `cell_size`).
    pub fn try_new_moving(
        density: FloatGrid,
        params: GridMediumParams,
        motion: Option<GridMotion>,
    ) -> Result<GridMedium, MajorantTooLarge> {
        let world_to_index = index_map(&density, &params.to_world);
        let may_clamp = density.background() < 0.0 || density.blocks().any(|b| b.min_value < 0.0);
        // Trilinear lookups reach one voxel beyond the active voxels.
        let (lo, hi) = density
            .index_bbox_active()
            .map(|(lo, hi)| {
                (
                    lo.saturating_sub(IVec3::ONE).as_vec3(),
                    hi.saturating_add(IVec3::ONE).as_vec3(),
                )
            })
            .unwrap_or((Vec3::ZERO, Vec3::ZERO));
        let cell = choose_cell_size(&density, &params, motion.is_some(), lo, hi);
        let majorants::Majorants {
            motion,
            grid: majorants,
            track: (track_lo, track_hi),
        } = build_majorants(
            &density,
            motion.as_ref(),
            (&params, &world_to_index),
            (lo, hi),
            cell,
        )?;
        let emission = emission_source(params.emission, &params.to_world);
        let peak_majorant =
            majorants.global_max() * (params.sigma_t_scale * params.density_scale).max_channel();
        Ok(GridMedium {
            density,
            world_to_index,
            bounds: Bounds3 { min: lo, max: hi },
            sigma_t_unit: params.sigma_t_scale * params.density_scale,
            albedo: params.albedo,
            phase: params.phase,
            emission,
            majorants,
            motion,
            track_bounds: Bounds3 {
                min: track_lo,
                max: track_hi,
            },
            exact: ExactVoxels::Auto,
            may_clamp,
            peak_majorant,
            channels: None,
            control_unit: params.sigma_t_scale * params.density_scale,
        })
    }

    /// Chooses where tracking integrates voxels exactly (default [`ExactVoxels::Auto`]).
    pub fn set_exact_voxels(&mut self, exact: ExactVoxels) {
        self.exact = exact;
    }

    /// Whether tracking may walk voxels exactly: for free flights (`flight`)
    /// the extinction must be grey, so that one distance distribution serves
    /// every channel (transmittance is exact per channel); moving media are
    /// looked up at displaced points, not along a line, so never.
    #[inline]
    pub fn exact_possible(&self, flight: bool) -> bool {
        let k = self.sigma_t_unit;
        self.exact != ExactVoxels::Never
            && self.motion.is_none()
            && self.channels.is_none()
            && !(flight && k.min_channel() != k.max_channel())
    }

    /// Whether some segment of `ray` may be walked exactly: [`Self::exact_possible`],
    /// and the volume's largest majorant reaches [`Self::exact_rate`] for this
    /// direction (else tracking keeps its null-collision loops, untouched).
    #[inline]
    pub fn may_walk_exactly(&self, ray: &Ray, flight: bool) -> bool {
        self.exact_possible(flight)
            && self.peak_majorant
                >= self.exact_rate(self.world_to_index.transform_vector3(ray.direction))
    }

    /// The majorant (per unit ray parameter) at or above which a segment of a
    /// ray with index-space direction `d` is walked exactly.
    #[inline]
    pub fn exact_rate(&self, d: Vec3) -> f32 {
        match self.exact {
            ExactVoxels::Never => f32::INFINITY,
            ExactVoxels::Always => 0.0,
            ExactVoxels::Auto => EXACT_VOXEL_DEPTH * d.abs().element_sum(),
        }
    }

    /// The voxel cells the index-space ray `o + t·d` crosses over `[t0, t1]`, with the density along each.
    #[inline]
    pub fn voxels(&self, o: Vec3, d: Vec3, t0: f32, t1: f32) -> VoxelWalk<'_> {
        VoxelWalk::new(&self.density, self.may_clamp, o, d, t0, t1)
    }

    /// The density grid.
    pub fn density_grid(&self) -> &FloatGrid {
        &self.density
    }

    /// The majorant grid (one cell in global mode).
    pub fn majorant_grid(&self) -> &MajorantGrid {
        &self.majorants
    }

    /// σt per unit density (per channel).
    pub fn sigma_t_unit(&self) -> Rgb {
        self.sigma_t_unit
    }

    /// Single-scattering albedo σs/σt.
    pub fn albedo(&self) -> Rgb {
        self.albedo
    }

    /// The albedo, where it is the same everywhere (no albedo grid).
    pub fn constant_albedo(&self) -> Option<Rgb> {
        match &self.channels {
            Some(c) if c.albedo.is_some() => None,
            _ => Some(self.albedo),
        }
    }

    /// Clamped density at world point `p`.
    #[inline]
    pub fn density(&self, p: Vec3) -> f32 {
        let q = self.world_to_index.transform_point3(p);
        if self.bounds.contains(q) {
            // max also turns a NaN into 0
            self.density.trilinear_index(q).max(0.0)
        } else {
            0.0
        }
    }

    /// Extinction at world point `p` (one density lookup, no emission).
    #[inline]
    pub fn sigma_t(&self, p: Vec3) -> Rgb {
        match &self.channels {
            None => self.sigma_t_unit * self.density(p),
            Some(c) => self.channel_sigma_t(c, p),
        }
    }

    /// Coefficients at world point `p`.
    #[inline]
    pub fn properties(&self, p: Vec3) -> MediumProperties {
        match &self.channels {
            None => self.properties_with_density(p, self.density(p)),
            Some(c) => self.channel_properties(c, p),
        }
    }

    /// σt from per-channel grids (or the density when σt is grey).
    fn channel_sigma_t(&self, c: &ChannelGrids, p: Vec3) -> Rgb {
        let q = self.world_to_index.transform_point3(p);
        if !self.bounds.contains(q) {
            return Rgb::BLACK;
        }
        match &c.sigma_t {
            Some(rgb) => self.sigma_t_unit * rgb.lookup(q),
            None => self.sigma_t_unit * self.density.trilinear_index(q).max(0.0),
        }
    }

    /// Coefficients with per-channel σt and the albedo grid looked up at `p`.
    fn channel_properties(&self, c: &ChannelGrids, p: Vec3) -> MediumProperties {
        let sigma_t = self.channel_sigma_t(c, p);
        let albedo = match &c.albedo {
            Some(a) => a.lookup_clamped(p),
            None => self.albedo,
        };
        self.properties_from(p, sigma_t, albedo)
    }

    /// The coefficients at `p` of extinction `sigma_t` and `albedo` (with the
    /// medium's emission where it absorbs).
    #[inline]
    fn properties_from(&self, p: Vec3, sigma_t: Rgb, albedo: Rgb) -> MediumProperties {
        let sigma_s = sigma_t * albedo;
        let sigma_a = sigma_t - sigma_s;
        let emission = if sigma_a.is_black() {
            Rgb::BLACK
        } else {
            self.emission_at(p)
        };
        MediumProperties {
            sigma_a,
            sigma_s,
            emission,
            phase: self.phase,
        }
    }

    /// Adds per-channel σt and albedo grids (see [`ChannelGrids`]); exact
    /// voxel walks are then off (they integrate the one density grid).
    pub fn set_channels(&mut self, channels: ChannelGrids) {
        if channels.sigma_t.is_some() {
            // The largest channel's minimum bounds no single channel from below.
            self.control_unit = Rgb::BLACK;
        }
        self.channels = Some(Box::new(channels));
    }

    /// Zero outside the index box `clip` (Mitsuba's grid bounding box): both
    /// the lookups and the box tracking walks, so exact voxel walks stay exact.
    pub fn set_clip(&mut self, clip: Bounds3) {
        let cut = |b: Bounds3| Bounds3 {
            min: b.min.max(clip.min),
            max: b.max.min(clip.max),
        };
        self.bounds = cut(self.bounds);
        self.track_bounds = cut(self.track_bounds);
    }

    /// Coefficients at world point `p` where the (clamped) density is `density`.
    #[inline]
    pub fn properties_with_density(&self, p: Vec3, density: f32) -> MediumProperties {
        self.properties_from(p, self.sigma_t_unit * density, self.albedo)
    }

    /// Coefficients at world point `p` at `time` (frames from the frame's time).
    #[inline]
    pub fn properties_at(&self, p: Vec3, time: f32) -> MediumProperties {
        match &self.motion {
            None => self.properties(p),
            Some(m) => self.properties(m.displaced(p, time)),
        }
    }

    /// Extinction at world point `p` at `time` (one density lookup, no emission).
    #[inline]
    pub fn sigma_t_at(&self, p: Vec3, time: f32) -> Rgb {
        match &self.motion {
            None => self.sigma_t(p),
            Some(m) => self.sigma_t(m.displaced(p, time)),
        }
    }

    /// True when a velocity grid moves the medium over the shutter.
    pub fn is_moving(&self) -> bool {
        self.motion.is_some()
    }

    /// Emitted radiance Le at world point `p`.
    pub fn emission_at(&self, p: Vec3) -> Rgb {
        match &self.emission {
            EmissionSource::None => Rgb::BLACK,
            EmissionSource::Constant(le) => *le,
            EmissionSource::Blackbody {
                temperature,
                world_to_index,
                temperature_scale,
                emission_scale,
                table,
            } => {
                let t = temperature.trilinear_index(world_to_index.transform_point3(p));
                *emission_scale * table.lookup(t * temperature_scale)
            }
            EmissionSource::Grid {
                grid,
                world_to_index,
                emission_scale,
            } => {
                let v = grid.trilinear_index(world_to_index.transform_point3(p));
                *emission_scale * v.max(0.0)
            }
        }
    }

    /// Majorant segments along `ray` within `[0, t_max)`: one per non-empty majorant cell crossed.
    pub fn majorants(&self, ray: &Ray, t_max: f32) -> GridMajorants<'_> {
        let index_ray = Ray::new(
            self.world_to_index.transform_point3(ray.origin),
            self.world_to_index.transform_vector3(ray.direction),
        );
        let dda = self
            .track_bounds
            .intersect_ray(&index_ray, t_max)
            .filter(|(t0, t1)| t0 < t1)
            .map(|(t0, t1)| {
                self.majorants
                    .walk(index_ray.origin, index_ray.direction, t0, t1)
            });
        GridMajorants {
            origin: index_ray.origin,
            direction: index_ray.direction,
            // Borrowed, not an Arc clone: no atomic on a shared cache line per ray.
            grid: &self.majorants,
            dda,
            sigma_t_unit: self.sigma_t_unit,
            control_unit: self.control_unit,
        }
    }
}

/// The majorant segments of a grid medium along one ray (a DDA over majorant cells).
#[derive(Clone, Debug)]
pub struct GridMajorants<'a> {
    origin: Vec3,
    direction: Vec3,
    grid: &'a MajorantGrid,
    dda: Option<Dda>,
    sigma_t_unit: Rgb,
    /// Factor on a cell's minimum giving the control extinction (zero when no lower bound is known).
    control_unit: Rgb,
}

impl GridMajorants<'_> {
    /// The ray in index space (origin, direction), with the world ray's parameter.
    pub fn index_ray(&self) -> (Vec3, Vec3) {
        (self.origin, self.direction)
    }
}

impl Iterator for GridMajorants<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        let dda = self.dda.as_mut()?;
        let dims = self.grid.dims();
        loop {
            let (cell, t0, t1) = dda.next_cell(dims)?;
            let (min, max) = self.grid.bounds(cell);
            // Empty cells and zero-length steps hold no collisions.
            if max <= 0.0 || t1 <= t0 {
                continue;
            }
            return Some(MajorantSegment {
                t0,
                t1,
                sigma_maj: max * self.sigma_t_unit.max_channel(),
                decay: 0.0,
                sigma_control: self.control_unit * min,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::GridTransform;

    fn grid_of(values: &[f32], voxel: f64) -> FloatGrid {
        let t = GridTransform::scale_translate(
            "UniformScaleMap",
            glam::DVec3::splat(voxel),
            glam::DVec3::ZERO,
        )
        .expect("transform");
        let dims = IVec3::new(values.len() as i32, 1, 1);
        FloatGrid::from_dense("density", IVec3::ZERO, dims, values, t).expect("grid")
    }

    fn params(to_world: Affine3A) -> GridMediumParams {
        GridMediumParams {
            to_world,
            density_scale: 1.0,
            sigma_t_scale: Rgb::WHITE,
            albedo: Rgb::splat(0.5),
            phase: PhaseFunction::Isotropic,
            emission: GridEmission::None,
            majorant: MajorantMode::Grid,
            cell_size: None,
        }
    }

    /// Two leaves at the two ends of the i32 index range (a damaged or hostile
    /// VDB file): the default cells grow so that the majorant grid stays within
    /// 2²² cells, its index arithmetic does not overflow, and the cells holding
    /// the leaves bound their density.
    #[test]
    fn a_grid_spanning_the_whole_index_range_gets_a_bounded_majorant_grid() {
        let mut b = crate::volume::GridBuilder::default();
        for origin in [IVec3::new(i32::MIN, 0, 0), IVec3::new(i32::MAX - 7, 0, 0)] {
            b.leaf_origins.push(origin);
            b.leaf_masks.push([u64::MAX; 8]);
            b.leaf_values.extend([2.0f32; 512]);
        }
        let t = GridTransform::scale_translate("ScaleMap", glam::DVec3::ONE, glam::DVec3::ZERO);
        let grid = b.finish("far", 0.0, t.expect("transform")).expect("grid");
        let medium = GridMedium::try_new_moving(grid, params(Affine3A::IDENTITY), None)
            .expect("a bounded majorant grid");
        let m = medium.majorant_grid();
        let cells = m.dims().as_i64vec3().element_product();
        assert!(cells <= 1 << 22, "{} cells", m.dims());
        let last = m.dims().x - 1;
        for x in [0, last] {
            let c = IVec3::new(x, 0, 0);
            assert!(m.bounds(c).1 >= 2.0, "cell {c}: {:?}", m.bounds(c));
        }
    }

    /// Along a row of 1 to 13 voxels, rays both ways (and one starting
    /// inside): wherever the lookup is non-zero, some majorant segment
    /// holds the point and bounds it. Rows whose support is a whole number of
    /// cells are among them, where a grid box one half voxel short loses its
    /// last cell.
    #[test]
    fn majorant_segments_cover_and_bound_every_lookup_of_a_row() {
        for n in 1..=13 {
            let values: Vec<f32> = (0..n).map(|i| 1.0 + (i % 3) as f32).collect();
            let medium = GridMedium::new(grid_of(&values, 0.1), params(Affine3A::IDENTITY));
            let (y, z) = (0.05, 0.05);
            let rays = [
                Ray::new(Vec3::new(-1.0, y, z), Vec3::X),
                Ray::new(Vec3::new(0.1 * n as f32 + 1.0, y, z), -Vec3::X),
                Ray::new(Vec3::new(0.1 * n as f32 * 0.5, y, z), Vec3::X),
            ];
            for ray in rays {
                let segments: Vec<MajorantSegment> = medium.majorants(&ray, 10.0).collect();
                let mut inside = 0;
                for k in 0..20_000 {
                    let t = 3.0 * (k as f32 + 0.5) / 20_000.0;
                    let sigma_t = medium.sigma_t(ray.at(t)).max_channel();
                    if sigma_t == 0.0 {
                        continue;
                    }
                    inside += 1;
                    let holder = segments.iter().find(|s| s.t0 <= t && t < s.t1);
                    let Some(seg) = holder else {
                        panic!(
                            "{n} voxels, {ray:?}: σt {sigma_t} at t = {t} outside every segment"
                        );
                    };
                    assert!(
                        sigma_t <= seg.sigma_maj,
                        "{n} voxels: σt {sigma_t} > σ̄ {} at t = {t}",
                        seg.sigma_maj
                    );
                }
                assert!(
                    inside > 100,
                    "{n} voxels, {ray:?}: the ray must cross the row"
                );
            }
        }
    }

    /// The cells a medium gets: a 32nd of the trilinear support (225 voxels
    /// for a row of 224: 8), no more than 3 / (peak σt per voxel) voxels
    /// but at least 2 where dense cells are walked exactly (grey σt: 3 at a
    /// peak of 2 · 5 · 0.1 = 1, 2 at 1.6 and above), else no more than 8 /
    /// (peak σt per voxel) voxels: 2 at a peak of 2 · 16 · 0.1 = 3.2, the
    /// default again at a peak of 0.04.
    #[test]
    fn a_medium_gets_the_cells_its_tracking_needs() {
        let values: Vec<f32> = (0..224).map(|i| 1.0 + (i % 2) as f32).collect();
        let cases = [
            (Rgb::WHITE, 0.1, 8.0),
            (Rgb::WHITE, 1.8, 8.0),
            (Rgb::WHITE, 5.0, 3.0),
            (Rgb::WHITE, 8.0, 2.0),
            (Rgb::WHITE, 1000.0, 2.0),
            (Rgb::new(1.0, 1.0, 2.0), 8.0, 2.0),
            (Rgb::new(1.0, 1.0, 2.0), 0.1, 8.0),
        ];
        for (sigma_t_scale, density_scale, cell) in cases {
            let params = GridMediumParams {
                sigma_t_scale,
                density_scale,
                ..params(Affine3A::IDENTITY)
            };
            let medium = GridMedium::new(grid_of(&values, 0.1), params);
            assert_eq!(
                medium.majorant_grid().cell_size(),
                Vec3::splat(cell),
                "σt scale {sigma_t_scale:?}, density scale {density_scale}"
            );
        }
    }

    /// `Auto` walks a segment exactly from one expected collision per voxel
    /// the ray crosses on (a ray crosses |dx| + |dy| + |dz| voxels per unit);
    /// `Always` walks every segment, `Never` none.
    #[test]
    fn exact_walks_start_at_one_collision_per_voxel_crossed() {
        let mut medium = GridMedium::new(grid_of(&[1.0, 2.0], 0.1), params(Affine3A::IDENTITY));
        let d = Vec3::new(2.0, -3.0, 0.5);
        for (mode, rate) in [
            (ExactVoxels::Auto, 5.5),
            (ExactVoxels::Always, 0.0),
            (ExactVoxels::Never, f32::INFINITY),
        ] {
            medium.set_exact_voxels(mode);
            assert_eq!(medium.exact_rate(d), rate, "{mode:?}");
        }
    }

    /// Without a velocity grid a medium is static (`tests/motion_blur.rs`
    /// checks the moving case).
    #[test]
    fn a_medium_without_velocities_is_static() {
        let medium = GridMedium::new(grid_of(&[1.0, 2.0], 0.1), params(Affine3A::IDENTITY));
        assert!(!medium.is_moving());
    }

    /// Lookups clamp negative values to 0 only where the grid holds some: a
    /// single negative voxel must switch the clamp on, non-negative grids leave it off.
    #[test]
    fn a_negative_voxel_switches_the_clamp_on() {
        let with =
            |values: &[f32]| GridMedium::new(grid_of(values, 0.1), params(Affine3A::IDENTITY));
        assert!(!with(&[0.0, 1.0, 2.0, 0.5]).may_clamp);
        assert!(with(&[0.0, 1.0, -0.25, 0.5]).may_clamp);
    }

    /// Only the background is negative (one full leaf of positive voxels):
    /// lookups beyond the box read it, so the clamp must be on; a positive
    /// or zero background leaves it off.
    #[test]
    fn a_negative_background_switches_the_clamp_on() {
        let values = [0.5f32; 512];
        let with = |background: f32| {
            let t = GridTransform::scale_translate(
                "UniformScaleMap",
                glam::DVec3::splat(0.1),
                glam::DVec3::ZERO,
            )
            .expect("transform");
            let density = FloatGrid::from_dense_over(
                "density",
                IVec3::ZERO,
                IVec3::splat(8),
                &values,
                background,
                t,
            )
            .expect("grid");
            assert_eq!(density.background(), background);
            GridMedium::new(density, params(Affine3A::IDENTITY)).may_clamp
        };
        assert!(with(-0.25));
        assert!(!with(0.0));
        assert!(!with(0.25));
    }
}
