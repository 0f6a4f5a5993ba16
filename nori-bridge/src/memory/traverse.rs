//! A software walk of our own memory layout in f32, the way the hardware
//! walks it: stack of node indices, near child first by the split axis,
//! Moller-Trumbore triangle test. Used to check the layout against Embree
//! and by `nori-bridge trace` to make a hits.csv without hardware.

use crate::geom::{Aabb, V3};
use crate::memory::{Image, FLAG_ZERO_AREA};
use crate::ray::{Hit, Ray};
use rayon::prelude::*;

/// PBRT's gamma(3) = 3u/(1-3u) with u = 2^-24: slab distances in f32 are
/// within gamma(3) relative of exact, so scaling the far distance by
/// 1 + 2*gamma(3) makes the box test conservative (never misses a box the
/// exact ray touches).
const BOX_FAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

pub struct TraceStats {
    pub max_stack: usize,
}

pub fn trace_all(img: &Image, rays: &[Ray]) -> (Vec<Hit>, TraceStats) {
    let res: Vec<(Hit, usize)> = rays.par_iter().map(|r| trace(img, r)).collect();
    let max_stack = res.iter().map(|x| x.1).max().unwrap_or(0);
    (res.into_iter().map(|x| x.0).collect(), TraceStats { max_stack })
}

/// Closest hit (or occlusion for shadow rays); also returns the largest
/// stack occupancy this ray needed.
pub fn trace(img: &Image, ray: &Ray) -> (Hit, usize) {
    let inv = [1.0 / ray.d[0], 1.0 / ray.d[1], 1.0 / ray.d[2]];
    let mut best = Hit::MISS;
    let mut tfar = ray.tmax;
    let mut stack: Vec<usize> = Vec::with_capacity(64);
    let mut max_stack = 0;
    let mut i = 0usize;
    loop {
        let n = &img.nodes[i];
        let next = if !box_hit(&n.bounds, ray, &inv, tfar) {
            None
        } else if n.is_leaf() {
            let first = n.word1 as usize;
            for rec in &img.tris[first..first + n.count() as usize] {
                // Zero-area triangles can never be hit; f32 rounding could
                // still make their det non-zero, so skip them by their flag.
                if rec.flags & FLAG_ZERO_AREA != 0 {
                    continue;
                }
                if let Some((t, u, v)) = moller_trumbore(&rec.tri.v, ray) {
                    if t >= ray.tmin && t <= tfar {
                        if ray.shadow {
                            return (Hit::occluded(true), max_stack);
                        }
                        // Equal t: keep the lower prim, as the double reference does.
                        if t < tfar || (rec.prim as i64) < best.prim || !best.hit {
                            best = Hit { hit: true, t, u, v, prim: rec.prim as i64, error: 0 };
                            tfar = t;
                        }
                    }
                }
            }
            None
        } else if ray.d[n.axis()] < 0.0 {
            stack.push(i + 1);
            Some(n.word1 as usize)
        } else {
            stack.push(n.word1 as usize);
            Some(i + 1)
        };
        max_stack = max_stack.max(stack.len());
        match next.or_else(|| stack.pop()) {
            Some(j) => i = j,
            None => return (best, max_stack),
        }
    }
}

fn box_hit(b: &Aabb, ray: &Ray, inv: &V3, tfar: f32) -> bool {
    let mut lo = ray.tmin;
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
        lo = lo.max(t0.min(t1));
        hi = hi.min(t0.max(t1) * BOX_FAR_SCALE);
    }
    lo <= hi
}

/// Moller-Trumbore in f32, edges inclusive. Returns (t, u, v) with Embree's
/// u,v convention.
pub fn moller_trumbore(v: &[V3; 3], ray: &Ray) -> Option<(f32, f32, f32)> {
    let sub = |a: V3, b: V3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: V3, b: V3| [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
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
