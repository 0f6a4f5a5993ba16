//! `nori-bridge hard-score`: a hits.csv (or a package's reference.csv)
//! against a hard case's expect.csv. Every ray falls in exactly one class:
//! flagged (error field non-zero: the producer refused the ray; never
//! counted as correct), else leak (expected hit, got miss), false hit
//! (expected miss, got hit), wrong prim (hit outside a non-empty allowed
//! set), else ok (`any` rays are ok unless flagged).

use crate::error::{at_line, in_file};
use crate::ray::Hit;
use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub enum Expected {
    Hit(Vec<i64>),
    Miss,
    Any,
}

pub const EXPECT_HEADER: &str = "ray,expect,prims";
const LIST_MAX: usize = 1000;

/// Read expect.csv; errors name the file, line and value.
pub fn read_expect(path: &Path) -> Result<Vec<Expected>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == EXPECT_HEADER => {}
        other => bail!(at_line(
            path,
            1,
            format!(
                "header is '{}', expected '{EXPECT_HEADER}'",
                other.map_or("", |l| l.1)
            )
        )),
    }
    let mut out = Vec::new();
    for (n, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let err = |msg: String| -> anyhow::Error { at_line(path, n + 1, msg).into() };
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != 3 {
            return Err(err(format!(
                "{} columns, expected 3 ({EXPECT_HEADER}): '{line}'",
                f.len()
            )));
        }
        if f[0].parse::<usize>().ok() != Some(out.len()) {
            return Err(err(format!(
                "ray number '{}', expected {}",
                f[0],
                out.len()
            )));
        }
        let prims = if f[2].is_empty() {
            Vec::new()
        } else {
            f[2].split(';')
                .map(|p| {
                    p.trim()
                        .parse::<i64>()
                        .ok()
                        .filter(|&x| x >= 0)
                        .ok_or_else(|| err(format!("prim '{p}' is not a prim number")))
                })
                .collect::<Result<Vec<_>>>()?
        };
        let e = match f[1] {
            "hit" => Expected::Hit(prims),
            "miss" | "any" if !prims.is_empty() => {
                return Err(err(format!(
                    "'{}' ray lists prims '{}'; only 'hit' may",
                    f[1], f[2]
                )))
            }
            "miss" => Expected::Miss,
            "any" => Expected::Any,
            other => return Err(err(format!("expect '{other}' must be hit, miss or any"))),
        };
        out.push(e);
    }
    if out.is_empty() {
        bail!(in_file(path, "no rows"));
    }
    Ok(out)
}

#[derive(Serialize, Debug, Default, PartialEq)]
pub struct Lists {
    pub leaks: Vec<usize>,
    pub false_hits: Vec<usize>,
    pub wrong_prims: Vec<usize>,
    pub flagged: Vec<usize>,
}

#[derive(Serialize, Debug, Default, PartialEq)]
pub struct Score {
    pub case: String,
    pub rays: usize,
    pub expect_hit: usize,
    pub expect_miss: usize,
    pub expect_any: usize,
    pub leaks: usize,
    pub false_hits: usize,
    pub wrong_prims: usize,
    pub flagged: usize,
    pub ok: usize,
    pub lists: Lists,
}

fn note(count: &mut usize, list: &mut Vec<usize>, ray: usize) {
    *count += 1;
    if list.len() < LIST_MAX {
        list.push(ray);
    }
}

/// Score hits against expectations (same length, checked by the caller).
pub fn score(case: &str, expect: &[Expected], hits: &[Hit]) -> Score {
    let mut s = Score {
        case: case.to_string(),
        rays: expect.len(),
        ..Score::default()
    };
    for (i, (e, h)) in expect.iter().zip(hits).enumerate() {
        match e {
            Expected::Hit(_) => s.expect_hit += 1,
            Expected::Miss => s.expect_miss += 1,
            Expected::Any => s.expect_any += 1,
        }
        let l = &mut s.lists;
        match e {
            _ if h.error != 0 => note(&mut s.flagged, &mut l.flagged, i),
            Expected::Hit(_) if !h.hit => note(&mut s.leaks, &mut l.leaks, i),
            Expected::Hit(p) if !p.is_empty() && !p.contains(&h.prim) => {
                note(&mut s.wrong_prims, &mut l.wrong_prims, i)
            }
            Expected::Miss if h.hit => note(&mut s.false_hits, &mut l.false_hits, i),
            _ => s.ok += 1,
        }
    }
    s
}

/// The command: checks that hits, expectations and the package agree in
/// ray count (and, when the expect file sits beside a rays.txt, that the
/// package was compiled from those very rays), then scores.
pub fn hard_score(package: &Path, hits: &Path, expect: &Path) -> Result<Score> {
    let pkg = crate::package::Package::load(package)?;
    let got = crate::ray::csv_io::read_hits(hits)?;
    let ex = read_expect(expect)?;
    if ex.len() != got.len() || ex.len() != pkg.rays.len() {
        bail!(
            "ray counts differ: {} has {} rows, {} has {} rows, package {} has {} rays",
            expect.display(),
            ex.len(),
            hits.display(),
            got.len(),
            package.display(),
            pkg.rays.len()
        );
    }
    let rays_txt = expect.with_file_name("rays.txt");
    if rays_txt.exists() {
        let want = crate::ray::txt::read_rays_txt(&rays_txt)?;
        if let Some(i) = (0..want.len()).find(|&i| want[i] != pkg.rays[i]) {
            bail!(
                "{}: ray {i} is {:?} but package {} has {:?}: compiled from other rays?",
                rays_txt.display(),
                want[i],
                package.display(),
                pkg.rays[i]
            );
        }
    }
    let tris = pkg.manifest.counts.triangles as i64;
    for (i, e) in ex.iter().enumerate() {
        if let Expected::Hit(p) = e {
            if let Some(bad) = p.iter().find(|&&x| x >= tris) {
                bail!(
                    "{}: ray {i} allows prim {bad}, the package has {tris} triangles",
                    expect.display()
                );
            }
        }
    }
    let case = expect
        .parent()
        .and_then(|d| d.file_name())
        .map_or("?".to_string(), |n| n.to_string_lossy().into_owned());
    Ok(score(&case, &ex, &got))
}

#[cfg(test)]
#[path = "score_tests.rs"]
mod tests;
