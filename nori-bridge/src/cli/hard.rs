//! The hard-case suite: `hard-cases` writes it, `hard-score` scores hits
//! against one case's expected answers.

use crate::package::compile::write_json;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(super) struct HardCasesArgs {
    #[arg(long, default_value = "scenes/hard")]
    out: PathBuf,
}

impl HardCasesArgs {
    pub(super) fn run(self) -> Result<()> {
        let n = crate::hard::cases::generate(&self.out)?;
        println!(
            "{}: {n} hard cases, seed {}",
            self.out.display(),
            crate::hard::cases::SEED
        );
        Ok(())
    }
}

#[derive(clap::Args)]
pub(super) struct HardScoreArgs {
    #[arg(long)]
    package: PathBuf,
    #[arg(long)]
    hits: PathBuf,
    #[arg(long)]
    expect: PathBuf,
    #[arg(long)]
    out: PathBuf,
}

impl HardScoreArgs {
    pub(super) fn run(self) -> Result<()> {
        let s = crate::hard::score::hard_score(&self.package, &self.hits, &self.expect)?;
        write_json(&self.out, &s)?;
        println!(
            "{}: {} rays, {} leaks, {} false hits, {} wrong prims, {} flagged, {} ok",
            s.case, s.rays, s.leaks, s.false_hits, s.wrong_prims, s.flagged, s.ok
        );
        Ok(())
    }
}
