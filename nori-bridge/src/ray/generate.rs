//! Ray sets: Nori perspective-camera rays, shadow and ambient-occlusion rays
//! from primary hits, uniform random rays. All randomness comes from one
//! ChaCha8 generator seeded with --seed, so a ray set is reproducible.

use crate::geom::{add64, cross64, dot64, normalize64, scale64, sub64, to32, to64, Aabb, Tri, D3};
use crate::ray::{Hit, Ray};
use crate::scene::Camera;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Nori's perspective camera, in f64 then rounded to f32 once. Sample
/// position (sx, sy) in pixels; Nori maps it to the near plane through
/// sampleToCamera, which reduces to the direction
/// ((1 - 2 sx/W) tan(fov/2), (1 - 2 sy/H) tan(fov/2) / aspect, 1),
/// normalised; mint = near / d.z, maxt = far / d.z (d in camera space).
pub fn camera_ray(cam: &Camera, sx: f64, sy: f64) -> Ray {
    let aspect = cam.width as f64 / cam.height as f64;
    let tan = (cam.fov_deg.to_radians() * 0.5).tan();
    let d_cam = normalize64([
        (1.0 - 2.0 * sx / cam.width as f64) * tan,
        (1.0 - 2.0 * sy / cam.height as f64) * tan / aspect,
        1.0,
    ]);
    let o = cam.to_world.point([0.0; 3]);
    let d = cam.to_world.vector(d_cam);
    Ray {
        o: to32(o),
        d: to32(d),
        tmin: (cam.near / d_cam[2]) as f32,
        tmax: (cam.far / d_cam[2]) as f32,
        shadow: false,
    }
}

/// Primary rays, ray number = (y * width + x) * spp + s. With spp = 1 the
/// sample is the pixel centre; otherwise uniform jitter inside the pixel.
pub fn primary(cam: &Camera, spp: u32, rng: &mut ChaCha8Rng) -> Vec<Ray> {
    let mut rays = Vec::with_capacity((cam.width * cam.height * spp) as usize);
    for y in 0..cam.height {
        for x in 0..cam.width {
            for _ in 0..spp {
                let (jx, jy) = if spp == 1 {
                    (0.5, 0.5)
                } else {
                    (rng.gen::<f64>(), rng.gen::<f64>())
                };
                rays.push(camera_ray(cam, x as f64 + jx, y as f64 + jy));
            }
        }
    }
    rays
}

/// The hit point in f64 and the face normal turned toward the ray origin.
pub fn hit_frame(tris: &[Tri], ray: &Ray, hit: &Hit) -> (D3, D3) {
    let p = ray.at64(hit.t as f64);
    let mut n = normalize64(tris[hit.prim as usize].normal64());
    if dot64(n, to64(ray.d)) > 0.0 {
        n = scale64(n, -1.0);
    }
    (p, n)
}

/// Shadow rays toward `light`, one per primary hit (in primary-ray order):
/// d = light - p unnormalised, so t in [1e-4, 1 - 1e-4] covers the segment
/// minus 0.01% at each end (self-hit at the origin and the light itself).
pub fn shadow(tris: &[Tri], prim_rays: &[Ray], hits: &[Hit], light: D3) -> Vec<Ray> {
    prim_rays
        .iter()
        .zip(hits)
        .filter(|(_, h)| h.hit)
        .map(|(r, h)| {
            let (p, _) = hit_frame(tris, r, h);
            Ray {
                o: to32(p),
                d: to32(sub64(light, p)),
                tmin: 1e-4,
                tmax: 1.0 - 1e-4,
                shadow: true,
            }
        })
        .collect()
}

/// Ambient-occlusion rays: `per_hit` cosine-distributed directions about the
/// face normal per primary hit. tmin = 1e-5 x the scene diagonal keeps the
/// ray off its own surface (f32 hit points are off by ~1e-7 relative).
pub fn ambient_occlusion(
    tris: &[Tri],
    prim_rays: &[Ray],
    hits: &[Hit],
    per_hit: u32,
    diag: f64,
    rng: &mut ChaCha8Rng,
) -> Vec<Ray> {
    let mut rays = Vec::new();
    for (r, h) in prim_rays.iter().zip(hits).filter(|(_, h)| h.hit) {
        let (p, n) = hit_frame(tris, r, h);
        for _ in 0..per_hit {
            let d = cosine_dir(n, rng);
            rays.push(Ray {
                o: to32(p),
                d: to32(d),
                tmin: (1e-5 * diag) as f32,
                tmax: f32::INFINITY,
                shadow: false,
            });
        }
    }
    rays
}

/// A cosine-distributed direction about the unit normal n (two uniforms from rng).
pub fn cosine_dir(n: D3, rng: &mut ChaCha8Rng) -> D3 {
    let (t, b) = basis(n);
    let (u1, u2): (f64, f64) = (rng.gen(), rng.gen());
    let (rad, phi) = (u1.sqrt(), 2.0 * std::f64::consts::PI * u2);
    let z = (1.0 - u1).max(0.0).sqrt();
    add64(
        add64(scale64(t, rad * phi.cos()), scale64(b, rad * phi.sin())),
        scale64(n, z),
    )
}

fn basis(n: D3) -> (D3, D3) {
    let a = if n[0].abs() > 0.9 {
        [0.0, 1.0, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let t = normalize64(cross64(n, a));
    (t, cross64(n, t))
}

/// Uniform random rays: origins uniform in the scene box grown by half its
/// size on each side; half the rays (even numbers) aim at a uniform point of
/// a uniformly chosen triangle, so many hit and some graze edges; the others
/// take a uniform direction on the sphere.
pub fn random(tris: &[Tri], bounds: &Aabb, count: usize, rng: &mut ChaCha8Rng) -> Vec<Ray> {
    let lo = to64(bounds.min);
    let size = sub64(to64(bounds.max), lo);
    (0..count)
        .map(|i| {
            let o: D3 =
                std::array::from_fn(|k| lo[k] - 0.5 * size[k] + 2.0 * size[k] * rng.gen::<f64>());
            let d = if i % 2 == 0 {
                let t = &tris[rng.gen_range(0..tris.len())];
                let (mut a, mut b): (f64, f64) = (rng.gen(), rng.gen());
                if a + b > 1.0 {
                    (a, b) = (1.0 - a, 1.0 - b);
                }
                let [p0, p1, p2] = t.vertices64();
                let target = add64(
                    p0,
                    add64(scale64(sub64(p1, p0), a), scale64(sub64(p2, p0), b)),
                );
                sub64(target, o)
            } else {
                let z: f64 = 2.0 * rng.gen::<f64>() - 1.0;
                let phi = 2.0 * std::f64::consts::PI * rng.gen::<f64>();
                let r = (1.0 - z * z).max(0.0).sqrt();
                [r * phi.cos(), r * phi.sin(), z]
            };
            let d = if d == [0.0; 3] {
                [0.0, 0.0, 1.0]
            } else {
                normalize64(d)
            };
            Ray {
                o: to32(o),
                d: to32(d),
                tmin: 0.0,
                tmax: f32::INFINITY,
                shadow: false,
            }
        })
        .collect()
}
