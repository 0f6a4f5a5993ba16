//! Per-ray judgement of a hits answer against the reference, with an
//! independent f64 evaluation (exact.rs) deciding disagreements.

use crate::exact::{eval64_in_range, eval64_plane, Hit64};
use crate::geom::Tri;
use crate::ray::{Hit, Ray};
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// Same answer (same prim, t within tolerance; or both miss).
    Agree,
    /// Different prims hit at the same t in f64 (shared edge or coplanar).
    Tie,
    /// The deciding f64 hit lies within `edge_tol` (barycentric) of an edge
    /// or vertex, or t within tolerance of tmin/tmax: both answers are
    /// defensible for an f32 evaluator.
    Edge,
    /// f64 says the hits file is right and the reference wrong.
    ReferenceWrong,
    FalseMiss,
    FalseHit,
    WrongPrim,
    TError,
}

impl Class {
    pub fn is_mismatch(self) -> bool {
        matches!(self, Class::FalseMiss | Class::FalseHit | Class::WrongPrim | Class::TError)
    }
}

#[derive(Clone, Copy, Debug, Serialize)]
pub struct Tolerances {
    /// Relative t tolerance. Default 1e-4 (~840 f32 ulps): f32
    /// Moller-Trumbore t is good to a few ulps times the conditioning of the
    /// hit; narrower hardware formats pass a larger value.
    pub t_rel: f64,
    /// Barycentric distance to an edge below which a hit is ambiguous in
    /// f32. Default 1e-5 (~84 f32 ulps of a unit barycentric).
    pub edge: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { t_rel: 1e-4, edge: 1e-5 }
    }
}

pub struct Judge<'a> {
    pub tris: &'a [Tri],
    pub tol: Tolerances,
}

impl Judge<'_> {
    fn t_close(&self, a: f64, b: f64) -> bool {
        (a - b).abs() <= self.tol.t_rel * a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
    }

    fn tri(&self, prim: i64) -> Option<&Tri> {
        usize::try_from(prim).ok().and_then(|p| self.tris.get(p))
    }

    /// f64 hit of `prim` within the ray's range, if any.
    fn eval(&self, prim: i64, ray: &Ray) -> Option<Hit64> {
        self.tri(prim).and_then(|t| eval64_in_range(t, ray))
    }

    /// Close to an edge or to the ends of [tmin, tmax]: f32 may go either way.
    fn ambiguous(&self, prim: i64, ray: &Ray) -> bool {
        let Some(h) = self.tri(prim).and_then(|t| eval64_plane(t, ray)) else { return false };
        let near_end = |end: f32| end.is_finite() && self.t_close(h.t, end as f64);
        h.margin > -self.tol.edge && (h.margin < self.tol.edge || near_end(ray.tmin) || near_end(ray.tmax))
    }

    pub fn classify(&self, ray: &Ray, got: &Hit, want: &Hit) -> Class {
        if ray.shadow {
            return self.classify_shadow(ray, got, want);
        }
        match (got.hit, want.hit) {
            (false, false) => Class::Agree,
            (true, true) if got.prim == want.prim => {
                if self.t_close(got.t as f64, want.t as f64) {
                    Class::Agree
                } else {
                    match self.eval(got.prim, ray) {
                        Some(h) if self.t_close(got.t as f64, h.t) => Class::ReferenceWrong,
                        _ => Class::TError,
                    }
                }
            }
            (true, false) => match self.eval(got.prim, ray) {
                _ if self.ambiguous(got.prim, ray) => Class::Edge,
                Some(h) if self.t_close(got.t as f64, h.t) => Class::ReferenceWrong,
                Some(_) => Class::TError,
                None => Class::FalseHit,
            },
            (false, true) => match self.eval(want.prim, ray) {
                _ if self.ambiguous(want.prim, ray) => Class::Edge,
                Some(_) => Class::FalseMiss,
                None => Class::ReferenceWrong,
            },
            (true, true) => self.classify_prims(ray, got, want),
        }
    }

    fn classify_prims(&self, ray: &Ray, got: &Hit, want: &Hit) -> Class {
        let (hg, hw) = (self.eval(got.prim, ray), self.eval(want.prim, ray));
        if let (Some(a), Some(b)) = (hg, hw) {
            if self.t_close(a.t, b.t) {
                return if self.t_close(got.t as f64, a.t) { Class::Tie } else { Class::TError };
            }
        }
        let edge = self.ambiguous(got.prim, ray) || self.ambiguous(want.prim, ray);
        let got_wins = match (hg, hw) {
            (Some(a), Some(b)) => a.t < b.t,
            (Some(_), None) => true,
            _ => false,
        };
        match (edge, got_wins) {
            (true, _) => Class::Edge,
            (false, true) if self.t_close(got.t as f64, hg.unwrap().t) => Class::ReferenceWrong,
            (false, true) => Class::TError,
            (false, false) => Class::WrongPrim,
        }
    }

    /// Shadow rays: only occlusion. The f64 truth is a brute-force search
    /// over all triangles (disagreements are rare, so this stays cheap).
    fn classify_shadow(&self, ray: &Ray, got: &Hit, want: &Hit) -> Class {
        if got.hit == want.hit {
            return Class::Agree;
        }
        let mut occluded = false;
        for (i, t) in self.tris.iter().enumerate() {
            if self.ambiguous(i as i64, ray) {
                return Class::Edge;
            }
            occluded |= eval64_in_range(t, ray).is_some();
        }
        match (occluded == got.hit, got.hit) {
            (true, _) => Class::ReferenceWrong,
            (false, true) => Class::FalseHit,
            (false, false) => Class::FalseMiss,
        }
    }
}
