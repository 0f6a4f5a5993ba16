//! What the precision sweep leaves under its directory (default
//! build/sweep), read strictly: a missing file or field is an error naming
//! the file and the field, never a skipped point.
//!
//! - points/<cfg>.json: one hardware configuration and its runs;
//! - area/<cfg>.json: Yosys xc7 area of the whole accelerator;
//! - hard-ref/<case>-<embree|robust|double>.json: hard-score of the
//!   software references on each hard case.
//!
//! Package and hits paths inside a point are used as written: relative
//! ones are relative to the directory sweep-report runs in (the repo root
//! under make).

use anyhow::{bail, Context, Result};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
pub struct PointConfig {
    pub name: String,
    pub float: String,
    pub exp_bits: u32,
    pub man_bits: u32,
    /// rne | conservative
    pub rounding: String,
    /// moller | watertight
    pub triangle: String,
    /// Node layout (nori-bridge compile --bvh): nori, 2, 4, 8, 4q, 8q. Points
    /// before the layout dimension ran on nori nodes.
    #[serde(default = "nori_layout")]
    pub layout: String,
    /// Box-lane and triangle formats; empty in points before the split: `float` for both.
    #[serde(default)]
    pub box_float: String,
    #[serde(default)]
    pub tri_float: String,
    /// How child boxes are tested: fp32 (box lanes), or grid (a 4q/8q node's children in its grid).
    #[serde(default = "fp32_box_test")]
    pub box_test: String,
}

fn nori_layout() -> String {
    "nori".into()
}

fn fp32_box_test() -> String {
    "fp32".into()
}

/// Exponent + mantissa bits of an `eXmY` name (0 if it is not one).
pub fn format_bits(f: &str) -> u32 {
    f.strip_prefix('e')
        .and_then(|r| r.split_once('m'))
        .and_then(|(e, m)| Some(e.parse::<u32>().ok()? + m.parse::<u32>().ok()?))
        .unwrap_or(0)
}

impl PointConfig {
    /// Rounding and triangle test (and the grid box test, a variant of its own): points of one variant
    /// differ in layout and formats.
    pub fn variant(&self) -> String {
        if self.grid() {
            format!("{}/{}/grid", self.rounding, self.triangle)
        } else {
            format!("{}/{}", self.rounding, self.triangle)
        }
    }
    pub fn grid(&self) -> bool {
        self.box_test == "grid"
    }
    /// The layout as the report names it: "4q", or "4q grid" for grid box tests.
    pub fn layout_label(&self) -> String {
        if self.grid() {
            format!("{} grid", self.layout)
        } else {
            self.layout.clone()
        }
    }
    pub fn box_fmt(&self) -> &str {
        if self.box_float.is_empty() {
            &self.float
        } else {
            &self.box_float
        }
    }
    pub fn tri_fmt(&self) -> &str {
        if self.tri_float.is_empty() {
            &self.float
        } else {
            &self.tri_float
        }
    }
    /// The unquantized layout of the same width: the FP32 layout a point is measured against ("4q" -> "4").
    pub fn plain_layout(&self) -> &str {
        self.layout.strip_suffix('q').unwrap_or(&self.layout)
    }
}

#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq)]
pub struct Latency {
    pub ray_prep: u32,
    #[serde(rename = "box")]
    pub box_test: u32,
    pub triangle: u32,
}

/// The fields of compare's accuracy.json that the report uses.
#[derive(Deserialize, Clone, Debug)]
pub struct AccuracyIn {
    pub rays: usize,
    /// Count per class; compare writes only the classes that occurred.
    pub counts: BTreeMap<String, usize>,
    pub max_t_rel_agree: f64,
}

impl AccuracyIn {
    pub fn count(&self, class: &str) -> usize {
        self.counts.get(class).copied().unwrap_or(0)
    }
}

/// hard-score's verdict on one hard case (the fields the table shows).
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
pub struct HardIn {
    pub case: String,
    pub rays: usize,
    pub leaks: usize,
    pub false_hits: usize,
    pub wrong_prims: usize,
    pub flagged: usize,
}

#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq)]
pub struct SpeedIn {
    pub rays: usize,
    pub cycles: u64,
    pub rays_per_cycle: f64,
    pub bound_rays_per_cycle: f64,
    pub share_of_bound: f64,
    pub golden_mismatches: usize,
}

#[derive(Deserialize, Clone, Debug)]
pub struct RunIn {
    pub run: String,
    pub scene: String,
    /// primary | ao | file
    pub rays: String,
    pub hard_case: Option<String>,
    pub package: PathBuf,
    pub hits: PathBuf,
    pub rays_total: usize,
    pub error_flagged: usize,
    pub node_tests_per_ray: f64,
    pub tri_tests_per_ray: f64,
    /// Node bytes read per ray (node fetches x node record size), from the golden walk over every ray.
    #[serde(default)]
    pub node_bytes_per_ray: Option<f64>,
    #[serde(default)]
    pub accuracy: Option<AccuracyIn>,
    #[serde(default)]
    pub hard: Option<HardIn>,
    pub speed: Option<SpeedIn>,
}

#[derive(Deserialize, Clone, Debug)]
pub struct PointIn {
    pub config: PointConfig,
    pub latency: Latency,
    pub runs: Vec<RunIn>,
    /// Wall seconds of the job that measured the point (absent in old files).
    #[serde(default)]
    pub seconds: f64,
}

#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Default)]
pub struct Cells {
    pub lut: u64,
    pub ff: u64,
    pub dsp: u64,
}

/// Yosys xc7 area of a whole accelerator and the ZC706 instances it allows.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
pub struct Area {
    pub lut: u64,
    pub ff: u64,
    pub dsp: u64,
    pub bram36: f64,
    pub instances_zc706: u64,
    pub units: BTreeMap<String, Cells>,
    /// All box lanes together (K lanes of one BoxLane unit); absent in old files.
    #[serde(default)]
    pub box_lanes: Option<Cells>,
}

#[derive(Deserialize, Clone, Debug)]
pub struct AreaIn {
    pub config: String,
    /// The cost itself, which the report passes on unchanged.
    #[serde(flatten)]
    pub cost: Area,
    /// Wall seconds of the area job (small when its units came from the Yosys cache; absent in old files).
    #[serde(default)]
    pub seconds: f64,
}

/// Everything one sweep directory holds, points sorted by name.
pub struct SweepIn {
    pub dir: PathBuf,
    pub points: Vec<(PointIn, AreaIn)>,
    /// hard case -> reference name (embree | robust | double) -> verdict.
    pub hard_refs: BTreeMap<String, BTreeMap<String, HardIn>>,
}

pub const HARD_REFS: [&str; 3] = ["embree", "robust", "double"];

fn read_json<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: not the expected JSON", path.display()))
}

/// The JSON files of a directory, sorted by name (error if there are none).
fn json_files(dir: &Path, what: &str) -> Result<Vec<PathBuf>> {
    let rd =
        std::fs::read_dir(dir).with_context(|| format!("{}: cannot list {what}", dir.display()))?;
    let mut v: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    v.sort();
    if v.is_empty() {
        bail!("{}: no {what} (*.json) found", dir.display());
    }
    Ok(v)
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

impl RunIn {
    pub fn is_hard(&self) -> bool {
        self.hard_case.is_some()
    }

    /// Checks the fields a run of its kind must have.
    fn check(&self, file: &Path) -> Result<()> {
        let at = |msg: String| anyhow::anyhow!("{}: run '{}': {msg}", file.display(), self.run);
        match (&self.hard_case, &self.accuracy, &self.hard) {
            (None, None, _) => Err(at(
                "field `accuracy` is missing (a non-hard run needs compare's accuracy JSON)".into(),
            )),
            (Some(c), _, None) => Err(at(format!(
                "field `hard` is missing (hard case '{c}' needs hard-score's JSON)"
            ))),
            (Some(c), _, Some(h)) if &h.case != c => Err(at(format!(
                "`hard.case` is '{}' but `hard_case` is '{c}'",
                h.case
            ))),
            (None, Some(a), _) if a.rays != self.rays_total => Err(at(format!(
                "`accuracy.rays` {} differs from `rays_total` {}",
                a.rays, self.rays_total
            ))),
            _ => Ok(()),
        }
    }
}

pub fn load(dir: &Path) -> Result<SweepIn> {
    let mut points = Vec::new();
    // A point may be measured by two jobs: `<cfg>.json` (image runs, speed) and
    // `<cfg>.hard.json` (the hard cases); their runs are merged here.
    for f in json_files(&dir.join("points"), "sweep points")? {
        if stem(&f).ends_with(".hard") {
            continue;
        }
        let mut p: PointIn = read_json(&f)?;
        let hard_file = dir.join("points").join(format!("{}.hard.json", stem(&f)));
        if hard_file.exists() {
            let h: PointIn = read_json(&hard_file)?;
            if h.config.name != p.config.name {
                bail!(
                    "{}: `config.name` is '{}', expected '{}'",
                    hard_file.display(),
                    h.config.name,
                    p.config.name
                );
            }
            p.runs.extend(h.runs);
            p.seconds += h.seconds;
        }
        if p.config.name != stem(&f) {
            bail!(
                "{}: `config.name` is '{}', expected the file name '{}'",
                f.display(),
                p.config.name,
                stem(&f)
            );
        }
        if p.runs.iter().all(|r| r.is_hard()) {
            bail!("{}: `runs` has no regression run (only hard cases or none): its error rate would read as zero", f.display());
        }
        for r in &p.runs {
            r.check(&f)?;
        }
        let af = dir.join("area").join(format!("{}.json", p.config.name));
        let a: AreaIn = read_json(&af).with_context(|| format!("area of point {}", f.display()))?;
        if a.config != p.config.name {
            bail!(
                "{}: `config` is '{}', expected '{}'",
                af.display(),
                a.config,
                p.config.name
            );
        }
        points.push((p, a));
    }
    let mut hard_refs: BTreeMap<String, BTreeMap<String, HardIn>> = BTreeMap::new();
    for case in points
        .iter()
        .flat_map(|(p, _)| p.runs.iter().filter_map(|r| r.hard_case.clone()))
    {
        if hard_refs.contains_key(&case) {
            continue;
        }
        let mut refs = BTreeMap::new();
        for r in HARD_REFS {
            let f = dir.join("hard-ref").join(format!("{case}-{r}.json"));
            let h: HardIn =
                read_json(&f).with_context(|| format!("reference '{r}' on hard case '{case}'"))?;
            if h.case != case {
                bail!("{}: `case` is '{}', expected '{case}'", f.display(), h.case);
            }
            refs.insert(r.to_string(), h);
        }
        hard_refs.insert(case, refs);
    }
    Ok(SweepIn {
        dir: dir.to_path_buf(),
        points,
        hard_refs,
    })
}

#[cfg(test)]
mod tests {
    use super::PointConfig;

    fn config(extra: &str) -> PointConfig {
        serde_json::from_str(&format!(
            r#"{{"name": "4q-e8m23-e8m23-cons-wt", "float": "e8m23", "exp_bits": 8, "man_bits": 23,
                "rounding": "conservative", "triangle": "watertight", "layout": "4q"{extra}}}"#
        ))
        .unwrap()
    }

    #[test]
    fn a_point_without_a_box_test_tests_fp32_boxes() {
        let c = config("");
        assert_eq!(c.box_test, "fp32");
        assert_eq!(c.variant(), "conservative/watertight");
        assert_eq!(c.layout_label(), "4q");
    }

    #[test]
    fn a_grid_point_is_a_variant_of_its_own_measured_against_fp32_on_plain_nodes() {
        let c = config(r#", "box_test": "grid""#);
        assert!(c.grid());
        assert_eq!(c.variant(), "conservative/watertight/grid");
        assert_eq!(c.layout_label(), "4q grid");
        assert_eq!(c.plain_layout(), "4");
    }
}
