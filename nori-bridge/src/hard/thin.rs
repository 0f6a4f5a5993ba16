//! Grazing rays and degenerate triangles. Hits and misses are by
//! construction with documented clearances; hard_cases::resolve checks each
//! one exactly on the snapped f32 values.

use crate::geom::V3;
use crate::hard::cases::{ray, Case, CaseRay, Intent, SEED};
use crate::hard::exact::{snap, Grid};
use crate::hard::mesh::{grid_box, quad, Mesh};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ANGLES: [f64; 6] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6];
const HALF: f64 = 1024.0;
/// Thin slab: z in [SLAB_Z, SLAB_Z + 2^-10] (1024 f32 ulps at 8).
const SLAB_Z: f64 = 8.0;
const SLAB_T: f64 = 1.0 / 1024.0;

fn dir(theta: f64, phi: f64, down: bool, g: &Grid) -> V3 {
    let s = if down { -theta.sin() } else { theta.sin() };
    [theta.cos() * phi.cos(), theta.cos() * phi.sin(), s].map(|c| snap(c, g.dir_exp))
}

/// Horizontal distance from (x, y) along phi to the edge of [-HALF, HALF]^2.
fn to_edge(x: f64, y: f64, phi: f64) -> f64 {
    let along = |p: f64, c: f64| {
        if c > 1e-12 {
            (HALF - p) / c
        } else if c < -1e-12 {
            (-HALF - p) / c
        } else {
            f64::INFINITY
        }
    };
    along(x, phi.cos()).min(along(y, phi.sin()))
}

fn grazing() -> Case {
    // Positions on 2^-24 (coordinates < 2048 stay below 2^35 units), the
    // directions on 2^-40 (sin 1e-6 keeps ~20 bits).
    let g = Grid {
        pos_exp: -24,
        dir_exp: -40,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(SEED ^ 5);
    let plane = quad(2, 0.0, [-HALF as f32; 2], [HALF as f32; 2]);
    let lo = [-HALF as f32, -HALF as f32, SLAB_Z as f32];
    let slab = grid_box(lo, [HALF as f32, HALF as f32, (SLAB_Z + SLAB_T) as f32], 1);
    let (mut hit_q, mut miss_q, mut inside, mut onto, mut over) =
        (vec![], vec![], vec![], vec![], vec![]);
    for &theta in &ANGLES {
        for k in 0..24 {
            let phi = (k as f64 + 0.37) * std::f64::consts::TAU / 24.0;
            let (tx, ty) = (rng.gen_range(-300.0..300.0), rng.gen_range(-300.0..300.0));
            let d = dir(theta, phi, true, &g);
            // Horizontal travel <= 3 / tan(theta) keeps every origin < 3.2
            // above its target level, so quad rays stay below the slab (z >= 8).
            let travel = (3.0 / theta.tan()).min(500.0);
            // Through the interior: meet z = level at (tx, ty) (> 200 inside).
            let start = |level: f64| {
                [
                    snap(tx - travel * phi.cos(), g.pos_exp),
                    snap(ty - travel * phi.sin(), g.pos_exp),
                    snap(level + travel * theta.tan(), g.pos_exp),
                ]
            };
            hit_q.push(CaseRay {
                ray: ray(start(0.0), d),
                intent: Intent::Hit,
            });
            onto.push(CaseRay {
                ray: ray(start(SLAB_Z + SLAB_T), d),
                intent: Intent::Hit,
            });
            // Just above: the ray would meet the plane 1 unit of horizontal
            // travel (~8000 f32 ulps at 1024) beyond the edge of the square.
            let edge = to_edge(tx, ty, phi);
            let (ex, ey) = (
                tx + (edge - travel) * phi.cos(),
                ty + (edge - travel) * phi.sin(),
            );
            let high = |level: f64| {
                [
                    snap(ex, g.pos_exp),
                    snap(ey, g.pos_exp),
                    snap(level + (travel + 1.0) * theta.tan(), g.pos_exp),
                ]
            };
            miss_q.push(CaseRay {
                ray: ray(high(0.0), d),
                intent: Intent::Miss,
            });
            over.push(CaseRay {
                ray: ray(high(SLAB_Z + SLAB_T), d),
                intent: Intent::Miss,
            });
            // From inside the closed slab, up or down: must hit.
            let mid = [
                snap(tx, g.pos_exp),
                snap(ty, g.pos_exp),
                snap(SLAB_Z + SLAB_T / 2.0, g.pos_exp),
            ];
            inside.push(CaseRay {
                ray: ray(mid, dir(theta, phi, k % 2 == 0, &g)),
                intent: Intent::Hit,
            });
        }
    }
    // Parallel to the plane at height 2^-10 with dz = +0 / -0: z never changes.
    let mut parallel = Vec::new();
    for k in 0..24 {
        let phi = k as f64 * std::f64::consts::TAU / 24.0;
        let mut d = dir(0.0, phi, false, &g);
        d[2] = if k % 2 == 0 { 0.0 } else { -0.0 };
        parallel.push(CaseRay {
            ray: ray([0.0, 0.0, 1.0 / 1024.0], d),
            intent: Intent::Miss,
        });
    }
    Case {
        name: "grazing",
        description: "rays at 1e-1..1e-6 rad to a 2048-wide quad (2 tris) and to a closed 2^-10-thick slab (12 tris): through the interior, from inside the slab, and just above".into(),
        derivation: "construction, exact check: interior hits land > 200 units inside; misses would meet the plane 1 unit (~8000 ulps) past the edge; parallel rays keep z = 2^-10".into(),
        grid: g,
        meshes: vec![("plane.obj".into(), plane), ("slab.obj".into(), slab)],
        groups: vec![
            ("quad z=0: descending through the interior".into(), hit_q),
            ("quad z=0: descending, passing above the far edge".into(), miss_q),
            ("slab: from inside, up or down".into(), inside),
            ("slab: descending onto the top face".into(), onto),
            ("slab: descending, passing above the far edge".into(), over),
            ("quad z=0: parallel at height 2^-10, dz = ±0".into(), parallel),
        ],
    }
}

/// Clearance threshold: 2^-18 is 16 f32 ulps of the coordinates (< 2) the
/// needle rays use (needles lie in [0,1]^2, oblique origins add (0.3,0.2)).
const CLEAR: f64 = 1.0 / 262_144.0;

fn degenerate() -> Case {
    let g = Grid {
        pos_exp: -30,
        dir_exp: -30,
    };
    let p = |x: f64, y: f64| [snap(x, g.pos_exp), snap(y, g.pos_exp), 0.0];
    let mut m = Mesh::default();
    let mut tri = |a: V3, b: V3, c: V3| {
        m.verts.extend([a, b, c]);
        let n = m.verts.len();
        m.faces.push([n - 3, n - 2, n - 1]);
    };
    tri(p(0.0, 0.0), p(0.0, 0.0), p(1.0, 0.0)); // prim 0: two equal vertices
    tri(p(2.0, 0.0), p(2.0, 0.0), p(2.0, 0.0)); // prim 1: three equal
    tri(p(0.0, 1.0), p(1.0, 1.0), p(0.5, 1.0)); // prim 2: collinear, distinct
    let widths = [1e-3, 1e-4, 1e-5, 1e-6]; // aspect ~1e3 .. 1e6
    for (i, w) in widths.iter().enumerate() {
        let y0 = 0.25 + 0.125 * i as f64;
        tri(p(0.0, y0 - w / 2.0), p(0.0, y0 + w / 2.0), p(1.0, y0)); // prims 3..6: needles
    }
    tri(p(3.0, 0.0), p(4.0, 0.0), p(3.0, 1.0)); // prims 7, 8: ordinary
    tri(p(4.0, 1.0), p(3.0, 1.0), p(4.0, 0.0));
    let down = |t: V3, zs: (f32, f32)| ray([t[0], t[1], 1.0], [zs.0, zs.1, -1.0]);
    let oblique = |t: V3| {
        let o = [
            t[0] + snap(0.3, g.pos_exp),
            t[1] + snap(0.2, g.pos_exp),
            1.0,
        ];
        ray(o, [0, 1, 2].map(|k| t[k] - o[k]))
    };
    // All four ±0 sign pairs for rays with a definite answer; `any` rays
    // get one vertical and one oblique ray (they only show what happens).
    let both = |t: V3, intent: Intent| {
        let signs: &[(f32, f32)] = if matches!(intent, Intent::Any(_)) {
            &[(0.0, 0.0)]
        } else {
            &[(0.0, 0.0), (-0.0, -0.0), (0.0, -0.0), (-0.0, 0.0)]
        };
        let mut v: Vec<CaseRay> = signs
            .iter()
            .map(|&zs| CaseRay {
                ray: down(t, zs),
                intent: intent.clone(),
            })
            .collect();
        v.push(CaseRay {
            ray: oblique(t),
            intent,
        });
        v
    };
    let seg = |y: f64, intent: Intent| {
        (0..=8)
            .flat_map(|k| both(p(k as f64 / 8.0, y), intent.clone()))
            .collect::<Vec<_>>()
    };
    let collinear = Intent::Any(
        "collinear distinct vertices: zero area, a hit is defensible only on the segment".into(),
    );
    let mut needles = Vec::new();
    for (i, w) in widths.iter().enumerate() {
        let y0 = 0.25 + 0.125 * i as f64;
        for x in [0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999, 0.9999, 1.0] {
            let half = w * (1.0 - x) / 2.0;
            for (dy, inside) in [
                (0.0, true),
                (0.5, true),
                (-0.5, true),
                (1.0 + 8.0 * CLEAR / half.max(1e-30), false),
                (-1.25, false),
            ] {
                let t = p(x, y0 + dy * half);
                let gap = if inside {
                    half * (1.0 - dy.abs())
                } else {
                    half * (dy.abs() - 1.0)
                };
                let intent = match (gap >= CLEAR, inside) {
                    (true, true) => Intent::Hit,
                    (true, false) => Intent::Miss,
                    _ => Intent::Any(format!(
                        "needle {w:e} at x={x}: distance to its edge {gap:.1e} < 2^-18"
                    )),
                };
                needles.extend(both(t, intent));
            }
        }
    }
    let ordinary = [p(3.25, 0.25), p(3.75, 0.75), p(3.5, 0.5)]
        .into_iter()
        .flat_map(|t| both(t, Intent::Hit))
        .collect();
    Case {
        name: "degenerate",
        description: "zero-area triangles (two / three equal vertices), collinear vertices, needles of aspect 1e3..1e6 and two ordinary triangles, all in z = 0".into(),
        derivation: "coincident vertices: miss (zero area; hardware rejects by rule); collinear: any; needles: hit/miss when >= 2^-18 (16 ulps) from the edge, else any; exact check".into(),
        grid: g,
        meshes: vec![("mesh.obj".into(), m)],
        groups: vec![
            ("prim 0 (two equal vertices): rays at 9 points of its segment".into(), seg(0.0, Intent::Miss)),
            ("prim 1 (three equal vertices)".into(), both(p(2.0, 0.0), Intent::Miss)),
            ("prim 2 (collinear): rays at 9 points of its segment".into(), seg(1.0, collinear)),
            ("prims 3..6 (needles): centre line, quarter widths, outside".into(), needles),
            ("prims 7, 8 (ordinary)".into(), ordinary),
        ],
    }
}

pub fn cases() -> Vec<Case> {
    vec![grazing(), degenerate()]
}
