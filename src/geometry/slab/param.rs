//! The parametrisation of lines by six two-plane slabs, and its grid.
//!
//! A line is filed under the axis `a` along which its direction is largest
//! and the sign of that component: six slabs, one per face the line can leave
//! the box by. With `b`, `c` the next two axes (cyclically), a line of slab
//! `(a, σ)` is `(u, v, s, t)`:
//!
//! - `(u, v)` ∈ [0, 1]²: where it crosses the box's mid-plane `a = centre_a`,
//!   over `[lo_b - e_a/2, hi_b + e_a/2] × [lo_c - e_a/2, hi_c + e_a/2]`
//!   (every line of slope ≤ 1 that meets the box crosses the mid-plane there);
//! - `(s, t)` ∈ [-1, 1]²: its slopes `d_b/|d_a|`, `d_c/|d_a|`, that is where it
//!   crosses the plane one unit further along `σ·a`, relative to `(u, v)`.
//!
//! The grid has `spatial` nodes per position axis and `angular` per slope
//! axis, edges included: record `(k, iu, iv, is, it)` is the line through
//! `u = iu/(spatial-1)`, ..., `s = -1 + 2·is/(angular-1)`, ....

use crate::math::{Bounds3, Vec3};

/// Nodes per axis of the grid of recorded lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    /// Nodes per position axis (u, v), ≥ 2.
    pub spatial: u32,
    /// Nodes per slope axis (s, t), ≥ 2.
    pub angular: u32,
}

impl Grid {
    /// Records in the six slabs: 6·spatial²·angular².
    pub fn records(&self) -> u64 {
        let s = self.spatial as u64;
        let a = self.angular as u64;
        6 * s * s * a * a
    }
}

/// The grid of lines of one box.
#[derive(Clone, Copy, Debug)]
pub struct Param {
    lo: Vec3,
    hi: Vec3,
    grid: Grid,
}

/// Where a line falls in the grid: its slab and continuous node coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPoint {
    /// Slab `2·a + (σ < 0)`.
    pub slab: usize,
    /// Node coordinates `(u, v)` in `[0, spatial-1]`, `(s, t)` in `[0, angular-1]`.
    pub x: [f32; 4],
}

impl Param {
    /// The lines of the box `bounds` on `grid`.
    pub fn new(bounds: Bounds3, grid: Grid) -> Param {
        Param {
            lo: bounds.min,
            hi: bounds.max,
            grid,
        }
    }

    /// The box.
    pub fn bounds(&self) -> Bounds3 {
        Bounds3::new(self.lo, self.hi)
    }

    /// The grid.
    pub fn grid(&self) -> Grid {
        self.grid
    }

    /// The flat index of record `(slab, [iu, iv, is, it])`.
    #[inline]
    pub fn index(&self, slab: usize, i: [u32; 4]) -> usize {
        let (s, a) = (self.grid.spatial as usize, self.grid.angular as usize);
        (((slab * s + i[0] as usize) * s + i[1] as usize) * a + i[2] as usize) * a + i[3] as usize
    }

    /// The slab and node indices of flat record `index`.
    pub fn node(&self, index: u64) -> (usize, [u32; 4]) {
        let (s, a) = (self.grid.spatial as u64, self.grid.angular as u64);
        let it = index % a;
        let is = (index / a) % a;
        let iv = (index / (a * a)) % s;
        let iu = (index / (a * a * s)) % s;
        let slab = index / (a * a * s * s);
        (slab as usize, [iu as u32, iv as u32, is as u32, it as u32])
    }

    /// The recorded line of flat record `index`: a point on it (on the
    /// mid-plane) and its unit direction, the way light leaves the box.
    pub fn line(&self, index: u64) -> (Vec3, Vec3) {
        let (slab, i) = self.node(index);
        let (a, sign) = (slab / 2, if slab % 2 == 0 { 1.0 } else { -1.0 });
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let frac = |k: u32, n: u32| k as f32 / (n - 1) as f32;
        let e = self.hi - self.lo;
        let mut p = Vec3::ZERO;
        p[a] = 0.5 * (self.lo[a] + self.hi[a]);
        p[b] = self.lo[b] - 0.5 * e[a] + frac(i[0], self.grid.spatial) * (e[b] + e[a]);
        p[c] = self.lo[c] - 0.5 * e[a] + frac(i[1], self.grid.spatial) * (e[c] + e[a]);
        let mut d = Vec3::ZERO;
        d[a] = sign;
        d[b] = -1.0 + 2.0 * frac(i[2], self.grid.angular);
        d[c] = -1.0 + 2.0 * frac(i[3], self.grid.angular);
        (p, d.normalize())
    }

    /// Where the line through `origin` along `dir` (any length, not zero)
    /// falls in the grid; coordinates clamped to the grid (a line meeting
    /// the box is always inside it).
    #[inline]
    pub fn locate(&self, origin: Vec3, dir: Vec3) -> GridPoint {
        let m = dir.abs();
        let a = if m.x >= m.y && m.x >= m.z {
            0
        } else if m.y >= m.z {
            1
        } else {
            2
        };
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let slab = 2 * a + usize::from(dir[a] < 0.0);
        let e = self.hi - self.lo;
        let t = (0.5 * (self.lo[a] + self.hi[a]) - origin[a]) / dir[a];
        let p = origin + dir * t;
        let u = (p[b] - self.lo[b] + 0.5 * e[a]) / (e[b] + e[a]);
        let v = (p[c] - self.lo[c] + 0.5 * e[a]) / (e[c] + e[a]);
        let s = 0.5 * (dir[b] / m[a] + 1.0);
        let tt = 0.5 * (dir[c] / m[a] + 1.0);
        let ns = (self.grid.spatial - 1) as f32;
        let na = (self.grid.angular - 1) as f32;
        let clamp = |x: f32, n: f32| if x.is_nan() { 0.0 } else { x.clamp(0.0, n) };
        GridPoint {
            slab,
            x: [
                clamp(u * ns, ns),
                clamp(v * ns, ns),
                clamp(s * na, na),
                clamp(tt * na, na),
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every recorded line is found again at its own node, with integer coordinates.
    #[test]
    fn recorded_lines_locate_at_their_nodes() {
        let b = Bounds3::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(0.5, 2.0, 3.0));
        let p = Param::new(
            b,
            Grid {
                spatial: 4,
                angular: 4,
            },
        );
        for index in 0..p.grid().records() {
            let (o, d) = p.line(index);
            let g = p.locate(o - 3.0 * d, d);
            let (slab, i) = p.node(index);
            assert_eq!(p.index(slab, i) as u64, index);
            // A slope of exactly ±1 ties two axes and the lookup files the
            // line under the first of them: only lines without a tie are checked here.
            let a = slab / 2;
            let m = d.abs();
            if (0..3).all(|k| k == a || m[k] < m[a]) {
                assert_eq!(g.slab, slab, "record {index}");
                for k in 0..4 {
                    let off = (g.x[k] - i[k] as f32).abs();
                    assert!(off < 1e-3, "record {index}: {g:?} vs {i:?}");
                }
            }
        }
    }
}
