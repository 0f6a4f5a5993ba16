//! The Möller–Trumbore layout walk: a software walk of our own memory image
//! in f32, in the image's layout (nori nodes near child first by the split
//! axis; wide nodes nearest hit slot first by entry distance), with a padded
//! box test and the Möller–Trumbore triangle test. It is **not** the
//! hardware's arithmetic (the RTL's default is watertight triangles and
//! conservatively rounded boxes): its one role is to check the node layouts
//! against Embree (tests/traversal_vs_embree.rs, wide_trace.rs,
//! quant_layout.rs) and to give `nori-bridge trace` a hits.csv without
//! hardware. The RTL's golden model is the Scala `TraversalGolden`; its
//! bit-exact C++ twin is nori-accel/golden/walk.cpp (docs/architecture.md,
//! "Golden models").

use crate::bvh::{Layout, Slot};
use crate::geom::{Aabb, V3};
use crate::memory::{Image, FLAG_ZERO_AREA};
use crate::ray::{Hit, Ray};
use rayon::prelude::*;

/// PBRT's gamma(3) = 3u/(1-3u) with u = 2^-24: slab distances in f32 are
/// within gamma(3) relative of exact, so scaling the far distance by
/// 1 + 2*gamma(3) makes the box test conservative (never misses a box the
/// exact ray touches).
const BOX_FAR_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

pub struct TraceStats {
    pub max_stack: usize,
}

pub fn trace_all(img: &Image, rays: &[Ray]) -> (Vec<Hit>, TraceStats) {
    let res: Vec<(Hit, usize)> = rays.par_iter().map(|r| trace(img, r)).collect();
    let max_stack = res.iter().map(|x| x.1).max().unwrap_or(0);
    (
        res.into_iter().map(|x| x.0).collect(),
        TraceStats { max_stack },
    )
}

/// Closest hit (or occlusion for shadow rays) in the image's own layout;
/// also returns the largest stack occupancy this ray needed.
pub fn trace(img: &Image, ray: &Ray) -> (Hit, usize) {
    let mut walk = Walk {
        img,
        ray,
        inv: [1.0 / ray.d[0], 1.0 / ray.d[1], 1.0 / ray.d[2]],
        best: Hit::MISS,
        tfar: ray.tmax,
    };
    let max_stack = match img.layout {
        Layout::Nori => walk.nori(),
        _ => walk.wide(),
    };
    (walk.best, max_stack)
}

/// One ray's state: its reciprocal direction and the closest hit so far.
struct Walk<'a> {
    img: &'a Image,
    ray: &'a Ray,
    inv: V3,
    best: Hit,
    tfar: f32,
}

/// A wide-walk stack entry: a slot that was hit and not yet visited.
#[derive(Clone, Copy)]
enum Entry {
    Inner(usize),
    Leaf(usize, usize),
}

impl Walk<'_> {
    /// Nori nodes: push the far child by the split axis, go to the near one;
    /// every node's box is tested when it is reached (popped ones too).
    /// Returns the largest stack.
    fn nori(&mut self) -> usize {
        let mut stack: Vec<usize> = Vec::with_capacity(64);
        let mut max_stack = 0;
        let mut i = 0usize;
        loop {
            let n = &self.img.nodes[i];
            let next = if box_near(&n.bounds, self.ray, &self.inv, self.tfar).is_none() {
                None
            } else if n.is_leaf() {
                if self.leaf(n.word1 as usize, n.count() as usize) {
                    return max_stack;
                }
                None
            } else if self.ray.d[n.axis()] < 0.0 {
                stack.push(i + 1);
                Some(n.word1 as usize)
            } else {
                stack.push(n.word1 as usize);
                Some(i + 1)
            };
            max_stack = max_stack.max(stack.len());
            match next.or_else(|| stack.pop()) {
                Some(j) => i = j,
                None => return max_stack,
            }
        }
    }

    /// Wide nodes (docs/memory-format.md, traversal order): test every used
    /// slot's box, visit the nearest hit slot (entry distance, ties to the
    /// lower slot), push the others farthest first. A popped leaf is tested
    /// without its box. Returns the largest stack.
    fn wide(&mut self) -> usize {
        let mut stack: Vec<Entry> = Vec::with_capacity(64);
        let mut max_stack = 0;
        let mut next = Some(Entry::Inner(0));
        while let Some(entry) = next {
            next = match entry {
                Entry::Leaf(first, count) => {
                    if self.leaf(first, count) {
                        return max_stack;
                    }
                    None
                }
                Entry::Inner(n) => {
                    let mut hit: Vec<(f32, usize, Entry)> = Vec::with_capacity(8);
                    for (i, s) in self.img.wide_node(n).iter().enumerate() {
                        let e = match s.slot() {
                            Slot::Inner { node } => Entry::Inner(node as usize),
                            Slot::Leaf { first, count } => {
                                Entry::Leaf(first as usize, count as usize)
                            }
                            // Image::parse rejects corrupt slots; used slots come first.
                            Slot::Empty | Slot::Corrupt => break,
                        };
                        if let Some(near) = box_near(&s.bounds, self.ray, &self.inv, self.tfar) {
                            hit.push((near, i, e));
                        }
                    }
                    hit.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                    stack.extend(hit.iter().skip(1).rev().map(|h| h.2));
                    max_stack = max_stack.max(stack.len());
                    hit.first().map(|h| h.2)
                }
            }
            .or_else(|| stack.pop());
        }
        max_stack
    }

    /// Test a leaf's triangles, keeping the closest hit (equal t: the lower
    /// prim, as the double reference does). True when a shadow ray is
    /// occluded (the walk ends).
    fn leaf(&mut self, first: usize, count: usize) -> bool {
        let ray = self.ray;
        for rec in &self.img.tris[first..first + count] {
            // Zero-area triangles can never be hit; f32 rounding could
            // still make their det non-zero, so skip them by their flag.
            if rec.flags & FLAG_ZERO_AREA != 0 {
                continue;
            }
            if let Some((t, u, v)) = moller_trumbore(&rec.tri.v, ray) {
                if t >= ray.tmin && t <= self.tfar {
                    if ray.shadow {
                        self.best = Hit::occluded(true);
                        return true;
                    }
                    if t < self.tfar || (rec.prim as i64) < self.best.prim || !self.best.hit {
                        self.best = Hit {
                            hit: true,
                            t,
                            u,
                            v,
                            prim: rec.prim as i64,
                            error: 0,
                        };
                        self.tfar = t;
                    }
                }
            }
        }
        false
    }
}

/// The slab test: Some(entry distance) when the ray meets the box within
/// [tmin, tfar] (`inv` = 1 / ray.d). The entry distance is the largest
/// per-axis entry (NaN axes ignored, tmin not applied): the wide walk orders
/// slots by it. Only the far side is padded, so a box whose f32 entry
/// rounds past the current best t is culled even if a triangle in it would
/// report that same t (or one an ulp or so below): which of two such hits
/// wins depends on the visiting order (tests/wide_trace.rs counts them).
pub fn box_near(b: &Aabb, ray: &Ray, inv: &V3, tfar: f32) -> Option<f32> {
    let mut near = f32::NEG_INFINITY;
    let mut hi = tfar;
    for k in 0..3 {
        let t0 = (b.min[k] - ray.o[k]) * inv[k];
        let t1 = (b.max[k] - ray.o[k]) * inv[k];
        // A NaN is 0 * inf: the origin lies on a plane of this slab and the
        // direction is parallel to it, so the ray stays inside the (closed)
        // slab for every t and the axis does not limit. f32::min/max alone
        // would not do: min(NaN, inf) is inf, which culled the node (the
        // axis-aligned hard case found it).
        if t0.is_nan() || t1.is_nan() {
            continue;
        }
        near = near.max(t0.min(t1));
        hi = hi.min(t0.max(t1) * BOX_FAR_SCALE);
    }
    (ray.tmin.max(near) <= hi).then_some(near)
}

/// Moller-Trumbore in f32, edges inclusive. Returns (t, u, v) with Embree's
/// u,v convention.
pub fn moller_trumbore(v: &[V3; 3], ray: &Ray) -> Option<(f32, f32, f32)> {
    let sub = |a: V3, b: V3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: V3, b: V3| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: V3, b: V3| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let e1 = sub(v[1], v[0]);
    let e2 = sub(v[2], v[0]);
    let p = cross(ray.d, e2);
    let det = dot(e1, p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(ray.o, v[0]);
    let u = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = cross(s, e1);
    let w = dot(ray.d, q) * inv;
    if w < 0.0 || u + w > 1.0 {
        return None;
    }
    Some((dot(e2, q) * inv, u, w))
}
