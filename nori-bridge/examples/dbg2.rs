use nori_bridge::*;
use nori_bridge::geom::*;
fn main() {
    let scene = scene_xml::load_scene(std::path::Path::new("../scenes/icosphere/icosphere.xml")).unwrap();
    let mut n = 0;
    for t in &scene.tris {
        for k in 0..3 {
            let target = to64(t.v[k]);
            for o in [[0.0, 0.0, -5.0], [3.0, 2.0, 1.0], [-2.0, -4.0, 0.5f64]] {
                let d = sub64(target, o);
                let r = ray::Ray { o: to32(o), d: to32(d), tmin: 0.0, tmax: f32::INFINITY, shadow: false };
                let any = scene.tris.iter().any(|tt| exact::eval64(tt, &r).is_some());
                if !any && n < 2 {
                    n += 1;
                    println!("escape: {:?}", r);
                    for (i, tt) in scene.tris.iter().enumerate() {
                        if let Some(h) = exact::eval64_plane(tt, &r) { if h.margin > -1e-3 { println!("  tri {i} {:?}", h); } }
                    }
                }
            }
        }
    }
}
