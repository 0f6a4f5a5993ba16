//! The scene package: one directory per compiled scene and ray set.
//! image.bin, rays.csv, reference.csv, scene.json, package.json.

pub mod compile;
pub mod needs;

use crate::memory::Image;
use crate::ray::csv_io::{read_hits, read_rays};
use crate::ray::{Hit, Ray};
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub const FILES: [&str; 5] = [
    "image.bin",
    "rays.csv",
    "reference.csv",
    "scene.json",
    "package.json",
];

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct Manifest {
    pub format_version: u32,
    pub tool: String,
    pub source_scene: String,
    /// primary | shadow | ao | random | file
    pub ray_kind: String,
    pub ray_file: Option<String>,
    pub seed: u64,
    pub spp: u32,
    /// Camera size for primary rays (ray = (y*width + x)*spp + s).
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// AO packages: the camera image the AO rays shade; ao_pixels.csv
    /// gives each AO ray's pixel (y * width + x). Absent for other kinds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ao_image: Option<ImageSize>,
    pub counts: Counts,
    pub build: BuildParams,
    pub reference: ReferenceParams,
    pub files: Vec<FileEntry>,
    /// Wall-clock seconds per step (informative; varies run to run).
    pub timings_seconds: Timings,
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    pub width: u32,
    pub height: u32,
}

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct Counts {
    pub triangles: usize,
    pub nodes: usize,
    pub rays: usize,
    pub reference_hits: usize,
}

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct BuildParams {
    pub builder: String,
    /// Node layout (`--bvh`): "nori", "2", "4" or "8".
    pub layout: String,
    pub max_leaf_size: u32,
    pub traversal_cost: f32,
    pub intersection_cost: f32,
}

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct ReferenceParams {
    /// embree | double
    pub kind: String,
    pub robust: bool,
}

#[derive(Serialize, Deserialize, Clone, Debug)]
pub struct FileEntry {
    pub name: String,
    /// Size in bytes; null for package.json itself.
    pub bytes: Option<u64>,
}

#[derive(Serialize, Deserialize, Clone, Debug, Default)]
pub struct Timings {
    pub load: f64,
    pub bvh_build: f64,
    /// Writing image.bin and scene.json.
    pub image_write: f64,
    /// Building Embree's own scene for the reference.
    pub reference_scene: f64,
    pub rays: f64,
    pub reference: f64,
    pub total: f64,
}

impl Manifest {
    /// package.json of a package directory, format version checked.
    pub fn load(dir: &Path) -> Result<Manifest> {
        let mpath = dir.join("package.json");
        let text = std::fs::read_to_string(&mpath).with_context(|| {
            format!(
                "{}: cannot read (is {} a package made by `nori-bridge compile`?)",
                mpath.display(),
                dir.display()
            )
        })?;
        // The version first: an older manifest lacks fields this one has.
        #[derive(Deserialize)]
        struct Version {
            format_version: u32,
        }
        let v: Version = serde_json::from_str(&text)
            .with_context(|| format!("{}: bad manifest", mpath.display()))?;
        if v.format_version != crate::memory::VERSION {
            anyhow::bail!(
                "{}: format version {}, this tool reads {}: compile the package again",
                mpath.display(),
                v.format_version,
                crate::memory::VERSION
            );
        }
        serde_json::from_str(&text).with_context(|| format!("{}: bad manifest", mpath.display()))
    }
}

/// A package read back for compare/render/trace.
pub struct Package {
    pub dir: PathBuf,
    pub manifest: Manifest,
    pub image: Image,
    pub rays: Vec<Ray>,
    pub reference: Vec<Hit>,
}

impl Package {
    pub fn load(dir: &Path) -> Result<Package> {
        let manifest = Manifest::load(dir)?;
        let image = Image::read(&dir.join("image.bin"))?;
        let rays = read_rays(&dir.join("rays.csv"))?;
        let reference = read_hits(&dir.join("reference.csv"))?;
        if reference.len() != rays.len() {
            anyhow::bail!(
                "{}: {} reference rows for {} rays",
                dir.display(),
                reference.len(),
                rays.len()
            );
        }
        Ok(Package {
            dir: dir.to_path_buf(),
            manifest,
            image,
            rays,
            reference,
        })
    }
}
