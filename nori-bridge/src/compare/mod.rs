//! `nori-bridge compare`: classify every ray of a hits file against the
//! package's reference and write accuracy.json.

pub mod judge;
pub mod pixels;
pub mod render;

use crate::compare::judge::{Class, Judge, Tolerances};
use crate::ray::{Hit, Ray};
use anyhow::{bail, Result};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// Ray numbers listed per class are capped so a broken run stays readable.
pub const LIST_CAP: usize = 10_000;
pub const WORST_CAP: usize = 20;
/// Shadow disagreements are judged by an f64 brute force over all
/// triangles; above this many ray x triangle tests (about a minute on two
/// cores) they are reported as mismatches without judging.
pub const SHADOW_JUDGE_BUDGET: f64 = 5e9;

#[derive(Serialize)]
pub struct Case {
    pub ray: usize,
    pub class: Class,
    pub hits: HitView,
    pub reference: HitView,
}

#[derive(Serialize)]
pub struct HitView {
    pub hit: bool,
    pub t: f32,
    pub prim: i64,
}

impl From<&Hit> for HitView {
    fn from(h: &Hit) -> Self {
        HitView {
            hit: h.hit,
            t: h.t,
            prim: h.prim,
        }
    }
}

#[derive(Serialize)]
pub struct Accuracy {
    pub format_version: u32,
    pub rays: usize,
    pub shadow_rays: usize,
    /// false when shadow disagreements were too many to judge (see
    /// SHADOW_JUDGE_BUDGET): they are then all counted as mismatches.
    pub shadow_judged: bool,
    pub tolerances: Tolerances,
    /// Count per class (agree, tie, edge, reference_wrong, false_miss, ...).
    pub counts: BTreeMap<Class, usize>,
    /// false_miss + false_hit + wrong_prim + t_error.
    pub mismatches: usize,
    /// Rays whose hits-file `error` field is non-zero.
    pub error_flagged: usize,
    /// Largest relative t difference among rays classed `agree` with a hit.
    pub max_t_rel_agree: f64,
    /// Ray numbers of every non-agreeing class (first LIST_CAP each).
    pub ray_lists: BTreeMap<Class, Vec<usize>>,
    /// Real errors first, then the largest t differences.
    pub worst: Vec<Case>,
}

pub fn classify_all(judge: &Judge, rays: &[Ray], got: &[Hit], want: &[Hit]) -> Result<Vec<Class>> {
    if got.len() != rays.len() || want.len() != rays.len() {
        bail!(
            "{} rays, {} hits, {} reference rows: the counts must match",
            rays.len(),
            got.len(),
            want.len()
        );
    }
    Ok((0..rays.len())
        .into_par_iter()
        .map(|i| judge.classify(&rays[i], &got[i], &want[i]))
        .collect())
}

pub fn compare(
    tris: &[crate::geom::Tri],
    rays: &[Ray],
    got: &[Hit],
    want: &[Hit],
    tol: Tolerances,
) -> Result<(Accuracy, Vec<Class>)> {
    let shadow_disagreements = (0..rays.len().min(got.len()).min(want.len()))
        .filter(|&i| rays[i].shadow && got[i].hit != want[i].hit)
        .count();
    let judge_shadow = shadow_disagreements as f64 * tris.len() as f64 <= SHADOW_JUDGE_BUDGET;
    let judge = Judge {
        tris,
        tol,
        judge_shadow,
    };
    let classes = classify_all(&judge, rays, got, want)?;
    let mut counts = BTreeMap::new();
    let mut lists: BTreeMap<Class, Vec<usize>> = BTreeMap::new();
    let mut max_t_rel_agree: f64 = 0.0;
    for (i, &c) in classes.iter().enumerate() {
        *counts.entry(c).or_insert(0) += 1;
        if c == Class::Agree {
            if got[i].hit && !rays[i].shadow {
                max_t_rel_agree = max_t_rel_agree.max(rel(got[i].t, want[i].t));
            }
        } else {
            let l = lists.entry(c).or_default();
            if l.len() < LIST_CAP {
                l.push(i);
            }
        }
    }
    let mut order: Vec<usize> = (0..rays.len())
        .filter(|&i| classes[i] != Class::Agree)
        .collect();
    order.sort_by(|&a, &b| {
        (!classes[a].is_mismatch(), -rel(got[a].t, want[a].t))
            .partial_cmp(&(!classes[b].is_mismatch(), -rel(got[b].t, want[b].t)))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let worst = order
        .iter()
        .take(WORST_CAP)
        .map(|&i| Case {
            ray: i,
            class: classes[i],
            hits: (&got[i]).into(),
            reference: (&want[i]).into(),
        })
        .collect();
    let acc = Accuracy {
        format_version: crate::memory::VERSION,
        rays: rays.len(),
        shadow_rays: rays.iter().filter(|r| r.shadow).count(),
        shadow_judged: judge_shadow,
        tolerances: tol,
        mismatches: classes.iter().filter(|c| c.is_mismatch()).count(),
        error_flagged: got.iter().filter(|h| h.error != 0).count(),
        counts,
        max_t_rel_agree,
        ray_lists: lists,
        worst,
    };
    Ok((acc, classes))
}

/// |a - b| / max(|a|, |b|); 0 when either is infinite.
pub fn rel(a: f32, b: f32) -> f64 {
    let (a, b) = (a as f64, b as f64);
    if a.is_finite() && b.is_finite() {
        (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
    } else {
        0.0
    }
}

pub fn summary(acc: &Accuracy) -> String {
    let mut s = format!(
        "{} rays ({} shadow, compared on occlusion only): {} mismatches",
        acc.rays, acc.shadow_rays, acc.mismatches
    );
    if !acc.shadow_judged {
        s.push_str(" (shadow disagreements too many to judge in f64: all counted)");
    }
    for (c, n) in &acc.counts {
        s.push_str(&format!(
            ", {} {n}",
            serde_json::to_value(c).unwrap().as_str().unwrap_or("?")
        ));
    }
    s.push_str(&format!(
        "; max agreeing t rel diff {:.3e}",
        acc.max_t_rel_agree
    ));
    s
}
