//! image.bin: the memory image the accelerator walks. Byte layout and the
//! reasons for it are in docs/memory-format.md (format version 3: the
//! header names the node layout, nori or K-wide; a triangle record is one
//! 64-byte line).

pub mod mt_walk;

use crate::bvh::layout::RECORD_BYTES;
use crate::bvh::quant::{self, QuantNode};
use crate::bvh::{Bvh, Layout, Node, Slot};
use crate::geom::{Aabb, Tri};
use anyhow::{bail, Context, Result};
use std::path::Path;

pub const MAGIC: &[u8; 8] = b"RTACCEL\0";
pub const VERSION: u32 = 3;
pub const HEADER_BYTES: usize = 64;
/// A triangle record's stride: 44 bytes of fields, zero-padded to one 64-byte
/// line so that no record straddles two DRAM bursts (docs/memory-format.md).
pub const TRI_BYTES: usize = 64;
pub const ALIGN: usize = 64;
/// Triangle record flag: the triangle has zero area when evaluated in f64.
pub const FLAG_ZERO_AREA: u32 = 1;

/// One triangle record as stored: vertices, prim number, flags.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriRecord {
    pub tri: Tri,
    pub prim: u32,
    pub flags: u32,
}

/// A decoded image: header values, nodes and triangle records.
#[derive(Clone, Debug)]
pub struct Image {
    pub layout: Layout,
    pub max_leaf_size: u32,
    /// The stack bound (see Bvh::depth).
    pub bvh_depth: u32,
    /// 32-byte records in file order: one per nori node, K per wide node
    /// (quantized layouts: K decoded slot records per node, boxes as the
    /// hardware decodes them).
    pub nodes: Vec<Node>,
    /// Quantized layouts: each node's quantization fields; empty otherwise.
    pub quant: Vec<QuantNode>,
    pub tris: Vec<TriRecord>,
}

pub fn align_up(x: usize) -> usize {
    x.div_ceil(ALIGN) * ALIGN
}

impl Image {
    pub fn from_bvh(bvh: &Bvh, tris: &[Tri]) -> Image {
        let records = bvh
            .slot_prim
            .iter()
            .map(|&p| {
                let tri = tris[p as usize];
                let flags = if tri.double_area64() == 0.0 {
                    FLAG_ZERO_AREA
                } else {
                    0
                };
                TriRecord {
                    tri,
                    prim: p,
                    flags,
                }
            })
            .collect();
        let mut nodes = bvh.nodes.clone();
        if bvh.layout.is_quant() {
            // What the image holds is the decoded box, not the exact one.
            let k = bvh.layout.records_per_node();
            for (n, q) in nodes.chunks_mut(k).zip(&bvh.quant) {
                for (i, s) in n
                    .iter_mut()
                    .enumerate()
                    .filter(|(_, s)| s.slot() != Slot::Empty)
                {
                    s.bounds = q.decoded(i);
                }
            }
        }
        Image {
            layout: bvh.layout,
            max_leaf_size: bvh.max_leaf_size,
            bvh_depth: bvh.depth,
            nodes,
            quant: bvh.quant.clone(),
            tris: records,
        }
    }

    pub fn node_offset() -> usize {
        HEADER_BYTES
    }

    pub fn tri_offset(&self) -> usize {
        align_up(HEADER_BYTES + self.layout.node_bytes() * self.node_count())
    }

    /// Nodes in the image: nori nodes, or wide nodes of K slots.
    pub fn node_count(&self) -> usize {
        self.nodes.len() / self.layout.records_per_node()
    }

    /// The K slots of wide node `i`.
    pub fn wide_node(&self, i: usize) -> &[Node] {
        let k = self.layout.records_per_node();
        &self.nodes[k * i..k * i + k]
    }

    /// Triangle records indexed by prim number.
    pub fn by_prim(&self) -> Vec<Tri> {
        let mut out = vec![Tri { v: [[0.0; 3]; 3] }; self.tris.len()];
        for r in &self.tris {
            out[r.prim as usize] = r.tri;
        }
        out
    }

    pub fn to_bytes(&self) -> Vec<u8> {
        let tri_off = self.tri_offset();
        let mut b = Vec::with_capacity(tri_off + TRI_BYTES * self.tris.len());
        b.extend_from_slice(MAGIC);
        for w in [
            VERSION,
            self.node_count() as u32,
            self.tris.len() as u32,
            Self::node_offset() as u32,
            tri_off as u32,
            self.layout.node_bytes() as u32,
            TRI_BYTES as u32,
            self.max_leaf_size,
            self.bvh_depth,
            self.layout.word(),
        ] {
            b.extend_from_slice(&w.to_le_bytes());
        }
        b.resize(HEADER_BYTES, 0);
        if self.layout.is_quant() {
            let k = self.layout.records_per_node();
            for (slots, q) in self.nodes.chunks(k).zip(&self.quant) {
                // Image::from_bvh and parse only make images that encode.
                b.extend(
                    quant::encode_bytes(q, slots, self.layout.node_bytes())
                        .expect("a quantized node that does not encode"),
                );
            }
        }
        for n in self.nodes.iter().filter(|_| !self.layout.is_quant()) {
            b.extend_from_slice(&n.word0.to_le_bytes());
            b.extend_from_slice(&n.word1.to_le_bytes());
            for f in n.bounds.min.iter().chain(n.bounds.max.iter()) {
                b.extend_from_slice(&f.to_le_bytes());
            }
        }
        b.resize(tri_off, 0);
        for r in &self.tris {
            for f in r.tri.v.iter().flatten() {
                b.extend_from_slice(&f.to_le_bytes());
            }
            for w in [r.prim, r.flags] {
                b.extend_from_slice(&w.to_le_bytes());
            }
            b.resize(b.len() + TRI_BYTES - 44, 0);
        }
        b
    }

    pub fn write(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.to_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))
    }

    pub fn read(path: &Path) -> Result<Image> {
        let b = std::fs::read(path)
            .with_context(|| format!("{}: cannot read memory image", path.display()))?;
        Image::parse(&b).with_context(|| format!("{}: bad memory image", path.display()))
    }

    pub fn parse(b: &[u8]) -> Result<Image> {
        if b.len() < HEADER_BYTES || &b[0..8] != MAGIC {
            bail!("no RTACCEL header");
        }
        let u = |off: usize| u32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        let f = |off: usize| f32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        let (version, nodes, tris, node_off, tri_off) = (
            u(8),
            u(12) as usize,
            u(16) as usize,
            u(20) as usize,
            u(24) as usize,
        );
        if version != VERSION {
            bail!("format version {version}, this tool reads {VERSION}: compile the package again");
        }
        let layout = Layout::from_word(u(44)).with_context(|| {
            format!(
                "header layout {} (bytes 44-47) is not 0 (nori), 2, 4, 8, 20 (4q) or 24 (8q)",
                u(44)
            )
        })?;
        if u(28) as usize != layout.node_bytes() || u(32) as usize != TRI_BYTES {
            bail!(
                "record sizes {}/{} differ from {}/{TRI_BYTES} (layout {layout})",
                u(28),
                u(32),
                layout.node_bytes()
            );
        }
        let records = nodes * layout.records_per_node();
        if node_off + layout.node_bytes() * nodes > tri_off || tri_off + TRI_BYTES * tris > b.len()
        {
            bail!("offsets/counts ({nodes} nodes at {node_off}, {tris} triangles at {tri_off}) exceed the file ({} bytes)", b.len());
        }
        let (nodes, quant): (Vec<Node>, Vec<QuantNode>) = if layout.is_quant() {
            let (nb, k) = (layout.node_bytes(), layout.records_per_node());
            let decoded: Vec<(Vec<Node>, QuantNode)> = (0..nodes)
                .map(|i| quant::decode_bytes(&b[node_off + nb * i..node_off + nb * (i + 1)], k))
                .collect();
            (
                decoded.iter().flat_map(|d| d.0.clone()).collect(),
                decoded.into_iter().map(|d| d.1).collect(),
            )
        } else {
            (
                (0..records)
                    .map(|i| {
                        let o = node_off + RECORD_BYTES * i;
                        Node {
                            word0: u(o),
                            word1: u(o + 4),
                            bounds: Aabb {
                                min: [f(o + 8), f(o + 12), f(o + 16)],
                                max: [f(o + 20), f(o + 24), f(o + 28)],
                            },
                        }
                    })
                    .collect(),
                Vec::new(),
            )
        };
        let tris = (0..tris)
            .map(|i| {
                let o = tri_off + TRI_BYTES * i;
                let v = |k: usize| [f(o + 12 * k), f(o + 12 * k + 4), f(o + 12 * k + 8)];
                TriRecord {
                    tri: Tri {
                        v: [v(0), v(1), v(2)],
                    },
                    prim: u(o + 36),
                    flags: u(o + 40),
                }
            })
            .collect();
        let img = Image {
            layout,
            max_leaf_size: u(36),
            bvh_depth: u(40),
            nodes,
            quant,
            tris,
        };
        if layout.is_wide() {
            img.check_wide_slots()?;
        }
        Ok(img)
    }

    /// Every slot of a wide image decodes, used slots come first, and child
    /// and triangle indices stay inside the file (so a walk cannot run off
    /// it).
    fn check_wide_slots(&self) -> Result<()> {
        let nodes = self.node_count();
        for n in 0..nodes {
            let mut seen_empty = false;
            for (i, s) in self.wide_node(n).iter().enumerate() {
                let bad = match s.slot() {
                    Slot::Corrupt => Some(format!("word0 {:#010x} is no slot kind", s.word0)),
                    Slot::Empty if s.word1 != 0 => Some("empty slot with word1 != 0".into()),
                    Slot::Empty => {
                        seen_empty = true;
                        None
                    }
                    _ if seen_empty => Some("used slot after an empty one".into()),
                    _ if !(s
                        .bounds
                        .min
                        .iter()
                        .chain(&s.bounds.max)
                        .all(|x| x.is_finite())) =>
                    {
                        Some(format!(
                            "non-finite box {:?} (quantized: a scale exponent outside {}..={})",
                            s.bounds,
                            quant::EXP_MIN,
                            quant::EXP_MAX
                        ))
                    }
                    Slot::Inner { node } if node as usize >= nodes || node as usize <= n => {
                        Some(format!("child node {node}"))
                    }
                    Slot::Leaf { first, count }
                        if count == 0 || first as usize + count as usize > self.tris.len() =>
                    {
                        Some(format!("leaf of {count} triangles at slot {first}"))
                    }
                    _ => None,
                };
                if let Some(what) = bad {
                    bail!(
                        "node {n} slot {i}: {what} ({nodes} nodes, {} triangles)",
                        self.tris.len()
                    );
                }
            }
        }
        Ok(())
    }
}
