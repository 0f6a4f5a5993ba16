//! Rays and hits as exchanged through rays.csv / reference.csv / hits.csv.

pub mod csv_io;
pub mod generate;
pub mod txt;

use crate::geom::{to64, D3, V3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub o: V3,
    pub d: V3,
    pub tmin: f32,
    pub tmax: f32,
    /// Any-hit (occlusion) query: only `Hit::hit` is meaningful.
    pub shadow: bool,
}

impl Ray {
    pub fn at64(&self, t: f64) -> D3 {
        let (o, d) = (to64(self.o), to64(self.d));
        [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]]
    }
}

/// Hit record. u,v follow Embree: point = (1-u-v)*v0 + u*v1 + v*v2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub hit: bool,
    pub t: f32,
    pub u: f32,
    pub v: f32,
    /// Scene prim number, -1 on a miss.
    pub prim: i64,
    /// Error bit flags reported by the producer (0 = none).
    pub error: u32,
}

impl Hit {
    pub const MISS: Hit = Hit {
        hit: false,
        t: f32::INFINITY,
        u: 0.0,
        v: 0.0,
        prim: -1,
        error: 0,
    };

    pub fn occluded(yes: bool) -> Hit {
        Hit {
            hit: yes,
            ..Hit::MISS
        }
    }
}
