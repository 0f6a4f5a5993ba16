//! Closed-sphere hard cases: rays from inside an icosphere aimed at every
//! vertex and every edge midpoint. The sphere's f32 mesh is checked to be
//! closed and strictly convex in exact arithmetic, with every origin strictly
//! inside; then the ray leaves the solid through exactly one surface point,
//! so the triangles it hits all contain that point. The exact test confirms
//! those lie in the target's star (the faces around the vertex, or the two
//! faces of the edge), which becomes the allowed prim set.

use crate::geom::V3;
use crate::hard::cases::{ray, Case, CaseRay, Intent, SEED};
use crate::hard::exact::{orient, snap, Grid};
use crate::hard::mesh::{icosphere, Mesh};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Panics unless every vertex off a face and every origin lies strictly on
/// the inner side of that face's plane.
fn check_convex(g: &Grid, m: &Mesh, origins: &[V3]) {
    assert!(m.is_closed(), "sphere mesh is not closed");
    m.tris().par_iter().enumerate().for_each(|(fi, t)| {
        for (vi, v) in m.verts.iter().enumerate() {
            if !m.faces[fi].contains(&vi) {
                assert!(
                    orient(g, t, *v) < 0,
                    "face {fi} vertex {vi}: not strictly convex"
                );
            }
        }
        for o in origins {
            assert!(
                orient(g, t, *o) < 0,
                "origin {o:?} not strictly inside face {fi}"
            );
        }
    });
}

/// Origins: the centre and `extra` seeded points at 10..50% of the radius.
fn origins(centre: [f64; 3], radius: f64, extra: usize, g: &Grid, rng: &mut ChaCha8Rng) -> Vec<V3> {
    let mut out = vec![centre.map(|c| snap(c, g.pos_exp))];
    while out.len() < extra + 1 {
        let u: [f64; 3] = [
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        ];
        let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        if !(0.1..=1.0).contains(&n) {
            continue;
        }
        let s = radius * rng.gen_range(0.1..0.5) / n;
        out.push([0, 1, 2].map(|k| snap(centre[k] + s * u[k], g.pos_exp)));
    }
    out
}

/// Rays to every vertex, then every edge midpoint (snapped to the grid);
/// target k uses origin k mod origins; d = fl32(target - origin).
fn aimed(g: &Grid, m: &Mesh, first_prim: usize, os: &[V3]) -> Vec<(String, Vec<CaseRay>)> {
    let own = first_prim..first_prim + m.faces.len();
    let global = |v: Vec<usize>| v.into_iter().map(|i| i + first_prim).collect::<Vec<_>>();
    let mk = |k: usize, target: V3, allowed: Vec<usize>| {
        let o = os[k % os.len()];
        let d = [0, 1, 2].map(|c| (target[c] as f64 - o[c] as f64) as f32);
        CaseRay {
            ray: ray(o, d),
            intent: Intent::Star {
                allowed,
                own: own.clone(),
            },
        }
    };
    let verts = (0..m.verts.len())
        .map(|i| mk(i, m.verts[i], global(m.star(i))))
        .collect();
    let mids = m
        .edges()
        .into_iter()
        .enumerate()
        .map(|(k, (a, b))| {
            let mid = [0, 1, 2].map(|c| {
                snap(
                    (m.verts[a][c] as f64 + m.verts[b][c] as f64) / 2.0,
                    g.pos_exp,
                )
            });
            mk(k, mid, global(m.edge_faces(a, b)))
        })
        .collect();
    vec![
        (
            format!(
                "{} rays at the vertices of prims {} to {}",
                m.verts.len(),
                own.start,
                own.end - 1
            ),
            verts,
        ),
        (
            format!(
                "rays at the edge midpoints of prims {} to {}",
                own.start,
                own.end - 1
            ),
            mids,
        ),
    ]
}

struct Sphere {
    levels: u32,
    radius: f64,
    centre: [f64; 3],
    extra_origins: usize,
}

fn sphere_case(
    name: &'static str,
    description: String,
    g: Grid,
    spheres: &[Sphere],
    salt: u64,
) -> Case {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED ^ salt);
    let (mut meshes, mut groups, mut first) = (Vec::new(), Vec::new(), 0);
    for (i, s) in spheres.iter().enumerate() {
        let m = icosphere(s.levels, s.radius, s.centre, g.pos_exp);
        let os = origins(s.centre, s.radius, s.extra_origins, &g, &mut rng);
        check_convex(&g, &m, &os);
        groups.extend(aimed(&g, &m, first, &os));
        first += m.faces.len();
        meshes.push((
            if spheres.len() == 1 {
                "mesh.obj".to_string()
            } else {
                format!("mesh{i}.obj")
            },
            m,
        ));
    }
    // Disjoint bounding boxes: a point of another sphere is outside this
    // one, hence beyond the exit point of a ray leaving it (convexity).
    for i in 0..meshes.len() {
        for j in 0..i {
            let (a, b) = (bounds(&meshes[i].1), bounds(&meshes[j].1));
            assert!(
                (0..3).any(|k| a.1[k] < b.0[k] || b.1[k] < a.0[k]),
                "{name}: spheres {i} and {j} overlap"
            );
        }
    }
    let derivation =
        "closed + strictly convex f32 mesh and origins strictly inside, checked exactly; \
                      allowed prims = star of the target, exact hit set checked to lie in it"
            .to_string();
    Case {
        name,
        description,
        derivation,
        grid: g,
        meshes,
        groups,
    }
}

fn bounds(m: &Mesh) -> (V3, V3) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for v in &m.verts {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    (lo, hi)
}

pub fn cases() -> Vec<Case> {
    let one = |radius: f64, c: f64| Sphere {
        levels: 3,
        radius,
        centre: [c; 3],
        extra_origins: 3,
    };
    vec![
        sphere_case("sphere-closed", "unit icosphere (1280 tris) at the origin; rays from 4 inside points at every vertex and edge midpoint".into(),
                    Grid { pos_exp: -30, dir_exp: -30 }, &[one(1.0, 0.0)], 1),
        // f32 spacing in [8192, 16384) is 2^-10 ~ 1e-3: edges ~0.13 are ~130 ulps.
        sphere_case("sphere-offset-1e4", "radius-1 icosphere centred at (1e4,1e4,1e4), f32 spacing 2^-10 there; rays at vertices and edge midpoints".into(),
                    Grid { pos_exp: -10, dir_exp: -10 }, &[one(1.0, 1e4)], 2),
        // f32 spacing in [2^19, 2^20) is 2^-4 = 1/16: radius 100 gives edges ~13 = ~200 ulps.
        sphere_case("sphere-offset-1e6", "radius-100 icosphere centred at (1e6,1e6,1e6), f32 spacing 1/16 there; rays at vertices and edge midpoints".into(),
                    Grid { pos_exp: -4, dir_exp: -4 }, &[one(100.0, 1e6)], 3),
        // Edges ~1e-6: radius 7.5e-6 at 3 levels (edge ~0.13 r), and radius
        // 3.7e-6 at 2 levels (edge ~0.27 r) offset to 0.01 where the f32
        // spacing is 2^-30 ~ 9e-10 (edges ~1000 ulps). Grid 2^-40.
        sphere_case("tiny-edges", "icospheres with ~1e-6 edges: r=7.5e-6 at the origin (1280 tris) and r=3.7e-6 at (0.01,0.01,0.01) (320 tris)".into(),
                    Grid { pos_exp: -40, dir_exp: -40 },
                    &[one(7.5e-6, 0.0), Sphere { levels: 2, radius: 3.7e-6, centre: [0.01; 3], extra_origins: 2 }], 4),
    ]
}
