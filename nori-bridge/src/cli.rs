//! Command line (clap derive). Errors go up to main as `Error: {:#}`.

use crate::bvh::Layout;
use crate::compare::judge::Tolerances;
use crate::compare::render::Shade;
use crate::compare::{compare, summary};
use crate::package::compile::{compile, write_json, CompileOpts, RaySpec};
use crate::package::Package;
use crate::scene::transform::parse_vec3;
use crate::shade::{Integrator, ShadeOpts};
use anyhow::{anyhow, Result};
use clap::{Parser, Subcommand};
use std::path::PathBuf;

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

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RefKind {
    Embree,
    Double,
}

/// What both shading stages take: the camera package, its hits from the
/// hit source, and the options the secondary rays are generated with.
#[derive(clap::Args)]
struct ShadeInput {
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

#[derive(Subcommand)]
enum Cmd {
    /// Compile a Nori XML scene and a ray set into a package directory.
    Compile {
        scene: PathBuf,
        #[arg(long)]
        out: PathBuf,
        /// primary | shadow | ao | random | path to a rays.txt
        #[arg(long, default_value = "primary")]
        rays: String,
        /// Samples per pixel (primary), AO rays per primary hit (ao).
        #[arg(long, default_value_t = 1)]
        spp: u32,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long, default_value_t = 4)]
        max_leaf_size: u32,
        /// Node layout of image.bin: nori (32-byte binary nodes) or 2, 4, 8
        /// (wide nodes of K 32-byte child slots).
        #[arg(long, default_value = "nori")]
        bvh: Layout,
        /// Embree's RTC_SCENE_FLAG_ROBUST for the reference.
        #[arg(long)]
        robust: bool,
        #[arg(long, value_enum, default_value = "embree")]
        reference: RefKind,
        /// Override the camera's width / height.
        #[arg(long)]
        width: Option<u32>,
        #[arg(long)]
        height: Option<u32>,
        /// Number of rays for --rays random.
        #[arg(long, default_value_t = 65536)]
        count: usize,
        /// Point light "x,y,z" for --rays shadow (default: the scene's point emitter).
        #[arg(long)]
        light: Option<String>,
    },
    /// Compare a hits.csv with the package's reference; write accuracy JSON.
    Compare {
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
    },
    /// PNGs (hits, reference, diff) for a camera-ray package.
    Render {
        #[arg(long)]
        package: PathBuf,
        #[arg(long)]
        hits: PathBuf,
        #[arg(long)]
        out_dir: PathBuf,
        #[arg(long, value_enum, default_value = "normal")]
        shade: Shade,
    },
    /// Secondary rays (AO, or shadow rays to the lights) of a camera
    /// package's hits, as a rays.txt for `compile --rays` / `make regress RAYS=`.
    ShadeRays {
        #[command(flatten)]
        input: ShadeInput,
        #[arg(long)]
        out: PathBuf,
    },
    /// Shaded PNGs of a camera package from a hit source (and, for ao and
    /// direct, the secondary package made from `shade-rays`' file with its
    /// hits): accel.png, embree.png (the same rays answered by the
    /// package's Embree reference), diff.png, montage.png, shade.json.
    Shade {
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
    },
    /// Trace the package's rays through its own memory image with the
    /// Möller–Trumbore layout walk (f32; checks the layouts against Embree; not
    /// the hardware's arithmetic: nori-accel's golden-trace is) and write a hits.csv.
    Trace {
        #[arg(long)]
        package: PathBuf,
        #[arg(long)]
        out: PathBuf,
    },
    /// The report of a `make regress SIM=cpp` run (scripts/regress-cpp.sh): stats.json,
    /// report.json and report.md from rtaccel-sim's output, the golden check's count,
    /// accuracy.json and the cold step's regress.json; prints the table.
    RegressReport {
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
    },
    /// Measure Embree reference throughput (Mrays/s, 2 threads) on a package's rays.
    Bench {
        #[arg(long)]
        package: PathBuf,
        /// Trace at least this many rays (the set is repeated).
        #[arg(long, default_value_t = 2_000_000)]
        min_rays: usize,
        #[arg(long)]
        robust: bool,
    },
    /// Precision sweep report: per-point JSON under --sweep in;
    /// speed-vs-error JSON, markdown and PNG plots out.
    SweepReport {
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
    },
    /// Count the pixels that differ between two PNGs of the same size
    /// (e.g. make render RTL=1's image against the golden walk's); prints the
    /// count, exits 1 if any differ, --out writes the difference image.
    DiffPng {
        a: PathBuf,
        b: PathBuf,
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write the hard-case suite (scenes, rays.txt, expect.csv; deterministic).
    HardCases {
        #[arg(long, default_value = "scenes/hard")]
        out: PathBuf,
    },
    /// Score a hits.csv (or a package's reference.csv) against a hard case's expect.csv.
    HardScore {
        #[arg(long)]
        package: PathBuf,
        #[arg(long)]
        hits: PathBuf,
        #[arg(long)]
        expect: PathBuf,
        #[arg(long)]
        out: PathBuf,
    },
}

pub fn run() -> Result<()> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build_global()
        .ok();
    match Cli::parse().cmd {
        Cmd::Compile {
            scene,
            out,
            rays,
            spp,
            seed,
            max_leaf_size,
            bvh,
            robust,
            reference,
            width,
            height,
            count,
            light,
        } => {
            if spp == 0 {
                return Err(anyhow!("--spp must be at least 1"));
            }
            let light = light
                .map(|l| parse_vec3(&l).map_err(|e| anyhow!("--light: {e}")))
                .transpose()?;
            let o = CompileOpts {
                scene,
                out,
                rays: RaySpec::parse(&rays),
                spp,
                seed,
                max_leaf_size,
                layout: bvh,
                robust,
                double_reference: reference == RefKind::Double,
                width,
                height,
                count,
                light,
            };
            let m = compile(&o)?;
            println!(
                "{}: {} triangles, {} nodes, {} rays ({} hit), build {:.3} s, total {:.3} s",
                o.out.display(),
                m.counts.triangles,
                m.counts.nodes,
                m.counts.rays,
                m.counts.reference_hits,
                m.timings_seconds.bvh_build,
                m.timings_seconds.total
            );
        }
        Cmd::Compare {
            package,
            hits,
            out,
            precision_bits,
            slack,
        } => {
            let pkg = Package::load(&package)?;
            let got = crate::ray::csv_io::read_hits(&hits)?;
            let tol = Tolerances {
                precision_bits,
                slack,
            };
            let (acc, _) = compare(&pkg.image.by_prim(), &pkg.rays, &got, &pkg.reference, tol)?;
            write_json(&out, &acc)?;
            println!("{}", summary(&acc));
        }
        Cmd::Render {
            package,
            hits,
            out_dir,
            shade,
        } => {
            let pkg = Package::load(&package)?;
            let got = crate::ray::csv_io::read_hits(&hits)?;
            let (_, classes) = compare(
                &pkg.image.by_prim(),
                &pkg.rays,
                &got,
                &pkg.reference,
                Tolerances::default(),
            )?;
            crate::compare::render::render(&pkg, &got, &classes, shade, &out_dir)?;
            println!("{}: hits.png reference.png diff.png", out_dir.display());
        }
        Cmd::ShadeRays { input, out } => {
            let pkg = Package::load(&input.package)?;
            let scene =
                crate::scene::xml::load_scene(std::path::Path::new(&pkg.manifest.source_scene))?;
            let got = crate::ray::csv_io::read_hits(&input.hits)?;
            let sec = crate::shade::secondary(&scene, &pkg, &got, &input.opts())?;
            crate::shade::write_rays_txt(&out, &sec)?;
            println!("{}: {} secondary rays", out.display(), sec.len());
        }
        Cmd::Shade {
            input,
            secondary,
            secondary_hits,
            source,
            out_dir,
        } => crate::shade::run::shade(&crate::shade::run::ShadeArgs {
            opts: input.opts(),
            package: input.package,
            hits: input.hits,
            secondary,
            secondary_hits,
            source,
            out_dir,
        })?,
        Cmd::Trace { package, out } => {
            let pkg = Package::load(&package)?;
            let (hits, stats) = crate::memory::mt_walk::trace_all(&pkg.image, &pkg.rays);
            crate::ray::csv_io::write_hits(&out, &hits)?;
            println!(
                "{}: {} rays, largest stack {} (bvhDepth {})",
                out.display(),
                hits.len(),
                stats.max_stack,
                pkg.image.bvh_depth
            );
        }
        Cmd::RegressReport {
            out,
            prepared,
            rays,
            golden_mismatches,
            wall_seconds,
        } => crate::regress::report::run(&crate::regress::report::ReportArgs {
            out,
            prepared,
            rays,
            golden_mismatches,
            wall_seconds,
        })?,
        Cmd::SweepReport {
            sweep,
            json,
            md,
            plots,
            baseline_format,
            runtime_note,
        } => crate::sweep::report::run(&crate::sweep::report::ReportOpts {
            sweep,
            json,
            md,
            plots,
            baseline_format,
            runtime_note,
        })?,
        Cmd::Bench {
            package,
            min_rays,
            robust,
        } => crate::reference::bench::bench(&Package::load(&package)?, min_rays, robust)?,
        Cmd::DiffPng { a, b, out } => {
            let load = |p: &PathBuf| {
                image::open(p)
                    .map(|i| i.to_rgb8())
                    .map_err(|e| anyhow!("{}: {e}", p.display()))
            };
            let (ia, ib) = (load(&a)?, load(&b)?);
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
            if let Some(o) = &out {
                d.save(o).map_err(|e| anyhow!("{}: {e}", o.display()))?;
            }
            println!(
                "{} pixels of {} differ between {} and {}",
                n,
                ia.width() * ia.height(),
                a.display(),
                b.display()
            );
            if n > 0 {
                std::process::exit(1);
            }
        }
        Cmd::HardCases { out } => {
            let n = crate::hard::cases::generate(&out)?;
            println!(
                "{}: {n} hard cases, seed {}",
                out.display(),
                crate::hard::cases::SEED
            );
        }
        Cmd::HardScore {
            package,
            hits,
            expect,
            out,
        } => {
            let s = crate::hard::score::hard_score(&package, &hits, &expect)?;
            write_json(&out, &s)?;
            println!(
                "{}: {} rays, {} leaks, {} false hits, {} wrong prims, {} flagged, {} ok",
                s.case, s.rays, s.leaks, s.false_hits, s.wrong_prims, s.flagged, s.ok
            );
        }
    }
    Ok(())
}
