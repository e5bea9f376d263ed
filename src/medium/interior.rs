//! Media bounded by shapes: a homogeneous or grid medium that exists only
//! inside a closed shape (`[[shape]] interior = { ... }`).
//!
//! ```toml
//! [[shape]]
//! type = "mesh"
//! file = "glass.obj"
//! material = { type = "dielectric", ior = 1.5 }   # omit for an index-matched boundary
//! interior = { type = "vdb", file = "smoke.vdb", density_scale = 20.0 }
//! ```
//!
//! # Mechanism
//!
//! A shape-masked medium is an ordinary medium (its coefficients are those
//! of the content) whose extent along a ray is the set of intervals inside
//! the shape: [`ShapeMask::intervals`] finds the ray's crossings with the
//! surface and keeps the stretches between an entering and the next leaving
//! crossing (for a mesh, the facing of each crossing says which; a sphere or
//! box has one interval in closed form). The content's majorant segments are
//! clipped to those intervals ([`MaskedMajorants`]), so tracking places
//! tentative collisions only inside the shape, and the content's majorant,
//! which bounds σt everywhere, still bounds it on every clipped piece: delta,
//! ratio and residual ratio tracking stay unbiased. Shadow rays estimate
//! transmittance over the same clipped segments (or, for homogeneous content,
//! in closed form over the same intervals), so next-event estimation sees the
//! same extent as free flights.
//!
//! The boundary is either index-matched (the shape has no material and is
//! not added to the surfaces: rays pass through it unchanged) or a dielectric
//! (the shape is also a glass surface: rays refract in and out, and, as for
//! any dielectric, shadow rays are blocked by it; light reaches the medium
//! inside through sampled refractions).
//!
//! A masked medium is one more entry of the scene's media list: it overlaps
//! world-space `[[medium]]` entries and other interiors additively, like any
//! two media (decomposition tracking over each one's own segments).
//!
//! # The crossing limit
//!
//! A ray keeps at most [`MAX_CROSSINGS`] crossings (the nearest), in a fixed
//! array: no allocation per ray. When a ray crosses a mesh more often than
//! that before `t_max`, the part of it past the last kept crossing is taken
//! as outside the shape, and the query is counted ([`take_thread_truncated_queries`]);
//! the render summary reports the count, so the bias is never silent.

use super::{GridMedium, HomogeneousMedium, MajorantSegment, MediumProperties, Region};
use crate::geometry::closed::{ClosedMesh, MAX_CROSSINGS};
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};
use std::cell::Cell;
use std::sync::Arc;

/// Most inside-intervals of one ray: every pair of kept crossings, plus a start inside.
pub const MAX_INTERVALS: usize = MAX_CROSSINGS / 2 + 1;

thread_local! {
    // Interval queries cut short by [`MAX_CROSSINGS`] on this thread: per
    // thread, so a render counts only its own rays (like the tracking counts).
    static TRUNCATED: Cell<u64> = const { Cell::new(0) };
}

/// Takes (and resets) this thread's count of queries cut short by the crossing limit.
pub fn take_thread_truncated_queries() -> u64 {
    TRUNCATED.with(|n| n.replace(0))
}

/// The closed shape a medium is masked by.
#[derive(Clone, Debug)]
pub enum ShapeMask {
    /// A sphere or a box (one interval per ray, in closed form).
    Region(Region),
    /// A closed triangle mesh.
    Mesh(Arc<ClosedMesh>),
}

/// The ray-parameter intervals inside a shape, increasing and disjoint.
#[derive(Clone, Copy, Debug)]
pub struct Intervals {
    spans: [(f32, f32); MAX_INTERVALS],
    len: usize,
}

impl Intervals {
    const EMPTY: Intervals = Intervals {
        spans: [(0.0, 0.0); MAX_INTERVALS],
        len: 0,
    };

    fn push(&mut self, a: f32, b: f32) {
        if a < b && self.len < MAX_INTERVALS {
            self.spans[self.len] = (a, b);
            self.len += 1;
        }
    }

    /// The intervals as a slice.
    pub fn as_slice(&self) -> &[(f32, f32)] {
        &self.spans[..self.len]
    }

    /// Total length of the intervals within `[t0, t1]`.
    pub fn length_within(&self, t0: f32, t1: f32) -> f32 {
        self.as_slice()
            .iter()
            .map(|&(a, b)| (b.min(t1) - a.max(t0)).max(0.0))
            .sum()
    }
}

impl ShapeMask {
    /// The intervals of `[0, t_max]` of `ray` inside the shape.
    pub fn intervals(&self, ray: &Ray, t_max: f32) -> Intervals {
        let mut out = Intervals::EMPTY;
        match self {
            ShapeMask::Region(region) => {
                if let Some((a, b)) = region.interval(ray, t_max) {
                    out.push(a, b);
                }
            }
            ShapeMask::Mesh(mesh) => {
                let c = mesh.crossings(ray);
                let kept = &c.t[..c.len];
                let mut inside = c.starts_inside();
                let mut start = 0.0f32;
                for (t, enters, leaves) in c.groups() {
                    if t >= t_max {
                        break;
                    }
                    // A group that does not change the state is a duplicate
                    // (a ray through an edge hits both triangles) or passes
                    // along the surface (both kinds at one t): skipped.
                    if enters == leaves {
                        continue;
                    }
                    if enters && !inside {
                        start = t;
                        inside = true;
                    } else if leaves && inside {
                        out.push(start, t);
                        inside = false;
                    }
                }
                let truncated = c.overflow && kept.last().is_some_and(|&last| last < t_max);
                if truncated {
                    TRUNCATED.with(|n| n.set(n.get() + 1));
                }
                if inside {
                    let end = if truncated { kept[c.len - 1] } else { t_max };
                    out.push(start, end);
                }
            }
        }
        out
    }

    /// True when world point `p` lies inside the shape.
    pub fn contains(&self, p: Vec3) -> bool {
        match self {
            ShapeMask::Region(region) => region.contains(p),
            ShapeMask::Mesh(mesh) => mesh.contains(p),
        }
    }
}

/// What fills a shape.
#[derive(Clone, Debug)]
pub enum InteriorContent {
    /// Constant coefficients (its region is all space; the mask bounds it).
    Homogeneous(HomogeneousMedium),
    /// A grid (VDB) medium, masked by the shape.
    Grid(Arc<GridMedium>),
}

/// A medium that exists only inside a closed shape.
#[derive(Clone, Debug)]
pub struct InteriorMedium {
    /// The medium's coefficients.
    pub content: InteriorContent,
    /// The shape bounding it.
    pub mask: ShapeMask,
}

impl InteriorMedium {
    /// Coefficients at `p`: the content's inside the shape, zero outside.
    pub fn properties(&self, p: Vec3, time: f32) -> MediumProperties {
        let props = match &self.content {
            InteriorContent::Homogeneous(m) => m.properties(p),
            InteriorContent::Grid(m) => m.properties_at(p, time),
        };
        if self.mask.contains(p) {
            props
        } else {
            MediumProperties {
                sigma_a: Rgb::BLACK,
                sigma_s: Rgb::BLACK,
                ..props
            }
        }
    }

    /// The content's majorant segments clipped to the inside of the shape.
    pub fn majorants(&self, ray: &Ray, t_max: f32) -> MaskedMajorants<'_> {
        let intervals = self.mask.intervals(ray, t_max);
        let t_end = intervals.as_slice().last().map_or(0.0, |s| s.1);
        let inner = match &self.content {
            InteriorContent::Homogeneous(m) => MaskedInner::Single(m.majorant(ray, t_end)),
            InteriorContent::Grid(m) => MaskedInner::Grid(m.majorants(ray, t_end)),
        };
        MaskedMajorants {
            inner,
            intervals,
            index: 0,
            pending: None,
        }
    }

    /// Optical depth over `[t0, t1]` in closed form (homogeneous content only).
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> Option<Rgb> {
        match &self.content {
            InteriorContent::Homogeneous(m) => {
                let length = self.mask.intervals(ray, t1).length_within(t0, t1);
                Some(m.sigma_t().depth_over(length))
            }
            InteriorContent::Grid(_) => None,
        }
    }
}

/// The content's own majorant segments, before clipping.
#[derive(Clone, Debug)]
enum MaskedInner<'a> {
    Single(Option<MajorantSegment>),
    Grid(super::grid::GridMajorants<'a>),
}

impl MaskedInner<'_> {
    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            MaskedInner::Single(s) => s.take(),
            MaskedInner::Grid(g) => g.next(),
        }
    }
}

/// Majorant segments of a content clipped to the intervals inside its shape.
#[derive(Clone, Debug)]
pub struct MaskedMajorants<'a> {
    inner: MaskedInner<'a>,
    intervals: Intervals,
    index: usize,
    /// A content segment reaching past the current interval, to clip against the next.
    pending: Option<MajorantSegment>,
}

impl Iterator for MaskedMajorants<'_> {
    type Item = MajorantSegment;
    fn next(&mut self) -> Option<MajorantSegment> {
        loop {
            let &(a, b) = self.intervals.as_slice().get(self.index)?;
            let seg = match self.pending.take() {
                Some(s) => s,
                None => self.inner.next()?,
            };
            if seg.t1 <= a {
                continue;
            }
            if seg.t0 >= b {
                self.index += 1;
                self.pending = Some(seg);
                continue;
            }
            let t0 = seg.t0.max(a);
            let t1 = seg.t1.min(b);
            if seg.t1 > b {
                self.index += 1;
                self.pending = Some(seg);
            }
            return Some(MajorantSegment {
                t0,
                t1,
                sigma_maj: seg.majorant_at(t0),
                ..seg
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(t0: f32, t1: f32, sigma_maj: f32) -> MajorantSegment {
        MajorantSegment {
            t0,
            t1,
            sigma_maj,
            decay: 0.0,
            sigma_control: Rgb::BLACK,
        }
    }

    /// A ray through 20 cubes in a row crosses the mesh 40 times: the
    /// 32 nearest crossings are kept, the 16 cubes they bound are inside, the
    /// rest of the ray is taken as outside, and the query is counted on this
    /// thread (from outside the row or from inside its first cube); a query
    /// ending before the last kept crossing is whole and not counted.
    #[test]
    fn a_ray_past_the_crossing_limit_is_cut_and_counted() {
        use crate::geometry::{closed::tests::cube, Primitive};
        let cubes: Vec<Primitive> = (0..20)
            .flat_map(|k| {
                let offset = Vec3::new(3.0 * k as f32, 0.0, 0.0);
                cube(true).into_iter().map(move |tri| match tri {
                    Primitive::Triangle { p, n } => Primitive::Triangle {
                        p: p.map(|v| v + offset),
                        n,
                    },
                    other => other,
                })
            })
            .collect();
        let mask = ShapeMask::Mesh(Arc::new(ClosedMesh::new(cubes).expect("closed")));
        // Cube k spans x in [3k − 1, 3k + 1]: the ray is inside it for t in [3k + 2, 3k + 4].
        let ray = Ray::new(Vec3::new(-3.0, 0.1, 0.2), Vec3::X);
        take_thread_truncated_queries();
        let cut = mask.intervals(&ray, 1000.0);
        assert_eq!(take_thread_truncated_queries(), 1);
        assert_eq!(cut.as_slice().len(), MAX_CROSSINGS / 2);
        assert_eq!(cut.as_slice()[0], (2.0, 4.0), "outside at the origin");
        let last = cut.as_slice()[MAX_CROSSINGS / 2 - 1];
        assert!(
            (last.0 - 47.0).abs() < 1e-4 && (last.1 - 49.0).abs() < 1e-4,
            "{last:?}"
        );
        // From inside the first cube the 32nd crossing enters the 17th cube:
        // the cut leaves nothing of it.
        let from_inside = Ray::new(Vec3::new(0.0, 0.1, 0.2), Vec3::X);
        let cut = mask.intervals(&from_inside, 1000.0);
        assert_eq!(take_thread_truncated_queries(), 1);
        assert_eq!(cut.as_slice().len(), MAX_CROSSINGS / 2);
        assert_eq!(cut.as_slice()[0], (0.0, 1.0));
        assert_eq!(cut.as_slice()[MAX_CROSSINGS / 2 - 1], (44.0, 46.0));
        let whole = mask.intervals(&ray, 45.0);
        assert_eq!(take_thread_truncated_queries(), 0);
        assert_eq!(whole.as_slice().len(), 15);
        assert_eq!(whole.as_slice()[14], (44.0, 45.0));
    }

    /// A ray through the diagonal edges of two faces of a cube hits both
    /// triangles of each: the second crossing of each pair changes nothing
    /// (the ray is inside for t in [2, 4], from outside or from inside).
    #[test]
    fn a_crossing_through_an_edge_counts_once() {
        use crate::geometry::closed::tests::cube;
        let mask = ShapeMask::Mesh(Arc::new(ClosedMesh::new(cube(true)).expect("closed")));
        // The faces z = ±1 are cut along their diagonals x = y.
        let ray = Ray::new(Vec3::new(0.3, 0.3, -3.0), Vec3::Z);
        let ShapeMask::Mesh(mesh) = &mask else {
            unreachable!()
        };
        assert_eq!(mesh.crossings(&ray).len, 4, "both triangles of each face");
        take_thread_truncated_queries();
        assert_eq!(mask.intervals(&ray, 10.0).as_slice(), &[(2.0, 4.0)]);
        assert_eq!(
            take_thread_truncated_queries(),
            0,
            "four crossings: none cut"
        );
        let from_inside = Ray::new(Vec3::new(0.3, 0.3, 0.0), Vec3::Z);
        assert_eq!(mask.intervals(&from_inside, 10.0).as_slice(), &[(0.0, 1.0)]);
    }

    /// A content segment that starts past an interval moves on to the
    /// interval it meets.
    #[test]
    fn a_segment_past_an_interval_is_clipped_to_the_next() {
        let mut intervals = Intervals::EMPTY;
        intervals.push(1.0, 2.0);
        intervals.push(3.0, 6.0);
        intervals.push(8.0, 9.0);
        let clipped = MaskedMajorants {
            inner: MaskedInner::Single(Some(segment(4.0, 10.0, 2.0))),
            intervals,
            index: 0,
            pending: None,
        };
        let got: Vec<(f32, f32)> = clipped.map(|s| (s.t0, s.t1)).collect();
        assert_eq!(got, vec![(4.0, 6.0), (8.0, 9.0)]);
    }

    #[test]
    fn clipping_splits_segments_across_intervals() {
        let mut intervals = Intervals::EMPTY;
        intervals.push(1.0, 2.0);
        intervals.push(3.0, 6.0);
        let clipped = MaskedMajorants {
            inner: MaskedInner::Single(Some(segment(0.0, 10.0, 2.0))),
            intervals,
            index: 0,
            pending: None,
        };
        let got: Vec<(f32, f32)> = clipped.map(|s| (s.t0, s.t1)).collect();
        assert_eq!(got, vec![(1.0, 2.0), (3.0, 6.0)]);
        assert_eq!(intervals.length_within(1.5, 4.0), 1.5);
    }
}
