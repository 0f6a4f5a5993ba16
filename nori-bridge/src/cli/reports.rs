//! Reports of whole runs: `regress-report` (a `make regress SIM=cpp` run)
//! and `sweep-report` (the precision sweep). Both hand their arguments to
//! the library's report module unchanged.

use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(super) struct RegressReportArgs {
    #[arg(long)]
    out: PathBuf,
    /// regress.json written by rtaccel.regress.CppSimPrepare.
    #[arg(long)]
    prepared: PathBuf,
    #[arg(long)]
    rays: usize,
    #[arg(long)]
    golden_mismatches: usize,
    #[arg(long)]
    wall_seconds: f64,
}

impl RegressReportArgs {
    pub(super) fn run(self) -> Result<()> {
        crate::regress::report::run(&crate::regress::report::ReportArgs {
            out: self.out,
            prepared: self.prepared,
            rays: self.rays,
            golden_mismatches: self.golden_mismatches,
            wall_seconds: self.wall_seconds,
        })
    }
}

#[derive(clap::Args)]
pub(super) struct SweepReportArgs {
    /// Directory with points/, area/, hard-ref/ (see src/sweep/input.rs).
    #[arg(long, default_value = "build/sweep")]
    sweep: PathBuf,
    #[arg(long, default_value = "docs/reports/speed-vs-error.json")]
    json: PathBuf,
    #[arg(long, default_value = "docs/reports/speed-vs-error.md")]
    md: PathBuf,
    /// Directory for the PNG plots.
    #[arg(long, default_value = "docs/reports/speed-vs-error")]
    plots: PathBuf,
    /// Format of the reference points (pixels and ratios are against it).
    #[arg(long, default_value = "e8m23")]
    baseline_format: String,
    /// How long the sweep took, quoted in the document's header.
    #[arg(long)]
    runtime_note: Option<String>,
}

impl SweepReportArgs {
    pub(super) fn run(self) -> Result<()> {
        crate::sweep::report::run(&crate::sweep::report::ReportOpts {
            sweep: self.sweep,
            json: self.json,
            md: self.md,
            plots: self.plots,
            baseline_format: self.baseline_format,
            runtime_note: self.runtime_note,
        })
    }
}
