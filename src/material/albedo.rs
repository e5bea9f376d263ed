//! Directional albedo tables of the single-scattering GGX lobes, for the
//! Kulla–Conty energy compensation of rough materials (`multiscatter`).
//!
//! E(μ, α) of a white (F = 1) conductor and E(μ, α, η) of a dielectric seen
//! from either side (energy: reflection plus transmission, without the
//! radiance scaling by η²) on uniform grids, estimated with brume's own
//! sampling of the single-scattering lobes by
//!
//! ```text
//! cargo run --release --example ggx_albedo -- src/material/ggx_albedo.bin
//! ```
//!
//! and decoded once, at the first lookup (scenes without rough materials
//! never touch them). Lookups interpolate linearly. The averages
//! E_avg = 2∫E(μ) μ dμ are integrated exactly from the same interpolant, so
//! the compensation lobe restores exactly 1 − E of the table.

use super::fresnel;
use crate::sampling::quadrature::gauss_legendre;
use std::sync::OnceLock;

/// Grid nodes in μ = cos θ (uniform on [0, 1]).
pub const MU_NODES: usize = 32;
/// Grid nodes in GGX α (uniform on [0, 1]; α = 0 has E = 1).
pub const ALPHA_NODES: usize = 32;
/// Grid nodes in the relative index η (uniform on [1, ETA_MAX]; η = 1 has E = 1).
pub const ETA_NODES: usize = 16;
/// Largest relative index the dielectric table covers (the smallest is 1 / ETA_MAX).
pub const ETA_MAX: f32 = 3.0;
/// The cosine the μ = 0 column is estimated at (the lobes are undefined at grazing).
pub const MIN_MU: f32 = 1e-3;

const CONDUCTOR_LEN: usize = MU_NODES * ALPHA_NODES;
const DIELECTRIC_LEN: usize = 2 * ETA_NODES * ALPHA_NODES * MU_NODES;
/// Number of f32 values in the table file: the conductor, then both dielectric sides.
pub const TABLE_LEN: usize = CONDUCTOR_LEN + DIELECTRIC_LEN;

static BYTES: &[u8] = include_bytes!("ggx_albedo.bin");

/// Which side of a dielectric interface the light arrives from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// From the lower index (relative η ≥ 1): into glass.
    Enter = 0,
    /// From the higher index (relative η < 1): out of glass.
    Leave = 1,
}

impl Side {
    /// The side and the index ratio ≥ 1 of the relative index `eta` (far over near).
    pub fn of(eta: f32) -> (Side, f32) {
        if eta >= 1.0 {
            (Side::Enter, eta)
        } else {
            (Side::Leave, 1.0 / eta)
        }
    }

    /// The other side of the interface.
    pub fn other(self) -> Side {
        match self {
            Side::Enter => Side::Leave,
            Side::Leave => Side::Enter,
        }
    }
}

/// μ of column `i` (as estimated: grazing is clamped to `MIN_MU`).
pub fn mu_node(i: usize) -> f32 {
    (i as f32 / (MU_NODES - 1) as f32).max(MIN_MU)
}

/// α of row `j`.
pub fn alpha_node(j: usize) -> f32 {
    j as f32 / (ALPHA_NODES - 1) as f32
}

/// η of slice `k`.
pub fn eta_node(k: usize) -> f32 {
    1.0 + (ETA_MAX - 1.0) * k as f32 / (ETA_NODES - 1) as f32
}

/// Offset of (side, η slice, α row) in the dielectric part of the file.
pub fn dielectric_row(side: Side, k: usize, j: usize) -> usize {
    CONDUCTOR_LEN + ((side as usize * ETA_NODES + k) * ALPHA_NODES + j) * MU_NODES
}

/// The decoded tables and the averages derived from them.
struct Tables {
    values: Vec<f32>,
    conductor_avg: Vec<f32>,
    dielectric_avg: Vec<f32>,
    fresnel_avg: Vec<f32>,
}

/// The position of `x` ∈ [0, 1] on a grid of `n` nodes: lower node and weight of the upper.
#[inline]
fn locate(x: f32, n: usize) -> (usize, f32) {
    let f = x.clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (f as usize).min(n - 2);
    (i, f - i as f32)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// 2∫ E(μ) μ dμ of the piecewise-linear interpolant of one row (exact).
fn row_average(row: &[f32]) -> f32 {
    let h = 1.0 / (MU_NODES - 1) as f64;
    let sum: f64 = row
        .windows(2)
        .enumerate()
        .map(|(i, w)| {
            let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
            h * (w[0] as f64 * (2.0 * a + b) + w[1] as f64 * (a + 2.0 * b)) / 6.0
        })
        .sum();
    (2.0 * sum) as f32
}

fn decode() -> Tables {
    assert_eq!(
        BYTES.len(),
        4 * TABLE_LEN,
        "ggx_albedo.bin does not match the grid (regenerate it, see material::albedo)"
    );
    let values: Vec<f32> = BYTES
        .chunks_exact(4)
        // Estimates a hair above 1 would make the lost energy negative.
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]).min(1.0))
        .collect();
    let conductor_avg = values[..CONDUCTOR_LEN]
        .chunks_exact(MU_NODES)
        .map(row_average)
        .collect();
    let dielectric_avg = values[CONDUCTOR_LEN..]
        .chunks_exact(MU_NODES)
        .map(row_average)
        .collect();
    // 2∫F(μ)μ dμ seen from the lower index: the share of the compensation that crosses.
    let fresnel_avg = (0..ETA_NODES)
        .map(|k| {
            let eta = eta_node(k);
            let f = |mu: f64| 2.0 * mu * fresnel::dielectric(mu as f32, eta) as f64;
            gauss_legendre(f, 0.0, 1.0, 16) as f32
        })
        .collect();
    Tables {
        values,
        conductor_avg,
        dielectric_avg,
        fresnel_avg,
    }
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(decode)
}

/// Bilinear lookup in the rows starting at `base` (one per α node, `stride` apart).
fn lookup_mu_alpha(values: &[f32], base: usize, mu: f32, alpha: f32) -> f32 {
    let (i, tm) = locate(mu, MU_NODES);
    let (j, ta) = locate(alpha, ALPHA_NODES);
    let row = |j: usize| {
        let r = &values[base + j * MU_NODES..];
        lerp(r[i], r[i + 1], tm)
    };
    lerp(row(j), row(j + 1), ta)
}

/// Position of the index ratio `eta` ≥ 1 on the η grid.
fn locate_eta(eta: f32) -> (usize, f32) {
    locate((eta - 1.0) / (ETA_MAX - 1.0), ETA_NODES)
}

/// Albedo E(μ, α) of the white single-scattering GGX conductor.
pub fn conductor(mu: f32, alpha: f32) -> f32 {
    lookup_mu_alpha(&tables().values, 0, mu, alpha)
}

/// Its average E_avg(α) = 2∫E μ dμ.
pub fn conductor_average(alpha: f32) -> f32 {
    let (j, t) = locate(alpha, ALPHA_NODES);
    let avg = &tables().conductor_avg;
    lerp(avg[j], avg[j + 1], t)
}

/// Albedo E(μ, α) of the single-scattering GGX dielectric of index ratio
/// `eta` ≥ 1, seen from `side`.
pub fn dielectric(side: Side, eta: f32, mu: f32, alpha: f32) -> f32 {
    let t = tables();
    let (k, te) = locate_eta(eta);
    let at = |k: usize| lookup_mu_alpha(&t.values, dielectric_row(side, k, 0), mu, alpha);
    lerp(at(k), at(k + 1), te)
}

/// Its average E_avg(α, η) = 2∫E μ dμ.
pub fn dielectric_average(side: Side, eta: f32, alpha: f32) -> f32 {
    let t = tables();
    let (k, te) = locate_eta(eta);
    let (j, ta) = locate(alpha, ALPHA_NODES);
    let at = |k: usize, j: usize| {
        t.dielectric_avg[(dielectric_row(side, k, j) - CONDUCTOR_LEN) / MU_NODES]
    };
    lerp(
        lerp(at(k, j), at(k, j + 1), ta),
        lerp(at(k + 1, j), at(k + 1, j + 1), ta),
        te,
    )
}

/// Hemispherical average of the smooth interface's Fresnel reflectance,
/// seen from the lower index, for the index ratio `eta` ≥ 1.
pub fn fresnel_average(eta: f32) -> f32 {
    let (k, t) = locate_eta(eta);
    let f = &tables().fresnel_avg;
    lerp(f[k], f[k + 1], t)
}

#[cfg(test)]
#[path = "albedo_tests.rs"]
mod tests;
