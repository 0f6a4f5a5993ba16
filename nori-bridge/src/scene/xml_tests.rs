//! XML transforms in Nori's order, checked on real vertices.

use super::*;
use std::io::Write;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::File::create(&p)
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    p
}

const TRI: &str = "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";

fn scene_with(transform: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "t.obj", TRI);
    let xml = format!(
        "<scene><mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/>\
         <transform name=\"toWorld\">{transform}</transform></mesh></scene>"
    );
    let p = write(dir.path(), "s.xml", &xml);
    load_scene(&p).unwrap()
}

#[test]
fn children_compose_in_nori_order() {
    // scale 2, then rotate 90 about z, then translate (10,0,0):
    // (1,0,0) -> (2,0,0) -> (0,2,0) -> (10,2,0).
    let s = scene_with("<scale value=\"2,2,2\"/><rotate axis=\"0,0,1\" angle=\"90\"/><translate value=\"10, 0, 0\"/>");
    let v = s.tris[0].v;
    let want = [[10.0, 2.0, 0.0], [8.0, 0.0, 0.0], [10.0, 0.0, 2.0]];
    for k in 0..3 {
        for c in 0..3 {
            assert!(
                (v[k][c] - want[k][c]).abs() < 1e-6,
                "vertex {k}: {:?} want {:?}",
                v[k],
                want[k]
            );
        }
    }
}

#[test]
fn matrix_element_is_row_major() {
    let s = scene_with("<matrix value=\"1 0 0 5  0 2 0 0  0 0 3 0  0 0 0 1\"/>");
    assert_eq!(
        s.tris[0].v,
        [[6.0, 0.0, 0.0], [5.0, 2.0, 0.0], [5.0, 0.0, 3.0]]
    );
}

#[test]
fn unknown_tags_warn_with_name_and_line() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "t.obj", TRI);
    let p = write(dir.path(), "s.xml",
        "<scene>\n<integrator type=\"path\"/>\n<volume type=\"x\"/>\n<mesh type=\"obj\"><string name=\"filename\" value=\"t.obj\"/><bsdf type=\"diffuse\"/>\n<texture/></mesh>\n</scene>");
    let s = load_scene(&p).unwrap();
    assert_eq!(s.warnings.len(), 2, "{:?}", s.warnings);
    assert!(
        s.warnings[0].contains(":3: warning: unknown tag <volume>"),
        "{}",
        s.warnings[0]
    );
    assert!(
        s.warnings[1].contains(":5: warning: unknown tag <texture> in <mesh>"),
        "{}",
        s.warnings[1]
    );
}

#[test]
fn shipped_cornell_box_camera_and_light() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell-box/cornell-box.xml");
    let s = load_scene(&p).unwrap();
    let cam = s.camera.unwrap();
    assert_eq!((cam.width, cam.height), (64, 64));
    assert_eq!(cam.to_world.point([0.0; 3]), [278.0, 273.0, -800.0]);
    assert_eq!(s.point_light, Some([278.0, 500.0, 279.5]));
    // room 5 quads + short 5 + tall 5 + light 1 = 16 quads = 32 triangles.
    assert_eq!(s.tris.len(), 32);
    assert_eq!(
        s.meshes.iter().map(|m| m.first_prim).collect::<Vec<_>>(),
        vec![0, 10, 20, 30]
    );
}
