//! The f32 walk of the wide layouts against the walk of the nori layout,
//! ray by ray, on 20k seeded random rays per shipped scene (and shadow
//! rays): the same hit, bit for bit, except ties (both hit, different
//! prims, at the same t or ulps apart), which are counted and must each
//! follow the tie rule (see `tie`). The
//! walk's stack never exceeds the header's bvhDepth. Compiles are
//! deterministic per layout and the CLI records the layout.

mod common;
use common::*;
use nori_bridge::bvh::Layout;
use nori_bridge::image_bin::Image;
use nori_bridge::mt_walk;
use std::process::Command;

#[test]
fn wide_walks_equal_the_nori_walk_ray_by_ray() {
    for (i, name) in SHIPPED.iter().enumerate() {
        let seed = 40 + i as u64;
        let scene = load(name);
        let rays = walk_rays(name, seed);
        let (_, nori_img) = build_as(&scene, 4, Layout::Nori);
        let (want, nori_stats) = mt_walk::trace_all(&nori_img, &rays);
        assert!(
            nori_stats.max_stack <= nori_img.bvh_depth as usize,
            "{name} seed {seed}: nori stack"
        );
        let hits = want[..RAYS].iter().filter(|h| h.hit).count();
        assert!(
            hits > RAYS / 10,
            "{name} seed {seed}: only {hits} hits, the ray set is too easy"
        );
        for layout in [Layout::Wide2, Layout::Wide4, Layout::Wide8] {
            let (_, img) = build_as(&scene, 4, layout);
            let (got, stats) = mt_walk::trace_all(&img, &rays);
            let what = format!("{name} --bvh {layout} seed {seed}");
            assert!(
                stats.max_stack <= img.bvh_depth as usize,
                "{what}: stack {} > bvhDepth {}",
                stats.max_stack,
                img.bvh_depth
            );
            let (mut ties, mut ulps) = (0, 0);
            for (r, (ray, (g, w))) in rays.iter().zip(got.iter().zip(&want)).enumerate() {
                if ray.shadow {
                    assert_eq!(g.hit, w.hit, "{what}: shadow ray {r} {ray:?}");
                } else if g != w {
                    let d = tie(ray, (g, &img), (w, &nori_img));
                    let d = d.unwrap_or_else(|| {
                        panic!("{what}: ray {r} {ray:?}: {g:?} vs nori {w:?} is no tie")
                    });
                    ties += 1;
                    ulps = ulps.max(d);
                }
            }
            println!("{what}: {} rays, {ties} ties (t up to {ulps} ulp apart), largest stack {} (bvhDepth {})", rays.len(), stats.max_stack, img.bvh_depth);
        }
    }
}

/// Two compiles per layout give the same bytes; scene.json and
/// package.json record the layout; `trace` follows the header and prints a
/// largest stack within bvhDepth.
#[test]
fn cli_compiles_each_layout_deterministically() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("icosphere");
    for layout in ["nori", "2", "4", "8", "4q", "8q"] {
        let pkg = |k: &str| dir.path().join(format!("{layout}-{k}"));
        for k in ["a", "b"] {
            run(&[
                "compile",
                s(&scene),
                "--out",
                s(&pkg(k)),
                "--rays",
                "random",
                "--count",
                "3000",
                "--bvh",
                layout,
            ]);
        }
        for f in ["image.bin", "rays.csv", "reference.csv", "scene.json"] {
            let (a, b) = (
                std::fs::read(pkg("a").join(f)).unwrap(),
                std::fs::read(pkg("b").join(f)).unwrap(),
            );
            assert!(a == b, "--bvh {layout}: {f} differs between two compiles");
        }
        let img = Image::read(&pkg("a").join("image.bin")).unwrap();
        let n = json(&pkg("a").join("scene.json"));
        assert_eq!(
            (n["format_version"].as_u64(), n["layout"].as_str()),
            (Some(3), Some(layout))
        );
        assert_eq!(n["nodes"].as_u64(), Some(img.node_count() as u64));
        assert_eq!(n["bvh_depth"].as_u64(), Some(img.bvh_depth as u64));
        assert!(
            n["tree_depth"].as_u64().unwrap() >= 1 && n["mean_children"].as_f64().unwrap() >= 2.0,
            "{n}"
        );
        let m = json(&pkg("a").join("package.json"));
        assert_eq!(m["build"]["layout"], layout);
        assert_eq!(m["counts"]["nodes"], n["nodes"]);
        let hits = dir.path().join(format!("{layout}.csv"));
        let said = run(&["trace", "--package", s(&pkg("a")), "--out", s(&hits)]);
        let stack: usize = said
            .split("largest stack ")
            .nth(1)
            .and_then(|x| x.split(' ').next())
            .unwrap()
            .parse()
            .unwrap();
        assert!(stack <= img.bvh_depth as usize, "--bvh {layout}: {said}");
        let acc = dir.path().join(format!("{layout}.json"));
        run(&[
            "compare",
            "--package",
            s(&pkg("a")),
            "--hits",
            s(&hits),
            "--out",
            s(&acc),
        ]);
        assert_eq!(json(&acc)["mismatches"], 0, "--bvh {layout}");
    }
    let out = Command::new(bridge_bin())
        .args(["compile", s(&scene), "--out", s(dir.path()), "--bvh", "3"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("BVH layout '3' is not one of nori, 2, 4, 8, 4q, 8q"));
}

/// `trace` on an image whose layout word is malformed fails naming the
/// file and the value.
#[test]
fn trace_refuses_a_malformed_layout_word() {
    let dir = tempfile::tempdir().unwrap();
    let pkg = dir.path().join("pkg");
    run(&[
        "compile",
        s(&scene_path("cornell-box")),
        "--out",
        s(&pkg),
        "--rays",
        "random",
        "--count",
        "10",
        "--bvh",
        "8",
    ]);
    let path = pkg.join("image.bin");
    let mut b = std::fs::read(&path).unwrap();
    b[44..48].copy_from_slice(&3u32.to_le_bytes());
    std::fs::write(&path, b).unwrap();
    let out = Command::new(bridge_bin())
        .args([
            "trace",
            "--package",
            s(&pkg),
            "--out",
            s(&dir.path().join("h.csv")),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(s(&path))
            && err.contains(
                "header layout 3 (bytes 44-47) is not 0 (nori), 2, 4, 8, 20 (4q) or 24 (8q)"
            ),
        "{err}"
    );
}
