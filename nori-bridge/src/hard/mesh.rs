//! Indexed meshes for the hard cases: icospheres and axis-aligned boxes and
//! quads, every vertex snapped to the case's grid (hard_exact::snap), faces
//! wound outward (right-handed normal points out).

use crate::geom::{Tri, V3};
use crate::hard::exact::snap;
use std::collections::HashMap;
use std::fmt::Write as _;

#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub verts: Vec<V3>,
    pub faces: Vec<[usize; 3]>,
}

impl Mesh {
    pub fn tris(&self) -> Vec<Tri> {
        self.faces
            .iter()
            .map(|f| Tri {
                v: f.map(|i| self.verts[i]),
            })
            .collect()
    }

    /// Each undirected edge once, as (low index, high index), in face order.
    pub fn edges(&self) -> Vec<(usize, usize)> {
        let mut seen = HashMap::new();
        let mut out = Vec::new();
        for f in &self.faces {
            for k in 0..3 {
                let e = (f[k].min(f[(k + 1) % 3]), f[k].max(f[(k + 1) % 3]));
                if seen.insert(e, ()).is_none() {
                    out.push(e);
                }
            }
        }
        out
    }

    /// Closed and consistently wound: every directed edge appears once and
    /// its reverse once.
    pub fn is_closed(&self) -> bool {
        let mut count: HashMap<(usize, usize), i32> = HashMap::new();
        for f in &self.faces {
            for k in 0..3 {
                *count.entry((f[k], f[(k + 1) % 3])).or_default() += 1;
            }
        }
        count
            .iter()
            .all(|(&(a, b), &n)| n == 1 && count.get(&(b, a)) == Some(&1))
    }

    /// Faces incident to vertex `v`, as local face numbers.
    pub fn star(&self, v: usize) -> Vec<usize> {
        (0..self.faces.len())
            .filter(|&i| self.faces[i].contains(&v))
            .collect()
    }

    /// Faces containing both ends of an edge.
    pub fn edge_faces(&self, a: usize, b: usize) -> Vec<usize> {
        (0..self.faces.len())
            .filter(|&i| self.faces[i].contains(&a) && self.faces[i].contains(&b))
            .collect()
    }

    pub fn to_obj(&self, header: &str) -> String {
        let mut s = format!("# {header}\n");
        for v in &self.verts {
            let _ = writeln!(s, "v {} {} {}", fmt_f32(v[0]), fmt_f32(v[1]), fmt_f32(v[2]));
        }
        for f in &self.faces {
            let _ = writeln!(s, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
        }
        s
    }
}

/// Shortest text that reads back to exactly this f32 (Rust's Display /
/// LowerExp are both round-trip exact); exponent form for small magnitudes.
pub fn fmt_f32(x: f32) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Icosphere: icosahedron subdivided `levels` times, vertices projected to
/// the sphere of `radius` about `centre` in f64, then snapped to 2^grid_exp.
pub fn icosphere(levels: u32, radius: f64, centre: [f64; 3], grid_exp: i32) -> Mesh {
    let p = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = vec![
        [-1.0, p, 0.0],
        [1.0, p, 0.0],
        [-1.0, -p, 0.0],
        [1.0, -p, 0.0],
        [0.0, -1.0, p],
        [0.0, 1.0, p],
        [0.0, -1.0, -p],
        [0.0, 1.0, -p],
        [p, 0.0, -1.0],
        [p, 0.0, 1.0],
        [-p, 0.0, -1.0],
        [-p, 0.0, 1.0],
    ];
    let mut f: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
        let mut next = Vec::with_capacity(f.len() * 4);
        for t in &f {
            let mut m = [0; 3];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                m[k] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    v.push([
                        (v[a][0] + v[b][0]) / 2.0,
                        (v[a][1] + v[b][1]) / 2.0,
                        (v[a][2] + v[b][2]) / 2.0,
                    ]);
                    v.len() - 1
                });
            }
            next.extend([
                [t[0], m[0], m[2]],
                [t[1], m[1], m[0]],
                [t[2], m[2], m[1]],
                [m[0], m[1], m[2]],
            ]);
        }
        f = next;
    }
    let verts = v
        .iter()
        .map(|q| {
            let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            [0, 1, 2].map(|k| snap(centre[k] + radius * q[k] / n, grid_exp))
        })
        .collect();
    Mesh { verts, faces: f }
}

/// Axis-aligned box [lo, hi], each face split into `n` x `n` squares of two
/// triangles; vertices shared by index, so the mesh is closed.
pub fn grid_box(lo: V3, hi: V3, n: usize) -> Mesh {
    let mut m = Mesh::default();
    let mut index: HashMap<[u32; 3], usize> = HashMap::new();
    let coord = |k: usize, i: usize| lo[k] + (hi[k] - lo[k]) * i as f32 / n as f32;
    for axis in 0..3 {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n] {
            let mut vid = |i: usize, j: usize| {
                let mut key = [0u32; 3];
                key[axis] = side as u32;
                key[u] = i as u32;
                key[w] = j as u32;
                *index.entry(key).or_insert_with(|| {
                    m.verts.push([0, 1, 2].map(|k| coord(k, key[k] as usize)));
                    m.verts.len() - 1
                })
            };
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1));
                    // (u, w, axis) is right-handed: a,b,c winds towards +axis.
                    let quad = if side == n {
                        [[a, b, c], [a, c, d]]
                    } else {
                        [[a, c, b], [a, d, c]]
                    };
                    m.faces.extend(quad);
                }
            }
        }
    }
    m
}

/// One axis-aligned quad (two triangles) normal to `axis` at `level`,
/// spanning [lo, hi] in the other two axes.
pub fn quad(axis: usize, level: f32, lo: [f32; 2], hi: [f32; 2]) -> Mesh {
    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
    let p = |a: f32, b: f32| {
        let mut v = [0.0; 3];
        v[axis] = level;
        v[u] = a;
        v[w] = b;
        v
    };
    Mesh {
        verts: vec![
            p(lo[0], lo[1]),
            p(hi[0], lo[1]),
            p(hi[0], hi[1]),
            p(lo[0], hi[1]),
        ],
        faces: vec![[0, 1, 2], [0, 2, 3]],
    }
}
