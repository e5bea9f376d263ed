//! The directional part of the guide: a quadtree over the square [0, 1)² of
//! the cylindrical (equal-area) map of the sphere, after Müller et al. 2017,
//! "Practical path guiding for efficient light-transport simulation", §3.
//!
//! A point (u, v) of the square is the direction with cos θ = 2u − 1 and
//! φ = 2πv; the map has the constant Jacobian dω = 4π du dv, so a density
//! over the square is a density over the sphere divided by 4π. Each node
//! holds the energy (the sum of radiance/pdf deposits) of its four quadrants
//! and, per quadrant, the index of the child that subdivides it (0: a leaf).
//! The piecewise-constant density is proportional to energy per area: at
//! each level the chosen quadrant carries the factor 4·e_q/Σe.

use crate::math::{Vec2, Vec3};
use std::f32::consts::PI;

/// Deepest level a quadrant is refined to (a leaf then spans 4^-12 of the sphere).
pub const MAX_DEPTH: u32 = 12;

/// Fraction of a tree's energy above which a quadrant is subdivided (Müller's ρ).
pub const SPLIT_FRACTION: f64 = 0.01;

/// One node: the energies of its four quadrants (index x + 2y) and their children.
#[derive(Clone, Copy, Debug, Default)]
struct Node {
    energy: [f64; 4],
    child: [u32; 4],
}

impl Node {
    fn total(&self) -> f64 {
        self.energy.iter().sum()
    }
}

/// A directional quadtree: a piecewise-constant density over the sphere.
#[derive(Clone, Debug)]
pub struct DTree {
    nodes: Vec<Node>,
}

impl Default for DTree {
    fn default() -> Self {
        DTree {
            nodes: vec![Node::default()],
        }
    }
}

/// The square point of a unit direction (cylindrical map), inside [0, 1)².
#[inline]
pub fn dir_to_square(d: Vec3) -> Vec2 {
    let u = ((d.z.clamp(-1.0, 1.0) + 1.0) * 0.5).min(ONE_MINUS_EPSILON);
    let v = (d.y.atan2(d.x) / (2.0 * PI))
        .rem_euclid(1.0)
        .min(ONE_MINUS_EPSILON);
    Vec2::new(u, v)
}

/// The unit direction of a square point (inverse of [`dir_to_square`]).
#[inline]
pub fn square_to_dir(p: Vec2) -> Vec3 {
    let cos_theta = 2.0 * p.x - 1.0;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (sin_phi, cos_phi) = (2.0 * PI * p.y).sin_cos();
    Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
}

const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// The quadrant of `p` in the unit square and `p` rescaled into it.
#[inline]
fn quadrant(p: Vec2) -> (usize, Vec2) {
    let (ix, iy) = ((p.x >= 0.5) as usize, (p.y >= 0.5) as usize);
    let local = Vec2::new(p.x * 2.0 - ix as f32, p.y * 2.0 - iy as f32);
    (ix + 2 * iy, local.min(Vec2::splat(ONE_MINUS_EPSILON)))
}

impl DTree {
    /// Nodes held (the memory unit of the guide's budget).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Total energy deposited.
    pub fn energy(&self) -> f64 {
        self.nodes[0].total()
    }

    /// Adds `weight` (radiance / sampling pdf) at direction `d`: O(depth).
    pub fn deposit(&mut self, d: Vec3, weight: f64) {
        let mut p = dir_to_square(d);
        let mut node = 0;
        loop {
            let (q, local) = quadrant(p);
            self.nodes[node].energy[q] += weight;
            let child = self.nodes[node].child[q];
            if child == 0 {
                return;
            }
            node = child as usize;
            p = local;
        }
    }

    /// Density per steradian of [`DTree::sample`] at direction `d` (0 without energy): O(depth).
    pub fn pdf(&self, d: Vec3) -> f32 {
        let mut p = dir_to_square(d);
        let mut node = 0;
        let mut density = 1.0f64;
        loop {
            let n = &self.nodes[node];
            let total = n.total();
            let (q, local) = quadrant(p);
            if total <= 0.0 || n.energy[q] <= 0.0 {
                return 0.0;
            }
            density *= 4.0 * n.energy[q] / total;
            if n.child[q] == 0 {
                return (density / (4.0 * std::f64::consts::PI)) as f32;
            }
            node = n.child[q] as usize;
            p = local;
        }
    }

    /// A direction drawn in proportion to energy per solid angle from `u` ∈ [0, 1)²
    /// (`None` without energy). Each level picks a column by `u.x`, then a row
    /// in it by `u.y`, and reuses the rescaled numbers below.
    pub fn sample(&self, mut u: Vec2) -> Option<Vec3> {
        if self.energy() <= 0.0 {
            return None;
        }
        let (mut origin, mut size, mut node) = (Vec2::ZERO, 1.0f32, 0usize);
        loop {
            let e = self.nodes[node].energy;
            let left = e[0] + e[2];
            let total = left + e[1] + e[3];
            let fx = (left / total) as f32;
            let ix = if u.x < fx {
                u.x /= fx;
                0
            } else {
                u.x = (u.x - fx) / (1.0 - fx);
                1
            };
            let (bottom, top) = (e[ix], e[ix + 2]);
            let fy = (bottom / (bottom + top)) as f32;
            let iy = if u.y < fy {
                u.y /= fy;
                0
            } else {
                u.y = (u.y - fy) / (1.0 - fy);
                1
            };
            u = u.clamp(Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON));
            size *= 0.5;
            origin += Vec2::new(ix as f32, iy as f32) * size;
            let child = self.nodes[node].child[ix + 2 * iy];
            if child == 0 {
                return Some(square_to_dir(origin + u * size));
            }
            node = child as usize;
        }
    }

    /// The structure for the next training iteration, energies zero: every
    /// quadrant holding more than [`SPLIT_FRACTION`] of this tree's energy is
    /// subdivided (a new child inheriting a quarter of its energy, which may
    /// subdivide again), every other one becomes a leaf; at most `budget` nodes.
    pub fn refined(&self, budget: usize) -> DTree {
        let total = self.energy();
        let mut out = DTree::default();
        if total <= 0.0 {
            return out;
        }
        let mut stack = vec![(0usize, Some(0usize), self.nodes[0].energy, 1u32)];
        while let Some((new, old, energy, depth)) = stack.pop() {
            for (q, &e) in energy.iter().enumerate() {
                if e / total <= SPLIT_FRACTION
                    || depth >= MAX_DEPTH
                    || out.nodes.len() >= budget.max(1)
                {
                    continue;
                }
                let old_child = old.map(|o| self.nodes[o].child[q]).filter(|&c| c != 0);
                let child_energy = match old_child {
                    Some(c) => self.nodes[c as usize].energy,
                    None => [e / 4.0; 4],
                };
                out.nodes.push(Node::default());
                let index = out.nodes.len() - 1;
                out.nodes[new].child[q] = index as u32;
                stack.push((
                    index,
                    old_child.map(|c| c as usize),
                    child_energy,
                    depth + 1,
                ));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map and its inverse agree, and equal areas of the square are equal solid angles.
    #[test]
    fn square_map_round_trips() {
        for &(u, v) in &[(0.1f32, 0.2f32), (0.5, 0.99), (0.93, 0.4)] {
            let d = square_to_dir(Vec2::new(u, v));
            assert!((d.length() - 1.0).abs() < 1e-5);
            let p = dir_to_square(d);
            assert!(
                (p.x - u).abs() < 1e-5 && (p.y - v).abs() < 1e-5,
                "{p} vs {u},{v}"
            );
        }
    }

    /// Energy in one quadrant of the sphere: the refined tree subdivides it
    /// until each piece holds at most ρ, and leaves the empty ones alone.
    /// A leaf's energy is taken as spread evenly over it, so each new child
    /// splits all four of its quadrants again.
    #[test]
    fn refinement_follows_the_energy() {
        let mut t = DTree::default();
        t.deposit(square_to_dir(Vec2::new(0.1, 0.1)), 1.0);
        let r = t.refined(1000);
        // Quadrant energies 1 → 1/4 → 1/16 → 1/64 → 1/256 ≤ ρ: the root,
        // then 1, 4 and 16 children each splitting their 4 quadrants.
        assert_eq!(r.node_count(), 1 + 1 + 4 + 16 + 64);
        assert_eq!(r.energy(), 0.0);
        assert_eq!(t.refined(3).node_count(), 3);
    }
}
