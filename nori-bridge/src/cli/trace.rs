//! Rays traced here rather than in the hardware: `trace` (the f32 layout
//! walk of the package's own image) and `bench` (Embree's throughput).

use crate::package::Package;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(super) struct TraceArgs {
    #[arg(long)]
    package: PathBuf,
    #[arg(long)]
    out: PathBuf,
}

impl TraceArgs {
    pub(super) fn run(self) -> Result<()> {
        let pkg = Package::load(&self.package)?;
        let (hits, stats) = crate::memory::mt_walk::trace_all(&pkg.image, &pkg.rays);
        crate::ray::csv_io::write_hits(&self.out, &hits)?;
        println!(
            "{}: {} rays, largest stack {} (bvhDepth {})",
            self.out.display(),
            hits.len(),
            stats.max_stack,
            pkg.image.bvh_depth
        );
        Ok(())
    }
}

#[derive(clap::Args)]
pub(super) struct BenchArgs {
    #[arg(long)]
    package: PathBuf,
    /// Trace at least this many rays (the set is repeated).
    #[arg(long, default_value_t = 2_000_000)]
    min_rays: usize,
    #[arg(long)]
    robust: bool,
}

impl BenchArgs {
    pub(super) fn run(self) -> Result<()> {
        crate::reference::bench::bench(&Package::load(&self.package)?, self.min_rays, self.robust)
    }
}
