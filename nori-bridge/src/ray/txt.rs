//! A user's ray file: one ray per line `ox oy oz dx dy dz [tmin [tmax]]`,
//! `#` starts a comment, `inf` is allowed, defaults tmin = 0, tmax = inf.
//! A ray's number is its 0-based position among the ray lines.

use crate::error::at_line;
use crate::ray::Ray;
use anyhow::{Context, Result};
use std::path::Path;

pub fn read_rays_txt(path: &Path) -> Result<Vec<Ray>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read ray file", path.display()))?;
    let mut rays = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let err = |msg: String| at_line(path, n + 1, msg);
        let mut v = Vec::new();
        for tok in line.split_whitespace() {
            let x: f32 = tok
                .parse()
                .map_err(|_| err(format!("'{tok}' is not a number")))?;
            if x.is_nan() {
                return Err(err(format!("'{tok}' is NaN")).into());
            }
            v.push(x);
        }
        if !(6..=8).contains(&v.len()) {
            return Err(err(format!(
                "{} numbers; a ray is 'ox oy oz dx dy dz [tmin [tmax]]'",
                v.len()
            ))
            .into());
        }
        let ray = Ray {
            o: [v[0], v[1], v[2]],
            d: [v[3], v[4], v[5]],
            tmin: v.get(6).copied().unwrap_or(0.0),
            tmax: v.get(7).copied().unwrap_or(f32::INFINITY),
            shadow: false,
        };
        if !ray.o.iter().all(|c| c.is_finite()) {
            return Err(err(format!("origin {:?} is not finite", ray.o)).into());
        }
        if !ray.d.iter().all(|c| c.is_finite()) || ray.d == [0.0; 3] {
            return Err(err(format!("direction {:?} must be finite and non-zero", ray.d)).into());
        }
        if !(ray.tmin >= 0.0 && ray.tmin.is_finite() && ray.tmin <= ray.tmax) {
            return Err(err(format!(
                "need 0 <= tmin ({}) <= tmax ({}), tmin finite",
                ray.tmin, ray.tmax
            ))
            .into());
        }
        rays.push(ray);
    }
    if rays.is_empty() {
        return Err(crate::error::in_file(path, "no ray lines").into());
    }
    Ok(rays)
}
