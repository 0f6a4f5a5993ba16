//! Reference hits from Embree 3: one triangle geometry holding the scene's
//! concatenated triangle list, so Embree's primID is our prim number.
//! Rays are traced in packets of 8 (rtcIntersect8 / rtcOccluded8) on a
//! rayon pool.

use crate::geom::Tri;
use crate::ray::{Hit, Ray};
use crate::reference::device::Device;
use anyhow::{bail, Result};
use embree::sys;
use rayon::prelude::*;

pub struct EmbreeScene {
    scene: sys::RTCScene,
    _device: std::sync::Arc<Device>,
}

unsafe impl Send for EmbreeScene {}
unsafe impl Sync for EmbreeScene {}

impl EmbreeScene {
    pub fn new(device: std::sync::Arc<Device>, tris: &[Tri], robust: bool) -> Result<EmbreeScene> {
        unsafe {
            let dev = device.raw();
            let geom = sys::rtcNewGeometry(dev, sys::RTCGeometryType::TRIANGLE);
            let verts = sys::rtcSetNewGeometryBuffer(
                geom,
                sys::RTCBufferType::VERTEX,
                0,
                sys::RTCFormat::FLOAT3,
                12,
                3 * tris.len(),
            ) as *mut f32;
            let idx = sys::rtcSetNewGeometryBuffer(
                geom,
                sys::RTCBufferType::INDEX,
                0,
                sys::RTCFormat::UINT3,
                12,
                tris.len(),
            ) as *mut u32;
            if verts.is_null() || idx.is_null() {
                bail!(
                    "Embree: cannot allocate geometry buffers: {:?}",
                    device.error()
                );
            }
            for (i, t) in tris.iter().enumerate() {
                for (k, p) in t.v.iter().enumerate() {
                    for c in 0..3 {
                        *verts.add(9 * i + 3 * k + c) = p[c];
                    }
                    *idx.add(3 * i + k) = (3 * i + k) as u32;
                }
            }
            sys::rtcCommitGeometry(geom);
            let scene = sys::rtcNewScene(dev);
            if robust {
                sys::rtcSetSceneFlags(scene, sys::RTCSceneFlags::ROBUST);
            }
            sys::rtcSetSceneBuildQuality(scene, sys::RTCBuildQuality::MEDIUM);
            sys::rtcAttachGeometry(scene, geom);
            sys::rtcReleaseGeometry(geom);
            sys::rtcCommitScene(scene);
            let err = device.error();
            if err != sys::RTCError::NONE {
                bail!("Embree: scene commit failed: {err:?}");
            }
            Ok(EmbreeScene {
                scene,
                _device: device,
            })
        }
    }

    /// Trace all rays (closest hit, or occlusion for shadow rays).
    pub fn trace(&self, rays: &[Ray]) -> Vec<Hit> {
        let mut hits = vec![Hit::MISS; rays.len()];
        // 256 rays per rayon task, traced as packets of 8.
        hits.par_chunks_mut(256)
            .zip(rays.par_chunks(256))
            .for_each(|(h, r)| {
                h.chunks_mut(8)
                    .zip(r.chunks(8))
                    .for_each(|(h, r)| self.trace8(r, h))
            });
        hits
    }

    /// The same answers one ray at a time (rtcIntersect1/rtcOccluded1), for
    /// throughput comparison with the packet path.
    pub fn trace_single(&self, rays: &[Ray]) -> Vec<Hit> {
        rays.par_iter().map(|r| self.trace1(r)).collect()
    }

    fn trace1(&self, r: &Ray) -> Hit {
        let mut rh: sys::RTCRayHit = unsafe { std::mem::zeroed() };
        let ray = &mut rh.ray;
        (ray.org_x, ray.org_y, ray.org_z, ray.tnear) = (r.o[0], r.o[1], r.o[2], r.tmin);
        (ray.dir_x, ray.dir_y, ray.dir_z, ray.tfar) = (r.d[0], r.d[1], r.d[2], r.tmax);
        ray.mask = u32::MAX;
        rh.hit.geomID = u32::MAX;
        let mut ctx = new_context();
        unsafe {
            if r.shadow {
                sys::rtcOccluded1(self.scene, &mut ctx, &mut rh.ray);
                return Hit::occluded(rh.ray.tfar == f32::NEG_INFINITY);
            }
            sys::rtcIntersect1(self.scene, &mut ctx, &mut rh);
        }
        if rh.hit.geomID == u32::MAX {
            Hit::MISS
        } else {
            Hit {
                hit: true,
                t: rh.ray.tfar,
                u: rh.hit.u,
                v: rh.hit.v,
                prim: rh.hit.primID as i64,
                error: 0,
            }
        }
    }

    fn trace8(&self, rays: &[Ray], out: &mut [Hit]) {
        let mut rh: sys::RTCRayHit8 = unsafe { std::mem::zeroed() };
        // Embree reads the valid mask with aligned 256-bit loads: it must be
        // 32-byte aligned ([i32; 8] alone is 4-aligned and crashed once the
        // stack layout moved it off a 32-byte boundary).
        #[repr(C, align(32))]
        struct Valid8([i32; 8]);
        let mut valid = Valid8([0; 8]);
        let any_shadow = rays.iter().any(|r| r.shadow);
        let all_shadow = rays.iter().all(|r| r.shadow);
        for (i, r) in rays.iter().enumerate() {
            valid.0[i] = -1;
            let ray = &mut rh.ray;
            (ray.org_x[i], ray.org_y[i], ray.org_z[i]) = (r.o[0], r.o[1], r.o[2]);
            (ray.dir_x[i], ray.dir_y[i], ray.dir_z[i]) = (r.d[0], r.d[1], r.d[2]);
            (ray.tnear[i], ray.tfar[i]) = (r.tmin, r.tmax);
            ray.mask[i] = u32::MAX;
            ray.id[i] = i as u32;
            rh.hit.geomID[i] = u32::MAX;
            rh.hit.primID[i] = u32::MAX;
        }
        let mut ctx = new_context();
        unsafe {
            if all_shadow {
                sys::rtcOccluded8(valid.0.as_ptr(), self.scene, &mut ctx, &mut rh.ray);
            } else if !any_shadow {
                sys::rtcIntersect8(valid.0.as_ptr(), self.scene, &mut ctx, &mut rh);
            } else {
                // A mixed packet: trace closest hits, the occlusion answer is the same.
                sys::rtcIntersect8(valid.0.as_ptr(), self.scene, &mut ctx, &mut rh);
            }
        }
        for (i, r) in rays.iter().enumerate() {
            out[i] = if all_shadow {
                Hit::occluded(rh.ray.tfar[i] == f32::NEG_INFINITY)
            } else if rh.hit.geomID[i] == u32::MAX {
                Hit::MISS
            } else if r.shadow {
                Hit::occluded(true)
            } else {
                Hit {
                    hit: true,
                    t: rh.ray.tfar[i],
                    u: rh.hit.u[i],
                    v: rh.hit.v[i],
                    prim: rh.hit.primID[i] as i64,
                    error: 0,
                }
            };
        }
    }
}

fn new_context() -> sys::RTCIntersectContext {
    // rtcInitIntersectContext is an inline C function: do what it does.
    sys::RTCIntersectContext {
        flags: sys::RTCIntersectContextFlags(0), // INCOHERENT = 0
        filter: None,
        instID: [u32::MAX],
    }
}

impl Drop for EmbreeScene {
    fn drop(&mut self) {
        unsafe { sys::rtcReleaseScene(self.scene) }
    }
}
