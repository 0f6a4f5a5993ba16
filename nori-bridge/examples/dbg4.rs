use nori_bridge::*;
use nori_bridge::geom::*;
fn main() {
    let scene = scene_xml::load_scene(std::path::Path::new("../scenes/icosphere/icosphere.xml")).unwrap();
    let mut rays = Vec::new();
    for t in &scene.tris { for k in 0..3 {
        let target = if rays.len() % 2 == 0 { to64(t.v[k]) } else { let (a, b) = (to64(t.v[k]), to64(t.v[(k + 1) % 3])); [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, (a[2] + b[2]) / 2.0] };
        for o in [[0.0, 0.0, -5.0], [3.0, 2.0, 1.0], [-2.0, -4.0, 0.5f64]] {
            let d = sub64(target, o);
            if -dot64(normalize64(target), normalize64(d)) < 0.3 { continue; }
            rays.push(ray::Ray { o: to32(o), d: to32(d), tmin: 0.0, tmax: f32::INFINITY, shadow: false });
        }
    }}
    let exact = double_ref::trace_double(&scene.tris, &rays).unwrap();
    let em = embree_ref::EmbreeScene::new(std::sync::Arc::new(embree_dev::Device::new(2).unwrap()), &scene.tris, false).unwrap();
    let reference = em.trace(&rays);
    let j = judge::Judge { tris: &scene.tris, tol: judge::Tolerances::default() };
    let mut n = 0;
    for i in 0..rays.len() {
        if j.classify(&rays[i], &exact[i], &reference[i]) == judge::Class::ReferenceWrong && n < 3 {
            n += 1;
            println!("ray {i} {:?}\n f64 {:?}\n emb {:?}", rays[i], exact[i], reference[i]);
            for p in [exact[i].prim, reference[i].prim] { println!("   prim {p} {:?}", exact::eval64_plane(&scene.tris[p as usize], &rays[i])); }
        }
    }
}
