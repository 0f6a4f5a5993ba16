//! Axis-aligned hard cases: ±0 direction components, and origins on the
//! planes that BVH node bounds share with the geometry (the slab test's
//! (plane - o) * (1/d) = 0 * inf = NaN case). Expectations: construction
//! where it is plain (origin strictly inside the closed box: hit; outside
//! the box's slab: miss), otherwise the exact hit set; a ray lying in the
//! plane of a rectangle it touches is `any` (closed and half-open edge
//! rules disagree there).

use crate::geom::V3;
use crate::hard::cases::{ray, Case, CaseRay, Intent};
use crate::hard::exact::{orient, Grid};
use crate::hard::mesh::{grid_box, quad, Mesh};

fn offset(meshes: &[(String, Mesh)]) -> usize {
    meshes.iter().map(|m| m.1.faces.len()).sum()
}

/// Directions along `axis` with sign `s` and every ±0 combination in the
/// other two components.
fn axis_dirs(axis: usize, s: f32) -> Vec<V3> {
    let mut out = Vec::new();
    for z1 in [0.0f32, -0.0] {
        for z2 in [0.0f32, -0.0] {
            let mut d = [0.0; 3];
            d[axis] = s;
            d[(axis + 1) % 3] = z1;
            d[(axis + 2) % 3] = z2;
            out.push(d);
        }
    }
    out
}

fn axis_aligned() -> Case {
    let g = Grid {
        pos_exp: -4,
        dir_exp: -4,
    };
    let bx = grid_box([-1.0; 3], [1.0; 3], 2);
    let perp = [-1.5f32, -1.0, -0.0, 0.0, 0.5, 1.0];
    let mut groups = Vec::new();
    for axis in 0..3 {
        for s in [1.0f32, -1.0] {
            for along in [0.25f32, -3.0, 3.0] {
                let mut rays = Vec::new();
                for d in axis_dirs(axis, s) {
                    for &p in &perp {
                        for &q in &perp {
                            let mut o = [0.0; 3];
                            o[axis] = along;
                            o[(axis + 1) % 3] = p;
                            o[(axis + 2) % 3] = q;
                            let strictly_inside = o.iter().all(|c| c.abs() < 1.0);
                            let outside_slab = p.abs() > 1.0 || q.abs() > 1.0;
                            let intent = if strictly_inside {
                                Intent::Hit
                            } else if outside_slab {
                                Intent::Miss
                            } else {
                                Intent::Derive
                            };
                            rays.push(CaseRay {
                                ray: ray(o, d),
                                intent,
                            });
                        }
                    }
                }
                groups.push((format!("axis {axis}, sign {s}, origin coordinate {along} along it; ±0 in the other components"), rays));
            }
        }
    }
    Case {
        name: "axis-aligned",
        description: "closed box [-1,1]^3, faces split 2x2 (48 tris); axis-parallel rays with +0/-0 other components from inside and outside at face interiors, inner edges and vertices, face planes and beyond".into(),
        derivation: "origin strictly inside: hit (closed box); perpendicular coordinate beyond ±1: miss; else exact hit set; ray in a face plane touching the face: any".into(),
        grid: g,
        meshes: vec![("mesh.obj".into(), bx)],
        groups,
    }
}

fn slab_planes() -> Case {
    let g = Grid {
        pos_exp: -4,
        dir_exp: -4,
    };
    let mut meshes: Vec<(String, Mesh)> = Vec::new();
    for (lo, hi) in [
        ([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        ([2.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
        ([0.0, 2.0, 0.0], [1.0, 3.0, 1.0]),
    ] {
        let name = format!("box{}.obj", meshes.len());
        meshes.push((name, grid_box(lo, hi, 1)));
    }
    meshes.push(("quad-z2.obj".into(), quad(2, 2.0, [0.0, 0.0], [3.0, 3.0])));
    meshes.push(("quad-x-1.obj".into(), quad(0, -1.0, [0.0, 0.0], [3.0, 2.0])));
    let tris: Vec<_> = meshes.iter().flat_map(|m| m.1.tris()).collect();
    debug_assert_eq!(offset(&meshes), tris.len());
    let mut dirs: Vec<V3> = Vec::new();
    for axis in 0..3 {
        for s in [1.0f32, -1.0] {
            let d = axis_dirs(axis, s);
            dirs.push(d[0]); // +0, +0
            dirs.push(d[3]); // -0, -0
        }
    }
    dirs.extend([
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, -0.0],
        [1.0, 0.0, -1.0],
        [0.0, -1.0, 1.0],
        [1.0, 2.0, 3.0],
        [-3.0, 1.0, -2.0],
        [2.0, -3.0, -1.0],
    ]);
    // An origin on a triangle would make t = 0 a hit by one rule and not by
    // another; those origins are left out (the planes still hold them).
    let on_geometry = |o: V3| {
        tris.iter().any(|t| {
            let b = t.bounds();
            orient(&g, t, o) == 0 && (0..3).all(|k| b.min[k] <= o[k] && o[k] <= b.max[k])
        })
    };
    let mut groups = Vec::new();
    for x in [-1.0f32, -0.0, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0] {
        let mut rays = Vec::new();
        for y in [-0.0f32, 0.5, 1.0, 1.5, 2.0, 3.0] {
            for z in [0.0f32, 0.5, 1.0, 1.5, 2.0, 2.5] {
                if on_geometry([x, y, z]) {
                    continue;
                }
                rays.extend(dirs.iter().map(|&d| CaseRay {
                    ray: ray([x, y, z], d),
                    intent: Intent::Derive,
                }));
            }
        }
        groups.push((format!("origins with x = {x}, y in {{-0,0.5,1,1.5,2,3}}, z in {{0,0.5,1,1.5,2,2.5}} (not on geometry), 19 directions each"), rays));
    }
    Case {
        name: "slab-planes",
        description: "three unit boxes and two quads whose planes are the BVH node bounds; origins on those planes (not on geometry), axis directions with ±0 and diagonal/oblique ones".into(),
        derivation: "exact hit set; a ray in the plane of a rectangle it touches: any".into(),
        grid: g,
        meshes,
        groups,
    }
}

pub fn cases() -> Vec<Case> {
    let mut v = vec![axis_aligned(), slab_planes()];
    v.extend(crate::hard::thin::cases());
    v
}
