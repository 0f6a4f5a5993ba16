//! Brute-force f64 reference for small scenes: every ray against every
//! triangle with `exact::eval64`. Closest t wins; equal t goes to the lower
//! prim number. Results are rounded to f32 once.

use crate::geom::Tri;
use crate::ray::{Hit, Ray};
use crate::reference::exact::eval64_in_range;
use anyhow::{bail, Result};
use rayon::prelude::*;

pub const MAX_TRIS: usize = 20_000;

pub fn trace_double(tris: &[Tri], rays: &[Ray]) -> Result<Vec<Hit>> {
    if tris.len() > MAX_TRIS {
        bail!(
            "--reference double is for scenes of at most {MAX_TRIS} triangles; this one has {}",
            tris.len()
        );
    }
    Ok(rays.par_iter().map(|r| closest(tris, r)).collect())
}

fn closest(tris: &[Tri], ray: &Ray) -> Hit {
    let mut best: Option<(usize, crate::reference::exact::Hit64)> = None;
    for (i, t) in tris.iter().enumerate() {
        if let Some(h) = eval64_in_range(t, ray) {
            if ray.shadow {
                return Hit::occluded(true);
            }
            if best.is_none_or(|(_, b)| h.t < b.t) {
                best = Some((i, h));
            }
        }
    }
    match best {
        None => Hit::MISS,
        Some((i, h)) => Hit {
            hit: true,
            t: h.t as f32,
            u: h.u as f32,
            v: h.v as f32,
            prim: i as i64,
            error: 0,
        },
    }
}
