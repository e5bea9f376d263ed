//! A hashed uniform grid over photon positions, rebuilt every pass by a
//! counting sort into buffers that are kept from pass to pass (no
//! allocation per photon, none at all once the buffers have grown).
//!
//! Cells are `2r` wide and each photon is listed in every cell its ball of
//! radius `r` overlaps (at most 2×2×2, each bucket once): every photon within
//! `r` of a point is then in the point's own cell, and a ray visits each cell
//! once, so a point query reads one bucket and a beam query reads the
//! buckets of the cells its segment crosses. A photon met in a crossed cell
//! counts only when its projection on the ray falls inside that cell's span,
//! so it counts once even when hashing puts two crossed cells in one bucket.

use crate::math::{Bounds3, Ray, Vec3};

/// The grid of one pass.
#[derive(Default)]
pub struct Grid {
    hash: Hashing,
    /// Bucket `b` lists `entries[starts[b]..starts[b + 1]]`.
    starts: Vec<u32>,
    entries: Vec<u32>,
    /// Photon bounds grown by the radius (beam queries are clipped to them).
    bounds: Option<Bounds3>,
}

/// Integer cell coordinates.
type Cell = [i32; 3];

/// Most cells across the photons' bounds along an axis: cells are `2r` wide
/// or wider, so a radius far below the scene's size neither makes a beam
/// query walk billions of cells nor pushes cell coordinates past `i32`.
const MAX_CELLS_PER_AXIS: f32 = 4096.0;

/// Most cells a beam query visits (a bound the walk cannot exceed even where
/// rounding keeps its parameter from advancing).
const MAX_WALK_CELLS: usize = 3 * (MAX_CELLS_PER_AXIS as usize + 2);

/// How positions map to buckets.
#[derive(Clone, Copy, Default)]
struct Hashing {
    radius: f32,
    /// Where cell [0, 0, 0] starts.
    origin: Vec3,
    cell: f32,
    /// Table size − 1 (the size is a power of two).
    mask: u32,
}

impl Hashing {
    fn cell_of(&self, p: Vec3) -> Cell {
        let q = (p - self.origin) / self.cell;
        [q.x.floor() as i32, q.y.floor() as i32, q.z.floor() as i32]
    }

    fn bucket(&self, c: Cell) -> u32 {
        let h = (c[0] as u32).wrapping_mul(73_856_093)
            ^ (c[1] as u32).wrapping_mul(19_349_663)
            ^ (c[2] as u32).wrapping_mul(83_492_791);
        h & self.mask
    }

    /// Calls `f` once per distinct bucket of the cells that `p`'s ball overlaps.
    fn for_buckets(&self, p: Vec3, mut f: impl FnMut(usize)) {
        let lo = self.cell_of(p - Vec3::splat(self.radius));
        let hi = self.cell_of(p + Vec3::splat(self.radius));
        let mut seen = [u32::MAX; 8];
        let mut n = 0;
        // Cells are 2r wide: a ball overlaps at most two per axis.
        for x in lo[0]..=hi[0].min(lo[0] + 1) {
            for y in lo[1]..=hi[1].min(lo[1] + 1) {
                for z in lo[2]..=hi[2].min(lo[2] + 1) {
                    let b = self.bucket([x, y, z]);
                    if !seen[..n].contains(&b) {
                        seen[n] = b;
                        n += 1;
                        f(b as usize);
                    }
                }
            }
        }
    }
}

impl Grid {
    /// Rebuilds the grid over `points` for gather radius `radius`.
    pub fn build(&mut self, points: &[Vec3], radius: f32) {
        let table = (2 * points.len()).next_power_of_two().max(1024);
        let bounds = points.iter().fold(None, |bounds: Option<Bounds3>, &p| {
            let ball = Bounds3::new(p - Vec3::splat(radius), p + Vec3::splat(radius));
            Some(bounds.map_or(ball, |a| a.union(&ball)))
        });
        self.bounds = bounds;
        let (origin, span) = bounds.map_or((Vec3::ZERO, 0.0), |b| {
            (b.min, (b.max - b.min).max_element())
        });
        let hash = Hashing {
            radius,
            origin,
            cell: (2.0 * radius).max(span / MAX_CELLS_PER_AXIS),
            mask: table as u32 - 1,
        };
        self.hash = hash;
        let starts = &mut self.starts;
        starts.clear();
        starts.resize(table + 1, 0);
        for &p in points {
            hash.for_buckets(p, |b| starts[b + 1] += 1);
        }
        for b in 0..table {
            starts[b + 1] += starts[b];
        }
        let total = starts[table] as usize;
        let entries = &mut self.entries;
        entries.clear();
        entries.resize(total, 0);
        // Fill each bucket from its end: `starts[b + 1]` counts down to the bucket's start.
        for (i, &p) in points.iter().enumerate().rev() {
            hash.for_buckets(p, |b| {
                starts[b + 1] -= 1;
                entries[starts[b + 1] as usize] = i as u32;
            });
        }
        // Counting down moved each end to its bucket's start: shift back by one.
        starts.rotate_left(1);
        starts[table] = total as u32;
    }

    /// Bytes the grid holds (its table and entries).
    pub fn bytes(&self) -> usize {
        4 * (self.starts.capacity() + self.entries.capacity())
    }

    fn bucket_entries(&self, b: u32) -> &[u32] {
        let b = b as usize;
        &self.entries[self.starts[b] as usize..self.starts[b + 1] as usize]
    }

    /// The photons listed where `p` lies: a superset of those within the radius of `p`.
    pub fn near(&self, p: Vec3) -> &[u32] {
        if self.entries.is_empty() {
            return &[];
        }
        self.bucket_entries(self.hash.bucket(self.hash.cell_of(p)))
    }

    /// Calls `f(index, t)` once for every photon within the radius of the
    /// segment `[t0, t1)` of `ray` (`positions` as built), `t` the parameter
    /// of its projection on the ray.
    pub fn along(
        &self,
        ray: &Ray,
        (t0, t1): (f32, f32),
        positions: &[Vec3],
        mut f: impl FnMut(u32, f32),
    ) {
        let Some(bounds) = self.bounds else {
            return;
        };
        let Some((a, b)) = bounds.intersect_ray(ray, t1) else {
            return;
        };
        let (t0, t1) = (t0.max(a), t1.min(b));
        if t0 >= t1 || self.entries.is_empty() {
            return;
        }
        let h = self.hash;
        let r2 = h.radius * h.radius;
        let mut walk = CellWalk::new(ray, t0, (h.origin, h.cell), h.cell_of(ray.at(t0)));
        for _ in 0..MAX_WALK_CELLS {
            let (enter, exit) = (walk.t, walk.next_t().min(t1));
            for &i in self.bucket_entries(h.bucket(walk.cell)) {
                let d = positions[i as usize] - ray.origin;
                let t = d.dot(ray.direction);
                if t < enter || t >= exit {
                    continue;
                }
                if (d - ray.direction * t).length_squared() < r2 {
                    f(i, t);
                }
            }
            if exit >= t1 {
                return;
            }
            walk.step();
        }
    }
}

/// A 3-D digital differential analyser over grid cells (Amanatides and Woo 1987).
struct CellWalk {
    cell: Cell,
    step: Cell,
    /// Ray parameter at which the walk leaves the cell along each axis.
    next: [f32; 3],
    /// Parameter change per cell along each axis.
    delta: [f32; 3],
    /// Parameter at which the walk entered the current cell.
    t: f32,
}

impl CellWalk {
    /// The walk from `cell`, where `ray.at(t0)` lies, over cells of `size` starting at `origin`.
    fn new(ray: &Ray, t0: f32, (origin, size): (Vec3, f32), cell: Cell) -> CellWalk {
        let o = ray.origin - origin;
        let d = ray.direction;
        let mut step = [0; 3];
        let mut next = [f32::INFINITY; 3];
        let mut delta = [f32::INFINITY; 3];
        for a in 0..3 {
            if d[a] > 0.0 {
                step[a] = 1;
                next[a] = (((cell[a] + 1) as f32) * size - o[a]) / d[a];
                delta[a] = size / d[a];
            } else if d[a] < 0.0 {
                step[a] = -1;
                next[a] = ((cell[a] as f32) * size - o[a]) / d[a];
                delta[a] = -size / d[a];
            }
        }
        CellWalk {
            cell,
            step,
            next,
            delta,
            t: t0,
        }
    }

    /// Where the walk leaves the current cell.
    fn next_t(&self) -> f32 {
        self.next[0].min(self.next[1]).min(self.next[2])
    }

    /// Moves to the next cell along the ray.
    fn step(&mut self) {
        let a = if self.next[0] <= self.next[1] && self.next[0] <= self.next[2] {
            0
        } else if self.next[1] <= self.next[2] {
            1
        } else {
            2
        };
        self.t = self.next[a];
        self.cell[a] += self.step[a];
        self.next[a] += self.delta[a];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    fn points(n: usize, seed: u64) -> Vec<Vec3> {
        let mut s = Sampler::from_seed(seed);
        (0..n)
            .map(|_| Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 4.0 - Vec3::splat(2.0))
            .collect()
    }

    /// Point queries find exactly the photons a brute-force scan finds.
    #[test]
    fn near_finds_every_photon_within_the_radius_once() {
        let pts = points(5000, 1);
        let mut grid = Grid::default();
        grid.build(&pts, 0.13);
        for q in points(200, 2) {
            let mut found: Vec<u32> = grid
                .near(q)
                .iter()
                .copied()
                .filter(|&i| (pts[i as usize] - q).length() < 0.13)
                .collect();
            found.sort();
            let brute: Vec<u32> = (0..pts.len() as u32)
                .filter(|&i| (pts[i as usize] - q).length() < 0.13)
                .collect();
            assert_eq!(found, brute);
        }
    }

    /// Beam queries find exactly the photons within the radius of the segment, each once.
    #[test]
    fn along_finds_every_photon_near_the_segment_once() {
        let pts = points(5000, 3);
        let mut grid = Grid::default();
        for radius in [0.05, 0.3] {
            grid.build(&pts, radius);
            let mut s = Sampler::from_seed(9);
            for _ in 0..100 {
                let o = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 6.0 - Vec3::splat(3.0);
                let d = (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - Vec3::splat(0.5))
                    .normalize();
                let ray = Ray::new(o, d);
                let (t0, t1) = (0.5, 5.0);
                let mut found = Vec::new();
                grid.along(&ray, (t0, t1), &pts, |i, _| found.push(i));
                found.sort();
                let brute: Vec<u32> = (0..pts.len() as u32)
                    .filter(|&i| {
                        let v = pts[i as usize] - o;
                        let t = v.dot(d);
                        t >= t0 && t < t1 && (v - d * t).length() < radius
                    })
                    .collect();
                assert_eq!(found, brute, "radius {radius}");
            }
        }
    }

    /// A radius far below the photons' spread, photons far from the origin:
    /// queries stay exact and a beam query ends (cells are capped at
    /// MAX_CELLS_PER_AXIS across the bounds, not 2r wide).
    #[test]
    fn tiny_radii_far_from_the_origin_stay_exact_and_end() {
        let offset = Vec3::new(3.0e5, -2.0e5, 1.0e5);
        let mut pts: Vec<Vec3> = points(2000, 5).into_iter().map(|p| p + offset).collect();
        // A pair closer than the radius, so that something is found.
        pts.push(offset + Vec3::new(0.1, 0.2, 0.3));
        let radius = 1.0e-3;
        let mut grid = Grid::default();
        grid.build(&pts, radius);
        let q = offset + Vec3::new(0.1, 0.2, 0.3 + 0.5e-3);
        let near: Vec<u32> = grid
            .near(q)
            .iter()
            .copied()
            .filter(|&i| (pts[i as usize] - q).length() < radius)
            .collect();
        assert_eq!(near, vec![2000]);
        let ray = Ray::new(offset + Vec3::new(0.1, 0.2, -3.0), Vec3::Z);
        let mut found = Vec::new();
        grid.along(&ray, (0.0, 10.0), &pts, |i, _| found.push(i));
        assert_eq!(found, vec![2000]);
        // 1e-30: every cell holds many photons, none within the radius.
        grid.build(&pts, 1.0e-30);
        let mut count = 0;
        grid.along(&ray, (0.0, 10.0), &pts, |_, _| count += 1);
        assert_eq!(count, 0);
    }
}
