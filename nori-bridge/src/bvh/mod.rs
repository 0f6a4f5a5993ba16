//! The flattened BVH in our memory layout (docs/memory-format.md): nodes in
//! depth-first order, left child = index + 1, triangles in leaf order.

pub mod build;

use crate::geom::Aabb;

pub const LEAF_BIT: u32 = 1 << 31;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// bit 31 = leaf; bits 30..0 = triangle count (leaf) or split axis (inner).
    pub word0: u32,
    /// first triangle slot (leaf) or right child index (inner).
    pub word1: u32,
    pub bounds: Aabb,
}

impl Node {
    pub fn is_leaf(&self) -> bool {
        self.word0 & LEAF_BIT != 0
    }
    pub fn count(&self) -> u32 {
        self.word0 & !LEAF_BIT
    }
    pub fn axis(&self) -> usize {
        (self.word0 & !LEAF_BIT) as usize
    }
}

#[derive(Clone, Debug)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    /// prim number of the triangle stored in each slot (leaf order).
    pub slot_prim: Vec<u32>,
    /// Largest number of inner nodes on a root-to-leaf path: the stack depth
    /// a traversal that pushes one child per inner node can reach.
    pub depth: u32,
    pub max_leaf_size: u32,
}

impl Bvh {
    pub fn largest_leaf(&self) -> u32 {
        self.nodes.iter().filter(|n| n.is_leaf()).map(|n| n.count()).max().unwrap_or(0)
    }

    pub fn leaf_count(&self) -> usize {
        self.nodes.iter().filter(|n| n.is_leaf()).count()
    }

    /// SAH cost with traversal and intersection cost 1 (Embree's defaults as
    /// we pass them to the builder): sum over inner nodes of A(n)/A(root)
    /// plus sum over leaves of A(l)/A(root) * triangles(l).
    pub fn sah_cost(&self) -> f64 {
        let root = self.nodes[0].bounds.area64();
        if root <= 0.0 {
            return f64::NAN;
        }
        self.nodes
            .iter()
            .map(|n| {
                let a = n.bounds.area64() / root;
                if n.is_leaf() { a * n.count() as f64 } else { a }
            })
            .sum()
    }

    /// Compute `depth` from the node array (used after reading an image too).
    pub fn compute_depth(nodes: &[Node]) -> u32 {
        let mut best = 0;
        let mut stack = vec![(0usize, 0u32)];
        while let Some((i, d)) = stack.pop() {
            let n = &nodes[i];
            if n.is_leaf() {
                best = best.max(d);
            } else {
                stack.push((i + 1, d + 1));
                stack.push((n.word1 as usize, d + 1));
            }
        }
        best
    }
}
