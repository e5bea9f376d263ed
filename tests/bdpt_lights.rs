//! Bidirectional path tracing with every light type and material against
//! the path tracer: area lights (spheres sampled by cone, textured and
//! two-sided quads), point, spot, sun disk, sky and environment map;
//! Phong, rough and smooth conductors and dielectrics; a thin lens; motion
//! blur (one time shared by both subpaths).

mod bdpt_support;

use bdpt_support::*;

/// A floor and a back wall seen by an 8×8 camera, with `body` appended.
fn stage(camera_extra: &str, body: &str) -> String {
    format!(
        r#"
        [camera]
        position = [0.0, 1.2, 4.0]
        look_at = [0.0, 0.6, 0.0]
        fov = 45.0
        resolution = [8, 8]
        {camera_extra}
        [integrator]
        max_depth = 8
        seed = 21
        [[shape]]
        type = "quad"
        center = [0.0, 0.0, 0.0]
        normal = [0.0, 1.0, 0.0]
        size = [5.0, 5.0]
        material = {{ type = "diffuse", albedo = [0.7, 0.65, 0.6] }}
        [[shape]]
        type = "quad"
        center = [0.0, 1.5, -1.5]
        normal = [0.0, 0.0, 1.0]
        size = [5.0, 3.0]
        material = {{ type = "phong", albedo = 0.6, exponent = 20.0 }}
        {body}
        "#
    )
}

const MATERIALS: &str = r#"
[[shape]]
type = "sphere"
center = [-0.9, 0.4, 0.0]
radius = 0.4
material = { type = "conductor", alpha = 0.25, eta = [0.18, 0.42, 1.37], k = [3.42, 2.35, 1.77] }
[[shape]]
type = "sphere"
center = [0.0, 0.35, 0.3]
radius = 0.35
material = { type = "dielectric", ior = 1.4, alpha = 0.2 }
[[shape]]
type = "sphere"
center = [0.9, 0.4, -0.2]
radius = 0.4
material = { type = "conductor", alpha = 0.0, f0 = [0.9, 0.8, 0.5] }
[[shape]]
type = "box"
center = [0.2, 0.15, -0.8]
size = [0.3, 0.3, 0.3]
material = { type = "phong", albedo = [0.8, 0.4, 0.3], exponent = 5.0 }
"#;

const AREA_LIGHTS: &str = r#"
[[shape]]
type = "sphere"
center = [-0.6, 1.6, 0.4]
radius = 0.15
emission = [6.0, 5.0, 4.0]
material = { type = "diffuse", albedo = 0.0 }
[[shape]]
type = "quad"
center = [0.8, 2.0, 0.0]
normal = [-0.3, -1.0, 0.2]
size = [0.6, 0.6]
emission = { type = "checkerboard", a = 0.5, b = 6.0, uv_scale = 3 }
material = { type = "diffuse", albedo = 0.2 }
[[shape]]
type = "quad"
center = [0.0, 1.0, -1.2]
normal = [0.0, 0.3, 1.0]
size = [0.3, 0.3]
emission = 3.0
two_sided = true
material = { type = "diffuse", albedo = 0.0 }
"#;

const DELTA_LIGHTS: &str = r#"
[[light]]
type = "point"
position = [-1.2, 1.8, 1.0]
intensity = [3.0, 3.0, 2.5]
[[light]]
type = "spot"
position = [1.2, 2.2, 1.2]
look_at = [0.3, 0.0, 0.0]
intensity = [8.0, 6.0, 5.0]
cone_angle = 30.0
"#;

const SKY_LIGHTS: &str = r#"
[[light]]
type = "sun"
direction = [-0.6, -1.0, -0.5]
irradiance = [2.0, 1.9, 1.7]
angular_radius = 3.0
[[light]]
type = "sky"
zenith = [0.2, 0.3, 0.6]
horizon = [0.5, 0.55, 0.6]
ground = [0.05, 0.05, 0.05]
"#;

const ENV_MAP: &str = r#"
[[light]]
type = "environment_map"
file = "scenes/sky.exr"
scale = 0.8
rotate = [0.0, 40.0, 0.0]
"#;

fn check(text: &str, what: &str) {
    let scene = scene_from_str(text);
    let path = estimate_pixels(&scene, 2048);
    let bdpt = bdpt_pixels(&scene, 512);
    eprintln!(
        "{what}: path {:?} bdpt {:?}",
        image_mean(&path),
        image_mean(&bdpt)
    );
    assert_agree(&bdpt, &path, what);
}

#[test]
fn area_lights_and_every_material() {
    check(
        &stage("", &format!("{AREA_LIGHTS}{MATERIALS}")),
        "area lights",
    );
}

#[test]
fn point_and_spot_lights_and_every_material() {
    check(
        &stage("", &format!("{DELTA_LIGHTS}{MATERIALS}")),
        "point and spot",
    );
}

#[test]
fn sun_disk_and_sky() {
    check(
        &stage("", &format!("{SKY_LIGHTS}{MATERIALS}")),
        "sun and sky",
    );
}

#[test]
fn environment_map() {
    check(
        &stage("", &format!("{ENV_MAP}{MATERIALS}")),
        "environment map",
    );
}

/// A thin lens focused on the middle sphere: t = 1 connects through lens points.
#[test]
fn thin_lens() {
    let lens = "aperture_radius = 0.15\nfocus_distance = 3.8";
    check(
        &stage(lens, &format!("{AREA_LIGHTS}{DELTA_LIGHTS}{MATERIALS}")),
        "thin lens",
    );
}

/// A moving camera, a moving area light and a moving sphere over the
/// shutter: both subpaths and every connection at the sample's one time.
#[test]
fn motion_blur() {
    let camera = "shutter = [-0.5, 0.5]\ntransform = { keyframes = [{ time = -0.5 }, { time = 0.5, translate = [0.3, 0.0, 0.0] }] }";
    let moving = r#"
[[shape]]
type = "sphere"
radius = 0.15
emission = [8.0, 6.0, 4.0]
material = { type = "diffuse", albedo = 0.0 }
transform = { keyframes = [{ time = -0.5, translate = [-0.8, 1.5, 0.2] }, { time = 0.5, translate = [0.8, 1.7, 0.2] }] }
[[shape]]
type = "sphere"
radius = 0.3
material = { type = "diffuse", albedo = [0.2, 0.7, 0.3] }
transform = { keyframes = [{ time = -0.5, translate = [0.0, 0.3, 0.9] }, { time = 0.5, translate = [0.0, 0.8, 0.9] }] }
"#;
    check(
        &stage(camera, &format!("{moving}{MATERIALS}")),
        "motion blur",
    );
}
