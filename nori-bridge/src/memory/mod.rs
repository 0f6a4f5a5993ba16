//! image.bin: the memory image the accelerator walks. Byte layout and the
//! reasons for it are in docs/memory-format.md (format version 1).

pub mod traverse;

use crate::bvh::{Bvh, Node};
use crate::geom::{Aabb, Tri};
use anyhow::{bail, Context, Result};
use std::path::Path;

pub const MAGIC: &[u8; 8] = b"RTACCEL\0";
pub const VERSION: u32 = 1;
pub const HEADER_BYTES: usize = 64;
pub const NODE_BYTES: usize = 32;
pub const TRI_BYTES: usize = 48;
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
    pub max_leaf_size: u32,
    pub bvh_depth: u32,
    pub nodes: Vec<Node>,
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
                let flags = if tri.double_area64() == 0.0 { FLAG_ZERO_AREA } else { 0 };
                TriRecord { tri, prim: p, flags }
            })
            .collect();
        Image { max_leaf_size: bvh.max_leaf_size, bvh_depth: bvh.depth, nodes: bvh.nodes.clone(), tris: records }
    }

    pub fn node_offset() -> usize {
        HEADER_BYTES
    }

    pub fn tri_offset(&self) -> usize {
        align_up(HEADER_BYTES + NODE_BYTES * self.nodes.len())
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
        for w in [VERSION, self.nodes.len() as u32, self.tris.len() as u32, Self::node_offset() as u32,
                  tri_off as u32, NODE_BYTES as u32, TRI_BYTES as u32, self.max_leaf_size, self.bvh_depth] {
            b.extend_from_slice(&w.to_le_bytes());
        }
        b.resize(HEADER_BYTES, 0);
        for n in &self.nodes {
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
            for w in [r.prim, r.flags, 0] {
                b.extend_from_slice(&w.to_le_bytes());
            }
        }
        b
    }

    pub fn write(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.to_bytes()).with_context(|| format!("{}: cannot write", path.display()))
    }

    pub fn read(path: &Path) -> Result<Image> {
        let b = std::fs::read(path).with_context(|| format!("{}: cannot read memory image", path.display()))?;
        Image::parse(&b).with_context(|| format!("{}: bad memory image", path.display()))
    }

    pub fn parse(b: &[u8]) -> Result<Image> {
        if b.len() < HEADER_BYTES || &b[0..8] != MAGIC {
            bail!("no RTACCEL header");
        }
        let u = |off: usize| u32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        let f = |off: usize| f32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        let (version, nodes, tris, node_off, tri_off) = (u(8), u(12) as usize, u(16) as usize, u(20) as usize, u(24) as usize);
        if version != VERSION {
            bail!("format version {version}, this tool reads {VERSION}");
        }
        if u(28) as usize != NODE_BYTES || u(32) as usize != TRI_BYTES {
            bail!("record sizes {}/{} differ from {NODE_BYTES}/{TRI_BYTES}", u(28), u(32));
        }
        if node_off + NODE_BYTES * nodes > tri_off || tri_off + TRI_BYTES * tris > b.len() {
            bail!("offsets/counts ({nodes} nodes at {node_off}, {tris} triangles at {tri_off}) exceed the file ({} bytes)", b.len());
        }
        let nodes = (0..nodes)
            .map(|i| {
                let o = node_off + NODE_BYTES * i;
                Node {
                    word0: u(o),
                    word1: u(o + 4),
                    bounds: Aabb { min: [f(o + 8), f(o + 12), f(o + 16)], max: [f(o + 20), f(o + 24), f(o + 28)] },
                }
            })
            .collect();
        let tris = (0..tris)
            .map(|i| {
                let o = tri_off + TRI_BYTES * i;
                let v = |k: usize| [f(o + 12 * k), f(o + 12 * k + 4), f(o + 12 * k + 8)];
                TriRecord { tri: Tri { v: [v(0), v(1), v(2)] }, prim: u(o + 36), flags: u(o + 40) }
            })
            .collect();
        Ok(Image { max_leaf_size: u(36), bvh_depth: u(40), nodes, tris })
    }
}
