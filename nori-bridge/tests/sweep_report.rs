//! sweep-report end to end on a tiny synthetic sweep: real Cornell-box
//! packages (primary and AO rays, 8x8 pixels), hits files made from their
//! reference with deliberate changes, compare's real accuracy JSON, fake
//! speed, area and hard-case verdicts. Checks the derived numbers, the
//! Pareto fronts, the summary sentence, the plots, and clear errors on
//! missing inputs. Also: each AO ray starts on a primary ray of its pixel.

mod common;
use common::*;
use nori_bridge::bvh::Layout;
use nori_bridge::compare::compare;
use nori_bridge::compile::{compile, write_json, CompileOpts, RaySpec};
use nori_bridge::csv_io::write_hits;
use nori_bridge::exact::eval64;
use nori_bridge::geom::{cross64, len64, sub64, to64};
use nori_bridge::judge::Tolerances;
use nori_bridge::package::Package;
use nori_bridge::pixels::{read_ao_pixels, AO_PIXELS_FILE};
use nori_bridge::ray::Hit;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Command;

const SPP: u32 = 2;

fn package(dir: &Path, rays: RaySpec) -> Package {
    let o = CompileOpts {
        scene: scene_path("cornell-box"),
        out: dir.to_path_buf(),
        rays,
        spp: SPP,
        seed: 7,
        max_leaf_size: 4,
        layout: Layout::Nori,
        robust: false,
        double_reference: false,
        width: Some(8),
        height: Some(8),
        count: 0,
        light: None,
    };
    compile(&o).unwrap();
    Package::load(dir).unwrap()
}

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

struct Fixture {
    dir: tempfile::TempDir,
    prim: Package,
    ao: Package,
}

impl Fixture {
    fn sweep(&self) -> PathBuf {
        self.dir.path().join("sweep")
    }

    /// Writes hits + compare's accuracy for one point and run; returns the run's JSON.
    fn run(&self, cfg: &str, pkg: &Package, name: &str, hits: &[Hit], speed: Value) -> Value {
        let h = self.sweep().join("hits").join(cfg);
        std::fs::create_dir_all(&h).unwrap();
        let (hp, ap) = (
            h.join(format!("{name}.csv")),
            h.join(format!("{name}.json")),
        );
        write_hits(&hp, hits).unwrap();
        let (acc, _) = compare(
            &pkg.image.by_prim(),
            &pkg.rays,
            hits,
            &pkg.reference,
            Tolerances::default(),
        )
        .unwrap();
        write_json(&ap, &acc).unwrap();
        let acc: Value = serde_json::from_str(&std::fs::read_to_string(&ap).unwrap()).unwrap();
        json!({"run": name, "scene": "cornell-box", "rays": pkg.manifest.ray_kind, "hard_case": null,
               "package": pkg.dir, "hits": hp, "rays_total": hits.len(), "error_flagged": acc["error_flagged"],
               "node_tests_per_ray": 10.0, "tri_tests_per_ray": 4.0, "accuracy": acc, "speed": speed})
    }

    fn point(&self, cfg: &str, runs: Vec<Value>, lut: u64, leaks: usize) -> Value {
        let parts: Vec<&str> = cfg.split('-').collect();
        let (e, m) = parts[0][1..].split_once('m').unwrap();
        let mut runs = runs;
        runs.push(json!({"run": "hard-sphere", "scene": "sphere", "rays": "file", "hard_case": "sphere", "package": "unused",
                         "hits": "unused", "rays_total": 40, "error_flagged": 0, "node_tests_per_ray": 3.0, "tri_tests_per_ray": 2.0,
                         "hard": {"case": "sphere", "rays": 40, "leaks": leaks, "false_hits": 0, "wrong_prims": 0, "flagged": 0, "ok": leaks == 0},
                         "speed": null}));
        let p = json!({"config": {"name": cfg, "float": parts[0], "exp_bits": e.parse::<u32>().unwrap(), "man_bits": m.parse::<u32>().unwrap(),
                                  "rounding": if parts[1] == "rne" { "rne" } else { "conservative" },
                                  "triangle": if parts[2] == "wt" { "watertight" } else { "moller" }},
                       "latency": {"ray_prep": 11, "box": 9, "triangle": 24}, "runs": runs});
        let a = json!({"config": cfg, "lut": lut, "ff": lut / 2, "dsp": 40, "bram36": 4.5, "instances_zc706": 218_600 / lut,
                       "units": {"RayPrep": {"lut": 1, "ff": 2, "dsp": 3}}, "seconds": 1.0});
        for (sub, v) in [("points", &p), ("area", &a)] {
            std::fs::create_dir_all(self.sweep().join(sub)).unwrap();
            write_json(&self.sweep().join(sub).join(format!("{cfg}.json")), v).unwrap();
        }
        p
    }
}

/// Index of a primary ray that hits well inside its triangle.
fn well_inside(p: &Package, skip: &[usize]) -> usize {
    let tris = p.image.by_prim();
    (0..p.rays.len())
        .find(|&i| {
            !skip.contains(&(i / SPP as usize))
                && p.reference[i].hit
                && eval64(&tris[p.reference[i].prim as usize], &p.rays[i])
                    .is_some_and(|h| h.margin > 0.1)
        })
        .expect("a well-conditioned hit")
}

fn speed(rpc: f64) -> Value {
    json!({"rays": 1024, "cycles": 1000, "rays_per_cycle": rpc, "bound_rays_per_cycle": 1.0, "share_of_bound": rpc, "golden_mismatches": 0})
}

fn bridge(args: &[&str]) -> std::process::Output {
    Command::new(bridge_bin()).args(args).output().unwrap()
}

#[test]
fn synthetic_sweep_gives_the_expected_numbers_fronts_sentence_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    let prim = package(&dir.path().join("pkg-primary"), RaySpec::Primary);
    let ao = package(&dir.path().join("pkg-ao"), RaySpec::Ao);
    let f = Fixture { dir, prim, ao };
    let (p, a) = (&f.prim, &f.ao);

    // Primary changes: a well-conditioned hit missed (pixel A); both rays of
    // pixel B on another prim (one pixel); one t off by 1e-3 (no pixel).
    let mut ph = p.reference.clone();
    let ra = well_inside(p, &[]);
    ph[ra] = Hit {
        hit: false,
        t: f32::INFINITY,
        u: 0.0,
        v: 0.0,
        prim: -1,
        error: 0,
    };
    let pix_b = (0..64)
        .find(|&q| q != ra / 2 && p.reference[2 * q].hit && p.reference[2 * q + 1].hit)
        .unwrap();
    for i in [2 * pix_b, 2 * pix_b + 1] {
        ph[i].prim = (ph[i].prim + 5) % 32;
    }
    let rc = well_inside(p, &[ra / 2, pix_b]);
    ph[rc].t *= 1.001;
    ph[rc].error = 2; // flagged by the "hardware"
                      // AO changes: one pixel loses an occluded ray; in another, a hit and a
                      // miss trade places (same count, same pixel value).
    let map = read_ao_pixels(&a.dir.join(AO_PIXELS_FILE), 64).unwrap();
    let mut ah = a.reference.clone();
    let flip = (0..ah.len()).find(|&i| ah[i].hit).unwrap();
    ah[flip] = Hit {
        hit: false,
        t: f32::INFINITY,
        u: 0.0,
        v: 0.0,
        prim: -1,
        error: 0,
    };
    let (s1, s2) = (0..ah.len())
        .flat_map(|i| (i + 1..ah.len()).map(move |j| (i, j)))
        .find(|&(i, j)| {
            map[i] == map[j] && map[i] != map[flip] && a.reference[i].hit && !a.reference[j].hit
        })
        .expect("a pixel with occluded and open AO rays");
    ah.swap(s1, s2);

    let pts = [
        (
            "e8m23-rne-wt",
            &p.reference,
            &a.reference,
            10_000,
            Some(0.5),
            0,
        ),
        ("e8m12-rne-wt", &ph, &ah, 7_000, Some(0.6), 0),
        (
            "e8m23-cons-wt",
            &p.reference,
            &a.reference,
            11_000,
            Some(0.45),
            0,
        ),
        ("e6m9-cons-wt", &p.reference, &a.reference, 6_600, None, 2),
    ];
    let mut e8m12_errors = 0;
    for (cfg, hp, ha, lut, rpc, leaks) in pts {
        let name = if cfg.contains("cons") {
            cfg.replace("cons", "conservative")
        } else {
            cfg.to_string()
        };
        let sp = rpc.map_or(Value::Null, speed);
        let runs = vec![
            f.run(&name, p, "cornell-primary", hp, sp.clone()),
            f.run(&name, a, "cornell-ao", ha, Value::Null),
        ];
        if cfg == "e8m12-rne-wt" {
            e8m12_errors = ["false_miss", "false_hit", "wrong_prim"]
                .iter()
                .map(|c| runs[0]["accuracy"]["counts"][c].as_u64().unwrap_or(0))
                .sum::<u64>()
                + ["false_miss", "false_hit", "wrong_prim"]
                    .iter()
                    .map(|c| runs[1]["accuracy"]["counts"][c].as_u64().unwrap_or(0))
                    .sum::<u64>();
        }
        f.point(&name, runs, lut, leaks);
    }
    assert!(
        e8m12_errors >= 1,
        "the missed well-conditioned hit must be an error"
    );
    std::fs::create_dir_all(f.sweep().join("hard-ref")).unwrap();
    for (r, leaks) in [("embree", 3), ("robust", 1), ("double", 0)] {
        write_json(&f.sweep().join("hard-ref").join(format!("sphere-{r}.json")),
                   &json!({"case": "sphere", "rays": 40, "leaks": leaks, "false_hits": 0, "wrong_prims": 0, "flagged": 0, "ok": leaks == 0})).unwrap();
    }

    let out = f.dir.path().join("docs");
    let (j, md, plots) = (out.join("r.json"), out.join("r.md"), out.join("r"));
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(
        out.join("r-notes.md"),
        "Hand-written: the e6m9 leaks are expected.\n",
    )
    .unwrap();
    let o = bridge(&[
        "sweep-report",
        "--sweep",
        f.sweep().to_str().unwrap(),
        "--json",
        j.to_str().unwrap(),
        "--md",
        md.to_str().unwrap(),
        "--plots",
        plots.to_str().unwrap(),
        "--runtime-note",
        "42 s on 2 cores",
    ]);
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
    let o = bridge(&[
        "sweep-report",
        "--sweep",
        f.sweep().to_str().unwrap(),
        "--json",
        j2.to_str().unwrap(),
        "--md",
        out.join("again.md").to_str().unwrap(),
        "--plots",
        p2.to_str().unwrap(),
    ]);
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
        let o = bridge(&[
            "sweep-report",
            "--sweep",
            sweep.to_str().unwrap(),
            "--json",
            j.to_str().unwrap(),
            "--md",
            md.to_str().unwrap(),
            "--plots",
            plots.to_str().unwrap(),
        ]);
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
