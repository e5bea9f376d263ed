//! Unit tests of the lights: sampling, densities and the emission escaping rays see.

use super::*;
use crate::sampling::Sampler;

#[test]
fn sun_disk_gives_its_irradiance() {
    let light = Light::Sun {
        to_sun: Vec3::Y,
        irradiance: Rgb::splat(3.0),
        cos_max: (0.1f32).cos(),
    };
    let geometry = Geometry::new(Vec::new());
    let mut s = Sampler::from_seed(4);
    let n = 10_000;
    let mut sum = 0.0;
    for _ in 0..n {
        let ls = light.sample(Vec3::ZERO, s.next_2d(), &geometry).unwrap();
        sum += ls.radiance.r * ls.wi.y / ls.pdf;
    }
    // cosθ varies by < 0.5% inside a 0.1 rad cone.
    assert!((sum / n as f32 - 3.0).abs() < 0.02);
}

/// An area light over several primitives picks each in proportion to its
/// area and reuses the rest of `u.x` uniformly inside it: with stratified
/// `u.x` the counts per primitive and the mean position inside each are
/// exact up to one stratum.
#[test]
fn multi_primitive_area_light_samples_uniformly_by_area() {
    // Three strips side by side at y = 2, widths 1, 2 and 0.5 along x.
    let strips = [(0.0, 1.0), (1.0, 2.0), (3.0, 0.5)];
    let prims = strips
        .iter()
        .map(|&(x0, w)| {
            let quad = Primitive::Parallelogram {
                corner: Vec3::new(x0, 2.0, 0.0),
                edge_u: Vec3::new(w, 0.0, 0.0),
                edge_v: Vec3::Z,
            };
            (quad, 0)
        })
        .collect();
    let geometry = Geometry::new(prims);
    let light = Light::area(0, Texture::Constant(Rgb::WHITE), true, &geometry);
    let n = 3500;
    let (mut count, mut sum_x) = ([0usize; 3], [0.0f64; 3]);
    let p = Vec3::new(1.0, 0.0, 0.5);
    for i in 0..n {
        let u = Vec2::new((i as f32 + 0.5) / n as f32, 0.5);
        let ls = light.sample(p, u, &geometry).unwrap();
        let x = (p + ls.wi * ls.distance).x;
        let k = strips.iter().rposition(|&(x0, _)| x >= x0 - 1e-4).unwrap();
        count[k] += 1;
        sum_x[k] += x as f64;
        let hit = p + ls.wi * ls.distance;
        let pdf = light.area_pdf(p, hit, Vec3::Y);
        assert!((pdf - ls.pdf).abs() < 1e-3 * pdf);
    }
    for (k, &(x0, w)) in strips.iter().enumerate() {
        let expected = n as f32 * w / 3.5;
        assert!((count[k] as f32 - expected).abs() <= 1.0, "{count:?}");
        let mean = sum_x[k] / count[k] as f64;
        let centre = (x0 + 0.5 * w) as f64;
        assert!(
            (mean - centre).abs() < 2e-3,
            "strip {k}: mean x {mean}, centre {centre}"
        );
    }
}

/// Escaping rays see a disk sun inside its disk only, with the radiance
/// and density light sampling gives there (MIS needs both); a delta sun
/// is never hit, and a constant environment everywhere.
#[test]
fn escaped_sun_and_environment_match_their_samples() {
    let cos_max = 0.99f32;
    let disk = Light::Sun {
        to_sun: Vec3::Y,
        irradiance: Rgb::splat(3.0),
        cos_max,
    };
    let le = 3.0 / (PI * (1.0 - cos_max * cos_max));
    let pdf = warp::uniform_cone_pdf(cos_max);
    let inside = Vec3::new(0.1, 1.0, 0.0).normalize(); // cos 0.995
    let outside = Vec3::new(0.2, 1.0, 0.0).normalize(); // cos 0.981
    for dir in [Vec3::Y, inside] {
        assert!((disk.escaped_radiance(dir).r - le).abs() < 1e-4 * le);
        assert!((disk.escaped_pdf(dir) - pdf).abs() < 1e-4 * pdf);
    }
    assert_eq!(disk.escaped_radiance(outside), Rgb::BLACK);
    assert_eq!(disk.escaped_pdf(outside), 0.0);
    let ls = disk.sample(Vec3::ZERO, Vec2::new(0.5, 0.25), &Geometry::new(Vec::new()));
    let ls = ls.unwrap();
    assert!((ls.radiance.r - le).abs() < 1e-4 * le && (ls.pdf - pdf).abs() < 1e-4 * pdf);

    let delta = Light::Sun {
        to_sun: Vec3::Y,
        irradiance: Rgb::splat(3.0),
        cos_max: 1.0,
    };
    assert_eq!(delta.escaped_radiance(Vec3::Y), Rgb::BLACK);
    assert_eq!(delta.escaped_pdf(Vec3::Y), 0.0);

    let env = Light::Environment(Environment::Constant {
        radiance: Rgb::splat(0.5),
    });
    assert_eq!(env.escaped_radiance(outside), Rgb::splat(0.5));
    assert_eq!(env.escaped_pdf(outside), warp::uniform_sphere_pdf());
}

/// A one-sided area light is dark from behind: no sample there, and no
/// emitted radiance toward that side; a two-sided one gives both.
#[test]
fn one_sided_area_light_is_dark_from_behind() {
    // Normal edge_u × edge_v = X × Z = −Y: it faces down.
    let quad = Primitive::Parallelogram {
        corner: Vec3::new(-0.5, 2.0, -0.5),
        edge_u: Vec3::X,
        edge_v: Vec3::Z,
    };
    let geometry = Geometry::new(vec![(quad, 0)]);
    let one = Light::area(0, Texture::Constant(Rgb::WHITE), false, &geometry);
    let two = Light::area(0, Texture::Constant(Rgb::WHITE), true, &geometry);
    let (below, above) = (Vec3::ZERO, Vec3::new(0.0, 4.0, 0.0));
    let mut s = Sampler::from_seed(5);
    for _ in 0..100 {
        let u = s.next_2d();
        assert!(one.sample(below, u, &geometry).is_some());
        assert!(one.sample(above, u, &geometry).is_none());
        assert!(two.sample(above, u, &geometry).is_some());
    }
    assert_eq!(
        one.area_radiance(-Vec3::Y, -Vec3::Y, || Vec2::ZERO),
        Rgb::WHITE
    );
    assert_eq!(
        one.area_radiance(-Vec3::Y, Vec3::Y, || Vec2::ZERO),
        Rgb::BLACK
    );
    assert_eq!(
        two.area_radiance(-Vec3::Y, Vec3::Y, || Vec2::ZERO),
        Rgb::WHITE
    );
}

/// A spot light gives no sample outside its cone, and `I/d²` on its axis.
#[test]
fn spot_light_samples_only_inside_its_cone() {
    let spot = Light::Spot {
        position: Vec3::ZERO,
        axis: -Vec3::Y,
        intensity: Rgb::splat(8.0),
        cos_inner: 0.9,
        cos_outer: 0.8,
        edge: SpotEdge::Smooth,
    };
    let geometry = Geometry::new(Vec::new());
    let u = Vec2::new(0.5, 0.5);
    let on_axis = spot
        .sample(Vec3::new(0.0, -2.0, 0.0), u, &geometry)
        .unwrap();
    assert_eq!(on_axis.radiance.r, 2.0);
    assert_eq!(on_axis.wi, Vec3::Y);
    assert!(spot
        .sample(Vec3::new(2.0, -1.0, 0.0), u, &geometry)
        .is_none());
    assert!(spot
        .sample(Vec3::new(0.0, 2.0, 0.0), u, &geometry)
        .is_none());
}

/// Only the sun and environments sit at infinity (escaping rays look them up).
#[test]
fn only_distant_lights_are_infinite() {
    let point = Light::Point {
        position: Vec3::ONE,
        intensity: Rgb::WHITE,
    };
    let sun = Light::Sun {
        to_sun: Vec3::Y,
        irradiance: Rgb::WHITE,
        cos_max: 1.0,
    };
    let env = Light::Environment(Environment::Constant {
        radiance: Rgb::WHITE,
    });
    let quad = Primitive::Parallelogram {
        corner: Vec3::ZERO,
        edge_u: Vec3::X,
        edge_v: Vec3::Z,
    };
    let area = Light::area(
        0,
        Texture::Constant(Rgb::WHITE),
        false,
        &Geometry::new(vec![(quad, 0)]),
    );
    assert!(!point.is_infinite() && !area.is_infinite());
    assert!(sun.is_infinite() && env.is_infinite());
    assert_eq!(point.point_position(), Some(Vec3::ONE));
    assert_eq!(sun.point_position(), None);
}

/// The sky gradient: ground below the horizon, the horizon colour at it,
/// then `horizon·(1 − √h) + zenith·√h` with h the height of the direction.
#[test]
fn sky_gradient_follows_its_formula() {
    let sky = Environment::Sky {
        zenith: Rgb::splat(3.0),
        horizon: Rgb::splat(1.0),
        ground: Rgb::splat(0.25),
        up: Vec3::Y,
    };
    let at = |h: f32| sky.radiance(Vec3::new((1.0 - h * h).sqrt(), h, 0.0)).r;
    assert_eq!(at(1.0), 3.0);
    // √0.25 = 0.5: 1·0.5 + 3·0.5.
    assert!((at(0.25) - 2.0).abs() < 1e-6, "{}", at(0.25));
    assert_eq!(sky.radiance(Vec3::X).r, 1.0, "exactly on the horizon");
    assert_eq!(at(-0.5), 0.25);
    assert_eq!(sky.radiance(-Vec3::Y).r, 0.25);
}

#[test]
fn area_light_pdf_matches_sample() {
    let quad = Primitive::Parallelogram {
        corner: Vec3::new(-0.5, 2.0, -0.5),
        edge_u: Vec3::X,
        edge_v: Vec3::Z,
    };
    let geometry = Geometry::new(vec![(quad, 0)]);
    let light = Light::area(0, Texture::Constant(Rgb::WHITE), true, &geometry);
    let mut s = Sampler::from_seed(8);
    for _ in 0..100 {
        let ls = light.sample(Vec3::ZERO, s.next_2d(), &geometry).unwrap();
        let hit_p = ls.wi * ls.distance;
        let pdf = light.area_pdf(Vec3::ZERO, hit_p, Vec3::Y);
        assert!((pdf - ls.pdf).abs() < 1e-3 * pdf);
    }
}

/// A textured emitter's light sample carries the texture at the sampled
/// point, the value a ray toward that point finds there (what MIS pairs).
#[test]
fn textured_area_light_samples_carry_the_texture_at_their_point() {
    use crate::math::Ray;
    let texture = Texture::Checkerboard {
        a: Rgb::new(1.0, 2.0, 3.0),
        b: Rgb::new(0.5, 0.25, 4.0),
        uv_scale: Vec2::new(3.0, 2.0),
        uv_offset: Vec2::ZERO,
    };
    let quad = Primitive::Parallelogram {
        corner: Vec3::new(-1.0, 2.0, -1.0),
        edge_u: Vec3::new(0.0, 0.0, 2.0),
        edge_v: Vec3::new(2.0, 0.0, 0.0),
    };
    let tri = Primitive::Triangle {
        p: [
            Vec3::new(-1.0, 3.0, -1.0),
            Vec3::new(1.0, 3.0, -1.0),
            Vec3::new(0.0, 3.0, 1.0),
        ],
        n: [Vec3::ZERO; 3],
    };
    let sphere = Primitive::Sphere {
        center: Vec3::new(0.0, 0.0, 4.0),
        radius: 1.0,
    };
    let corners = [
        Vec2::new(0.2, 0.1),
        Vec2::new(0.9, 0.4),
        Vec2::new(0.3, 0.8),
    ];
    for (shape, prim) in [quad, tri, sphere].into_iter().enumerate() {
        let geometry = Geometry::with_texcoords(vec![(prim, 0)], vec![corners]);
        let light = Light::area(0, texture.clone(), true, &geometry);
        let mut s = Sampler::from_seed(3 + shape as u64);
        let mut seen = [false; 2];
        for _ in 0..200 {
            let Some(ls) = light.sample(Vec3::ZERO, s.next_2d(), &geometry) else {
                continue;
            };
            let hit = geometry
                .intersect(&Ray::new(Vec3::ZERO, ls.wi), f32::INFINITY)
                .unwrap();
            let uv = geometry.uv(hit.primitive, hit.st, hit.p);
            let at_hit = light.area_radiance(hit.geometric_normal, -ls.wi, || uv);
            assert_eq!(ls.radiance, at_hit, "shape {shape} at {uv}");
            seen[(ls.radiance == Rgb::new(1.0, 2.0, 3.0)) as usize] = true;
        }
        assert_eq!(seen, [true, true], "shape {shape}: both colours sampled");
    }
}

/// Mean of `f` over the sphere by a stratified grid of uniform directions.
fn sphere_mean(f: impl Fn(Vec3) -> f64) -> f64 {
    let n = 400;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            sum += f(warp::square_to_uniform_sphere(u));
        }
    }
    sum / (n * n) as f64
}

#[test]
fn sky_average_is_its_mean_over_the_sphere() {
    let sky = Environment::Sky {
        zenith: Rgb::new(0.2, 0.4, 1.0),
        horizon: Rgb::new(0.9, 0.8, 0.5),
        ground: Rgb::new(0.1, 0.3, 0.05),
        up: Vec3::new(0.3, 0.9, -0.2).normalize(),
    };
    let avg = sky.average();
    for c in 0..3 {
        let mean = sphere_mean(|d| sky.radiance(d)[c] as f64);
        assert!(
            (avg[c] as f64 - mean).abs() < 1e-3,
            "{c}: {} vs {mean}",
            avg[c]
        );
    }
}

/// Mitsuba's spot edge: linear in the angle between beam_width and
/// cutoff_angle, and its power the falloff integrated over the sphere.
#[test]
fn linear_spot_edge_falls_linearly_in_angle_and_its_power_is_its_flux() {
    let (inner, outer) = (20f32.to_radians(), 30f32.to_radians());
    let edge = SpotEdge::LinearAngle;
    for (deg, want) in [
        (10.0f32, 1.0),
        (22.5, 0.75),
        (25.0, 0.5),
        (29.0, 0.1),
        (31.0, 0.0),
    ] {
        let got = edge.falloff(deg.to_radians().cos(), inner.cos(), outer.cos());
        assert!((got - want).abs() < 1e-4, "{deg}°: {got} vs {want}");
    }
    let spot = Light::Spot {
        position: Vec3::ZERO,
        axis: Vec3::new(0.0, -0.6, 0.8),
        intensity: Rgb::splat(3.0),
        cos_inner: inner.cos(),
        cos_outer: outer.cos(),
        edge,
    };
    let axis = Vec3::new(0.0, -0.6, 0.8);
    let flux = 4.0
        * std::f64::consts::PI
        * sphere_mean(|d| 3.0 * edge.falloff(d.dot(axis), inner.cos(), outer.cos()) as f64);
    assert!(
        (spot.power(1.0) as f64 - flux).abs() < 1e-3 * flux,
        "{} vs {flux}",
        spot.power(1.0)
    );
}

/// Point and spot powers are the intensity integrated over the sphere
/// (the spot's smoothstep edge included); areas and distant lights follow
/// their formulas.
#[test]
fn powers_are_the_emitted_flux() {
    let spot = Light::Spot {
        position: Vec3::ZERO,
        axis: Vec3::new(0.0, -0.6, 0.8),
        intensity: Rgb::splat(3.0),
        cos_inner: 0.9,
        cos_outer: 0.6,
        edge: SpotEdge::Smooth,
    };
    let Light::Spot { axis, .. } = spot else {
        unreachable!()
    };
    let flux = 4.0
        * std::f64::consts::PI
        * sphere_mean(|d| 3.0 * spot_falloff(d.dot(axis), 0.9, 0.6) as f64);
    assert!(
        (spot.power(1.0) as f64 - flux).abs() < 1e-3 * flux,
        "{} vs {flux}",
        spot.power(1.0)
    );
    let point = Light::Point {
        position: Vec3::ONE,
        intensity: Rgb::splat(2.0),
    };
    assert!((point.power(5.0) - 8.0 * PI).abs() < 1e-5);
    let sun = Light::Sun {
        to_sun: Vec3::Y,
        irradiance: Rgb::splat(4.0),
        cos_max: 1.0,
    };
    assert!((sun.power(2.0) - 16.0 * PI).abs() < 1e-4);
    let env = Light::Environment(Environment::Constant {
        radiance: Rgb::splat(0.5),
    });
    assert!((env.power(2.0) - 2.0 * PI * PI).abs() < 1e-4);
    let quad = Geometry::new(vec![(
        Primitive::Parallelogram {
            corner: Vec3::ZERO,
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 3.0),
        },
        0,
    )]);
    for (two_sided, sides) in [(false, 1.0), (true, 2.0)] {
        let area = Light::area(0, Texture::Constant(Rgb::splat(0.5)), two_sided, &quad);
        assert!((area.power(9.0) - PI * 6.0 * 0.5 * sides).abs() < 1e-4);
    }
}

/// Every light sample the estimator can receive has a finite, positive
/// density and a unit direction (it divides by the density). The grid of u
/// includes the edges of [0, 1)²: u = (0, ½) puts the cosine-weighted
/// environment sample exactly in the surface's plane, where its density is 0.
#[test]
fn every_light_sample_has_a_positive_density() {
    let top = 1.0 - f32::EPSILON / 2.0;
    let quad = Primitive::Parallelogram {
        corner: Vec3::new(-1.0, 2.0, -1.0),
        edge_u: Vec3::Z * 2.0,
        edge_v: Vec3::X * 2.0,
    };
    let ball = Primitive::Sphere {
        center: Vec3::new(0.0, 0.0, 4.0),
        radius: 1.0,
    };
    let geometry = Geometry::new(vec![(quad, 0), (ball, 1)]);
    let white = || Texture::Constant(Rgb::WHITE);
    let lights = [
        Light::Point {
            position: Vec3::new(0.5, 1.0, 0.0),
            intensity: Rgb::WHITE,
        },
        Light::Spot {
            position: Vec3::new(0.0, 3.0, 0.0),
            axis: -Vec3::Y,
            intensity: Rgb::WHITE,
            cos_inner: 0.9,
            cos_outer: 0.5,
            edge: SpotEdge::LinearAngle,
        },
        Light::area(0, white(), false, &geometry),
        Light::area(0, white(), true, &geometry),
        Light::area(1, white(), false, &geometry),
        Light::Sun {
            to_sun: Vec3::new(0.3, 1.0, 0.2).normalize(),
            irradiance: Rgb::WHITE,
            cos_max: 0.99,
        },
        Light::Sun {
            to_sun: Vec3::Y,
            irradiance: Rgb::WHITE,
            cos_max: 1.0,
        },
        Light::Environment(Environment::Constant {
            radiance: Rgb::WHITE,
        }),
        Light::Environment(Environment::Sky {
            zenith: Rgb::splat(2.0),
            horizon: Rgb::WHITE,
            ground: Rgb::splat(0.1),
            up: Vec3::Y,
        }),
    ];
    let normals = [
        None,
        Some(Vec3::Y),
        Some(-Vec3::Z),
        Some(Vec3::new(1.0, 1.0, -1.0).normalize()),
    ];
    let grid = [0.0, 0.25, 0.5, 0.75, top];
    for (i, light) in lights.iter().enumerate() {
        for normal in normals {
            for ux in grid {
                for uy in grid {
                    let u = Vec2::new(ux, uy);
                    let Some(ls) = light.sample_facing(Vec3::ZERO, normal, u, &geometry, 0.0)
                    else {
                        continue;
                    };
                    assert!(
                        ls.pdf.is_finite() && ls.pdf > 0.0,
                        "light {i}, normal {normal:?}, u = {u}: pdf {}",
                        ls.pdf
                    );
                    assert!((ls.wi.length() - 1.0).abs() < 1e-5, "light {i}: {}", ls.wi);
                }
            }
        }
    }
}
