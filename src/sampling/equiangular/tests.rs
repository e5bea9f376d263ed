use super::*;
use crate::sampling::chi2::IntervalChi2;
use crate::sampling::quadrature::gauss_legendre;
use crate::sampling::Sampler;

/// (name, light position) along the ray from the origin along +x over t in [1, 5].
const CONFIGS: [(&str, Vec3); 7] = [
    ("beside", Vec3::new(3.0, 1.0, 0.0)),
    ("beside, close", Vec3::new(2.0, 0.0, 0.02)),
    ("ahead", Vec3::new(9.0, 0.5, -0.3)),
    ("behind", Vec3::new(-2.0, 0.3, 0.4)),
    ("near the start", Vec3::new(1.0, 0.1, 0.0)),
    ("on the line, ahead", Vec3::new(8.0, 0.0, 0.0)),
    ("on the line, behind", Vec3::new(-1.0, 0.0, 0.0)),
];
const T_MIN: f32 = 1.0;
const T_MAX: f32 = 5.0;

fn pdf(light: Vec3, t: f32) -> f32 {
    equiangular_pdf(Vec3::ZERO, Vec3::X, light, T_MIN, T_MAX, t)
}

#[test]
fn pdf_integrates_to_one() {
    for (name, light) in CONFIGS {
        let f = |t: f64| pdf(light, t as f32) as f64;
        let coarse = gauss_legendre(f, T_MIN as f64, T_MAX as f64, 1024);
        let fine = gauss_legendre(f, T_MIN as f64, T_MAX as f64, 2048);
        // Panel halving changes a converged 8-point rule by far less than its own error; the
        // difference bounds the quadrature error, and f32 evaluation of the pdf limits both to ~1e-6.
        assert!((coarse - fine).abs() < 1e-5, "{name}: {coarse} vs {fine}");
        assert!((fine - 1.0).abs() < 1e-4, "{name}: ∫ pdf = {fine}");
    }
}

#[test]
fn samples_lie_in_the_interval_with_consistent_pdf() {
    let mut rng = Sampler::from_seed(21);
    for (name, light) in CONFIGS {
        for i in 0..2_000 {
            // The ends of [0, 1) are included deliberately.
            let u = if i == 0 { 0.0 } else { rng.next_1d() };
            let s = sample_equiangular(Vec3::ZERO, Vec3::X, light, T_MIN, T_MAX, u)
                .unwrap_or_else(|| panic!("{name}: no sample for u = {u}"));
            assert!(
                (T_MIN..=T_MAX).contains(&s.value),
                "{name}: t = {}",
                s.value
            );
            assert_eq!(s.pdf, pdf(light, s.value), "{name}");
            assert!((s.weight * s.pdf - 1.0).abs() < 1e-6, "{name}");
        }
    }
}

#[test]
fn samples_pass_chi_square() {
    // One test per configuration, Šidák-corrected as a family.
    for (k, (name, light)) in CONFIGS.into_iter().enumerate() {
        let test = IntervalChi2::new(T_MIN, T_MAX, 40_000, 100 + k as u64);
        let result = test.run(
            |u| sample_equiangular(Vec3::ZERO, Vec3::X, light, T_MIN, T_MAX, u).map(|s| s.value),
            |t| pdf(light, t),
        );
        assert!(result.passes(0.01, CONFIGS.len()), "{name}: {result}");
    }
}

#[test]
fn light_on_the_segment_has_no_density() {
    let light = Vec3::new(3.0, 0.0, 0.0);
    assert!(sample_equiangular(Vec3::ZERO, Vec3::X, light, T_MIN, T_MAX, 0.5).is_none());
    assert_eq!(pdf(light, 3.0), 0.0);
    assert_eq!(pdf(light, 2.0), 0.0);
    // On the line at either end of the segment: no density there either.
    for end in [T_MIN, T_MAX] {
        let light = Vec3::new(end, 0.0, 0.0);
        assert!(sample_equiangular(Vec3::ZERO, Vec3::X, light, T_MIN, T_MAX, 0.5).is_none());
        for t in [T_MIN, 3.0, T_MAX] {
            assert_eq!(pdf(light, t), 0.0, "light at {end}, t = {t}");
        }
    }
}

#[test]
fn a_light_at_the_ray_origin_has_the_on_line_density() {
    // The 1/s² limit with s = t: pdf = t_min·t_max / ((t_max − t_min) t²).
    for t in [T_MIN, 2.0, T_MAX] {
        let expected = T_MIN * T_MAX / ((T_MAX - T_MIN) * t * t);
        assert!(
            (pdf(Vec3::ZERO, t) / expected - 1.0).abs() < 1e-6,
            "t = {t}"
        );
    }
    let s =
        sample_equiangular(Vec3::ZERO, Vec3::X, Vec3::ZERO, T_MIN, T_MAX, 0.5).expect("a sample");
    assert_eq!(s.pdf, pdf(Vec3::ZERO, s.value));
}

#[test]
fn on_or_beside_the_line_does_not_depend_on_the_scene_scale() {
    // A diagonal ray: the light put on it in f32 is off it by rounding only.
    let dir = Vec3::ONE.normalize();
    for k in [1e-3f32, 1.0, 1e3] {
        let on = dir * (3.0 * k);
        assert!(
            sample_equiangular(Vec3::ZERO, dir, on, k, 5.0 * k, 0.5).is_none(),
            "scale {k}: a light on the segment"
        );
        // 1e-4 of the scale beside a segment 1e4 long: beside it, at every scale.
        let beside = Vec3::new(3.0 * k, 1e-4 * k, 0.0);
        let peak = equiangular_pdf(Vec3::ZERO, Vec3::X, beside, 0.0, 1e4 * k, 3.0 * k);
        let expected = 1.0 / (std::f32::consts::PI * 1e-4 * k);
        assert!(
            (peak / expected - 1.0).abs() < 1e-3,
            "scale {k}: {peak} vs {expected}"
        );
    }
}

#[test]
fn the_density_is_zero_just_outside_the_interval() {
    // The light far behind: t − Δ rounds t's neighbours onto the interval's ends in s.
    let light = Vec3::new(-1000.0, 1.0, 0.0);
    let (a, b) = (1.5f32, 5.0f32);
    for t in [a.next_down(), b.next_up()] {
        assert_eq!(
            equiangular_pdf(Vec3::ZERO, Vec3::X, light, a, b, t),
            0.0,
            "t = {t}"
        );
    }
    assert!(equiangular_pdf(Vec3::ZERO, Vec3::X, light, a, b, a) > 0.0);
}

#[test]
fn a_sample_never_has_a_zero_or_infinite_density() {
    // At extreme scales the f32 density overflows or rounds to 0 (on the line
    // 10¹⁹ behind, (s_b − s_a)·s² overflows); such samples are refused, not
    // returned with a zero or infinite weight.
    let mut cases: Vec<(&str, Vec3, f32, f32)> = vec![(
        "on the line, 1e19 behind",
        Vec3::new(-1e19, 0.0, 0.0),
        1e18,
        5e18,
    )];
    for k in [1e-20f32, 1.0, 1e20] {
        for (name, light) in CONFIGS {
            cases.push((name, light * k, T_MIN * k, T_MAX * k));
        }
    }
    let mut rng = Sampler::from_seed(5);
    for (name, light, a, b) in cases {
        for _ in 0..100 {
            let u = rng.next_1d();
            if let Some(s) = sample_equiangular(Vec3::ZERO, Vec3::X, light, a, b, u) {
                assert!(
                    s.pdf.is_finite() && s.pdf > 0.0 && s.weight.is_finite(),
                    "{name} over [{a}, {b}]: pdf {}",
                    s.pdf
                );
            }
        }
    }
}

#[test]
fn nearly_on_the_line_matches_the_on_line_limit() {
    // Either side of the threshold the densities agree: the fallback is the limit, not a jump.
    let on = Vec3::new(8.0, 0.0, 0.0);
    let near = Vec3::new(8.0, 1e-3, 0.0);
    for t in [1.0, 2.5, 4.9] {
        let (a, b) = (pdf(on, t), pdf(near, t));
        assert!((a - b).abs() < 1e-5 * a, "t = {t}: {a} vs {b}");
    }
}

#[test]
fn bad_intervals_are_refused() {
    let light = Vec3::new(3.0, 1.0, 0.0);
    for (a, b) in [
        (2.0, 2.0),
        (3.0, 1.0),
        (0.0, f32::INFINITY),
        (f32::NAN, 1.0),
    ] {
        assert!(sample_equiangular(Vec3::ZERO, Vec3::X, light, a, b, 0.5).is_none());
        for t in [1.0, a, b] {
            assert_eq!(equiangular_pdf(Vec3::ZERO, Vec3::X, light, a, b, t), 0.0);
        }
    }
}

#[test]
fn a_light_close_beside_a_long_segment_keeps_its_density() {
    // D = 1e-4 beside a segment 1e4 long: far above the rounding of D (1e-6 of the
    // light's distance 3), so the light is beside the line, not on it, whatever the
    // segment's length; the density peaks at the closest point with 1/(θ D), θ ≈ π.
    let light = Vec3::new(3.0, 1e-4, 0.0);
    let (a, b) = (0.0, 1.0e4);
    let s = sample_equiangular(Vec3::ZERO, Vec3::X, light, a, b, 0.5).expect("a sample");
    assert!((s.value - 3.0).abs() < 1e-3, "t = {}", s.value);
    let peak = equiangular_pdf(Vec3::ZERO, Vec3::X, light, a, b, 3.0);
    let expected = 1.0 / (std::f32::consts::PI * 1e-4);
    assert!((peak / expected - 1.0).abs() < 1e-3, "{peak} vs {expected}");
}
