//! The mirrored spotlight beam in fog of `bdpt_beam.rs` and `sppm.rs`: the
//! scene and the quadrature of its single scattering (see `bdpt_beam.rs`).
#![allow(dead_code)]

use brume::sampling::quadrature::gauss_legendre;

pub const SIGMA_S: f64 = 0.3;
pub const SIGMA_A: f64 = 0.05;
pub const G: f64 = 0.4;
pub const INTENSITY: [f64; 3] = [10.0, 8.0, 6.0];
pub const REFLECTANCE: f64 = 0.9;
/// The spot above the mirror plane y = 0, aimed at the origin.
pub const SPOT: [f64; 3] = [-1.5, 1.5, 0.0];
pub const CONE: f64 = 20.0;
pub const FALLOFF: f64 = 5.0;
/// A 1×1 camera looking along −z through the reflected beam's axis at (1.5, 1.5, 0).
pub const EYE: [f64; 3] = [1.5, 1.5, 3.0];
pub const FOV: f64 = 6.0;

/// The fog: x ≥ 0.9, y ≥ 0.6, |z| ≤ 2.5 (the spot's cone stays out of it).
pub const FOG_MIN: [f64; 3] = [0.9, 0.6, -2.5];
pub const FOG_MAX: [f64; 3] = [3.0, 3.0, 2.5];

pub fn scene(integrator: &str) -> String {
    format!(
        r#"
        [camera]
        position = {EYE:?}
        look_at = [1.5, 1.5, 0.0]
        fov = {FOV:?}
        resolution = [1, 1]
        [integrator]
        max_depth = 2
        seed = 29
        {integrator}
        [[light]]
        type = "spot"
        position = {SPOT:?}
        look_at = [0.0, 0.0, 0.0]
        intensity = {INTENSITY:?}
        cone_angle = {CONE:?}
        cone_falloff = {FALLOFF:?}
        [[shape]]
        type = "quad"
        center = [0.0, 0.0, 0.0]
        normal = [0.0, 1.0, 0.0]
        size = [8.0, 8.0]
        material = {{ type = "mirror", reflectance = {REFLECTANCE:?} }}
        [[medium]]
        type = "homogeneous"
        sigma_a = {SIGMA_A:?}
        sigma_s = {SIGMA_S:?}
        phase = {{ type = "hg", g = {G:?} }}
        bounds = {{ type = "box", min = {FOG_MIN:?}, max = {FOG_MAX:?} }}
        "#
    )
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

pub fn hg(cos: f64) -> f64 {
    let d = 1.0 + G * G - 2.0 * G * cos;
    (1.0 - G * G) / (4.0 * std::f64::consts::PI * d * d.sqrt())
}

pub fn smoothstep_falloff(cos: f64) -> f64 {
    let (inner, outer) = ((CONE - FALLOFF).to_radians().cos(), CONE.to_radians().cos());
    if cos >= inner {
        1.0
    } else if cos <= outer {
        0.0
    } else {
        let t = (cos - outer) / (inner - outer);
        t * t * (3.0 - 2.0 * t)
    }
}

pub fn inside(x: [f64; 3]) -> bool {
    (0..3).all(|c| x[c] >= FOG_MIN[c] && x[c] <= FOG_MAX[c])
}

/// Single scattering of the mirror image along the ray from the eye along
/// `dir`, per unit intensity. The camera ray (x and y within 1.5 ± 0.32) is
/// in the fog once past the box's face z = 2.5; the reflected light, on its
/// way from the mirror point m to x, once past x = 0.9 (and y = 0.6 before).
pub fn line(dir: [f64; 3], panels: usize) -> f64 {
    let image = [SPOT[0], -SPOT[1], SPOT[2]];
    let axis = normalize([-SPOT[0], SPOT[1], -SPOT[2]]);
    let sigma_t = SIGMA_S + SIGMA_A;
    let t_enter = (EYE[2] - FOG_MAX[2]) / -dir[2];
    let integrand = |t: f64| {
        let x = [
            EYE[0] + t * dir[0],
            EYE[1] + t * dir[1],
            EYE[2] + t * dir[2],
        ];
        if !inside(x) {
            return 0.0;
        }
        let d = [x[0] - image[0], x[1] - image[1], x[2] - image[2]];
        let r2 = dot(d, d);
        let r = r2.sqrt();
        let w = [d[0] / r, d[1] / r, d[2] / r];
        // Where the light meets the mirror, and the part of its way after it that is in the fog.
        let to_mirror = -image[1] / (x[1] - image[1]);
        let m = [
            image[0] + d[0] * to_mirror,
            0.0,
            image[2] + d[2] * to_mirror,
        ];
        let enter = ((FOG_MIN[0] - m[0]) / (x[0] - m[0])).max(FOG_MIN[1] / x[1]);
        let fog = (1.0 - enter) * r * (1.0 - to_mirror);
        let cos_scatter = -dot(w, dir);
        SIGMA_S * hg(cos_scatter) * REFLECTANCE * smoothstep_falloff(dot(w, axis)) / r2
            * (-sigma_t * (t - t_enter + fog)).exp()
    };
    // Break the integral where the spot's falloff starts and ends (C¹ kinks).
    let cone_cos = |t: f64| {
        let x = [
            EYE[0] + t * dir[0],
            EYE[1] + t * dir[1],
            EYE[2] + t * dir[2],
        ];
        dot(
            normalize([x[0] - image[0], x[1] - image[1], x[2] - image[2]]),
            axis,
        )
    };
    let (t0, t1) = (t_enter, 6.0);
    let mut breaks = vec![t0, t1];
    for edge in [CONE - FALLOFF, CONE] {
        let c = edge.to_radians().cos();
        let steps = 600;
        for i in 0..steps {
            let (mut a, mut b) = (
                t0 + (t1 - t0) * i as f64 / steps as f64,
                t0 + (t1 - t0) * (i + 1) as f64 / steps as f64,
            );
            if (cone_cos(a) - c).signum() == (cone_cos(b) - c).signum() {
                continue;
            }
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if (cone_cos(a) - c).signum() == (cone_cos(m) - c).signum() {
                    a = m;
                } else {
                    b = m;
                }
            }
            breaks.push(0.5 * (a + b));
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks
        .windows(2)
        .map(|w| gauss_legendre(integrand, w[0], w[1], panels))
        .sum()
}

/// The pixel's mean over its area (uniform in raster space, as the camera samples it).
pub fn pixel(panels: usize, uv_panels: usize) -> f64 {
    let tan = (FOV.to_radians() * 0.5).tan();
    let ray = |u: f64, v: f64| {
        let (nx, ny) = (2.0 * u - 1.0, 1.0 - 2.0 * v);
        normalize([nx * tan, ny * tan, -1.0])
    };
    gauss_legendre(
        |u| gauss_legendre(|v| line(ray(u, v), panels), 0.0, 1.0, uv_panels),
        0.0,
        1.0,
        uv_panels,
    )
}
