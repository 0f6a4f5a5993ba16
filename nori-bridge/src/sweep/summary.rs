//! The headline: the smallest format with zero false misses and
//! fewer than 0.1% of pixels differing from FP32, and its area saving.

use crate::sweep::metrics::PointOut;

/// Pixels may differ from FP32 on fewer than this share (0.1%).
pub const MAX_PIXEL_SHARE: f64 = 0.001;

/// What the selection looks at, per point.
#[derive(Clone, Copy, Debug)]
pub struct Candidate<'a> {
    pub name: &'a str,
    /// exponent + mantissa bits (the sign bit is common to all).
    pub bits: u32,
    pub lut: u64,
    pub false_miss: usize,
    /// None when the point has no image run.
    pub pixel_share: Option<f64>,
}

impl<'a> From<&'a PointOut> for Candidate<'a> {
    fn from(p: &'a PointOut) -> Self {
        Candidate {
            name: &p.name,
            bits: p.config.exp_bits + p.config.man_bits,
            lut: p.area.lut,
            false_miss: p.errors.false_miss,
            pixel_share: p.pixel_share,
        }
    }
}

pub fn qualifies(c: &Candidate) -> bool {
    c.false_miss == 0 && c.pixel_share.is_some_and(|s| s < MAX_PIXEL_SHARE)
}

/// Index of the qualifying point with the fewest bits; ties go to the
/// smaller LUT count, then to the name (deterministic).
pub fn smallest_safe(cands: &[Candidate]) -> Option<usize> {
    (0..cands.len()).filter(|&i| qualifies(&cands[i])).min_by(|&a, &b| {
        let k = |c: &Candidate<'_>| (c.bits, c.lut, c.name.to_string());
        k(&cands[a]).cmp(&k(&cands[b]))
    })
}

fn saving(r: Option<f64>) -> String {
    r.map_or("n/a (baseline value 0)".into(), |r| format!("{:.1}%", (1.0 - r) * 100.0))
}

fn savings(p: &PointOut) -> String {
    let r = &p.vs_baseline;
    format!("saving {} LUT ({} FF, {} DSP) against FP32 ({}, same variant)", saving(r.lut), saving(r.ff), saving(r.dsp), p.baseline)
}

fn none_qualifies(baseline_format: &str) -> String {
    format!(
        "No configuration qualifies: none has zero false misses together with fewer than {}% of pixels different from {baseline_format} \
         (a point without an image run cannot qualify).",
        MAX_PIXEL_SHARE * 100.0
    )
}

/// The sentence about `points`.
pub fn sentence(points: &[PointOut], baseline_format: &str) -> String {
    let cands: Vec<Candidate> = points.iter().map(Candidate::from).collect();
    let Some(i) = smallest_safe(&cands) else { return none_qualifies(baseline_format) };
    let p = &points[i];
    format!(
        "The smallest format with zero false misses and < {}% pixels different from FP32 is **{}** ({} rounding, {} test; point {}), {}. \
         It differs from FP32 on {} of pixels; its hard-case leaks: {} over {} case(s).",
        MAX_PIXEL_SHARE * 100.0,
        p.config.float,
        p.config.rounding,
        p.config.triangle,
        p.name,
        savings(p),
        p.pixel_share.map_or("n/a".into(), |s| format!("{:.4}%", s * 100.0)),
        p.hard.leaks,
        p.hard.cases
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

/// One line per variant: its smallest safe format, or none.
pub fn per_variant(points: &[PointOut], baseline_format: &str) -> Vec<String> {
    let mut variants: Vec<&str> = points.iter().map(|p| p.variant.as_str()).collect();
    variants.sort();
    variants.dedup();
    variants
        .into_iter()
        .map(|v| {
            let mine: Vec<&PointOut> = points.iter().filter(|p| p.variant == v).collect();
            let cands: Vec<Candidate> = mine.iter().map(|p| Candidate::from(*p)).collect();
            match smallest_safe(&cands) {
                Some(i) => format!("- {v}: **{}**, {}", mine[i].config.float, savings(mine[i])),
                None => format!("- {v}: {}", none_qualifies(baseline_format)),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(name: &str, bits: u32, lut: u64, fm: usize, px: Option<f64>) -> Candidate<'_> {
        Candidate { name, bits, lut, false_miss: fm, pixel_share: px }
    }

    #[test]
    fn picks_fewest_bits_among_points_with_no_false_miss_and_few_pixels() {
        let v = [
            c("e8m23-rne-wt", 31, 9000, 0, Some(0.0)),
            c("e8m10-rne-wt", 18, 5000, 0, Some(0.0005)),
            c("e8m7-rne-wt", 15, 4000, 0, Some(0.002)), // too many pixels
            c("e6m9-rne-wt", 15, 3900, 3, Some(0.0)), // false misses
            c("e8m12-rne-mt", 20, 4500, 0, Some(0.0)),
        ];
        assert_eq!(smallest_safe(&v), Some(1));
    }

    #[test]
    fn exactly_the_limit_does_not_qualify_and_no_image_run_never_does() {
        assert!(!qualifies(&c("a", 10, 1, 0, Some(MAX_PIXEL_SHARE))));
        assert!(!qualifies(&c("a", 10, 1, 0, None)));
        assert!(qualifies(&c("a", 10, 1, 0, Some(MAX_PIXEL_SHARE * 0.999))));
    }

    #[test]
    fn ties_in_bits_go_to_fewer_luts_then_name_and_none_when_nothing_qualifies() {
        let v = [c("b", 18, 5000, 0, Some(0.0)), c("a", 18, 5000, 0, Some(0.0)), c("c", 18, 4000, 0, Some(0.0))];
        assert_eq!(smallest_safe(&v), Some(2));
        assert_eq!(smallest_safe(&v[..2]), Some(1));
        assert_eq!(smallest_safe(&[c("x", 8, 1, 1, Some(0.0))]), None);
        assert_eq!(smallest_safe(&[]), None);
    }
}
