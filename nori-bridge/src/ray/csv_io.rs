//! rays.csv and hits.csv (reference.csv has the hits format). Floats are f32
//! printed by Rust's Display: the shortest string that parses back to the
//! same f32, `inf`/`-inf` for infinities.

use crate::error::at_line;
use crate::ray::{Hit, Ray};
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::Path;

pub const RAYS_HEADER: &str = "ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow";
pub const HITS_HEADER: &str = "ray,hit,t,u,v,prim,error";

pub fn write_rays(path: &Path, rays: &[Ray]) -> Result<()> {
    let mut s = String::with_capacity(rays.len() * 80);
    s.push_str(RAYS_HEADER);
    s.push('\n');
    for (i, r) in rays.iter().enumerate() {
        let _ = writeln!(
            s,
            "{i},{},{},{},{},{},{},{},{},{}",
            r.o[0], r.o[1], r.o[2], r.d[0], r.d[1], r.d[2], r.tmin, r.tmax, r.shadow as u8
        );
    }
    std::fs::write(path, s).with_context(|| format!("{}: cannot write", path.display()))
}

pub fn write_hits(path: &Path, hits: &[Hit]) -> Result<()> {
    let mut s = String::with_capacity(hits.len() * 48);
    s.push_str(HITS_HEADER);
    s.push('\n');
    for (i, h) in hits.iter().enumerate() {
        if h.hit {
            let _ = writeln!(s, "{i},1,{},{},{},{},{}", h.t, h.u, h.v, h.prim, h.error);
        } else {
            let _ = writeln!(s, "{i},0,inf,0,0,-1,{}", h.error);
        }
    }
    std::fs::write(path, s).with_context(|| format!("{}: cannot write", path.display()))
}

/// Read the data rows of a CSV with the given header; checks that column
/// `ray` counts 0,1,2,... so a dropped or reordered line is caught.
fn read_rows(path: &Path, header: &str) -> Result<Vec<(usize, Vec<String>)>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == header => {}
        other => bail!(at_line(
            path,
            1,
            format!(
                "header is '{}', expected '{header}'",
                other.map_or("", |l| l.1)
            )
        )),
    }
    let cols = header.split(',').count();
    let mut rows = Vec::new();
    for (n, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<String> = line.split(',').map(|x| x.trim().to_string()).collect();
        if f.len() != cols {
            bail!(at_line(
                path,
                n + 1,
                format!("{} columns, expected {cols}: '{line}'", f.len())
            ));
        }
        if f[0].parse::<usize>().ok() != Some(rows.len()) {
            bail!(at_line(
                path,
                n + 1,
                format!("ray number '{}', expected {}", f[0], rows.len())
            ));
        }
        rows.push((n + 1, f));
    }
    Ok(rows)
}

fn num<T: std::str::FromStr>(path: &Path, line: usize, name: &str, v: &str) -> Result<T> {
    v.parse::<T>()
        .map_err(|_| at_line(path, line, format!("{name} '{v}' is not a valid number")).into())
}

pub fn read_rays(path: &Path) -> Result<Vec<Ray>> {
    read_rows(path, RAYS_HEADER)?
        .into_iter()
        .map(|(n, f)| {
            let g = |i: usize, name: &str| num::<f32>(path, n, name, &f[i]);
            Ok(Ray {
                o: [g(1, "ox")?, g(2, "oy")?, g(3, "oz")?],
                d: [g(4, "dx")?, g(5, "dy")?, g(6, "dz")?],
                tmin: g(7, "tmin")?,
                tmax: g(8, "tmax")?,
                shadow: flag(path, n, "shadow", &f[9])?,
            })
        })
        .collect()
}

pub fn read_hits(path: &Path) -> Result<Vec<Hit>> {
    read_rows(path, HITS_HEADER)?
        .into_iter()
        .map(|(n, f)| {
            let hit = flag(path, n, "hit", &f[1])?;
            let prim = num::<i64>(path, n, "prim", &f[5])?;
            Ok(Hit {
                hit,
                t: num(path, n, "t", &f[2])?,
                u: num(path, n, "u", &f[3])?,
                v: num(path, n, "v", &f[4])?,
                prim: if hit { prim } else { -1 },
                error: num(path, n, "error", &f[6])?,
            })
        })
        .collect()
}

fn flag(path: &Path, line: usize, name: &str, v: &str) -> Result<bool> {
    match v {
        "0" => Ok(false),
        "1" => Ok(true),
        _ => bail!(at_line(path, line, format!("{name} '{v}' must be 0 or 1"))),
    }
}
