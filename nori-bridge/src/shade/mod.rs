//! Shaded images from hits (`make render`): normals / eye light, ambient
//! occlusion and direct light from the scene's area emitters, each computed
//! from the answers of a hit source (the golden walk, the RTL, or Embree's
//! reference). Shading is a pure function of the hits: the same hits give
//! the same pixels bit for bit, whoever produced them.
//!
//! Two stages: the camera rays' hits, then (ao, direct) the secondary rays
//! generated from them (`secondary`), whose answers say which contributions
//! count. The secondary rays are regenerated from the same primary hits and
//! seed at shading time, so nothing but the ray file travels between stages.

pub mod montage;
pub mod run;

use crate::geom::{add64, dot64, normalize64, scale64, sub64, to32, to64, Tri, D3};
use crate::package::Package;
use crate::ray::generate::{cosine_dir, hit_frame};
use crate::ray::{Hit, Ray};
use crate::scene::Scene;
use anyhow::{bail, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::io::Write;
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Integrator {
    /// Eye light: the face normal as a colour, times the cosine to the eye.
    Normals,
    /// Ambient occlusion: the unoccluded share of cosine-distributed rays.
    Ao,
    /// Direct light from the area emitters (point light if there is none), with shadow rays.
    Direct,
}

/// Ambient-occlusion radius as a share of the scene's diagonal.
const AO_RADIUS: f64 = 0.15;

/// Diffuse albedo of every surface (Nori's diffuse default is 0.5).
const ALBEDO: f64 = 0.5;

/// One secondary ray: the pixel it belongs to and the radiance it adds to
/// that pixel when nothing blocks it.
pub struct Secondary {
    pub pixel: usize,
    pub ray: Ray,
    pub weight: D3,
}

/// The lights of a scene: area emitter triangles with their radiance and a
/// cumulative area table for sampling, or else its point light.
struct Lights {
    tris: Vec<(Tri, D3, f64)>,
    total_area: f64,
    point: Option<D3>,
}

fn lights(scene: &Scene) -> Lights {
    let mut tris = Vec::new();
    let mut total_area = 0.0;
    for m in &scene.meshes {
        if let Some(le) = m.emitter {
            for t in &scene.tris[m.first_prim..m.first_prim + m.tri_count] {
                total_area += 0.5 * t.double_area64();
                tris.push((*t, le, total_area));
            }
        }
    }
    Lights {
        tris,
        total_area,
        point: scene.point_light,
    }
}

/// Radiance a primary ray sees directly: the emitter's, if it hit one.
fn emitted(scene: &Scene, hit: &Hit) -> D3 {
    if !hit.hit {
        return [0.0; 3];
    }
    scene
        .meshes
        .iter()
        .find(|m| {
            (hit.prim as usize) >= m.first_prim && (hit.prim as usize) < m.first_prim + m.tri_count
        })
        .and_then(|m| m.emitter)
        .unwrap_or([0.0; 3])
}

/// Shading options shared by both stages (they must agree for the rays to match).
#[derive(Clone, Copy, Debug)]
pub struct ShadeOpts {
    pub integrator: Integrator,
    /// AO rays, or light samples, per primary hit.
    pub samples: u32,
    pub seed: u64,
}

/// The camera image's size and samples per pixel, from the primary package.
fn camera(pkg: &Package) -> Result<(u32, u32, usize)> {
    let m = &pkg.manifest;
    match (m.width, m.height) {
        (Some(w), Some(h)) if m.ray_kind == "primary" => Ok((w, h, m.spp.max(1) as usize)),
        _ => bail!(
            "{}: ray kind '{}' has no camera image; shading needs a --rays primary package",
            pkg.dir.display(),
            m.ray_kind
        ),
    }
}

/// The secondary rays of `primary_hits` (ray order: primary ray order, then
/// sample), deterministic in `o.seed`. Normals has none.
pub fn secondary(
    scene: &Scene,
    pkg: &Package,
    primary_hits: &[Hit],
    o: &ShadeOpts,
) -> Result<Vec<Secondary>> {
    let (_, _, spp) = camera(pkg)?;
    let tris = pkg.image.by_prim();
    let lights = lights(scene);
    let diag = {
        let b = scene.bounds();
        let d = sub64(to64(b.max), to64(b.min));
        dot64(d, d).sqrt()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed);
    let mut out = Vec::new();
    let n = o.samples.max(1);
    for (i, (r, h)) in pkg.rays.iter().zip(primary_hits).enumerate() {
        if !h.hit || h.prim < 0 || h.prim as usize >= tris.len() {
            continue;
        }
        let pixel = i / spp;
        let (p, nrm) = hit_frame(&tris, r, h);
        match o.integrator {
            Integrator::Normals => {}
            Integrator::Ao => {
                for _ in 0..n {
                    let d = cosine_dir(nrm, &mut rng);
                    // tmin = 1e-5 x the scene diagonal keeps the ray off its own surface (as
                    // nori-bridge's AO rays); d is a unit vector, so tmax = AO_RADIUS x the diagonal
                    // is the occlusion radius (an unbounded radius turns a closed room black).
                    let ray = Ray {
                        o: to32(p),
                        d: to32(d),
                        tmin: (1e-5 * diag) as f32,
                        tmax: (AO_RADIUS * diag) as f32,
                        shadow: true,
                    };
                    let w = 1.0 / (n as f64 * spp as f64);
                    out.push(Secondary {
                        pixel,
                        ray,
                        weight: [w; 3],
                    });
                }
            }
            Integrator::Direct => {
                if !lights.tris.is_empty() {
                    for _ in 0..n {
                        // A triangle by area, then a uniform point on it.
                        let pick: f64 = rng.gen::<f64>() * lights.total_area;
                        let k = lights
                            .tris
                            .partition_point(|x| x.2 < pick)
                            .min(lights.tris.len() - 1);
                        let (lt, le, _) = &lights.tris[k];
                        let (u1, u2): (f64, f64) = (rng.gen(), rng.gen());
                        let su = u1.sqrt();
                        let [a, b, c] = lt.vertices64();
                        let y = add64(
                            add64(scale64(a, 1.0 - su), scale64(b, su * (1.0 - u2))),
                            scale64(c, su * u2),
                        );
                        out.extend(light_sample(
                            p,
                            nrm,
                            y,
                            normalize64(lt.normal64()),
                            *le,
                            lights.total_area / (n as f64 * spp as f64),
                            pixel,
                        ));
                    }
                } else if let Some(lp) = lights.point {
                    // No area emitter: the point light, with an intensity that gives
                    // irradiance 1 at half the scene diagonal (the scene gives no power we read).
                    let i = (0.5 * diag) * (0.5 * diag);
                    let d = sub64(lp, p);
                    let r2 = dot64(d, d);
                    let cos = dot64(nrm, d) / r2.sqrt();
                    if cos > 0.0 {
                        let w = ALBEDO / std::f64::consts::PI * i * cos / r2 / spp as f64;
                        out.push(Secondary {
                            pixel,
                            ray: shadow_ray(p, d),
                            weight: [w; 3],
                        });
                    }
                }
            }
        }
    }
    Ok(out)
}

/// Shadow ray from p to p + d: t in [1e-4, 1 - 1e-4] (as nori-bridge's shadow rays).
fn shadow_ray(p: D3, d: D3) -> Ray {
    Ray {
        o: to32(p),
        d: to32(d),
        tmin: 1e-4,
        tmax: 1.0 - 1e-4,
        shadow: true,
    }
}

/// One area-light sample at y (light normal nl, radiance le) seen from p
/// (normal n): the estimator albedo/pi Le cos_x cos_y / r^2 x area_over_n.
/// The light emits on both sides. None when the light is behind the surface.
fn light_sample(
    p: D3,
    n: D3,
    y: D3,
    nl: D3,
    le: D3,
    area_over_n: f64,
    pixel: usize,
) -> Option<Secondary> {
    let d = sub64(y, p);
    let r2 = dot64(d, d);
    let r = r2.sqrt();
    let cos_x = dot64(n, d) / r;
    let cos_y = dot64(nl, d).abs() / r;
    if cos_x <= 0.0 || r2 == 0.0 {
        return None;
    }
    let g = ALBEDO / std::f64::consts::PI * cos_x * cos_y / r2 * area_over_n;
    Some(Secondary {
        pixel,
        ray: shadow_ray(p, d),
        weight: scale64(le, g),
    })
}

/// Linear radiance per pixel from the primary hits and (ao, direct) the
/// secondary rays with their answers (`blocked[i]`: secondary ray i hit something).
pub fn radiance(
    scene: &Scene,
    pkg: &Package,
    primary_hits: &[Hit],
    sec: &[Secondary],
    blocked: &[bool],
    o: &ShadeOpts,
) -> Result<Vec<D3>> {
    let (w, h, spp) = camera(pkg)?;
    if primary_hits.len() != pkg.rays.len() {
        bail!(
            "{}: {} primary hits for {} rays",
            pkg.dir.display(),
            primary_hits.len(),
            pkg.rays.len()
        );
    }
    if blocked.len() != sec.len() {
        bail!("{} secondary answers for {} secondary rays (were they made with the same --integrator, --samples and --seed?)", blocked.len(), sec.len());
    }
    let tris = pkg.image.by_prim();
    let mut img = vec![[0.0f64; 3]; (w * h) as usize];
    for (i, (r, hit)) in pkg.rays.iter().zip(primary_hits).enumerate() {
        if !hit.hit || hit.prim < 0 || hit.prim as usize >= tris.len() {
            continue;
        }
        let px = &mut img[i / spp];
        match o.integrator {
            Integrator::Normals => {
                let n = normalize64(tris[hit.prim as usize].normal64());
                let cos = dot64(n, normalize64(to64(r.d))).abs();
                for k in 0..3 {
                    px[k] += (0.5 * (n[k] + 1.0)) * (0.2 + 0.8 * cos) / spp as f64;
                }
            }
            Integrator::Direct => *px = add64(*px, scale64(emitted(scene, hit), 1.0 / spp as f64)),
            Integrator::Ao => {}
        }
    }
    for (s, b) in sec.iter().zip(blocked) {
        if !b {
            img[s.pixel] = add64(img[s.pixel], s.weight);
        }
    }
    Ok(img)
}

/// Pixel values to 8 bits: clamp to [0, 1], then `x^(1/gamma)` (2.2 for
/// radiance; 1 for ambient occlusion, a visibility share shown as it is).
pub fn to_rgb8(img: &[D3], w: u32, h: u32, gamma: f64) -> image::RgbImage {
    let mut out = image::RgbImage::new(w, h);
    for (i, p) in img.iter().enumerate() {
        let c =
            std::array::from_fn(|k| (p[k].clamp(0.0, 1.0).powf(1.0 / gamma) * 255.0).round() as u8);
        out.put_pixel(i as u32 % w, i as u32 / w, image::Rgb(c));
    }
    out
}

/// The secondary rays as a rays.txt (`nori-bridge compile --rays file`,
/// `make regress RAYS=file`): `ox oy oz dx dy dz tmin tmax`, each f32 in its
/// shortest exact decimal, so the file is the rays bit for bit.
pub fn write_rays_txt(path: &Path, sec: &[Secondary]) -> Result<()> {
    let mut f = std::io::BufWriter::new(
        std::fs::File::create(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
    );
    writeln!(
        f,
        "# secondary rays of nori-bridge shade-rays: ox oy oz dx dy dz tmin tmax"
    )?;
    for s in sec {
        let r = &s.ray;
        writeln!(
            f,
            "{} {} {} {} {} {} {} {}",
            r.o[0], r.o[1], r.o[2], r.d[0], r.d[1], r.d[2], r.tmin, r.tmax
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::txt::read_rays_txt;

    #[test]
    fn cornell_light_is_an_area_emitter() {
        let scene =
            crate::scene::xml::load_scene(Path::new("../scenes/cornell-box/cornell-box.xml"))
                .unwrap();
        let e: Vec<_> = scene.meshes.iter().map(|m| m.emitter).collect();
        assert_eq!(e, vec![None, None, None, Some([17.0, 12.0, 4.0])]);
        let l = lights(&scene);
        assert_eq!(l.tris.len(), scene.meshes[3].tri_count);
        assert!(l.total_area > 0.0 && (l.tris.last().unwrap().2 - l.total_area).abs() == 0.0);
    }

    /// rays.txt carries the secondary rays bit for bit (shortest exact decimals).
    #[test]
    fn rays_txt_round_trips_exactly() {
        let seed = 7u64;
        println!("seed {seed}");
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sec: Vec<Secondary> = (0..2000)
            .map(|i| {
                let mut f = || f32::from_bits(rng.gen::<u32>() & 0xbfff_ffff); // finite: exponent never all ones
                let ray = Ray {
                    o: [f(), f(), f()],
                    d: [f(), f(), 1.0 + f().abs()],
                    tmin: f().abs(),
                    tmax: f32::INFINITY,
                    shadow: false,
                };
                let ray = Ray {
                    tmax: if i % 2 == 0 {
                        f32::INFINITY
                    } else {
                        ray.tmin * 2.0 + 1.0
                    },
                    ..ray
                };
                Secondary {
                    pixel: i,
                    ray,
                    weight: [0.0; 3],
                }
            })
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("rays.txt");
        write_rays_txt(&p, &sec).unwrap();
        let back = read_rays_txt(&p).unwrap();
        assert_eq!(back.len(), sec.len());
        for (i, (a, b)) in sec.iter().zip(&back).enumerate() {
            let bits = |r: &Ray| {
                [r.o, r.d]
                    .concat()
                    .iter()
                    .chain([r.tmin, r.tmax].iter())
                    .map(|x| x.to_bits())
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&a.ray), bits(b), "ray {i}");
        }
    }
}
