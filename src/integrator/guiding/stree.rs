//! The spatial part of the guide: a binary tree over a box, each leaf with
//! the directional quadtrees of its region (Müller et al. 2017, §3): a leaf
//! splits at its middle, along its longest axis, when a training iteration
//! deposited more records in it than a threshold that grows with the
//! iteration's samples, so the tree follows where paths go.

use super::dtree::DTree;
use crate::math::{Bounds3, Vec3};

/// The directional distributions of one region.
#[derive(Clone, Debug, Default)]
pub struct Leaf {
    /// What paths sample from: the energies of the last finished iteration.
    pub sampling: DTree,
    /// What the running iteration deposits into (the refined structure).
    pub building: DTree,
    /// Records deposited in the running iteration.
    pub records: u64,
}

/// A node: a leaf (index into the leaves) or a split with its two children.
#[derive(Clone, Copy, Debug)]
enum Node {
    Leaf(u32),
    Split {
        axis: u8,
        at: f32,
        children: [u32; 2],
    },
}

/// The spatial binary tree.
#[derive(Clone, Debug)]
pub struct STree {
    bounds: Bounds3,
    nodes: Vec<(Node, Bounds3)>,
    /// The leaves, in the order they were made.
    pub leaves: Vec<Leaf>,
}

impl STree {
    /// One leaf covering `bounds`.
    pub fn new(bounds: Bounds3) -> STree {
        STree {
            bounds,
            nodes: vec![(Node::Leaf(0), bounds)],
            leaves: vec![Leaf::default()],
        }
    }

    /// The box the tree subdivides (points outside fall in the nearest leaf).
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Index of the leaf holding `p`: O(depth).
    #[inline]
    pub fn leaf_index(&self, p: Vec3) -> usize {
        let mut node = 0;
        loop {
            match self.nodes[node].0 {
                Node::Leaf(l) => return l as usize,
                Node::Split { axis, at, children } => {
                    node = children[(p[axis as usize] >= at) as usize] as usize;
                }
            }
        }
    }

    /// Splits, in node order, every leaf holding more than `threshold`
    /// records (each half assumed to hold half of them, and split again
    /// while that is above the threshold), while the leaves stay within
    /// `max_leaves` and the quadtree nodes within `node_budget`.
    pub fn subdivide(&mut self, threshold: u64, max_leaves: usize, node_budget: usize) {
        let mut nodes_held: usize = self.quad_nodes();
        let mut i = 0;
        while i < self.nodes.len() {
            if let (Node::Leaf(l), bounds) = self.nodes[i] {
                let leaf = &self.leaves[l as usize];
                let cost = leaf.sampling.node_count() + leaf.building.node_count();
                if leaf.records > threshold
                    && self.leaves.len() < max_leaves
                    && nodes_held + cost <= node_budget
                {
                    nodes_held += cost;
                    self.split(i, l as usize, bounds);
                }
            }
            i += 1;
        }
    }

    /// Quadtree nodes held by all leaves.
    pub fn quad_nodes(&self) -> usize {
        self.leaves
            .iter()
            .map(|l| l.sampling.node_count() + l.building.node_count())
            .sum()
    }

    /// Node `i` (leaf `l` over `bounds`) becomes a split at the middle of its longest axis.
    fn split(&mut self, i: usize, l: usize, bounds: Bounds3) {
        let extent = bounds.max - bounds.min;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let at = 0.5 * (bounds.min[axis] + bounds.max[axis]);
        let (mut lower, mut upper) = (bounds, bounds);
        lower.max[axis] = at;
        upper.min[axis] = at;
        let mut half = self.leaves[l].clone();
        half.records /= 2;
        self.leaves[l].records = half.records;
        self.leaves.push(half);
        let new_leaf = (self.leaves.len() - 1) as u32;
        let first = self.nodes.len() as u32;
        self.nodes.push((Node::Leaf(l as u32), lower));
        self.nodes.push((Node::Leaf(new_leaf), upper));
        self.nodes[i].0 = Node::Split {
            axis: axis as u8,
            at,
            children: [first, first + 1],
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A leaf over the threshold splits until its halves are under it; points find their halves.
    #[test]
    fn busy_leaves_split_until_their_halves_are_below_the_threshold() {
        let b = Bounds3 {
            min: Vec3::ZERO,
            max: Vec3::new(4.0, 1.0, 1.0),
        };
        let mut t = STree::new(b);
        t.leaves[0].records = 100;
        t.subdivide(30, 1000, 1_000_000);
        // 100 → 50 → 25: two levels, four leaves along x.
        assert_eq!(t.leaves.len(), 4);
        let a = t.leaf_index(Vec3::new(0.1, 0.5, 0.5));
        let c = t.leaf_index(Vec3::new(3.9, 0.5, 0.5));
        assert_ne!(a, c);
        let mut t = STree::new(b);
        t.leaves[0].records = 100;
        t.subdivide(30, 2, 1_000_000);
        assert_eq!(t.leaves.len(), 2);
    }
}
