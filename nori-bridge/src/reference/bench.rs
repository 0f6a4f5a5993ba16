//! `nori-bridge bench`: reference throughput. Not a test: figures go to
//! stdout for the notes.

use crate::package::Package;
use crate::reference::device::Device;
use crate::reference::embree::EmbreeScene;
use anyhow::Result;
use std::sync::Arc;
use std::time::Instant;

pub fn bench(pkg: &Package, min_rays: usize, robust: bool) -> Result<()> {
    let tris = pkg.image.by_prim();
    let t = Instant::now();
    let scene = EmbreeScene::new(Arc::new(Device::new(2)?), &tris, robust)?;
    let build = t.elapsed().as_secs_f64();
    let reps = min_rays.div_ceil(pkg.rays.len().max(1));
    let t = Instant::now();
    for _ in 0..reps {
        std::hint::black_box(scene.trace(&pkg.rays));
    }
    let secs = t.elapsed().as_secs_f64();
    let n = reps * pkg.rays.len();
    let t = Instant::now();
    for _ in 0..reps {
        std::hint::black_box(scene.trace_single(&pkg.rays));
    }
    let single = n as f64 / t.elapsed().as_secs_f64() / 1e6;
    assert_eq!(
        scene.trace_single(&pkg.rays),
        scene.trace(&pkg.rays),
        "packet and single-ray paths disagree"
    );
    let t = Instant::now();
    std::hint::black_box(crate::memory::mt_walk::trace_all(&pkg.image, &pkg.rays));
    let ours = pkg.rays.len() as f64 / t.elapsed().as_secs_f64() / 1e6;
    println!(
        "{}: {} triangles, {} rays x {reps} ({}): Embree{} {:.2} Mrays/s in packets of 8, {single:.2} Mrays/s one by one, on {} threads (scene build {:.3} s); our f32 layout walk {:.2} Mrays/s",
        pkg.dir.display(), tris.len(), pkg.rays.len(), pkg.manifest.ray_kind, if robust { " ROBUST" } else { "" },
        n as f64 / secs / 1e6, rayon::current_num_threads(), build, ours
    );
    Ok(())
}
