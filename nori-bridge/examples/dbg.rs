use nori_bridge::*;
use rand::SeedableRng;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = &args[1];
    let seed: u64 = args[2].parse().unwrap();
    let ids: Vec<usize> = args[3..].iter().map(|s| s.parse().unwrap()).collect();
    let scene = scene_xml::load_scene(std::path::Path::new(&format!("../scenes/{name}/{name}.xml"))).unwrap();
    let rays = ray_gen::random(&scene.tris, &scene.bounds(), 100_000, &mut rand_chacha::ChaCha8Rng::seed_from_u64(seed));
    let dev = std::sync::Arc::new(embree_dev::Device::new(2).unwrap());
    let bvh = bvh_build::build_bvh(&dev, &scene.tris, 4).unwrap();
    let img = image_bin::Image::from_bvh(&bvh, &scene.tris);
    let em = embree_ref::EmbreeScene::new(dev.clone(), &scene.tris, false).unwrap();
    for &i in &ids {
        let r = rays[i];
        let e = em.trace(&[r])[0];
        let (o, _) = traverse::trace(&img, &r);
        let bf = double_ref::trace_double(&scene.tris[..], &[r]);
        println!("ray {i}: {:?}\n embree {:?}\n ours {:?}", r, e, o);
        for p in [e.prim, o.prim] {
            if p >= 0 {
                let t = &scene.tris[p as usize];
                let n = geom::normalize64(t.normal64());
                let d = geom::normalize64(geom::to64(r.d));
                println!("  prim {p}: eval64 {:?} plane {:?} cos {:e} mt32 {:?}", exact::eval64(t, &r), exact::eval64_plane(t, &r), geom::dot64(n, d), traverse::moller_trumbore(&t.v, &r));
            }
        }
        if let Ok(b) = bf { println!("  brute f64: {:?}", b[0]); }
    }
}
