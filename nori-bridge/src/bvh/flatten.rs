//! Laying out the builder's tree (docs/memory-format.md): nori nodes in
//! depth-first pre-order (the left child is implicit), wide and quantized
//! nodes breadth first; children in the builder's order, triangles in the
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
    if layout == Layout::Nori {
        let mut f = Flattener {
            tris,
            nodes: Vec::new(),
            slot_prim: Vec::new(),
        };
        let d = f.nori(tree)?;
        return Ok(Bvh {
            layout,
            nodes: f.nodes,
            slot_prim: f.slot_prim,
            depth: d,
            tree_depth: d,
            max_leaf_size,
            quant: Vec::new(),
        });
    }
    let k = layout.records_per_node();
    let w = wide_breadth_first(tree, tris, k)?;
    let quant = if layout.is_quant() {
        w.nodes
            .chunks(k)
            .map(|slots| {
                QuantNode::encode(
                    &slots
                        .iter()
                        .map(|s| (s.slot() != Slot::Empty).then_some(s.bounds))
                        .collect::<Vec<_>>(),
                )
            })
            .collect::<Result<Vec<_>>>()?
    } else {
        Vec::new()
    };
    Ok(Bvh {
        layout,
        nodes: w.nodes,
        slot_prim: w.slot_prim,
        depth: w.stack,
        tree_depth: w.depth,
        max_leaf_size,
        quant,
    })
}

struct Flattener<'a> {
    tris: &'a [Tri],
    nodes: Vec<Node>,
    slot_prim: Vec<u32>,
}

impl Flattener<'_> {
    /// Emit the subtree in nori nodes, depth-first; returns its stack depth
    /// (inner nodes on its longest root-to-leaf path).
    fn nori(&mut self, t: &Tree) -> Result<u32> {
        let me = self.nodes.len();
        self.nodes.push(Node {
            word0: 0,
            word1: 0,
            bounds: Aabb::empty(),
        });
        let kids = match t {
            Tree::Leaf(prims) => {
                self.nodes[me] = leaf(self.tris, &mut self.slot_prim, prims);
                return Ok(0);
            }
            Tree::Inner(kids) if kids.len() == 2 => kids,
            Tree::Inner(kids) => bail!(
                "Embree gave a node of {} children for the binary nori layout",
                kids.len()
            ),
        };
        let dl = self.nori(&kids[0])?;
        let right = self.nodes.len();
        let dr = self.nori(&kids[1])?;
        let (lb, rb) = (self.nodes[me + 1].bounds, self.nodes[right].bounds);
        self.nodes[me] = Node {
            word0: split_axis(&lb, &rb),
            word1: right as u32,
            bounds: lb.union(&rb),
        };
        Ok(1 + dl.max(dr))
    }
}

/// Append a leaf's triangles to `slot_prim`; returns its leaf record.
fn leaf(tris: &[Tri], slot_prim: &mut Vec<u32>, prims: &[u32]) -> Node {
    let first = slot_prim.len() as u32;
    let mut b = Aabb::empty();
    for &prim in prims {
        b = b.union(&tris[prim as usize].bounds());
        slot_prim.push(prim);
    }
    Node {
        word0: LEAF_BIT | prims.len() as u32,
        word1: first,
        bounds: b,
    }
}

/// A wide tree laid out: K records per node, the stack bound (sum of used
/// slots - 1 along the worst path) and the depth in nodes.
pub struct WideTree {
    pub nodes: Vec<Node>,
    pub slot_prim: Vec<u32>,
    pub stack: u32,
    pub depth: u32,
}

/// Lays out the builder's tree in K-wide nodes, breadth first (every wide
/// and quantized layout): node 0 is the root; nodes are numbered in the
/// order a FIFO walk from the root meets them, so each level follows the
/// one above and a node's inner children get consecutive indices in slot
/// order; its leaves' triangles get the next consecutive triangle slots
/// when the node is laid out (triangle records in the same node order).
/// Why breadth first: the system's node store preloads the first bytes of
/// the node array (docs/node-store.md), and this puts the top levels,
/// which every ray reads, there. Contiguous children and triangles per node
/// are what the quantized nodes' one-byte child references need.
pub fn wide_breadth_first(tree: &Tree, tris: &[Tri], k: usize) -> Result<WideTree> {
    let root = match tree {
        Tree::Leaf(_) => std::slice::from_ref(tree),
        Tree::Inner(kids) => kids.as_slice(),
    };
    let empty = Node {
        word0: EMPTY_SLOT,
        word1: 0,
        bounds: Aabb {
            min: [0.0; 3],
            max: [0.0; 3],
        },
    };
    let mut out = WideTree {
        nodes: Vec::new(),
        slot_prim: Vec::new(),
        stack: 0,
        depth: 0,
    };
    // The queue holds each node's children in index order: queue[n] is node n.
    let mut queue: Vec<&[Tree]> = vec![root];
    let mut n = 0;
    while n < queue.len() {
        let kids = queue[n];
        if kids.len() > k {
            bail!(
                "Embree gave a node of {} children for {k}-wide nodes",
                kids.len()
            );
        }
        for kid in kids {
            let slot = match kid {
                Tree::Leaf(prims) => leaf(tris, &mut out.slot_prim, prims),
                Tree::Inner(grand) => {
                    queue.push(grand.as_slice());
                    // The box is the union of the child's slots, filled in below.
                    Node {
                        word0: 0,
                        word1: (queue.len() - 1) as u32,
                        bounds: Aabb::empty(),
                    }
                }
            };
            out.nodes.push(slot);
        }
        out.nodes.resize((n + 1) * k, empty);
        n += 1;
    }
    // Every child's index is above its parent's: boxes, stack bounds and
    // depths from the last node up.
    let (mut stack, mut depth) = (vec![0u32; n], vec![0u32; n]);
    for m in (0..n).rev() {
        let used = queue[m].len() as u32;
        let (mut s, mut d) = (0, 0);
        for i in 0..used as usize {
            if let Slot::Inner { node } = out.nodes[m * k + i].slot() {
                let c = node as usize;
                out.nodes[m * k + i].bounds = out.nodes[c * k..c * k + k]
                    .iter()
                    .take(queue[c].len())
                    .fold(Aabb::empty(), |b, x| b.union(&x.bounds));
                s = s.max(stack[c]);
                d = d.max(depth[c]);
            }
        }
        // At this node the walk pushes at most (used slots - 1) entries.
        stack[m] = used.saturating_sub(1) + s;
        depth[m] = 1 + d;
    }
    out.stack = stack[0];
    out.depth = depth[0];
    Ok(out)
}

/// The axis along which the children's box centres lie farthest apart.
/// The nori walk only uses it to pick which child to visit first.
fn split_axis(l: &Aabb, r: &Aabb) -> u32 {
    let gap = |k: usize| ((r.min[k] + r.max[k]) as f64 - (l.min[k] + l.max[k]) as f64).abs();
    (0..3).max_by(|&a, &b| gap(a).total_cmp(&gap(b))).unwrap() as u32
}
