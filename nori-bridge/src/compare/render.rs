//! `nori-bridge render`: PNGs for camera-ray packages. Each pixel shows its
//! first sample (s = 0). hits.png and reference.png shade by the face
//! normal (|n| mapped to RGB) or by depth; diff.png is the reference in grey
//! with mismatching pixels in magenta and ties/edge/reference-wrong in cyan.

use crate::compare::judge::Class;
use crate::geom::normalize64;
use crate::package::Package;
use crate::ray::Hit;
use anyhow::{bail, Context, Result};
use image::{Rgb, RgbImage};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Shade {
    Normal,
    Depth,
}

const MISMATCH: Rgb<u8> = Rgb([255, 0, 255]);
const DEBATABLE: Rgb<u8> = Rgb([0, 255, 255]);

pub fn render(
    pkg: &Package,
    hits: &[Hit],
    classes: &[Class],
    shade: Shade,
    out: &Path,
) -> Result<()> {
    let m = &pkg.manifest;
    let (Some(w), Some(h)) = (m.width, m.height) else {
        bail!(
            "{}: ray kind '{}' has no camera image; render needs --rays primary",
            pkg.dir.display(),
            m.ray_kind
        );
    };
    let spp = m.spp.max(1) as usize;
    let tris = pkg.image.by_prim();
    let depth_range = depth_range(&pkg.reference);
    let pix = |hit: &Hit| -> Rgb<u8> {
        if !hit.hit {
            return Rgb([0, 0, 0]);
        }
        match (shade, tris.get(hit.prim as usize)) {
            (Shade::Normal, Some(t)) => {
                let n = normalize64(t.normal64());
                Rgb(std::array::from_fn(|k| (n[k].abs() * 255.0).round() as u8))
            }
            _ => {
                let (lo, hi) = depth_range;
                let g = 1.0 - ((hit.t - lo) / (hi - lo).max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
                let g = (40.0 + 215.0 * g).round() as u8;
                Rgb([g, g, g])
            }
        }
    };
    let mut a = RgbImage::new(w, h);
    let mut r = RgbImage::new(w, h);
    let mut d = RgbImage::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let i0 = (y * w + x) as usize * spp;
            a.put_pixel(x, y, pix(&hits[i0]));
            let rp = pix(&pkg.reference[i0]);
            r.put_pixel(x, y, rp);
            let cls = &classes[i0..i0 + spp];
            let grey = ((rp[0] as u32 + rp[1] as u32 + rp[2] as u32) / 6) as u8;
            d.put_pixel(
                x,
                y,
                if cls.iter().any(|c| c.is_mismatch()) {
                    MISMATCH
                } else if cls.iter().any(|c| *c != Class::Agree) {
                    DEBATABLE
                } else {
                    Rgb([grey, grey, grey])
                },
            );
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("{}: cannot create", out.display()))?;
    for (name, img) in [("hits.png", &a), ("reference.png", &r), ("diff.png", &d)] {
        let p = out.join(name);
        img.save(&p)
            .with_context(|| format!("{}: cannot write PNG", p.display()))?;
    }
    Ok(())
}

fn depth_range(hits: &[Hit]) -> (f32, f32) {
    hits.iter()
        .filter(|h| h.hit)
        .fold((f32::INFINITY, 0.0f32), |(lo, hi), h| {
            (lo.min(h.t), hi.max(h.t))
        })
}
