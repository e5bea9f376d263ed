//! Estimating the entries of the albedo tables of [`super::albedo`] (used by
//! `examples/ggx_albedo.rs`, which writes the table file, and by the test
//! that checks the committed file is what it writes).

use super::albedo::{self, Side, ALPHA_NODES, ETA_NODES, MU_NODES, TABLE_LEN};
use super::{ConductorFresnel, Distribution, Material, Shading};
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};
use crate::sampling::Sampler;

/// Jittered strata per axis of a conductor entry.
pub const CONDUCTOR_STRATA: u32 = 128;
/// Jittered strata per axis of a dielectric entry.
pub const DIELECTRIC_STRATA: u32 = 64;

/// The single-scattering albedo (energy: transmission without the radiance
/// scaling by η²) of `m` seen at cosine `mu` on the side `front` of a
/// surface with normal +z, from `strata`² jittered samples of its sampler.
pub fn albedo(m: Material, front: bool, mu: f32, strata: u32, seed: u64) -> f64 {
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let normal = if front { Vec3::Z } else { -Vec3::Z };
    let sp = Shading::facing(normal, wo);
    let eta = match m {
        Material::Dielectric { ior, .. } => super::relative_eta(ior, &sp),
        _ => 1.0,
    };
    let mut s = Sampler::from_seed(seed);
    let mut sum = 0.0f64;
    for a in 0..strata {
        for b in 0..strata {
            let j = s.next_2d();
            let u = Vec2::new(
                (a as f32 + j.x) / strata as f32,
                (b as f32 + j.y) / strata as f32,
            );
            let Some(bs) = m.sample(&sp, wo, u.min(Vec2::splat(1.0 - 1e-7)), s.next_1d()) else {
                continue;
            };
            let through = bs.wi.dot(sp.n) < 0.0;
            sum += (bs.weight.r * if through { eta * eta } else { 1.0 }) as f64;
        }
    }
    sum / (strata * strata) as f64
}

/// The table entry at flat index `index` (layout of [`albedo`]).
pub fn entry(index: usize) -> f32 {
    let conductor_len = MU_NODES * ALPHA_NODES;
    let (i, rest) = (index % MU_NODES, index / MU_NODES);
    let (j, rest) = (rest % ALPHA_NODES, rest / ALPHA_NODES);
    let (mu, alpha) = (albedo::mu_node(i), albedo::alpha_node(j));
    if alpha == 0.0 {
        // A smooth interface reflects or transmits everything.
        return 1.0;
    }
    if index < conductor_len {
        let m = Material::Conductor {
            alpha,
            fresnel: ConductorFresnel::Schlick { f0: Rgb::WHITE },
            distribution: Distribution::Ggx,
            multiscatter: false,
        };
        return albedo(m, true, mu, CONDUCTOR_STRATA, index as u64) as f32;
    }
    let rest = rest - 1;
    let (k, side) = (rest % ETA_NODES, rest / ETA_NODES);
    let eta = albedo::eta_node(k);
    if k == 0 {
        // An index-matched interface does nothing.
        return 1.0;
    }
    let m = Material::Dielectric {
        ior: eta,
        alpha,
        distribution: Distribution::Ggx,
        multiscatter: false,
    };
    let front = side == Side::Enter as usize;
    albedo(m, front, mu, DIELECTRIC_STRATA, index as u64) as f32
}

/// Every entry, in file order.
pub fn table() -> Vec<f32> {
    (0..TABLE_LEN).map(entry).collect()
}
