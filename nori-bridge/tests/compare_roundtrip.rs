//! compare: the reference fed back as hits gives zero mismatches; a
//! deliberately corrupted copy has every corruption reported in its class.
//! Rays aimed exactly at vertices and edges of the closed icosphere show the
//! judge siding with the f64 answer when Embree lets rays escape.

mod common;
use common::*;
use nori_bridge::bvh::Layout;
use nori_bridge::compare::compare;
use nori_bridge::compile::{compile, CompileOpts, RaySpec};
use nori_bridge::exact::{eval64, eval64_plane};
use nori_bridge::geom::{dot64, len64, normalize64, to64};
use nori_bridge::judge::{Class, Tolerances};
use nori_bridge::package::Package;
use nori_bridge::ray::{Hit, Ray};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

fn opts(scene: &str, out: &Path, rays: RaySpec) -> CompileOpts {
    CompileOpts {
        scene: scene_path(scene),
        out: out.to_path_buf(),
        rays,
        spp: 1,
        seed: 5,
        max_leaf_size: 4,
        layout: Layout::Nori,
        robust: false,
        double_reference: false,
        width: None,
        height: None,
        count: 20_000,
        light: None,
    }
}

/// A hit whose f64 evaluation is far from every edge and not grazing, so a
/// corruption of it cannot be excused as an edge case.
fn well_conditioned(tris: &[nori_bridge::geom::Tri], r: &Ray, h: &Hit) -> bool {
    let t = &tris[h.prim as usize];
    let cos = dot64(normalize64(t.normal64()), normalize64(to64(r.d))).abs();
    eval64(t, r).is_some_and(|e| e.margin > 0.05) && cos > 0.2
}

#[test]
fn reference_as_hits_has_no_mismatch_and_corruptions_are_all_reported() {
    let seed = 99;
    let dir = tempfile::tempdir().unwrap();
    compile(&opts("multi-mesh", dir.path(), RaySpec::Random)).unwrap();
    let pkg = Package::load(dir.path()).unwrap();
    let tris = pkg.image.by_prim();
    let (acc, classes) = compare(
        &tris,
        &pkg.rays,
        &pkg.reference,
        &pkg.reference,
        Tolerances::default(),
    )
    .unwrap();
    assert_eq!(acc.mismatches, 0);
    assert!(
        classes.iter().all(|c| *c == Class::Agree),
        "{:?}",
        acc.counts
    );

    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut hits = pkg.reference.clone();
    let mut expect: Vec<(usize, Class)> = Vec::new();
    let mut used = std::collections::HashSet::new();
    let kinds = [
        Class::FalseMiss,
        Class::TError,
        Class::WrongPrim,
        Class::FalseHit,
    ];
    while expect.len() < 400 {
        let i = rng.gen_range(0..pkg.rays.len());
        let kind = kinds[expect.len() % kinds.len()];
        let (r, h) = (&pkg.rays[i], pkg.reference[i]);
        if used.contains(&i) {
            continue;
        }
        let ok = match kind {
            Class::FalseMiss => h.hit && well_conditioned(&tris, r, &h),
            Class::TError => h.hit && well_conditioned(&tris, r, &h),
            Class::WrongPrim | Class::FalseHit => {
                let wanted_hit = kind == Class::WrongPrim;
                if h.hit != wanted_hit || (h.hit && !well_conditioned(&tris, r, &h)) {
                    false
                } else {
                    // a prim whose plane the ray meets far outside the triangle, or never
                    let p = rng.gen_range(0..tris.len());
                    let far = eval64_plane(&tris[p], r).is_none_or(|e| e.margin < -0.5);
                    if far {
                        hits[i] = Hit {
                            hit: true,
                            t: if h.hit { h.t } else { 1.0 },
                            u: 0.2,
                            v: 0.2,
                            prim: p as i64,
                            error: 0,
                        };
                    }
                    far
                }
            }
            _ => unreachable!(),
        };
        if !ok {
            continue;
        }
        match kind {
            Class::FalseMiss => hits[i] = Hit::MISS,
            Class::TError => hits[i].t = h.t * 1.01,
            _ => {}
        }
        used.insert(i);
        expect.push((i, kind));
    }
    let (acc, classes) = compare(
        &tris,
        &pkg.rays,
        &hits,
        &pkg.reference,
        Tolerances::default(),
    )
    .unwrap();
    for &(i, kind) in &expect {
        assert_eq!(
            classes[i], kind,
            "seed {seed}: ray {i} corrupted as {kind:?} classified {:?}",
            classes[i]
        );
        assert!(
            acc.ray_lists[&kind].contains(&i),
            "ray {i} missing from the {kind:?} list"
        );
    }
    assert_eq!(
        acc.mismatches,
        expect.len(),
        "seed {seed}: only the corrupted rays may mismatch: {:?}",
        acc.counts
    );
    assert_eq!(acc.worst.len(), 20);
    assert!(acc.worst.iter().all(|c| c.class.is_mismatch()));
}

#[test]
fn shadow_corruptions_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    compile(&opts("cornell-box", dir.path(), RaySpec::Shadow)).unwrap();
    let pkg = Package::load(dir.path()).unwrap();
    assert!(pkg.rays.iter().all(|r| r.shadow));
    let tris = pkg.image.by_prim();
    let mut hits = pkg.reference.clone();
    let flipped: Vec<usize> = (0..hits.len()).step_by(37).collect();
    for &i in &flipped {
        hits[i].hit = !hits[i].hit;
    }
    let (acc, classes) = compare(
        &tris,
        &pkg.rays,
        &hits,
        &pkg.reference,
        Tolerances::default(),
    )
    .unwrap();
    for (i, c) in classes.iter().enumerate() {
        if flipped.contains(&i) {
            let want = if hits[i].hit {
                Class::FalseHit
            } else {
                Class::FalseMiss
            };
            assert!(
                *c == want || *c == Class::Edge,
                "ray {i}: flipped shadow answer classified {c:?}"
            );
        } else {
            assert_eq!(*c, Class::Agree, "ray {i}");
        }
    }
    let edge = classes.iter().filter(|c| **c == Class::Edge).count();
    assert!(
        edge * 10 < flipped.len(),
        "{edge} of {} flips excused as edge cases",
        flipped.len()
    );
    assert_eq!(acc.mismatches + edge, flipped.len());
}

/// Rays from outside aimed exactly at the vertices and edge midpoints of the
/// closed icosphere, from origins that see the point well in front (not on
/// the silhouette, where an f32-rounded direction may rightly miss), must
/// all hit. The f64 brute force never lets one
/// escape; where Embree does, compare(hits = f64, reference = Embree) calls
/// it reference_wrong, never a mismatch.
#[test]
fn vertex_aimed_rays_judge_embree_escapes_as_reference_wrong() {
    let scene = load("icosphere");
    let mut rays = Vec::new();
    for t in &scene.tris {
        for k in 0..3 {
            let target = if rays.len() % 2 == 0 {
                to64(t.v[k])
            } else {
                let (a, b) = (to64(t.v[k]), to64(t.v[(k + 1) % 3]));
                [
                    (a[0] + b[0]) / 2.0,
                    (a[1] + b[1]) / 2.0,
                    (a[2] + b[2]) / 2.0,
                ]
            };
            for o in [[0.0, 0.0, -5.0], [3.0, 2.0, 1.0], [-2.0, -4.0, 0.5]] {
                let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
                // unit sphere: the outward normal at the target is ~target
                if -dot64(normalize64(target), normalize64(d)) < 0.3 {
                    continue;
                }
                rays.push(Ray {
                    o: [o[0] as f32, o[1] as f32, o[2] as f32],
                    d: [d[0] as f32, d[1] as f32, d[2] as f32],
                    tmin: 0.0,
                    tmax: f32::INFINITY,
                    shadow: false,
                });
            }
        }
    }
    rays.retain(|r| len64(to64(r.d)) > 0.0);
    let exact = nori_bridge::double_ref::trace_double(&scene.tris, &rays).unwrap();
    let escapes64 = exact.iter().filter(|h| !h.hit).count();
    assert_eq!(
        escapes64,
        0,
        "the f64 reference let {escapes64} of {} vertex/edge-aimed rays escape a closed mesh",
        rays.len()
    );
    for robust in [false, true] {
        let embree =
            nori_bridge::embree_ref::EmbreeScene::new(device(), &scene.tris, robust).unwrap();
        let reference = embree.trace(&rays);
        let (acc, classes) = compare(
            &scene.tris,
            &rays,
            &exact,
            &reference,
            Tolerances::default(),
        )
        .unwrap();
        let escapes = reference.iter().filter(|h| !h.hit).count();
        println!(
            "Embree robust={robust}: {escapes} of {} vertex/edge-aimed rays escape; judge: {:?}",
            rays.len(),
            acc.counts
        );
        assert_eq!(acc.mismatches, 0, "{:?}", acc.counts);
        for (i, c) in classes.iter().enumerate() {
            if !reference[i].hit {
                assert_eq!(
                    *c,
                    Class::ReferenceWrong,
                    "ray {i}: Embree escape judged {c:?}"
                );
            }
        }
    }
}
