//! Per-ray judgement of a hits answer against the reference, with an
//! independent f64 evaluation (reference/exact.rs) deciding disagreements.

use crate::geom::{add64, dot64, len64, scale64, sub64, to64, Tri};
use crate::ray::{Hit, Ray};
use crate::reference::exact::{eval64_in_range, eval64_plane, Hit64};
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// Same answer (same prim, t within tolerance; or both miss).
    Agree,
    /// Different prims hit at the same t in f64, each inside its triangle or
    /// within its error bound of it (shared edges, vertices, coplanar).
    Tie,
    /// The deciding f64 hit lies within its error bound (see Tolerances) of
    /// an edge or vertex, or of tmin/tmax: both answers are defensible for
    /// an evaluator of the given precision.
    Edge,
    /// f64 says the hits file is right and the reference wrong (e.g. Embree
    /// letting a ray escape through a vertex of a closed mesh).
    ReferenceWrong,
    FalseMiss,
    FalseHit,
    WrongPrim,
    TError,
}

impl Class {
    pub fn is_mismatch(self) -> bool {
        matches!(
            self,
            Class::FalseMiss | Class::FalseHit | Class::WrongPrim | Class::TError
        )
    }
}

/// Tolerances scale with the unit roundoff u = 2^-precision_bits of the
/// evaluator under test and with the conditioning of each hit, because an
/// f32 ray/triangle test is only as good as its inputs allow:
/// - t is good to about u (|t| |d| + M) k / (|d| |cos a|) absolute, where
///   a = angle between ray and normal (a grazing ray meets the plane at an
///   ill-determined t), M = largest coordinate magnitude among origin and
///   vertices (o - v0 is rounded at that scale) and k = |e1| |e2| / |n| =
///   1 / sin(angle at v0) >= 1 (Moller-Trumbore's t = s.(e1 x e2) / det is
///   formed from products of the edges, which cancel on slivers);
/// - barycentrics are good to about u (distance + M) e / (2 area |cos a|),
///   e = longest edge: Moller-Trumbore's u = (s . (d x e2)) / det with
///   |s| ~ distance + M; on a sliver (2 area << e^2) this grows without
///   bound, and rightly: f32 cannot place a ray relative to it.
///
/// `slack` multiplies both (default 16: observed f32 errors stay below ~1x
/// these bounds, so 16 leaves room for a different operation order and
/// still catches any real bug, which is off by far more).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Tolerances {
    /// Mantissa bits (with the hidden bit) of the evaluator: 24 for f32.
    pub precision_bits: u32,
    pub slack: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            precision_bits: 24,
            slack: 16.0,
        }
    }
}

impl Tolerances {
    pub fn unit(&self) -> f64 {
        self.slack * (-(self.precision_bits as f64)).exp2()
    }
}

/// One prim's f64 view of a ray: where it meets the plane and how well an
/// evaluator can know that.
#[derive(Clone, Copy, Debug)]
struct Cond {
    h: Hit64,
    inside: bool,
    /// Absolute t error bound.
    t_tol: f64,
    bary_tol: f64,
}

pub struct Judge<'a> {
    pub tris: &'a [Tri],
    pub tol: Tolerances,
    /// Judge shadow disagreements by f64 brute force (compare turns this
    /// off when disagreements x triangles exceeds its budget; they then
    /// count as mismatches unjudged).
    pub judge_shadow: bool,
}

impl Judge<'_> {
    fn cond(&self, prim: i64, ray: &Ray) -> Option<Cond> {
        let tri = usize::try_from(prim).ok().and_then(|p| self.tris.get(p))?;
        let h = eval64_plane(tri, ray)?;
        let n = tri.normal64();
        let d = to64(ray.d);
        let cos = (dot64(n, d) / (len64(n) * len64(d))).abs().max(1e-300);
        let c = tri.vertices64();
        let longest = (0..3)
            .map(|i| len64(sub64(c[(i + 1) % 3], c[i])))
            .fold(0.0, f64::max);
        let centroid = scale64(add64(add64(c[0], c[1]), c[2]), 1.0 / 3.0);
        let dist = len64(sub64(centroid, to64(ray.o)));
        let m = c
            .iter()
            .chain(std::iter::once(&to64(ray.o)))
            .flatten()
            .fold(0.0f64, |a, x| a.max(x.abs()));
        let u = self.tol.unit();
        let dl = len64(d);
        let k = (len64(sub64(c[1], c[0])) * len64(sub64(c[2], c[0])) / len64(n)).max(1.0);
        let in_range = h.t >= ray.tmin as f64 && h.t <= ray.tmax as f64;
        Some(Cond {
            h,
            inside: h.margin >= 0.0 && in_range,
            t_tol: u * (h.t.abs() * dl + m) * k / (dl * cos.min(1.0)),
            bary_tol: u * ((dist + m) * longest / (len64(n) * cos)).max(1.0),
        })
    }

    fn t_close(a: f64, b: f64, abs_tol: f64) -> bool {
        (a - b).abs() <= abs_tol
    }

    /// f64 hit of `prim` within the ray's range, if any.
    fn eval(&self, prim: i64, ray: &Ray) -> Option<Cond> {
        self.cond(prim, ray).filter(|c| c.inside)
    }

    /// Within the error bound of an edge/vertex or of tmin/tmax: an f32
    /// evaluator may go either way.
    fn ambiguous(&self, prim: i64, ray: &Ray) -> bool {
        let Some(c) = self.cond(prim, ray) else {
            return false;
        };
        let near_end = |end: f32| end.is_finite() && Self::t_close(c.h.t, end as f64, c.t_tol);
        c.h.margin > -c.bary_tol
            && (c.h.margin < c.bary_tol || near_end(ray.tmin) || near_end(ray.tmax))
    }

    fn in_range_within(&self, c: &Cond, ray: &Ray) -> bool {
        c.h.t >= ray.tmin as f64 - c.t_tol && c.h.t <= ray.tmax as f64 + c.t_tol
    }

    /// Is the reported t right for this prim (within its error bound)?
    fn t_ok(&self, t: f32, c: &Cond) -> bool {
        Self::t_close(t as f64, c.h.t, c.t_tol)
    }

    pub fn classify(&self, ray: &Ray, got: &Hit, want: &Hit) -> Class {
        if ray.shadow {
            return self.classify_shadow(ray, got, want);
        }
        match (got.hit, want.hit) {
            (false, false) => Class::Agree,
            (true, true) if got.prim == want.prim => match self.cond(got.prim, ray) {
                None if Self::t_close(
                    got.t as f64,
                    want.t as f64,
                    self.tol.unit() * (want.t as f64).abs(),
                ) =>
                {
                    Class::Agree
                }
                None => Class::TError,
                Some(c) => {
                    let (got_ok, want_ok) = (self.t_ok(got.t, &c), self.t_ok(want.t, &c));
                    if Self::t_close(got.t as f64, want.t as f64, c.t_tol) || (got_ok && want_ok) {
                        Class::Agree
                    } else if got_ok {
                        Class::ReferenceWrong
                    } else {
                        Class::TError
                    }
                }
            },
            // The f64 judge decides; a losing hits answer is forgiven (Edge)
            // only when it lies within its own error bound.
            (true, false) => match self.eval(got.prim, ray) {
                Some(c) if self.t_ok(got.t, &c) => Class::ReferenceWrong,
                Some(_) => Class::TError,
                None if self.ambiguous(got.prim, ray) => Class::Edge,
                None => Class::FalseHit,
            },
            (false, true) => match self.eval(want.prim, ray) {
                None => Class::ReferenceWrong,
                Some(_) if self.ambiguous(want.prim, ray) => Class::Edge,
                Some(_) => Class::FalseMiss,
            },
            (true, true) => self.classify_prims(ray, got, want),
        }
    }

    fn classify_prims(&self, ray: &Ray, got: &Hit, want: &Hit) -> Class {
        // Tie: both prims hit, or within their error bound of being hit, at
        // the same t (shared edges and vertices, coplanar overlaps).
        let near = |p: i64| {
            self.cond(p, ray)
                .filter(|c| c.h.margin > -c.bary_tol && self.in_range_within(c, ray))
        };
        if let (Some(a), Some(b)) = (near(got.prim), near(want.prim)) {
            if Self::t_close(a.h.t, b.h.t, a.t_tol.max(b.t_tol)) {
                return if self.t_ok(got.t, &a) {
                    Class::Tie
                } else {
                    Class::TError
                };
            }
        }
        let (hg, hw) = (self.eval(got.prim, ray), self.eval(want.prim, ray));
        let edge = self.ambiguous(got.prim, ray) || self.ambiguous(want.prim, ray);
        let got_wins = match (hg, hw) {
            (Some(a), Some(b)) => a.h.t < b.h.t,
            (Some(_), None) => true,
            _ => false,
        };
        match (got_wins, edge) {
            (true, _) if hg.is_some_and(|c| self.t_ok(got.t, &c)) => Class::ReferenceWrong,
            (true, _) => Class::TError,
            (false, true) => Class::Edge,
            (false, false) => Class::WrongPrim,
        }
    }

    /// Shadow rays: only occlusion. The f64 truth is a brute-force search
    /// over all triangles (disagreements are rare, so this stays cheap).
    fn classify_shadow(&self, ray: &Ray, got: &Hit, want: &Hit) -> Class {
        if got.hit == want.hit {
            return Class::Agree;
        }
        if !self.judge_shadow {
            return if got.hit {
                Class::FalseHit
            } else {
                Class::FalseMiss
            };
        }
        let (mut occluded, mut edge) = (false, false);
        for (i, t) in self.tris.iter().enumerate() {
            edge |= self.ambiguous(i as i64, ray);
            occluded |= eval64_in_range(t, ray).is_some();
        }
        match (occluded == got.hit, edge, got.hit) {
            (true, _, _) => Class::ReferenceWrong,
            (false, true, _) => Class::Edge,
            (false, false, true) => Class::FalseHit,
            (false, false, false) => Class::FalseMiss,
        }
    }
}
