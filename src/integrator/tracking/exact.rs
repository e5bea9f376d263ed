//! Tracking through grid media with exact voxel integration in dense cells.
//!
//! In a majorant segment where null collisions would be many (a dense
//! volume, `density_scale = 1e6`, or a cell whose bound is far above most of
//! its density) the trilinear density is integrated voxel cell by voxel cell
//! in closed form (`medium::voxel`): the optical depth of each cell's piece
//! of the ray is exact, so a shadow ray multiplies exact transmittances
//! (with the same Russian roulette as ratio tracking below 0.1), and a free
//! flight inverts the optical depth at an exponential target (regular
//! tracking). A dense interior then costs about one voxel step per event,
//! as a homogeneous medium costs one collision. Thin segments keep
//! null-collision tracking (ratio tracking, spectral tracking), which takes
//! fewer steps there. Segments are independent (exponential targets are
//! memoryless), so mixing the two along one ray stays unbiased.

use super::{collide, negligible, roulette, FreeFlight, Step, Tally, ROULETTE_THRESHOLD};
use super::{stats, MAX_TENTATIVE_COLLISIONS};
use crate::math::color::Rgb;
use crate::math::Ray;
use crate::math::Vec3;
use crate::medium::voxel::{VoxelSpan, VoxelWalk};
use crate::medium::{GridMedium, MajorantSegment};
use crate::sampling::Sampler;

/// Tentative collisions plus voxel steps of one ray, against the cap.
struct Budget(u32);

impl Budget {
    /// Counts one step; false (and the ray counted as capped) past the cap.
    #[inline]
    fn take(&mut self) -> bool {
        self.0 += 1;
        if self.0 > MAX_TENTATIVE_COLLISIONS {
            stats::count_capped_ray();
            return false;
        }
        true
    }
}

/// An exponential optical-depth target: -ln(1 - u).
#[inline]
fn exp_target(sampler: &mut Sampler) -> f32 {
    -(1.0 - sampler.next_1d()).ln()
}

/// Transmittance of a grid medium along `ray` over `[0, t_max)`: exact in
/// dense segments, ratio tracking with roulette in the others.
pub(super) fn grid_transmittance(
    medium: &GridMedium,
    ray: &Ray,
    t_max: f32,
    sampler: &mut Sampler,
) -> Rgb {
    let segments = medium.majorants(ray, t_max);
    let (o, d) = segments.index_ray();
    let rate = medium.exact_rate(d);
    let mut walk = Walk::default();
    let mut tr = ExactProduct::new(medium.sigma_t_unit());
    let mut tally = Tally::default();
    let mut budget = Budget(0);
    for seg in segments {
        if seg.sigma_maj < rate {
            let mut w = tr.value();
            let go_on = ratio_segment(medium, &seg, ray, &mut w, &mut budget, &mut tally, sampler);
            if !go_on {
                return w;
            }
            tr = ExactProduct::from(w, medium.sigma_t_unit());
            continue;
        }
        let spans = walk.over(medium, o, d, &seg);
        for span in spans.by_ref() {
            if !budget.take() {
                return Rgb::BLACK;
            }
            tally.voxel();
            let len = span.t1 - span.t0;
            if span.clamped {
                // The lookup's clamp to 0 makes the density no cubic here: ratio tracking
                // against the cell's own bound.
                let mut w = tr.value();
                if !ratio_span(
                    &span,
                    &mut w,
                    &mut budget,
                    &mut tally,
                    sampler,
                    medium.sigma_t_unit(),
                ) {
                    return w;
                }
                tr = ExactProduct::from(w, medium.sigma_t_unit());
                continue;
            }
            if let Some(end) = tr.add(len * span.density.integral(1.0), sampler) {
                return end;
            }
        }
    }
    tr.value()
}

/// A transmittance weight times exp(-k·D) for a pending density integral D,
/// taken out (and Russian roulette played) only once it may be below the
/// roulette threshold: one exp per flush, not one per voxel.
struct ExactProduct {
    weight: Rgb,
    k: Rgb,
    depth: f32,
    /// Largest D for which the product surely stays at or above the threshold.
    safe_depth: f32,
}

impl ExactProduct {
    fn new(k: Rgb) -> ExactProduct {
        ExactProduct::from(Rgb::WHITE, k)
    }

    fn from(weight: Rgb, k: Rgb) -> ExactProduct {
        // max_c w_c e^(-k_c D) ≥ max(w) e^(-max(k) D) ≥ threshold while D ≤ safe_depth.
        let m = weight.map(f32::abs).max_channel();
        let safe_depth = if m > 0.0 && k.max_channel() > 0.0 {
            ((m / ROULETTE_THRESHOLD).ln() / k.max_channel()).max(0.0)
        } else {
            0.0
        };
        ExactProduct {
            weight,
            k,
            depth: 0.0,
            safe_depth,
        }
    }

    /// The product so far.
    fn value(&self) -> Rgb {
        self.weight * self.k.depth_over(self.depth).exp_neg()
    }

    /// Multiplies in exp(-k·`depth`); `Some(final value)` when tracking is over.
    #[inline]
    fn add(&mut self, depth: f32, sampler: &mut Sampler) -> Option<Rgb> {
        self.depth += depth;
        if self.depth <= self.safe_depth {
            return None;
        }
        let mut w = self.value();
        if negligible(w) {
            return Some(w);
        }
        if !roulette(&mut w, sampler) {
            return Some(Rgb::BLACK);
        }
        *self = ExactProduct::from(w, self.k);
        None
    }
}

/// A voxel walk kept across consecutive dense segments of one ray.
#[derive(Default)]
struct Walk<'a> {
    walk: Option<VoxelWalk<'a>>,
}

impl<'a> Walk<'a> {
    /// The walk over `seg`: the previous one extended when `seg` starts where it stopped.
    fn over(
        &mut self,
        medium: &'a GridMedium,
        o: Vec3,
        d: Vec3,
        seg: &MajorantSegment,
    ) -> &mut VoxelWalk<'a> {
        match &mut self.walk {
            Some(w) if w.reach() == (seg.t0, seg.t0) => w.extend_to(seg.t1),
            w => *w = Some(medium.voxels(o, d, seg.t0, seg.t1)),
        }
        self.walk.as_mut().expect("just set")
    }
}

/// Ratio tracking inside one clamped voxel span into `w`; false when tracking is over (`w` final).
fn ratio_span(
    span: &VoxelSpan,
    w: &mut Rgb,
    budget: &mut Budget,
    tally: &mut Tally,
    sampler: &mut Sampler,
    k: Rgb,
) -> bool {
    let maj = span_majorant(span, k.max_channel());
    let len = span.t1 - span.t0;
    let mut t = span.t0;
    loop {
        t += exp_target(sampler) / maj;
        if t >= span.t1 {
            return true;
        }
        if !budget.take() {
            *w = Rgb::BLACK;
            return false;
        }
        let sigma_t = k * span.density.eval((t - span.t0) / len).max(0.0);
        tally.add(sigma_t.max_channel(), maj);
        *w *= Rgb::WHITE - sigma_t / maj;
        if negligible(*w) {
            return false;
        }
        if !roulette(w, sampler) {
            *w = Rgb::BLACK;
            return false;
        }
    }
}

/// The null-collision bound of one voxel span: σt per unit density times its largest corner, padded for rounding.
#[inline]
fn span_majorant(span: &VoxelSpan, k_max: f32) -> f32 {
    (span.max_corner.max(0.0) * k_max * (1.0 + 1e-5)).max(f32::MIN_POSITIVE)
}

/// Ratio tracking over one thin segment into `tr`; false when tracking is over (`tr` final).
fn ratio_segment(
    medium: &GridMedium,
    seg: &MajorantSegment,
    ray: &Ray,
    tr: &mut Rgb,
    budget: &mut Budget,
    tally: &mut Tally,
    sampler: &mut Sampler,
) -> bool {
    let mut t = seg.t0;
    loop {
        t += exp_target(sampler) / seg.sigma_maj;
        if t >= seg.t1 {
            return true;
        }
        if !budget.take() {
            *tr = Rgb::BLACK;
            return false;
        }
        let sigma_t = medium.sigma_t(ray.at(t));
        tally.add(sigma_t.max_channel(), seg.sigma_maj);
        *tr *= Rgb::WHITE - sigma_t / seg.sigma_maj;
        if negligible(*tr) {
            return false;
        }
        if !roulette(tr, sampler) {
            return false;
        }
    }
}

/// What a piece of a free flight ended in.
enum Flight {
    /// Went on past the piece.
    Through,
    /// The flight is over.
    Done(FreeFlight),
}

/// Free flight through a grid medium with grey extinction: exact in dense
/// segments, spectral tracking (null collisions) in the others.
pub(super) fn grid_free_flight(
    medium: &GridMedium,
    ray: &Ray,
    t_max: f32,
    throughput: &mut Rgb,
    radiance: &mut Rgb,
    sampler: &mut Sampler,
) -> FreeFlight {
    let segments = medium.majorants(ray, t_max);
    let (o, d) = segments.index_ray();
    let rate = medium.exact_rate(d);
    let mut tally = Tally::default();
    let mut budget = Budget(0);
    let mut walk = Walk::default();
    let mut io = FlightState {
        medium,
        ray,
        t_max,
        throughput,
        radiance,
        budget: &mut budget,
        tally: &mut tally,
    };
    for seg in segments {
        let piece = if seg.sigma_maj < rate {
            io.null_span(seg.t0, seg.t1, seg.sigma_maj, None, sampler)
        } else {
            io.exact_segment(walk.over(medium, o, d, &seg), sampler)
        };
        if let Flight::Done(f) = piece {
            return f;
        }
    }
    FreeFlight::Passed
}

/// A free flight in progress.
struct FlightState<'a, 'b> {
    medium: &'a GridMedium,
    ray: &'a Ray,
    t_max: f32,
    throughput: &'b mut Rgb,
    radiance: &'b mut Rgb,
    budget: &'b mut Budget,
    tally: &'b mut Tally,
}

impl FlightState<'_, '_> {
    /// Ends the flight at the cap: the throughput is lost (counted as a capped ray).
    fn capped(&mut self) -> Flight {
        *self.throughput = Rgb::BLACK;
        Flight::Done(FreeFlight::Absorbed)
    }

    /// Walks the voxel spans of a dense segment, inverting the exact optical depth.
    fn exact_segment(&mut self, spans: &mut VoxelWalk, sampler: &mut Sampler) -> Flight {
        let k = self.medium.sigma_t_unit().max_channel();
        // Target in units of density × length (k is grey here).
        let mut target = exp_target(sampler) / k;
        for span in spans {
            if !self.budget.take() {
                return self.capped();
            }
            self.tally.voxel();
            if span.clamped {
                let maj = span_majorant(&span, k);
                if let Flight::Done(f) = self.null_span(span.t0, span.t1, maj, Some(&span), sampler)
                {
                    return Flight::Done(f);
                }
                // Memoryless: a fresh target after a null-tracked span.
                target = exp_target(sampler) / k;
                continue;
            }
            let len = span.t1 - span.t0;
            let depth = len * span.density.integral(1.0);
            if depth < target {
                target -= depth;
                continue;
            }
            let w = span.density.solve_integral(target / len);
            let t = span.t0 + w * len;
            if t >= self.t_max {
                break;
            }
            let density = span.density.eval(w).max(0.0);
            return Flight::Done(self.real_collision(t, density));
        }
        Flight::Through
    }

    /// A real collision sampled in proportion to σt·T: emission σa·Le/σt, then
    /// scattering with weight σs/σt (the albedo; σt is grey).
    fn real_collision(&mut self, t: f32, density: f32) -> FreeFlight {
        let properties = self.medium.properties_with_density(self.ray.at(t), density);
        let albedo = self.medium.albedo();
        if !properties.emission.is_black() {
            *self.radiance += *self.throughput * (Rgb::WHITE - albedo) * properties.emission;
        }
        *self.throughput *= albedo;
        if self.throughput.is_black() {
            return FreeFlight::Absorbed;
        }
        FreeFlight::Scatter {
            t,
            medium: 0,
            properties,
        }
    }

    /// Spectral tracking over `[t0, t1)` against the constant bound `maj`, the
    /// density read from the grid or, inside one voxel, from its `span`.
    fn null_span(
        &mut self,
        t0: f32,
        t1: f32,
        maj: f32,
        span: Option<&VoxelSpan>,
        sampler: &mut Sampler,
    ) -> Flight {
        let mut t = t0;
        loop {
            t += exp_target(sampler) / maj;
            if t >= t1 || t >= self.t_max {
                return Flight::Through;
            }
            if !self.budget.take() {
                return self.capped();
            }
            let p = self.ray.at(t);
            let props = match span {
                None => self.medium.properties_at(p, self.ray.time),
                Some(s) => {
                    let density = s.density.eval((t - s.t0) / (s.t1 - s.t0)).max(0.0);
                    self.medium.properties_with_density(p, density)
                }
            };
            let collision = super::Collision {
                t,
                sigma_maj: maj,
                sigma_control: Rgb::BLACK,
            };
            match collide(
                &props,
                &collision,
                self.throughput,
                self.radiance,
                sampler,
                self.tally,
            ) {
                Step::Scatter => {
                    return Flight::Done(FreeFlight::Scatter {
                        t,
                        medium: 0,
                        properties: props,
                    })
                }
                Step::Absorbed => return Flight::Done(FreeFlight::Absorbed),
                Step::Inert => return Flight::Done(FreeFlight::Passed),
                Step::Null => {}
            }
        }
    }
}
