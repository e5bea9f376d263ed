//! The trilinear density along a ray, voxel cell by voxel cell, in closed form.
//!
//! Inside one voxel cell `[i, i + 1]³` (index space, voxel centres at integer
//! ijk) a trilinear lookup reads the same eight corners, and along a straight
//! line it is the product of three linear functions: a cubic in the ray
//! parameter. Its integral (a quartic) is the exact optical depth of the
//! cell's piece of the ray, so transmittance needs no estimator and a free
//! flight can be sampled by inverting it (regular tracking, with the
//! trilinear field integrated exactly). Tracking uses this where a majorant
//! cell is so dense that null collisions would cost more than a walk over its
//! voxels (see `integrator::tracking::exact`).

use glam::{IVec3, Vec3};

use crate::volume::FloatGrid;

/// A density `c0 + c1 w + c2 w² + c3 w³` over the fraction `w ∈ [0, 1]` of a ray's span in one voxel cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cubic(pub [f32; 4]);

impl Cubic {
    /// The trilinear interpolation of `corners` (index `4·dx + 2·dy + dz`) along
    /// the line from local point `a` to `b` (both in `[0, 1]³`).
    #[inline]
    pub fn along(corners: &[f32; 8], a: Vec3, b: Vec3) -> Cubic {
        let e = b - a;
        // Along x: four lines (p0 + p1 w), one per (dy, dz).
        let line = |jk: usize| {
            let (c0, c1) = (corners[jk], corners[4 + jk]);
            let d = c1 - c0;
            [c0 + a.x * d, e.x * d]
        };
        let l = [line(0), line(1), line(2), line(3)];
        // Along y: two quadratics, one per dz.
        let quad = |k: usize| {
            let (l0, l1) = (l[k], l[2 + k]);
            let d = [l1[0] - l0[0], l1[1] - l0[1]];
            [
                l0[0] + a.y * d[0],
                l0[1] + a.y * d[1] + e.y * d[0],
                e.y * d[1],
            ]
        };
        let (q0, q1) = (quad(0), quad(1));
        // Along z: the cubic.
        let d = [q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]];
        Cubic([
            q0[0] + a.z * d[0],
            q0[1] + a.z * d[1] + e.z * d[0],
            q0[2] + a.z * d[2] + e.z * d[1],
            e.z * d[2],
        ])
    }

    /// The density at fraction `w`.
    #[inline]
    pub fn eval(&self, w: f32) -> f32 {
        let c = self.0;
        c[0] + w * (c[1] + w * (c[2] + w * c[3]))
    }

    /// ∫₀ʷ density.
    #[inline]
    pub fn integral(&self, w: f32) -> f32 {
        let c = self.0;
        w * (c[0] + w * (c[1] * 0.5 + w * (c[2] * (1.0 / 3.0) + w * c[3] * 0.25)))
    }

    /// The fraction `w` where ∫₀ʷ density = `target`, for `0 ≤ target ≤ integral(1)`
    /// and a density ≥ 0 on `[0, 1]` (so the integral is monotone).
    ///
    /// Newton's method kept inside a shrinking bracket (bisection when a step
    /// leaves it), to a relative 2⁻²⁰ of the span: well below one voxel's f32 resolution.
    pub fn solve_integral(&self, target: f32) -> f32 {
        self.solve_integral_counted(target).0
    }

    /// [`Self::solve_integral`] and the number of integral evaluations it
    /// took (the work a free flight's exact collision costs).
    fn solve_integral_counted(&self, target: f32) -> (f32, u32) {
        const TOLERANCE: f32 = 1.0 / (1 << 20) as f32;
        let total = self.integral(1.0);
        if total.is_nan() || total <= 0.0 || target <= 0.0 {
            return (0.0, 0);
        }
        if target >= total {
            return (1.0, 0);
        }
        let (mut lo, mut hi) = (0.0f32, 1.0f32);
        let mut w = target / total;
        for step in 1..=40 {
            let f = self.integral(w) - target;
            if f > 0.0 {
                hi = w;
            } else {
                lo = w;
            }
            let slope = self.eval(w);
            let newton = w - f / slope;
            // Converged: checked before the bracket test, which rejects a step
            // onto the bracket's end (w itself, once f is 0 or rounds to it)
            // and would bisect away from the root and back.
            if slope > 0.0 && (newton - w).abs() <= TOLERANCE {
                return (newton.clamp(lo, hi), step);
            }
            let next = if slope > 0.0 && newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - w).abs() <= TOLERANCE || hi - lo <= 0.25 * TOLERANCE {
                return (next.clamp(0.0, 1.0), step);
            }
            w = next;
        }
        (w, 40)
    }
}

/// One voxel cell's piece `[t0, t1]` of a ray, with the density along it.
#[derive(Clone, Copy, Debug)]
pub struct VoxelSpan {
    /// Entry (ray parameter).
    pub t0: f32,
    /// Exit.
    pub t1: f32,
    /// The density over the span's fraction `w = (t - t0) / (t1 - t0)`.
    pub density: Cubic,
    /// Whether some corner is negative, so that the lookup's clamp to 0 acts
    /// and the density is `max(0, cubic)`, not the cubic.
    pub clamped: bool,
    /// Largest corner value (the density is at most this on the span); only
    /// computed where `clamped`, else 0.
    pub max_corner: f32,
}

/// A 3D DDA over unit voxel cells (Amanatides & Woo 1987) along an index-space ray.
#[derive(Clone, Debug)]
pub struct VoxelWalk<'a> {
    grid: &'a FloatGrid,
    /// Whether the grid holds negative values (see [`VoxelSpan::clamped`]).
    may_clamp: bool,
    origin: Vec3,
    dir: Vec3,
    cell: IVec3,
    step: IVec3,
    t: f32,
    t_end: f32,
    t_next: Vec3,
    t_delta: Vec3,
}

impl<'a> VoxelWalk<'a> {
    /// Walks the voxel cells of `grid` crossed by the index-space ray `o + t·d`
    /// over `[t0, t1]`; `may_clamp`: the grid holds negative values.
    pub fn new(
        grid: &'a FloatGrid,
        may_clamp: bool,
        o: Vec3,
        d: Vec3,
        t0: f32,
        t1: f32,
    ) -> VoxelWalk<'a> {
        // The cell of the span's midpoint near t0: a start exactly on a cell plane
        // rounds either way, and the first cell must be the one the ray enters.
        let probe = t0 + ((t1 - t0) * 0.5).min(1e-3 / d.abs().max_element().max(1e-30));
        let cell = (o + d * probe).floor().as_ivec3();
        let step = IVec3::select(d.cmpge(Vec3::ZERO), IVec3::ONE, IVec3::NEG_ONE);
        let mut t_next = Vec3::INFINITY;
        let mut t_delta = Vec3::INFINITY;
        for a in 0..3 {
            if d[a] != 0.0 {
                let plane = (cell[a] + (step[a] > 0) as i32) as f32;
                t_next[a] = (plane - o[a]) / d[a];
                t_delta[a] = 1.0 / d[a].abs();
            }
        }
        VoxelWalk {
            grid,
            may_clamp,
            origin: o,
            dir: d,
            cell,
            step,
            t: t0,
            t_end: t1,
            t_next,
            t_delta,
        }
    }
}

impl Iterator for VoxelWalk<'_> {
    type Item = VoxelSpan;

    #[inline]
    fn next(&mut self) -> Option<VoxelSpan> {
        loop {
            if self.t >= self.t_end {
                return None;
            }
            let (cell, t0, t1) = self.step_cell();
            // A zero-length step (rounding at a cell corner) holds nothing.
            if t1 > t0 {
                return Some(self.span(cell, t0, t1));
            }
        }
    }
}

impl VoxelWalk<'_> {
    /// Moves to the next cell: the one left behind and its `[t0, t1]`.
    #[inline]
    fn step_cell(&mut self) -> (IVec3, f32, f32) {
        let axis = if self.t_next.x < self.t_next.y {
            if self.t_next.x < self.t_next.z {
                0
            } else {
                2
            }
        } else if self.t_next.y < self.t_next.z {
            1
        } else {
            2
        };
        let cell = self.cell;
        let t0 = self.t;
        let plane = self.t_next[axis];
        if plane > self.t_end {
            // The walk stops inside this cell: stay in it, so that `extend_to` goes on from here.
            self.t = self.t_end;
            return (cell, t0, self.t_end.max(t0));
        }
        let t1 = plane.max(t0);
        self.t = t1;
        self.cell[axis] += self.step[axis];
        self.t_next[axis] += self.t_delta[axis];
        (cell, t0, t1)
    }

    /// The span of `cell` over `[t0, t1]`.
    #[inline]
    fn span(&self, cell: IVec3, t0: f32, t1: f32) -> VoxelSpan {
        let corners = self.grid.corners(cell);
        let base = cell.as_vec3();
        // Rounding may put the span's ends a hair outside the cell: clamp, so the
        // cubic stays a convex combination of the corners.
        let a = (self.origin + self.dir * t0 - base).clamp(Vec3::ZERO, Vec3::ONE);
        let b = (self.origin + self.dir * t1 - base).clamp(Vec3::ZERO, Vec3::ONE);
        let mut density = Cubic::along(&corners, a, b);
        if density.0.iter().sum::<f32>().is_nan() {
            // A NaN corner: the lookup's clamp to ≥ 0 turns its NaN into 0 wherever it weighs.
            density = Cubic([0.0; 4]);
        }
        let (clamped, max_corner) = if self.may_clamp && corners.iter().any(|&c| c < 0.0) {
            (true, corners.iter().copied().fold(0.0, f32::max))
        } else {
            (false, 0.0)
        };
        VoxelSpan {
            t0,
            t1,
            density,
            clamped,
            max_corner,
        }
    }

    /// Where the walk is (the start of the next span) and where it stops.
    pub fn reach(&self) -> (f32, f32) {
        (self.t, self.t_end)
    }

    /// Lets the walk go on to `t_end` (a following segment that starts where it stopped).
    pub fn extend_to(&mut self, t_end: f32) {
        self.t_end = t_end;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trilinear(c: &[f32; 8], p: Vec3) -> f32 {
        let mut v = 0.0;
        for (n, &cn) in c.iter().enumerate() {
            let (dx, dy, dz) = ((n >> 2) & 1, (n >> 1) & 1, n & 1);
            let wx = if dx == 1 { p.x } else { 1.0 - p.x };
            let wy = if dy == 1 { p.y } else { 1.0 - p.y };
            let wz = if dz == 1 { p.z } else { 1.0 - p.z };
            v += cn * wx * wy * wz;
        }
        v
    }

    const CORNERS: [f32; 8] = [0.3, 1.7, 0.0, 2.5, 4.0, 0.1, 0.9, 3.3];

    /// The cubic is the trilinear interpolation along the line, and its integral the quadrature of it.
    #[test]
    fn cubic_matches_trilinear_and_its_integral() {
        let (a, b) = (Vec3::new(0.1, 0.95, 0.0), Vec3::new(0.8, 0.05, 1.0));
        let cubic = Cubic::along(&CORNERS, a, b);
        let n = 4000;
        let mut sum = 0.0f64;
        for k in 0..=n {
            let w = k as f32 / n as f32;
            let exact = trilinear(&CORNERS, a + (b - a) * w);
            assert!((cubic.eval(w) - exact).abs() < 1e-5, "at {w}");
            let weight = if k == 0 || k == n { 0.5 } else { 1.0 };
            sum += weight * exact as f64 / n as f64;
        }
        assert!((cubic.integral(1.0) as f64 - sum).abs() < 1e-5);
    }

    /// Inverting the integral returns the fraction that gives each target.
    #[test]
    fn solve_integral_inverts_the_integral() {
        let cubic = Cubic::along(&CORNERS, Vec3::new(0.0, 0.2, 0.9), Vec3::new(1.0, 0.7, 0.1));
        let total = cubic.integral(1.0);
        for k in 0..=50 {
            let target = total * k as f32 / 50.0;
            let w = cubic.solve_integral(target);
            assert!(
                (cubic.integral(w) - target).abs() < 2e-6 * total,
                "{k}: {w}"
            );
        }
        // A flat zero stretch (corners 0) before a ramp.
        let ramp = Cubic([0.0, 0.0, 0.0, 4.0]);
        let w = ramp.solve_integral(0.5);
        assert!(
            (w - 1.0f32.powf(0.25) * 0.5f32.powf(0.25)).abs() < 1e-5,
            "{w}"
        );
    }

    /// The work of an exact collision: Newton's method takes at most 4
    /// evaluations of the integral for any target where the density is
    /// positive (≥ 1 here, along two lines through a cell), not the 20 of
    /// bisection. Before stop 25 a step that landed on the bracket's end
    /// (the root itself, once the integral matched the target) was rejected
    /// and the iteration bisected away and back: up to 22 evaluations.
    #[test]
    fn solve_integral_takes_a_few_newton_steps() {
        let corners = CORNERS.map(|c| c + 1.0);
        let lines = [
            (Vec3::new(0.0, 0.2, 0.9), Vec3::new(1.0, 0.7, 0.1)),
            (Vec3::new(0.1, 0.95, 0.0), Vec3::new(0.8, 0.05, 1.0)),
        ];
        for (a, b) in lines {
            let cubic = Cubic::along(&corners, a, b);
            let total = cubic.integral(1.0);
            for k in 0..=200 {
                let target = total * k as f32 / 200.0;
                let (w, evaluations) = cubic.solve_integral_counted(target);
                assert!(
                    evaluations <= 4,
                    "target {target}: {evaluations} evaluations"
                );
                assert!((cubic.integral(w) - target).abs() < 2e-6 * total);
            }
        }
    }

    /// A density that touches 0 inside the span, (w − a)², and (w − a)²(1 + w):
    /// Newton's slope is 0 or tiny near `a`, so an unguarded step would leave
    /// the span (to ±∞ at a zero, or so far that 40 steps do not come back).
    /// Every first guess `target / total` near `a` and elsewhere still gives
    /// the fraction whose integral is the target, in a few evaluations on average.
    #[test]
    fn solve_integral_survives_a_zero_of_the_density() {
        let (mut total_evaluations, mut solves) = (0, 0);
        for a in [0.25f32, 0.5, 0.75, 0.9] {
            let square = [a * a, -2.0 * a, 1.0, 0.0];
            let times_ramp = [
                square[0],
                square[0] + square[1],
                square[1] + square[2],
                square[2],
            ];
            for c in [square, times_ramp] {
                let cubic = Cubic(c);
                let total = cubic.integral(1.0);
                let guesses = (0..=100).map(|k| k as f32 / 100.0);
                let near_zero = [-1e-3f32, -1e-5, 0.0, 1e-5, 1e-3].map(|d| a + d);
                for guess in guesses.chain(near_zero) {
                    let target = total * guess;
                    let (w, evaluations) = cubic.solve_integral_counted(target);
                    total_evaluations += evaluations;
                    solves += 1;
                    // Within 2⁻¹⁹ of the fraction where the density is steep (the
                    // iteration's stopping step), or of the integral where it is flat.
                    let allowed = 2e-6 * total + cubic.eval(w).abs() / (1 << 19) as f32;
                    assert!(
                        (0.0..=1.0).contains(&w) && (cubic.integral(w) - target).abs() <= allowed,
                        "a = {a}, {c:?}, first guess {guess}: w = {w}"
                    );
                }
            }
        }
        // Newton converges only linearly at a zero of the density, so a few
        // solves take bisection's 20 evaluations; on average about 5.
        let mean = total_evaluations as f32 / solves as f32;
        assert!(mean <= 6.0, "{mean} evaluations a solve");
    }

    /// A walk stopped anywhere (mid-cell too) and extended gives the spans of one whole walk.
    #[test]
    fn extended_walk_matches_one_walk() {
        use crate::volume::GridTransform;
        use glam::DVec3;
        let dims = IVec3::new(12, 10, 9);
        let n = (dims.x * dims.y * dims.z) as usize;
        let values: Vec<f32> = (0..n).map(|i| ((i * 7919) % 101) as f32 / 50.0).collect();
        let t = GridTransform::scale_translate("ScaleMap", DVec3::ONE, DVec3::ZERO).unwrap();
        let grid = FloatGrid::from_dense("d", IVec3::new(-2, 0, -3), dims, &values, t).unwrap();
        let o = Vec3::new(-2.5, 0.3, -2.9);
        let d = Vec3::new(1.0, 0.6, 0.75);
        let depth = |w: &mut VoxelWalk| {
            w.map(|s| (s.t1 - s.t0) * s.density.integral(1.0))
                .sum::<f32>()
        };
        let whole = depth(&mut VoxelWalk::new(&grid, false, o, d, 0.1, 9.0));
        let mut walk = VoxelWalk::new(&grid, false, o, d, 0.1, 2.37);
        let mut split = depth(&mut walk);
        for end in [3.0, 4.111, 6.5, 9.0] {
            walk.extend_to(end);
            split += depth(&mut walk);
        }
        assert!((split - whole).abs() <= 1e-5 * whole, "{split} vs {whole}");
    }
}
