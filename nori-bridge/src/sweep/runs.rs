//! Per-run metrics that need the rays themselves: relative t error against
//! the package's reference and pixels differing from the FP32 baseline's
//! answer to the same package. Counts of errors come from compare's
//! accuracy JSON (input::AccuracyIn); this module reads hits files.

use crate::compare::pixels::{
    ao_pixels_differing, primary_pixels_differing, read_ao_pixels, AO_PIXELS_FILE,
};
use crate::package::Manifest;
use crate::ray::csv_io::read_hits;
use crate::ray::Hit;
use anyhow::{bail, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// How the rays of a package map to image pixels.
pub enum PixelMap {
    /// Camera rays, `spp` per pixel in pixel order.
    Primary { spp: u32 },
    /// AO rays: the pixel of each ray.
    Ao(Vec<u32>),
}

/// What the report needs of a package: its reference and pixel map.
pub struct PackageData {
    pub dir: PathBuf,
    pub manifest: Manifest,
    pub reference: Vec<Hit>,
    /// None for ray sets that are not an image (e.g. a rays.txt).
    pub pixels: Option<(PixelMap, u64)>,
}

impl PackageData {
    pub fn load(dir: &Path) -> Result<PackageData> {
        let manifest = Manifest::load(dir)?;
        let reference = read_hits(&dir.join("reference.csv"))?;
        let n = reference.len() as u64;
        let pj = dir.join("package.json");
        let pixels = match manifest.ray_kind.as_str() {
            "primary" => {
                let (Some(w), Some(h)) = (manifest.width, manifest.height) else {
                    bail!(
                        "{}: primary rays but `width`/`height` missing",
                        pj.display()
                    );
                };
                let count = w as u64 * h as u64;
                if count * manifest.spp.max(1) as u64 != n {
                    bail!(
                        "{}: {w}x{h} pixels x {} spp != {n} reference rows",
                        pj.display(),
                        manifest.spp
                    );
                }
                Some((PixelMap::Primary { spp: manifest.spp }, count))
            }
            "ao" => {
                let Some(size) = manifest.ao_image else {
                    bail!("{}: AO rays but field `ao_image` missing (package from an older nori-bridge: compile it again)", pj.display());
                };
                let count = size.width as u64 * size.height as u64;
                let map = read_ao_pixels(&dir.join(AO_PIXELS_FILE), count)?;
                if map.len() as u64 != n {
                    bail!(
                        "{}: {} rows for {n} rays",
                        dir.join(AO_PIXELS_FILE).display(),
                        map.len()
                    );
                }
                Some((PixelMap::Ao(map), count))
            }
            _ => None,
        };
        Ok(PackageData {
            dir: dir.to_path_buf(),
            manifest,
            reference,
            pixels,
        })
    }

    /// A hits file for this package, its length checked.
    pub fn read_answer(&self, hits: &Path) -> Result<Vec<Hit>> {
        let got = read_hits(hits)?;
        if got.len() != self.reference.len() {
            bail!(
                "{}: {} rows, but package {} has {} rays",
                hits.display(),
                got.len(),
                self.dir.display(),
                self.reference.len()
            );
        }
        Ok(got)
    }
}

/// Relative t difference |a - b| / max(|a|, |b|) over rays where the answer
/// and the reference hit the same prim (shadow rays have prim -1 in the
/// reference and so never count).
#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct TRel {
    pub count: usize,
    pub sum: f64,
    pub max: f64,
}

impl TRel {
    pub fn of(got: &[Hit], want: &[Hit]) -> TRel {
        let mut r = TRel::default();
        for (g, w) in got.iter().zip(want) {
            if g.hit && w.hit && w.prim >= 0 && g.prim == w.prim {
                let e = crate::compare::rel(g.t, w.t);
                r.count += 1;
                r.sum += e;
                r.max = r.max.max(e);
            }
        }
        r
    }

    pub fn add(&mut self, o: &TRel) {
        self.count += o.count;
        self.sum += o.sum;
        self.max = self.max.max(o.max);
    }

    pub fn mean(&self) -> Option<f64> {
        (self.count > 0).then(|| self.sum / self.count as f64)
    }
}

/// Pixels differing between an answer and the baseline's answer.
#[derive(Serialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelDiff {
    pub differing: u64,
    pub total: u64,
}

impl PixelDiff {
    pub fn of(map: &PixelMap, total: u64, got: &[Hit], baseline: &[Hit]) -> PixelDiff {
        let differing = match map {
            PixelMap::Primary { spp } => primary_pixels_differing(got, baseline, *spp),
            PixelMap::Ao(of_ray) => ao_pixels_differing(got, baseline, of_ray),
        } as u64;
        PixelDiff { differing, total }
    }

    pub fn add(&mut self, o: &PixelDiff) {
        self.differing += o.differing;
        self.total += o.total;
    }

    pub fn share(&self) -> Option<f64> {
        (self.total > 0).then(|| self.differing as f64 / self.total as f64)
    }
}
