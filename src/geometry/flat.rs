//! Small scenes without a BVH: the boxes of runs of primitives, tested in turn.
//!
//! A scene of a few boxes and quads (a ground with some blocks) spends most
//! of a ray's geometry time walking a BVH over the boxes' faces: six flat
//! leaves per box, and the nodes above them. Grouping each shape's
//! consecutive primitives into one run (a box's six faces), and testing
//! every run's bounding box in turn, costs fewer box tests than that walk
//! as long as the runs are few; past [`MAX_FLAT_RUNS`] the BVH takes over.

use crate::math::{Bounds3, Ray};
use glam::Vec4;
use std::ops::Range;

/// Up to this many runs a scene tests each run's box instead of walking a BVH.
pub(super) const MAX_FLAT_RUNS: usize = 12;

/// A run holds at most this many primitives (a box's faces).
const MAX_RUN_LENGTH: usize = 6;

/// The padded boxes of four runs, one lane each, in structure-of-arrays form
/// so that one ray meets all four in the same instructions.
#[derive(Clone, Copy, Debug)]
struct RunBatch {
    min: [Vec4; 3],
    max: [Vec4; 3],
    /// Lanes that hold a run.
    lanes: u32,
}

/// The runs of a small scene's primitives (in traversal order) and their boxes.
#[derive(Clone, Debug, Default)]
pub(super) struct FlatRuns {
    batches: Vec<RunBatch>,
    /// The primitives of each run.
    runs: Vec<Range<u32>>,
}

/// A ray's origin and inverse direction, each axis in all four lanes.
pub(super) struct RayLanes {
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
}

impl RayLanes {
    /// The lanes of `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> RayLanes {
        let inv = ray.direction.recip();
        let o = ray.origin;
        RayLanes {
            origin: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv_dir: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
        }
    }
}

impl FlatRuns {
    /// True when there are no runs (the scene walks a BVH, or has only loose primitives).
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// Calls `visit` with the primitives of every run whose box the ray may
    /// meet within `[0, t_max]`, where `t_max` is what the last call returned
    /// (closest-hit searches shorten it); stops when `visit` returns `None`.
    #[inline]
    pub fn visit(
        &self,
        ray: &RayLanes,
        mut t_max: f32,
        mut visit: impl FnMut(Range<usize>, f32) -> Option<f32>,
    ) {
        for (b, batch) in self.batches.iter().enumerate() {
            let mut mask = batch.may_hit(ray, t_max);
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let run = &self.runs[4 * b + lane];
                match visit(run.start as usize..run.end as usize, t_max) {
                    Some(t) => t_max = t,
                    None => return,
                }
            }
        }
    }
}

impl RunBatch {
    /// The lanes whose box the ray may meet for some t in `[0, t_max]` (slab
    /// tests); a NaN (a ray in one of a padded box's planes, which hold no
    /// primitive) may go either way.
    #[inline]
    fn may_hit(&self, ray: &RayLanes, t_max: f32) -> u32 {
        let mut t_near = Vec4::ZERO;
        let mut t_far = Vec4::splat(t_max);
        for a in 0..3 {
            let ta = (self.min[a] - ray.origin[a]) * ray.inv_dir[a];
            let tb = (self.max[a] - ray.origin[a]) * ray.inv_dir[a];
            t_near = t_near.max(ta.min(tb));
            t_far = t_far.min(ta.max(tb));
        }
        t_near.cmple(t_far).bitmask() & self.lanes
    }
}

/// Runs of the primitives given as (bounds, shape index) in traversal
/// order, each of consecutive primitives of one shape, at most
/// [`MAX_RUN_LENGTH`] long, with their boxes grown by `pad`; `None` as soon
/// as there would be more than [`MAX_FLAT_RUNS`] (a large mesh is not read
/// past its 73rd primitive).
pub(super) fn flat_runs(
    primitives: impl IntoIterator<Item = (Bounds3, u32)>,
    pad: f32,
) -> Option<FlatRuns> {
    let mut runs: Vec<(Range<u32>, Bounds3)> = Vec::new();
    let mut run_shape = u32::MAX;
    for (i, (b, shape)) in primitives.into_iter().enumerate() {
        let i = i as u32;
        match runs.last_mut() {
            Some((run, boxed)) if shape == run_shape && run.len() < MAX_RUN_LENGTH => {
                *boxed = boxed.union(&b);
                run.end = i + 1;
            }
            _ => {
                if runs.len() == MAX_FLAT_RUNS {
                    return None;
                }
                runs.push((i..i + 1, b));
                run_shape = shape;
            }
        }
    }
    let batches = runs
        .chunks(4)
        .map(|chunk| {
            let mut batch = RunBatch {
                min: [Vec4::ZERO; 3],
                max: [Vec4::ZERO; 3],
                lanes: (1 << chunk.len()) - 1,
            };
            for (lane, (_, b)) in chunk.iter().enumerate() {
                for a in 0..3 {
                    batch.min[a][lane] = b.min[a] - pad;
                    batch.max[a][lane] = b.max[a] + pad;
                }
            }
            batch
        })
        .collect();
    Some(FlatRuns {
        batches,
        runs: runs.into_iter().map(|(run, _)| run).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn unit_box(at: f32) -> Bounds3 {
        Bounds3::new(Vec3::splat(at), Vec3::splat(at + 1.0))
    }

    /// The runs `visit` offers along `ray` up to `t_max`, as primitive ranges.
    fn visited(runs: &FlatRuns, ray: &Ray, t_max: f32) -> Vec<Range<usize>> {
        let mut seen = Vec::new();
        runs.visit(&RayLanes::new(ray), t_max, |run, t| {
            seen.push(run);
            Some(t)
        });
        seen
    }

    /// Consecutive primitives of one shape share a run, up to six; a new
    /// shape starts one; past the limit of runs there is none.
    #[test]
    fn runs_group_a_shapes_consecutive_primitives() {
        let bounds: Vec<Bounds3> = (0..9).map(|i| unit_box(i as f32)).collect();
        let shapes = [0, 0, 0, 0, 0, 0, 0, 1, 0];
        let runs = flat_runs(bounds.iter().copied().zip(shapes), 0.0).unwrap();
        assert_eq!(runs.runs, vec![0..6, 6..7, 7..8, 8..9]);
        assert_eq!(runs.batches.len(), 1);
        assert_eq!(runs.batches[0].lanes, 0b1111);
        assert_eq!(runs.batches[0].max[1][0], 6.0);
        let many: Vec<u32> = (0..MAX_FLAT_RUNS as u32 + 1).collect();
        let boxes = vec![unit_box(0.0); many.len()];
        assert!(flat_runs(boxes.iter().copied().zip(many.iter().copied()), 0.0).is_none());
        let most = flat_runs(
            boxes[1..].iter().copied().zip(many[1..].iter().copied()),
            0.0,
        )
        .unwrap();
        assert_eq!(most.batches.len(), MAX_FLAT_RUNS.div_ceil(4));
    }

    /// The box test keeps rays that meet a box within `[0, t_max]`, rays
    /// starting inside it and rays along an axis, and drops the others; a
    /// run the last visit ends stops the walk.
    #[test]
    fn the_box_test_keeps_the_rays_that_meet_the_box() {
        let bounds: Vec<Bounds3> = (0..5).map(|i| unit_box(2.0 + 3.0 * i as f32)).collect();
        let runs = flat_runs(bounds.iter().copied().zip(0..), 0.0).unwrap();
        let seen =
            |o: Vec3, d: Vec3, t_max: f32| visited(&runs, &Ray::new(o, d.normalize()), t_max);
        let toward = Vec3::new(1.0, 1.0, 1.0);
        assert_eq!(
            seen(Vec3::ZERO, toward, 100.0),
            vec![0..1, 1..2, 2..3, 3..4, 4..5]
        );
        assert_eq!(
            seen(Vec3::ZERO, toward, 3.0),
            vec![],
            "stops short of the box"
        );
        assert_eq!(seen(Vec3::ZERO, toward, 9.0), vec![0..1, 1..2]);
        assert_eq!(
            seen(Vec3::ZERO, -toward, 100.0),
            vec![],
            "behind the origin"
        );
        assert_eq!(
            seen(Vec3::splat(14.5), -toward, 0.1),
            vec![4..5],
            "starts inside"
        );
        let along = seen(Vec3::new(5.5, 5.5, 0.0), Vec3::Z, 100.0);
        assert_eq!(along, vec![1..2], "along an axis");
        assert_eq!(seen(Vec3::new(5.5, 7.0, 0.0), Vec3::Z, 100.0), vec![]);
        let mut first = Vec::new();
        runs.visit(
            &RayLanes::new(&Ray::new(Vec3::ZERO, toward.normalize())),
            100.0,
            |run, _| {
                first.push(run);
                None
            },
        );
        assert_eq!(first, vec![0..1]);
    }
}
