//! The estimate of one recorded line of a light slab (`brume slab bake`):
//! the radiance leaving the box along it, from what is inside the box, and
//! the transmittance across the box.

use super::{li_from_inside, Scene};
use crate::math::color::Rgb;
use crate::math::{Bounds3, Ray, Vec3};
use crate::sampling::Sampler;

/// Marks a slab bake's random streams apart from any render's pixel streams.
const STREAM_TAG: u32 = 0x51AB_0000;

/// Sums of samples of one recorded line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecordSums {
    /// Sum of the radiance leaving the box along the line, from inside it.
    pub radiance: Rgb,
    /// Sum of the transmittance across the box along the line (0 through a surface).
    pub transmittance: Rgb,
    /// Finite samples summed.
    pub samples: u32,
    /// Samples that were NaN or infinite, left out of the sums.
    pub nonfinite: u32,
}

/// Sums samples `samples` of the line through `point` along the unit `dir`
/// (the way light leaves) across `bounds`; sample `j` draws from the stream
/// of `(seed, record, j)`, so a record depends on the seed only.
///
/// The eye ray starts where the line leaves the box and looks back along it;
/// its first segment ends where the line enters the box, so what lies
/// behind the box does not count (it shows through the transmittance when
/// the slab is viewed). A line that misses the box records no light and
/// full transmittance.
pub fn estimate(
    scene: &Scene,
    bounds: &Bounds3,
    (point, dir): (Vec3, Vec3),
    (samples, seed, record): (std::ops::Range<u32>, u64, u64),
) -> RecordSums {
    let count = samples.len() as u32;
    let clear = RecordSums {
        radiance: Rgb::BLACK,
        transmittance: Rgb::WHITE * count as f32,
        samples: count,
        nonfinite: 0,
    };
    let far = 2.0 * (bounds.max - bounds.min).length() + (point - bounds.center()).length();
    let inward = Ray::new(point + dir * far, -dir);
    let Some((t_exit, t_entry)) = bounds.intersect_ray(&inward, f32::INFINITY) else {
        return clear;
    };
    if t_entry <= t_exit {
        return clear;
    }
    let eye = Ray::new(inward.at(t_exit), -dir);
    let length = t_entry - t_exit;
    let blocked = scene.geometry.occluded(&eye, length);
    let (mut radiance, mut transmittance, mut nonfinite) = (Rgb::BLACK, Rgb::BLACK, 0u32);
    for j in samples {
        let y = (record >> 32) as u32 ^ STREAM_TAG;
        let mut sampler = Sampler::new(seed, record as u32, y, j as u64);
        let l = li_from_inside(scene, eye, length, &mut sampler);
        let t = match blocked {
            true => Rgb::BLACK,
            false => scene.transmittance(&eye, length, &mut sampler),
        };
        if l.is_finite() && t.is_finite() {
            radiance += l;
            transmittance += t;
        } else {
            nonfinite += 1;
        }
    }
    RecordSums {
        radiance,
        transmittance,
        samples: count - nonfinite,
        nonfinite,
    }
}
