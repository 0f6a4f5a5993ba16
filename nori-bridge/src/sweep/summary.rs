//! The headline: the smallest safe configuration (box and triangle
//! formats, layout), its t error, and whether it meets the goal against the
//! FP32 layout of the same width.
//!
//! Safe means safe: zero false misses, zero false hits and zero wrong
//! primitives (ties, a different triangle at the same f64 t, are classed
//! apart by compare and documented), zero leaks, false hits or wrong
//! primitives on every hard case, and zero pixels different from FP32 on
//! every image (per image, not pooled).

use crate::sweep::input::format_bits;
use crate::sweep::metrics::PointOut;

/// The narrow-format goal, against the FP32 layout of the same width.
pub const GOAL_BOX_LUT_RATIO: f64 = 0.6;
pub const GOAL_NODE_BYTES_RATIO: f64 = 0.5;

/// What the selection looks at, per point.
#[derive(Clone, Debug)]
pub struct Candidate<'a> {
    pub name: &'a str,
    /// Box + triangle format bits (exponent + mantissa each).
    pub bits: u32,
    pub lut: u64,
    /// false misses + false hits + wrong prims, non-hard runs.
    pub errors: usize,
    /// leaks + false hits + wrong prims over the hard cases.
    pub hard: usize,
    /// Image runs with any pixel different from FP32; None when the point has no image run.
    pub images_differing: Option<usize>,
}

impl<'a> From<&'a PointOut> for Candidate<'a> {
    fn from(p: &'a PointOut) -> Self {
        let images = p.runs.iter().filter(|r| r.pixels.is_some()).count();
        Candidate {
            name: &p.name,
            bits: format_bits(p.config.box_fmt()) + format_bits(p.config.tri_fmt()),
            lut: p.area.lut,
            errors: p.errors.errors(),
            hard: p.hard.leaks + p.hard.false_hits + p.hard.wrong_prims,
            images_differing: (images > 0).then_some(p.images_differing),
        }
    }
}

pub fn qualifies(c: &Candidate) -> bool {
    c.errors == 0 && c.hard == 0 && c.images_differing == Some(0)
}

/// Index of the safe point with the fewest format bits; ties go to the
/// smaller LUT count, then to the name (deterministic).
pub fn smallest_safe(cands: &[Candidate]) -> Option<usize> {
    (0..cands.len())
        .filter(|&i| qualifies(&cands[i]))
        .min_by(|&a, &b| {
            let k = |c: &Candidate<'_>| (c.bits, c.lut, c.name.to_string());
            k(&cands[a]).cmp(&k(&cands[b]))
        })
}

fn saving(r: Option<f64>) -> String {
    r.map_or("n/a".into(), |r| format!("{:.1}%", (1.0 - r) * 100.0))
}

/// A ratio against FP32 as a change: "33.1% fewer", "17.1% more" (a point
/// can cost more than FP32 in one resource while saving in another).
fn change(r: Option<f64>) -> String {
    match r {
        None => "n/a".into(),
        // Within the 0.1% the sentence prints.
        Some(r) if (r - 1.0).abs() < 5e-4 => "unchanged".into(),
        Some(r) if r > 1.0 => format!("{:.1}% more", (r - 1.0) * 100.0),
        Some(r) => format!("{:.1}% fewer", (1.0 - r) * 100.0),
    }
}

fn savings(p: &PointOut) -> String {
    let r = &p.vs_baseline;
    format!(
        "against FP32 ({}): box-lane LUTs {}, core LUTs {} (FF {}, DSP {}), node bytes per ray {}",
        p.baseline,
        change(r.box_lane_lut),
        change(r.lut),
        change(r.ff),
        change(r.dsp),
        change(r.node_bytes_per_ray)
    )
}

/// The goal, checked item by item: (met, sentence).
pub fn goal(p: &PointOut) -> (bool, String) {
    let r = &p.vs_baseline;
    let lut = r.box_lane_lut.is_some_and(|x| x <= GOAL_BOX_LUT_RATIO);
    let bytes = r
        .node_bytes_per_ray
        .is_some_and(|x| x <= GOAL_NODE_BYTES_RATIO);
    let speed = r.rays_per_cycle.is_some_and(|x| x > 1.0);
    let yes = |b: bool| if b { "met" } else { "NOT met" };
    (
        lut && bytes && speed,
        format!(
            ">= 40% fewer box-lane LUTs: {} ({}); >= 2x fewer node bytes per ray: {} (ratio {}); rays/cycle above FP32's on the DDR model: {} (ratio {}).",
            yes(lut), saving(r.box_lane_lut), yes(bytes), r.node_bytes_per_ray.map_or("n/a".into(), |x| format!("{x:.3}")),
            yes(speed), r.rays_per_cycle.map_or("n/a".into(), |x| format!("{x:.3}"))
        ),
    )
}

fn none_qualifies() -> String {
    "No configuration is safe: none has zero false misses, false hits and wrong primitives, zero hard-case failures and zero \
     pixels different from FP32 on every image (a point without an image run cannot qualify)."
        .into()
}

/// The sentence about `points`.
pub fn sentence(points: &[PointOut], _baseline_format: &str) -> String {
    let cands: Vec<Candidate> = points.iter().map(Candidate::from).collect();
    let Some(i) = smallest_safe(&cands) else {
        return none_qualifies();
    };
    let p = &points[i];
    let (met, g) = goal(p);
    format!(
        "The smallest safe configuration is **{}**: {} nodes, boxes in **{}** ({} rounding), triangles in **{}** ({} test), {}. \
         Its t error: {} same-primitive hits outside FP32's tolerance, mean relative t error {}. Goal {}: {}",
        p.name,
        p.config.layout_label(),
        p.config.box_fmt(),
        p.config.rounding,
        p.config.tri_fmt(),
        p.config.triangle,
        savings(p),
        p.errors.t_error,
        p.t_rel_mean.map_or("n/a".into(), |x| format!("{x:.2e}")),
        if met { "met" } else { "not met" },
        g
    )
}

/// Each variant's smallest safe point (its name), or None: the machine-readable
/// form of `per_variant`, which `make verilog FLOAT=auto` reads.
pub fn safe_by_variant(points: &[PointOut]) -> std::collections::BTreeMap<String, Option<String>> {
    let mut out = std::collections::BTreeMap::new();
    for p in points {
        out.entry(p.variant.clone()).or_insert(None);
    }
    for (v, slot) in out.iter_mut() {
        let mine: Vec<&PointOut> = points.iter().filter(|p| &p.variant == v).collect();
        let cands: Vec<Candidate> = mine.iter().map(|p| Candidate::from(*p)).collect();
        *slot = smallest_safe(&cands).map(|i| mine[i].name.clone());
    }
    out
}

/// One line per variant: its smallest safe configuration, or none.
pub fn per_variant(points: &[PointOut], _baseline_format: &str) -> Vec<String> {
    let mut variants: Vec<&str> = points.iter().map(|p| p.variant.as_str()).collect();
    variants.sort();
    variants.dedup();
    variants
        .into_iter()
        .map(|v| {
            let mine: Vec<&PointOut> = points.iter().filter(|p| p.variant == v).collect();
            let cands: Vec<Candidate> = mine.iter().map(|p| Candidate::from(*p)).collect();
            match smallest_safe(&cands) {
                Some(i) => format!(
                    "- {v}: **{}** ({} nodes, boxes {}, triangles {}), {}",
                    mine[i].name,
                    mine[i].config.layout_label(),
                    mine[i].config.box_fmt(),
                    mine[i].config.tri_fmt(),
                    savings(mine[i])
                ),
                None => format!("- {v}: {}", none_qualifies()),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(
        name: &str,
        bits: u32,
        lut: u64,
        errors: usize,
        hard: usize,
        images: Option<usize>,
    ) -> Candidate<'_> {
        Candidate {
            name,
            bits,
            lut,
            errors,
            hard,
            images_differing: images,
        }
    }

    #[test]
    fn picks_fewest_bits_among_points_with_no_error_no_hard_failure_and_no_differing_image() {
        let v = [
            c("4-e8m23-e8m23-cons-wt", 62, 9000, 0, 0, Some(0)),
            c("4q-e8m10-e8m23-cons-wt", 49, 5000, 0, 0, Some(0)),
            c("4q-e8m7-e8m23-cons-wt", 46, 4000, 0, 0, Some(1)), // one image differs
            c("4q-e6m9-e8m23-cons-wt", 46, 3900, 0, 2, Some(0)), // hard-case failures
            c("4q-e8m10-e8m15-cons-wt", 41, 3500, 3, 0, Some(0)), // errors
        ];
        assert_eq!(smallest_safe(&v), Some(1));
    }

    #[test]
    fn no_image_run_never_qualifies() {
        assert!(!qualifies(&c("a", 10, 1, 0, 0, None)));
        assert!(qualifies(&c("a", 10, 1, 0, 0, Some(0))));
    }

    #[test]
    fn ties_in_bits_go_to_fewer_luts_then_name_and_none_when_nothing_qualifies() {
        let v = [
            c("b", 18, 5000, 0, 0, Some(0)),
            c("a", 18, 5000, 0, 0, Some(0)),
            c("c", 18, 4000, 0, 0, Some(0)),
        ];
        assert_eq!(smallest_safe(&v), Some(2));
        assert_eq!(smallest_safe(&v[..2]), Some(1));
        assert_eq!(smallest_safe(&[c("x", 8, 1, 1, 0, Some(0))]), None);
        assert_eq!(smallest_safe(&[]), None);
    }
}
