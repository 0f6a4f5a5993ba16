//! The accelerator's image beside Embree's, their difference, and one
//! labelled montage of the three.

use crate::sweep::chart::{register_font, FONT};
use anyhow::{anyhow, Result};
use image::{Rgb, RgbImage};
use plotters::prelude::*;

/// Pixels that differ: grey copies of Embree's image where equal; where not,
/// red scaled by the largest channel difference (at least 96, so a one-level
/// difference shows). Returns the image and the count of differing pixels.
pub fn diff(a: &RgbImage, b: &RgbImage) -> (RgbImage, usize) {
    let mut d = RgbImage::new(a.width(), a.height());
    let mut n = 0;
    for (x, y, pa) in a.enumerate_pixels() {
        let pb = b.get_pixel(x, y);
        let m = (0..3)
            .map(|k| (pa[k] as i32 - pb[k] as i32).unsigned_abs())
            .max()
            .unwrap_or(0);
        d.put_pixel(
            x,
            y,
            if m == 0 {
                let g = ((pb[0] as u32 + pb[1] as u32 + pb[2] as u32) / 9) as u8;
                Rgb([g, g, g])
            } else {
                n += 1;
                Rgb([(96 + 4 * m).min(255) as u8, 0, 0])
            },
        );
    }
    (d, n)
}

/// Side by side with a title bar over each panel.
pub fn montage(panels: &[(&str, &RgbImage)], caption: &str) -> Result<RgbImage> {
    const BAR: u32 = 28;
    const FOOT: u32 = 22;
    const GAP: u32 = 8;
    let (w, h) = (panels[0].1.width(), panels[0].1.height());
    let tw = panels.len() as u32 * (w + GAP) + GAP;
    let th = BAR + h + FOOT;
    let mut out = RgbImage::from_pixel(tw, th, Rgb([255, 255, 255]));
    for (i, (_, img)) in panels.iter().enumerate() {
        image::imageops::replace(
            &mut out,
            *img,
            (GAP + i as u32 * (w + GAP)) as i64,
            BAR as i64,
        );
    }
    register_font()?;
    {
        let mut buf = out.as_raw().clone();
        let root = BitMapBackend::with_buffer(&mut buf, (tw, th)).into_drawing_area();
        let font = (FONT, 16).into_font().color(&BLACK);
        for (i, (label, _)) in panels.iter().enumerate() {
            root.draw(&Text::new(
                label.to_string(),
                ((GAP + i as u32 * (w + GAP)) as i32, 6),
                font.clone(),
            ))
            .map_err(|e| anyhow!("montage label: {e}"))?;
        }
        root.draw(&Text::new(
            caption.to_string(),
            (GAP as i32, (BAR + h + 4) as i32),
            (FONT, 13).into_font().color(&BLACK),
        ))
        .map_err(|e| anyhow!("montage caption: {e}"))?;
        root.present().map_err(|e| anyhow!("montage: {e}"))?;
        drop(root);
        out = RgbImage::from_raw(tw, th, buf).ok_or_else(|| anyhow!("montage buffer"))?;
    }
    Ok(out)
}
