//! Per-channel grids of a grid medium: RGB extinction and a grey or RGB
//! albedo, as Mitsuba's `heterogeneous` medium takes them from `.vol` files.
//!
//! With RGB σt the medium's density grid holds the largest channel of each
//! voxel. A trilinear lookup is a convex combination of eight voxels with
//! the same weights in every channel, so each channel's lookup is at most
//! the density's: the majorant grid built over the density bounds every
//! channel, and tracking treats the extinction as chromatic (spectral
//! tracking) through the ordinary `properties`/`sigma_t` lookups.
//!
//! The albedo is its own grid with its own placement, looked up at the
//! collision with the index clamped to the voxel centres (Mitsuba's `clamp`
//! wrap mode: it is never zero outside its box).

use crate::math::color::Rgb;
use crate::math::{Affine3A, Vec3};
use crate::volume::FloatGrid;

/// Three grids, one per colour channel, on one index map.
#[derive(Clone, Debug)]
pub struct RgbGrids(pub [FloatGrid; 3]);

impl RgbGrids {
    /// The three channels at index point `q`, each clamped to ≥ 0.
    #[inline]
    pub fn lookup(&self, q: Vec3) -> Rgb {
        let [r, g, b] = &self.0;
        Rgb::new(
            r.trilinear_index(q).max(0.0),
            g.trilinear_index(q).max(0.0),
            b.trilinear_index(q).max(0.0),
        )
    }
}

/// An albedo grid (1 or 3 channels) placed in the world.
#[derive(Clone, Debug)]
pub struct AlbedoGrid {
    /// One grey grid, or three (red, green, blue).
    grids: AlbedoChannels,
    world_to_index: Affine3A,
    /// The outermost voxel centre (index); the innermost is 0.
    last: Vec3,
}

/// The channels of an albedo grid.
#[derive(Clone, Debug)]
enum AlbedoChannels {
    Grey(Box<FloatGrid>),
    Rgb(Box<RgbGrids>),
}

impl AlbedoGrid {
    /// `grids` (1 or 3, else `None`) of `res` voxels whose index → world map is
    /// their own transform placed by `to_world`.
    pub fn new(mut grids: Vec<FloatGrid>, res: [usize; 3], to_world: &Affine3A) -> Option<Self> {
        let world_to_index = grids.first()?.transform().world_to_index_placed(to_world);
        let channels = match grids.len() {
            1 => AlbedoChannels::Grey(Box::new(grids.pop()?)),
            3 => {
                let b = grids.pop()?;
                let g = grids.pop()?;
                let r = grids.pop()?;
                AlbedoChannels::Rgb(Box::new(RgbGrids([r, g, b])))
            }
            _ => return None,
        };
        Some(AlbedoGrid {
            grids: channels,
            world_to_index,
            last: Vec3::from_array(res.map(|r| r as f32 - 1.0)),
        })
    }

    /// The albedo at world point `p`, the index clamped to the voxel centres.
    #[inline]
    pub fn lookup_clamped(&self, p: Vec3) -> Rgb {
        let q = self
            .world_to_index
            .transform_point3(p)
            .clamp(Vec3::ZERO, self.last);
        match &self.grids {
            AlbedoChannels::Grey(g) => Rgb::splat(g.trilinear_index(q)),
            AlbedoChannels::Rgb(rgb) => rgb.lookup(q),
        }
    }
}

/// The per-channel grids a grid medium may carry besides its density.
#[derive(Clone, Debug, Default)]
pub struct ChannelGrids {
    /// σt per channel (times the medium's `sigma_t_unit`), on the density's
    /// index map; `None`: grey σt from the density.
    pub sigma_t: Option<RgbGrids>,
    /// The albedo; `None`: the medium's constant albedo.
    pub albedo: Option<AlbedoGrid>,
}
