//! The flattened BVH in one of our memory layouts (docs/memory-format.md):
//! 32-byte records; nori nodes depth first, wide nodes breadth first;
//! triangles in the order the layout's walk meets the leaves.
//! `nori`: one record per node, left child = index + 1. Wide (K = 2, 4, 8):
//! K records (slots) per node, slot i of node n at record K n + i.

pub mod build;
pub mod flatten;
pub mod layout;
pub mod quant;

pub use layout::{Layout, Slot, EMPTY_SLOT, LEAF_BIT};

use crate::geom::Aabb;

/// One 32-byte record: a nori node, or one slot of a wide node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// bit 31 = leaf; bits 30..0 = triangle count (leaf) or split axis
    /// (nori inner node); 0 = inner child, EMPTY_SLOT = unused (wide slot).
    pub word0: u32,
    /// first triangle slot (leaf), right child index (nori inner node) or
    /// child node index (wide inner slot).
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
    /// This record read as a wide node's slot.
    pub fn slot(&self) -> Slot {
        Slot::decode(self.word0, self.word1)
    }
}

#[derive(Clone, Debug)]
pub struct Bvh {
    pub layout: Layout,
    /// The records in image order (one per nori node, K per wide node).
    pub nodes: Vec<Node>,
    /// prim number of the triangle stored in each slot (leaf order).
    pub slot_prim: Vec<u32>,
    /// The stack bound (header bvhDepth): the largest sum of (used slots - 1)
    /// over the nodes on a path from the root; for nori, the largest number
    /// of inner nodes on a root-to-leaf path.
    pub depth: u32,
    /// Inner (wide) nodes on the longest root-to-leaf path.
    pub tree_depth: u32,
    pub max_leaf_size: u32,
    /// Quantized layouts: each node's quantization fields (`nodes` keep the
    /// exact boxes); empty otherwise.
    pub quant: Vec<quant::QuantNode>,
}

impl Bvh {
    /// Nodes in the image: nori nodes, or wide nodes of K slots.
    pub fn node_count(&self) -> usize {
        self.nodes.len() / self.layout.records_per_node()
    }

    /// The root's box: nori node 0, or the union of the wide root's slots.
    pub fn root_bounds(&self) -> Aabb {
        match self.layout {
            Layout::Nori => self.nodes[0].bounds,
            wide => self.nodes[..wide.records_per_node()]
                .iter()
                .filter(|n| n.slot() != Slot::Empty)
                .fold(Aabb::empty(), |b, n| b.union(&n.bounds)),
        }
    }

    /// Mean used slots per inner node (nori: 2; a root that is a leaf gives 0
    /// for nori, 1 for the wide layouts).
    pub fn mean_children(&self) -> f64 {
        let (children, inner) = match self.layout {
            Layout::Nori => {
                let inner = self.nodes.iter().filter(|n| !n.is_leaf()).count();
                (2 * inner, inner)
            }
            _ => (self.used_records().count(), self.node_count()),
        };
        if inner == 0 {
            0.0
        } else {
            children as f64 / inner as f64
        }
    }

    /// Every record but the empty slots of wide nodes.
    fn used_records(&self) -> impl Iterator<Item = &Node> + '_ {
        let wide = self.layout.is_wide();
        self.nodes
            .iter()
            .filter(move |n| !(wide && n.slot() == Slot::Empty))
    }

    pub fn largest_leaf(&self) -> u32 {
        self.nodes
            .iter()
            .filter(|n| n.is_leaf())
            .map(|n| n.count())
            .max()
            .unwrap_or(0)
    }

    pub fn leaf_count(&self) -> usize {
        self.nodes.iter().filter(|n| n.is_leaf()).count()
    }

    /// SAH cost with traversal and intersection cost 1 (Embree's defaults as
    /// we pass them to the builder): sum over inner nodes of A(n)/A(root)
    /// plus sum over leaves of A(l)/A(root) * triangles(l). A wide node
    /// counts once: the root (1) plus the box of each inner slot.
    pub fn sah_cost(&self) -> f64 {
        let root = self.root_bounds().area64();
        if root <= 0.0 {
            return f64::NAN;
        }
        let wide_root = self.layout.is_wide().then_some(1.0);
        wide_root
            .into_iter()
            .chain(self.used_records().map(|n| {
                let a = n.bounds.area64() / root;
                if n.is_leaf() {
                    a * n.count() as f64
                } else {
                    a
                }
            }))
            .sum()
    }

    /// The nori layout's `depth` from its node array (used after reading an
    /// image too).
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
