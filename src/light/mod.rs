//! Lights: point, spot, area (emissive shapes), sun and environment.

pub mod envmap;

use crate::geometry::{Geometry, Primitive};
use crate::light::envmap::EnvMap;
use crate::material::texture::Texture;
use crate::math::color::Rgb;
use crate::math::{Frame, Vec2, Vec3};
use crate::sampling::warp;
use std::f32::consts::PI;
use std::sync::Arc;

mod emission;
mod moving;
mod pick;
mod sphere;
pub use emission::{EmissionSample, SceneSphere};
pub use pick::{environment_share, LightPick, MAX_ENVIRONMENT_SHARE, UNIFORM_SHARE};
use sphere::Cone;

/// Radiance arriving from the sky in a direction, for environments.
#[derive(Clone, Debug)]
pub enum Environment {
    /// The same radiance from every direction.
    Constant {
        /// Radiance.
        radiance: Rgb,
    },
    /// A gradient from horizon to zenith above the horizon and a flat ground colour below.
    Sky {
        /// Radiance straight up.
        zenith: Rgb,
        /// Radiance at the horizon.
        horizon: Rgb,
        /// Radiance from below the horizon.
        ground: Rgb,
        /// Unit up axis.
        up: Vec3,
    },
    /// A lat-long HDR image, importance-sampled.
    Map(Arc<EnvMap>),
}

/// A map whose brightest texel is at most this many times its average
/// luminance is smooth enough to take as a control variate with no light
/// samples ([`Light::smooth_environment`]): `scenes/sky.exr`, a gradient
/// with a bright aureole, is 10.3; a map with the sun's disc in it is far above.
pub const SMOOTH_MAP_PEAK: f32 = 16.0;

/// An environment whose floor (least radiance) has less luminance than this
/// share of its average's is not taken as a control variate: the control
/// would book too little of it to pay for its lost light samples (a black
/// ground under a dark sky books nothing at all).
pub const MIN_FLOOR_SHARE: f32 = 0.2;

impl Environment {
    /// The least radiance from any direction, per channel.
    pub fn floor(&self) -> Rgb {
        match self {
            Environment::Constant { radiance } => *radiance,
            Environment::Map(map) => map.floor(),
            Environment::Sky {
                zenith,
                horizon,
                ground,
                ..
            } => zenith.min_per_channel(*horizon).min_per_channel(*ground),
        }
    }

    /// Radiance averaged over all directions of the sphere.
    pub fn average(&self) -> Rgb {
        match self {
            Environment::Constant { radiance } => *radiance,
            Environment::Map(map) => map.average(),
            // Directions are uniform in h = cos θ from the up axis: the ground holds
            // half the sphere, and over the upper half E[√h] = 2/3.
            Environment::Sky {
                zenith,
                horizon,
                ground,
                ..
            } => *ground * 0.5 + (*horizon * (1.0 / 3.0) + *zenith * (2.0 / 3.0)) * 0.5,
        }
    }

    /// Radiance arriving from direction `dir` (pointing away from the receiver).
    pub fn radiance(&self, dir: Vec3) -> Rgb {
        match *self {
            Environment::Constant { radiance } => radiance,
            Environment::Map(ref map) => map.radiance(dir),
            Environment::Sky {
                zenith,
                horizon,
                ground,
                up,
            } => {
                let h = dir.dot(up);
                if h < 0.0 {
                    ground
                } else {
                    // sqrt keeps the horizon band narrow, as a clear sky looks.
                    let s = h.sqrt();
                    horizon * (1.0 - s) + zenith * s
                }
            }
        }
    }
}

/// An emitter.
#[derive(Clone, Debug)]
pub enum Light {
    /// Isotropic point light of radiant intensity `intensity` (W/sr per channel).
    Point {
        /// Position.
        position: Vec3,
        /// Radiant intensity.
        intensity: Rgb,
    },
    /// Spot light: a point light restricted to a cone with a smooth edge.
    Spot {
        /// Position.
        position: Vec3,
        /// Unit axis the light points along.
        axis: Vec3,
        /// Radiant intensity on the axis.
        intensity: Rgb,
        /// Cosine of the angle where the falloff starts.
        cos_inner: f32,
        /// Cosine of the cone's half-angle (no light outside).
        cos_outer: f32,
        /// How the edge falls from 1 to 0 between the two cones.
        edge: SpotEdge,
    },
    /// An emissive shape: radiance constant or a texture over its surface.
    ///
    /// Sampling does not depend on the radiance (uniform by area, or by cone
    /// for a sphere): a textured emitter is sampled like a constant one and
    /// its texture evaluated at the sampled point, so both MIS strategies use
    /// the same pdf.
    Area {
        /// Index of the shape in the scene.
        shape: u32,
        /// Emitted radiance.
        radiance: Texture,
        /// Emit from both sides instead of only the front (normal) side.
        two_sided: bool,
        /// Indices into `Geometry::primitives` of the shape's primitives.
        primitives: Vec<u32>,
        /// Cumulative areas of `primitives`, last entry = total area.
        cumulative_area: Vec<f32>,
        /// Centre and radius when the shape is one sphere: sampled by its cone of directions.
        sphere: Option<(Vec3, f32)>,
        /// The shape moves: primitives and sphere are in its local frame (see `moving`).
        moving: bool,
    },
    /// A distant disk light (the sun); a delta light when `cos_max` is 1.
    Sun {
        /// Unit direction toward the sun.
        to_sun: Vec3,
        /// Irradiance on a plane facing the sun.
        irradiance: Rgb,
        /// Cosine of the angular radius.
        cos_max: f32,
    },
    /// Light arriving from infinitely far in every direction.
    Environment(Environment),
}

/// A point sampled on a light, seen from a receiver.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the receiver toward the light.
    pub wi: Vec3,
    /// Distance to the light point (infinite for distant lights).
    pub distance: f32,
    /// Radiance (or for delta lights, irradiance-like `I/d²`) arriving along `wi`.
    pub radiance: Rgb,
    /// Solid-angle density of the sample (1 for delta lights).
    pub pdf: f32,
    /// True when no other strategy can find this light.
    pub is_delta: bool,
    /// Unit geometric normal of an area light at the sampled point (zero for
    /// point lights and lights at infinity): bidirectional MIS converts the
    /// sample's density to area measure with it.
    pub normal: Vec3,
}

impl Light {
    /// Builds an area light for `shape` over its primitives in `geometry`.
    pub fn area(shape: u32, radiance: Texture, two_sided: bool, geometry: &Geometry) -> Light {
        // In the input's order, not the BVH's: which primitive a sample
        // picks must not change with the tree.
        let sources = geometry.primitive_sources();
        let mut primitives: Vec<u32> = (0..geometry.primitives().len() as u32)
            .filter(|&i| geometry.primitive_shapes()[i as usize] == shape)
            .collect();
        primitives.sort_unstable_by_key(|&i| sources[i as usize]);
        let mut total = 0.0;
        let cumulative_area = primitives
            .iter()
            .map(|&i| {
                total += geometry.primitives()[i as usize].area();
                total
            })
            .collect();
        let sphere = match primitives.as_slice() {
            &[only] => match geometry.primitives()[only as usize] {
                Primitive::Sphere { center, radius } => Some((center, radius)),
                _ => None,
            },
            _ => None,
        };
        Light::Area {
            shape,
            radiance,
            two_sided,
            primitives,
            cumulative_area,
            sphere,
            moving: false,
        }
    }

    /// An area light for moving `shape` over its local primitives `local` (`Geometry::moving_shape`).
    pub fn moving_area(shape: u32, radiance: Texture, two_sided: bool, local: &Geometry) -> Light {
        let mut light = Light::area(shape, radiance, two_sided, local);
        if let Light::Area { moving, .. } = &mut light {
            *moving = true;
        }
        light
    }

    /// The light's power (luminance) as the light pick weighs it: the flux it
    /// emits, and for a light at infinity the flux it sends onto a disk of
    /// radius `scene_radius` (the scene's bounding sphere) facing it.
    ///
    /// A sun sends πr²·E; an environment of average radiance L sends πr²·πL,
    /// the irradiance πL it gives a flat surface facing anywhere. (pbrt counts
    /// 4π²r²L, the flux into a sphere's cross-section from all directions;
    /// πL weighs an environment as a surface sees it, and BSDF and phase
    /// sampling, combined with the environment's own by MIS, already find a
    /// smooth sky well: the B4 fog layer renders with a lower error per sample
    /// with the sun asked more often, not less.)
    pub fn power(&self, scene_radius: f32) -> f32 {
        let disk = PI * scene_radius * scene_radius;
        match self {
            Light::Point { intensity, .. } => 4.0 * PI * intensity.luminance(),
            // The smoothstep falloff integrates to half the band between the cones.
            Light::Spot {
                intensity,
                cos_inner,
                cos_outer,
                edge,
                ..
            } => 2.0 * PI * intensity.luminance() * edge.cone_integral(*cos_inner, *cos_outer),
            Light::Area {
                radiance,
                two_sided,
                cumulative_area,
                ..
            } => {
                let area = cumulative_area.last().copied().unwrap_or(0.0);
                let sides = if *two_sided { 2.0 } else { 1.0 };
                PI * area * sides * radiance.average().luminance()
            }
            Light::Sun { irradiance, .. } => disk * irradiance.luminance(),
            Light::Environment(env) => disk * PI * env.average().luminance(),
        }
    }

    /// Position of a point or spot light (the lights equiangular sampling aims at).
    pub fn point_position(&self) -> Option<Vec3> {
        match self {
            Light::Point { position, .. } | Light::Spot { position, .. } => Some(*position),
            _ => None,
        }
    }

    /// The floor and the average of an environment smooth enough to leave to
    /// the sky control variate (`integrator::sky_control`) with no light
    /// samples, or why it is not: a map's peak more than [`SMOOTH_MAP_PEAK`]
    /// times its average, a floor below [`MIN_FLOOR_SHARE`] of it. `None` for other lights.
    pub fn smooth_environment(&self) -> Option<Result<(Rgb, Rgb), String>> {
        let Light::Environment(env) = self else {
            return None;
        };
        let (floor, average) = (env.floor(), env.average());
        if let Environment::Map(map) = env {
            let peak = map.peak_luminance() / average.luminance();
            if peak > SMOOTH_MAP_PEAK {
                return Some(Err(format!(
                    "the map's brightest texel is {peak:.0} times its average (at most {SMOOTH_MAP_PEAK}: a sun in a map needs its light samples)"
                )));
            }
        }
        let share = floor.luminance() / average.luminance();
        if share.is_nan() || share < MIN_FLOOR_SHARE {
            return Some(Err(format!(
                "the environment's least radiance is {share:.2} of its average (at least {MIN_FLOOR_SHARE}: too little to book)"
            )));
        }
        Some(Ok((floor, average)))
    }

    /// True for environment lights (constant, gradient sky or map).
    pub fn is_environment(&self) -> bool {
        matches!(self, Light::Environment(_))
    }

    /// True for lights at infinity that a ray escaping the scene can see.
    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::Sun { .. } | Light::Environment(_))
    }

    /// Samples a direction toward the light from receiver point `p` (a moving light at time 0).
    pub fn sample(&self, p: Vec3, u: Vec2, geometry: &Geometry) -> Option<LightSample> {
        self.sample_facing(p, None, u, geometry, 0.0)
    }

    /// Samples a direction toward the light from `p`, a surface point with unit
    /// shading normal `normal` (on the side it reflects into) or, with `None`,
    /// a point in a medium; a moving light is placed at `time`.
    ///
    /// Constant and sky environments seen from a surface are sampled
    /// cosine-weighted about the normal: uniform directions over the sphere put
    /// half of them below the surface, where a reflecting BSDF is zero.
    /// Directions behind the surface are then left to BSDF sampling alone,
    /// which `escaped_pdf_facing` (0 there) tells MIS.
    pub fn sample_facing(
        &self,
        p: Vec3,
        normal: Option<Vec3>,
        u: Vec2,
        geometry: &Geometry,
        time: f32,
    ) -> Option<LightSample> {
        match self {
            Light::Point {
                position,
                intensity,
            } => Some(sample_point(*position, *intensity, p)),
            Light::Spot {
                position,
                axis,
                intensity,
                cos_inner,
                cos_outer,
                edge,
            } => sample_spot(
                *position,
                *axis,
                *intensity,
                (*cos_inner, *cos_outer, *edge),
                p,
            ),
            Light::Area {
                moving: true,
                shape,
                ..
            } => moving::sample(self, geometry.moving_shape(*shape)?, p, u, time),
            Light::Area { .. } => self.sample_area(p, u, geometry),
            Light::Sun {
                to_sun,
                irradiance,
                cos_max,
            } => Some(sample_sun(*to_sun, *irradiance, *cos_max, u)),
            Light::Environment(Environment::Map(map)) => map.sample(u).map(|s| LightSample {
                wi: s.wi,
                distance: f32::INFINITY,
                radiance: s.radiance,
                pdf: s.pdf,
                is_delta: false,
                normal: Vec3::ZERO,
            }),
            Light::Environment(env) => sample_uniform_environment(env, normal, u),
        }
    }

    /// Samples an area light: a sphere by its cone of directions, other shapes by area.
    fn sample_area(&self, p: Vec3, u: Vec2, geometry: &Geometry) -> Option<LightSample> {
        let Light::Area {
            radiance,
            two_sided,
            primitives,
            cumulative_area,
            sphere,
            ..
        } = self
        else {
            return None;
        };
        if let Some((center, radius)) = *sphere {
            if let Some(cone) = Cone::new(p, center, radius) {
                let mut ls = cone.light_sample(u, radius, Rgb::WHITE)?;
                ls.radiance = match radiance.constant() {
                    Some(c) => c,
                    None => radiance.eval(geometry.uv(
                        primitives[0],
                        Vec2::ZERO,
                        p + ls.wi * ls.distance,
                    )),
                };
                return Some(ls);
            }
        }
        let total = *cumulative_area.last()?;
        let (k, ux) = pick_by_area(cumulative_area, primitives.len(), u.x)?;
        let prim: &Primitive = &geometry.primitives()[primitives[k] as usize];
        let a = prim.sample_area(Vec2::new(ux, u.y));
        let d = a.p - p;
        let dist2 = d.length_squared();
        let distance = dist2.sqrt();
        if distance == 0.0 {
            return None;
        }
        let wi = d / distance;
        let cos_light = a.n.dot(-wi);
        if cos_light <= 0.0 && !two_sided || cos_light == 0.0 {
            return None;
        }
        let radiance = match radiance.constant() {
            Some(c) => c,
            None => radiance.eval(geometry.uv(primitives[k], a.st, a.p)),
        };
        Some(LightSample {
            wi,
            distance,
            radiance,
            pdf: dist2 / (cos_light.abs() * total),
            is_delta: false,
            normal: a.n,
        })
    }

    /// Radiance an escaping ray with direction `dir` receives from this infinite light.
    pub fn escaped_radiance(&self, dir: Vec3) -> Rgb {
        match self {
            Light::Sun {
                to_sun,
                irradiance,
                cos_max,
            } if *cos_max < 1.0 && dir.dot(*to_sun) >= *cos_max => {
                sun_radiance(*irradiance, *cos_max)
            }
            Light::Environment(env) => env.radiance(dir),
            _ => Rgb::BLACK,
        }
    }

    /// Solid-angle density with which `sample` would pick escaping direction `dir`.
    pub fn escaped_pdf(&self, dir: Vec3) -> f32 {
        self.escaped_pdf_facing(dir, None)
    }

    /// Solid-angle density with which `sample_facing` from a receiver with
    /// `normal` would pick escaping direction `dir`.
    pub fn escaped_pdf_facing(&self, dir: Vec3, normal: Option<Vec3>) -> f32 {
        match self {
            Light::Sun {
                to_sun, cos_max, ..
            } if *cos_max < 1.0 && dir.dot(*to_sun) >= *cos_max => warp::uniform_cone_pdf(*cos_max),
            Light::Environment(Environment::Map(map)) => map.pdf(dir),
            Light::Environment(_) => match normal {
                Some(n) => n.dot(dir).max(0.0) * std::f32::consts::FRAC_1_PI,
                None => warp::uniform_sphere_pdf(),
            },
            _ => 0.0,
        }
    }

    /// Emitted radiance leaving an area light's surface toward `wo`, for
    /// normal `n`, at texture coordinates `uv()` (only called for a texture).
    pub fn area_radiance(&self, n: Vec3, wo: Vec3, uv: impl FnOnce() -> Vec2) -> Rgb {
        match self {
            Light::Area {
                radiance,
                two_sided,
                ..
            } if *two_sided || n.dot(wo) > 0.0 => match radiance.constant() {
                Some(c) => c,
                None => radiance.eval(uv()),
            },
            _ => Rgb::BLACK,
        }
    }

    /// [`Light::area_pdf`] of a light that may move, placed at `time`.
    pub fn area_pdf_at(
        &self,
        p: Vec3,
        hit_p: Vec3,
        n: Vec3,
        geometry: &Geometry,
        time: f32,
    ) -> f32 {
        match self {
            Light::Area {
                moving: true,
                shape,
                ..
            } => geometry
                .moving_shape(*shape)
                .map_or(0.0, |m| moving::area_pdf(self, m, p, hit_p, n, time)),
            _ => self.area_pdf(p, hit_p, n),
        }
    }

    /// Solid-angle density with which `sample` from `p` picks the area-light point `hit_p` with normal `n`.
    pub fn area_pdf(&self, p: Vec3, hit_p: Vec3, n: Vec3) -> f32 {
        match self {
            Light::Area {
                cumulative_area,
                sphere,
                ..
            } => {
                let cone = sphere.and_then(|(center, radius)| Cone::new(p, center, radius));
                if let Some(cone) = cone {
                    return cone.pdf();
                }
                let total = cumulative_area.last().copied().unwrap_or(0.0);
                let d = hit_p - p;
                let dist2 = d.length_squared();
                let cos_light = n.dot(d / dist2.sqrt()).abs();
                if cos_light == 0.0 || total == 0.0 {
                    0.0
                } else {
                    dist2 / (cos_light * total)
                }
            }
            _ => 0.0,
        }
    }
}

/// Radiance of a uniform sun disk that yields `irradiance` on a plane facing it.
fn sun_radiance(irradiance: Rgb, cos_max: f32) -> Rgb {
    // ∫cone L cosθ dω = L π sin²θmax.
    irradiance / (PI * (1.0 - cos_max * cos_max))
}

/// The shape of a spot light's edge between its inner and outer cones.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpotEdge {
    /// A smoothstep in the cosine (brume's default).
    #[default]
    Smooth,
    /// Linear in the angle (Mitsuba 3's `beam_width` to `cutoff_angle`).
    LinearAngle,
}

impl SpotEdge {
    /// Falloff at cosine `cos_angle` from the axis: 1 inside the inner cone, 0 outside the outer.
    pub fn falloff(self, cos_angle: f32, cos_inner: f32, cos_outer: f32) -> f32 {
        match self {
            SpotEdge::Smooth => spot_falloff(cos_angle, cos_inner, cos_outer),
            SpotEdge::LinearAngle if cos_angle >= cos_inner => 1.0,
            SpotEdge::LinearAngle if cos_angle <= cos_outer => 0.0,
            SpotEdge::LinearAngle => {
                let (inner, outer) = (cos_inner.acos(), cos_outer.acos());
                ((outer - cos_angle.acos()) / (outer - inner)).clamp(0.0, 1.0)
            }
        }
    }

    /// ∫ falloff dω / 2π over the sphere: the spot's power over 2π I.
    fn cone_integral(self, cos_inner: f32, cos_outer: f32) -> f32 {
        match self {
            // The smoothstep integrates to half the band between the cones.
            SpotEdge::Smooth => 1.0 - 0.5 * (cos_inner + cos_outer),
            // 1 − cos β + ∫β^γ (γ − θ)/(γ − β) sin θ dθ = 1 − (sin γ − sin β)/(γ − β).
            SpotEdge::LinearAngle => {
                let (b, g) = (cos_inner.acos(), cos_outer.acos());
                if g - b < 1e-6 {
                    return 1.0 - cos_outer;
                }
                1.0 - (g.sin() - b.sin()) / (g - b)
            }
        }
    }
}

/// Smooth spot falloff: 1 inside the inner cone, 0 outside the outer, smoothstep between.
fn spot_falloff(cos_angle: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    if cos_angle >= cos_inner {
        1.0
    } else if cos_angle <= cos_outer {
        0.0
    } else {
        let t = (cos_angle - cos_outer) / (cos_inner - cos_outer);
        t * t * (3.0 - 2.0 * t)
    }
}

/// A point light seen from `p`: its one direction, radiance falling as 1/d².
#[inline]
fn sample_point(position: Vec3, intensity: Rgb, p: Vec3) -> LightSample {
    let d = position - p;
    let dist2 = d.length_squared();
    let distance = dist2.sqrt();
    LightSample {
        wi: d / distance,
        distance,
        radiance: intensity / dist2,
        pdf: 1.0,
        is_delta: true,
        normal: Vec3::ZERO,
    }
}

/// A spot light seen from `p`: a point light times its cone's falloff (none outside the cone).
#[inline]
fn sample_spot(
    position: Vec3,
    axis: Vec3,
    intensity: Rgb,
    (cos_inner, cos_outer, edge): (f32, f32, SpotEdge),
    p: Vec3,
) -> Option<LightSample> {
    let d = position - p;
    let dist2 = d.length_squared();
    let distance = dist2.sqrt();
    let wi = d / distance;
    let falloff = edge.falloff(axis.dot(-wi), cos_inner, cos_outer);
    (falloff > 0.0).then(|| LightSample {
        wi,
        distance,
        radiance: intensity * (falloff / dist2),
        pdf: 1.0,
        is_delta: true,
        normal: Vec3::ZERO,
    })
}

/// The sun: its one direction when it is a point on the sky, else a uniform
/// direction in its disc's cone.
#[inline]
fn sample_sun(to_sun: Vec3, irradiance: Rgb, cos_max: f32, u: Vec2) -> LightSample {
    if cos_max >= 1.0 {
        return LightSample {
            wi: to_sun,
            distance: f32::INFINITY,
            radiance: irradiance,
            pdf: 1.0,
            is_delta: true,
            normal: Vec3::ZERO,
        };
    }
    let local = warp::square_to_uniform_cone(u, cos_max);
    LightSample {
        wi: Frame::from_z(to_sun).to_world(local).normalize(),
        distance: f32::INFINITY,
        radiance: sun_radiance(irradiance, cos_max),
        pdf: warp::uniform_cone_pdf(cos_max),
        is_delta: false,
        normal: Vec3::ZERO,
    }
}

/// A constant or sky environment: cosine-weighted about a surface's
/// `normal`, uniform over the sphere from a point in a medium.
#[inline]
fn sample_uniform_environment(
    env: &Environment,
    normal: Option<Vec3>,
    u: Vec2,
) -> Option<LightSample> {
    let (wi, pdf) = match normal {
        Some(n) => {
            let local = warp::square_to_cosine_hemisphere(u);
            let pdf = warp::cosine_hemisphere_pdf(local);
            (Frame::from_z(n).to_world(local).normalize(), pdf)
        }
        None => (
            warp::square_to_uniform_sphere(u),
            warp::uniform_sphere_pdf(),
        ),
    };
    (pdf > 0.0).then(|| LightSample {
        wi,
        distance: f32::INFINITY,
        radiance: env.radiance(wi),
        pdf,
        is_delta: false,
        normal: Vec3::ZERO,
    })
}

#[cfg(test)]
mod tests;

/// The primitive of an emissive shape picked by area from `cumulative_area`
/// (one entry per primitive, `count` of them) with `u`, and the remainder
/// of `u` inside it, reused to place the point on the primitive.
pub(crate) fn pick_by_area(cumulative_area: &[f32], count: usize, u: f32) -> Option<(usize, f32)> {
    let total = *cumulative_area.last()?;
    let target = u * total;
    let k = cumulative_area
        .partition_point(|&c| c <= target)
        .min(count - 1);
    let lo = if k == 0 { 0.0 } else { cumulative_area[k - 1] };
    let width = cumulative_area[k] - lo;
    let rest = if width > 0.0 {
        ((target - lo) / width).clamp(0.0, 1.0 - f32::EPSILON)
    } else {
        0.0
    };
    Some((k, rest))
}
