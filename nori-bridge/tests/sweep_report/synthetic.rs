//! The synthetic sweep's contents: four points whose numbers the test can
//! derive by hand. e8m12 gets hits with deliberate changes (a missed hit, a
//! pixel on another prim, a t off by 1e-3 and flagged, an AO ray lost and
//! two traded); the others answer exactly the reference, so they differ only
//! in their fake area, speed and hard-case leaks.

use crate::fixture::{Fixture, SPP};
use nori_bridge::compile::write_json;
use nori_bridge::exact::eval64;
use nori_bridge::package::Package;
use nori_bridge::pixels::{read_ao_pixels, AO_PIXELS_FILE};
use nori_bridge::ray::Hit;
use serde_json::{json, Value};

/// Writes every point, its area and the hard-case references under the
/// fixture's sweep directory; returns e8m12's misses, false hits and wrong
/// prims over both runs (the error rate the report must quote).
pub fn write_sweep(f: &Fixture) -> u64 {
    let (p, a) = (&f.prim, &f.ao);

    // Primary changes: a well-conditioned hit missed (pixel A); both rays of
    // pixel B on another prim (one pixel); one t off by 1e-3 (no pixel).
    let mut ph = p.reference.clone();
    let ra = well_inside(p, &[]);
    ph[ra] = Hit::MISS;
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
    ah[flip] = Hit::MISS;
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
    e8m12_errors
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

/// A timed point's fake speed result at `rpc` rays per cycle.
fn speed(rpc: f64) -> Value {
    json!({"rays": 1024, "cycles": 1000, "rays_per_cycle": rpc, "bound_rays_per_cycle": 1.0, "share_of_bound": rpc, "golden_mismatches": 0})
}
