//! Light slabs against closed forms: a baked sphere of absorbing, emitting
//! medium reproduces its leaving radiance and transmittance at every recorded
//! line, and the lookup between records converges at the rate of its filter.

mod common;

use brume::geometry::slab::{Filter, Grid, LightSlab, Param, SlabHeader, SlabShape};
use brume::math::color::Rgb;
use brume::math::{Affine3A, Bounds3, Ray, Vec3};
use brume::render::slab_bake::bake;
use brume::render::RenderOptions;
use common::stats::tolerance;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Relative rounding of a value stored as a half float (half an ulp, 2⁻¹¹).
const HALF_ROUNDING: f64 = 1.0 / 2048.0;

/// Grey absorption of the sphere (1/m); it does not scatter.
const SIGMA_A: f64 = 0.8;
/// Emitted radiance Le of the medium (the source term is σa·Le).
const LE: [f64; 3] = [1.0, 0.6, 0.3];
/// Radius of the sphere, centred at the origin.
const RADIUS: f64 = 1.0;

/// The sphere of medium under a constant environment of 0.7: the
/// environment must not show in the records (it lies behind the box).
fn sphere_scene() -> String {
    format!(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\
         [[light]]\ntype = \"environment\"\nradiance = 0.7\n\
         [[medium]]\ntype = \"homogeneous\"\nsigma_a = {SIGMA_A}\nemission = {LE:?}\n\
         bounds = {{ type = \"sphere\", center = [0, 0, 0], radius = {RADIUS} }}\n"
    )
}

/// Length of the line through `p` along unit `d` inside the sphere.
fn chord(p: Vec3, d: Vec3) -> f64 {
    let disc = discriminant(p, d);
    if disc > 0.0 {
        2.0 * disc.sqrt()
    } else {
        0.0
    }
}

/// (Half the chord)²: b² − (|p|² − R²) with b = p·d.
fn discriminant(p: Vec3, d: Vec3) -> f64 {
    let (p, d) = (p.as_dvec3(), d.as_dvec3());
    let b = p.dot(d);
    b * b - (p.length_squared() - RADIUS * RADIUS)
}

/// Lines this close to tangent (|disc| < 1e-4 R², a chord under 0.02 R) are
/// not checked: there the chord is ill-conditioned (dℓ/d disc = 1/√disc ≥ 100),
/// so the renderer's f32 sphere test may find it a few times longer or
/// shorter than the f64 closed form, or hit a line that misses it.
const GRAZING: f64 = 1e-4;

/// The box baked: off-centre, so that the sphere lies away from the
/// mid-planes where lines are anchored and the slopes' interpolation shows.
fn bake_box() -> Bounds3 {
    Bounds3::new(Vec3::splat(-1.2), Vec3::new(2.0, 2.4, 1.8))
}

/// Every recorded line of the baked sphere: transmittance exp(-σa·ℓ) (the
/// homogeneous medium's closed-form optical depth: exact up to the half
/// float), and radiance Le·(1 - exp(-σa·ℓ)) within k standard errors. With
/// σs = 0 and the majorant σa, a sample adds Le exactly when its first
/// tentative collision falls inside the chord, so its standard error is
/// Le·sqrt(p(1-p)/n) with p = 1 - exp(-σa·ℓ), known in closed form too.
#[test]
fn baked_sphere_matches_closed_form_at_recorded_lines() {
    let scene = common::scene_from_str(&sphere_scene());
    let grid = Grid {
        spatial: 7,
        angular: 5,
    };
    let spp = 256;
    let header = SlabHeader {
        bounds: bake_box(),
        grid,
        spp,
        seed: 11,
    };
    let options = RenderOptions {
        spp,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(2),
        progress: false,
    };
    let out = bake(&scene, header, &options, &AtomicBool::new(false));
    let slab = out.slab.expect("a finished bake");
    assert_eq!((out.spp, out.nonfinite, out.clamped), (spp, 0, 0));
    let param = slab.param();
    let records = grid.records();
    let m = 3 * records as usize;
    let k = common::k_sigma(m);
    let mut crossing = 0;
    for index in 0..records {
        let (p, d) = param.line(index);
        let (l, t) = slab.record(index as usize);
        if discriminant(p, d).abs() < GRAZING * RADIUS * RADIUS {
            continue;
        }
        let t_exact = (-SIGMA_A * chord(p, d)).exp();
        let p_hit = 1.0 - t_exact;
        crossing += usize::from(p_hit > 0.0);
        for c in 0..3 {
            let t_err = (t[c] as f64 - t_exact).abs();
            assert!(
                t_err <= HALF_ROUNDING * t_exact + 1e-6,
                "record {index} channel {c}: transmittance {} vs exp(-σa·ℓ) = {t_exact}",
                t[c]
            );
            let expected = LE[c] * p_hit;
            let se = LE[c] * (p_hit * (1.0 - p_hit) / spp as f64).sqrt();
            let diff = (l[c] as f64 - expected).abs();
            assert!(
                diff <= tolerance(se, expected, k) + HALF_ROUNDING * expected,
                "record {index} channel {c}: radiance {} vs Le(1 - T) = {expected} ± {se} (allowed {k:.2} σ)",
                l[c]
            );
        }
    }
    // The grid spans every line meeting the box at slopes up to 1, most of
    // which miss the sphere: the check must still cover many that cross it
    // (626 of 7350 on this grid).
    assert!(
        crossing >= 500,
        "only {crossing} of {records} lines cross the sphere"
    );
}

/// The sphere's transmittance recorded exactly on `grid` (no bake noise):
/// what the lookup interpolates.
fn exact_slab(grid: Grid) -> LightSlab {
    let header = SlabHeader {
        bounds: bake_box(),
        grid,
        spp: 1,
        seed: 0,
    };
    let param = Param::new(header.bounds, grid);
    LightSlab::from_records(header, |i| {
        let (p, d) = param.line(i);
        let t = (-SIGMA_A * chord(p, d)).exp() as f32;
        (Rgb::splat(1.0 - t), Rgb::splat(t))
    })
    .0
}

/// Mean absolute error of the looked-up transmittance over fixed random
/// lines through the inner half of the sphere (where the chord is a smooth
/// function of the line, so that the filter's order shows).
fn lookup_error(grid: Grid, filter: Filter) -> f64 {
    let shape = SlabShape::new(0, Arc::new(exact_slab(grid)), Affine3A::IDENTITY, filter);
    let mut sampler = brume::sampling::Sampler::from_seed(3);
    let n = 4000;
    let mut total = 0.0;
    for _ in 0..n {
        let u = sampler.next_2d();
        let d = brume::sampling::warp::square_to_uniform_sphere(u);
        let q = sampler.next_2d();
        let target = Vec3::new(q.x - 0.5, q.y - 0.5, sampler.next_1d() - 0.5) * 0.5;
        let ray = Ray::new(target - d * 5.0, d);
        let c = shape
            .crossing(&ray, f32::INFINITY)
            .expect("the ray enters the box");
        // The recorded line runs the other way: light leaving toward the ray's origin.
        let exact = (-SIGMA_A * chord(target, -d)).exp();
        total += (c.transmittance.g as f64 - exact).abs();
    }
    total / n as f64
}

/// Halving every grid step divides the lookup error by about 4 for
/// quadrilinear interpolation (second order) and by about 2 for the nearest
/// record (first order): the observed orders over two halvings.
#[test]
fn lookup_error_shrinks_at_the_filters_order() {
    let grids = [(11, 6), (21, 11), (41, 21)].map(|(spatial, angular)| Grid { spatial, angular });
    for (filter, lo, hi) in [
        (Filter::Quadrilinear, 1.7, 2.4),
        (Filter::Nearest, 0.7, 1.3),
    ] {
        let errors = grids.map(|g| lookup_error(g, filter));
        eprintln!("{filter:?}: mean |error| {errors:?}");
        for w in errors.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!(
                (lo..=hi).contains(&order),
                "{filter:?}: errors {errors:?}, observed order {order:.2}, expected {lo} to {hi}"
            );
        }
    }
}
