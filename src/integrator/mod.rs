//! The radiance estimator `li` and the runtime `Scene` it reads.
//!
//! One loop handles every vertex of a path. Along each ray segment the
//! media are tracked first (free-flight sampling); a real scattering event
//! makes a medium vertex, otherwise the ray reaches a surface (or escapes).
//! Both kinds of vertex do next-event estimation with transmittance-weighted
//! shadow rays, combined by MIS with phase/BSDF sampling.

pub mod adaptive_settings;
pub mod aov;
pub mod bdpt;
mod direct;
mod equiangular;
pub mod estimator;
mod forced;
pub mod guiding;
pub mod interfaces;
pub mod mlt;
pub mod sky_control;
pub mod slab_record;
pub mod sppm;
pub mod sun_lobe;
pub mod tracking;

use crate::camera::Camera;
use crate::geometry::{Geometry, SurfaceHit};
use crate::light::{Light, LightPick};
use crate::material::texture::Texture;
use crate::material::{Material, Shading};
use crate::math::color::Rgb;
use crate::math::{offset_origin, Ray, Vec3};
use crate::medium::{Medium, MediumProperties};
use crate::sampling::{power_heuristic, PixelStreams, Sampler, SamplerKind};
use direct::{direct_light, direct_light_mixed, Vertex};
use guiding::{Guide, PathLog};
pub use tracking::TransmittanceEstimator;
use tracking::{sample_free_flight, FreeFlight};

/// Which estimator renders the image (`[integrator] type`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum IntegratorKind {
    /// The volumetric path tracer [`li`].
    #[default]
    Path,
    /// Bidirectional path tracing ([`bdpt`]).
    Bdpt,
    /// Stochastic progressive photon mapping ([`sppm`]).
    Sppm,
    /// Metropolis light transport over the bidirectional strategies ([`mlt`]).
    Mlt(mlt::MltSettings),
}

/// Sampling settings of a render.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// The estimator.
    pub integrator: IntegratorKind,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum number of scattering events on a path (0 = emission only, 1 = direct light).
    pub max_depth: u32,
    /// Maximum number of medium scattering events on a path.
    pub max_scatter_depth: u32,
    /// Depth from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Scene seed of the random streams.
    pub seed: u64,
    /// Transmittance estimator for shadow rays.
    pub transmittance: TransmittanceEstimator,
    /// Add equiangular sampling toward point and spot lights along rays in media.
    pub equiangular: bool,
    /// Sample lights from a point drawn over each medium segment (module `forced`),
    /// not from the free flight's collision.
    pub forced_scattering: bool,
    /// Where the sky is a control variate, book its change at a diffuse
    /// surface a segment aims at ahead, by its expectation (module
    /// [`sky_control`]); on by default, off only to compare.
    pub sky_ahead: bool,
    /// Sun-lobe sampling of the first medium scatterings (module [`sun_lobe`]);
    /// `None` without a sun or with `integrator.sun_lobe = 0`.
    pub sun_lobe: Option<sun_lobe::SunLobe>,
    /// Camera shutter `[open, close]` in frames relative to the frame's time
    /// (`None`: every ray at time 0, the instant of the frame).
    pub shutter: Option<[f32; 2]>,
    /// How pixel samples draw their random numbers.
    pub sampler: SamplerKind,
    /// Photon counts and radii of `integrator = sppm` (unused by the others).
    pub sppm: sppm::SppmSettings,
    /// Adaptive sampling and the noise target (`integrator.adaptive`, `integrator.noise`).
    pub adaptive: adaptive_settings::AdaptiveSettings,
    /// Path guiding of the path tracer (`integrator.guiding`, module [`guiding`]).
    pub guiding: bool,
}

impl Settings {
    /// The time of a camera sample whose time dimension is `u` ∈ [0, 1): uniform over the shutter.
    #[inline]
    pub fn sample_time(&self, u: f32) -> f32 {
        match self.shutter {
            Some([open, close]) => open + (close - open) * u,
            None => 0.0,
        }
    }

    /// The random streams of pixel `(x, y)`: this scene's sampler and seed.
    pub fn pixel_streams(&self, x: u32, y: u32) -> PixelStreams {
        PixelStreams::new(self.sampler, self.seed, x, y)
    }
}

/// Everything the estimator needs, built by `scene::load`.
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// All primitives and the BVH.
    pub geometry: Geometry,
    /// Material of each shape.
    pub shape_materials: Vec<Material>,
    /// Texture of each shape's material colour (albedo, reflectance or f0), replacing its constant.
    pub shape_textures: Vec<Option<Texture>>,
    /// Index into `lights` of each shape's area light, if it emits.
    pub shape_lights: Vec<Option<u32>>,
    /// All lights.
    pub lights: Vec<Light>,
    /// How bidirectional strategies (bdpt, mlt, sppm's photons) pick one of `lights`: by power (`light::LightPick`).
    pub light_pick: LightPick,
    /// How the path tracer's next-event estimation picks one of `lights`: as
    /// `light_pick`, with a smooth sky beside other lights asked less
    /// (`light::environment_share`); every MIS weight of the path tracer uses it.
    pub nee_pick: LightPick,
    /// All participating media (they overlap additively, unless `interfaces` says which one a ray is in).
    pub media: Vec<Medium>,
    /// Mitsuba's rule for the medium a ray is in (imported scenes that need it; `None`: containment).
    pub interfaces: Option<interfaces::Interfaces>,
    /// Sampling settings.
    pub settings: Settings,
    /// AOVs to write beside the beauty (`[film] aovs`).
    pub aovs: Vec<aov::Aov>,
    /// The constant U′ the path tracer books where it takes the (smooth)
    /// environment as a control variate (module [`sky_control`]; the path
    /// tracer then never light-samples it, and an escape along ω meets L(ω) − U′).
    pub sky_control: Option<Rgb>,
}

impl Scene {
    /// Probability that the path tracer's next-event estimation picks light `index`.
    #[inline]
    fn light_pick_probability(&self, index: usize) -> f32 {
        self.nee_pick.pmf(index)
    }

    /// The material at `hit`: the shape's, its colour looked up in the shape's texture.
    #[inline]
    pub fn material_at(&self, hit: &SurfaceHit) -> Material {
        let material = self.shape_materials[hit.shape as usize];
        match &self.shape_textures[hit.shape as usize] {
            None => material,
            Some(t) => material.with_color(t.eval(self.geometry.uv(hit.primitive, hit.st, hit.p))),
        }
    }

    /// Radiance from infinite lights for a ray escaping along `dir`, MIS-weighted
    /// against light sampling from the vertex it left (a surface one with `prev_normal`).
    fn escaped(
        &self,
        dir: Vec3,
        prev_pdf: f32,
        prev_delta: bool,
        prev_normal: Option<Vec3>,
    ) -> Rgb {
        let mut total = Rgb::BLACK;
        for (index, light) in self.lights.iter().enumerate() {
            if !light.is_infinite() {
                continue;
            }
            if let Some(booked) = self.booked_sky(light) {
                // The path books U′ as it goes (module `sky_control`); never
                // light-sampled, the rest of the sky comes by escapes alone.
                total += light.escaped_radiance(dir) - booked;
                continue;
            }
            let le = light.escaped_radiance(dir);
            if le.is_black() {
                continue;
            }
            let weight = if prev_delta {
                1.0
            } else {
                let light_pdf =
                    light.escaped_pdf_facing(dir, prev_normal) * self.light_pick_probability(index);
                power_heuristic(prev_pdf, light_pdf)
            };
            total += le * weight;
        }
        total
    }

    /// The constant U′ the path tracer books for `light` where it leaves that
    /// light to the sky control variate (module [`sky_control`]).
    #[inline]
    fn booked_sky(&self, light: &Light) -> Option<Rgb> {
        self.sky_control.filter(|_| light.is_environment())
    }

    /// Whether the path tracer leaves `light` to the sky control variate (module [`sky_control`]).
    #[inline]
    pub(crate) fn sky_controls(&self, light: &Light) -> bool {
        self.booked_sky(light).is_some()
    }

    /// Transmittance along `ray` over `[0, t_max)` through every medium (1 with no media).
    pub fn transmittance(&self, ray: &Ray, t_max: f32, sampler: &mut Sampler) -> Rgb {
        let mut tr = Rgb::WHITE;
        for medium in &self.media {
            tr *= tracking::medium_transmittance(
                medium,
                ray,
                t_max,
                self.settings.transmittance,
                sampler,
            );
            if tr.is_black() {
                break;
            }
        }
        tr
    }
}

/// State of one path being traced.
struct PathState<'g> {
    /// The ray of the current segment.
    ray: Ray,
    throughput: Rgb,
    radiance: Rgb,
    /// Solid-angle pdf of the direction that produced the current ray.
    prev_pdf: f32,
    /// True when that direction came from a delta lobe (or the camera).
    prev_delta: bool,
    /// Where the current ray started (for area-light MIS).
    prev_point: Vec3,
    /// The normal light sampling used there when it was a surface vertex (for environment MIS).
    prev_normal: Option<Vec3>,
    /// Scattering events so far (surface and medium).
    depth: u32,
    /// Medium scattering events so far.
    scatter_depth: u32,
    /// The current ray leaves the last scattering event the depth limits allow:
    /// it only gathers the emission it meets (surfaces, media, lights at
    /// infinity), MIS-weighted against that vertex's light sampling, then stops.
    emission_only: bool,
    /// The far end of the first segment when it is bounded (a slab bake's
    /// line leaving a box): past it the ray gathers nothing.
    first_segment_end: Option<f32>,
    /// The learned guide to sample from (`[integrator] guiding`), if any.
    guide: Option<&'g Guide>,
    /// A training path's log of guided vertices, if it trains the guide.
    log: Option<&'g mut PathLog>,
    /// The medium the current ray is in, under the interface rule (unused by containment).
    medium: Option<u32>,
    /// The sky light booked so far, where the sky is a control variate (module [`sky_control`]).
    sky: Option<sky_control::SkyBook>,
}

/// Whether a path goes on after a step.
enum Step {
    Continue,
    Stop,
}

/// Estimates the radiance arriving at the ray origin along `-ray.direction`.
///
/// Every scattering vertex, the last one included, samples a light (NEE) and
/// a continuation direction, combined by MIS; after the last vertex the
/// continuation segment is traced for emission only. So `max_depth = 1` is
/// exactly direct lighting, including light that NEE cannot sample (delta
/// BSDFs, emissive media).
pub fn li(scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Rgb {
    li_gathering(scene, ray, sampler, &mut NoGather, None)
}

/// [`li`] for the light leaving a box along `-ray.direction`, from inside
/// it only: the first segment ends at `t_end` (where `ray` leaves the box),
/// so what lies behind the box along the line adds nothing. Scattered paths
/// are traced as usual, through and beyond the box.
pub fn li_from_inside(scene: &Scene, ray: Ray, t_end: f32, sampler: &mut Sampler) -> Rgb {
    li_gathering(scene, ray, sampler, &mut NoGather, Some(t_end))
}

/// What a photon-mapping eye path asks of [`li`]: told of every segment and
/// non-Dirac surface vertex before the first non-Dirac scattering event, it
/// adds the indirect light there; [`li`] then stops scattering after that
/// event (its direct light and the emission it meets are still gathered).
pub(crate) trait Gather {
    /// False for the plain path tracer: no calls, no early stop.
    const ACTIVE: bool;
    /// `ray` crosses the media over `[0, t_surface)` with `throughput`, after `depth` scattering events.
    fn segment(
        &mut self,
        scene: &Scene,
        ray: &Ray,
        t_surface: f32,
        throughput: Rgb,
        depth: u32,
        sampler: &mut Sampler,
    );
    /// A surface vertex with a non-Dirac BSDF, reached after `depth` scattering events.
    fn surface(
        &mut self,
        scene: &Scene,
        hit: &SurfaceHit,
        material: &Material,
        wo: Vec3,
        throughput: Rgb,
        depth: u32,
    );
}

/// The path tracer's [`Gather`]: nothing.
struct NoGather;

impl Gather for NoGather {
    const ACTIVE: bool = false;
    fn segment(&mut self, _: &Scene, _: &Ray, _: f32, _: Rgb, _: u32, _: &mut Sampler) {}
    fn surface(&mut self, _: &Scene, _: &SurfaceHit, _: &Material, _: Vec3, _: Rgb, _: u32) {}
}

/// [`li`] with `gather` told of the path's vertices up to its first non-Dirac scattering event.
pub(crate) fn li_gathering<G: Gather>(
    scene: &Scene,
    ray: Ray,
    sampler: &mut Sampler,
    gather: &mut G,
    first_segment_end: Option<f32>,
) -> Rgb {
    let mut path = PathState::new(scene, ray, (first_segment_end, G::ACTIVE), None, None);
    while let Step::Continue = trace_segment(scene, &mut path, sampler, gather) {}
    path.radiance
}

/// [`li`] sampling from `guide` (module [`guiding`]), noting its guided vertices in `log`.
pub(crate) fn li_path(
    scene: &Scene,
    ray: Ray,
    sampler: &mut Sampler,
    guide: Option<&Guide>,
    log: Option<&mut PathLog>,
) -> Rgb {
    let mut path = PathState::new(scene, ray, (None, false), guide, log);
    while let Step::Continue = trace_segment(scene, &mut path, sampler, &mut NoGather) {}
    path.radiance
}

impl<'g> PathState<'g> {
    /// A path starting along `ray` from the camera (or a slab's line).
    fn new(
        scene: &Scene,
        ray: Ray,
        (first_segment_end, gathering): (Option<f32>, bool),
        guide: Option<&'g Guide>,
        log: Option<&'g mut PathLog>,
    ) -> PathState<'g> {
        // A slab's bounded line asks for the light from inside its box only, and
        // photon mapping's eye paths pair with photons of the sky: no control there.
        let sky = scene
            .sky_control
            .filter(|_| first_segment_end.is_none() && !gathering);
        PathState {
            ray,
            throughput: Rgb::WHITE,
            // The sky light U the path books at its start (module `sky_control`).
            radiance: sky.unwrap_or(Rgb::BLACK),
            prev_pdf: 1.0,
            prev_delta: true,
            prev_point: ray.origin,
            prev_normal: None,
            depth: 0,
            scatter_depth: 0,
            emission_only: scene.settings.max_depth == 0 || scene.settings.max_scatter_depth == 0,
            first_segment_end,
            guide,
            log,
            medium: scene.interfaces.as_ref().and_then(|i| i.camera),
            sky: sky.map(sky_control::SkyBook::start),
        }
    }

    /// Books the throughput's changes since the last booking into the sky light (module [`sky_control`]).
    #[inline]
    fn book_sky(&mut self) {
        if let Some(book) = &mut self.sky {
            self.radiance += book.book(self.throughput);
        }
    }

    /// Ends the path at a vertex (not by escaping, not by roulette): `Step::Stop`,
    /// with the sky light it will never gather taken back (module [`sky_control`]).
    #[inline]
    fn end_at_vertex(&mut self) -> Step {
        if let Some(book) = &mut self.sky {
            self.radiance += book.end(self.throughput);
        }
        Step::Stop
    }

    /// Notes the vertex at `p` about to be left along `dir`, drawn with density
    /// `pdf`, its weight already in the throughput (training only). Before
    /// roulette: what comes back is then an unbiased estimate of the radiance along `dir`.
    #[inline]
    fn log_vertex(&mut self, p: Vec3, dir: Vec3, pdf: f32) {
        if let Some(log) = self.log.as_deref_mut() {
            log.push(p, dir, pdf, self.throughput, self.radiance);
        }
    }
}

/// Follows the path's current ray to its next vertex, adding what it gathers on the way.
fn trace_segment<G: Gather>(
    scene: &Scene,
    path: &mut PathState,
    sampler: &mut Sampler,
    gather: &mut G,
) -> Step {
    let t_end = path.first_segment_end.take().unwrap_or(f32::INFINITY);
    let hit = scene.geometry.intersect(&path.ray, t_end);
    let t_surface = hit.map_or(t_end, |h| h.t);
    if let Some(crossing) = scene.geometry.slab_crossing(&path.ray, t_surface) {
        return slab_segment(scene, path, &crossing, sampler);
    }
    let media = scene.media_along(path.medium);
    if !media.is_empty() {
        if let Some(hit) = &hit {
            book_surface_ahead(scene, media, path, hit);
        }
        if G::ACTIVE && !path.emission_only {
            gather.segment(
                scene,
                &path.ray,
                t_surface,
                path.throughput,
                path.depth,
                sampler,
            );
        }
        if let Some(step) = medium_segment(scene, media, path, t_surface, (sampler, G::ACTIVE)) {
            return step;
        }
    }
    let Some(hit) = hit else {
        return escape(scene, path, t_end);
    };
    if let Some(book) = &mut path.sky {
        path.radiance += book.arrived(path.throughput);
    }
    add_surface_emission(scene, path, &hit);
    if let Some(interfaces) = scene.interfaces.as_ref().filter(|i| i.is_null(hit.shape)) {
        return pass_through(interfaces, path, &hit);
    }
    if let Material::ThinDielectric { ior } = scene.shape_materials[hit.shape as usize] {
        return thin_sheet(scene, path, &hit, ior, sampler);
    }
    if path.emission_only {
        return path.end_at_vertex();
    }
    surface_vertex(scene, path, &hit, sampler, gather)
}

/// A segment that meets no surface before `t_end`: the light of the
/// infinite lights along an escaping ray, or nothing past a bounded first
/// segment's end (what lies beyond it is not asked for).
fn escape(scene: &Scene, path: &mut PathState, t_end: f32) -> Step {
    if t_end.is_finite() {
        return Step::Stop;
    }
    let escaped = scene.escaped(
        path.ray.direction,
        path.prev_pdf,
        path.prev_delta,
        path.prev_normal,
    );
    path.radiance += path.throughput * escaped;
    path.book_sky();
    Step::Stop
}

/// Books ahead, by its expectation, the sky light's change at the diffuse
/// surface `hit` the path's segment aims at through media of closed-form
/// transmittance T (module [`sky_control`]). A path gets there with
/// throughput β_arrive, E[β_arrive·1(reached)] = β·T for any unbiased
/// tracking, and the surface then scales it by ρ on average (any unbiased
/// sampling of a Lambertian BSDF); so its booking there, β_arrive·(ρ − 1)·U′
/// if reached, is replaced by T·β·(ρ − 1)·U′ made whether or not the flight
/// gets there. The coin of reaching the ground no longer carries the sky's
/// deficit (the airlight fog: variance 0.73×). Grid media would need a
/// tracked estimate of T per segment: it costs more than it saves there.
#[inline]
fn book_surface_ahead(scene: &Scene, media: &[Medium], path: &mut PathState, hit: &SurfaceHit) {
    let Some(book) = &mut path.sky else {
        return;
    };
    if path.emission_only || scene.interfaces.is_some() || !scene.settings.sky_ahead {
        return;
    }
    let mut depth = Rgb::BLACK;
    for medium in media {
        let Some(tau) = medium.optical_depth(&path.ray, 0.0, hit.t) else {
            return;
        };
        depth += tau;
    }
    let Material::Diffuse { albedo } = scene.material_at(hit) else {
        return;
    };
    path.radiance += book.ahead(path.throughput, depth.exp_neg(), albedo);
}

/// A thin dielectric sheet: reflection (probability R) is a scattering
/// event; the straight transmission (1 − R) is not, as Mitsuba's volpath
/// counts it (an index-matched event): the ray goes on unbent past any
/// depth limit, in the medium on the side it enters. Both lobes are Dirac
/// with weight 1 (f = R or 1 − R, drawn with that probability), so the
/// light the ray meets next is taken unweighted: next-event estimation's
/// shadow rays stop at the sheet.
fn thin_sheet(
    scene: &Scene,
    path: &mut PathState,
    hit: &SurfaceHit,
    ior: f32,
    sampler: &mut Sampler,
) -> Step {
    let wo = -path.ray.direction;
    let shading = Shading::facing(hit.shading_normal, wo);
    let (wi, reflectance, reflects) =
        crate::material::layered::thin_lobe(ior, &shading, wo, sampler.next_1d());
    if reflects && path.emission_only {
        return path.end_at_vertex();
    }
    if let Some(interfaces) = &scene.interfaces {
        path.medium = interfaces.after(hit.shape, hit.geometric_normal, wi, path.medium);
    }
    let ray = path
        .ray
        .spawn(offset_origin(hit.p, hit.geometric_normal, wi), wi);
    path.prev_normal = Some(shading.n);
    if !reflects {
        path.prev_delta = true;
        path.ray = ray;
        return Step::Continue;
    }
    continue_path(scene, path, ray, (reflectance, true, false), hit.p, sampler)
}

/// A ray crossing a surfaceless shape under the interface rule: it goes on
/// unchanged, in the medium on the side it enters (not a scattering event).
fn pass_through(
    interfaces: &interfaces::Interfaces,
    path: &mut PathState,
    hit: &SurfaceHit,
) -> Step {
    let dir = path.ray.direction;
    path.medium = interfaces.after(hit.shape, hit.geometric_normal, dir, path.medium);
    path.ray = path
        .ray
        .spawn(offset_origin(hit.p, hit.geometric_normal, dir), dir);
    Step::Continue
}

/// A ray entering a baked slab: the media up to the box, then the slab's
/// recorded light over the transmittance-weighted rest, which the ray goes
/// on to meet from the far side of the box. The box hides what the scene
/// has inside it; the path's MIS state stays that of the ray's origin (the
/// line is the same).
fn slab_segment(
    scene: &Scene,
    path: &mut PathState,
    crossing: &crate::geometry::slab::lookup::SlabCrossing,
    sampler: &mut Sampler,
) -> Step {
    let media = scene.media_along(path.medium);
    if !media.is_empty() {
        if let Some(step) = medium_segment(scene, media, path, crossing.t_enter, (sampler, false)) {
            return step;
        }
    }
    path.radiance += path.throughput * crossing.radiance;
    path.throughput *= crossing.transmittance;
    if path.throughput.is_black() {
        return Step::Stop;
    }
    path.ray = path
        .ray
        .spawn(path.ray.at(crossing.t_exit), path.ray.direction);
    Step::Continue
}

/// Free flight through the media up to `t_surface`, with equiangular sampling
/// toward point lights; `None` when the ray reaches the surface (or escapes).
/// With `last_event`, a medium event is the path's last scattering event.
fn medium_segment(
    scene: &Scene,
    media: &[Medium],
    path: &mut PathState,
    t_surface: f32,
    (sampler, last_event): (&mut Sampler, bool),
) -> Option<Step> {
    // An equiangular sample is one more scattering event: not past the last one.
    let segment = if path.emission_only {
        None
    } else {
        equiangular::segment(scene, &path.ray, t_surface)
    };
    if let Some(segment) = &segment {
        path.radiance += path.throughput * equiangular::estimate(scene, segment, sampler);
    }
    let forced = forced_in_scattering(
        scene,
        media,
        path,
        t_surface,
        segment.is_some() || last_event,
        sampler,
    );
    if let Some(light) = forced {
        path.radiance += path.throughput * light;
    }
    let event = sample_free_flight(
        media,
        &path.ray,
        t_surface,
        &mut path.throughput,
        &mut path.radiance,
        sampler,
    );
    if !matches!(event, FreeFlight::Passed) {
        if let Some(book) = &mut path.sky {
            book.missed();
        }
    }
    match event {
        FreeFlight::Absorbed => Some(path.end_at_vertex()),
        FreeFlight::Passed => None,
        FreeFlight::Scatter { .. } if path.emission_only => Some(path.end_at_vertex()),
        FreeFlight::Scatter { t, properties, .. } => Some(scatter_in_segment(
            scene,
            path,
            (t, &properties),
            (segment.as_ref(), forced.is_some()),
            (last_event, sampler),
        )),
    }
}

/// The segment's light sampled from a forced point (module [`forced`]), where
/// that strategy applies: one medium on the ray, no equiangular segment or
/// photon gathering (`excluded`), no guide, no interface rule.
fn forced_in_scattering(
    scene: &Scene,
    media: &[Medium],
    path: &PathState,
    t_surface: f32,
    excluded: bool,
    sampler: &mut Sampler,
) -> Option<Rgb> {
    let [medium] = media else {
        return None;
    };
    if !scene.settings.forced_scattering
        || excluded
        || path.emission_only
        || path.guide.is_some()
        || path.log.is_some()
        || scene.interfaces.is_some()
    {
        return None;
    }
    forced::estimate(
        scene,
        medium,
        &path.ray,
        t_surface,
        (path.ray.time, path.medium),
        sampler,
    )
}

/// A real collision at `t` of the path's segment: next-event estimation,
/// then the next direction from the phase function (or its mixture with the
/// guide) and the path carried on.
fn scatter_in_segment(
    scene: &Scene,
    path: &mut PathState,
    (t, properties): (f32, &MediumProperties),
    (segment, forced): (Option<&equiangular::Segment>, bool),
    (last_event, sampler): (bool, &mut Sampler),
) -> Step {
    let p = path.ray.at(t);
    path.scatter_depth += 1;
    let tree = guiding::tree_at(path.guide, p, path.depth);
    let vertex = Vertex::Medium {
        p,
        dir_in: path.ray.direction,
        phase: &properties.phase,
        equiangular: segment.map(|s| (s, t)),
    };
    let phase = &properties.phase;
    let mixture = match (
        tree,
        sun_lobe_at(scene, path, phase, (tree.is_some(), forced)),
    ) {
        (Some(tree), _) => MediumMixture::Guide(tree, guiding::phase_fraction(phase)),
        (None, Some(lobe)) => MediumMixture::SunLobe(lobe),
        (None, None) => MediumMixture::Phase,
    };
    // Forced in-scattering sampled this segment's light already (module `forced`).
    if !forced {
        let at = (path.ray.time, path.medium);
        path.radiance += path.throughput
            * direct_light_mixed(scene, &vertex, at, sampler, |d, pdf| {
                mixture.pdf(phase, d, pdf)
            });
    }
    let Some((dir, weight, pdf)) = mixture.sample(phase, path.ray.direction, sampler) else {
        return path.end_at_vertex();
    };
    path.throughput *= weight;
    path.prev_normal = None;
    path.log_vertex(p, dir, pdf);
    continue_path(
        scene,
        path,
        path.ray.spawn(p, dir),
        (pdf, false, last_event),
        p,
        sampler,
    )
}

/// The sun lobe a medium vertex of `path` mixes into its continuation, if
/// any: none where the vertex samples from a guide's mixture or its segment
/// was forced (whose light sample weighs against the phase density alone),
/// nor on a training path (its log records the guide's own densities).
#[inline]
fn sun_lobe_at(
    scene: &Scene,
    path: &PathState,
    phase: &crate::medium::PhaseFunction,
    (guided, forced): (bool, bool),
) -> Option<sun_lobe::SunLobe> {
    if guided || forced || path.log.is_some() {
        return None;
    }
    scene
        .settings
        .sun_lobe
        .filter(|l| l.applies(phase, path.scatter_depth))
}

/// Next-event estimation at `vertex`, MIS-weighted against the mixture with
/// the guide's tree (with share α) where the vertex samples from one.
#[inline]
fn vertex_direct_light(
    scene: &Scene,
    path: &PathState,
    vertex: &Vertex,
    mixed: Option<(&guiding::dtree::DTree, f32)>,
    sampler: &mut Sampler,
) -> Rgb {
    match mixed {
        None => direct_light(scene, vertex, (path.ray.time, path.medium), sampler),
        Some((tree, alpha)) => direct_light_mixed(
            scene,
            vertex,
            (path.ray.time, path.medium),
            sampler,
            |d, pdf| guiding::mixture_pdf(tree, alpha, d, pdf),
        ),
    }
}

/// The density a medium collision draws its continuation from: the phase
/// function alone, or its mixture with the guide's tree (share α) or with
/// the sun's lobe. Next-event estimation weighs against the same density.
#[derive(Clone, Copy)]
enum MediumMixture<'a> {
    /// The phase function alone.
    Phase,
    /// The guide's tree with share α.
    Guide(&'a guiding::dtree::DTree, f32),
    /// The lobe toward the sun (module [`sun_lobe`]).
    SunLobe(sun_lobe::SunLobe),
}

impl MediumMixture<'_> {
    /// The mixture's density at `d`, given the phase function's `phase_pdf` there.
    #[inline]
    fn pdf(&self, phase: &crate::medium::PhaseFunction, d: Vec3, phase_pdf: f32) -> f32 {
        match *self {
            MediumMixture::Phase => phase_pdf,
            MediumMixture::Guide(tree, alpha) => guiding::mixture_pdf(tree, alpha, d, phase_pdf),
            MediumMixture::SunLobe(lobe) => lobe.mixture_pdf(phase, d, phase_pdf),
        }
    }

    /// A continuation for a path arriving along `dir_in`: direction, weight
    /// and density. `None` ends the path.
    #[inline]
    fn sample(
        &self,
        phase: &crate::medium::PhaseFunction,
        dir_in: Vec3,
        sampler: &mut Sampler,
    ) -> Option<(Vec3, Rgb, f32)> {
        match *self {
            MediumMixture::Phase => {
                let ps = phase.sample(dir_in, sampler.next_2d())?;
                Some((ps.direction, Rgb::splat(ps.weight), ps.pdf))
            }
            MediumMixture::Guide(tree, _) => {
                let u_sel = sampler.next_1d();
                let ms = guiding::sample_phase(tree, phase, dir_in, u_sel, sampler.next_2d())?;
                Some((ms.dir, ms.weight, ms.pdf))
            }
            MediumMixture::SunLobe(lobe) => lobe.sample(phase, dir_in, sampler),
        }
    }
}

/// Emission of an area light the ray hit, MIS-weighted against light sampling.
fn add_surface_emission(scene: &Scene, path: &mut PathState, hit: &SurfaceHit) {
    let Some(light_index) = scene.shape_lights[hit.shape as usize] else {
        return;
    };
    let light = &scene.lights[light_index as usize];
    let le = light.area_radiance(hit.geometric_normal, -path.ray.direction, || {
        scene.geometry.uv(hit.primitive, hit.st, hit.p)
    });
    if le.is_black() {
        return;
    }
    let weight = if path.prev_delta {
        1.0
    } else {
        let light_pdf = light.area_pdf_at(
            path.prev_point,
            hit.p,
            hit.geometric_normal,
            &scene.geometry,
            path.ray.time,
        ) * scene.light_pick_probability(light_index as usize);
        power_heuristic(path.prev_pdf, light_pdf)
    };
    path.radiance += path.throughput * le * weight;
}

/// A surface scattering vertex: light sampling, then a BSDF-sampled continuation.
fn surface_vertex<G: Gather>(
    scene: &Scene,
    path: &mut PathState,
    hit: &SurfaceHit,
    sampler: &mut Sampler,
    gather: &mut G,
) -> Step {
    let wo = -path.ray.direction;
    let material = &scene.material_at(hit);
    let shading = Shading::facing(hit.shading_normal, wo);
    let mut tree = None;
    if !material.is_delta() {
        if G::ACTIVE {
            gather.surface(scene, hit, material, wo, path.throughput, path.depth);
        }
        tree = guiding::tree_at(path.guide, hit.p, path.depth);
        let vertex = Vertex::Surface {
            hit,
            shading,
            wo,
            material,
        };
        let mixed = tree.map(|t| (t, guiding::bsdf_fraction(material)));
        path.radiance +=
            path.throughput * vertex_direct_light(scene, path, &vertex, mixed, sampler);
    }
    let Some(bs) = scatter_at_surface(tree, material, &shading, wo, sampler) else {
        return path.end_at_vertex();
    };
    path.throughput *= bs.weight;
    path.prev_normal = Some(shading.n);
    if let Some(interfaces) = &scene.interfaces {
        path.medium = interfaces.after(hit.shape, hit.geometric_normal, bs.wi, path.medium);
    }
    if !bs.is_delta {
        path.log_vertex(hit.p, bs.wi, bs.pdf);
    }
    let ray = path
        .ray
        .spawn(offset_origin(hit.p, hit.geometric_normal, bs.wi), bs.wi);
    let stop = G::ACTIVE && !bs.is_delta;
    continue_path(
        scene,
        path,
        ray,
        (bs.pdf, bs.is_delta, stop),
        hit.p,
        sampler,
    )
}

/// A surface vertex's continuation from the BSDF or its mixture with the guide's `tree`.
#[inline]
fn scatter_at_surface(
    tree: Option<&guiding::dtree::DTree>,
    material: &Material,
    shading: &Shading,
    wo: Vec3,
    sampler: &mut Sampler,
) -> Option<crate::material::BsdfSample> {
    match tree {
        None => {
            let u = sampler.next_2d();
            material.sample(shading, wo, u, sampler.next_1d())
        }
        Some(tree) => {
            let u_sel = sampler.next_1d();
            let u = sampler.next_2d();
            let numbers = (u_sel, u, sampler.next_1d());
            let ms = guiding::sample_bsdf(tree, material, shading, wo, numbers)?;
            Some(crate::material::BsdfSample {
                wi: ms.dir,
                weight: ms.weight,
                pdf: ms.pdf,
                is_delta: false,
            })
        }
    }
}

/// Moves the path onto the sampled continuation `ray` from vertex `p`.
///
/// `(pdf, is_delta, last)`: the direction's density, whether a Dirac lobe
/// gave it, and whether the vertex is the last scattering event anyway.
/// Past the last vertex the depth limits allow, the new ray is marked
/// emission-only. Russian roulette may end the path here.
fn continue_path(
    scene: &Scene,
    path: &mut PathState,
    ray: Ray,
    (pdf, is_delta, last): (f32, bool, bool),
    p: Vec3,
    sampler: &mut Sampler,
) -> Step {
    let settings = &scene.settings;
    path.prev_pdf = pdf;
    path.prev_delta = is_delta;
    path.prev_point = p;
    path.ray = ray;
    path.depth += 1;
    path.emission_only = last
        || path.depth >= settings.max_depth
        || path.scatter_depth >= settings.max_scatter_depth;
    path.book_sky();
    if !russian_roulette(&mut path.throughput, path.depth, settings.rr_depth, sampler) {
        // Roulette's loss is booked by its expectation, with the survivors' gain: nothing.
        return Step::Stop;
    }
    if let Some(book) = &mut path.sky {
        book.rescaled(path.throughput);
    }
    Step::Continue
}

/// Depth from which Russian roulette's survival probability is capped below 1.
///
/// Up to it a path survives with probability min(1, its throughput's largest
/// channel), so a survivor's throughput never grows past 1: in a dense,
/// nearly white medium (a cloud of albedo 0.99) a cap of 0.95 at every event
/// would multiply a long walk's throughput by 0.99/0.95 per event and turn
/// its rare deep paths into fireflies. Past it the cap of
/// [`RR_DEEP_SURVIVAL`] guarantees that every path ends, even in a lossless
/// furnace without a depth limit.
pub const RR_UNCAPPED_DEPTH: u32 = 256;

/// Largest survival probability past [`RR_UNCAPPED_DEPTH`] events.
///
/// Below the albedo of real clouds' walks (0.99–0.999 per event) it would
/// grow their throughput again, event after event, as 0.95 did; at 0.999 a
/// lossless walk still ends, after about 1000 more events on average.
pub const RR_DEEP_SURVIVAL: f32 = 0.999;

/// Survival probability of Russian roulette for a path whose throughput,
/// relative to its start, has largest channel `relative` after `depth` events.
#[inline]
pub fn survival_probability(relative: f32, depth: u32) -> f32 {
    let cap = if depth < RR_UNCAPPED_DEPTH {
        1.0
    } else {
        RR_DEEP_SURVIVAL
    };
    relative.min(cap)
}

/// Ends the path with probability `1 - q` past `rr_depth`, reweighting survivors by `1/q`.
fn russian_roulette(
    throughput: &mut Rgb,
    depth: u32,
    rr_depth: u32,
    sampler: &mut Sampler,
) -> bool {
    if depth < rr_depth {
        return true;
    }
    let q = survival_probability(throughput.max_channel(), depth);
    if q <= 0.0 || sampler.next_1d() >= q {
        return false;
    }
    *throughput /= q;
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Forced in-scattering runs on a plain path and stands aside for a
    /// guided path, a training path, an excluded segment and the interface
    /// rule (their densities or media are not the ones its weights assume).
    #[test]
    fn forced_in_scattering_stands_aside_for_guides_logs_and_interfaces() {
        let text = "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
            [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 3.0, 0.0]\nradius = 0.5\nemission = 10.0\n\
            [[medium]]\ntype = \"homogeneous\"\nsigma_t = 1.0\nalbedo = 0.9\n\
            bounds = { type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }\n";
        let file = std::path::Path::new("test.toml");
        let desc = crate::scene::parse(text, file).expect("parse");
        let mut scene = crate::scene::build(&desc, file, std::path::Path::new(".")).expect("build");
        assert!(scene.settings.forced_scattering);
        let media = scene.media.clone();
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let mut sampler = Sampler::new(1, 0, 0, 0);
        let mut forced = |scene: &Scene, path: &PathState, excluded: bool| {
            forced_in_scattering(scene, &media, path, f32::INFINITY, excluded, &mut sampler)
        };
        let plain = PathState::new(&scene, ray, (None, false), None, None);
        assert!(forced(&scene, &plain, false).is_some());
        assert!(forced(&scene, &plain, true).is_none());
        let guide = Guide::new();
        let guided = PathState::new(&scene, ray, (None, false), Some(&guide), None);
        assert!(forced(&scene, &guided, false).is_none());
        let mut log = PathLog::new();
        let training = PathState::new(&scene, ray, (None, false), None, Some(&mut log));
        assert!(forced(&scene, &training, false).is_none());
        scene.interfaces = Some(interfaces::Interfaces {
            sides: vec![None],
            null: vec![false],
            camera: Some(0),
        });
        let ruled = PathState::new(&scene, ray, (None, false), None, None);
        assert!(forced(&scene, &ruled, false).is_none());
    }

    /// Sun-lobe sampling runs at a plain path's first medium vertices in a
    /// forward medium and stands aside for a guided or forced vertex, a
    /// training path and vertices past its depth.
    #[test]
    fn the_sun_lobe_stands_aside_for_guides_forced_segments_logs_and_depth() {
        let text = "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
            [[light]]\ntype = \"sun\"\ndirection = [0.0, -1.0, 0.0]\nirradiance = 3.0\n\
            [[medium]]\ntype = \"homogeneous\"\nsigma_t = 1.0\nalbedo = 0.9\n\
            phase = { type = \"hg\", g = 0.8 }\n\
            bounds = { type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }\n";
        let file = std::path::Path::new("test.toml");
        let desc = crate::scene::parse(text, file).expect("parse");
        let scene = crate::scene::build(&desc, file, std::path::Path::new(".")).expect("build");
        let phase = crate::medium::PhaseFunction::HenyeyGreenstein { g: 0.8 };
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let mut plain = PathState::new(&scene, ray, (None, false), None, None);
        plain.scatter_depth = 1;
        let lobe = |path: &PathState, guided: bool, forced: bool| {
            sun_lobe_at(&scene, path, &phase, (guided, forced))
        };
        assert_eq!(lobe(&plain, false, false), scene.settings.sun_lobe);
        assert!(lobe(&plain, false, false).is_some());
        assert_eq!(lobe(&plain, true, false), None);
        assert_eq!(lobe(&plain, false, true), None);
        plain.scatter_depth = sun_lobe::SUN_LOBE_DEPTH + 1;
        assert_eq!(lobe(&plain, false, false), None);
        let mut log = PathLog::new();
        let mut training = PathState::new(&scene, ray, (None, false), None, Some(&mut log));
        training.scatter_depth = 1;
        assert_eq!(lobe(&training, false, false), None);
    }

    /// A walk of 255 events in a medium of albedo 0.99 (a cloud): every
    /// survivor's throughput stays at most 1, where a survival probability
    /// capped at 0.95 would have grown it by 0.99/0.95 per event (to ~10^4).
    #[test]
    fn roulette_never_grows_a_survivors_throughput_before_the_cap_depth() {
        let mut largest = 0.0f32;
        for i in 0..200 {
            let mut sampler = Sampler::new(3, 4, 5, i);
            let mut throughput = Rgb::new(1.0, 1.0, 1.0);
            for depth in 1..RR_UNCAPPED_DEPTH {
                throughput *= 0.99;
                if !russian_roulette(&mut throughput, depth, 1, &mut sampler) {
                    break;
                }
                largest = largest.max(throughput.max_channel());
            }
        }
        assert!(largest <= 1.0, "a survivor's throughput grew to {largest}");
        assert_eq!(survival_probability(3.0, RR_UNCAPPED_DEPTH - 1), 1.0);
        assert_eq!(
            survival_probability(3.0, RR_UNCAPPED_DEPTH),
            RR_DEEP_SURVIVAL
        );
    }

    /// Past `rr_depth` a path survives with probability q = max channel
    /// (at most 1, or [`RR_DEEP_SURVIVAL`] past [`RR_UNCAPPED_DEPTH`]) and its survivors carry 1/q; before it, and never with
    /// zero throughput, nothing is drawn.
    #[test]
    fn russian_roulette_keeps_a_path_with_its_largest_channel_as_probability() {
        let mut sampler = Sampler::new(5, 0, 0, 0);
        let mut early = Rgb::new(0.5, 0.25, 0.1);
        assert!(russian_roulette(&mut early, 2, 3, &mut sampler));
        assert_eq!(early, Rgb::new(0.5, 0.25, 0.1));
        let mut dark = Rgb::BLACK;
        assert!(!russian_roulette(&mut dark, 3, 3, &mut sampler));
        let n = 20_000;
        let mut survived = 0;
        for i in 0..n {
            let mut sampler = Sampler::new(7, 1, 2, i);
            let mut throughput = Rgb::new(0.5, 0.25, 0.1);
            if russian_roulette(&mut throughput, 3, 3, &mut sampler) {
                survived += 1;
                assert_eq!(throughput, Rgb::new(1.0, 0.5, 0.2));
            }
        }
        // One check at the suite's k (tests/common/k_sigma.rs).
        let p = survived as f64 / n as f64;
        let se = (0.5f64 * 0.5 / n as f64).sqrt();
        assert!(
            (p - 0.5).abs() < crate::suite_k::k_sigma(1) * se,
            "survival {p}"
        );
    }
}
