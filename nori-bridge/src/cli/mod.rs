//! Command line (clap derive). Errors go up to main as `Error: {:#}`.
//!
//! This file is the list of subcommands: their order and doc comments here
//! are the help text (a subcommand's argument struct carries no doc comment
//! of its own, so its description is written in one place). Each
//! subcommand's arguments and what it does live in the file of its group.

mod compare;
mod compile;
mod hard;
mod reports;
mod shade;
mod trace;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "nori-bridge",
    version,
    about = "Nori scenes to rtaccel memory images, rays and Embree reference hits; hits back to reports and images"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Compile a Nori XML scene and a ray set into a package directory.
    Compile(compile::CompileArgs),
    /// Compare a hits.csv with the package's reference; write accuracy JSON.
    Compare(compare::CompareArgs),
    /// PNGs (hits, reference, diff) for a camera-ray package.
    Render(compare::RenderArgs),
    /// Secondary rays (AO, or shadow rays to the lights) of a camera
    /// package's hits, as a rays.txt for `compile --rays` / `make regress RAYS=`.
    ShadeRays(shade::ShadeRaysArgs),
    /// Shaded PNGs of a camera package from a hit source (and, for ao and
    /// direct, the secondary package made from `shade-rays`' file with its
    /// hits): accel.png, embree.png (the same rays answered by the
    /// package's Embree reference), diff.png, montage.png, shade.json.
    Shade(shade::ShadeArgs),
    /// Trace the package's rays through its own memory image with the
    /// Möller–Trumbore layout walk (f32; checks the layouts against Embree; not
    /// the hardware's arithmetic: nori-accel's golden-trace is) and write a hits.csv.
    Trace(trace::TraceArgs),
    /// The report of a `make regress SIM=cpp` run (scripts/regress-cpp.sh): stats.json,
    /// report.json and report.md from rtaccel-sim's output, the golden check's count,
    /// accuracy.json and the cold step's regress.json; prints the table.
    RegressReport(reports::RegressReportArgs),
    /// Measure Embree reference throughput (Mrays/s, 2 threads) on a package's rays.
    Bench(trace::BenchArgs),
    /// Precision sweep report: per-point JSON under --sweep in;
    /// speed-vs-error JSON, markdown and PNG plots out.
    SweepReport(reports::SweepReportArgs),
    /// Count the pixels that differ between two PNGs of the same size
    /// (e.g. make render RTL=1's image against the golden walk's); prints the
    /// count, exits 1 if any differ, --out writes the difference image.
    DiffPng(compare::DiffPngArgs),
    /// Write the hard-case suite (scenes, rays.txt, expect.csv; deterministic).
    HardCases(hard::HardCasesArgs),
    /// Score a hits.csv (or a package's reference.csv) against a hard case's expect.csv.
    HardScore(hard::HardScoreArgs),
}

pub fn run() -> Result<()> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build_global()
        .ok();
    match Cli::parse().cmd {
        Cmd::Compile(a) => a.run(),
        Cmd::Compare(a) => a.run(),
        Cmd::Render(a) => a.run(),
        Cmd::ShadeRays(a) => a.run(),
        Cmd::Shade(a) => a.run(),
        Cmd::Trace(a) => a.run(),
        Cmd::RegressReport(a) => a.run(),
        Cmd::Bench(a) => a.run(),
        Cmd::SweepReport(a) => a.run(),
        Cmd::DiffPng(a) => a.run(),
        Cmd::HardCases(a) => a.run(),
        Cmd::HardScore(a) => a.run(),
    }
}
