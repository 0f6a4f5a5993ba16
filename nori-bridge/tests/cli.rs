//! End to end through the binary: compile every ray kind, trace our layout,
//! compare, render; determinism; the double reference.

mod common;
use common::*;
use std::process::Command;

#[test]
fn every_ray_kind_compiles_traces_and_compares_clean() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("cornell-box");
    let rays_txt = dir.path().join("rays.txt");
    std::fs::write(
        &rays_txt,
        "# two rays\n278 273 -800 0 0 1\n278 273 -800 0 1 0 0 100\n",
    )
    .unwrap();
    let kinds: [(&str, Vec<&str>); 5] = [
        ("primary", vec!["--spp", "2"]),
        ("shadow", vec![]),
        ("ao", vec!["--spp", "2"]),
        ("random", vec!["--count", "5000"]),
        (s(&rays_txt), vec![]),
    ];
    for (i, (kind, extra)) in kinds.iter().enumerate() {
        let pkg = dir.path().join(format!("pkg{i}"));
        let mut args = vec![
            "compile",
            s(&scene),
            "--out",
            s(&pkg),
            "--rays",
            kind,
            "--seed",
            "3",
        ];
        args.extend(extra.iter());
        run(&args);
        for f in nori_bridge::package::FILES {
            assert!(pkg.join(f).exists(), "{kind}: {f} missing");
        }
        let m = json(&pkg.join("package.json"));
        assert_eq!(m["format_version"], 3);
        assert_eq!(m["counts"]["triangles"], 32);
        let rays = m["counts"]["rays"].as_u64().unwrap();
        match *kind {
            "primary" => assert_eq!(rays, 64 * 64 * 2),
            "random" => assert_eq!(rays, 5000),
            "shadow" | "ao" => assert!(rays > 1000, "{kind}: {rays} rays"),
            _ => assert_eq!(rays, 2),
        }
        let hits = dir.path().join(format!("hits{i}.csv"));
        let acc = dir.path().join(format!("acc{i}.json"));
        run(&["trace", "--package", s(&pkg), "--out", s(&hits)]);
        let summary = run(&[
            "compare",
            "--package",
            s(&pkg),
            "--hits",
            s(&hits),
            "--out",
            s(&acc),
        ]);
        let a = json(&acc);
        assert_eq!(a["mismatches"], 0, "{kind}: {summary}");
        assert_eq!(a["rays"].as_u64().unwrap(), rays);
        assert!(summary.contains("0 mismatches"), "{summary}");
    }
    let img = dir.path().join("img");
    run(&[
        "render",
        "--package",
        s(&dir.path().join("pkg0")),
        "--hits",
        s(&dir.path().join("hits0.csv")),
        "--out-dir",
        s(&img),
    ]);
    for f in ["hits.png", "reference.png", "diff.png"] {
        let im = image::open(img.join(f)).unwrap();
        assert_eq!((im.width(), im.height()), (64, 64), "{f}");
    }
    // render refuses a package without a camera image
    let out = Command::new(bridge_bin())
        .args([
            "render",
            "--package",
            s(&dir.path().join("pkg3")),
            "--hits",
            s(&dir.path().join("hits3.csv")),
            "--out-dir",
            s(&img),
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("render needs --rays primary"));
}

#[test]
fn same_seed_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("multi-mesh");
    for k in ["a", "b"] {
        run(&[
            "compile",
            s(&scene),
            "--out",
            s(&dir.path().join(k)),
            "--rays",
            "ao",
            "--seed",
            "42",
            "--max-leaf-size",
            "2",
        ]);
    }
    for f in ["image.bin", "rays.csv", "reference.csv", "scene.json"] {
        let a = std::fs::read(dir.path().join("a").join(f)).unwrap();
        let b = std::fs::read(dir.path().join("b").join(f)).unwrap();
        assert!(a == b, "{f} differs between two runs with the same seed");
    }
    run(&[
        "compile",
        s(&scene),
        "--out",
        s(&dir.path().join("c")),
        "--rays",
        "ao",
        "--seed",
        "43",
        "--max-leaf-size",
        "2",
    ]);
    assert_ne!(
        std::fs::read(dir.path().join("a/rays.csv")).unwrap(),
        std::fs::read(dir.path().join("c/rays.csv")).unwrap()
    );
}

#[test]
fn double_reference_and_embree_reference_agree_up_to_ties() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("icosphere");
    let (d, e) = (dir.path().join("double"), dir.path().join("embree"));
    run(&[
        "compile",
        s(&scene),
        "--out",
        s(&d),
        "--rays",
        "random",
        "--count",
        "20000",
        "--reference",
        "double",
    ]);
    run(&[
        "compile",
        s(&scene),
        "--out",
        s(&e),
        "--rays",
        "random",
        "--count",
        "20000",
        "--robust",
    ]);
    assert_eq!(json(&d.join("package.json"))["reference"]["kind"], "double");
    assert_eq!(json(&e.join("package.json"))["reference"]["robust"], true);
    // the double reference as "hits" against the Embree package
    let acc = dir.path().join("acc.json");
    run(&[
        "compare",
        "--package",
        s(&e),
        "--hits",
        s(&d.join("reference.csv")),
        "--out",
        s(&acc),
    ]);
    assert_eq!(json(&acc)["mismatches"], 0);
    // more than 20k triangles is refused
    let out = Command::new(bridge_bin())
        .args([
            "compile",
            s(&scene_path("dragon")),
            "--out",
            s(&dir.path().join("x")),
            "--rays",
            "random",
            "--count",
            "10",
            "--reference",
            "double",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("at most 20000 triangles; this one has 202520"));
}

#[test]
fn scene_json_needs_for_cornell_box() {
    let dir = tempfile::tempdir().unwrap();
    run(&[
        "compile",
        s(&scene_path("cornell-box")),
        "--out",
        s(dir.path()),
        "--width",
        "8",
        "--height",
        "4",
    ]);
    let n = json(&dir.path().join("scene.json"));
    assert_eq!(n["triangles"], 32);
    assert_eq!(n["extent_min"], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(n["extent_max"][0], 556.0);
    // smallest coordinate magnitude 65 (2^6), largest 559.2 (2^9)
    assert_eq!(
        (n["exponent_min"].as_i64(), n["exponent_max"].as_i64()),
        (Some(6), Some(9))
    );
    assert_eq!(n["degenerate_triangles"], 0);
    assert_eq!(n["index_bits"]["prim"], 5);
    assert_eq!(json(&dir.path().join("package.json"))["counts"]["rays"], 32);
    let img = nori_bridge::image_bin::Image::read(&dir.path().join("image.bin")).unwrap();
    assert_eq!(n["bvh_depth"].as_u64().unwrap(), img.bvh_depth as u64);
    assert_eq!(n["nodes"].as_u64().unwrap(), img.nodes.len() as u64);
}
