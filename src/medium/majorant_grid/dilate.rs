//! Dilation of a majorant grid for velocity motion blur: max and min filters
//! over each cell's (2k + 1)³ neighbourhood.
//!
//! Each axis is one pass of a running max (min) over every line of cells,
//! by van Herk and Gil–Werman's method: the line, padded by k identity
//! values on both ends, is cut into blocks of 2k + 1 cells, and a window of
//! that length spans the end of one block and the start of the next, so its
//! extremum is that of a suffix and a prefix extremum computed once per
//! block. Three operations per cell whatever k, where the direct filter
//! took 2k + 1: a medium displaced by hundreds of cells costs no more to
//! dilate than a still one. Max and min are exact and order-free, so the
//! result is the direct filter's to the bit.

use super::MajorantGrid;
use glam::{IVec3, Vec3};

impl MajorantGrid {
    /// The bounds over every point within `k` cells (per axis) of each cell:
    /// max and min filters over the (2k + 1)³ neighbourhood, separable by axis.
    ///
    /// Neighbours outside the grid count as density 0 for the minimum, and so
    /// do cells not inside `inside` (an index box beyond which the density
    /// is 0 whatever the grid stores). Used by velocity motion blur; `k = 0`
    /// returns the grid unchanged.
    pub fn dilated(mut self, k: IVec3, inside: (Vec3, Vec3)) -> MajorantGrid {
        if k == IVec3::ZERO {
            return self;
        }
        let d = self.dims;
        let mut i = 0;
        for z in 0..d.z {
            for y in 0..d.y {
                for x in 0..d.x {
                    let lo = self.origin + IVec3::new(x, y, z).as_vec3() * self.cell;
                    let hi = lo + self.cell;
                    if lo.cmplt(inside.0).any() || hi.cmpgt(inside.1).any() {
                        self.min[i] = 0.0;
                    }
                    i += 1;
                }
            }
        }
        for axis in 0..3 {
            filter_axis(d, &mut self.max, axis, k[axis], Extremum::Max);
            filter_axis(d, &mut self.min, axis, k[axis], Extremum::Min);
        }
        self
    }
}

/// One axis of the separable neighbourhood filter over every line of cells
/// of a `d` grid, in place (each line is read into a buffer first).
fn filter_axis(d: IVec3, values: &mut [f32], axis: usize, r: i32, op: Extremum) {
    if r <= 0 {
        return;
    }
    let n = d[axis] as usize;
    if axis == 0 {
        // Lines along x are contiguous: one at a time.
        let mut lines = Lines::<1>::new(n, r as usize);
        for start in (0..values.len()).step_by(n) {
            lines.filter(values, (start, 1), 1, op);
        }
        return;
    }
    // Lines along y or z are far apart in memory: filter LANES neighbours
    // in x together, so that every read and write is a contiguous run.
    let (stride, plane) = match axis {
        1 => (d.x as usize, (d.x * d.y) as usize),
        _ => ((d.x * d.y) as usize, d.x as usize),
    };
    let planes = if axis == 1 { d.z } else { d.y } as usize;
    let mut lines = Lines::<LANES>::new(n, r as usize);
    for o in 0..planes {
        for x0 in (0..d.x as usize).step_by(LANES) {
            let used = LANES.min(d.x as usize - x0);
            lines.filter(values, (o * plane + x0, stride), used, op);
        }
    }
}

/// Lines filtered together along y and z.
const LANES: usize = 32;

/// Which extremum a filter takes, and what it takes beyond the grid.
#[derive(Clone, Copy)]
enum Extremum {
    /// The maximum; cells beyond the grid do not count.
    Max,
    /// The minimum; cells beyond the grid count as density 0.
    Min,
}

impl Extremum {
    /// The value that changes no extremum, padding the line's ends.
    fn identity(self) -> f32 {
        match self {
            Extremum::Max => f32::NEG_INFINITY,
            Extremum::Min => f32::INFINITY,
        }
    }
}

/// Buffers for filtering up to `W` neighbouring lines of `n` cells with
/// radius `r` together (cell-major: a cell's `W` lanes side by side),
/// reused across lines.
struct Lines<const W: usize> {
    n: usize,
    /// The radius asked for: windows reaching past the grid take the outside value.
    r: usize,
    /// The radius used: beyond n every window holds the whole line anyway.
    pad: usize,
    /// The lines, padded by `pad` identity values at each end.
    cells: Vec<[f32; W]>,
    /// Extremum from the start of each block to each cell (padded coordinates).
    prefix: Vec<[f32; W]>,
    /// Extremum from each cell to the end of its block.
    suffix: Vec<[f32; W]>,
}

impl<const W: usize> Lines<W> {
    fn new(n: usize, r: usize) -> Lines<W> {
        let pad = r.min(n);
        let len = n + 2 * pad;
        Lines {
            n,
            r,
            pad,
            cells: vec![[0.0; W]; len],
            prefix: vec![[0.0; W]; len],
            suffix: vec![[0.0; W]; len],
        }
    }

    /// Filters `used` lines of `values` in place: line l's cell i at
    /// `start + i·stride + l`.
    fn filter(&mut self, values: &mut [f32], at: (usize, usize), used: usize, op: Extremum) {
        // Values are never NaN (finite densities, ±∞ padding), so a plain
        // comparison is the extremum, and it vectorises where f32::max does not.
        match op {
            Extremum::Max => self.run(values, at, used, op, |a, b| if b > a { b } else { a }),
            Extremum::Min => self.run(values, at, used, op, |a, b| if b < a { b } else { a }),
        }
    }

    /// [`Lines::filter`] with the extremum as a function the compiler sees.
    fn run(
        &mut self,
        values: &mut [f32],
        (start, stride): (usize, usize),
        used: usize,
        op: Extremum,
        of: impl Fn(f32, f32) -> f32 + Copy,
    ) {
        let (n, pad) = (self.n, self.pad);
        let block = 2 * pad + 1;
        self.cells.fill([op.identity(); W]);
        // Element loops, not copy_from_slice: a memcpy call per cell costs
        // more than the filter when lines are one lane wide.
        for i in 0..n {
            let from = start + i * stride;
            for (c, v) in self.cells[pad + i]
                .iter_mut()
                .zip(&values[from..from + used])
            {
                *c = *v;
            }
        }
        let lanes = |m: &mut [f32; W], c: &[f32; W]| {
            for (m, c) in m.iter_mut().zip(c) {
                *m = of(*m, *c);
            }
        };
        for (cells, prefix) in self.cells.chunks(block).zip(self.prefix.chunks_mut(block)) {
            let mut m = [op.identity(); W];
            for (c, p) in cells.iter().zip(prefix) {
                lanes(&mut m, c);
                *p = m;
            }
        }
        for (cells, suffix) in self.cells.chunks(block).zip(self.suffix.chunks_mut(block)) {
            let mut m = [op.identity(); W];
            for (c, s) in cells.iter().zip(suffix).rev() {
                lanes(&mut m, c);
                *s = m;
            }
        }
        for i in 0..n {
            // The window of cell i is padded cells i ..= i + 2·pad.
            let mut m = self.suffix[i];
            lanes(&mut m, &self.prefix[i + 2 * pad]);
            if matches!(op, Extremum::Min) && (i < self.r || i + self.r >= n) {
                m.iter_mut().for_each(|v| *v = of(*v, 0.0));
            }
            let to = start + i * stride;
            for (o, v) in values[to..to + used].iter_mut().zip(&m) {
                *o = *v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The direct filter: each cell's extremum over its clipped window, then the outside value.
    fn direct(values: &[f32], r: usize, op: Extremum) -> Vec<f32> {
        let n = values.len();
        (0..n)
            .map(|i| {
                let lo = i.saturating_sub(r);
                let hi = (i + r).min(n - 1);
                let of = |a: f32, b: f32| match op {
                    Extremum::Max => a.max(b),
                    Extremum::Min => a.min(b),
                };
                let mut m = values[lo..=hi].iter().copied().fold(op.identity(), of);
                if matches!(op, Extremum::Min) && (i < r || i + r >= n) {
                    m = m.min(0.0);
                }
                m
            })
            .collect()
    }

    #[test]
    fn running_extrema_equal_the_direct_filter_for_every_radius() {
        let n = 23;
        let value = |i: usize, lane: usize| ((i * 7919 + lane * 104729) % 31) as f32 * 0.5 + 0.25;
        let check = |lanes: usize, out: &[f32], r: usize, op: Extremum| {
            for lane in 0..lanes {
                let line: Vec<f32> = (0..n).map(|i| value(i, lane)).collect();
                let got: Vec<f32> = (0..n).map(|i| out[i * lanes + lane]).collect();
                assert_eq!(got, direct(&line, r, op), "r = {r}, lane {lane} of {lanes}");
            }
        };
        for r in [1, 2, 3, 5, 11, 22, 23, 40] {
            for op in [Extremum::Max, Extremum::Min] {
                let mut out: Vec<f32> = (0..n).map(|i| value(i, 0)).collect();
                Lines::<1>::new(n, r).filter(&mut out, (0, 1), 1, op);
                check(1, &out, r, op);
                // Three neighbouring lines (cell i of line l at 3i + l), as along y or z.
                let mut out: Vec<f32> = (0..3 * n).map(|k| value(k / 3, k % 3)).collect();
                Lines::<LANES>::new(n, r).filter(&mut out, (0, 3), 3, op);
                check(3, &out, r, op);
            }
        }
    }
}
