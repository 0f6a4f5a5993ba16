//! Our f32 walk of our own memory image against Embree on 100k seeded random
//! rays per shipped scene. Disagreements are judged in f64: ties, edge cases
//! and Embree-wrong cases are counted apart; a real mismatch fails.

mod common;
use common::*;
use nori_bridge::compare::compare;
use nori_bridge::embree_ref::EmbreeScene;
use nori_bridge::judge::{Class, Tolerances};
use nori_bridge::ray::Ray;
use nori_bridge::{double_ref, mt_walk, ray_gen};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const RAYS: usize = 100_000;

fn check(name: &str, rays: &[Ray], robust: bool, seed: u64) {
    let scene = load(name);
    let (_, img) = build(&scene, 4);
    let embree = EmbreeScene::new(device(), &scene.tris, robust).unwrap();
    let want = embree.trace(rays);
    let (got, stats) = mt_walk::trace_all(&img, rays);
    assert!(
        stats.max_stack <= img.bvh_depth as usize,
        "{name}: stack {} > bvhDepth {}",
        stats.max_stack,
        img.bvh_depth
    );
    let (acc, _) = compare(&scene.tris, rays, &got, &want, Tolerances::default()).unwrap();
    let hits = want.iter().filter(|h| h.hit).count();
    println!(
        "{name} seed {seed} robust {robust}: {} rays, {hits} Embree hits: {:?}",
        rays.len(),
        acc.counts
    );
    assert!(
        hits > rays.len() / 10,
        "{name}: only {hits} hits, the ray set is too easy"
    );
    assert_eq!(
        acc.mismatches,
        0,
        "{name} seed {seed}: mismatches {:?}, worst {}",
        acc.counts,
        serde_json::to_string(&acc.worst).unwrap()
    );
}

fn random_rays(name: &str, seed: u64, count: usize) -> Vec<Ray> {
    let scene = load(name);
    ray_gen::random(
        &scene.tris,
        &scene.bounds(),
        count,
        &mut ChaCha8Rng::seed_from_u64(seed),
    )
}

#[test]
fn cornell_box_agrees_with_embree() {
    check(
        "cornell-box",
        &random_rays("cornell-box", 11, RAYS),
        false,
        11,
    );
}

#[test]
fn icosphere_agrees_with_embree() {
    check("icosphere", &random_rays("icosphere", 12, RAYS), false, 12);
}

#[test]
fn multi_mesh_agrees_with_embree() {
    check("multi-mesh", &random_rays("multi-mesh", 13, RAYS), true, 13);
}

#[test]
fn dragon_agrees_with_embree() {
    check("dragon", &random_rays("dragon", 14, RAYS), false, 14);
}

#[test]
fn shadow_rays_agree_with_embree() {
    for (i, name) in SHIPPED.iter().enumerate() {
        let seed = 20 + i as u64;
        let mut rays = random_rays(name, seed, 20_000);
        for (k, r) in rays.iter_mut().enumerate() {
            r.shadow = true;
            r.tmax = if k % 3 == 0 {
                f32::INFINITY
            } else {
                0.05 * (k % 40) as f32
            };
        }
        check(name, &rays, false, seed);
    }
}

/// Our walk against the f64 brute force on the small closed mesh: the f64
/// reference is exact-as-possible, so only edge cases and ties may differ.
#[test]
fn icosphere_agrees_with_double_reference() {
    let seed = 15;
    let scene = load("icosphere");
    let rays = random_rays("icosphere", seed, 20_000);
    let want = double_ref::trace_double(&scene.tris, &rays).unwrap();
    let (_, img) = build(&scene, 4);
    let (got, _) = mt_walk::trace_all(&img, &rays);
    let (acc, classes) = compare(&scene.tris, &rays, &got, &want, Tolerances::default()).unwrap();
    println!("icosphere vs double, seed {seed}: {:?}", acc.counts);
    assert_eq!(acc.mismatches, 0, "seed {seed}: {:?}", acc.counts);
    assert_eq!(
        classes
            .iter()
            .filter(|c| **c == Class::ReferenceWrong)
            .count(),
        0,
        "the f64 brute force must never be judged wrong by the f64 judge"
    );
}

/// Axis-aligned rays lying exactly in the planes of flat boxes and faces
/// (floor y=0, block tops y=165 and y=330, ceiling y=548.8) and in wall
/// planes: the slab test sees 0 * inf there. Our walk must match the f64
/// brute force; Embree is judged (reference_wrong counted apart).
#[test]
fn in_plane_axis_aligned_rays_on_cornell_box() {
    let scene = load("cornell-box");
    let mut rays = Vec::new();
    for y in [0.0f32, 165.0, 330.0, 548.8, 100.0] {
        for k in 0..=40 {
            let s = -20.0 + 15.0 * k as f32;
            for (o, d) in [
                ([s, y, -100.0], [0.0, 0.0, 1.0]),
                ([-50.0, y, s], [1.0, 0.0, 0.0]),
                ([600.0, y, s], [-1.0, 0.0, 0.0]),
                ([s, y, 700.0], [0.0, 0.0, -1.0]),
            ] {
                rays.push(Ray {
                    o,
                    d,
                    tmin: 0.0,
                    tmax: f32::INFINITY,
                    shadow: false,
                });
            }
        }
    }
    for x in [0.0f32, 556.0, 130.0] {
        for k in 0..=40 {
            let s = -20.0 + 15.0 * k as f32;
            rays.push(Ray {
                o: [x, s, -100.0],
                d: [0.0, 0.0, 1.0],
                tmin: 0.0,
                tmax: f32::INFINITY,
                shadow: false,
            });
            rays.push(Ray {
                o: [x, -10.0, s],
                d: [0.0, 1.0, 0.0],
                tmin: 0.0,
                tmax: f32::INFINITY,
                shadow: false,
            });
        }
    }
    let exact = double_ref::trace_double(&scene.tris, &rays).unwrap();
    let (_, img) = build(&scene, 4);
    let (ours, _) = mt_walk::trace_all(&img, &rays);
    let (acc, _) = compare(&scene.tris, &rays, &ours, &exact, Tolerances::default()).unwrap();
    println!("in-plane rays, ours vs f64: {:?}", acc.counts);
    assert_eq!(
        acc.mismatches,
        0,
        "{:?} worst {}",
        acc.counts,
        serde_json::to_string(&acc.worst).unwrap()
    );
    let embree = EmbreeScene::new(device(), &scene.tris, false)
        .unwrap()
        .trace(&rays);
    let (acc, _) = compare(&scene.tris, &rays, &exact, &embree, Tolerances::default()).unwrap();
    println!("in-plane rays, f64 as hits vs Embree: {:?}", acc.counts);
    assert_eq!(acc.mismatches, 0, "{:?}", acc.counts);
}

/// A soup of 3000 triangles: exactly degenerate ones (collinear or
/// coincident vertices on a 1/8 grid, so f64 area is exactly 0) and, if
/// `slivers`, near-collinear ones (a, a+e, a+2e rounded to f32: 2 area
/// ~1e-7 with unit edges), the rest ordinary.
fn soup(seed: u64, slivers: bool) -> (Vec<nori_bridge::geom::Tri>, Vec<Ray>) {
    use nori_bridge::geom::Tri;
    use rand::Rng;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let grid = |rng: &mut ChaCha8Rng, r: i32| -> [f32; 3] {
        std::array::from_fn(|_| rng.gen_range(-r..=r) as f32 / 8.0)
    };
    let tris: Vec<Tri> = (0..3000)
        .map(|i| {
            let (a, e, f) = if slivers && i % 3 == 0 {
                let a: [f32; 3] = std::array::from_fn(|_| rng.gen_range(-10.0..10.0));
                let e: [f32; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
                (a, e, e.map(|x| 2.0 * x))
            } else {
                let (a, e, f) = (grid(&mut rng, 80), grid(&mut rng, 8), grid(&mut rng, 8));
                match i % 3 {
                    0 => (a, e, e.map(|x| 2.0 * x)),
                    1 => (a, [0.0; 3], e),
                    _ => (a, e, f),
                }
            };
            let add = |p: [f32; 3], q: [f32; 3]| [p[0] + q[0], p[1] + q[1], p[2] + q[2]];
            Tri {
                v: [a, add(a, e), add(a, f)],
            }
        })
        .collect();
    let bounds = tris.iter().fold(nori_bridge::geom::Aabb::empty(), |b, t| {
        b.union(&t.bounds())
    });
    let rays = ray_gen::random(&tris, &bounds, 50_000, &mut rng);
    (tris, rays)
}

/// Exactly degenerate triangles are flagged and never hit; the walk agrees
/// with Embree.
#[test]
fn degenerate_triangles_are_never_hit() {
    let seed = 31;
    let (tris, rays) = soup(seed, false);
    let img = nori_bridge::image_bin::Image::from_bvh(
        &nori_bridge::bvh_build::build_bvh(&device(), &tris, 4).unwrap(),
        &tris,
    );
    assert_eq!(
        img.tris
            .iter()
            .filter(|r| r.flags & nori_bridge::image_bin::FLAG_ZERO_AREA != 0)
            .count(),
        2000
    );
    let want = EmbreeScene::new(device(), &tris, false)
        .unwrap()
        .trace(&rays);
    let (got, _) = mt_walk::trace_all(&img, &rays);
    for (i, h) in got.iter().enumerate() {
        assert!(
            !h.hit || tris[h.prim as usize].double_area64() > 0.0,
            "seed {seed}: ray {i} hit zero-area prim {}",
            h.prim
        );
    }
    let (acc, _) = compare(&tris, &rays, &got, &want, Tolerances::default()).unwrap();
    println!("degenerate soup seed {seed}: {:?}", acc.counts);
    assert_eq!(acc.mismatches, 0, "seed {seed}: {:?}", acc.counts);
}

/// Near-collinear slivers (2 area ~1e-7 with unit edges) are below f32's
/// resolution: f32 Moller-Trumbore reports hits far outside them (det is
/// pure rounding). The judge's barycentric bound grows as e / (2 area), so
/// these count as edge cases, never as agreeing or as mismatches, while
/// the ordinary triangles in the same soup still agree exactly.
#[test]
fn sliver_hits_are_judged_edge_cases() {
    let seed = 32;
    let (tris, rays) = soup(seed, true);
    let img = nori_bridge::image_bin::Image::from_bvh(
        &nori_bridge::bvh_build::build_bvh(&device(), &tris, 4).unwrap(),
        &tris,
    );
    let want = EmbreeScene::new(device(), &tris, false)
        .unwrap()
        .trace(&rays);
    let (got, _) = mt_walk::trace_all(&img, &rays);
    let (acc, classes) = compare(&tris, &rays, &got, &want, Tolerances::default()).unwrap();
    println!("sliver soup seed {seed}: {:?}", acc.counts);
    assert_eq!(
        acc.mismatches,
        0,
        "seed {seed}: {:?} worst {}",
        acc.counts,
        serde_json::to_string(&acc.worst).unwrap()
    );
    let sliver = |p: i64| p >= 0 && p % 3 == 0 && tris[p as usize].double_area64() > 0.0;
    let edge = classes.iter().filter(|c| **c == Class::Edge).count();
    assert!(
        edge > 50,
        "seed {seed}: only {edge} edge cases; the slivers should produce many"
    );
    for (i, c) in classes.iter().enumerate() {
        if *c == Class::Edge {
            assert!(
                sliver(got[i].prim) || sliver(want[i].prim),
                "seed {seed}: ray {i} judged edge without a sliver: {:?} vs {:?}",
                got[i],
                want[i]
            );
        }
    }
}
