use nori_bridge::*;
fn main() {
    let dir = std::path::Path::new("/tmp/pk/cbs");
    let o = compile::CompileOpts { scene: "../scenes/cornell-box/cornell-box.xml".into(), out: dir.into(), rays: compile::RaySpec::Shadow, spp: 1, seed: 5, max_leaf_size: 4, robust: false, double_reference: false, width: None, height: None, count: 1, light: None };
    compile::compile(&o).unwrap();
    let pkg = package::Package::load(dir).unwrap();
    let tris = pkg.image.by_prim();
    let j = judge::Judge { tris: &tris, tol: judge::Tolerances::default() };
    let mut n = 0;
    for i in (0..pkg.rays.len()).step_by(37) {
        let mut h = pkg.reference[i]; h.hit = !h.hit;
        let c = j.classify(&pkg.rays[i], &h, &pkg.reference[i]);
        if c == judge::Class::Edge && n < 4 {
            n += 1;
            let r = pkg.rays[i];
            println!("ray {i} {:?} ref {:?}", r, pkg.reference[i]);
            for (k, t) in tris.iter().enumerate() {
                if let Some(e) = exact::eval64_plane(t, &r) { if e.margin > -1e-3 && e.t > -0.01 && e.t < 1.01 { println!("   tri {k} {:?}", e); } }
            }
        }
    }
}
