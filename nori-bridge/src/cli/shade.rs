//! The shading stages: `shade-rays` (the secondary rays of a camera
//! package's hits) and `shade` (the shaded images from a hit source).

use crate::package::Package;
use crate::shade::{Integrator, ShadeOpts};
use anyhow::Result;
use std::path::PathBuf;

/// What both shading stages take: the camera package, its hits from the
/// hit source, and the options the secondary rays are generated with.
#[derive(clap::Args)]
pub(super) struct ShadeInput {
    #[arg(long)]
    package: PathBuf,
    #[arg(long)]
    hits: PathBuf,
    #[arg(long, value_enum)]
    integrator: Integrator,
    /// AO rays, or light samples, per camera hit.
    #[arg(long, default_value_t = 4)]
    samples: u32,
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

impl ShadeInput {
    fn opts(&self) -> ShadeOpts {
        ShadeOpts {
            integrator: self.integrator,
            samples: self.samples,
            seed: self.seed,
        }
    }
}

#[derive(clap::Args)]
pub(super) struct ShadeRaysArgs {
    #[command(flatten)]
    input: ShadeInput,
    #[arg(long)]
    out: PathBuf,
}

impl ShadeRaysArgs {
    pub(super) fn run(self) -> Result<()> {
        let (input, out) = (self.input, self.out);
        let pkg = Package::load(&input.package)?;
        let scene =
            crate::scene::xml::load_scene(std::path::Path::new(&pkg.manifest.source_scene))?;
        let got = crate::ray::csv_io::read_hits(&input.hits)?;
        let sec = crate::shade::secondary(&scene, &pkg, &got, &input.opts())?;
        crate::shade::write_rays_txt(&out, &sec)?;
        println!("{}: {} secondary rays", out.display(), sec.len());
        Ok(())
    }
}

#[derive(clap::Args)]
pub(super) struct ShadeArgs {
    #[command(flatten)]
    input: ShadeInput,
    /// The package compiled from shade-rays' rays.txt (ao, direct).
    #[arg(long)]
    secondary: Option<PathBuf>,
    /// The hit source's answers for the secondary package's rays.
    #[arg(long)]
    secondary_hits: Option<PathBuf>,
    /// Label of the hit source in the montage (e.g. "golden", "RTL").
    #[arg(long, default_value = "accelerator")]
    source: String,
    #[arg(long)]
    out_dir: PathBuf,
}

impl ShadeArgs {
    pub(super) fn run(self) -> Result<()> {
        crate::shade::run::shade(&crate::shade::run::ShadeArgs {
            opts: self.input.opts(),
            package: self.input.package,
            hits: self.input.hits,
            secondary: self.secondary,
            secondary_hits: self.secondary_hits,
            source: self.source,
            out_dir: self.out_dir,
        })
    }
}
