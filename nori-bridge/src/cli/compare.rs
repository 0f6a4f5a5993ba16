//! Hits against a reference: `compare` (accuracy JSON), `render` (PNGs of
//! the classes) and `diff-png` (two images pixel by pixel).

use crate::compare::judge::Tolerances;
use crate::compare::render::Shade;
use crate::compare::{compare, summary};
use crate::package::compile::write_json;
use crate::package::Package;
use anyhow::{anyhow, Result};
use std::path::PathBuf;

#[derive(clap::Args)]
pub(super) struct CompareArgs {
    #[arg(long)]
    package: PathBuf,
    #[arg(long)]
    hits: PathBuf,
    #[arg(long)]
    out: PathBuf,
    /// Mantissa bits (hidden bit included) of the hardware's arithmetic:
    /// tolerances scale with 2^-bits (24 = f32).
    #[arg(long, default_value_t = Tolerances::default().precision_bits)]
    precision_bits: u32,
    /// Multiplier on the per-hit error bounds (see docs/memory-format.md).
    #[arg(long, default_value_t = Tolerances::default().slack)]
    slack: f64,
}

impl CompareArgs {
    pub(super) fn run(self) -> Result<()> {
        let pkg = Package::load(&self.package)?;
        let got = crate::ray::csv_io::read_hits(&self.hits)?;
        let tol = Tolerances {
            precision_bits: self.precision_bits,
            slack: self.slack,
        };
        let (acc, _) = compare(&pkg.image.by_prim(), &pkg.rays, &got, &pkg.reference, tol)?;
        write_json(&self.out, &acc)?;
        println!("{}", summary(&acc));
        Ok(())
    }
}

#[derive(clap::Args)]
pub(super) struct RenderArgs {
    #[arg(long)]
    package: PathBuf,
    #[arg(long)]
    hits: PathBuf,
    #[arg(long)]
    out_dir: PathBuf,
    #[arg(long, value_enum, default_value = "normal")]
    shade: Shade,
}

impl RenderArgs {
    pub(super) fn run(self) -> Result<()> {
        let pkg = Package::load(&self.package)?;
        let got = crate::ray::csv_io::read_hits(&self.hits)?;
        let (_, classes) = compare(
            &pkg.image.by_prim(),
            &pkg.rays,
            &got,
            &pkg.reference,
            Tolerances::default(),
        )?;
        crate::compare::render::render(&pkg, &got, &classes, self.shade, &self.out_dir)?;
        println!(
            "{}: hits.png reference.png diff.png",
            self.out_dir.display()
        );
        Ok(())
    }
}

#[derive(clap::Args)]
pub(super) struct DiffPngArgs {
    a: PathBuf,
    b: PathBuf,
    #[arg(long)]
    out: Option<PathBuf>,
}

impl DiffPngArgs {
    pub(super) fn run(self) -> Result<()> {
        let (a, b) = (&self.a, &self.b);
        let load = |p: &PathBuf| {
            image::open(p)
                .map(|i| i.to_rgb8())
                .map_err(|e| anyhow!("{}: {e}", p.display()))
        };
        let (ia, ib) = (load(a)?, load(b)?);
        if ia.dimensions() != ib.dimensions() {
            return Err(anyhow!(
                "{} is {:?}, {} is {:?}: not the same size",
                a.display(),
                ia.dimensions(),
                b.display(),
                ib.dimensions()
            ));
        }
        let (d, n) = crate::shade::montage::diff(&ia, &ib);
        if let Some(o) = &self.out {
            d.save(o).map_err(|e| anyhow!("{}: {e}", o.display()))?;
        }
        println!(
            "{} pixels of {} differ between {} and {}",
            n,
            ia.width() * ia.height(),
            a.display(),
            b.display()
        );
        // The count is the answer; the exit code lets make and scripts test it.
        if n > 0 {
            std::process::exit(1);
        }
        Ok(())
    }
}
