//! Derived metrics of the sweep: per run, pooled per point, and ratios
//! against the FP32 baseline of the same variant. These structs are what
//! docs/reports/speed-vs-error.json holds.

use crate::sweep::input::{AccuracyIn, Area, AreaIn, HardIn, Latency, PointConfig, RunIn, SpeedIn};
use crate::sweep::runs::{PixelDiff, TRel};
use serde::Serialize;

/// compare's classes. The first four are errors; tie, edge and
/// reference_wrong are shown apart as "not errors".
#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorCounts {
    pub false_miss: usize,
    pub false_hit: usize,
    pub wrong_prim: usize,
    pub t_error: usize,
    pub tie: usize,
    pub edge: usize,
    pub reference_wrong: usize,
}

impl ErrorCounts {
    pub fn of(a: &AccuracyIn) -> ErrorCounts {
        ErrorCounts {
            false_miss: a.count("false_miss"),
            false_hit: a.count("false_hit"),
            wrong_prim: a.count("wrong_prim"),
            t_error: a.count("t_error"),
            tie: a.count("tie"),
            edge: a.count("edge"),
            reference_wrong: a.count("reference_wrong"),
        }
    }

    pub fn add(&mut self, o: &ErrorCounts) {
        self.false_miss += o.false_miss;
        self.false_hit += o.false_hit;
        self.wrong_prim += o.wrong_prim;
        self.t_error += o.t_error;
        self.tie += o.tie;
        self.edge += o.edge;
        self.reference_wrong += o.reference_wrong;
    }

    /// The error plotted: false misses + false hits + wrong prims (a t
    /// error is a hit on the right triangle, shown in its own column).
    pub fn errors(&self) -> usize {
        self.false_miss + self.false_hit + self.wrong_prim
    }
}

#[derive(Serialize, Clone, Debug)]
pub struct RunOut {
    pub run: String,
    pub scene: String,
    pub rays: String,
    pub hard_case: Option<String>,
    pub package: String,
    pub hits: String,
    pub rays_total: usize,
    pub error_flagged: usize,
    pub node_tests_per_ray: f64,
    pub tri_tests_per_ray: f64,
    pub node_bytes_per_ray: Option<f64>,
    /// Non-hard runs: compare's counts.
    pub errors: Option<ErrorCounts>,
    /// compare's largest relative t difference among `agree` rays.
    pub max_t_rel_agree: Option<f64>,
    /// Non-hard runs: relative t error over rays hitting the reference's prim.
    pub t_rel: Option<TRel>,
    pub t_rel_mean: Option<f64>,
    /// Image runs (primary, ao): pixels differing from the baseline.
    pub pixels: Option<PixelDiff>,
    pub hard: Option<HardIn>,
    pub speed: Option<SpeedIn>,
}

impl RunOut {
    pub fn new(r: &RunIn, t_rel: Option<TRel>, pixels: Option<PixelDiff>) -> RunOut {
        RunOut {
            run: r.run.clone(),
            scene: r.scene.clone(),
            rays: r.rays.clone(),
            hard_case: r.hard_case.clone(),
            package: r.package.display().to_string(),
            hits: r.hits.display().to_string(),
            rays_total: r.rays_total,
            error_flagged: r.error_flagged,
            node_tests_per_ray: r.node_tests_per_ray,
            tri_tests_per_ray: r.tri_tests_per_ray,
            node_bytes_per_ray: r.node_bytes_per_ray,
            errors: r
                .accuracy
                .as_ref()
                .filter(|_| !r.is_hard())
                .map(ErrorCounts::of),
            max_t_rel_agree: r
                .accuracy
                .as_ref()
                .filter(|_| !r.is_hard())
                .map(|a| a.max_t_rel_agree),
            t_rel_mean: t_rel.and_then(|t| t.mean()),
            t_rel,
            pixels,
            hard: r.hard.clone(),
            speed: r.speed,
        }
    }
}

#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct SpeedAgg {
    pub runs: usize,
    /// Means over the non-hard runs that were timed.
    pub rays_per_cycle: f64,
    pub share_of_bound: f64,
    pub golden_mismatches: usize,
}

#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct HardTotals {
    pub cases: usize,
    pub leaks: usize,
    pub false_hits: usize,
    pub wrong_prims: usize,
    pub flagged: usize,
}

/// point / baseline; None when the baseline's value is zero or absent.
#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Ratios {
    pub lut: Option<f64>,
    pub ff: Option<f64>,
    pub dsp: Option<f64>,
    pub instances_zc706: Option<f64>,
    pub rays_per_cycle: Option<f64>,
    pub node_bytes_per_ray: Option<f64>,
    pub box_lane_lut: Option<f64>,
}

pub fn ratio(a: f64, b: f64) -> Option<f64> {
    (b != 0.0).then(|| a / b)
}

#[derive(Serialize, Clone, Debug)]
pub struct PointOut {
    pub name: String,
    pub config: PointConfig,
    pub variant: String,
    /// The FP32 point of the same variant that pixels and ratios refer to.
    pub baseline: String,
    pub latency: Latency,
    pub area: Area,
    /// Pooled over the non-hard runs.
    pub rays: usize,
    pub errors: ErrorCounts,
    pub errors_per_million_rays: f64,
    /// Rays the hardware flagged (hits-file `error` != 0), non-hard runs.
    pub error_flagged: usize,
    pub t_rel: TRel,
    pub t_rel_mean: Option<f64>,
    /// Pooled over the image runs (primary and ao).
    pub pixels: PixelDiff,
    pub pixel_share: Option<f64>,
    /// Ray-weighted means over the non-hard runs.
    pub node_tests_per_ray: f64,
    pub tri_tests_per_ray: f64,
    /// Ray-weighted mean over the non-hard runs; None if a run lacks it (old files).
    pub node_bytes_per_ray: Option<f64>,
    /// Image runs whose pixels differ from the baseline (any number > 0): "safe" needs none.
    pub images_differing: usize,
    pub speed: Option<SpeedAgg>,
    pub hard: HardTotals,
    pub vs_baseline: Ratios,
    pub pareto_error_lut: bool,
    pub pareto_error_speed: bool,
    pub pareto_error_bytes: bool,
    pub runs: Vec<RunOut>,
}

impl PointOut {
    /// Pools the runs; ratios and Pareto flags are filled in later.
    pub fn pool(
        config: &PointConfig,
        latency: Latency,
        area: &AreaIn,
        baseline: &str,
        mut runs: Vec<RunOut>,
    ) -> PointOut {
        runs.sort_by(|a, b| a.run.cmp(&b.run));
        let (mut errors, mut t_rel, mut pixels, mut hard) = (
            ErrorCounts::default(),
            TRel::default(),
            PixelDiff::default(),
            HardTotals::default(),
        );
        let (mut rays, mut flagged, mut node, mut tri) = (0usize, 0usize, 0.0, 0.0);
        let (mut bytes, mut images_differing) = (Some(0.0), 0usize);
        let mut speeds = Vec::new();
        for r in &runs {
            if let Some(e) = &r.errors {
                errors.add(e);
                rays += r.rays_total;
                flagged += r.error_flagged;
                node += r.node_tests_per_ray * r.rays_total as f64;
                tri += r.tri_tests_per_ray * r.rays_total as f64;
                bytes = bytes
                    .zip(r.node_bytes_per_ray)
                    .map(|(b, x)| b + x * r.rays_total as f64);
                if let Some(s) = &r.speed {
                    speeds.push(*s);
                }
            }
            t_rel.add(&r.t_rel.unwrap_or_default());
            pixels.add(&r.pixels.unwrap_or_default());
            images_differing += r.pixels.is_some_and(|p| p.differing > 0) as usize;
            if let Some(h) = &r.hard {
                hard.cases += 1;
                hard.leaks += h.leaks;
                hard.false_hits += h.false_hits;
                hard.wrong_prims += h.wrong_prims;
                hard.flagged += h.flagged;
            }
        }
        let mean = |f: fn(&SpeedIn) -> f64| speeds.iter().map(f).sum::<f64>() / speeds.len() as f64;
        let speed = (!speeds.is_empty()).then(|| SpeedAgg {
            runs: speeds.len(),
            rays_per_cycle: mean(|s| s.rays_per_cycle),
            share_of_bound: mean(|s| s.share_of_bound),
            golden_mismatches: speeds.iter().map(|s| s.golden_mismatches).sum(),
        });
        let per_ray = |x: f64| if rays > 0 { x / rays as f64 } else { 0.0 };
        PointOut {
            name: config.name.clone(),
            config: config.clone(),
            variant: config.variant(),
            baseline: baseline.to_string(),
            latency,
            area: area.cost.clone(),
            rays,
            errors_per_million_rays: per_ray(errors.errors() as f64 * 1e6),
            errors,
            error_flagged: flagged,
            t_rel_mean: t_rel.mean(),
            t_rel,
            pixel_share: pixels.share(),
            pixels,
            node_tests_per_ray: per_ray(node),
            tri_tests_per_ray: per_ray(tri),
            node_bytes_per_ray: bytes.map(per_ray),
            images_differing,
            speed,
            hard,
            vs_baseline: Ratios::default(),
            pareto_error_lut: false,
            pareto_error_speed: false,
            pareto_error_bytes: false,
            runs,
        }
    }

    pub fn set_ratios(&mut self, base: &PointOut) {
        let a = |p: &PointOut| {
            [p.area.lut, p.area.ff, p.area.dsp, p.area.instances_zc706].map(|x| x as f64)
        };
        let (x, b) = (a(self), a(base));
        self.vs_baseline = Ratios {
            lut: ratio(x[0], b[0]),
            ff: ratio(x[1], b[1]),
            dsp: ratio(x[2], b[2]),
            instances_zc706: ratio(x[3], b[3]),
            rays_per_cycle: self
                .speed
                .zip(base.speed)
                .and_then(|(s, t)| ratio(s.rays_per_cycle, t.rays_per_cycle)),
            node_bytes_per_ray: self
                .node_bytes_per_ray
                .zip(base.node_bytes_per_ray)
                .and_then(|(s, t)| ratio(s, t)),
            box_lane_lut: self
                .area
                .box_lanes
                .zip(base.area.box_lanes)
                .and_then(|(s, t)| ratio(s.lut as f64, t.lut as f64)),
        };
    }
}
