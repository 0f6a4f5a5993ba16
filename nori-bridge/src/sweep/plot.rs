//! The sweep's plots: error against LUTs, error against rays/cycle (both
//! with the Pareto front), pixels differing and hard-case failures against
//! mantissa bits.

use crate::sweep::chart::{draw, Chart, Marker, Point, Series};
use crate::sweep::metrics::PointOut;
use crate::sweep::report::Report;
use anyhow::{Context, Result};
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// A PNG written (or not, with the reason) for the document.
pub struct Plot {
    pub title: String,
    pub file: PathBuf,
    /// None when drawn; otherwise why there is no plot.
    pub missing: Option<String>,
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// One series per variant (sorted), coloured by variant; watertight points
/// are triangles, the others circles.
fn by_variant(
    points: &[&PointOut],
    joined: bool,
    xy: impl Fn(&PointOut) -> (f64, f64),
) -> Vec<Series> {
    let mut variants: Vec<&str> = points.iter().map(|p| p.variant.as_str()).collect();
    variants.sort();
    variants.dedup();
    variants
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let mut mine: Vec<&&PointOut> = points.iter().filter(|p| p.variant == *v).collect();
            mine.sort_by(|a, b| xy(a).0.total_cmp(&xy(b).0).then(a.name.cmp(&b.name)));
            Series {
                name: v.to_string(),
                color: PALETTE[i % PALETTE.len()],
                marker: if mine[0].config.triangle == "watertight" {
                    Marker::Triangle
                } else {
                    Marker::Circle
                },
                joined,
                points: mine
                    .iter()
                    .map(|p| Point {
                        x: xy(p).0,
                        y: xy(p).1,
                        label: format!(
                            "{} {}/{}",
                            p.config.layout_label(),
                            p.config.box_fmt(),
                            p.config.tri_fmt()
                        ),
                    })
                    .collect(),
            }
        })
        .collect()
}

fn front(r: &Report, names: &[String], xy: impl Fn(&PointOut) -> (f64, f64)) -> Vec<(f64, f64)> {
    names
        .iter()
        .filter_map(|n| r.points.iter().find(|p| &p.name == n))
        .map(xy)
        .collect()
}

/// Errors per million rays against one measure `xy` of `points`, one series per variant, with its Pareto front.
fn error_chart(
    r: &Report,
    title: &str,
    x_desc: &str,
    x_integer: bool,
    points: &[&PointOut],
    front_names: &[String],
    xy: impl Fn(&PointOut) -> (f64, f64) + Copy,
) -> Chart {
    Chart {
        title: title.into(),
        x_desc: x_desc.into(),
        y_desc: "false misses + false hits + wrong prims per million rays".into(),
        x_integer,
        series: by_variant(points, false, xy),
        front: front(r, front_names, xy),
    }
}

fn plot(dir: &Path, file: &str, title: &str, chart: Option<Chart>, why_not: &str) -> Result<Plot> {
    let path = dir.join(file);
    match chart {
        Some(c) => {
            draw(&c, &path)?;
            Ok(Plot {
                title: title.into(),
                file: path,
                missing: None,
            })
        }
        None => {
            // A stale PNG from an earlier sweep must not be shown as this one's.
            if path.exists() {
                std::fs::remove_file(&path)
                    .with_context(|| format!("{}: cannot remove stale plot", path.display()))?;
            }
            Ok(Plot {
                title: title.into(),
                file: path,
                missing: Some(why_not.into()),
            })
        }
    }
}

pub fn write_all(r: &Report, dir: &Path) -> Result<Vec<Plot>> {
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let all: Vec<&PointOut> = r.points.iter().collect();
    let lut = |p: &PointOut| (p.area.lut as f64, p.errors_per_million_rays);
    let a = error_chart(
        r,
        "Error against area (Yosys xc7 LUTs, whole accelerator)",
        "LUT",
        true,
        &all,
        &r.pareto.error_lut,
        lut,
    );
    let timed: Vec<&PointOut> = r.points.iter().filter(|p| p.speed.is_some()).collect();
    let speed = |p: &PointOut| {
        (
            p.speed.map_or(f64::NAN, |s| s.rays_per_cycle),
            p.errors_per_million_rays,
        )
    };
    let b = (!timed.is_empty()).then(|| {
        error_chart(
            r,
            "Error against speed (rays per cycle, mean over timed runs)",
            "rays / cycle",
            false,
            &timed,
            &r.pareto.error_speed,
            speed,
        )
    });
    let with_bytes: Vec<&PointOut> = r
        .points
        .iter()
        .filter(|p| p.node_bytes_per_ray.is_some())
        .collect();
    let bytes = |p: &PointOut| {
        (
            p.node_bytes_per_ray.unwrap_or(f64::NAN),
            p.errors_per_million_rays,
        )
    };
    let e = (!with_bytes.is_empty()).then(|| {
        error_chart(
            r,
            "Error against memory traffic (node bytes read per ray, golden walk over every ray)",
            "node bytes / ray",
            false,
            &with_bytes,
            &r.pareto.error_bytes,
            bytes,
        )
    });
    let imaged: Vec<&PointOut> = r
        .points
        .iter()
        .filter(|p| p.pixel_share.is_some())
        .collect();
    let px = |p: &PointOut| {
        (
            p.config.man_bits as f64,
            p.pixel_share.unwrap_or(f64::NAN) * 100.0,
        )
    };
    let c = (!imaged.is_empty()).then(|| Chart {
        title: format!(
            "Pixels differing from {} against mantissa bits",
            r.baseline_format
        ),
        x_desc: "mantissa bits (stored, without the hidden bit)".into(),
        y_desc: "% of pixels differing".into(),
        x_integer: true,
        series: by_variant(&imaged, true, px),
        front: Vec::new(),
    });
    // The hard cases apart: adversarial rays (vertex- and edge-aimed, on slab
    // planes, huge offsets) where the rounding variants differ most.
    let hard: Vec<&PointOut> = r.points.iter().filter(|p| p.hard.cases > 0).collect();
    let hx = |p: &PointOut| {
        (
            p.config.man_bits as f64,
            (p.hard.leaks + p.hard.false_hits + p.hard.wrong_prims) as f64,
        )
    };
    let d = (!hard.is_empty()).then(|| Chart {
        title: "Hard-case failures against mantissa bits".into(),
        x_desc: "mantissa bits (stored, without the hidden bit)".into(),
        y_desc: "leaks + false hits + wrong prims, all hard cases".into(),
        x_integer: true,
        series: by_variant(&hard, true, hx),
        front: Vec::new(),
    });
    Ok(vec![
        plot(dir, "error-vs-lut.png", "Error against LUTs", Some(a), "")?,
        plot(
            dir,
            "error-vs-speed.png",
            "Error against rays/cycle",
            b,
            "no point has a timed run (`speed` is null everywhere)",
        )?,
        plot(
            dir,
            "error-vs-node-bytes.png",
            "Error against node bytes per ray",
            e,
            "no point has node bytes per ray (old point files)",
        )?,
        plot(
            dir,
            "pixels-vs-mantissa.png",
            "Pixels differing against mantissa bits",
            c,
            "no point has an image run (primary or ao rays)",
        )?,
        plot(
            dir,
            "hard-vs-mantissa.png",
            "Hard-case failures against mantissa bits",
            d,
            "no point ran the hard cases",
        )?,
    ])
}
