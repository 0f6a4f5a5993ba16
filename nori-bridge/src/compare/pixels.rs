//! Which image pixel each ray belongs to, and how many pixels two hits
//! files paint differently. Used by `sweep-report` to measure "share of
//! pixels that differ from FP32".
//!
//! - primary rays: ray = (y * width + x) * spp + s (ray::generate::primary), so
//!   pixel = ray / spp; a pixel differs when any of its rays differs in hit
//!   flag or prim (t is ignored: the same triangle shades the same).
//! - ambient-occlusion rays: `spp` rays per primary hit, primary hits in
//!   primary-ray order (ray::generate::ambient_occlusion), the primary rays
//!   themselves `spp` per pixel. compile writes the resulting map to
//!   ao_pixels.csv; a pixel differs when its count of occluded AO rays does.

use crate::error::at_line;
use crate::ray::Hit;
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::Path;

pub const AO_PIXELS_FILE: &str = "ao_pixels.csv";
pub const AO_PIXELS_HEADER: &str = "ray,pixel";

/// Pixel (y * width + x) of every AO ray, given the primary rays' hits that
/// the AO rays were generated from (`per_hit` AO rays per primary hit,
/// `spp` primary rays per pixel).
pub fn ao_pixels(primary_hits: &[Hit], spp: u32, per_hit: u32) -> Vec<u32> {
    let spp = spp.max(1) as usize;
    primary_hits
        .iter()
        .enumerate()
        .filter(|(_, h)| h.hit)
        .flat_map(|(i, _)| std::iter::repeat_n((i / spp) as u32, per_hit as usize))
        .collect()
}

pub fn write_ao_pixels(path: &Path, pixels: &[u32]) -> Result<()> {
    let mut s = String::with_capacity(pixels.len() * 12);
    s.push_str(AO_PIXELS_HEADER);
    s.push('\n');
    for (i, p) in pixels.iter().enumerate() {
        let _ = writeln!(s, "{i},{p}");
    }
    std::fs::write(path, s).with_context(|| format!("{}: cannot write", path.display()))
}

/// Reads ao_pixels.csv; every pixel must be below `pixel_count`.
pub fn read_ao_pixels(path: &Path, pixel_count: u64) -> Result<Vec<u32>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == AO_PIXELS_HEADER => {}
        other => bail!(at_line(
            path,
            1,
            format!(
                "header is '{}', expected '{AO_PIXELS_HEADER}'",
                other.map_or("", |l| l.1)
            )
        )),
    }
    let mut out = Vec::new();
    for (n, line) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let (ray, pixel) = match f[..] {
            [r, p] => (r.parse::<usize>().ok(), p.parse::<u32>().ok()),
            _ => (None, None),
        };
        if ray != Some(out.len()) {
            bail!(at_line(
                path,
                n + 1,
                format!("'{line}': expected ray number {} and a pixel", out.len())
            ));
        }
        match pixel {
            Some(p) if (p as u64) < pixel_count => out.push(p),
            _ => bail!(at_line(
                path,
                n + 1,
                format!("pixel in '{line}' is not below the image's {pixel_count} pixels")
            )),
        }
    }
    Ok(out)
}

/// Pixels painted differently by two answers to the same primary rays.
pub fn primary_pixels_differing(a: &[Hit], b: &[Hit], spp: u32) -> usize {
    let spp = spp.max(1) as usize;
    let mut differs = vec![false; a.len().div_ceil(spp)];
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        differs[i / spp] |= x.hit != y.hit || (x.hit && x.prim != y.prim);
    }
    differs.iter().filter(|d| **d).count()
}

/// Pixels whose count of occluded AO rays differs between two answers.
pub fn ao_pixels_differing(a: &[Hit], b: &[Hit], pixel_of_ray: &[u32]) -> usize {
    let mut balance: std::collections::BTreeMap<u32, i64> = std::collections::BTreeMap::new();
    for ((x, y), &p) in a.iter().zip(b).zip(pixel_of_ray) {
        *balance.entry(p).or_insert(0) += x.hit as i64 - y.hit as i64;
    }
    balance.values().filter(|d| **d != 0).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(prim: i64) -> Hit {
        Hit {
            hit: prim >= 0,
            t: if prim >= 0 { 1.0 } else { f32::INFINITY },
            u: 0.0,
            v: 0.0,
            prim,
            error: 0,
        }
    }

    #[test]
    fn ao_rays_map_to_the_pixel_of_their_primary_hit() {
        // 3 pixels x 2 spp; rays 1, 2, 5 hit; 3 AO rays per hit.
        let prim = [hit(-1), hit(4), hit(7), hit(-1), hit(-1), hit(2)];
        assert_eq!(ao_pixels(&prim, 2, 3), vec![0, 0, 0, 1, 1, 1, 2, 2, 2]);
        assert_eq!(ao_pixels(&prim, 1, 1), vec![1, 2, 5]);
    }

    #[test]
    fn primary_pixel_differs_on_hit_flag_or_prim_of_any_sample_not_on_t() {
        let a = [hit(1), hit(2), hit(3), hit(-1), hit(5), hit(5)];
        let mut b = a;
        b[1] = hit(9); // pixel 0: prim
        b[3] = hit(4); // pixel 1: hit flag
        b[5].t = 2.0; // pixel 2: t only, same image
        assert_eq!(primary_pixels_differing(&a, &b, 2), 2);
        assert_eq!(primary_pixels_differing(&a, &b, 1), 2);
        assert_eq!(primary_pixels_differing(&a, &a, 3), 0);
    }

    #[test]
    fn ao_pixel_differs_only_when_its_occluded_count_changes() {
        let map = [0, 0, 1, 1, 2, 2];
        let a = [hit(1), hit(-1), hit(1), hit(-1), hit(1), hit(1)];
        let mut b = a;
        (b[0], b[1]) = (hit(-1), hit(3)); // pixel 0: swapped, same count
        b[2] = hit(-1); // pixel 1: one fewer occluded
        b[4] = hit(8); // pixel 2: other prim, still occluded
        assert_eq!(ao_pixels_differing(&a, &b, &map), 1);
    }

    #[test]
    fn ao_pixels_file_round_trips_and_rejects_out_of_image_pixels() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join(AO_PIXELS_FILE);
        write_ao_pixels(&p, &[3, 3, 0, 7]).unwrap();
        assert_eq!(read_ao_pixels(&p, 8).unwrap(), vec![3, 3, 0, 7]);
        let e = format!("{:#}", read_ao_pixels(&p, 7).unwrap_err());
        assert!(
            e.contains("ao_pixels.csv:5:") && e.contains("7 pixels"),
            "{e}"
        );
    }
}
