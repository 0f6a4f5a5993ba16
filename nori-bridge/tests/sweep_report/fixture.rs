//! The test's sweep on disk: the two Cornell-box packages (8x8 pixels,
//! SPP rays a pixel) and writers of the files the sweep flow leaves under
//! build/sweep (hits, compare's accuracy, points/, area/).

use crate::common::*;
use nori_bridge::bvh::Layout;
use nori_bridge::compare::compare;
use nori_bridge::compile::{compile, write_json, CompileOpts, RaySpec};
use nori_bridge::csv_io::write_hits;
use nori_bridge::judge::Tolerances;
use nori_bridge::package::Package;
use nori_bridge::ray::Hit;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

pub const SPP: u32 = 2;

/// The Cornell box with `rays` compiled into `dir`, small enough that a
/// changed hit is one pixel to count by hand.
pub fn package(dir: &Path, rays: RaySpec) -> Package {
    let o = CompileOpts {
        scene: scene_path("cornell-box"),
        out: dir.to_path_buf(),
        rays,
        spp: SPP,
        seed: 7,
        max_leaf_size: 4,
        layout: Layout::Nori,
        robust: false,
        double_reference: false,
        width: Some(8),
        height: Some(8),
        count: 0,
        light: None,
    };
    compile(&o).unwrap();
    Package::load(dir).unwrap()
}

/// A temporary directory with the two packages the sweep's runs trace
/// (primary and AO rays) and the sweep's input tree under `sweep/`.
pub struct Fixture {
    pub dir: tempfile::TempDir,
    pub prim: Package,
    pub ao: Package,
}

impl Fixture {
    pub fn new() -> Fixture {
        let dir = tempfile::tempdir().unwrap();
        let prim = package(&dir.path().join("pkg-primary"), RaySpec::Primary);
        let ao = package(&dir.path().join("pkg-ao"), RaySpec::Ao);
        Fixture { dir, prim, ao }
    }

    pub fn sweep(&self) -> PathBuf {
        self.dir.path().join("sweep")
    }

    /// Writes hits + compare's accuracy for one point and run; returns the run's JSON.
    pub fn run(&self, cfg: &str, pkg: &Package, name: &str, hits: &[Hit], speed: Value) -> Value {
        let h = self.sweep().join("hits").join(cfg);
        std::fs::create_dir_all(&h).unwrap();
        let (hp, ap) = (
            h.join(format!("{name}.csv")),
            h.join(format!("{name}.json")),
        );
        write_hits(&hp, hits).unwrap();
        let (acc, _) = compare(
            &pkg.image.by_prim(),
            &pkg.rays,
            hits,
            &pkg.reference,
            Tolerances::default(),
        )
        .unwrap();
        write_json(&ap, &acc).unwrap();
        let acc: Value = serde_json::from_str(&std::fs::read_to_string(&ap).unwrap()).unwrap();
        json!({"run": name, "scene": "cornell-box", "rays": pkg.manifest.ray_kind, "hard_case": null,
               "package": pkg.dir, "hits": hp, "rays_total": hits.len(), "error_flagged": acc["error_flagged"],
               "node_tests_per_ray": 10.0, "tri_tests_per_ray": 4.0, "accuracy": acc, "speed": speed})
    }

    pub fn point(&self, cfg: &str, runs: Vec<Value>, lut: u64, leaks: usize) -> Value {
        let parts: Vec<&str> = cfg.split('-').collect();
        let (e, m) = parts[0][1..].split_once('m').unwrap();
        let mut runs = runs;
        runs.push(json!({"run": "hard-sphere", "scene": "sphere", "rays": "file", "hard_case": "sphere", "package": "unused",
                         "hits": "unused", "rays_total": 40, "error_flagged": 0, "node_tests_per_ray": 3.0, "tri_tests_per_ray": 2.0,
                         "hard": {"case": "sphere", "rays": 40, "leaks": leaks, "false_hits": 0, "wrong_prims": 0, "flagged": 0, "ok": leaks == 0},
                         "speed": null}));
        let p = json!({"config": {"name": cfg, "float": parts[0], "exp_bits": e.parse::<u32>().unwrap(), "man_bits": m.parse::<u32>().unwrap(),
                                  "rounding": if parts[1] == "rne" { "rne" } else { "conservative" },
                                  "triangle": if parts[2] == "wt" { "watertight" } else { "moller" }},
                       "latency": {"ray_prep": 11, "box": 9, "triangle": 24}, "runs": runs});
        let a = json!({"config": cfg, "lut": lut, "ff": lut / 2, "dsp": 40, "bram36": 4.5, "instances_zc706": 218_600 / lut,
                       "units": {"RayPrep": {"lut": 1, "ff": 2, "dsp": 3}}, "seconds": 1.0});
        for (sub, v) in [("points", &p), ("area", &a)] {
            std::fs::create_dir_all(self.sweep().join(sub)).unwrap();
            write_json(&self.sweep().join(sub).join(format!("{cfg}.json")), v).unwrap();
        }
        p
    }
}
