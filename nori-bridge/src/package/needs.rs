//! scene.json: what the hardware generator needs to size itself.

use crate::bvh::Bvh;
use crate::geom::{len64, sub64, Tri};
use serde::Serialize;

/// A triangle is a sliver when its smallest altitude is below this fraction
/// of its longest edge (1e-3: thinner than 1:1000). Zero-area ones are
/// counted as degenerate, not as slivers.
pub const SLIVER_RATIO: f64 = 1e-3;

#[derive(Serialize)]
pub struct Needs {
    pub format_version: u32,
    /// Node layout: "nori", "2", "4" or "8" (= image header layout).
    pub layout: String,
    pub triangles: usize,
    /// Node records in the image: nori nodes, or wide nodes of K slots.
    pub nodes: usize,
    pub leaves: usize,
    /// Largest stack a traversal needs (= image header bvhDepth).
    pub bvh_depth: u32,
    /// Inner (wide) nodes on the longest root-to-leaf path.
    pub tree_depth: u32,
    /// Mean used slots per inner node (nori: 2).
    pub mean_children: f64,
    pub largest_leaf: u32,
    pub max_leaf_size: u32,
    pub sah_cost: f64,
    pub extent_min: [f32; 3],
    pub extent_max: [f32; 3],
    /// Unbiased binary exponents (floor(log2|x|)) over all non-zero vertex
    /// coordinates (box bounds are vertex coordinates, so they are covered).
    pub exponent_min: i32,
    pub exponent_max: i32,
    pub smallest_edge: f64,
    pub degenerate_triangles: usize,
    pub sliver_triangles: usize,
    /// Bits needed for each index: ceil(log2(count)) with at least 1.
    pub index_bits: IndexBits,
}

#[derive(Serialize)]
pub struct IndexBits {
    pub node: u32,
    pub triangle_slot: u32,
    pub prim: u32,
    pub leaf_count: u32,
    pub stack_depth: u32,
}

pub fn bits_for(count: u64) -> u32 {
    (64 - count.saturating_sub(1).leading_zeros()).max(1)
}

fn exponent(x: f32) -> Option<i32> {
    (x != 0.0 && x.is_finite()).then(|| (x.abs() as f64).log2().floor() as i32)
}

pub fn compute(tris: &[Tri], bvh: &Bvh) -> Needs {
    let root = bvh.root_bounds();
    let coords = tris.iter().flat_map(|t| t.v.iter().flatten().copied());
    let exps: Vec<i32> = coords.filter_map(exponent).collect();
    let (mut smallest_edge, mut degenerate, mut sliver) = (f64::INFINITY, 0, 0);
    for t in tris {
        let p = t.vertices64();
        let edges = [
            len64(sub64(p[1], p[0])),
            len64(sub64(p[2], p[1])),
            len64(sub64(p[0], p[2])),
        ];
        let longest = edges.iter().cloned().fold(0.0, f64::max);
        smallest_edge = edges.iter().cloned().fold(smallest_edge, f64::min);
        let area2 = t.double_area64();
        if area2 == 0.0 {
            degenerate += 1;
        } else if area2 / longest < SLIVER_RATIO * longest {
            sliver += 1; // altitude = 2*area/longest
        }
    }
    Needs {
        format_version: crate::memory::VERSION,
        layout: bvh.layout.name().into(),
        triangles: tris.len(),
        nodes: bvh.node_count(),
        leaves: bvh.leaf_count(),
        bvh_depth: bvh.depth,
        tree_depth: bvh.tree_depth,
        mean_children: bvh.mean_children(),
        largest_leaf: bvh.largest_leaf(),
        max_leaf_size: bvh.max_leaf_size,
        sah_cost: bvh.sah_cost(),
        extent_min: root.min,
        extent_max: root.max,
        exponent_min: exps.iter().copied().min().unwrap_or(0),
        exponent_max: exps.iter().copied().max().unwrap_or(0),
        smallest_edge,
        degenerate_triangles: degenerate,
        sliver_triangles: sliver,
        index_bits: IndexBits {
            node: bits_for(bvh.node_count() as u64),
            triangle_slot: bits_for(tris.len() as u64),
            prim: bits_for(tris.len() as u64),
            leaf_count: bits_for(bvh.largest_leaf() as u64 + 1),
            stack_depth: bits_for(bvh.depth as u64 + 1),
        },
    }
}
