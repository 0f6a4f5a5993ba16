//! Exact-as-possible ray/triangle evaluation in f64, used as the judge.
//!
//! Inputs are f32, so the differences v_i - o are exact in f64 (f32 values
//! of similar magnitude; exact unless exponents differ by more than 29),
//! each cross-product term is a product of two 25-bit values (exact in
//! 53 bits) and only the sums round. The three signed volumes
//! w_i = d . (e_j x e_k) are thus correct to a few f64 ulps, about 1e-15
//! relative, far below f32's 6e-8: a sign decided here is the true sign
//! except for rays within ~1e-15 of an edge, which `margin` exposes.

use crate::geom::{cross64, dot64, sub64, to64, Tri};
use crate::ray::Ray;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit64 {
    pub t: f64,
    pub u: f64,
    pub v: f64,
    /// Smallest barycentric coordinate: 0 means on an edge or vertex.
    pub margin: f64,
}

/// Ray/triangle hit in f64, ignoring tmin/tmax. Edges and vertices count as
/// inside (closed triangles), so a ray through a shared edge hits both.
pub fn eval64(tri: &Tri, ray: &Ray) -> Option<Hit64> {
    eval64_plane(tri, ray).filter(|h| h.margin >= 0.0)
}

/// Where the ray meets the triangle's plane, with barycentrics; `margin` is
/// negative when that point lies outside the triangle (how far outside, in
/// barycentric units). None for a ray parallel to the plane or zero area.
pub fn eval64_plane(tri: &Tri, ray: &Ray) -> Option<Hit64> {
    let o = to64(ray.o);
    let d = to64(ray.d);
    let [p0, p1, p2] = tri.vertices64();
    let (a, b, c) = (sub64(p0, o), sub64(p1, o), sub64(p2, o));
    let w0 = dot64(d, cross64(b, c));
    let w1 = dot64(d, cross64(c, a));
    let w2 = dot64(d, cross64(a, b));
    let det = w0 + w1 + w2;
    if det == 0.0 {
        return None; // parallel to the plane, or a zero-area triangle
    }
    let n = cross64(sub64(p1, p0), sub64(p2, p0));
    let dn = dot64(d, n);
    if dn == 0.0 {
        return None;
    }
    let t = dot64(a, n) / dn;
    let (u, v) = (w1 / det, w2 / det);
    let margin = (w0 / det).min(u).min(v);
    Some(Hit64 { t, u, v, margin })
}

/// eval64 restricted to the ray's [tmin, tmax] interval.
pub fn eval64_in_range(tri: &Tri, ray: &Ray) -> Option<Hit64> {
    eval64(tri, ray).filter(|h| h.t >= ray.tmin as f64 && h.t <= ray.tmax as f64)
}
