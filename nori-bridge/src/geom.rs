//! Small vector and box types. Triangles are kept in f32 (what the hardware
//! and Embree see); f64 helpers exist for the exact-as-possible evaluations.

pub type V3 = [f32; 3];
pub type D3 = [f64; 3];

/// One triangle as the scene gives it: three f32 vertices after the mesh's
/// toWorld transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tri {
    pub v: [V3; 3],
}

impl Tri {
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::empty();
        for p in &self.v {
            b.grow(*p);
        }
        b
    }

    pub fn vertices64(&self) -> [D3; 3] {
        [to64(self.v[0]), to64(self.v[1]), to64(self.v[2])]
    }

    /// Twice the area, in f64 (inputs are exact, one rounding per operation).
    pub fn double_area64(&self) -> f64 {
        let [a, b, c] = self.vertices64();
        len64(cross64(sub64(b, a), sub64(c, a)))
    }

    /// Geometric normal (v1-v0)x(v2-v0), f64, not normalised.
    pub fn normal64(&self) -> D3 {
        let [a, b, c] = self.vertices64();
        cross64(sub64(b, a), sub64(c, a))
    }
}

/// Axis-aligned box in f32. Min/max of f32 values is exact, so a box grown
/// from vertices contains them with no rounding and no padding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: V3,
    pub max: V3,
}

impl Aabb {
    pub fn empty() -> Aabb {
        Aabb {
            min: [f32::INFINITY; 3],
            max: [f32::NEG_INFINITY; 3],
        }
    }

    pub fn grow(&mut self, p: V3) {
        for k in 0..3 {
            self.min[k] = self.min[k].min(p[k]);
            self.max[k] = self.max[k].max(p[k]);
        }
    }

    pub fn union(&self, o: &Aabb) -> Aabb {
        let mut b = *self;
        b.grow(o.min);
        b.grow(o.max);
        b
    }

    pub fn contains(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= o.min[k] && o.max[k] <= self.max[k])
    }

    /// Surface area in f64 (used for SAH statistics only).
    pub fn area64(&self) -> f64 {
        let d: Vec<f64> = (0..3)
            .map(|k| (self.max[k] as f64 - self.min[k] as f64).max(0.0))
            .collect();
        2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0])
    }
}

pub fn to64(p: V3) -> D3 {
    [p[0] as f64, p[1] as f64, p[2] as f64]
}

pub fn sub64(a: D3, b: D3) -> D3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn add64(a: D3, b: D3) -> D3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub fn scale64(a: D3, s: f64) -> D3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub fn dot64(a: D3, b: D3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross64(a: D3, b: D3) -> D3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn len64(a: D3) -> f64 {
    dot64(a, a).sqrt()
}

pub fn normalize64(a: D3) -> D3 {
    scale64(a, 1.0 / len64(a))
}

pub fn to32(p: D3) -> V3 {
    [p[0] as f32, p[1] as f32, p[2] as f32]
}
