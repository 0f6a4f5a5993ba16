//! Exact ray/triangle predicates for the hard-case generator, in i128 on a
//! fixed-point grid. Every f32 a case uses is a multiple of 2^pos_exp
//! (positions) or 2^dir_exp (directions); `units` checks that and that the
//! integer stays below 2^35 (positions) / 2^41 (directions), so the degree-3
//! products below stay under 2^(36+36+41+3) < 2^127. All arithmetic is
//! checked: an overflow panics instead of deciding wrongly.

use crate::geom::{Tri, V3};
use crate::ray::Ray;

pub type I3 = [i128; 3];

/// Grid exponents of one case (see the module comment).
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    pub pos_exp: i32,
    pub dir_exp: i32,
}

const POS_LIMIT: i128 = 1 << 35;
const DIR_LIMIT: i128 = 1 << 41;

/// `x / 2^exp` as an exact integer; panics if x is off the grid or too big.
pub fn units(x: f32, exp: i32, limit: i128) -> i128 {
    let s = x as f64 * 2f64.powi(-exp); // power-of-two scaling: exact
    assert!(
        s.fract() == 0.0 && s.abs() < limit as f64,
        "{x} is not a multiple of 2^{exp} below {limit} units"
    );
    s as i128
}

/// Round `x` to f32, then to a multiple of 2^exp (a no-op where the f32
/// spacing is already coarser); panics unless the result is an f32.
pub fn snap(x: f64, exp: i32) -> f32 {
    let s = ((x as f32) as f64 * 2f64.powi(-exp)).round() * 2f64.powi(exp);
    let f = s as f32;
    assert!(f as f64 == s, "{x} snapped to 2^{exp} is not an f32");
    f
}

impl Grid {
    pub fn pos(&self, p: V3) -> I3 {
        p.map(|c| units(c, self.pos_exp, POS_LIMIT))
    }
    pub fn dir(&self, d: V3) -> I3 {
        d.map(|c| units(c, self.dir_exp, DIR_LIMIT))
    }
}

fn sub(a: I3, b: I3) -> I3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn mul(a: i128, b: i128) -> i128 {
    a.checked_mul(b)
        .expect("hard_exact: i128 overflow (grid too fine for these coordinates)")
}

fn cross(a: I3, b: I3) -> I3 {
    [
        mul(a[1], b[2]) - mul(a[2], b[1]),
        mul(a[2], b[0]) - mul(a[0], b[2]),
        mul(a[0], b[1]) - mul(a[1], b[0]),
    ]
}

fn dot(a: I3, b: I3) -> i128 {
    mul(a[0], b[0])
        .checked_add(mul(a[1], b[1]))
        .and_then(|s| s.checked_add(mul(a[2], b[2])))
        .expect("hard_exact: i128 overflow")
}

/// Sign of (q - p0) . ((p1 - p0) x (p2 - p0)): > 0 when q is on the side the
/// right-handed normal points to.
pub fn orient(g: &Grid, tri: &Tri, q: V3) -> i32 {
    let [p0, p1, p2] = tri.v.map(|p| g.pos(p));
    dot(sub(g.pos(q), p0), cross(sub(p1, p0), sub(p2, p0))).signum() as i32
}

/// Exact closed-triangle test (edges and vertices count as inside) for
/// t >= 0; tmin/tmax are not used (the generator's rays have tmin = 0,
/// tmax = inf). Returns t rounded to f64 (two roundings of exact integers and
/// one division: relative error < 4e-16), None on a miss, a ray parallel to
/// the plane, or a zero-area triangle.
pub fn hit_t(g: &Grid, tri: &Tri, ray: &Ray) -> Option<f64> {
    hit_t_units(g, &tri.v.map(|p| g.pos(p)), g.pos(ray.o), g.dir(ray.d))
}

/// hit_t on vertices, origin and direction already in grid units.
pub fn hit_t_units(g: &Grid, v: &[I3; 3], o: I3, d: I3) -> Option<f64> {
    hit_units(g, v, o, d).map(|h| h.0)
}

/// (t, on_edge): on_edge[k] is true when the hit point lies exactly on the
/// edge opposite vertex k (its edge function is zero).
pub fn hit_units(g: &Grid, v: &[I3; 3], o: I3, d: I3) -> Option<(f64, [bool; 3])> {
    let [a0, a1, a2] = v.map(|p| sub(p, o));
    let w = [
        dot(d, cross(a1, a2)),
        dot(d, cross(a2, a0)),
        dot(d, cross(a0, a1)),
    ];
    let det = w[0] + w[1] + w[2];
    if det == 0 || w.iter().any(|x| x.signum() == -det.signum()) {
        return None;
    }
    let num = dot(a0, cross(a1, a2));
    if num != 0 && num.signum() != det.signum() {
        return None; // behind the origin
    }
    Some((
        num as f64 / det as f64 * 2f64.powi(g.pos_exp - g.dir_exp),
        w.map(|x| x == 0),
    ))
}

/// True when the ray lies in the triangle's plane (parallel and the origin
/// on the plane).
pub fn coplanar(g: &Grid, tri: &Tri, ray: &Ray) -> bool {
    let [p0, p1, p2] = tri.v.map(|p| g.pos(p));
    let n = cross(sub(p1, p0), sub(p2, p0));
    n != [0; 3] && dot(g.dir(ray.d), n) == 0 && dot(sub(g.pos(ray.o), p0), n) == 0
}

/// Exact closed slab test: does the half-line t >= 0 meet the closed box
/// [lo, hi]? Entry/exit parameters are compared as fractions (num/den with
/// den > 0) by cross-multiplication.
pub fn meets_box(g: &Grid, ray: &Ray, lo: V3, hi: V3) -> bool {
    let (o, d, lo, hi) = (g.pos(ray.o), g.dir(ray.d), g.pos(lo), g.pos(hi));
    let mut enter = (0i128, 1i128); // t = 0
    let mut exit: Option<(i128, i128)> = None; // +inf
    for k in 0..3 {
        if d[k] == 0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return false;
            }
            continue;
        }
        let (mut a, mut b) = ((lo[k] - o[k], d[k]), (hi[k] - o[k], d[k]));
        if d[k] < 0 {
            a = (-a.0, -a.1);
            b = (-b.0, -b.1);
            std::mem::swap(&mut a, &mut b);
        }
        if mul(a.0, enter.1) > mul(enter.0, a.1) {
            enter = a;
        }
        if exit.is_none_or(|e| mul(b.0, e.1) < mul(e.0, b.1)) {
            exit = Some(b);
        }
    }
    exit.is_none_or(|e| mul(enter.0, e.1) <= mul(e.0, enter.1))
}
