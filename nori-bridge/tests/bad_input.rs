//! Every bad input gets a clear error naming the file, the line or element,
//! and the value; nothing panics.

mod common;
use nori_bridge::scene_xml::load_scene;
use std::path::{Path, PathBuf};

struct Case {
    dir: tempfile::TempDir,
}

impl Case {
    fn new() -> Case {
        Case {
            dir: tempfile::tempdir().unwrap(),
        }
    }
    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
    /// A scene with one mesh `m.obj` (OBJ text given) and extra XML.
    fn scene(&self, obj: &str, extra: &str) -> PathBuf {
        self.file("m.obj", obj);
        self.file("s.xml", &format!(
            "<scene>\n{extra}\n<mesh type=\"obj\">\n<string name=\"filename\" value=\"m.obj\"/>\n</mesh>\n</scene>\n"))
    }
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// The error text must contain every needle.
fn expect_err(path: &Path, needles: &[&str]) {
    let e = match load_scene(path) {
        Ok(_) => panic!(
            "{}: loaded, expected an error containing {needles:?}",
            path.display()
        ),
        Err(e) => format!("{e:#}"),
    };
    for n in needles {
        assert!(e.contains(n), "error '{e}' lacks '{n}'");
    }
}

#[test]
fn malformed_xml_names_file_and_line() {
    let c = Case::new();
    let p = c.file("s.xml", "<scene>\n<mesh type=\"obj\">\n</scene>\n");
    expect_err(&p, &["s.xml:3:", "malformed XML"]);
}

#[test]
fn missing_obj_names_the_obj_and_the_mesh_line() {
    let c = Case::new();
    let p = c.file("s.xml", "<scene>\n\n<mesh type=\"obj\"><string name=\"filename\" value=\"nothere.obj\"/></mesh>\n</scene>");
    expect_err(&p, &["nothere.obj", "cannot read OBJ file", "s.xml:3"]);
}

#[test]
fn face_index_out_of_range_names_line_and_index() {
    let c = Case::new();
    expect_err(
        &c.scene("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n", ""),
        &["m.obj:5:", "face index 7 out of range", "3 vertices"],
    );
    expect_err(
        &c.scene("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", ""),
        &["m.obj:4:", "face index -4 out of range"],
    );
    expect_err(
        &c.scene("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ""),
        &["m.obj:4:", "face index 0 out of range"],
    );
}

#[test]
fn nan_vertex_names_line_and_value() {
    let c = Case::new();
    expect_err(
        &c.scene("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", ""),
        &["m.obj:2:", "'nan'", "not finite"],
    );
}

#[test]
fn infinite_vertex_names_line_and_value() {
    let c = Case::new();
    expect_err(
        &c.scene("v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n", ""),
        &["m.obj:3:", "'-inf'", "not finite"],
    );
}

#[test]
fn vertex_overflowing_after_transform_is_an_error() {
    let c = Case::new();
    c.file("m.obj", "v 0 0 0\nv 1e38 0 0\nv 0 1 0\nf 1 2 3\n");
    let p = c.file(
        "s.xml",
        "<scene><mesh type=\"obj\"><string name=\"filename\" value=\"m.obj\"/>\
        <transform name=\"toWorld\"><scale value=\"1e10,1,1\"/></transform></mesh></scene>",
    );
    expect_err(&p, &["m.obj", "not finite after the toWorld transform"]);
}

#[test]
fn empty_mesh_names_the_file() {
    let c = Case::new();
    expect_err(
        &c.scene("# nothing\nv 0 0 0\nv 1 0 0\n", ""),
        &["m.obj", "empty mesh"],
    );
}

#[test]
fn bad_vertex_text_names_line() {
    let c = Case::new();
    expect_err(
        &c.scene("v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", ""),
        &["m.obj:2:", "v 1 zero 0"],
    );
}

#[test]
fn camera_width_zero_names_line_and_value() {
    let c = Case::new();
    let cam = "<camera type=\"perspective\">\n<integer name=\"width\" value=\"0\"/>\n</camera>";
    expect_err(&c.scene(TRI, cam), &["s.xml:3:", "camera width '0'"]);
}

#[test]
fn bad_transform_values_name_line_and_value() {
    let c = Case::new();
    c.file("m.obj", TRI);
    let p = c.file(
        "s.xml",
        "<scene><mesh type=\"obj\"><string name=\"filename\" value=\"m.obj\"/>\n\
        <transform name=\"toWorld\">\n<translate value=\"1, two, 3\"/></transform></mesh></scene>",
    );
    expect_err(&p, &["s.xml:3:", "'two'"]);
    let p = c.file(
        "s.xml",
        "<scene><mesh type=\"obj\"><string name=\"filename\" value=\"m.obj\"/>\n\
        <transform name=\"toWorld\"><matrix value=\"1 2 3\"/></transform></mesh></scene>",
    );
    expect_err(&p, &["s.xml:2:", "16 numbers, got 3"]);
}

#[test]
fn unsupported_types_name_line_and_value() {
    let c = Case::new();
    let p = c.file("s.xml", "<scene>\n<mesh type=\"ply\"/>\n</scene>");
    expect_err(&p, &["s.xml:2:", "mesh type 'ply'"]);
    let p = c.file("s.xml", "<scene>\n<camera type=\"thinlens\"/>\n</scene>");
    expect_err(&p, &["s.xml:2:", "camera type 'thinlens'"]);
    let p = c.file("s.xml", "<notascene/>");
    expect_err(&p, &["s.xml:1:", "<notascene>"]);
}

fn rays_err(text: &str, needles: &[&str]) {
    let c = Case::new();
    let p = c.file("rays.txt", text);
    let e = format!(
        "{:#}",
        nori_bridge::rays_txt::read_rays_txt(&p).expect_err("expected an error")
    );
    for n in needles {
        assert!(e.contains(n), "error '{e}' lacks '{n}'");
    }
}

#[test]
fn zero_length_ray_direction_names_line_and_value() {
    rays_err(
        "# header\n0 0 0 1 0 0\n\n1 2 3 0 0 0 0 inf\n",
        &["rays.txt:4:", "direction [0.0, 0.0, 0.0]"],
    );
}

#[test]
fn nan_in_ray_file_names_line_and_value() {
    rays_err(
        "0 0 0 1 0 0\n0 0 NaN 1 0 0\n",
        &["rays.txt:2:", "'NaN' is NaN"],
    );
    rays_err("0 0 0 1 0 0 0 nan\n", &["rays.txt:1:", "'nan' is NaN"]);
}

#[test]
fn other_bad_rays_name_line_and_value() {
    rays_err("0 0 0 1 0\n", &["rays.txt:1:", "5 numbers"]);
    rays_err("0 0 0 1 0 0 x\n", &["rays.txt:1:", "'x' is not a number"]);
    rays_err(
        "0 0 0 1 0 0 5 1\n",
        &["rays.txt:1:", "tmin (5)", "tmax (1)"],
    );
    rays_err("inf 0 0 1 0 0\n", &["rays.txt:1:", "origin"]);
    rays_err("# only a comment\n", &["rays.txt", "no ray lines"]);
}

#[test]
fn ray_file_numbering_skips_comments_and_defaults() {
    let c = Case::new();
    let p = c.file(
        "rays.txt",
        "# a\n\n1 2 3 0 0 1  # first\n  # b\n4 5 6 1 0 0 0.5\n7 8 9 0 1 0 0 inf\n",
    );
    let r = nori_bridge::rays_txt::read_rays_txt(&p).unwrap();
    assert_eq!(r.len(), 3);
    assert_eq!(
        (r[0].o, r[0].tmin, r[0].tmax),
        ([1.0, 2.0, 3.0], 0.0, f32::INFINITY)
    );
    assert_eq!((r[1].tmin, r[1].tmax), (0.5, f32::INFINITY));
    assert_eq!(r[2].d, [0.0, 1.0, 0.0]);
}

#[test]
fn bad_hits_csv_names_line_and_value() {
    let c = Case::new();
    let h = nori_bridge::csv_io::HITS_HEADER;
    for (text, needles) in [
        (
            format!("{h}\n0,1,1.5,0,0,3,0\n1,2,1,0,0,3,0\n"),
            vec!["h.csv:3:", "hit '2'"],
        ),
        (
            format!("{h}\n0,1,1.5,0,0,3,0\n2,1,1,0,0,3,0\n"),
            vec!["h.csv:3:", "ray number '2', expected 1"],
        ),
        (
            format!("{h}\n0,1,abc,0,0,3,0\n"),
            vec!["h.csv:2:", "t 'abc'"],
        ),
        (format!("{h}\n0,1,1\n"), vec!["h.csv:2:", "3 columns"]),
        (
            "ray,hit\n".to_string(),
            vec!["h.csv:1:", "header is 'ray,hit'"],
        ),
    ] {
        let p = c.file("h.csv", &text);
        let e = format!(
            "{:#}",
            nori_bridge::csv_io::read_hits(&p).expect_err("expected an error")
        );
        for n in needles {
            assert!(e.contains(n), "error '{e}' lacks '{n}'");
        }
    }
}

#[test]
fn bad_memory_image_is_rejected() {
    let c = Case::new();
    let p = c.file(
        "image.bin",
        "not an image at all, just text that is long enough to pass the header length check....",
    );
    let e = format!("{:#}", nori_bridge::image_bin::Image::read(&p).unwrap_err());
    assert!(
        e.contains("image.bin") && e.contains("no RTACCEL header"),
        "{e}"
    );
}

/// Through the binary: exit status 1 (not a panic's 101), `Error: ` prefix.
#[test]
fn binary_reports_errors_with_exit_1() {
    let c = Case::new();
    let p = c.file("s.xml", "<scene>\n<mesh type=\"obj\">\n</scene>\n");
    let out = std::process::Command::new(common::bridge_bin())
        .args([
            "compile",
            p.to_str().unwrap(),
            "--out",
            c.dir.path().join("pkg").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(
        err.starts_with("Error: ") && err.contains("s.xml:3:"),
        "stderr: {err}"
    );
    let out = std::process::Command::new(common::bridge_bin())
        .args([
            "compare",
            "--package",
            c.dir.path().to_str().unwrap(),
            "--hits",
            "x.csv",
            "--out",
            "a.json",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(err.contains("package.json: cannot read"), "stderr: {err}");
}
