//! Primary rays against Nori's own matrix formulation of the perspective
//! camera, and the CSV float round trip.

mod common;
use nori_bridge::csv_io::{read_hits, read_rays, write_hits, write_rays};
use nori_bridge::ray::{Hit, Ray};
use nori_bridge::ray_gen::camera_ray;
use nori_bridge::scene::Camera;
use nori_bridge::transform::Mat4;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn inverse(m: &Mat4) -> Mat4 {
    let mut a = m.m;
    let mut inv = Mat4::identity().m;
    for c in 0..4 {
        let p = (c..4)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        a.swap(c, p);
        inv.swap(c, p);
        let d = a[c][c];
        for k in 0..4 {
            a[c][k] /= d;
            inv[c][k] /= d;
        }
        for r in 0..4 {
            if r != c {
                let f = a[r][c];
                for k in 0..4 {
                    a[r][k] -= f * a[c][k];
                    inv[r][k] -= f * inv[c][k];
                }
            }
        }
    }
    Mat4 { m: inv }
}

/// Nori: cameraToSample = Scale(-0.5, -0.5 aspect, 1) times
/// Translate(-1, -1/aspect, 0) times perspective(fov, near, far);
/// nearP = sampleToCamera (sx/W, sy/H, 0); d = normalize(nearP);
/// o = toWorld(0); mint = near / d.z; maxt = far / d.z.
fn nori_ray(cam: &Camera, sx: f64, sy: f64) -> ([f64; 3], [f64; 3], f64, f64) {
    let aspect = cam.width as f64 / cam.height as f64;
    let cot = 1.0 / (cam.fov_deg.to_radians() / 2.0).tan();
    let (n, f) = (cam.near, cam.far);
    let recip = 1.0 / (f - n);
    let persp = Mat4::from_rows(&[
        cot,
        0.,
        0.,
        0.,
        0.,
        cot,
        0.,
        0.,
        0.,
        0.,
        f * recip,
        -n * f * recip,
        0.,
        0.,
        1.,
        0.,
    ]);
    let to_sample = Mat4::scale([-0.5, -0.5 * aspect, 1.0])
        .mul(&Mat4::translate([-1.0, -1.0 / aspect, 0.0]))
        .mul(&persp);
    let near_p = inverse(&to_sample).point([sx / cam.width as f64, sy / cam.height as f64, 0.0]);
    let len = (near_p[0] * near_p[0] + near_p[1] * near_p[1] + near_p[2] * near_p[2]).sqrt();
    let d = [near_p[0] / len, near_p[1] / len, near_p[2] / len];
    (
        cam.to_world.point([0.0; 3]),
        cam.to_world.vector(d),
        n / d[2],
        f / d[2],
    )
}

#[test]
fn primary_rays_match_nori_matrices() {
    let seed = 8;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for name in ["cornell-box", "multi-mesh", "icosphere"] {
        let mut cam = common::load(name).camera.unwrap();
        for (w, h) in [(cam.width, cam.height), (37, 91), (640, 360)] {
            (cam.width, cam.height) = (w, h);
            for _ in 0..200 {
                let (sx, sy) = (rng.gen_range(0.0..w as f64), rng.gen_range(0.0..h as f64));
                let r = camera_ray(&cam, sx, sy);
                let (o, d, mint, maxt) = nori_ray(&cam, sx, sy);
                let close = |a: f32, b: f64| (a as f64 - b).abs() <= 1e-6 * b.abs().max(1.0);
                for k in 0..3 {
                    assert!(
                        close(r.o[k], o[k]) && close(r.d[k], d[k]),
                        "{name} {w}x{h} seed {seed} ({sx},{sy}): {r:?} vs o {o:?} d {d:?}"
                    );
                }
                assert!(
                    close(r.tmin, mint) && close(r.tmax, maxt),
                    "{name} ({sx},{sy}): t range {} {} vs {mint} {maxt}",
                    r.tmin,
                    r.tmax
                );
            }
        }
    }
}

#[test]
fn csv_floats_round_trip_bit_exactly() {
    let seed = 9;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut f = || -> f32 {
        match rng.gen_range(0..6) {
            0 => f32::from_bits(rng.gen::<u32>() & 0x807f_ffff), // subnormals and zeros
            1 => f32::INFINITY,
            2 => -rng.gen::<f32>() * 1e30,
            _ => {
                let x = f32::from_bits(rng.gen());
                if x.is_nan() {
                    1.5
                } else {
                    x
                }
            }
        }
    };
    let rays: Vec<Ray> = (0..5000)
        .map(|i| Ray {
            o: [f(), f(), f()],
            d: [f(), f(), f()],
            tmin: f().abs(),
            tmax: f(),
            shadow: i % 3 == 0,
        })
        .collect();
    let hits: Vec<Hit> = (0..5000)
        .map(|i| {
            if i % 4 == 0 {
                Hit::MISS
            } else {
                Hit {
                    hit: true,
                    t: f(),
                    u: f(),
                    v: f(),
                    prim: i as i64 * 7,
                    error: (i % 3) as u32,
                }
            }
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let (rp, hp) = (dir.path().join("rays.csv"), dir.path().join("hits.csv"));
    write_rays(&rp, &rays).unwrap();
    write_hits(&hp, &hits).unwrap();
    let bits = |r: &Ray| {
        [r.o, r.d]
            .concat()
            .iter()
            .chain([r.tmin, r.tmax].iter())
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    for (a, b) in rays.iter().zip(read_rays(&rp).unwrap()) {
        assert_eq!(bits(a), bits(&b), "seed {seed}: {a:?} vs {b:?}");
        assert_eq!(a.shadow, b.shadow);
    }
    for (a, b) in hits.iter().zip(read_hits(&hp).unwrap()) {
        assert_eq!(
            (
                a.hit,
                a.t.to_bits(),
                a.u.to_bits(),
                a.v.to_bits(),
                a.prim,
                a.error
            ),
            (
                b.hit,
                b.t.to_bits(),
                b.u.to_bits(),
                b.v.to_bits(),
                b.prim,
                b.error
            ),
            "seed {seed}"
        );
    }
}
