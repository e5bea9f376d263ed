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

use super::{collide, negligible, roulette, FreeFlight, Step, Tally};
use super::{CAPPED_RAYS, MAX_TENTATIVE_COLLISIONS};
use crate::color::Rgb;
use crate::math::Ray;
use crate::medium::voxel::VoxelSpan;
use crate::medium::{GridMedium, MajorantSegment};
use crate::sampling::Sampler;
use std::sync::atomic::Ordering;

/// Tentative collisions plus voxel steps of one ray, against the cap.
struct Budget(u32);

impl Budget {
    /// Counts one step; false (and the ray counted as capped) past the cap.
    #[inline]
    fn take(&mut self) -> bool {
        self.0 += 1;
        if self.0 > MAX_TENTATIVE_COLLISIONS {
            CAPPED_RAYS.fetch_add(1, Ordering::Relaxed);
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
    let k = medium.sigma_t_unit();
    let mut tr = Rgb::WHITE;
    let mut tally = Tally::default();
    let mut budget = Budget(0);
    for seg in segments {
        if seg.sigma_maj < rate {
            if !ratio_segment(medium, &seg, ray, &mut tr, &mut budget, &mut tally, sampler) {
                return tr;
            }
            continue;
        }
        for span in medium.voxels(o, d, seg.t0, seg.t1) {
            if !budget.take() {
                return Rgb::BLACK;
            }
            tally.voxel();
            let len = span.t1 - span.t0;
            if span.min_corner < 0.0 {
                // The lookup's clamp to 0 makes the density no cubic here: ratio tracking
                // against the cell's own bound.
                let maj = span_majorant(&span, k.max_channel());
                let mut t = span.t0;
                loop {
                    t += exp_target(sampler) / maj;
                    if t >= span.t1 {
                        break;
                    }
                    if !budget.take() {
                        return Rgb::BLACK;
                    }
                    let sigma_t = k * span.density.eval((t - span.t0) / len).max(0.0);
                    tally.add(sigma_t.max_channel(), maj);
                    tr *= Rgb::WHITE - sigma_t / maj;
                    if negligible(tr) {
                        return tr;
                    }
                    if !roulette(&mut tr, sampler) {
                        return Rgb::BLACK;
                    }
                }
                continue;
            }
            tr *= k.depth_over(len * span.density.integral(1.0)).exp_neg();
            if negligible(tr) {
                return tr;
            }
            if !roulette(&mut tr, sampler) {
                return Rgb::BLACK;
            }
        }
    }
    tr
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
            io.exact_segment(medium.voxels(o, d, seg.t0, seg.t1), sampler)
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
    fn exact_segment(
        &mut self,
        spans: impl Iterator<Item = VoxelSpan>,
        sampler: &mut Sampler,
    ) -> Flight {
        let k = self.medium.sigma_t_unit().max_channel();
        // Target in units of density × length (k is grey here).
        let mut target = exp_target(sampler) / k;
        for span in spans {
            if !self.budget.take() {
                return self.capped();
            }
            self.tally.voxel();
            if span.min_corner < 0.0 {
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
