//! Path guiding (issue 35): a distribution of incident radiance learned
//! during the render, sampled in a one-sample mixture with the phase
//! function or BSDF at medium collisions and non-Dirac surface vertices.
//!
//! The guide is an SD-tree (Müller et al. 2017): a spatial binary tree
//! ([`stree`]) whose leaves hold directional quadtrees ([`dtree`]). It is
//! trained before the image's samples in iterations of 1, 2, 4, … samples
//! per pixel of the whole frame (their own random streams), each traced
//! with the previous iteration's guide; every scattering vertex of those
//! paths records where it was (p), the direction it continued in (ω), and
//! the radiance that came back along ω over the density of choosing ω.
//! Records are collected per image row and deposited row by row in row
//! order, so the guide, and the image, depend on the seed only.
//!
//! Sampling is the mixture p(ω) = α·p_guide(ω) + (1 − α)·p_scatter(ω) with
//! α = [`GUIDE_FRACTION`] where the vertex's leaf holds energy (else α = 0):
//! one number picks the component, the weight is f(ω)/p(ω), and p(ω) is the
//! density used by MIS both for hits of emitters and for next-event
//! estimation at the vertex, so the estimator stays unbiased whatever the
//! guide has learned. The radiance recorded behind a vertex is what the
//! path gathered there: emission met along ω enters MIS-weighted against
//! the vertex's own next-event estimation.
//!
//! Memory: at most [`MAX_LEAVES`] spatial leaves and [`NODE_BUDGET`]
//! quadtree nodes (48 bytes each: 24 MB), plus one image row of records
//! (28 bytes per vertex) per row in flight.

pub mod dtree;
pub mod stree;

use super::estimator::Estimator;
use super::{li_path, Scene};
use crate::film::Splat;
use crate::material::{Material, Shading};
use crate::math::color::Rgb;
use crate::math::{Bounds3, Vec2, Vec3};
use crate::medium::PhaseFunction;
use crate::sampling::{PixelStreams, Sampler};
use dtree::DTree;
use stree::STree;

/// Probability of drawing a direction from the guide rather than the phase function or BSDF.
pub const GUIDE_FRACTION: f32 = 0.5;

/// Training iterations before the image: 1, 2, 4, … samples per pixel (7 in all).
pub const TRAINING_ITERATIONS: u32 = 3;

/// Most spatial leaves the guide holds.
pub const MAX_LEAVES: usize = 4096;

/// Most quadtree nodes the guide holds over all leaves (sampling and building trees).
pub const NODE_BUDGET: usize = 500_000;

/// Records a leaf may take per √(spp of the iteration) before it splits
/// (Müller's c = 12000 is for longer trainings; ours is shorter).
const SPLIT_RECORDS: f64 = 4000.0;

/// Vertices of one path that record what came back (the rest do not record).
const MAX_LOGGED: usize = 32;

/// One training record: radiance/pdf arriving at `p` from `dir`.
#[derive(Clone, Copy, Debug)]
pub struct Record {
    /// Where the vertex was.
    pub p: Vec3,
    /// The direction the path continued in.
    pub dir: Vec3,
    /// Mean over channels of the radiance that came back along `dir`, over the density of `dir`.
    pub value: f32,
}

/// The learned guide: an SD-tree and the iterations it has finished.
#[derive(Clone, Debug)]
pub struct Guide {
    tree: STree,
    /// Box of the records deposited so far in the first iteration.
    seen: Option<Bounds3>,
    iterations: u32,
}

impl Default for Guide {
    fn default() -> Self {
        Guide::new()
    }
}

impl Guide {
    /// An untrained guide: one leaf, nothing to sample from.
    pub fn new() -> Guide {
        let unit = Bounds3::new(Vec3::ZERO, Vec3::ONE);
        Guide {
            tree: STree::new(unit),
            seen: None,
            iterations: 0,
        }
    }

    /// Training iterations finished.
    pub fn iterations(&self) -> u32 {
        self.iterations
    }

    /// Spatial leaves and quadtree nodes held.
    pub fn size(&self) -> (usize, usize) {
        (self.tree.leaves.len(), self.tree.quad_nodes())
    }

    /// The directional distribution to sample at `p`, if it has learned anything there.
    #[inline]
    pub fn at(&self, p: Vec3) -> Option<&DTree> {
        if self.iterations == 0 {
            return None;
        }
        let t = &self.tree.leaves[self.tree.leaf_index(p)].sampling;
        (t.energy() > 0.0).then_some(t)
    }

    /// Deposits a row's records, in their order, into the running iteration.
    pub fn deposit(&mut self, records: &[Record]) {
        for r in records {
            if !(r.value.is_finite() && r.value >= 0.0 && r.p.is_finite()) {
                continue;
            }
            if self.iterations == 0 {
                let b = Bounds3::new(r.p, r.p);
                self.seen = Some(self.seen.map_or(b, |s| s.union(&b)));
            }
            let index = self.tree.leaf_index(r.p);
            let leaf = &mut self.tree.leaves[index];
            leaf.building.deposit(r.dir, r.value as f64);
            leaf.records += 1;
        }
    }

    /// Ends an iteration of `spp` samples per pixel: what was deposited
    /// becomes the sampling distribution, each quadtree is refined for the
    /// next one, and busy leaves split.
    pub fn finish_iteration(&mut self, spp: u32) {
        if self.iterations == 0 {
            // The first iteration had one leaf: it now covers the box the paths reached.
            let b = self.seen.unwrap_or(self.tree.bounds());
            let pad = (b.max - b.min).max_element().max(1e-3) * 1e-3;
            let leaf = std::mem::take(&mut self.tree.leaves[0]);
            self.tree = STree::new(Bounds3::new(b.min - pad, b.max + pad));
            self.tree.leaves[0] = leaf;
        }
        let per_tree = (NODE_BUDGET / (2 * self.tree.leaves.len())).max(1);
        for leaf in &mut self.tree.leaves {
            let refined = leaf.building.refined(per_tree);
            leaf.sampling = std::mem::replace(&mut leaf.building, refined);
        }
        let threshold = (SPLIT_RECORDS * (spp as f64).sqrt()) as u64;
        self.tree.subdivide(threshold, MAX_LEAVES, NODE_BUDGET);
        for leaf in &mut self.tree.leaves {
            leaf.records = 0;
        }
        self.iterations += 1;
    }
}

/// Scattering events after which a path samples from its phase functions
/// and BSDFs alone: each guided vertex multiplies the throughput by a
/// weight of mean 1 but spread (up to 1/(1 − α)), and over the tens of
/// collisions of a dense medium that product grows heavy tails (fireflies).
pub const MAX_GUIDED_DEPTH: u32 = 4;

/// The tree a vertex at `p`, after `depth` scattering events, samples from (if any).
#[inline]
pub fn tree_at(guide: Option<&Guide>, p: Vec3, depth: u32) -> Option<&DTree> {
    match guide {
        Some(g) if depth < MAX_GUIDED_DEPTH => g.at(p),
        _ => None,
    }
}

/// A direction drawn from the mixture, its weight f/p and the mixture density p.
#[derive(Clone, Copy, Debug)]
pub struct MixtureSample {
    /// The direction (propagation direction of the continued path).
    pub dir: Vec3,
    /// Scattering value over the mixture density.
    pub weight: Rgb,
    /// The mixture density per steradian.
    pub pdf: f32,
}

/// The guide's share α of the mixture at a medium collision: [`GUIDE_FRACTION`]
/// scaled by 1 − |⟨cos θ⟩|. Where the phase function is peaked, every guided
/// vertex multiplies the path's throughput by phase/mixture ∈ [0, 1/(1 − α)],
/// whose second moment grows with the peak; over the tens of collisions of a
/// dense medium that product has heavy tails, so peaked phases take less.
#[inline]
pub fn phase_fraction(phase: &PhaseFunction) -> f32 {
    GUIDE_FRACTION * (1.0 - phase.mean_cosine().abs())
}

/// The guide's share α at a surface: [`GUIDE_FRACTION`] for a diffuse BSDF,
/// less for glossy lobes (peaked, for the reason of [`phase_fraction`]).
#[inline]
pub fn bsdf_fraction(material: &Material) -> f32 {
    match material {
        Material::Diffuse { .. } => GUIDE_FRACTION,
        _ => 0.2 * GUIDE_FRACTION,
    }
}

/// The mixture density α·p_guide + (1 − α)·p_scatter at `d`.
#[inline]
pub fn mixture_pdf(tree: &DTree, alpha: f32, d: Vec3, scatter_pdf: f32) -> f32 {
    alpha * tree.pdf(d) + (1.0 - alpha) * scatter_pdf
}

/// A medium collision's continuation from the mixture of `tree` and `phase`
/// (α = [`phase_fraction`]); `u_sel` picks the component.
pub fn sample_phase(
    tree: &DTree,
    phase: &PhaseFunction,
    dir_in: Vec3,
    u_sel: f32,
    u: Vec2,
) -> Option<MixtureSample> {
    let alpha = phase_fraction(phase);
    let dir = if u_sel < alpha {
        tree.sample(u)?
    } else {
        phase.sample(dir_in, u)?.direction
    };
    let pdf = mixture_pdf(tree, alpha, dir, phase.pdf(dir_in, dir));
    (pdf > 0.0 && pdf.is_finite()).then(|| MixtureSample {
        dir,
        weight: Rgb::splat(phase.eval(dir_in, dir) / pdf),
        pdf,
    })
}

/// A non-Dirac surface vertex's continuation from the mixture of `tree` and
/// the BSDF (α = [`bsdf_fraction`]); numbers `(u_sel, u, u_lobe)`.
pub fn sample_bsdf(
    tree: &DTree,
    material: &Material,
    shading: &Shading,
    wo: Vec3,
    (u_sel, u, u_lobe): (f32, Vec2, f32),
) -> Option<MixtureSample> {
    let alpha = bsdf_fraction(material);
    let dir = if u_sel < alpha {
        tree.sample(u)?
    } else {
        material.sample(shading, wo, u, u_lobe)?.wi
    };
    let pdf = mixture_pdf(tree, alpha, dir, material.pdf(shading, wo, dir));
    let f = material.eval(shading, wo, dir);
    (pdf > 0.0 && pdf.is_finite() && !f.is_black()).then(|| MixtureSample {
        dir,
        weight: f * (1.0 / pdf),
        pdf,
    })
}

/// The guided vertices of one training path, to turn into records when it ends.
pub(crate) struct PathLog {
    vertices: [Logged; MAX_LOGGED],
    len: usize,
}

/// A vertex as the path left it: the throughput and radiance after its sampling.
#[derive(Clone, Copy, Default)]
struct Logged {
    p: Vec3,
    dir: Vec3,
    pdf: f32,
    throughput: Rgb,
    radiance: Rgb,
}

impl PathLog {
    /// An empty log (on the stack: no allocation per path).
    pub(crate) fn new() -> PathLog {
        PathLog {
            vertices: [Logged::default(); MAX_LOGGED],
            len: 0,
        }
    }

    /// Notes a vertex at `p` continuing along `dir` with density `pdf`, the path's
    /// throughput (after the vertex's weight) and radiance at that moment.
    pub(crate) fn push(&mut self, p: Vec3, dir: Vec3, pdf: f32, throughput: Rgb, radiance: Rgb) {
        if self.len < MAX_LOGGED && pdf > 0.0 {
            self.vertices[self.len] = Logged {
                p,
                dir,
                pdf,
                throughput,
                radiance,
            };
            self.len += 1;
        }
    }

    /// The records of a path that ended with `radiance`: at each vertex, what the
    /// path gathered after it, divided by its throughput there, over its density.
    pub(crate) fn finish(&self, radiance: Rgb, out: &mut Vec<Record>) {
        for v in &self.vertices[..self.len] {
            let after = radiance - v.radiance;
            let l = Rgb::new(
                ratio(after.r, v.throughput.r),
                ratio(after.g, v.throughput.g),
                ratio(after.b, v.throughput.b),
            );
            out.push(Record {
                p: v.p,
                dir: v.dir,
                value: l.average().max(0.0) / v.pdf,
            });
        }
    }
}

/// `a / b`, 0 where the throughput channel is 0.
#[inline]
fn ratio(a: f32, b: f32) -> f32 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}

/// The random streams of training iteration `iteration`: apart from the image's.
fn training_streams(scene: &Scene, iteration: u32, x: u32, y: u32) -> PixelStreams {
    let salt = 0x6a09_e667_f3bc_c909u64.wrapping_mul(iteration as u64 + 1);
    PixelStreams::new(scene.settings.sampler, scene.settings.seed ^ salt, x, y)
}

/// Traces `spp` training paths through every pixel of row `y` with `guide`,
/// appending their records to `out` in pixel and sample order.
pub fn train_row(
    scene: &Scene,
    guide: Option<&Guide>,
    (y, spp, iteration): (u32, u32, u32),
    out: &mut Vec<Record>,
) {
    let mut log = PathLog::new();
    for x in 0..scene.camera.width() {
        let streams = training_streams(scene, iteration, x, y);
        for s in 0..spp {
            let mut sampler: Sampler = streams.sampler(s as u64);
            let time = match scene.settings.shutter {
                Some(_) => scene.settings.sample_time(sampler.time_1d()),
                None => 0.0,
            };
            let ray = scene.camera.sample_ray_at(x, y, time, &mut sampler);
            log.len = 0;
            let radiance = li_path(scene, ray, &mut sampler, guide, Some(&mut log));
            log.finish(radiance, out);
        }
    }
}

/// The path tracer sampling from a trained [`Guide`].
pub struct GuidedPathTracer<'g> {
    /// The guide, fixed for the whole image.
    pub guide: &'g Guide,
}

impl GuidedPathTracer<'_> {
    /// Radiance of sample `s` of pixel (x, y): what a guided render adds for it.
    pub fn pixel_sample(&self, scene: &Scene, x: u32, y: u32, s: u32) -> Rgb {
        let streams = scene.settings.pixel_streams(x, y);
        self.sample(scene, (x, y), &streams, s, &mut (), &mut Vec::new())
    }
}

impl Estimator for GuidedPathTracer<'_> {
    type Arena = ();

    fn arena(&self) {}

    fn splats(&self) -> bool {
        false
    }

    #[inline]
    fn sample(
        &self,
        scene: &Scene,
        (x, y): (u32, u32),
        streams: &PixelStreams,
        s: u32,
        _arena: &mut (),
        _splats: &mut Vec<Splat>,
    ) -> Rgb {
        let mut sampler = streams.sampler(s as u64);
        let time = match scene.settings.shutter {
            Some(_) => scene.settings.sample_time(sampler.time_1d()),
            None => 0.0,
        };
        let ray = scene.camera.sample_ray_at(x, y, time, &mut sampler);
        li_path(scene, ray, &mut sampler, Some(self.guide), None)
    }
}
