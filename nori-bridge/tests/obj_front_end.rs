//! OBJ loading: n-gon fans in face order, negative indices, missing .mtl,
//! prim numbering across meshes; and a proptest that the OBJ and XML front
//! end never panics on arbitrary input (errors are fine, panics are not).

mod common;
use nori_bridge::obj::load_obj;
use nori_bridge::scene_xml::load_scene;
use nori_bridge::transform::Mat4;
use proptest::prelude::*;

fn obj(text: &str) -> anyhow::Result<Vec<nori_bridge::geom::Tri>> {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("m.obj");
    std::fs::write(&p, text).unwrap();
    load_obj(&p, &Mat4::identity())
}

#[test]
fn ngons_become_fans_in_face_order() {
    // a triangle, a quad, a hexagon: 1 + 2 + 4 triangles, in that order
    let t = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 3 1 0\n\
                 f 1 2 3\nf 1 2 3 4\nf 1 2 5 6 3 4\n")
    .unwrap();
    let idx = |p: [f32; 3]| {
        [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [2., 0., 0.],
            [3., 1., 0.],
        ]
        .iter()
        .position(|q| *q == p)
        .unwrap()
            + 1
    };
    let faces: Vec<[usize; 3]> = t
        .iter()
        .map(|t| [idx(t.v[0]), idx(t.v[1]), idx(t.v[2])])
        .collect();
    assert_eq!(
        faces,
        vec![
            [1, 2, 3],
            [1, 2, 3],
            [1, 3, 4],
            [1, 2, 5],
            [1, 5, 6],
            [1, 6, 3],
            [1, 3, 4]
        ]
    );
}

#[test]
fn negative_indices_count_back_from_the_last_vertex() {
    let t = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -1 -2\n").unwrap();
    assert_eq!(t[0].v, [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]]);
    assert_eq!(t[1].v, [[0., 0., 0.], [5., 5., 5.], [0., 1., 0.]]);
}

#[test]
fn missing_mtl_and_texture_normal_indices_are_fine() {
    let t = obj(
        "mtllib nowhere.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
                 f 1/1/1 2/1/1 3/1/1\ng other\nusemtl blue\nf 3//1 2//1 1//1\n",
    )
    .unwrap();
    assert_eq!(t.len(), 2);
    assert_eq!(t[1].v[0], [0., 1., 0.]);
}

/// tobj starts a new model at each g/o/usemtl; prim order must still be
/// the file's face order, even when a group name comes back.
#[test]
fn groups_and_materials_keep_file_face_order() {
    let t = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
                 g a\nf 1 2 3\ng b\nusemtl m1\nf 1 2 4\ng a\nf 1 3 4\nusemtl m2\nf 2 3 4\no o2\nf 3 2 1\n").unwrap();
    let third = |t: &nori_bridge::geom::Tri| t.v[2];
    assert_eq!(
        t.iter().map(third).collect::<Vec<_>>(),
        vec![
            [0., 1., 0.],
            [0., 0., 1.],
            [0., 0., 1.],
            [0., 0., 1.],
            [0., 0., 0.]
        ]
    );
    assert_eq!(t[3].v[0], [1., 0., 0.]);
    assert_eq!(t[2].v[1], [0., 1., 0.]);
}

#[test]
fn multi_mesh_scene_concatenates_in_xml_order_with_transforms() {
    let s = load_scene(&common::scene_path("multi-mesh")).unwrap();
    let firsts: Vec<usize> = s.meshes.iter().map(|m| m.first_prim).collect();
    assert_eq!(firsts, vec![0, 2, 1282, 2562]);
    assert_eq!(s.tris.len(), 2578); // prism: 2 pentagons x 3 + 5 quads x 2
                                    // ground: scale 4,1,4 of (-1,0,-1): prim 0 vertex 0
    assert_eq!(s.tris[0].v[0], [-4.0, 0.0, -4.0]);
    // prism: rotate 15 about y, then the matrix: (1,0,0) -> (cos15, 0, -sin15) -> (0.6 cos15 + 0.5, 0, -0.6 sin15 - 1.5)
    let (sn, cs) = 15f64.to_radians().sin_cos();
    let want = [(0.6 * cs + 0.5) as f32, 0.0, (-0.6 * sn - 1.5) as f32];
    let got = s.tris[2562].v[0];
    for k in 0..3 {
        assert!(
            (got[k] - want[k]).abs() <= 1e-6,
            "prism vertex {got:?} want {want:?}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: fuzz_cases(), failure_persistence: None, ..ProptestConfig::default() })]

    /// Arbitrary OBJ-like text (lines from OBJ keywords and numbers, plus
    /// junk) loads or errors, never panics; a success has finite vertices.
    #[test]
    fn obj_front_end_never_panics(lines in prop::collection::vec(obj_line(), 0..30)) {
        if let Ok(tris) = obj(&lines.join("\n")) {
            prop_assert!(!tris.is_empty());
            prop_assert!(tris.iter().all(|t| t.v.iter().flatten().all(|c| c.is_finite())));
        }
    }

    /// Arbitrary XML-ish scenes built from Nori tags and random attribute
    /// values load or error, never panic.
    #[test]
    fn xml_front_end_never_panics(body in prop::collection::vec(xml_element(), 0..8), junk in "[<>/=\" a-z0-9]{0,20}") {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let p = dir.path().join("s.xml");
        std::fs::write(&p, format!("<scene>{}{junk}</scene>", body.join("\n"))).unwrap();
        let _ = load_scene(&p);
    }
}

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-1000i32..1000).prop_map(|i| i.to_string()),
        any::<f32>().prop_map(|f| f.to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-0".to_string()),
        Just("1e39".to_string()),
        "[a-z/]{0,4}",
    ]
}

fn obj_line() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::collection::vec(number(), 0..5).prop_map(|n| format!("v {}", n.join(" "))),
        prop::collection::vec((-12i32..12).prop_map(|i| i.to_string()), 0..7)
            .prop_map(|n| format!("f {}", n.join(" "))),
        prop::collection::vec("-?[0-9]{1,2}/[0-9]{0,2}/?[0-9]{0,2}", 0..5)
            .prop_map(|n| format!("f {}", n.join(" "))),
        Just("usemtl x".to_string()),
        Just("mtllib none.mtl".to_string()),
        Just("g grp".to_string()),
        Just("o obj".to_string()),
        Just("l 1 2".to_string()),
        Just("p 1".to_string()),
        "[ -~]{0,30}",
    ]
}

fn vec3() -> impl Strategy<Value = String> {
    prop::collection::vec(number(), 0..5).prop_map(|v| v.join(", "))
}

fn transforms() -> impl Strategy<Value = String> {
    let tf = prop_oneof![
        vec3().prop_map(|v| format!("<translate value=\"{v}\"/>")),
        vec3().prop_map(|v| format!("<scale value=\"{v}\"/>")),
        (vec3(), number()).prop_map(|(v, a)| format!("<rotate axis=\"{v}\" angle=\"{a}\"/>")),
        prop::collection::vec(number(), 0..18)
            .prop_map(|v| format!("<matrix value=\"{}\"/>", v.join(" "))),
        (vec3(), vec3(), vec3())
            .prop_map(|(a, b, c)| format!("<lookat origin=\"{a}\" target=\"{b}\" up=\"{c}\"/>")),
        Just("<bogus/>".to_string()),
    ];
    prop::collection::vec(tf, 0..4)
        .prop_map(|t| format!("<transform name=\"toWorld\">{}</transform>", t.join("")))
}

fn xml_element() -> impl Strategy<Value = String> {
    prop_oneof![
        (transforms(), prop_oneof![Just("m.obj"), Just("missing.obj"), Just("")]).prop_map(|(t, f)| format!(
            "<mesh type=\"obj\"><string name=\"filename\" value=\"{f}\"/>{t}</mesh>")),
        (transforms(), number(), number(), number()).prop_map(|(t, w, h, fov)| format!(
            "<camera type=\"perspective\"><integer name=\"width\" value=\"{w}\"/><integer name=\"height\" value=\"{h}\"/>\
             <float name=\"fov\" value=\"{fov}\"/>{t}</camera>")),
        vec3().prop_map(|v| format!("<emitter type=\"point\"><point name=\"position\" value=\"{v}\"/></emitter>")),
        Just("<integrator type=\"path\"/>".to_string()),
        Just("<mesh type=\"obj\"/>".to_string()),
        "[a-z]{1,6}".prop_map(|t| format!("<{t}/>")),
    ]
}

/// 3000 cases per `cargo test`; PROPTEST_CASES=N for a longer campaign.
fn fuzz_cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000)
}
