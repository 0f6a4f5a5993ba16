//! 4x4 affine transforms with Nori's constructors. Nori composes a
//! `<transform>` element by left-multiplying each child onto the running
//! matrix (`M = child * M`), so the first child listed is applied first.
//! We compute in f64 (Nori uses f32 Eigen); vertices are rounded to f32 once,
//! after the whole transform, which is within 0.5 ulp of the exact result.

use crate::geom::{cross64, dot64, normalize64, sub64, D3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mat4 {
    pub m: [[f64; 4]; 4],
}

impl Mat4 {
    pub fn identity() -> Mat4 {
        let mut m = [[0.0; 4]; 4];
        for (i, row) in m.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        Mat4 { m }
    }

    pub fn from_rows(v: &[f64; 16]) -> Mat4 {
        let mut m = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] = v[i * 4 + j];
            }
        }
        Mat4 { m }
    }

    pub fn translate(t: D3) -> Mat4 {
        let mut r = Mat4::identity();
        for k in 0..3 {
            r.m[k][3] = t[k];
        }
        r
    }

    pub fn scale(s: D3) -> Mat4 {
        let mut r = Mat4::identity();
        for k in 0..3 {
            r.m[k][k] = s[k];
        }
        r
    }

    /// Rotation by `deg` degrees about `axis` (normalised here; Eigen's
    /// AngleAxis assumes a unit axis and Nori does not normalise it, so a
    /// non-unit axis in Nori gives a non-rotation; we give the rotation).
    pub fn rotate(axis: D3, deg: f64) -> Mat4 {
        let a = normalize64(axis);
        let (s, c) = deg.to_radians().sin_cos();
        let t = 1.0 - c;
        let (x, y, z) = (a[0], a[1], a[2]);
        Mat4::from_rows(&[
            t * x * x + c,
            t * x * y - s * z,
            t * x * z + s * y,
            0.0,
            t * x * y + s * z,
            t * y * y + c,
            t * y * z - s * x,
            0.0,
            t * x * z - s * y,
            t * y * z + s * x,
            t * z * z + c,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
        ])
    }

    /// Nori's lookat: columns are left = up x dir, newUp = dir x left, dir,
    /// and the origin.
    pub fn lookat(origin: D3, target: D3, up: D3) -> Mat4 {
        let dir = normalize64(sub64(target, origin));
        let left = normalize64(cross64(normalize64(up), dir));
        let new_up = normalize64(cross64(dir, left));
        let mut r = Mat4::identity();
        for k in 0..3 {
            r.m[k][0] = left[k];
            r.m[k][1] = new_up[k];
            r.m[k][2] = dir[k];
            r.m[k][3] = origin[k];
        }
        r
    }

    pub fn mul(&self, o: &Mat4) -> Mat4 {
        let mut m = [[0.0; 4]; 4];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, cell) in row.iter_mut().enumerate() {
                *cell = (0..4).map(|k| self.m[i][k] * o.m[k][j]).sum();
            }
        }
        Mat4 { m }
    }

    /// Point transform with the homogeneous divide, as Nori's
    /// `Transform::operator*(Point3f)` does.
    pub fn point(&self, p: D3) -> D3 {
        let h = [p[0], p[1], p[2], 1.0];
        let r: Vec<f64> = (0..4).map(|i| dot4(self.m[i], h)).collect();
        [r[0] / r[3], r[1] / r[3], r[2] / r[3]]
    }

    /// Vector transform: the linear part only.
    pub fn vector(&self, v: D3) -> D3 {
        let row = |i: usize| [self.m[i][0], self.m[i][1], self.m[i][2]];
        [dot64(row(0), v), dot64(row(1), v), dot64(row(2), v)]
    }
}

fn dot4(a: [f64; 4], b: [f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

/// Parse Nori's number lists: tokens separated by commas and/or whitespace.
pub fn parse_floats(text: &str) -> Result<Vec<f64>, String> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| format!("'{t}' is not a number"))
        })
        .collect()
}

pub fn parse_vec3(text: &str) -> Result<D3, String> {
    let v = parse_floats(text)?;
    match v.len() {
        3 => Ok([v[0], v[1], v[2]]),
        n => Err(format!("expected 3 numbers, got {n} in '{text}'")),
    }
}

#[cfg(test)]
#[path = "transform_tests.rs"]
mod tests;
