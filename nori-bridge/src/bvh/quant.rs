//! Quantized wide nodes, layouts `4q` and `8q` (docs/memory-format.md,
//! "Quantized wide node"; after Ylitie, Karras and Laine, HPG 2017, and
//! Vaidyanathan et al., HPG 2016).
//!
//! A node stores, per axis, an FP32 origin and a power-of-two scale 2^s,
//! and each child box as 8-bit unsigned plane offsets q from it, rounded
//! outward (min down, max up): the decoded box origin + q 2^s contains
//! the exact child box. The origin is itself a multiple of 2^s, m 2^s
//! with |m| <= 2^24 - 256, so every decoded plane (m + q) 2^s has an
//! integer significand below 2^24 and the FP32 sum origin + q 2^s is
//! exact in any rounding mode: the hardware's one FP32 add per plane
//! reproduces it bit for bit.
//!
//! Child references: a node's inner children are consecutive nodes from
//! `childBase` and its leaves' triangles consecutive slots from `triBase`,
//! in slot order, so one byte per child (its kind and leaf count) suffices.

use crate::bvh::layout::{EMPTY_SLOT, LEAF_BIT};
use crate::bvh::{Node, Slot};
use crate::geom::Aabb;
use anyhow::{bail, ensure, Result};

/// Meta byte of an unused slot.
pub const META_EMPTY: u8 = 0;
/// Meta byte of an inner child.
pub const META_INNER: u8 = 1;
/// Meta bit of a leaf child (bits 6..0 = triangle count, 1..127).
pub const META_LEAF: u8 = 0x80;
/// Largest |m| of an origin m 2^s: m + q stays below 2^24 for q <= 255.
pub const ORIGIN_LIMIT: f64 = (1 << 24) as f64 - 256.0;
/// Scale exponent field range: 2^(e - 127) and q 2^(e - 127) (q <= 255)
/// are normal FP32 numbers for 1 <= e <= 247. The encoder needs at most
/// 231 (finite boxes); the hardware flags a used slot of a node with any
/// other value as bad scene data.
pub const EXP_MIN: u8 = 1;
pub const EXP_MAX: u8 = 247;

/// The quantization fields of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct QuantNode {
    pub origin: [f32; 3],
    /// Biased scale exponents: scale = 2^(exp - 127).
    pub exp: [u8; 3],
    /// Per slot: q of the box's min planes (x, y, z), then of its max planes.
    pub lo: Vec<[u8; 3]>,
    pub hi: Vec<[u8; 3]>,
}

/// q 2^(exp - 127) in FP32, exact for exp in EXP_MIN..=EXP_MAX.
pub fn q_scaled(q: u8, exp: u8) -> f32 {
    q as f32 * f32::from_bits((exp as u32) << 23)
}

/// One decoded plane as the hardware computes it: one FP32 add (exact for
/// what the encoder writes). A bad exponent decodes to NaN, which the walk
/// and the hardware treat as bad scene data.
pub fn plane(origin: f32, q: u8, exp: u8) -> f32 {
    if !(EXP_MIN..=EXP_MAX).contains(&exp) {
        return f32::NAN;
    }
    origin + q_scaled(q, exp)
}

impl QuantNode {
    /// The decoded box of slot `i`.
    pub fn decoded(&self, i: usize) -> Aabb {
        let (lo, hi) = (self.lo[i], self.hi[i]);
        Aabb {
            min: std::array::from_fn(|a| plane(self.origin[a], lo[a], self.exp[a])),
            max: std::array::from_fn(|a| plane(self.origin[a], hi[a], self.exp[a])),
        }
    }

    /// Quantizes the used slots' exact boxes outward (empty slots: all 0).
    pub fn encode(boxes: &[Option<Aabb>]) -> Result<QuantNode> {
        let used: Vec<&Aabb> = boxes.iter().flatten().collect();
        let k = boxes.len();
        let mut q = QuantNode {
            origin: [0.0; 3],
            exp: [127; 3],
            lo: vec![[0; 3]; k],
            hi: vec![[0; 3]; k],
        };
        if used.is_empty() {
            return Ok(q);
        }
        for a in 0..3 {
            let lo = used.iter().map(|b| b.min[a]).fold(f32::INFINITY, f32::min);
            let hi = used
                .iter()
                .map(|b| b.max[a])
                .fold(f32::NEG_INFINITY, f32::max);
            ensure!(
                lo.is_finite() && hi.is_finite() && lo <= hi,
                "cannot quantize the non-finite or inverted bounds [{lo}, {hi}]"
            );
            let (s, m) = axis_scale(lo, hi)?;
            let sc = 2f64.powi(s);
            q.origin[a] = (m * sc) as f32;
            debug_assert_eq!(q.origin[a] as f64, m * sc);
            q.exp[a] = (s + 127) as u8;
            for (i, b) in boxes.iter().enumerate() {
                if let Some(b) = b {
                    // f32 / 2^s is exact in f64; floor/ceil round outward.
                    let ql = (b.min[a] as f64 / sc).floor() - m;
                    let qh = (b.max[a] as f64 / sc).ceil() - m;
                    ensure!(
                        (0.0..=255.0).contains(&ql) && (0.0..=255.0).contains(&qh),
                        "quantization out of range"
                    );
                    q.lo[i][a] = ql as u8;
                    q.hi[i][a] = qh as u8;
                }
            }
        }
        Ok(q)
    }
}

/// The smallest s (scale 2^s) for which the parent interval [lo, hi] fits
/// 255 steps from an origin m 2^s = floor(lo / 2^s) 2^s with |m| within
/// ORIGIN_LIMIT. Returns (s, m).
fn axis_scale(lo: f32, hi: f32) -> Result<(i32, f64)> {
    let (extent, mag) = (hi as f64 - lo as f64, (lo.abs().max(hi.abs())) as f64);
    let mut s = -126;
    if extent > 0.0 {
        s = s.max((extent / 255.0).log2().floor() as i32 - 1);
    }
    if mag > 0.0 {
        s = s.max(mag.log2().floor() as i32 - 25);
    }
    loop {
        ensure!(
            s <= 104,
            "bounds [{lo}, {hi}] are too wide for 8-bit quantization"
        );
        let sc = 2f64.powi(s);
        let m = (lo as f64 / sc).floor();
        if m.abs() <= ORIGIN_LIMIT && (hi as f64 / sc).ceil() - m <= 255.0 {
            return Ok((s, m));
        }
        s += 1;
    }
}

/// Bytes of a node's fixed part: origin, exponents, a zero byte, childBase, triBase.
const FIXED_BYTES: usize = 24;

/// The node's bytes (docs/memory-format.md): `slots` are its K records
/// (word0/word1 in the wide meaning), whose references must be contiguous
/// as `flatten::wide_breadth_first` lays them out.
pub fn encode_bytes(q: &QuantNode, slots: &[Node], node_bytes: usize) -> Result<Vec<u8>> {
    let k = slots.len();
    let mut b = Vec::with_capacity(node_bytes);
    for o in q.origin {
        b.extend_from_slice(&o.to_le_bytes());
    }
    b.extend_from_slice(&q.exp);
    b.push(0);
    let child_base = slots
        .iter()
        .find(|s| matches!(s.slot(), Slot::Inner { .. }))
        .map_or(0, |s| s.word1);
    let tri_base = slots.iter().find(|s| s.is_leaf()).map_or(0, |s| s.word1);
    b.extend_from_slice(&child_base.to_le_bytes());
    b.extend_from_slice(&tri_base.to_le_bytes());
    let meta: Vec<u8> = slots
        .iter()
        .map(|s| match s.slot() {
            Slot::Empty => Ok(META_EMPTY),
            Slot::Inner { .. } => Ok(META_INNER),
            Slot::Leaf { count, .. } if (1..=127).contains(&count) => Ok(META_LEAF | count as u8),
            other => bail!("slot {other:?} has no quantized encoding"),
        })
        .collect::<Result<_>>()?;
    ensure!(
        decode_refs(&meta, child_base, tri_base)
            == slots.iter().map(|s| (s.word0, s.word1)).collect::<Vec<_>>(),
        "a node's children or leaf triangles are not contiguous in slot order"
    );
    b.extend_from_slice(&meta);
    for hi in [false, true] {
        for a in 0..3 {
            b.extend((0..k).map(|i| if hi { q.hi[i][a] } else { q.lo[i][a] }));
        }
    }
    debug_assert_eq!(b.len(), FIXED_BYTES + 7 * k);
    b.resize(node_bytes, 0);
    Ok(b)
}

/// (word0, word1) of each slot from its meta byte, as the hardware forms
/// them: an inner child is node childBase + (inner slots before it), a
/// leaf starts at triBase + (triangles of the leaf slots before it). A meta
/// byte that is no kind becomes a word0 that is none either (the byte
/// itself), which the slot decoder rejects (IndexOverflow).
pub fn decode_refs(meta: &[u8], child_base: u32, tri_base: u32) -> Vec<(u32, u32)> {
    let (mut inner, mut tris) = (0u32, 0u32);
    meta.iter()
        .map(|&m| match m {
            META_EMPTY => (EMPTY_SLOT, 0),
            META_INNER => {
                inner += 1;
                (0, child_base.wrapping_add(inner - 1))
            }
            m if m & META_LEAF != 0 => {
                let count = (m & !META_LEAF) as u32;
                tris += count;
                (LEAF_BIT | count, tri_base.wrapping_add(tris - count))
            }
            m => (m as u32, 0),
        })
        .collect()
}

/// Decodes one node's bytes into its K slot records (decoded boxes) and
/// quantization fields.
pub fn decode_bytes(b: &[u8], k: usize) -> (Vec<Node>, QuantNode) {
    let f = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    let u = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    let meta = &b[FIXED_BYTES..FIXED_BYTES + k];
    let plane = |p: usize, i: usize| b[FIXED_BYTES + k + p * k + i];
    let q = QuantNode {
        origin: [f(0), f(4), f(8)],
        exp: [b[12], b[13], b[14]],
        lo: (0..k)
            .map(|i| [plane(0, i), plane(1, i), plane(2, i)])
            .collect(),
        hi: (0..k)
            .map(|i| [plane(3, i), plane(4, i), plane(5, i)])
            .collect(),
    };
    let nodes = decode_refs(meta, u(16), u(20))
        .into_iter()
        .enumerate()
        .map(|(i, (word0, word1))| {
            let empty = word0 == EMPTY_SLOT;
            let bounds = if empty {
                Aabb {
                    min: [0.0; 3],
                    max: [0.0; 3],
                }
            } else {
                q.decoded(i)
            };
            Node {
                word0,
                word1,
                bounds,
            }
        })
        .collect();
    (nodes, q)
}
