//! sweep-report end to end on a tiny synthetic sweep: real Cornell-box
//! packages (primary and AO rays, 8x8 pixels), hits files made from their
//! reference with deliberate changes, compare's real accuracy JSON, fake
//! speed, area and hard-case verdicts. Checks the derived numbers, the
//! Pareto fronts, the summary sentence, the plots, and clear errors on
//! missing inputs. Also: each AO ray starts on a primary ray of its pixel.

// The test's own parts sit beside this file (fixture, synthetic); the
// helpers every integration test shares are one folder up.
#[path = "../common/mod.rs"]
mod common;
mod fixture;
mod synthetic;

use common::*;
use fixture::{package, Fixture, SPP};
use nori_bridge::compile::{write_json, RaySpec};
use nori_bridge::geom::{cross64, len64, sub64, to64};
use nori_bridge::pixels::{read_ao_pixels, AO_PIXELS_FILE};
use serde_json::{json, Value};
use std::path::Path;
use std::process::{Command, Output};
use synthetic::write_sweep;

/// Primary rays of the AO package's camera are the primary package's rays
/// (same seed, spp and size), so every AO origin lies on one of the rays
/// of the pixel ao_pixels.csv names.
#[test]
fn ao_rays_start_on_a_primary_ray_of_their_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let prim = package(&dir.path().join("p"), RaySpec::Primary);
    let ao = package(&dir.path().join("ao"), RaySpec::Ao);
    let m = ao.manifest.ao_image.expect("ao_image in package.json");
    assert_eq!((m.width, m.height), (8, 8));
    let map = read_ao_pixels(&ao.dir.join(AO_PIXELS_FILE), 64).unwrap();
    assert_eq!(map.len(), ao.rays.len());
    for (i, (r, &p)) in ao.rays.iter().zip(&map).enumerate() {
        let on_ray = (0..SPP as usize).any(|s| {
            let q = &prim.rays[p as usize * SPP as usize + s];
            let d = to64(q.d);
            len64(cross64(sub64(to64(r.o), to64(q.o)), d)) / len64(d) < 1e-2 // mm, in a 550 mm box
        });
        assert!(
            on_ray,
            "AO ray {i} (pixel {p}) does not start on a primary ray of that pixel"
        );
    }
}

/// Runs sweep-report (the binary cargo built for this test) on `sweep`,
/// writing `json`, `md` and `plots`; `extra` arguments go last.
fn sweep_report(sweep: &Path, json: &Path, md: &Path, plots: &Path, extra: &[&str]) -> Output {
    Command::new(bridge_bin())
        .arg("sweep-report")
        .arg("--sweep")
        .arg(sweep)
        .arg("--json")
        .arg(json)
        .arg("--md")
        .arg(md)
        .arg("--plots")
        .arg(plots)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn synthetic_sweep_gives_the_expected_numbers_fronts_sentence_and_plots() {
    let f = Fixture::new();
    let (p, a) = (&f.prim, &f.ao);
    let e8m12_errors = write_sweep(&f);

    let out = f.dir.path().join("docs");
    let (j, md, plots) = (out.join("r.json"), out.join("r.md"), out.join("r"));
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(
        out.join("r-notes.md"),
        "Hand-written: the e6m9 leaks are expected.\n",
    )
    .unwrap();
    let o = sweep_report(
        &f.sweep(),
        &j,
        &md,
        &plots,
        &["--runtime-note", "42 s on 2 cores"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&j).unwrap()).unwrap();
    let pts: Vec<&Value> = r["points"].as_array().unwrap().iter().collect();
    let names: Vec<&str> = pts.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "e6m9-conservative-wt",
            "e8m12-rne-wt",
            "e8m23-conservative-wt",
            "e8m23-rne-wt"
        ]
    );
    let e12 = pts[1];
    assert_eq!(e12["baseline"], "e8m23-rne-wt");
    assert_eq!(pts[0]["baseline"], "e8m23-conservative-wt");
    assert_eq!(
        e12["pixels"]["differing"], 3,
        "2 primary pixels + 1 AO pixel"
    );
    assert_eq!(e12["pixels"]["total"], 128);
    assert_eq!(e12["error_flagged"], 1);
    let run = |p: &Value, n: &str| {
        p["runs"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["run"] == n)
            .unwrap()
            .clone()
    };
    assert_eq!(run(e12, "cornell-primary")["pixels"]["differing"], 2);
    assert_eq!(run(e12, "cornell-ao")["pixels"]["differing"], 1);
    // t: only ray rc differs among same-prim hits.
    let hits_same = p.reference.iter().filter(|h| h.hit).count() - 3;
    let tr = run(e12, "cornell-primary")["t_rel"].clone();
    assert_eq!(tr["count"], hits_same);
    let want_max = 0.001 / 1.001;
    assert!(
        (tr["max"].as_f64().unwrap() - want_max).abs() < 1e-6,
        "{tr}"
    );
    assert!(
        (run(e12, "cornell-primary")["t_rel_mean"].as_f64().unwrap() - want_max / hits_same as f64)
            .abs()
            < 1e-8
    );
    let rate = e12["errors_per_million_rays"].as_f64().unwrap();
    let rays = (p.rays.len() + a.rays.len()) as f64;
    assert!(
        (rate - e8m12_errors as f64 * 1e6 / rays).abs() < 1e-6,
        "{rate}"
    );
    for q in [pts[0], pts[2], pts[3]] {
        assert_eq!(q["pixels"]["differing"], 0);
        assert_eq!(q["errors_per_million_rays"], 0.0);
    }
    assert!((pts[0]["vs_baseline"]["lut"].as_f64().unwrap() - 0.6).abs() < 1e-12);
    assert!((e12["vs_baseline"]["rays_per_cycle"].as_f64().unwrap() - 1.2).abs() < 1e-12);
    assert_eq!(pts[0]["hard"]["leaks"], 2);
    // Fronts: e6m9 (0 errors, 6600 LUT) dominates on area; on speed the
    // untimed e6m9 is out, FP32 rne (0 errors, 0.5) and e8m12 (errors, 0.6) stay.
    assert_eq!(r["pareto"]["error_lut"], json!(["e6m9-conservative-wt"]));
    assert_eq!(
        r["pareto"]["error_speed"],
        json!(["e8m23-rne-wt", "e8m12-rne-wt"])
    );
    assert_eq!(
        r["pareto"]["without_speed"],
        json!(["e6m9-conservative-wt"])
    );
    let summary = r["summary"].as_str().unwrap();
    // Safe means 0 errors, 0 hard-case failures and no image differing: e6m9 leaks on the
    // sphere and e8m12 has errors, so the FP32 points remain; rne has fewer LUTs.
    assert!(
        summary.contains("**e8m23-rne-wt**")
            && summary.contains("boxes in **e8m23**")
            && summary.contains("box-lane LUTs n/a, core LUTs unchanged"),
        "{summary}"
    );

    let doc = std::fs::read_to_string(&md).unwrap();
    for want in [
        "42 s on 2 cores",
        "- rne/watertight: **e8m23-rne-wt** (nori nodes, boxes e8m23, triangles e8m23)",
        "- conservative/watertight: **e8m23-conservative-wt**",
        "![Error against LUTs](r/error-vs-lut.png)",
        "`sphere` on `e6m9-conservative-wt`: 2 leaks",
        "| configuration | sphere (40 rays) |",
        "| e6m9-conservative-wt | 2/0/0 |",
        "| Embree | 3/0/0 |",
        "| Embree ROBUST | 1/0/0 |",
        "| f64 reference | 0/0/0 |",
        "Hand-written: the e6m9 leaks are expected.",
    ] {
        assert!(doc.contains(want), "missing '{want}' in:\n{doc}");
    }
    assert!(!doc.contains("**Warning:**"), "{doc}");
    for png in [
        "error-vs-lut.png",
        "error-vs-speed.png",
        "pixels-vs-mantissa.png",
    ] {
        let img = image::open(plots.join(png))
            .unwrap_or_else(|e| panic!("{png}: {e}"))
            .to_rgb8();
        assert_eq!(img.dimensions(), (1100, 750), "{png}");
        let non_white = img.pixels().filter(|px| px.0 != [255, 255, 255]).count();
        assert!(non_white > 5_000, "{png}: only {non_white} drawn pixels");
    }

    // Same inputs, same bytes (JSON and plots).
    let (j2, p2) = (out.join("again.json"), out.join("again"));
    let o = sweep_report(&f.sweep(), &j2, &out.join("again.md"), &p2, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&j).unwrap(),
        std::fs::read(&j2).unwrap(),
        "JSON differs between two runs"
    );
    for png in [
        "error-vs-lut.png",
        "error-vs-speed.png",
        "pixels-vs-mantissa.png",
    ] {
        assert_eq!(
            std::fs::read(plots.join(png)).unwrap(),
            std::fs::read(p2.join(png)).unwrap(),
            "{png} differs between two runs"
        );
    }

    // Inputs missing: the error names the file and what is missing.
    let sweep = f.sweep();
    let bad = |what: &str| {
        let o = sweep_report(&sweep, &j, &md, &plots, &[]);
        assert!(!o.status.success(), "{what}: should fail");
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let area = sweep.join("area/e8m12-rne-wt.json");
    std::fs::rename(&area, sweep.join("moved")).unwrap();
    let e = bad("area");
    assert!(e.contains("area/e8m12-rne-wt.json: cannot read"), "{e}");
    std::fs::rename(sweep.join("moved"), &area).unwrap();
    let pf = sweep.join("points/e8m12-rne-wt.json");
    let good = std::fs::read_to_string(&pf).unwrap();
    let mut v: Value = serde_json::from_str(&good).unwrap();
    v.as_object_mut().unwrap().remove("latency");
    write_json(&pf, &v).unwrap();
    let e = bad("latency");
    assert!(
        e.contains("points/e8m12-rne-wt.json") && e.contains("missing field `latency`"),
        "{e}"
    );
    std::fs::write(&pf, good).unwrap();
    let hr = sweep.join("hard-ref/sphere-robust.json");
    std::fs::rename(&hr, sweep.join("moved")).unwrap();
    let e = bad("hard-ref");
    assert!(
        e.contains("hard-ref/sphere-robust.json: cannot read")
            && e.contains("reference 'robust' on hard case 'sphere'"),
        "{e}"
    );
    std::fs::rename(sweep.join("moved"), &hr).unwrap();
    std::fs::remove_file(sweep.join("points/e8m23-rne-wt.json")).unwrap();
    let e = bad("baseline");
    assert!(
        e.contains("no baseline for point 'e8m12-rne-wt'")
            && e.contains(
                "layout nori, box and triangle format e8m23, rounding rne, triangle watertight"
            ),
        "{e}"
    );
}
