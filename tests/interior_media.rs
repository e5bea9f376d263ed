//! Media bounded by shapes (`[[shape]] interior`): transmittance through
//! mesh-, sphere- and box-bounded interiors against exp(−σt·d) with d the
//! closed-form chord length (a sum of chords for a concave mesh), images of
//! a mesh-bounded medium against the box-bounded one, and glass (dielectric)
//! boundaries against closed forms and the furnace.

mod common;

use brume::integrator::Scene;
use brume::math::color::Rgb;
use brume::math::{Ray, Vec3};
use brume::sampling::Sampler;
use common::*;

const SIGMA_T: [f32; 3] = [0.7, 1.1, 1.6];

/// A scene holding only `shapes` (TOML), with the given shadow-ray estimator.
fn scene(shapes: &str, estimator: &str) -> Scene {
    let text = SceneText::camera([0.0, 0.0, 9.0], [0.0; 3], [4, 4])
        .integrator(&format!("transmittance = \"{estimator}\""))
        .raw(shapes);
    scene_from_str(&text.build())
}

/// Parameter interval of `ray` inside the box [lo, hi] (slab method), clipped to [0, t_max].
fn slab(ray: &Ray, lo: Vec3, hi: Vec3, t_max: f32) -> f32 {
    let (mut t0, mut t1) = (0.0f64, t_max as f64);
    for a in 0..3 {
        let (o, d) = (ray.origin[a] as f64, ray.direction[a] as f64);
        let (u, v) = ((lo[a] as f64 - o) / d, (hi[a] as f64 - o) / d);
        t0 = t0.max(u.min(v));
        t1 = t1.min(u.max(v));
    }
    (t1 - t0).max(0.0) as f32
}

/// Parameter length of `ray` (unit direction) inside a sphere, clipped to [0, t_max].
fn sphere_chord(ray: &Ray, center: Vec3, radius: f32, t_max: f32) -> f32 {
    let oc = ray.origin - center;
    let b = oc.dot(ray.direction) as f64;
    let c = (oc.length_squared() - radius * radius) as f64;
    let disc = b * b - c;
    if disc <= 0.0 {
        return 0.0;
    }
    let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
    (t1.min(t_max as f64) - t0.max(0.0)).max(0.0) as f32
}

/// Rays through (and from inside) the region around the origin, with their ends.
fn rays() -> Vec<(Ray, f32)> {
    let mut sampler = Sampler::from_seed(7);
    let mut out = Vec::new();
    for i in 0..24 {
        let target = Vec3::new(
            sampler.next_1d() * 2.4 - 1.2,
            sampler.next_1d() * 2.4 - 1.2,
            sampler.next_1d() * 2.4 - 1.2,
        );
        let dir = Vec3::new(
            sampler.next_1d() - 0.5,
            sampler.next_1d() - 0.5,
            sampler.next_1d() - 0.5,
        )
        .normalize();
        // Every third ray starts inside the region; every other one ends before leaving.
        let origin = if i % 3 == 0 {
            target
        } else {
            target - dir * 5.0
        };
        let t_max = if i % 2 == 0 { f32::INFINITY } else { 5.3 };
        out.push((Ray::new(origin, dir), t_max));
    }
    out
}

fn expected(d: f32) -> [f64; 3] {
    SIGMA_T.map(|s| (-(s as f64) * d as f64).exp())
}

/// Closed-form (auto) transmittance equals exp(−σt d) to rounding; ratio tracking within its SE.
fn check_transmittance(shapes: &str, chord: impl Fn(&Ray, f32) -> f32, what: &str) {
    let exact = scene(shapes, "auto");
    let tracked = scene(shapes, "ratio");
    let mut inside_rays = 0;
    for (i, &(ray, t_max)) in rays().iter().enumerate() {
        let d = chord(&ray, t_max);
        inside_rays += usize::from(d > 0.0);
        let want = expected(d);
        let tr = exact.transmittance(&ray, t_max, &mut Sampler::from_seed(1));
        for c in 0..3 {
            assert_within(
                tr[c] as f64,
                0.0,
                want[c],
                3,
                &format!("{what} ray {i} closed form"),
            );
        }
        let mut acc = Accumulator::default();
        for s in 0..4000 {
            let mut sampler = Sampler::new(11, i as u32, 0, s);
            acc.add(tracked.transmittance(&ray, t_max, &mut sampler));
        }
        assert_estimate(
            &acc.estimate(),
            want,
            &format!("{what} ray {i} ratio tracking"),
        );
    }
    assert!(
        inside_rays >= 12,
        "{what}: only {inside_rays} rays met the medium"
    );
}

const INTERIOR: &str =
    r#"interior = { type = "homogeneous", sigma_t = [0.7, 1.1, 1.6], albedo = 0.5 }"#;

#[test]
fn transmittance_through_a_transformed_mesh_cube_is_exp_of_the_chord() {
    // cube.obj is [-1, 1]^3; scaled by [1.1, 0.6, 0.9] and moved, an axis-aligned box still.
    let (scale, shift) = (Vec3::new(1.1, 0.6, 0.9), Vec3::new(0.1, -0.2, 0.05));
    check_transmittance(
        &format!(
            r#"[[shape]]
            type = "mesh"
            file = "tests/data/meshes/cube.obj"
            transform = {{ scale = [1.1, 0.6, 0.9], translate = [0.1, -0.2, 0.05] }}
            {INTERIOR}"#
        ),
        |ray, t_max| slab(ray, shift - scale, shift + scale, t_max),
        "mesh cube",
    );
}

#[test]
fn transmittance_through_a_sphere_interior_is_exp_of_the_chord() {
    let center = Vec3::new(0.2, 0.1, -0.1);
    check_transmittance(
        &format!(
            r#"[[shape]]
            type = "sphere"
            center = [0.2, 0.1, -0.1]
            radius = 1.1
            {INTERIOR}"#
        ),
        |ray, t_max| sphere_chord(ray, center, 1.1, t_max),
        "sphere",
    );
}

#[test]
fn transmittance_through_a_concave_mesh_sums_its_inside_chords() {
    // u_shape.obj: three unit-voxel boxes, [0,3]x[0,1], [0,1]x[1,3], [2,3]x[1,3] (z in [0, 1]),
    // moved so that the region of the rays covers it; a ray can enter, leave and re-enter.
    let shift = Vec3::new(-1.5, -1.5, -0.5);
    let boxes = [
        (Vec3::new(0.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 1.0)),
        (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 3.0, 1.0)),
        (Vec3::new(2.0, 1.0, 0.0), Vec3::new(3.0, 3.0, 1.0)),
    ];
    let chord = |ray: &Ray, t_max: f32| -> f32 {
        boxes
            .iter()
            .map(|&(lo, hi)| slab(ray, lo + shift, hi + shift, t_max))
            .sum()
    };
    let shapes = format!(
        r#"[[shape]]
        type = "mesh"
        file = "tests/data/meshes/u_shape.obj"
        transform = {{ translate = [-1.5, -1.5, -0.5] }}
        {INTERIOR}"#
    );
    check_transmittance(&shapes, chord, "U mesh");
    // The ray across both prongs: in, out, in again: d = 1 + 1.
    let ray = Ray::new(Vec3::new(-3.0, 0.9, 0.1), Vec3::X);
    let tr = scene(&shapes, "auto").transmittance(&ray, f32::INFINITY, &mut Sampler::from_seed(1));
    assert_within(tr[0] as f64, 0.0, expected(2.0)[0], 1, "across both prongs");
}

/// Constant-density VDB (`homogeneous_box.vdb`: density 1 on [0, 0.969]³) scaled to cover [-1.94, 1.94]³.
const VDB_INTERIOR: &str = r#"interior = { type = "vdb", file = "tests/data/volumes/homogeneous_box.vdb", density_scale = 1.1, albedo = 0.5, transform = { scale = 4.0, translate = [-1.9375, -1.9375, -1.9375] } }"#;

#[test]
fn a_constant_vdb_masked_by_a_mesh_or_sphere_transmits_exp_of_the_chord() {
    for (shapes, chord, what) in [
        (
            format!(
                r#"[[shape]]
                type = "mesh"
                file = "tests/data/meshes/cube.obj"
                {VDB_INTERIOR}"#
            ),
            Box::new(|ray: &Ray, t_max| slab(ray, Vec3::splat(-1.0), Vec3::splat(1.0), t_max))
                as Box<dyn Fn(&Ray, f32) -> f32>,
            "VDB in mesh cube",
        ),
        (
            format!(
                r#"[[shape]]
                type = "sphere"
                radius = 1.2
                {VDB_INTERIOR}"#
            ),
            Box::new(|ray: &Ray, t_max| sphere_chord(ray, Vec3::ZERO, 1.2, t_max)),
            "VDB in sphere",
        ),
    ] {
        let scene = scene(&shapes, "auto");
        for (i, &(ray, t_max)) in rays().iter().enumerate() {
            let want = (-1.1 * chord(&ray, t_max) as f64).exp();
            let mut acc = Accumulator::default();
            for s in 0..4000 {
                let mut sampler = Sampler::new(13, i as u32, 0, s);
                acc.add(scene.transmittance(&ray, t_max, &mut sampler));
            }
            assert_estimate(&acc.estimate(), [want; 3], &format!("{what} ray {i}"));
        }
    }
}

/// A lit scene around `medium`: a point light, a sky, a floor and a red ball beside it.
fn lit_scene(medium: &str) -> String {
    SceneText::camera([0.3, 1.2, 5.0], [0.0; 3], [8, 8])
        .fov(45.0)
        .integrator("max_depth = 24")
        .point_light([2.0, 3.0, 1.5], [12.0, 10.0, 8.0])
        .environment(0.3)
        .quad([0.0, -1.2, 0.0], [0.0, 1.0, 0.0], [12.0, 12.0])
        .with("material = { type = \"diffuse\", albedo = 0.6 }")
        .sphere([1.6, -0.6, -0.8], 0.6)
        .with("material = { type = \"diffuse\", albedo = [0.7, 0.3, 0.2] }")
        .raw(medium)
        .build()
}

const PLACE: &str = "transform = { scale = [0.8, 0.9, 0.7], rotate = [0.0, 30.0, 10.0], translate = [0.0, 0.1, 0.0] }";

#[test]
fn a_mesh_bounded_box_renders_like_the_box_bounded_medium() {
    let medium = "sigma_t = [1.2, 1.5, 2.0], albedo = 0.8, phase = { type = \"hg\", g = 0.4 }";
    let mesh = lit_scene(&format!(
        "[[shape]]\ntype = \"mesh\"\nfile = \"tests/data/meshes/cube.obj\"\n{PLACE}\n\
         interior = {{ type = \"homogeneous\", {medium} }}"
    ));
    let boxed = lit_scene(&format!(
        "[[medium]]\ntype = \"homogeneous\"\nsigma_t = [1.2, 1.5, 2.0]\nalbedo = 0.8\n\
         phase = {{ type = \"hg\", g = 0.4 }}\n\
         bounds = {{ type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }}\n{PLACE}"
    ));
    compare_images(&mesh, &boxed, "mesh cube vs box medium");
    // The same with the VDB content: grid tracking clipped to the mesh.
    let vdb = lit_scene(&format!(
        "[[shape]]\ntype = \"mesh\"\nfile = \"tests/data/meshes/cube.obj\"\n{PLACE}\n{}",
        VDB_INTERIOR
            // The VDB is placed in world space, independent of the shape; it covers the placed cube.
            .replace(
                "density_scale = 1.1, albedo = 0.5",
                "density_scale = 1.5, albedo = 0.8, phase = { type = \"hg\", g = 0.4 }"
            )
    ));
    let boxed_grey = lit_scene(&format!(
        "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 1.5\nalbedo = 0.8\nphase = {{ type = \"hg\", g = 0.4 }}\n\
         bounds = {{ type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }}\n{PLACE}"
    ));
    compare_images(&vdb, &boxed_grey, "VDB in mesh cube vs box medium");
}

fn compare_images(a: &str, b: &str, what: &str) {
    let a = estimate_pixels(&scene_from_str(a), 2048);
    let b = estimate_pixels(&scene_from_str(b), 2048);
    let b_mean: Vec<[f64; 3]> = b.iter().map(|p| p.mean).collect();
    let b_se: Vec<[f64; 3]> = b.iter().map(|p| p.std_error).collect();
    assert_pixels(&a, &b_mean, &b_se, what);
    let spread = b_mean.iter().flatten().fold(0.0f64, |m, &v| m.max(v))
        - b_mean
            .iter()
            .flatten()
            .fold(f64::INFINITY, |m, &v| m.min(v));
    assert!(spread > 0.05, "{what}: the image has structure: {spread}");
}

/// Radiance along a ray through the centre of an absorbing glass body at
/// normal incidence, in a uniform environment of 1: the front reflection F
/// plus every path that bounces k times inside (a = e^(−σa·chord) per crossing),
/// L = F + (1 − F)² a / (1 − F a).
fn normal_incidence(ior: f64, sigma_a: f64, chord: f64) -> f64 {
    let f = ((ior - 1.0) / (ior + 1.0)).powi(2);
    let a = (-sigma_a * chord).exp();
    f + (1.0 - f).powi(2) * a / (1.0 - f * a)
}

fn glass_scene(shape: &str, interior: &str) -> Scene {
    scene_from_str(&furnace_scene(
        &format!("[[shape]]\n{shape}\nmaterial = {{ type = \"dielectric\", ior = 1.5 }}\ninterior = {interior}"),
        1.0,
    ))
}

#[test]
fn an_absorbing_glass_body_at_normal_incidence_matches_the_reflection_series() {
    let absorbing = "{ type = \"homogeneous\", sigma_a = [0.3, 0.8, 2.0] }";
    for (shape, chord, origin) in [
        (
            "type = \"sphere\"\nradius = 1.0",
            2.0,
            Vec3::new(0.0, 0.0, 4.0),
        ),
        (
            "type = \"mesh\"\nfile = \"tests/data/meshes/cube.obj\"",
            2.0,
            Vec3::new(0.31, -0.17, 4.0),
        ),
    ] {
        let scene = glass_scene(shape, absorbing);
        let est = estimate_ray(&scene, Ray::new(origin, -Vec3::Z), 40_000, 3);
        let want = [0.3, 0.8, 2.0].map(|s| normal_incidence(1.5, s, chord));
        assert_estimate(&est, want, &format!("absorbing glass {shape}"));
    }
}

#[test]
fn a_glass_body_full_of_white_smoke_is_invisible_in_the_furnace() {
    let white = "{ type = \"homogeneous\", sigma_s = 3.0, phase = { type = \"hg\", g = 0.5 } }";
    for shape in [
        "type = \"sphere\"\nradius = 1.0",
        "type = \"mesh\"\nfile = \"tests/data/meshes/cube.obj\"\ntransform = { scale = 0.8, rotate = [20.0, 30.0, 0.0] }",
    ] {
        let pixels = estimate_pixels(&glass_scene(shape, white), 48);
        assert_pixels_equal(&pixels, [1.0; 3], &format!("white smoke in glass {shape}"));
    }
}

#[test]
fn an_index_matched_shape_is_no_surface() {
    // Without a material the shape bounds its medium and nothing else: a
    // clear interior (σt = 0) leaves the furnace at exactly 1 and the
    // transmittance at 1, where a surface would block or scatter.
    let scene = scene_from_str(&furnace_scene(
        "[[shape]]\ntype = \"mesh\"\nfile = \"tests/data/meshes/cube.obj\"\n\
         interior = { type = \"homogeneous\", sigma_a = 0.0 }",
        1.0,
    ));
    let ray = Ray::new(Vec3::new(0.2, 0.1, 4.0), -Vec3::Z);
    assert_eq!(
        scene.transmittance(&ray, 10.0, &mut Sampler::from_seed(1)),
        Rgb::WHITE
    );
    assert!(scene.geometry.intersect(&ray, f32::INFINITY).is_none());
}

#[test]
fn bad_interiors_are_refused_naming_the_key() {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("test.toml");
    let cube = "type = \"mesh\"\nfile = \"tests/data/meshes/cube.obj\"";
    let homogeneous = "{ type = \"homogeneous\", sigma_t = 1.0 }";
    for (shape, key) in [
        (
            format!("type = \"mesh\"\nfile = \"tests/data/meshes/open_box.obj\"\ninterior = {homogeneous}"),
            "shape[0].interior: ",
        ),
        (
            format!("type = \"quad\"\nnormal = [0.0, 1.0, 0.0]\nsize = [1.0, 1.0]\ninterior = {homogeneous}"),
            "shape[0].interior: a quad encloses no volume",
        ),
        (
            format!("{cube}\nmaterial = {{ type = \"mirror\" }}\ninterior = {homogeneous}"),
            "shape[0].material",
        ),
        (
            format!("{cube}\nemission = 1.0\ninterior = {homogeneous}"),
            "shape[0].emission",
        ),
        (
            format!("{cube}\ninterior = {{ type = \"homogeneous\", sigma_t = 1.0, global = true }}"),
            "shape[0].interior.global",
        ),
        (
            format!("{cube}\ninterior = {{ type = \"height_fog\", visibility = 10.0, scale_height = 1.0 }}"),
            "shape[0].interior",
        ),
        (
            format!("{cube}\ninterior = {{ type = \"homogeneous\", sigma_t = -1.0 }}"),
            "shape[0].interior.sigma_t",
        ),
        (
            format!("{cube}\ninterior = {{ type = \"homogeneous\", sigma_t = 1.0, bogus = 2 }}"),
            "bogus",
        ),
    ] {
        let text = format!(
            "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n[[shape]]\n{shape}\n"
        );
        let err = match brume::scene::parse(&text, &file) {
            Err(e) => e.to_string(),
            Ok(desc) => brume::scene::build(&desc, &file, std::path::Path::new(env!("CARGO_MANIFEST_DIR")))
                .err()
                .unwrap_or_else(|| panic!("accepted: {shape}"))
                .to_string(),
        };
        assert!(err.contains(key), "{shape}: {err}");
        assert!(err.contains("test.toml"), "{shape}: file not named: {err}");
    }
}

#[test]
fn an_open_mesh_interior_exits_with_2_and_one_line_naming_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let mesh =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/open_box.obj");
    let scene = dir.path().join("open.toml");
    std::fs::write(
        &scene,
        format!(
            "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n[[shape]]\ntype = \"mesh\"\n\
             file = {:?}\ninterior = {{ type = \"homogeneous\", sigma_t = 1.0 }}\n",
            mesh.display().to_string()
        ),
    )
    .unwrap();
    let output = cli::brume()
        .args(["render", "--quiet"])
        .arg(&scene)
        .arg("--out")
        .arg(dir.path().join("out.exr"))
        .output()
        .unwrap();
    let culprits = [
        "open.toml",
        "shape[0].interior",
        "open_box.obj",
        "only one triangle",
    ];
    cli::assert_refused(&output, &culprits, "open mesh interior");
}
