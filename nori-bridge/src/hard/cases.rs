//! `nori-bridge hard-cases`: the hard-case suite. Each
//! case is built in code (spheres.rs, planes.rs) as meshes plus
//! rays, each ray carrying an intent; `resolve` turns intents into
//! expectations with the exact predicates of exact.rs and panics if a
//! construction and the exact arithmetic disagree (a generator bug, never a
//! silent wrong expectation). Output is deterministic: same seed, same bytes.

use crate::geom::Tri;
use crate::hard::exact::{coplanar, hit_t_units, hit_units, meets_box, Grid, I3};
use crate::hard::mesh::{fmt_f32, Mesh};
use crate::ray::Ray;
use anyhow::{Context, Result};
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::path::Path;

/// Seed of every random choice in the suite (origins inside the spheres).
pub const SEED: u64 = 20_261_122;

/// What the case builder claims about a ray, before the exact check.
#[derive(Clone, Debug)]
pub enum Intent {
    /// Origin strictly inside a convex closed mesh (global prims `own`):
    /// the first hit is a triangle of `allowed` (global prim numbers).
    Star {
        allowed: Vec<usize>,
        own: std::ops::Range<usize>,
    },
    /// Must hit / must miss by construction; the exact test confirms.
    Hit,
    Miss,
    /// Decide from the exact test alone (coplanar contact -> any).
    Derive,
    /// Both answers defensible; the reason goes into rays.txt.
    Any(String),
}

#[derive(Clone, Debug)]
pub struct CaseRay {
    pub ray: Ray,
    pub intent: Intent,
}

pub struct Case {
    pub name: &'static str,
    pub description: String,
    pub derivation: String,
    pub grid: Grid,
    /// (OBJ file name, mesh); prim numbers follow this order.
    pub meshes: Vec<(String, Mesh)>,
    /// Ray groups: a comment line for rays.txt, then the rays.
    pub groups: Vec<(String, Vec<CaseRay>)>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Expect {
    Hit(Vec<usize>),
    Miss,
    Any(String),
}

pub fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
    Ray {
        o,
        d,
        tmin: 0.0,
        tmax: f32::INFINITY,
        shadow: false,
    }
}

impl Case {
    pub fn tris(&self) -> Vec<Tri> {
        self.meshes.iter().flat_map(|(_, m)| m.tris()).collect()
    }
    pub fn ray_count(&self) -> usize {
        self.groups.iter().map(|g| g.1.len()).sum()
    }
}

/// Edges (by vertex positions) that belong to exactly one triangle of the
/// scene: the border of an open surface.
fn border_edges(tris: &[Tri]) -> HashSet<[[u32; 3]; 2]> {
    let mut count: HashMap<[[u32; 3]; 2], usize> = HashMap::new();
    for t in tris {
        for k in 0..3 {
            *count.entry(edge_key(t, k)).or_default() += 1;
        }
    }
    count
        .into_iter()
        .filter(|e| e.1 == 1)
        .map(|e| e.0)
        .collect()
}

/// The edge opposite vertex k, as sorted f32 bit patterns.
fn edge_key(t: &Tri, k: usize) -> [[u32; 3]; 2] {
    let (a, b) = (
        t.v[(k + 1) % 3].map(f32::to_bits),
        t.v[(k + 2) % 3].map(f32::to_bits),
    );
    [a.min(b), a.max(b)]
}

/// Exact hits sorted by t; the first-hit set is every prim whose t equals
/// the smallest (f64 t within 1e-9 relative: exact ties differ only by the
/// final rounding); the next distinct t must be 1e-6 relative further,
/// otherwise the case is too close to call and the generator panics.
/// The flag is true when a first hit lies exactly on a border edge.
fn first_hits(
    case: &Case,
    units: &[[I3; 3]],
    tris: &[Tri],
    border: &HashSet<[[u32; 3]; 2]>,
    r: &Ray,
) -> (Vec<usize>, bool) {
    let (o, d) = (case.grid.pos(r.o), case.grid.dir(r.d));
    let mut h: Vec<(f64, usize, [bool; 3])> = units
        .iter()
        .enumerate()
        .filter_map(|(i, v)| hit_units(&case.grid, v, o, d).map(|(t, e)| (t, i, e)))
        .collect();
    h.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let Some(&(t0, _, _)) = h.first() else {
        return (Vec::new(), false);
    };
    let first: Vec<_> = h.iter().filter(|x| x.0 <= t0 + t0 * 1e-9).collect();
    if let Some(next) = h.iter().find(|x| x.0 > t0 + t0 * 1e-9) {
        assert!(
            next.0 > t0 * (1.0 + 1e-6),
            "{}: ray {r:?}: hits at t {t0} and {} are too close to order",
            case.name,
            next.0
        );
    }
    let on_border = first
        .iter()
        .any(|x| (0..3).any(|k| x.2[k] && border.contains(&edge_key(&tris[x.1], k))));
    (first.iter().map(|x| x.1).collect(), on_border)
}

/// A ray lying in the plane of a triangle it touches (its closed bounding
/// box, which for our axis-aligned rectangles split in two is the
/// rectangle): the closed-triangle rule and a half-open rule differ.
fn coplanar_contact(case: &Case, tris: &[Tri], r: &Ray) -> Option<usize> {
    tris.iter().position(|t| {
        let b = t.bounds();
        coplanar(&case.grid, t, r) && meets_box(&case.grid, r, b.min, b.max)
    })
}

pub fn resolve(case: &Case) -> Vec<Expect> {
    let tris = case.tris();
    let units: Vec<[I3; 3]> = tris.iter().map(|t| t.v.map(|p| case.grid.pos(p))).collect();
    let border = border_edges(&tris);
    let all: Vec<&CaseRay> = case.groups.iter().flat_map(|g| &g.1).collect();
    all.par_iter()
        .map(|cr| {
            let r = &cr.ray;
            match &cr.intent {
                Intent::Star { allowed, own } => {
                    let (o, d) = (case.grid.pos(r.o), case.grid.dir(r.d));
                    let mine: Vec<usize> = own.clone().filter(|&i| hit_t_units(&case.grid, &units[i], o, d).is_some()).collect();
                    assert!(!mine.is_empty() && mine.iter().all(|i| allowed.contains(i)),
                            "{}: ray {r:?}: exact hits {mine:?} not inside the allowed star {allowed:?}", case.name);
                    Expect::Hit(allowed.clone())
                }
                Intent::Any(why) => Expect::Any(why.clone()),
                intent => {
                    if let Some(p) = coplanar_contact(case, &tris, r) {
                        assert!(matches!(intent, Intent::Derive), "{}: ray {r:?} lies in the plane of prim {p}", case.name);
                        Expect::Any(format!("lies in the plane of prim {p} and touches it"))
                    } else if let Some((first, on_border)) = Some(first_hits(case, &units, &tris, &border, r)).filter(|f| !f.0.is_empty()) {
                        assert!(!matches!(intent, Intent::Miss), "{}: ray {r:?} meant to miss hits {first:?}", case.name);
                        if on_border {
                            assert!(matches!(intent, Intent::Derive), "{}: ray {r:?} meets a border edge", case.name);
                            Expect::Any(format!("meets the border edge of an open surface exactly (prims {first:?})"))
                        } else {
                            Expect::Hit(first)
                        }
                    } else {
                        assert!(!matches!(intent, Intent::Hit), "{}: ray {r:?} meant to hit misses exactly", case.name);
                        Expect::Miss
                    }
                }
            }
        })
        .collect()
}

pub fn all_cases() -> Vec<Case> {
    let mut v = crate::hard::spheres::cases();
    v.extend(crate::hard::planes::cases());
    v
}

fn counts(ex: &[Expect]) -> [usize; 3] {
    let n = |f: fn(&Expect) -> bool| ex.iter().filter(|e| f(e)).count();
    [
        n(|e| matches!(e, Expect::Hit(_))),
        n(|e| matches!(e, Expect::Miss)),
        n(|e| matches!(e, Expect::Any(_))),
    ]
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("{}: cannot write", path.display()))
}

/// Write every case under `out` (created if needed) plus README.md and
/// cases.json. Returns the number of cases.
pub fn generate(out: &Path) -> Result<usize> {
    let cases = all_cases();
    let mut readme = format!(
        "# Hard-case scenes (generated)\n\nWritten by `nori-bridge hard-cases --out scenes/hard` (make hard-cases); \
         do not edit by hand. Seed {SEED}. Each case has `<case>.xml`, its OBJ files, `rays.txt` and `expect.csv` \
         (`ray,expect,prims`: hit / miss / any; prims = allowed first-hit prims, empty = any prim).\n\
         Expectations come from the construction and are checked with exact integer arithmetic on the f32 inputs \
         (nori-bridge/src/hard/exact.rs); the generator panics if the two disagree.\n\n\
         Run a case: `nori-bridge compile scenes/hard/C/C.xml --rays scenes/hard/C/rays.txt --reference double --out PKG` \
         (or `--reference embree [--robust]`), then `nori-bridge hard-score --package PKG --hits HITS.csv \
         --expect scenes/hard/C/expect.csv --out score.json` (HITS.csv may be PKG/reference.csv).\n\n\
         | case | triangles | rays | hit | miss | any | tests | derivation |\n|---|---|---|---|---|---|---|---|\n");
    let mut json = Vec::new();
    for case in &cases {
        let dir = out.join(case.name);
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("{}: cannot create", dir.display()))?;
        let ex = resolve(case);
        let ntris = case.tris().len();
        let mut xml = format!(
            "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- hard case {}: {} -->\n<scene>\n",
            case.name, case.description
        );
        for (file, mesh) in &case.meshes {
            write(
                &dir.join(file),
                &mesh.to_obj(&format!(
                    "hard case {}, {} triangles",
                    case.name,
                    mesh.faces.len()
                )),
            )?;
            let _ = writeln!(xml, "\t<mesh type=\"obj\">\n\t\t<string name=\"filename\" value=\"{file}\"/>\n\t</mesh>");
        }
        xml.push_str("</scene>\n");
        write(&dir.join(format!("{}.xml", case.name)), &xml)?;
        let mut rays = format!(
            "# hard case {}: ox oy oz dx dy dz (tmin 0, tmax inf)\n",
            case.name
        );
        let mut csv = String::from("ray,expect,prims\n");
        let mut i = 0;
        for (comment, group) in &case.groups {
            let _ = writeln!(rays, "# {comment}");
            for cr in group {
                let (o, d) = (cr.ray.o.map(fmt_f32), cr.ray.d.map(fmt_f32));
                let _ = write!(
                    rays,
                    "{} {} {} {} {} {}",
                    o[0], o[1], o[2], d[0], d[1], d[2]
                );
                let (word, prims) = match &ex[i] {
                    Expect::Hit(p) => (
                        "hit",
                        p.iter()
                            .map(|x| x.to_string())
                            .collect::<Vec<_>>()
                            .join(";"),
                    ),
                    Expect::Miss => ("miss", String::new()),
                    Expect::Any(why) => {
                        let _ = write!(rays, " # any: {why}");
                        ("any", String::new())
                    }
                };
                rays.push('\n');
                let _ = writeln!(csv, "{i},{word},{prims}");
                i += 1;
            }
        }
        write(&dir.join("rays.txt"), &rays)?;
        write(&dir.join("expect.csv"), &csv)?;
        let [h, m, a] = counts(&ex);
        let _ = writeln!(
            readme,
            "| {} | {ntris} | {i} | {h} | {m} | {a} | {} | {} |",
            case.name, case.description, case.derivation
        );
        json.push(serde_json::json!({"name": case.name, "description": case.description, "triangles": ntris,
                                     "rays": i, "expect_hit": h, "expect_miss": m, "expect_any": a}));
    }
    write(&out.join("README.md"), &readme)?;
    let doc =
        serde_json::json!({"seed": SEED, "generator": "nori-bridge hard-cases", "cases": json});
    write(
        &out.join("cases.json"),
        &(serde_json::to_string_pretty(&doc)? + "\n"),
    )?;
    Ok(cases.len())
}

#[cfg(test)]
#[path = "cases_tests.rs"]
mod tests;
