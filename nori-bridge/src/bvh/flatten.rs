//! Laying out the builder's tree (docs/memory-format.md): nodes in
//! depth-first pre-order, children in the builder's order, triangles in the
//! order the same walk meets the leaves (so each leaf is contiguous), boxes
//! the exact min/max of the f32 vertices below them.

use crate::bvh::layout::{EMPTY_SLOT, LEAF_BIT};
use crate::bvh::quant::QuantNode;
use crate::bvh::{Bvh, Layout, Node, Slot};
use crate::geom::{Aabb, Tri};
use anyhow::{bail, Result};

/// The builder's tree: a leaf holds prim numbers, an inner node its
/// children in the order Embree's setNodeChildren gave them.
#[derive(Clone, Debug, PartialEq)]
pub enum Tree {
    Leaf(Vec<u32>),
    Inner(Vec<Tree>),
}

pub fn flatten(tree: &Tree, tris: &[Tri], max_leaf_size: u32, layout: Layout) -> Result<Bvh> {
    let mut f = Flattener { tris, nodes: Vec::new(), slot_prim: Vec::new() };
    let (depth, tree_depth) = match layout {
        Layout::Nori => {
            let d = f.nori(tree)?;
            (d, d)
        }
        quant if quant.is_quant() => {
            let k = quant.records_per_node();
            let q = crate::bvh::quant::flatten_quant(tree, tris, k)?;
            let fields = q.nodes.chunks(k).map(|slots| QuantNode::encode(&slots.iter().map(|s| (s.slot() != Slot::Empty).then_some(s.bounds)).collect::<Vec<_>>()))
                .collect::<Result<Vec<_>>>()?;
            return Ok(Bvh { layout, nodes: q.nodes, slot_prim: q.slot_prim, depth: q.stack, tree_depth: q.depth, max_leaf_size, quant: fields });
        }
        wide => {
            let k = wide.records_per_node();
            let root = match tree {
                Tree::Leaf(_) => std::slice::from_ref(tree),
                Tree::Inner(kids) => kids.as_slice(),
            };
            let w = f.wide(root, k)?;
            (w.stack, w.depth)
        }
    };
    Ok(Bvh { layout, nodes: f.nodes, slot_prim: f.slot_prim, depth, tree_depth, max_leaf_size, quant: Vec::new() })
}

struct Flattener<'a> {
    tris: &'a [Tri],
    nodes: Vec<Node>,
    slot_prim: Vec<u32>,
}

/// What a wide subtree needs: its box, its stack bound (sum of used slots
/// - 1 along the worst path, this node included) and its depth in nodes.
struct WideOut {
    index: u32,
    bounds: Aabb,
    stack: u32,
    depth: u32,
}

impl Flattener<'_> {
    /// Append a leaf's triangles; returns its leaf record.
    fn leaf(&mut self, prims: &[u32]) -> Node {
        let first = self.slot_prim.len() as u32;
        let mut b = Aabb::empty();
        for &prim in prims {
            b = b.union(&self.tris[prim as usize].bounds());
            self.slot_prim.push(prim);
        }
        Node { word0: LEAF_BIT | prims.len() as u32, word1: first, bounds: b }
    }

    /// Emit the subtree in nori nodes, depth-first; returns its stack depth
    /// (inner nodes on its longest root-to-leaf path).
    fn nori(&mut self, t: &Tree) -> Result<u32> {
        let me = self.nodes.len();
        self.nodes.push(Node { word0: 0, word1: 0, bounds: Aabb::empty() });
        let kids = match t {
            Tree::Leaf(prims) => {
                self.nodes[me] = self.leaf(prims);
                return Ok(0);
            }
            Tree::Inner(kids) if kids.len() == 2 => kids,
            Tree::Inner(kids) => bail!("Embree gave a node of {} children for the binary nori layout", kids.len()),
        };
        let dl = self.nori(&kids[0])?;
        let right = self.nodes.len();
        let dr = self.nori(&kids[1])?;
        let (lb, rb) = (self.nodes[me + 1].bounds, self.nodes[right].bounds);
        self.nodes[me] = Node { word0: split_axis(&lb, &rb), word1: right as u32, bounds: lb.union(&rb) };
        Ok(1 + dl.max(dr))
    }

    /// Emit a wide node holding `kids` in its first slots, then the subtree
    /// of each inner kid in slot order (pre-order).
    fn wide(&mut self, kids: &[Tree], k: usize) -> Result<WideOut> {
        if kids.len() > k {
            bail!("Embree gave a node of {} children for {k}-wide nodes", kids.len());
        }
        let me = self.nodes.len();
        let empty = Node { word0: EMPTY_SLOT, word1: 0, bounds: Aabb { min: [0.0; 3], max: [0.0; 3] } };
        self.nodes.resize(me + k, empty);
        let (mut bounds, mut stack_below, mut depth_below) = (Aabb::empty(), 0, 0);
        for (i, kid) in kids.iter().enumerate() {
            let slot = match kid {
                Tree::Leaf(prims) => self.leaf(prims),
                Tree::Inner(grand) => {
                    let sub = self.wide(grand, k)?;
                    stack_below = stack_below.max(sub.stack);
                    depth_below = depth_below.max(sub.depth);
                    Node { word0: 0, word1: sub.index, bounds: sub.bounds }
                }
            };
            bounds = bounds.union(&slot.bounds);
            self.nodes[me + i] = slot;
        }
        // At this node the walk pushes at most (used slots - 1) entries.
        let stack = (kids.len() as u32).saturating_sub(1) + stack_below;
        Ok(WideOut { index: (me / k) as u32, bounds, stack, depth: 1 + depth_below })
    }
}

/// The axis along which the children's box centres lie farthest apart.
/// The nori walk only uses it to pick which child to visit first.
fn split_axis(l: &Aabb, r: &Aabb) -> u32 {
    let gap = |k: usize| ((r.min[k] + r.max[k]) as f64 - (l.min[k] + l.max[k]) as f64).abs();
    (0..3).max_by(|&a, &b| gap(a).total_cmp(&gap(b))).unwrap() as u32
}
