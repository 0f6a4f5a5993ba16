//! `nori-bridge regress-report`: the report of a `make regress SIM=cpp` run
//! made with no JVM (scripts/regress-cpp.sh). From what rtaccel-sim wrote
//! (sim.json, sim-memory.json, hits.bin), the golden check's count, the
//! Embree judgement (accuracy.json) and the configuration the cold step
//! recorded (regress.json, rtaccel.regress.CppSimPrepare), it writes
//! stats.json, report.json and report.md with the fields and figures of the
//! Scala path (rtaccel.regress.Report and CppSim.result), and prints the
//! same console table.

use anyhow::{bail, Context, Result};
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};

/// What one run's report is made from.
pub struct ReportArgs {
    /// The run's directory: sim.json, sim-memory.json, hits.bin, accuracy.json in; the reports out.
    pub out: PathBuf,
    /// regress.json of the cold step.
    pub prepared: PathBuf,
    pub rays: usize,
    pub golden_mismatches: usize,
    /// From the simulator's start to the golden check's end.
    pub wall_seconds: f64,
}

fn read_json(p: &Path) -> Result<Value> {
    let s = std::fs::read_to_string(p).with_context(|| format!("{}: cannot read", p.display()))?;
    serde_json::from_str(&s).with_context(|| format!("{}: not JSON", p.display()))
}

fn num(v: &Value, what: &str) -> Result<f64> {
    v.as_f64()
        .with_context(|| format!("{what}: not a number ({v})"))
}

/// Hit records whose error bits are set (hits.bin: status word at +4, errors in bits 8..).
fn error_rays(hits_bin: &Path, rays: usize) -> Result<usize> {
    let b =
        std::fs::read(hits_bin).with_context(|| format!("{}: cannot read", hits_bin.display()))?;
    if b.len() != 32 * rays {
        bail!(
            "{}: {} bytes, expected {rays} hit records of 32 bytes",
            hits_bin.display(),
            b.len()
        );
    }
    Ok(b.chunks(32)
        .filter(|r| (u32::from_le_bytes(r[4..8].try_into().unwrap()) >> 8) & 0xff != 0)
        .count())
}

/// One port's statistics as the Scala MemStats writes them: the system has one AXI port, so requests are the
/// hardware's fetch counters and dramBytes the bursts that fell in the port's array; cache fields are 0.
fn port(name: &str, cycles: f64, record_bytes: f64, fetches: f64, dram_bytes: f64) -> Value {
    json!({"name": name, "cycles": cycles, "recordBytes": record_bytes, "requests": fetches, "responses": fetches,
      "portBytes": fetches * record_bytes, "dramBytes": dram_bytes, "requestHits": 0, "lineHits": 0, "primaryMisses": 0,
      "mergedMisses": 0, "hitRate": 0.0, "stallCycles": 0, "meanOutstanding": 0.0, "maxOutstanding": 0, "meanMshrs": 0.0})
}

/// stats.json (Report.stats with CppSim.result's run).
pub fn stats(a: &ReportArgs) -> Result<Map<String, Value>> {
    let prep = read_json(&a.prepared)?;
    let sim = read_json(&a.out.join("sim.json"))?;
    let mem = read_json(&a.out.join("sim-memory.json"))?;
    if let Some(v) = mem["violations"].as_array().filter(|v| !v.is_empty()) {
        bail!(
            "cppsim: AXI protocol violations by rtaccel_system:\n  {}",
            v.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join("\n  ")
        );
    }
    let counters = sim["counters"]
        .as_object()
        .context("sim.json: no counters")?;
    let c = |k: &str| -> Result<f64> {
        num(
            counters.get(k).unwrap_or(&Value::Null),
            &format!("sim.json counters.{k}"),
        )
    };
    let cycles = c("cycles")?;
    let rays = a.rays as f64;
    let region = |k: &str| mem["regions"][k]["readBytes"].as_f64().unwrap_or(0.0);
    let dram = &mem["dram"];
    let (dram_bytes, bytes_per_cycle) = (
        num(&dram["bytes"], "sim-memory.json dram.bytes")?,
        num(&dram["bytesPerCycle"], "dram.bytesPerCycle")?,
    );
    let node = port(
        "node",
        cycles,
        num(&prep["nodeBytes"], "regress.json nodeBytes")?,
        c("nodeFetches")?,
        region("nodes"),
    );
    let tri = port(
        "triangle",
        cycles,
        num(&prep["triBytes"], "regress.json triBytes")?,
        c("triFetches")?,
        region("triangles"),
    );
    // Report.Bound: each resource's capacity per cycle over the run's use of it per ray; the smallest bounds.
    let per_ray = |x: f64| (x / rays.max(1.0)).max(1e-9);
    let terms = [
        ("boxLanes", 1.0 / per_ray(c("boxTests")?)),
        ("triangleLanes", 1.0 / per_ray(c("triTests")?)),
        (
            "control",
            1.0 / per_ray((c("decisions")? - c("leafReturns")?).max(c("leafReturns")?)),
        ),
        ("dram", bytes_per_cycle / per_ray(dram_bytes)),
    ];
    let (limited_by, bound) = terms
        .iter()
        .fold(terms[0], |m, t| if t.1 < m.1 { *t } else { m });
    let mut simulation = sim["simulation"]
        .as_object()
        .cloned()
        .context("sim.json: no simulation")?;
    simulation.insert("wallSeconds".into(), json!(a.wall_seconds));
    simulation.insert("harness".into(), json!("cpp"));
    let per = |k: &str| -> Result<f64> { Ok(c(k)? / rays.max(1.0)) };
    let busy_share = if cycles == 0.0 {
        0.0
    } else {
        dram_bytes / (bytes_per_cycle * cycles)
    };
    let out = json!({
        "rays": a.rays,
        "cycles": cycles,
        "raysPerCycle": rays / cycles,
        "boundRaysPerCycle": bound,
        "boundLimitedBy": limited_by,
        "boundTerms": terms.iter().map(|(k, v)| (k.to_string(), json!(v))).collect::<Map<_, _>>(),
        "efficiency": (rays / cycles) / bound,
        "dramBytesPerRay": dram_bytes / rays.max(1.0),
        "nodeTestsPerRay": per("boxTests")?,
        "nodeBytesPerRay": node["portBytes"].as_f64().unwrap_or(0.0) / rays.max(1.0),
        "triangleTestsPerRay": per("triTests")?,
        "decisionsPerRay": per("decisions")?,
        "meanRaysInFlight": c("inFlightSum")? / cycles,
        "goldenMismatches": a.golden_mismatches,
        "errorRays": error_rays(&a.out.join("hits.bin"), a.rays)?,
        "memory": {"kind": prep["memoryKind"], "node": node, "triangle": tri, "dramBytes": dram_bytes,
          "dram": {"bytes": dram_bytes, "bytesPerCycle": bytes_per_cycle, "burstBytes": dram["burstBytes"], "busyShare": busy_share,
            "busyCycles": dram["busyCycles"]}},
        "counters": counters.clone(),
        "simulation": simulation,
        "configuration": prep["configuration"],
    });
    Ok(out.as_object().cloned().unwrap())
}

const CLASSES: [(&str, &str); 8] = [
    ("false_miss", "falseMiss"),
    ("false_hit", "falseHit"),
    ("wrong_prim", "wrongPrim"),
    ("t_error", "tOutOfTolerance"),
    ("tie", "ties"),
    ("edge", "edgeCases"),
    ("reference_wrong", "referenceWrong"),
    ("agree", "agree"),
];

/// report.json: stats plus the mismatch classes and nori-bridge's accuracy (Report.combine).
pub fn combine(stats: &Map<String, Value>, accuracy: &Value) -> Map<String, Value> {
    let mut m: Map<String, Value> = CLASSES
        .iter()
        .map(|(k, name)| {
            (
                name.to_string(),
                accuracy["counts"].get(*k).cloned().unwrap_or(json!(0)),
            )
        })
        .collect();
    m.insert(
        "total".into(),
        accuracy.get("mismatches").cloned().unwrap_or(json!(0)),
    );
    let mut out = stats.clone();
    out.insert("mismatches".into(), Value::Object(m));
    out.insert("accuracy".into(), accuracy.clone());
    out
}

/// Report.n: whole numbers with thousands separators, others with `digits` decimals.
fn n(v: &Value, digits: usize) -> String {
    match v.as_f64() {
        Some(x) if x == x.round() && x.abs() < 1e15 => {
            let s = (x.abs() as u64).to_string();
            let mut g = String::new();
            for (i, ch) in s.chars().enumerate() {
                if i > 0 && (s.len() - i) % 3 == 0 {
                    g.push(',');
                }
                g.push(ch);
            }
            if x < 0.0 {
                format!("-{g}")
            } else {
                g
            }
        }
        Some(x) => format!("{x:.digits$}"),
        None => v
            .as_str()
            .map(str::to_string)
            .unwrap_or_else(|| v.to_string()),
    }
}

/// The console table (Report.table).
pub fn table(r: &Map<String, Value>) -> String {
    let m = &r["mismatches"];
    let rays = r["rays"].as_f64().unwrap_or(0.0);
    let dram = {
        let v = &r["dramBytesPerRay"];
        let node = r["memory"]["node"]["dramBytes"].as_f64().unwrap_or(0.0) / rays;
        let tri = r["memory"]["triangle"]["dramBytes"].as_f64().unwrap_or(0.0) / rays;
        let other = v.as_f64().unwrap_or(0.0) - node - tri;
        format!(
            "{} (node {}, triangle {}{}; DRAM busy {})",
            n(v, 1),
            n(&json!(node), 1),
            n(&json!(tri), 1),
            if other > 0.05 {
                format!(", rays and hits {}", n(&json!(other), 1))
            } else {
                String::new()
            },
            n(&r["memory"]["dram"]["busyShare"], 2)
        )
    };
    // In Report.Bound's order (serde_json's maps are sorted).
    let terms = ["boxLanes", "triangleLanes", "control", "dram"]
        .iter()
        .filter_map(|k| r["boundTerms"].get(*k).map(|v| format!("{k} {}", n(v, 4))))
        .collect::<Vec<_>>()
        .join(", ");
    let rows = [
        ("rays", n(&r["rays"], 4)),
        ("cycles", n(&r["cycles"], 4)),
        ("rays/cycle", format!("{} (bound {}, {} of it; limited by {})", n(&r["raysPerCycle"], 4), n(&r["boundRaysPerCycle"], 4),
            n(&r["efficiency"], 2), n(&r["boundLimitedBy"], 0))),
        ("bound terms (rays/cycle)", terms),
        ("DRAM bytes per ray", dram),
        ("node / triangle tests per ray", format!("{} / {}", n(&r["nodeTestsPerRay"], 2), n(&r["triangleTestsPerRay"], 2))),
        ("node bytes per ray", n(&r["nodeBytesPerRay"], 1)),
        ("mean rays in flight", n(&r["meanRaysInFlight"], 1)),
        ("golden mismatches", n(&r["goldenMismatches"], 4)),
        ("vs Embree", format!("{} mismatches (false miss {}, false hit {}, wrong prim {}, t {}); ties {}, edge {}, reference wrong {}",
            n(&m["total"], 4), n(&m["falseMiss"], 4), n(&m["falseHit"], 4), n(&m["wrongPrim"], 4), n(&m["tOutOfTolerance"], 4),
            n(&m["ties"], 4), n(&m["edgeCases"], 4), n(&m["referenceWrong"], 4))),
        ("rays with errors", n(&r["errorRays"], 4)),
        ("simulator", format!("{} cycles/s, {} s", n(&r["simulation"]["cyclesPerSecond"], 0), n(&r["simulation"]["wallSeconds"], 1))),
    ];
    rows.iter()
        .map(|(k, v)| format!("  {k:<30} {v}"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// report.md (Report.markdown).
pub fn markdown(r: &Map<String, Value>) -> String {
    let mut lines = vec![
        "# Regression report".to_string(),
        String::new(),
        "Generated by `make regress`; do not edit.".into(),
        String::new(),
        "```".into(),
        table(r),
        "```".into(),
        String::new(),
        "| configuration | value |".into(),
        "| --- | --- |".into(),
    ];
    // In Report.configuration's order (serde_json's maps are sorted).
    const KEYS: [&str; 12] = [
        "datapath",
        "float",
        "triangle",
        "rounding",
        "numRayIds",
        "stackDepth",
        "nodeIndexBits",
        "triIndexBits",
        "maxLeafSize",
        "memory",
        "fabricMhz",
        "seed",
    ];
    lines.extend(KEYS.iter().filter_map(|k| {
        r["configuration"]
            .get(*k)
            .map(|v| format!("| {k} | {} |", n(v, 4)))
    }));
    lines.push(String::new());
    lines.join("\n")
}

/// Writes stats.json, report.json and report.md into `a.out` and prints the table.
pub fn run(a: &ReportArgs) -> Result<()> {
    let stats = stats(a)?;
    let write = |name: &str, text: String| -> Result<()> {
        let p = a.out.join(name);
        std::fs::write(&p, text).with_context(|| format!("{}: cannot write", p.display()))
    };
    write("stats.json", serde_json::to_string_pretty(&stats)?)?;
    let report = combine(&stats, &read_json(&a.out.join("accuracy.json"))?);
    write("report.json", serde_json::to_string_pretty(&report)?)?;
    write("report.md", markdown(&report))?;
    println!("{}", table(&report));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_as_report_scala_prints_them() {
        assert_eq!(n(&json!(20491.0), 4), "20,491");
        assert_eq!(n(&json!(4096), 4), "4,096");
        assert_eq!(n(&json!(0.19990234375), 4), "0.1999");
        assert_eq!(n(&json!("dram"), 4), "dram");
    }

    /// A run of 2 rays, one with an error bit: every stats field from the simulator's files, the bound's smallest term.
    #[test]
    fn stats_from_the_simulators_files() {
        let dir = std::env::temp_dir().join(format!("regress-report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let counters = json!({"cycles": 100, "nodeFetches": 10, "triFetches": 4, "boxTests": 10, "triTests": 8, "decisions": 12,
            "leafReturns": 2, "inFlightSum": 150});
        std::fs::write(
            dir.join("sim.json"),
            json!({"counters": counters, "simulation": {"seconds": 0.5, "cyclesPerSecond": 200.0}})
                .to_string(),
        )
        .unwrap();
        std::fs::write(dir.join("sim-memory.json"), json!({"violations": [], "regions": {"nodes": {"readBytes": 640}, "triangles": {"readBytes": 192}},
            "dram": {"bytes": 256, "bytesPerCycle": 64.0, "burstBytes": 64, "busyCycles": 16}}).to_string()).unwrap();
        let mut hits = vec![0u8; 64];
        hits[32 + 4..32 + 8].copy_from_slice(&(1u32 << 8).to_le_bytes());
        std::fs::write(dir.join("hits.bin"), hits).unwrap();
        std::fs::write(dir.join("regress.json"), json!({"nodeBytes": 128, "triBytes": 48, "memoryKind": "ddr", "configuration": {"seed": 1}}).to_string()).unwrap();
        let a = ReportArgs {
            out: dir.clone(),
            prepared: dir.join("regress.json"),
            rays: 2,
            golden_mismatches: 0,
            wall_seconds: 1.0,
        };
        let s = stats(&a).unwrap();
        assert_eq!(s["errorRays"], json!(2 - 1));
        assert_eq!(s["raysPerCycle"], json!(0.02));
        // boxLanes 0.2, triangleLanes 0.25, control 1/5 = 0.2 (box results 10 vs leaf returns 2), dram 64/128: the first smallest.
        assert_eq!(s["boundLimitedBy"], json!("boxLanes"));
        assert_eq!(s["memory"]["node"]["portBytes"], json!(1280.0));
        assert_eq!(s["memory"]["dram"]["busyShare"], json!(256.0 / 6400.0));
        assert_eq!(s["simulation"]["harness"], json!("cpp"));
        let r = combine(&s, &json!({"mismatches": 0, "counts": {"tie": 3}}));
        assert_eq!(r["mismatches"]["ties"], json!(3));
        assert!(table(&r).contains("limited by boxLanes"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
