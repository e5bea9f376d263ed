//! Lights of a scene: emissive shapes' area lights, the `[[light]]`
//! entries and the pick of a light by power.

use super::description::{self, LightDesc, SceneDesc};
use super::validate::Check;
use super::{envmap, resolve};
use crate::camera::Camera;
use crate::error::Result;
use crate::geometry::Geometry;
use crate::light::{environment_share, Environment, Light, LightPick};
use crate::material::texture::Texture;
use crate::math::color::Rgb;
use crate::medium::Medium;
use std::path::Path;

/// The area lights of emissive shapes (indexed by shape) followed by the
/// `[[light]]` entries; at most one environment.
pub(super) fn build_lights(
    desc: &SceneDesc,
    check: &Check,
    base: &Path,
    geometry: &Geometry,
    emissions: Vec<Option<Texture>>,
) -> Result<(Vec<Light>, Vec<Option<u32>>)> {
    let mut lights = Vec::new();
    let mut shape_lights = vec![None; desc.shapes.len()];
    for (i, (shape, emission)) in desc.shapes.iter().zip(emissions).enumerate() {
        if let Some(radiance) = emission.filter(|e| e.max_channel() > 0.0) {
            shape_lights[i] = Some(lights.len() as u32);
            lights.push(match geometry.moving_shape(i as u32) {
                Some(m) => Light::moving_area(i as u32, radiance, shape.two_sided, m.local()),
                None => Light::area(i as u32, radiance, shape.two_sided, geometry),
            });
        }
    }
    let mut environments = 0;
    for (i, light) in desc.lights.iter().enumerate() {
        let built = build_light(light, &format!("light[{i}]"), check, base)?;
        if matches!(built, Light::Environment(_)) {
            environments += 1;
            if environments > 1 {
                return Err(check.error(
                    &format!("light[{i}]"),
                    "only one environment, sky or environment_map light is allowed",
                ));
            }
        }
        lights.push(built);
    }
    Ok((lights, shape_lights))
}

/// The lights' powers for the picks, lights at infinity weighed over the
/// scene's bounding sphere: the shapes, the camera and the point and spot lights.
pub(super) fn light_powers(lights: &[Light], geometry: &Geometry, camera: &Camera) -> Vec<f32> {
    let mut bounds = geometry.bounds().include(camera.view_at(0.0).position);
    for light in lights {
        if let Some(p) = light.point_position() {
            bounds = bounds.include(p);
        }
    }
    let radius = 0.5 * (bounds.max - bounds.min).length();
    let radius = if radius.is_finite() && radius > 0.0 {
        radius
    } else {
        1.0
    };
    lights.iter().map(|l| l.power(radius)).collect()
}

/// The index of a constant or sky environment when the scene has other lights too.
pub(super) fn smooth_sky_beside_others(lights: &[Light]) -> Option<usize> {
    let sky = lights.iter().position(|l| {
        matches!(
            l,
            Light::Environment(Environment::Constant { .. } | Environment::Sky { .. })
        )
    })?;
    (lights.len() > 1).then_some(sky)
}

/// The path tracer's next-event pick over lights of powers `power`: by
/// power, except that `sky` (from [`smooth_sky_beside_others`]) is asked
/// with probability `share` (`integrator.environment_share`), by default
/// [`environment_share`] of the powers. An image map keeps its share by
/// power (its importance sampling finds a bright sun in it; scattering
/// sampling would not).
pub(super) fn nee_pick(power: &[f32], sky: Option<usize>, share: Option<f32>) -> LightPick {
    match sky {
        Some(sky) => {
            let share = share.unwrap_or_else(|| default_sky_share(power, sky));
            LightPick::with_fixed_share(power, sky, share)
        }
        None => LightPick::new(power),
    }
}

/// The light of one `[[light]]` entry.
fn build_light(desc: &LightDesc, field: &str, check: &Check, base: &Path) -> Result<Light> {
    let f = |name: &str| format!("{field}.{name}");
    Ok(match desc {
        LightDesc::Point {
            position,
            intensity,
        } => Light::Point {
            position: check.vec3(&f("position"), *position)?,
            intensity: check.color(&f("intensity"), *intensity)?,
        },
        LightDesc::Spot {
            position,
            look_at,
            intensity,
            cone_angle,
            cone_falloff,
            cone_edge,
        } => build_spot(
            (*position, *look_at),
            *intensity,
            (*cone_angle, *cone_falloff, *cone_edge),
            field,
            check,
        )?,
        LightDesc::Sun {
            direction,
            irradiance,
            angular_radius,
        } => build_sun(*direction, *irradiance, *angular_radius, field, check)?,
        LightDesc::Environment { radiance } => Light::Environment(Environment::Constant {
            radiance: check.color(&f("radiance"), *radiance)?,
        }),
        LightDesc::EnvironmentMap {
            file,
            scale,
            rotate,
            filter,
        } => Light::Environment(Environment::Map(std::sync::Arc::new(envmap::build(
            check,
            field,
            &resolve(base, file),
            (*scale, *rotate),
            *filter,
        )?))),
        LightDesc::Sky {
            zenith,
            horizon,
            ground,
            up,
        } => Light::Environment(Environment::Sky {
            zenith: check.color(&f("zenith"), *zenith)?,
            horizon: check.color(&f("horizon"), *horizon)?,
            ground: check.color(&f("ground"), *ground)?,
            up: check.direction(&f("up"), *up)?,
        }),
    })
}

/// A spot light from its `(position, look_at)` and `(cone_angle, cone_falloff, cone_edge)` keys.
fn build_spot(
    (position, look_at): ([f32; 3], [f32; 3]),
    intensity: description::Color,
    (cone_angle, cone_falloff, edge): (f32, Option<f32>, description::SpotEdgeDesc),
    field: &str,
    check: &Check,
) -> Result<Light> {
    let f = |name: &str| format!("{field}.{name}");
    let position = check.vec3(&f("position"), position)?;
    let axis = (check.vec3(&f("look_at"), look_at)? - position)
        .try_normalize()
        .ok_or_else(|| check.error(&f("look_at"), "equals the light position"))?;
    let outer = check.range(&f("cone_angle"), cone_angle, 0.0, 180.0, false)?;
    // The default edge never exceeds a narrow cone: only a value the user wrote is checked.
    let falloff = match cone_falloff {
        Some(v) => check.range(&f("cone_falloff"), v, 0.0, outer, true)?,
        None => description::DEFAULT_CONE_FALLOFF.min(outer),
    };
    Ok(Light::Spot {
        position,
        axis,
        intensity: check.color(&f("intensity"), intensity)?,
        cos_inner: (outer - falloff).to_radians().cos(),
        cos_outer: outer.to_radians().cos(),
        edge: match edge {
            description::SpotEdgeDesc::Smooth => crate::light::SpotEdge::Smooth,
            description::SpotEdgeDesc::Linear => crate::light::SpotEdge::LinearAngle,
        },
    })
}

/// A sun light shining along `direction` from a disc of `angular_radius` degrees.
fn build_sun(
    direction: [f32; 3],
    irradiance: description::Color,
    angular_radius: f32,
    field: &str,
    check: &Check,
) -> Result<Light> {
    let f = |name: &str| format!("{field}.{name}");
    let travel = check.direction(&f("direction"), direction)?;
    let radius = check.range(&f("angular_radius"), angular_radius, 0.0, 90.0, true)?;
    Ok(Light::Sun {
        to_sun: -travel,
        irradiance: check.color(&f("irradiance"), irradiance)?,
        cos_max: radius.to_radians().cos(),
    })
}

/// `integrator.sky_control`: the constant U′ the path tracer books where it
/// takes the environment as a control variate (`integrator::sky_control`;
/// the path tracer then never light-samples that light, and an escape along
/// ω meets L(ω) − U′). The environment must be smooth
/// ([`Light::smooth_environment`]: a constant, a gradient sky, or a map
/// without a sun in it; a scene has one at most). Automatic: on for the
/// path tracer with such an environment and a medium (where roulette's
/// variance in the sky light it carries is the control variate's gain),
/// with U′ its floor (the least radiance of any direction, per channel: U
/// for a constant sky) when the light samples leave the sky out anyway (a
/// sun brighter than it: [`environment_share`] of the powers `power` is 0),
/// and U′ the least of the floor and R(a)·(its average) where they would
/// ask it (a sky alone or brighter), R(a) the light a deep medium of the
/// media's least albedo a returns under a uniform sky
/// ([`sky_share_returned`]): the light a walk meets there. Booking at most
/// the floor keeps every escape's L(ω) − U′ at or above 0. Off without a
/// medium, for albedo grids or media that scatter nothing under a
/// light-sampled sky, where a key asks for the environment's own sampling
/// (guiding, `environment_share`) or where a light slab has baked the sky
/// into its light.
pub(super) fn sky_control(
    desc: &SceneDesc,
    check: &Check,
    (lights, power): (&[Light], &[f32]),
    media: &[Medium],
    has_slabs: bool,
) -> Result<Option<Rgb>> {
    const KEY: &str = "integrator.sky_control";
    let integrator = &desc.integrator;
    let environment = lights.iter().find_map(Light::smooth_environment);
    let smooth = environment.as_ref().and_then(|e| e.as_ref().ok().copied());
    let refusal = sky_control_refusal(desc, environment, has_slabs);
    let booked = smooth.and_then(|(floor, average)| match sky_light_sampled(lights, power) {
        false => Some(floor),
        true => sky_share_returned(media).map(|share| floor.min_per_channel(average * share)),
    });
    Ok(match integrator.sky_control {
        Some(true) => match refusal {
            Some(message) => return Err(check.error(KEY, message)),
            None => booked.or(smooth.map(|(floor, _)| floor)),
        },
        Some(false) => None,
        None if refusal.is_some() || media.is_empty() => None,
        None if integrator.environment_share.is_some() => None,
        None => booked,
    })
}

/// Why the sky control variate cannot be used in this scene, if it cannot
/// (`environment`: what [`Light::smooth_environment`] says of its environment).
fn sky_control_refusal(
    desc: &SceneDesc,
    environment: Option<std::result::Result<(Rgb, Rgb), String>>,
    has_slabs: bool,
) -> Option<String> {
    let integrator = &desc.integrator;
    if integrator.kind != "path" {
        Some(format!(
            "needs type = \"path\": type = \"{}\" samples the environment in its own strategies",
            integrator.kind
        ))
    } else if integrator.guiding {
        Some("cannot be used with integrator.guiding: the guide learns the sky light the control variate takes out".into())
    } else if has_slabs {
        Some("cannot be used with a light slab or a [slab] bake: a slab's light holds the environment's".into())
    } else {
        match environment {
            None => Some("needs an environment light ([[light]] type = \"environment\", \"sky\" or \"environment_map\")".into()),
            Some(Err(why)) => Some(format!("needs a smooth environment: {why}")),
            Some(Ok(_)) => None,
        }
    }
}

/// R(a) = (1 − s) / (1 + s), s = √(1 − a), per channel, of the media's
/// least albedo a: the share of a uniform sky's light a deep medium of
/// albedo a returns (the two-stream similarity solution of a semi-infinite
/// medium), the light a walk in it meets on average. `None` without media,
/// for an albedo grid (not known everywhere) or for media that scatter
/// nothing (no share to book: the sky keeps its light samples). Measured
/// against other constants under a sky alone (BENCHMARKS.md, "The sky as a
/// control variate under a light-sampled sky"): the smoke of albedo 0.9
/// best near 0.3–0.5 of the sky (R = 0.52), the cloud of 0.99 near 0.9
/// (R = 0.82).
fn sky_share_returned(media: &[Medium]) -> Option<Rgb> {
    let mut least = Rgb::WHITE;
    for medium in media {
        let a = medium.constant_albedo()?;
        least = least.min_per_channel(a);
    }
    let returned = |a: f32| {
        let s = (1.0 - a.clamp(0.0, 1.0)).sqrt();
        (1.0 - s) / (1.0 + s)
    };
    (!media.is_empty())
        .then(|| least.map(returned))
        .filter(|share| share.max_channel() > 0.0)
}

/// Whether the path tracer's light samples would ask the sky by default: a
/// sky alone always, beside other lights by [`environment_share`] of the powers.
fn sky_light_sampled(lights: &[Light], power: &[f32]) -> bool {
    let Some(sky) = smooth_sky_beside_others(lights) else {
        return true;
    };
    default_sky_share(power, sky) > 0.0
}

/// The share of light samples the sky at index `sky` gets by default:
/// [`environment_share`] of its power and the other lights'.
fn default_sky_share(power: &[f32], sky: usize) -> f32 {
    let rest: f32 = (0..power.len())
        .filter(|&i| i != sky)
        .map(|i| power[i])
        .sum();
    environment_share(power[sky], rest)
}
