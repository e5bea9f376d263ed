//! The time of a camera sample: uniform over the shutter, 0 without one
//! (`Settings::sample_time`, the map from the reserved time dimension).

use brume::integrator::{Settings, TransmittanceEstimator};

fn settings(shutter: Option<[f32; 2]>) -> Settings {
    Settings {
        integrator: Default::default(),
        spp: 1,
        max_depth: 1,
        max_scatter_depth: 1,
        rr_depth: 1,
        seed: 0,
        transmittance: TransmittanceEstimator::Auto,
        equiangular: false,
        forced_scattering: true,
        sky_ahead: true,
        sun_lobe: None,
        shutter,
        sampler: brume::sampling::SamplerKind::Independent,
        sppm: Default::default(),
        adaptive: Default::default(),
        guiding: false,
    }
}

/// u ∈ [0, 1) maps affinely onto [open, close): open + (close − open)·u.
#[test]
fn sample_time_is_affine_over_the_shutter() {
    let s = settings(Some([-0.25, 0.5]));
    assert_eq!(s.sample_time(0.0), -0.25);
    assert_eq!(s.sample_time(0.5), 0.125);
    assert_eq!(s.sample_time(0.75), 0.3125);
    let late = settings(Some([0.5, 1.0]));
    assert_eq!(late.sample_time(0.5), 0.75);
}

/// Without a shutter every ray is at the frame's instant.
#[test]
fn sample_time_without_a_shutter_is_zero() {
    assert_eq!(settings(None).sample_time(0.7), 0.0);
}
