//! Analytic-media suite, single scattering: a slab lit by the sun (closed
//! form) and a medium lit by a point or spot light (1D quadrature).
//!
//! Phase convention (src/medium/phase.rs): `eval(dir_in, dir_out)` takes
//! propagation directions. Light travelling along s scatters toward a camera
//! whose ray has direction v, i.e. it leaves along -v: cos Θ = s · (-v).

mod analytic_support;

use analytic_support::*;
use brume::math::{Ray, Vec3};
use brume::sampling::quadrature::gauss_legendre;

const N: usize = 100_000;

/// A unit vector at polar angle θ from +y (degrees) and azimuth φ (degrees) about +y.
fn from_zenith(theta: f64, phi: f64) -> [f64; 3] {
    let (t, p) = (theta.to_radians(), phi.to_radians());
    [t.sin() * p.cos(), t.cos(), t.sin() * p.sin()]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

/// One slab configuration: sun and view angles (degrees), σt of the unit-thick slab, albedo, HG g (0 = isotropic).
struct Slab {
    sun: (f64, f64),
    view: (f64, f64),
    sigma_t: [f64; 3],
    albedo: [f64; 3],
    g: f64,
    black_ground: bool,
}

const IRRADIANCE: [f64; 3] = [3.0, 2.0, 4.0];

impl Slab {
    /// The slab y ∈ [0, 1], 400 m wide, under a delta sun.
    fn scene(&self, max_scatter_depth: Option<u32>) -> String {
        let s = from_zenith(self.sun.0, self.sun.1);
        let phase = if self.g == 0.0 {
            "{ type = \"isotropic\" }".to_string()
        } else {
            format!("{{ type = \"hg\", g = {:?} }}", self.g)
        };
        let depth = max_scatter_depth.map_or(String::new(), |d| format!("max_scatter_depth = {d}"));
        let ground = if self.black_ground {
            "[[shape]]\ntype = \"quad\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nsize = [400.0, 400.0]\nmaterial = { type = \"diffuse\", albedo = 0.0 }\n"
        } else {
            ""
        };
        SceneText::view([0.0, 5.0, 5.0], [0.0; 3])
            .integrator("max_depth = 1000")
            .with(&depth)
            .sun([-s[0], -s[1], -s[2]], IRRADIANCE)
            .with("angular_radius = 0.0")
            .raw(ground)
            .medium(&format!(
                "type = \"homogeneous\"\nsigma_t = {:?}\nalbedo = {:?}\nphase = {phase}\n\
                 bounds = {{ type = \"box\", min = [-200.0, 0.0, -200.0], max = [200.0, 1.0, 200.0] }}",
                self.sigma_t, self.albedo
            ))
            .build()
    }

    /// The camera ray: from above the slab, looking down at the view zenith angle.
    fn ray(&self) -> Ray {
        let up = from_zenith(self.view.0, self.view.1);
        let v = vec3([-up[0], -up[1], -up[2]]);
        Ray::new(Vec3::new(0.0, 1.0, 0.0) - v * 3.0, v)
    }

    /// L = α E p(Θ) μ0/(μ0+μ) (1 - e^(-τ(1/μ0+1/μ))), per channel.
    fn single_scattering(&self) -> [f64; 3] {
        let to_sun = from_zenith(self.sun.0, self.sun.1);
        let to_eye = from_zenith(self.view.0, self.view.1);
        let (mu0, mu) = (to_sun[1], to_eye[1]);
        // s = -to_sun (travel), -v = to_eye: cos Θ = s·(-v).
        let cos_theta = -dot(to_sun, to_eye);
        let p = hg(self.g, cos_theta);
        per_channel(|c| {
            let tau = self.sigma_t[c];
            self.albedo[c] * IRRADIANCE[c] * p * mu0 / (mu0 + mu)
                * (1.0 - (-tau * (1.0 / mu0 + 1.0 / mu)).exp())
        })
    }
}

fn slabs() -> Vec<Slab> {
    vec![
        Slab {
            sun: (30.0, 0.0),
            view: (0.0, 0.0),
            sigma_t: [0.5; 3],
            albedo: [0.8; 3],
            g: 0.0,
            black_ground: false,
        },
        Slab {
            sun: (60.0, 0.0),
            view: (45.0, 180.0),
            sigma_t: [1.0; 3],
            albedo: [0.9; 3],
            g: 0.6,
            black_ground: false,
        },
        Slab {
            sun: (20.0, 30.0),
            view: (50.0, 90.0),
            sigma_t: [2.0; 3],
            albedo: [0.7; 3],
            g: -0.3,
            black_ground: true,
        },
        Slab {
            sun: (45.0, 0.0),
            view: (30.0, 0.0),
            sigma_t: [0.3; 3],
            albedo: [1.0; 3],
            g: 0.8,
            black_ground: false,
        },
        Slab {
            sun: (40.0, 0.0),
            view: (25.0, 200.0),
            sigma_t: [0.2, 0.6, 1.5],
            albedo: [0.9, 0.7, 0.5],
            g: 0.4,
            black_ground: true,
        },
    ]
}

/// max_scatter_depth = 1: the slab's radiance is the single-scattering
/// closed form, whether light is sampled from the free flight's collisions or
/// from forced points (`forced_scattering`, off by default under a sun).
#[test]
fn sunlit_slab_single_scattering() {
    for forced in [false, true] {
        for (k, slab) in slabs().iter().enumerate() {
            let text = slab.scene(Some(1)).replace(
                "[integrator]",
                &format!("[integrator]\nforced_scattering = {forced}"),
            );
            let scene = scene_from_str(&text);
            assert_eq!(scene.settings.forced_scattering, forced);
            let est = estimate_li(&scene, slab.ray(), N, 60 + k as u64);
            assert_estimate(
                &est,
                slab.single_scattering(),
                &format!(
                    "slab σt={:?} α={:?} g={} sun={:?} view={:?} forced={forced}",
                    slab.sigma_t, slab.albedo, slab.g, slab.sun, slab.view
                ),
            );
        }
    }
}

/// Without the scatter-depth limit, multiple scattering adds energy: for a
/// bright, thick slab L_multi exceeds the single-scattering closed form by
/// more than five standard errors.
#[test]
fn sunlit_slab_multiple_scattering_adds_energy() {
    let slab = Slab {
        sun: (30.0, 0.0),
        view: (20.0, 90.0),
        sigma_t: [2.0; 3],
        albedo: [0.95; 3],
        g: 0.0,
        black_ground: false,
    };
    let scene = scene_from_str(&slab.scene(None));
    let est = estimate_li(&scene, slab.ray(), N, 90);
    let single = slab.single_scattering();
    for (c, single) in single.into_iter().enumerate() {
        assert!(
            est.mean[c] > single + k_sigma(3) * est.std_error[c],
            "channel {c}: multiple {} ± {} vs single {single}",
            est.mean[c],
            est.std_error[c],
        );
    }
}

/// A global medium lit by a point (or spot) light beside a camera ray.
struct Beam {
    sigma_a: [f64; 3],
    sigma_s: [f64; 3],
    g: f64,
    intensity: [f64; 3],
    light: [f64; 3],
    /// (look_at, cone_angle, cone_falloff) for a spot light.
    spot: Option<([f64; 3], f64, f64)>,
}

impl Beam {
    /// The scene, with shadow-ray transmittance by `estimator` (auto, ratio, residual_ratio, delta).
    fn scene(&self, estimator: &str, equiangular: bool) -> String {
        let light = match self.spot {
            None => format!(
                "type = \"point\"\nposition = {}\nintensity = {}",
                toml3(self.light),
                toml3(self.intensity)
            ),
            Some((look_at, angle, falloff)) => format!(
                "type = \"spot\"\nposition = {}\nlook_at = {}\nintensity = {}\ncone_angle = {angle:?}\ncone_falloff = {falloff:?}",
                toml3(self.light),
                toml3(look_at),
                toml3(self.intensity)
            ),
        };
        SceneText::view([0.0, 0.0, 5.0], [0.0; 3])
            .integrator(&format!(
                "max_scatter_depth = 1\ntransmittance = \"{estimator}\"\nequiangular = {equiangular}"
            ))
            .light(&light)
            .medium(&format!(
                "type = \"homogeneous\"\nsigma_a = {:?}\nsigma_s = {:?}\n\
                 phase = {{ type = \"hg\", g = {:?} }}\nglobal = true",
                self.sigma_a, self.sigma_s, self.g
            ))
            .build()
    }

    /// Spot falloff at cos of the angle off the axis (smoothstep between the cones).
    fn falloff(&self, to_point: [f64; 3]) -> f64 {
        let Some((look_at, angle, soft)) = self.spot else {
            return 1.0;
        };
        let axis = [
            look_at[0] - self.light[0],
            look_at[1] - self.light[1],
            look_at[2] - self.light[2],
        ];
        let cos = dot(axis, to_point) / dot(axis, axis).sqrt();
        let (cos_inner, cos_outer) = ((angle - soft).to_radians().cos(), angle.to_radians().cos());
        if cos >= cos_inner {
            1.0
        } else if cos <= cos_outer {
            0.0
        } else {
            let t = (cos - cos_outer) / (cos_inner - cos_outer);
            t * t * (3.0 - 2.0 * t)
        }
    }

    /// ∫0^∞ σs p(θ(t)) I f(t) e^(-σt (t + r(t))) / r(t)² dt along the ray o + t·x̂, o = 0.
    fn integrand(&self, c: usize, t: f64) -> f64 {
        let from_light = [t - self.light[0], -self.light[1], -self.light[2]];
        let r = dot(from_light, from_light).sqrt();
        // Light travels along from_light / r, then toward the camera along -x̂.
        let cos_theta = -from_light[0] / r;
        let sigma_t = self.sigma_a[c] + self.sigma_s[c];
        let unit = [from_light[0] / r, from_light[1] / r, from_light[2] / r];
        self.sigma_s[c]
            * hg(self.g, cos_theta)
            * self.intensity[c]
            * self.falloff(unit)
            * (-sigma_t * (t + r)).exp()
            / (r * r)
    }

    /// The integral by composite Gauss–Legendre on [0, 200] (e^(-σt t) < 1e-10 beyond),
    /// with panel ends around the light's abscissa and at the spot's cone edges; checked by doubling.
    fn single_scattering(&self) -> [f64; 3] {
        // Panels shrink toward the peak at the light's abscissa, h from the ray.
        let h = (self.light[1].powi(2) + self.light[2].powi(2)).sqrt();
        let mut breaks = vec![0.0, self.light[0], 200.0];
        for scale in [1.0, 4.0, 16.0, 64.0] {
            breaks.extend([self.light[0] - scale * h, self.light[0] + scale * h]);
        }
        if let Some((_, angle, soft)) = self.spot {
            // The spot points at the ray's closest point: cone edges at light.x ± h tan(angle).
            for a in [angle, angle - soft] {
                let w = h * a.to_radians().tan();
                breaks.extend([self.light[0] - w, self.light[0] + w]);
            }
        }
        breaks.retain(|&b| (0.0..=200.0).contains(&b));
        breaks.sort_by(f64::total_cmp);
        per_channel(|c| {
            let integrate = |panels: usize| -> f64 {
                breaks
                    .windows(2)
                    .map(|w| gauss_legendre(|t| self.integrand(c, t), w[0], w[1], panels))
                    .sum()
            };
            let (coarse, fine) = (integrate(50), integrate(100));
            assert!(
                (coarse - fine).abs() <= 1e-9 * fine.abs().max(1e-12),
                "quadrature converged"
            );
            fine
        })
    }
}

/// max_scatter_depth = 1 in a global medium: the radiance along a ray passing
/// beside a point light equals the quadrature of
/// ∫0^∞ σs p(θ(t)) I e^(-σt (t + r(t))) / r(t)² dt, whatever distance sampling
/// the integrator uses and whichever estimator its shadow rays use.
#[test]
fn point_light_single_scattering_matches_quadrature() {
    let beams = [
        Beam {
            sigma_a: [0.05; 3],
            sigma_s: [0.25; 3],
            g: 0.5,
            intensity: [10.0; 3],
            light: [3.0, 0.8, 0.4],
            spot: None,
        },
        Beam {
            sigma_a: [0.02; 3],
            sigma_s: [0.1; 3],
            g: -0.4,
            intensity: [4.0, 6.0, 8.0],
            light: [1.5, 0.3, 0.0],
            spot: None,
        },
        Beam {
            sigma_a: [0.05, 0.02, 0.2],
            sigma_s: [0.2, 0.3, 0.1],
            g: 0.0,
            intensity: [5.0; 3],
            light: [2.0, 0.5, -0.5],
            spot: None,
        },
    ];
    for (k, beam) in beams.iter().enumerate() {
        let expected = beam.single_scattering();
        let grey = beam
            .sigma_a
            .iter()
            .zip(&beam.sigma_s)
            .all(|(a, s)| a + s == beam.sigma_a[0] + beam.sigma_s[0]);
        // Shadow rays by closed form and by every tracking estimator (delta on grey
        // media only), with equiangular sampling; and once with free flight alone.
        for (estimator, equiangular) in [
            ("auto", true),
            ("ratio", true),
            ("residual_ratio", true),
            ("delta", true),
            ("auto", false),
        ] {
            if estimator == "delta" && !grey {
                continue;
            }
            let scene = scene_from_str(&beam.scene(estimator, equiangular));
            let est = estimate_li(&scene, Ray::new(Vec3::ZERO, Vec3::X), 2 * N, 120 + k as u64);
            assert_estimate(
                &est,
                expected,
                &format!(
                    "point light σa={:?} σs={:?} g={}, {estimator} shadow rays, equiangular {equiangular}",
                    beam.sigma_a, beam.sigma_s, beam.g
                ),
            );
        }
    }
}

/// Two point lights of unequal power beside the ray: single scattering is the
/// sum of each light's quadrature. The light pick asks the brighter one about
/// five times in six, so NEE, the free-flight weight of equiangular sampling
/// and equiangular's own estimate must all use that pick probability, not 1/N.
#[test]
fn two_point_lights_of_unequal_power_add_up() {
    let bright = Beam {
        sigma_a: [0.05; 3],
        sigma_s: [0.25; 3],
        g: 0.5,
        intensity: [12.0; 3],
        light: [3.0, 0.8, 0.4],
        spot: None,
    };
    let dim = Beam {
        intensity: [1.5; 3],
        light: [0.8, -0.5, 0.3],
        ..bright
    };
    let (a, b) = (bright.single_scattering(), dim.single_scattering());
    let expected = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    for equiangular in [true, false] {
        let scene = format!(
            "{}
[[light]]
type = \"point\"
position = {}
intensity = {}
",
            bright.scene("auto", equiangular),
            toml3(dim.light),
            toml3(dim.intensity)
        );
        let est = estimate_li(
            &scene_from_str(&scene),
            Ray::new(Vec3::ZERO, Vec3::X),
            2 * N,
            131,
        );
        assert_estimate(
            &est,
            expected,
            &format!("two point lights, equiangular {equiangular}"),
        );
    }
}

/// The same with a spot light aimed down at the ray, its cone (with soft edge) covering part of it.
#[test]
fn spot_light_single_scattering_matches_quadrature() {
    let beams = [
        Beam {
            sigma_a: [0.05; 3],
            sigma_s: [0.3; 3],
            g: 0.3,
            intensity: [12.0, 8.0, 4.0],
            light: [3.0, 1.0, 0.0],
            spot: Some(([3.0, 0.0, 0.0], 50.0, 15.0)),
        },
        Beam {
            sigma_a: [0.1, 0.05, 0.0],
            sigma_s: [0.2, 0.4, 0.3],
            g: 0.7,
            intensity: [10.0; 3],
            light: [2.0, 0.6, 0.3],
            spot: Some(([2.0, 0.0, 0.0], 35.0, 10.0)),
        },
    ];
    for (k, beam) in beams.iter().enumerate() {
        for equiangular in [true, false] {
            let scene = scene_from_str(&beam.scene("auto", equiangular));
            let est = estimate_li(&scene, Ray::new(Vec3::ZERO, Vec3::X), 2 * N, 140 + k as u64);
            assert_estimate(
                &est,
                beam.single_scattering(),
                &format!(
                    "spot light σa={:?} σs={:?} g={}, equiangular {equiangular}",
                    beam.sigma_a, beam.sigma_s, beam.g
                ),
            );
        }
    }
}
