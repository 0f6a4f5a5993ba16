//! docs/reports/speed-vs-error.md, generated line by line from the report. Never
//! edit the output: hand-written text goes in the notes file beside it
//! (`<md stem>-notes.md`), which is included verbatim at the end.

use crate::sweep::metrics::PointOut;
use crate::sweep::plot::Plot;
use crate::sweep::report::{Report, ReportOpts};
use anyhow::{Context, Result};
use std::path::{Component, Path, PathBuf};

fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or("n/a".into(), f)
}

fn pct(v: Option<f64>) -> String {
    opt(v, |x| format!("{:.3}%", x * 100.0))
}

fn pct1(v: Option<f64>) -> String {
    opt(v, |x| format!("{:.1}%", x * 100.0))
}

fn sci(v: Option<f64>) -> String {
    opt(v, |x| {
        if x == 0.0 {
            "0".into()
        } else {
            format!("{x:.2e}")
        }
    })
}

fn x2(v: Option<f64>) -> String {
    opt(v, |x| format!("{x:.3}"))
}

/// `target` as a link from a document in `base` (both relative to the same
/// directory, or both absolute).
fn relative(target: &Path, base: &Path) -> PathBuf {
    let t: Vec<Component> = target
        .components()
        .filter(|c| *c != Component::CurDir)
        .collect();
    let b: Vec<Component> = base
        .components()
        .filter(|c| *c != Component::CurDir)
        .collect();
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out: PathBuf = b[common..].iter().map(|_| Component::ParentDir).collect();
    out.extend(&t[common..]);
    out
}

pub fn notes_path(md: &Path) -> PathBuf {
    let stem = md
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    md.with_file_name(format!("{stem}-notes.md"))
}

fn method(r: &Report) -> Vec<String> {
    let b = &r.baseline_format;
    [
        "## Method".to_string(),
        String::new(),
        "Each point is one hardware configuration, named `<layout>-<box format>-<triangle format>-<rounding>-<test>`: node layout \
         (`4`, `8`: FP32 child boxes, K wide; `4q`, `8q`: quantized child boxes), the box lanes' number format and the triangle \
         test's (`eXmY`: X exponent bits, Y stored mantissa bits), rounding of the box test (`rne` round-to-nearest-even, or \
         `conservative`: bounds rounded outward so a box is never missed; with a box format narrower than the triangle format the \
         box constants bound the triangle unit's FP32 ray, docs/kernels.md \"Split formats\"), and triangle test (`moller` \
         Möller–Trumbore or `watertight`). Each point ran the regression's runs (scene x ray set) and the hard cases."
            .into(),
        String::new(),
        "- **false miss / false hit / wrong prim / t err**: `nori-bridge compare` classes of the accelerator's hits against the \
         package's reference (Embree 3, or the f64 evaluator), each disagreement judged in f64 (docs/memory-format.md, accuracy.json). \
         Pooled over the non-hard runs. **tie / edge / ref wrong** are not errors: a tie hits another triangle at the same t (shared \
         edge or vertex), an edge case is within the format's error bound of an edge, and `ref wrong` means f64 sides with the hardware."
            .into(),
        "- **flagged**: rays whose hits-file `error` field is non-zero (the hardware raised its error flag), non-hard runs.".into(),
        "- **error** (plots, Pareto): (false misses + false hits + wrong prims) per million rays, pooled over the non-hard runs.".into(),
        format!(
            "- **% px diff**: share of image pixels that differ from the {b} point of the same variant, pooled over the image runs. \
             Primary rays: pixel = ray / spp; a pixel differs when any of its rays differs in hit flag or prim. Ambient-occlusion rays: \
             each AO ray belongs to the pixel of the primary hit it starts from (`ao_pixels.csv` of the package); a pixel differs when \
             its number of occluded AO rays differs (the AO rays are fixed by the package, cast from the reference's primary hits; a pixel \
             whose primary ray missed has none and never differs). Rays classed `tie` still count here: a different triangle changes the image."
        ),
        "- **mean / max rel t**: |t − t_ref| / max(|t|, |t_ref|) over the rays where the hardware and the reference hit the same prim \
         (computed by sweep-report from the hits files and reference.csv, not taken from compare; all same-prim rays, so t errors \
         count too)."
            .into(),
        "- **rays/cyc, % of bound**: mean over the timed non-hard runs of the cycle-accurate simulation's rays per cycle and its share \
         of the issue-rate bound. **node / tri per ray**: box and triangle tests per ray, ray-weighted mean over the non-hard runs \
         (a narrow format may visit more nodes)."
            .into(),
        "- **latency**: pipeline depth in cycles of the ray-preparation, box and triangle units. **LUT / FF / DSP**: Yosys \
         `synth_xilinx -family xc7` of the whole accelerator; **ZC706**: how many instances fit on its XC7Z045."
            .into(),
        "- **node B/ray**: node bytes read per ray (node fetches of the golden walk x the layout's node record size), ray-weighted mean over the non-hard runs. **box LUT**: Yosys LUTs of the K box lanes together.".into(),
        "- **safe**: zero false misses, false hits and wrong prims (ties apart), zero leaks, false hits and wrong prims on every hard case, \
         and zero pixels different from FP32 on every image (per image, `img diff` counts the images with any). **Smallest safe**: \
         fewest box + triangle format bits, then fewest LUTs.".into(),
    ]
    .into()
}

fn main_table(points: &[PointOut]) -> Vec<String> {
    let mut out = vec![
        "| point | layout | box | tri | rounding | test | false miss | false hit | wrong prim | t err | flagged | tie / edge / ref wrong | img diff | hard fail | % px diff | mean / max rel t | rays/cyc | % of bound | node / tri per ray | node B/ray | latency prep/box/tri | box LUT / FF / DSP | LUT | FF | DSP | ZC706 |".to_string(),
        "| --- | --- | --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |".to_string(),
    ];
    for p in points {
        let e = &p.errors;
        let l = &p.latency;
        out.push(format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} / {} / {} | {} | {} | {} | {} / {} | {} | {} | {:.2} / {:.2} | {} | {}/{}/{} | {} | {} | {} | {} | {} |",
            p.name, p.config.layout_label(), p.config.box_fmt(), p.config.tri_fmt(), p.config.rounding, p.config.triangle, e.false_miss, e.false_hit,
            e.wrong_prim, e.t_error, p.error_flagged, e.tie, e.edge, e.reference_wrong, p.images_differing,
            p.hard.leaks + p.hard.false_hits + p.hard.wrong_prims, pct(p.pixel_share), sci(p.t_rel_mean), sci(Some(p.t_rel.max)),
            x2(p.speed.map(|s| s.rays_per_cycle)), pct1(p.speed.map(|s| s.share_of_bound)), p.node_tests_per_ray, p.tri_tests_per_ray,
            p.node_bytes_per_ray.map_or("n/a".into(), |b| format!("{b:.0}")),
            l.ray_prep, l.box_test, l.triangle, p.area.box_lanes.map_or("n/a".into(), |b| format!("{} / {} / {}", b.lut, b.ff, b.dsp)),
            p.area.lut, p.area.ff, p.area.dsp, p.area.instances_zc706
        ));
    }
    out
}

fn ratio_table(points: &[PointOut]) -> Vec<String> {
    let mut out = vec![
        "| point | against | box-lane LUT | LUT | FF | DSP | ZC706 instances | node B/ray | rays/cyc | Pareto (error vs LUT, rays/cyc, node B/ray) |".to_string(),
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |".to_string(),
    ];
    for p in points {
        let r = &p.vs_baseline;
        let front = [
            (p.pareto_error_lut, "LUT"),
            (p.pareto_error_speed, "rays/cyc"),
            (p.pareto_error_bytes, "node B/ray"),
        ]
        .iter()
        .filter(|f| f.0)
        .map(|f| f.1)
        .collect::<Vec<_>>()
        .join(", ");
        out.push(format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            p.name,
            p.baseline,
            x2(r.box_lane_lut),
            x2(r.lut),
            x2(r.ff),
            x2(r.dsp),
            x2(r.instances_zc706),
            x2(r.node_bytes_per_ray),
            x2(r.rays_per_cycle),
            front
        ));
    }
    out
}

fn run_table(points: &[PointOut]) -> Vec<String> {
    let mut out = vec![
        "| point | run | rays | false miss / hit / wrong prim / t err | tie / edge / ref wrong | px diff | mean / max rel t | node / tri per ray | node B/ray | rays/cyc | % of bound | golden mismatches |".to_string(),
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |".to_string(),
    ];
    for p in points {
        for r in p.runs.iter().filter(|r| r.hard_case.is_none()) {
            let e = r.errors.unwrap_or_default();
            out.push(format!(
                "| {} | {} | {} | {} / {} / {} / {} | {} / {} / {} | {} | {} / {} | {:.2} / {:.2} | {} | {} | {} | {} |",
                p.name, r.run, r.rays_total, e.false_miss, e.false_hit, e.wrong_prim, e.t_error, e.tie, e.edge, e.reference_wrong,
                r.pixels.map_or("n/a".into(), |d| format!("{} / {}", d.differing, d.total)),
                sci(r.t_rel_mean), sci(r.t_rel.map(|t| t.max)), r.node_tests_per_ray, r.tri_tests_per_ray,
                r.node_bytes_per_ray.map_or("n/a".into(), |b| format!("{b:.0}")),
                x2(r.speed.map(|s| s.rays_per_cycle)), pct1(r.speed.map(|s| s.share_of_bound)),
                r.speed.map_or("n/a".into(), |s| s.golden_mismatches.to_string())
            ));
        }
    }
    out
}

fn fronts(r: &Report) -> Vec<String> {
    let describe = |names: &[String], speed: bool| -> String {
        let items: Vec<String> = names
            .iter()
            .filter_map(|n| r.points.iter().find(|p| &p.name == n))
            .map(|p| {
                let x = if speed {
                    format!("{} rays/cyc", x2(p.speed.map(|s| s.rays_per_cycle)))
                } else {
                    format!("{} LUT", p.area.lut)
                };
                format!(
                    "{} ({:.1} errors/Mray, {x})",
                    p.name, p.errors_per_million_rays
                )
            })
            .collect();
        if items.is_empty() {
            "none".into()
        } else {
            items.join("; ")
        }
    };
    let mut out = vec![
        "## Pareto fronts".to_string(),
        String::new(),
        format!("- error vs LUT: {}", describe(&r.pareto.error_lut, false)),
        format!(
            "- error vs rays/cycle: {}",
            describe(&r.pareto.error_speed, true)
        ),
        format!(
            "- error vs node bytes per ray: {}",
            r.pareto.error_bytes.join(", ")
        ),
    ];
    if !r.pareto.without_speed.is_empty() {
        out.push(format!(
            "- not timed, so not on the speed front or plot: {}",
            r.pareto.without_speed.join(", ")
        ));
    }
    out
}

pub fn document(r: &Report, o: &ReportOpts, plots: &[Plot]) -> Result<String> {
    let md_dir = o.md.parent().unwrap_or(Path::new(""));
    let mut l: Vec<String> = vec![
        "# Speed against error: the precision sweep (`make speed-vs-error`)".into(),
        String::new(),
        "<!-- Generated file: do not edit. Hand-written notes go in the -notes.md file beside it. -->".into(),
        String::new(),
        format!(
            "Generated by `nori-bridge sweep-report --sweep {} --json {} --md {} --plots {} --baseline-format {}` from {} points.",
            o.sweep.display(), o.json.display(), o.md.display(), o.plots.display(), r.baseline_format, r.points.len()
        ),
        format!("Sweep time: {}.", o.runtime_note.as_deref().unwrap_or("not recorded (the caller passed no --runtime-note)")),
        format!(
            "Job time: the wall times of the point jobs sum to {:.0} min and those of the area jobs (Yosys; units already in \
             `build/area-cache/` cost nothing) to {:.0} min, {:.0} min in all: about {:.0} min of wall time at two jobs at a time (`make -j2`).",
            r.job_seconds.points / 60.0, r.job_seconds.area / 60.0,
            (r.job_seconds.points + r.job_seconds.area) / 60.0, (r.job_seconds.points + r.job_seconds.area) / 120.0
        ),
        String::new(),
        "## Smallest safe configuration".into(),
        String::new(),
        r.summary.clone(),
        String::new(),
    ];
    l.push("Per variant:".into());
    l.push(String::new());
    l.extend(crate::sweep::summary::per_variant(
        &r.points,
        &r.baseline_format,
    ));
    l.push(String::new());
    l.extend(method(r));
    l.extend([String::new(), "## Points".into(), String::new()]);
    l.extend(main_table(&r.points));
    let golden: Vec<String> = r
        .points
        .iter()
        .filter_map(|p| {
            p.speed
                .filter(|s| s.golden_mismatches > 0)
                .map(|s| format!("{} ({})", p.name, s.golden_mismatches))
        })
        .collect();
    let timed = |p: &PointOut| {
        p.runs
            .iter()
            .filter(|r| r.speed.is_some() && r.hard_case.is_none())
            .map(|r| r.run.clone())
            .collect::<Vec<_>>()
    };
    let sets: Vec<Vec<String>> = r
        .points
        .iter()
        .map(timed)
        .filter(|v| !v.is_empty())
        .collect();
    if sets.windows(2).any(|w| w[0] != w[1]) {
        l.extend([String::new(), "**Warning:** the points were timed on different runs, so their mean rays/cycle are not directly comparable (see the per-run table).".into()]);
    }
    if !golden.is_empty() {
        l.extend([
            String::new(),
            format!(
                "**Warning:** the timed simulation disagreed with its golden model on: {}.",
                golden.join(", ")
            ),
        ]);
    }
    l.extend([String::new(), format!("## Against {} (ratio point / baseline: same rounding and test, the unquantized layout of the same width)", r.baseline_format), String::new()]);
    l.extend(ratio_table(&r.points));
    l.extend([String::new(), "## Plots".into(), String::new()]);
    for p in plots {
        match &p.missing {
            None => l.push(format!(
                "![{}]({})",
                p.title,
                relative(&p.file, md_dir).display()
            )),
            Some(why) => l.push(format!("{}: not drawn, {why}.", p.title)),
        }
        l.push(String::new());
    }
    l.extend(fronts(r));
    l.extend([String::new(), "## Per run".into(), String::new()]);
    l.extend(run_table(&r.points));
    l.push(String::new());
    l.extend(crate::sweep::md_hard::section(r, &notes_path(&o.md)));
    l.extend([
        String::new(),
        "## Notes (hand-written)".into(),
        String::new(),
    ]);
    let notes = notes_path(&o.md);
    if notes.exists() {
        l.push(
            std::fs::read_to_string(&notes)
                .with_context(|| format!("{}: cannot read", notes.display()))?
                .trim_end()
                .to_string(),
        );
    } else {
        l.push(format!("None yet: write them in `{}`.", notes.display()));
    }
    Ok(l.join("\n") + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_are_relative_to_the_document() {
        assert_eq!(
            relative(
                Path::new("docs/reports/speed-vs-error/a.png"),
                Path::new("docs/reports")
            ),
            PathBuf::from("speed-vs-error/a.png")
        );
        assert_eq!(
            relative(Path::new("build/p/a.png"), Path::new("./docs")),
            PathBuf::from("../build/p/a.png")
        );
        assert_eq!(
            notes_path(Path::new("docs/reports/speed-vs-error.md")),
            PathBuf::from("docs/reports/speed-vs-error-notes.md")
        );
    }
}
