//! The χ² test of a material's sampling against its pdf, shared by the
//! material test files.

use brume::material::{Material, Shading};
use brume::math::color::Rgb;
use brume::math::Vec3;
use brume::sampling::chi2::{Chi2Result, SphereChi2};
use brume::sampling::Sampler;
use std::cell::RefCell;

/// The unit direction at `theta_deg` from +z in the xz-plane.
pub fn direction(theta_deg: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin(), 0.0, t.cos())
}

/// Chi-square of `m` sampled from `wo` with the surface normal +z (`front`
/// picks the side); the lobe choice draws from a stream keyed by `seed ^ salt`.
pub fn chi2_of(m: Material, wo: Vec3, front: bool, (seed, salt): (u64, u64)) -> Chi2Result {
    let normal = if front { Vec3::Z } else { -Vec3::Z };
    let sp = Shading::facing(normal, wo);
    let lobe = RefCell::new(Sampler::from_seed(seed ^ salt));
    let mut test = SphereChi2::new(200_000, seed);
    test.cos_theta_bins = 20;
    test.run(
        |u| {
            let u_lobe = lobe.borrow_mut().next_1d();
            m.sample(&sp, wo, u, u_lobe).map(|s| s.wi)
        },
        |d| m.pdf(&sp, wo, d),
    )
}

/// Mean `f cos / pdf` over the sampler from `wo` (the directional albedo),
/// normal +z, 200 000 samples.
pub fn directional_albedo(m: Material, wo: Vec3, seed: u64) -> super::Estimate {
    let sp = Shading::facing(Vec3::Z, wo);
    super::estimate(200_000, seed, |s| {
        m.sample(&sp, wo, s.next_2d(), s.next_1d())
            .map_or(Rgb::BLACK, |b| b.weight)
    })
}

/// The error of building the material test scene `scene`, or a panic naming what was accepted.
pub fn build_error(scene: &str) -> String {
    let file = std::path::Path::new("mat.toml");
    match brume::scene::parse(scene, file) {
        Ok(desc) => brume::scene::build(&desc, file, std::path::Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("accepted: {scene}"))
            .to_string(),
        Err(e) => e.to_string(),
    }
}
