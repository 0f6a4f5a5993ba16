//! `nori-bridge sweep-report`: the precision sweep's per-point JSON files
//! in; docs/reports/speed-vs-error.{json,md} and PNG plots out.

use crate::package::compile::write_json;
use crate::ray::Hit;
use crate::sweep::input::{self, HardIn, PointIn, SweepIn};
use crate::sweep::metrics::{PointOut, RunOut};
use crate::sweep::pareto;
use crate::sweep::runs::{PackageData, PixelDiff, TRel};
use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub struct ReportOpts {
    pub sweep: PathBuf,
    pub json: PathBuf,
    pub md: PathBuf,
    /// Directory for the PNGs.
    pub plots: PathBuf,
    /// The reference format pixels and ratios are measured against.
    pub baseline_format: String,
    /// How long the sweep took, as the caller wants it quoted.
    pub runtime_note: Option<String>,
}

#[derive(Serialize)]
pub struct Fronts {
    /// Names along the (errors per Mray, LUT) front, by error.
    pub error_lut: Vec<String>,
    /// Names along the (errors per Mray, rays/cycle) front, by error.
    pub error_speed: Vec<String>,
    /// Names along the (errors per Mray, node bytes per ray) front, by error.
    pub error_bytes: Vec<String>,
    /// Points that have no timed run and so are not on the speed plot.
    pub without_speed: Vec<String>,
}

#[derive(Serialize)]
pub struct Report {
    pub format_version: u32,
    pub sweep: String,
    pub baseline_format: String,
    pub points: Vec<PointOut>,
    pub pareto: Fronts,
    pub summary: String,
    /// Variant ("rounding/triangle") -> name of its smallest safe point (see summary.rs).
    pub smallest_safe: BTreeMap<String, Option<String>>,
    /// hard case -> embree | robust | double -> hard-score verdict.
    pub hard_references: BTreeMap<String, BTreeMap<String, HardIn>>,
    /// Sum of the wall seconds of every point job and area job: the sweep's
    /// cost whatever order or machines the jobs ran on.
    pub job_seconds: JobSeconds,
}

#[derive(Serialize, Clone, Copy, Debug, Default)]
pub struct JobSeconds {
    pub points: f64,
    pub area: f64,
}

/// Resolves the baseline point of every point: same rounding and triangle
/// test, boxes and triangles in the baseline format, on the unquantized
/// layout of the same width (4q is measured against FP32 on 4-wide nodes).
fn baselines(s: &SweepIn, format: &str) -> Result<Vec<usize>> {
    s.points
        .iter()
        .map(|(p, _)| {
            let c = &p.config;
            s.points
                .iter()
                .position(|(q, _)| {
                    let d = &q.config;
                    d.box_fmt() == format && d.tri_fmt() == format && d.rounding == c.rounding && d.triangle == c.triangle && d.layout == c.plain_layout() && !d.grid()
                })
                .with_context(|| {
                    format!(
                        "{}: no baseline for point '{}': need a point with layout {}, box and triangle format {format}, rounding {}, triangle {}",
                        s.dir.join("points").display(), c.name, c.plain_layout(), c.rounding, c.triangle
                    )
                })
        })
        .collect()
}

/// Every hard case must be run by every point (one table, no holes).
fn check_hard_cases(s: &SweepIn) -> Result<()> {
    let all: Vec<&String> = s.hard_refs.keys().collect();
    for (p, _) in &s.points {
        let mut mine: Vec<&String> = p.runs.iter().filter_map(|r| r.hard_case.as_ref()).collect();
        mine.sort();
        mine.dedup();
        if mine != all {
            let missing: Vec<&&String> = all.iter().filter(|c| !mine.contains(c)).collect();
            bail!(
                "{}: point '{}' lacks hard case(s) {missing:?} that other points run",
                s.dir
                    .join("points")
                    .join(format!("{}.json", p.config.name))
                    .display(),
                p.config.name
            );
        }
    }
    Ok(())
}

fn point_runs(
    p: &PointIn,
    base: &PointIn,
    base_hits: &BTreeMap<String, Vec<Hit>>,
    pkgs: &BTreeMap<PathBuf, PackageData>,
) -> Result<Vec<RunOut>> {
    p.runs
        .iter()
        .map(|r| {
            if r.is_hard() {
                return Ok(RunOut::new(r, None, None));
            }
            let pkg = &pkgs[&r.package];
            if pkg.reference.len() != r.rays_total {
                bail!("point '{}', run '{}': `rays_total` {} but package {} has {} rays", p.config.name, r.run, r.rays_total, r.package.display(), pkg.reference.len());
            }
            if pkg.manifest.ray_kind != r.rays {
                bail!("point '{}', run '{}': `rays` is '{}' but package {} holds '{}' rays", p.config.name, r.run, r.rays, r.package.display(), pkg.manifest.ray_kind);
            }
            let got = pkg.read_answer(&r.hits).with_context(|| format!("point '{}', run '{}'", p.config.name, r.run))?;
            let t_rel = TRel::of(&got, &pkg.reference);
            let pixels = match &pkg.pixels {
                None => None,
                Some((map, total)) => {
                    let b = base.runs.iter().find(|b| b.run == r.run).with_context(|| {
                        format!("baseline point '{}' has no run '{}' (point '{}' has)", base.config.name, r.run, p.config.name)
                    })?;
                    // The baseline may run another node layout (4q against 4): another
                    // package, but the same rays, which is what pixels compare.
                    if b.rays_total != r.rays_total || b.rays != r.rays {
                        bail!("run '{}': {} {} rays in point '{}' but {} {} rays in its baseline '{}'", r.run, r.rays_total, r.rays, p.config.name, b.rays_total, b.rays, base.config.name);
                    }
                    Some(PixelDiff::of(map, *total, &got, &base_hits[&r.run]))
                }
            };
            Ok(RunOut::new(r, Some(t_rel), pixels))
        })
        .collect()
}

pub fn build(sweep: &Path, baseline_format: &str) -> Result<Report> {
    let s = input::load(sweep)?;
    check_hard_cases(&s)?;
    let base_of = baselines(&s, baseline_format)?;
    let mut dirs: Vec<&PathBuf> = s
        .points
        .iter()
        .flat_map(|(p, _)| p.runs.iter().filter(|r| !r.is_hard()).map(|r| &r.package))
        .collect();
    dirs.sort();
    dirs.dedup();
    let pkgs: BTreeMap<PathBuf, PackageData> = dirs
        .par_iter()
        .map(|d| Ok(((*d).clone(), PackageData::load(d)?)))
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .collect();
    let mut bases: Vec<usize> = base_of.clone();
    bases.sort();
    bases.dedup();
    let base_hits: BTreeMap<usize, BTreeMap<String, Vec<Hit>>> = bases
        .par_iter()
        .map(|&b| {
            let p = &s.points[b].0;
            let runs = p
                .runs
                .iter()
                .filter(|r| !r.is_hard())
                .map(|r| Ok((r.run.clone(), pkgs[&r.package].read_answer(&r.hits)?)));
            Ok((b, runs.collect::<Result<BTreeMap<_, _>>>()?))
        })
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .collect();
    let mut points: Vec<PointOut> = (0..s.points.len())
        .into_par_iter()
        .map(|i| {
            let ((p, area), b) = (&s.points[i], base_of[i]);
            let runs = point_runs(p, &s.points[b].0, &base_hits[&b], &pkgs)?;
            Ok(PointOut::pool(
                &p.config,
                p.latency,
                area,
                &s.points[b].0.config.name,
                runs,
            ))
        })
        .collect::<Result<_>>()?;
    let snapshot = points.clone();
    for (i, p) in points.iter_mut().enumerate() {
        p.set_ratios(&snapshot[base_of[i]]);
    }
    let pareto = mark_fronts(&mut points);
    let summary = crate::sweep::summary::sentence(&points, baseline_format);
    let smallest_safe = crate::sweep::summary::safe_by_variant(&points);
    let job_seconds = JobSeconds {
        points: s.points.iter().map(|(p, _)| p.seconds).sum(),
        area: s.points.iter().map(|(_, a)| a.seconds).sum(),
    };
    Ok(Report {
        job_seconds,
        format_version: 1,
        sweep: sweep.display().to_string(),
        baseline_format: baseline_format.to_string(),
        points,
        pareto,
        summary,
        smallest_safe,
        hard_references: s.hard_refs,
    })
}

fn mark_fronts(points: &mut [PointOut]) -> Fronts {
    let err = |p: &PointOut| p.errors_per_million_rays;
    let lut: Vec<(f64, f64)> = points.iter().map(|p| (err(p), p.area.lut as f64)).collect();
    let timed: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].speed.is_some())
        .collect();
    let speed: Vec<(f64, f64)> = timed
        .iter()
        .map(|&i| (err(&points[i]), -points[i].speed.unwrap().rays_per_cycle))
        .collect();
    let bytes: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (err(p), p.node_bytes_per_ray.unwrap_or(f64::INFINITY)))
        .collect();
    let f_bytes = pareto::front(&bytes);
    for &i in &f_bytes {
        points[i].pareto_error_bytes = true;
    }
    let f_lut = pareto::front(&lut);
    let f_speed: Vec<usize> = pareto::front(&speed)
        .into_iter()
        .map(|k| timed[k])
        .collect();
    for &i in &f_lut {
        points[i].pareto_error_lut = true;
    }
    for &i in &f_speed {
        points[i].pareto_error_speed = true;
    }
    let names = |v: &[usize]| v.iter().map(|&i| points[i].name.clone()).collect();
    Fronts {
        error_lut: names(&f_lut),
        error_speed: names(&f_speed),
        error_bytes: names(&f_bytes),
        without_speed: points
            .iter()
            .filter(|p| p.speed.is_none())
            .map(|p| p.name.clone())
            .collect(),
    }
}

pub fn run(o: &ReportOpts) -> Result<()> {
    let report = build(&o.sweep, &o.baseline_format)?;
    for f in [&o.json, &o.md] {
        if let Some(d) = f.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(d)
                .with_context(|| format!("{}: cannot create", d.display()))?;
        }
    }
    write_json(&o.json, &report)?;
    let plots = crate::sweep::plot::write_all(&report, &o.plots)?;
    let md = crate::sweep::md::document(&report, o, &plots)?;
    std::fs::write(&o.md, md).with_context(|| format!("{}: cannot write", o.md.display()))?;
    println!(
        "{}: {} points; {}; plots in {}",
        o.md.display(),
        report.points.len(),
        o.json.display(),
        o.plots.display()
    );
    Ok(())
}
