//! `partition_of_unity`: the weights every traced strategy gives one fixed
//! path sum to one. Each strategy's subpath prefixes are rebuilt as the
//! random walks would record them (module `subpath`'s densities), so a
//! density that one strategy computes differently from another shows here
//! as a sum off one, deterministically.

use super::media::Surrogate;
use super::subpath::{forward_density, reverse_density, reverse_pdf};
use super::vertex::{Kind, Vertex};
use super::weights::{weight_joined, weight_s0, Context};
use super::{allowed, scene_sphere};
use crate::integrator::Scene;
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};
use crate::medium::PhaseFunction;
use std::path::Path;

const BOX: &str = r#"
[camera]
position = [0.0, 1.0, 3.4]
look_at = [0.0, 1.0, 0.0]
fov = 45.0
resolution = [8, 8]
[integrator]
max_depth = 8
max_scatter_depth = 8
[[shape]]
type = "quad"
center = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [2.0, 2.0]
material = { type = "diffuse", albedo = 0.8 }
[[shape]]
type = "quad"
center = [0.0, 1.0, -1.0]
normal = [0.0, 0.0, 1.0]
size = [2.0, 2.0]
material = { type = "diffuse", albedo = 0.7 }
[[shape]]
type = "quad"
center = [-1.0, 1.0, 0.0]
normal = [1.0, 0.0, 0.0]
size = [2.0, 2.0]
material = { type = "mirror", reflectance = 0.9 }
[[shape]]
type = "quad"
center = [0.0, 1.99, 0.0]
normal = [0.0, -1.0, 0.0]
size = [0.6, 0.6]
emission = 4.0
material = { type = "diffuse", albedo = 0.0 }
[[light]]
type = "point"
position = [0.5, 1.5, 0.2]
intensity = 2.0
"#;

const FOG: &str = r#"
[[medium]]
type = "homogeneous"
sigma_a = 0.1
sigma_s = 0.6
phase = { type = "hg", g = 0.4 }
global = true
"#;

fn scene(text: &str) -> Scene {
    let file = Path::new("partition_of_unity.toml");
    let desc = crate::scene::parse(text, file).expect("parse");
    crate::scene::build(&desc, file, Path::new(".")).expect("build")
}

/// Where a path vertex is: on the surface a ray from the previous vertex
/// toward a point meets first, or a medium event at a point.
enum At {
    Toward(Vec3),
    Medium(Vec3),
}

/// The path x₀ … x_k as unlinked vertices: x₀ on `light` at `light_p` (its
/// normal `light_n`), then `inner`, then the lens (the camera's position).
fn path(scene: &Scene, light: u32, light_p: Vec3, light_n: Vec3, inner: &[At]) -> Vec<Vertex> {
    let mut xs = vec![Vertex::new(
        Kind::Light { light },
        light_p,
        light_n,
        Rgb::WHITE,
    )];
    for at in inner {
        let from = xs.last().unwrap().p;
        let v = match *at {
            At::Medium(p) => {
                let phase = PhaseFunction::HenyeyGreenstein { g: 0.4 };
                Vertex::new(Kind::Medium { phase }, p, Vec3::ZERO, Rgb::WHITE)
            }
            At::Toward(p) => {
                let dir = (p - from).normalize();
                let hit = scene
                    .geometry
                    .intersect(&Ray::new(from + dir * 1e-3, dir), f32::INFINITY)
                    .expect("the path's surface");
                let material = scene.material_at(&hit);
                let kind = Kind::Surface {
                    material,
                    ns: hit.shading_normal,
                    shape: hit.shape,
                    primitive: hit.primitive,
                    st: hit.st,
                };
                let mut v = Vertex::new(kind, hit.p, hit.geometric_normal, Rgb::WHITE);
                v.delta = material.is_delta();
                v
            }
        };
        xs.push(v);
    }
    let lens = scene.camera.view_at(0.0).position;
    xs.push(Vertex::new(Kind::Camera, lens, Vec3::ZERO, Rgb::WHITE));
    xs
}

/// Links `vs` (in subpath order) as a walk records them: `first_pdf` is the
/// solid-angle density of the first segment's direction at `vs[0]`.
fn link(ctx: &Context, vs: &mut [Vertex], first_pdf: impl Fn(Vec3) -> f32) {
    for i in 1..vs.len() {
        let dir = (vs[i].p - vs[i - 1].p).normalize();
        vs[i].w_prev = -dir;
        let pdf = if i == 1 {
            first_pdf(dir)
        } else {
            vs[i - 1].pdf_dir(vs[i - 1].w_prev, dir)
        };
        let (head, tail) = vs.split_at_mut(i);
        forward_density(&ctx.sur, &head[i - 1], &mut tail[0], dir, pdf, None);
        if i >= 2 {
            let rev = reverse_pdf(&vs[i - 1], dir);
            let (p, tau) = (vs[i - 1].p, vs[i - 1].tau_in);
            vs[i - 2].pdf_rev = reverse_density(ctx.scene, &vs[i - 2], rev, p, tau);
        }
    }
}

/// The camera subpath z₀ … z_{t−1} = x_k … x_{k−t+1}; when it reaches
/// x₀, that vertex is the emitter's surface as the camera walk meets it.
fn camera_prefix(ctx: &Context, xs: &[Vertex], surface_x0: &Vertex, t: usize) -> Vec<Vertex> {
    let k = xs.len() - 1;
    let mut zs: Vec<Vertex> = (0..t).map(|j| xs[k - j]).collect();
    if t == k + 1 {
        zs[k] = Vertex {
            p: xs[0].p,
            ng: xs[0].ng,
            ..*surface_x0
        };
    }
    zs[0].pdf_fwd = 1.0;
    let camera = &ctx.scene.camera;
    link(ctx, &mut zs, |dir| camera.direction_pdf(dir, 0.0));
    zs
}

/// The light subpath y₀ … y_{s−1} = x₀ … x_{s−1}, started by the light pick.
fn light_prefix(ctx: &Context, xs: &[Vertex], s: usize) -> Vec<Vertex> {
    let mut ys = xs[..s].to_vec();
    ys[0].pdf_fwd = ctx.emit_density(&ys[0]);
    let y0 = ys[0];
    let Kind::Light { light } = y0.kind else {
        unreachable!("x₀ is a light point")
    };
    let l = &ctx.scene.lights[light as usize];
    link(ctx, &mut ys, |dir| l.emission_pdf_dir(y0.ng, dir));
    ys
}

/// Σ over the strategies the sampler traces for path `xs` of their weights.
fn weight_sum(ctx: &Context, xs: &[Vertex], surface_x0: Option<&Vertex>) -> f64 {
    let k = xs.len() - 1;
    let mut sum = 0.0;
    for s in 0..=k {
        let t = k + 1 - s;
        if s == 0 && surface_x0.is_none() {
            continue; // a point light: no camera path hits it
        }
        let x0_surface = surface_x0.copied().unwrap_or(xs[0]);
        let camera = camera_prefix(ctx, xs, &x0_surface, t);
        let light = if s == 1 {
            vec![Vertex {
                pdf_fwd: 0.0,
                ..xs[0]
            }]
        } else {
            light_prefix(ctx, xs, s.max(1))
        };
        if !allowed(ctx.scene, &light, &camera, s, t) {
            continue;
        }
        let w = match s {
            0 => weight_s0(ctx, &camera, &xs[0]),
            _ => weight_joined(ctx, &light[..s], &camera),
        };
        eprintln!("(s, t) = ({s}, {t}): weight {w}");
        sum += w as f64;
    }
    sum
}

/// Checks the path from the area light (`point` false) or the point light.
fn check(text: &str, point: bool, light_p: Vec3, light_n: Vec3, inner: &[At], what: &str) {
    let scene = scene(text);
    let light = scene
        .lights
        .iter()
        .position(|l| l.is_delta_position() == point)
        .unwrap() as u32;
    let ctx = Context {
        scene: &scene,
        sur: Surrogate::new(&scene, 0.0),
        sphere: scene_sphere(&scene),
        time: 0.0,
    };
    let xs = path(&scene, light, light_p, light_n, inner);
    // The camera walk's vertex on the emitter: the ceiling light's quad.
    let surface_x0 = (!point).then(|| {
        let below = light_p - light_n * 1e-2;
        let at = [At::Toward(light_p)];
        path(&scene, light, below, light_n, &at)[1]
    });
    let sum = weight_sum(&ctx, &xs, surface_x0.as_ref());
    assert!((sum - 1.0).abs() < 1e-4, "{what}: weights sum to {sum}");
}

const CEILING: Vec3 = Vec3::new(0.1, 1.99, -0.1);
const DOWN: Vec3 = Vec3::new(0.0, -1.0, 0.0);

#[test]
fn partition_of_unity() {
    let floor = Vec3::new(0.3, 0.0, 0.2);
    let back = Vec3::new(-0.2, 0.8, -1.0);
    let diffuse = [At::Toward(floor), At::Toward(back)];
    check(
        BOX,
        false,
        CEILING,
        DOWN,
        &diffuse,
        "area light, two diffuse bounces",
    );
    let point = Vec3::new(0.5, 1.5, 0.2);
    check(BOX, true, point, Vec3::ZERO, &diffuse, "point light");
    // Light off the mirror wall onto the back wall: only s = 0 and the
    // strategies joining at the back wall or beyond count.
    let mirror = Vec3::new(-1.0, 1.2, -0.3);
    let mirrored = [At::Toward(mirror), At::Toward(back), At::Toward(floor)];
    check(BOX, false, CEILING, DOWN, &mirrored, "a mirror bounce");
    let fog = format!("{BOX}{FOG}");
    let in_fog = [
        At::Medium(Vec3::new(0.2, 1.2, 0.1)),
        At::Toward(floor),
        At::Medium(Vec3::new(-0.1, 0.9, 0.8)),
    ];
    check(
        &fog,
        false,
        CEILING,
        DOWN,
        &in_fog,
        "medium vertices in fog",
    );
}
