//! Fresnel reflectance of dielectric and conductor interfaces (unpolarized light).

use crate::math::color::Rgb;
use crate::math::Vec3;

/// Fraction of light reflected at a dielectric interface.
///
/// `cos_i` ≥ 0 is the cosine of the angle of incidence on the side the light
/// arrives from; `eta` = η_transmitted / η_incident. Returns 1 under total
/// internal reflection.
pub fn dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_s * r_s + r_p * r_p)
}

/// Fresnel reflectance of a conductor of complex relative index `eta + i k` per channel.
pub fn conductor(cos_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    Rgb::new(
        conductor_channel(cos_i, eta.r, k.r),
        conductor_channel(cos_i, eta.g, k.g),
        conductor_channel(cos_i, eta.b, k.b),
    )
}

/// The closed form for one wavelength, with a² + b² = |η̂² − sin²θ| (Born & Wolf).
fn conductor_channel(cos_i: f32, eta: f32, k: f32) -> f32 {
    let cos2 = cos_i.clamp(0.0, 1.0).powi(2);
    let sin2 = 1.0 - cos2;
    let t0 = eta * eta - k * k - sin2;
    let a2_plus_b2 = (t0 * t0 + 4.0 * eta * eta * k * k).sqrt();
    let a = (0.5 * (a2_plus_b2 + t0)).max(0.0).sqrt();
    let t1 = a2_plus_b2 + cos2;
    let t2 = 2.0 * cos_i.clamp(0.0, 1.0) * a;
    let r_s = (t1 - t2) / (t1 + t2);
    let t3 = cos2 * a2_plus_b2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let r_p = r_s * (t3 - t4) / (t3 + t4);
    0.5 * (r_s + r_p)
}

/// Schlick's approximation F0 + (1 − F0)(1 − cosθ)⁵ (an artist-friendly conductor tint).
pub fn schlick(cos_i: f32, f0: Rgb) -> Rgb {
    let m = (1.0 - cos_i.clamp(0.0, 1.0)).powi(5);
    f0 + (Rgb::WHITE - f0) * m
}

/// Refracts `wo` (pointing away from the surface, on the side of `n`) through
/// an interface with relative index `eta` = η_other / η_wo-side.
///
/// Returns `None` under total internal reflection.
pub fn refract(wo: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = wo.dot(n);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wo / eta + (cos_i / eta - cos_t) * n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fresnel's equations written with the angles themselves (f64), from Snell's law.
    fn reference(theta_i: f64, eta: f64) -> f64 {
        let sin_t = theta_i.sin() / eta;
        if sin_t >= 1.0 {
            return 1.0;
        }
        let theta_t = sin_t.asin();
        if theta_i == 0.0 {
            return ((eta - 1.0) / (eta + 1.0)).powi(2);
        }
        let r_s = ((theta_i - theta_t).sin() / (theta_i + theta_t).sin()).powi(2);
        let r_p = ((theta_i - theta_t).tan() / (theta_i + theta_t).tan()).powi(2);
        0.5 * (r_s + r_p)
    }

    #[test]
    fn dielectric_matches_the_angle_form_of_fresnels_equations() {
        for eta in [1.5f64, 1.33, 2.4, 1.0 / 1.5, 1.0 / 1.33] {
            for deg in [0.0f64, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0] {
                let theta = deg.to_radians();
                let got = dielectric(theta.cos() as f32, eta as f32) as f64;
                let want = reference(theta, eta);
                assert!(
                    (got - want).abs() < 2e-5,
                    "eta {eta} at {deg}°: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn dielectric_special_angles() {
        // Normal incidence: ((η−1)/(η+1))² = 0.04 for glass.
        assert!((dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Brewster's angle: p-polarized light is fully transmitted, so R = R_s / 2.
        let brewster = 1.5f64.atan();
        let r_s = (brewster - (std::f64::consts::FRAC_PI_2 - brewster))
            .sin()
            .powi(2);
        let got = dielectric(brewster.cos() as f32, 1.5) as f64;
        assert!((got - 0.5 * r_s).abs() < 1e-5, "{got} vs {}", 0.5 * r_s);
        // Grazing incidence reflects everything; beyond the critical angle too.
        assert!((dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
        let critical = (1.0f32 / 1.5).asin();
        assert_eq!(dielectric((critical + 0.01).cos(), 1.0 / 1.5), 1.0);
        assert!(dielectric((critical - 0.01).cos(), 1.0 / 1.5) < 1.0);
    }

    #[test]
    fn conductor_reduces_to_the_dielectric_without_absorption_and_has_its_normal_value() {
        for deg in [0.0f32, 20.0, 50.0, 70.0, 88.0] {
            let c = deg.to_radians().cos();
            let got = conductor_channel(c, 1.5, 0.0);
            assert!((got - dielectric(c, 1.5)).abs() < 1e-5, "{deg}°");
        }
        // Normal incidence: ((η−1)² + k²) / ((η+1)² + k²), gold-like η = 0.2, k = 3.
        let want = (0.8f32 * 0.8 + 9.0) / (1.2 * 1.2 + 9.0);
        assert!((conductor_channel(1.0, 0.2, 3.0) - want).abs() < 1e-5);
        assert!((conductor_channel(0.0, 0.2, 3.0) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn refraction_obeys_snell() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let wt = refract(wo, Vec3::Z, 1.5).unwrap();
        assert!((wt.length() - 1.0).abs() < 1e-5);
        assert!((0.6 - 1.5 * -wt.x).abs() < 1e-5 && wt.z < 0.0);
        assert!(refract(Vec3::new(0.9, 0.0, 0.4359).normalize(), Vec3::Z, 1.0 / 1.5).is_none());
    }
}
