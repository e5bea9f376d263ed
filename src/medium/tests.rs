//! Unit tests of the medium enum: what each kind answers at a point.

use super::*;
use crate::math::keyframes::{Key, Keyframes};
use crate::math::{Affine3A, Bounds3, Quat};

fn boxed(sigma_a: Rgb, sigma_s: Rgb, emission: Rgb) -> HomogeneousMedium {
    HomogeneousMedium {
        sigma_a,
        sigma_s,
        emission,
        phase: PhaseFunction::Isotropic,
        region: Region::Box {
            world_to_local: Affine3A::IDENTITY,
            local: Bounds3::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
        },
    }
}

fn fog() -> HeightFog {
    HeightFog {
        sigma_a: Rgb::new(0.02, 0.03, 0.01),
        sigma_s: Rgb::new(0.3, 0.2, 0.25),
        emission: Rgb::splat(0.5),
        phase: PhaseFunction::Isotropic,
        up: Vec3::Y,
        height: 0.5,
        scale_height: 2.0,
    }
}

/// A medium sliding along x over the shutter.
fn moving(inner: Medium) -> Medium {
    let key = |time: f32, x: f32| Key {
        time,
        translate: Vec3::new(x, 0.0, 0.0),
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };
    let keys = Keyframes::new(&[key(-0.5, -0.4), key(0.5, 0.6)]).expect("keys");
    inner.moved_by(Some(keys))
}

/// `content` as an interior medium masked to the box [−0.75, 0.75]³.
fn masked(content: HomogeneousMedium) -> InteriorMedium {
    InteriorMedium {
        content: InteriorContent::Homogeneous(content),
        mask: ShapeMask::Region(Region::Box {
            world_to_local: Affine3A::IDENTITY,
            local: Bounds3::new(Vec3::splat(-0.75), Vec3::splat(0.75)),
        }),
    }
}

/// σt read alone (what shadow rays read) is σa + σs of the full properties
/// (what free flights read), for every kind of medium, at points inside and
/// outside, at several times.
#[test]
fn extinction_is_absorption_plus_scattering_for_every_medium() {
    let homogeneous = boxed(Rgb::new(0.3, 0.1, 0.2), Rgb::new(0.5, 0.9, 0.4), Rgb::BLACK);
    // A box-masked interior: the point at (0.9, 0.3, -0.8) lies outside its mask.
    let interior = masked(homogeneous.clone());
    let media = [
        Medium::Homogeneous(homogeneous.clone()),
        Medium::HeightFog(fog()),
        Medium::Interior(std::sync::Arc::new(interior)),
        moving(Medium::Homogeneous(homogeneous)),
    ];
    for medium in &media {
        for (i, p) in [
            Vec3::ZERO,
            Vec3::new(0.5, -0.7, 0.2),
            Vec3::new(0.9, 0.3, -0.8),
            Vec3::new(2.0, 0.0, 0.0),
        ]
        .into_iter()
        .enumerate()
        {
            for time in [-0.5, 0.0, 0.3] {
                let props = medium.properties(p, time);
                let expected = props.sigma_a + props.sigma_s;
                assert_eq!(
                    medium.sigma_t_at(p, time),
                    expected,
                    "{i} at {time}: {medium:?}"
                );
                if time == 0.0 {
                    assert_eq!(medium.sigma_t(p), expected, "{i}: {medium:?}");
                }
            }
            // The point inside the box at time 0 has a non-zero extinction: the check can fail.
            if i == 0 && !matches!(medium, Medium::HeightFog(_)) {
                assert!(!medium.sigma_t(p).is_black());
            }
        }
    }
}

/// A decaying majorant σ̄(t) = σ̄₀ e^(−k (t − t0)) starts at σ̄₀ at the
/// segment's start, wherever that start is, and falls by e^(−k) per unit.
#[test]
fn a_decaying_majorant_starts_at_its_segment() {
    let seg = MajorantSegment {
        t0: 3.0,
        t1: 9.0,
        sigma_maj: 2.0,
        decay: 0.5,
        sigma_control: Rgb::BLACK,
    };
    assert_eq!(seg.majorant_at(3.0), 2.0);
    let expected = 2.0 * (-0.5f32 * 2.0).exp();
    assert!(
        (seg.majorant_at(5.0) - expected).abs() < 1e-6,
        "{}",
        seg.majorant_at(5.0)
    );
    let flat = MajorantSegment { decay: 0.0, ..seg };
    assert_eq!(flat.majorant_at(7.0), 2.0);
}

/// A homogeneous medium has its coefficients inside its region and none
/// outside it.
#[test]
fn a_homogeneous_medium_is_empty_outside_its_region() {
    let m = boxed(Rgb::new(0.2, 0.3, 0.4), Rgb::splat(0.5), Rgb::BLACK);
    let inside = m.properties(Vec3::new(0.5, -0.5, 0.9));
    assert_eq!((inside.sigma_a, inside.sigma_s), (m.sigma_a, m.sigma_s));
    let outside = m.properties(Vec3::new(1.5, 0.0, 0.0));
    assert_eq!((outside.sigma_a, outside.sigma_s), (Rgb::BLACK, Rgb::BLACK));
}

/// The optical depth over [t0, t1] counts only the part inside the region:
/// a ray from x = −3 along x is inside the box [−1, 1]³ for t in [2, 4].
#[test]
fn homogeneous_optical_depth_counts_only_the_region() {
    let m = boxed(Rgb::new(0.2, 0.3, 0.4), Rgb::splat(0.5), Rgb::BLACK);
    let ray = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
    for (t0, t1, inside) in [
        (0.0, 10.0, 2.0),
        (3.0, 10.0, 1.0),
        (0.0, 3.0, 1.0),
        (2.5, 3.5, 1.0),
        (5.0, 10.0, 0.0),
        (0.0, 1.0, 0.0),
    ] {
        let depth = m.optical_depth(&ray, t0, t1);
        let want = m.sigma_t() * inside;
        for c in 0..3 {
            assert!(
                (depth[c] - want[c]).abs() < 1e-6,
                "[{t0}, {t1}]: {depth:?} != {want:?}"
            );
        }
    }
}

/// An interior medium has its content's coefficients inside its mask and
/// none outside it, though its content fills the point (a box of half-width
/// 1 masked to half-width 0.75).
#[test]
fn an_interior_medium_is_empty_outside_its_mask() {
    let content = boxed(Rgb::new(0.3, 0.1, 0.2), Rgb::new(0.5, 0.9, 0.4), Rgb::BLACK);
    let interior = masked(content.clone());
    let inside = interior.properties(Vec3::new(0.5, 0.0, 0.0), 0.0);
    assert_eq!(
        (inside.sigma_a, inside.sigma_s),
        (content.sigma_a, content.sigma_s)
    );
    let outside = interior.properties(Vec3::new(0.9, 0.0, 0.0), 0.0);
    assert_eq!((outside.sigma_a, outside.sigma_s), (Rgb::BLACK, Rgb::BLACK));
}

/// A moving homogeneous medium keeps its closed-form optical depth, along
/// the ray in the medium's frame at the ray's time: at time 0.25 the box
/// [−1, 1]³ has slid to x in [−0.65, 1.35].
#[test]
fn a_moving_homogeneous_medium_has_a_closed_form_optical_depth() {
    let content = boxed(Rgb::new(0.3, 0.1, 0.2), Rgb::new(0.5, 0.9, 0.4), Rgb::BLACK);
    let sigma_t = content.sigma_t();
    let medium = moving(Medium::Homogeneous(content));
    let ray = Ray {
        time: 0.25,
        ..Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X)
    };
    for (t1, inside) in [(10.0, 2.0), (3.0, 0.65)] {
        let depth = medium.optical_depth(&ray, 0.0, t1).expect("a closed form");
        for c in 0..3 {
            assert!(
                (depth[c] - sigma_t[c] * inside).abs() < 1e-5,
                "t1 = {t1}: {depth:?}"
            );
        }
    }
}
