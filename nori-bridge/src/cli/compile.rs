//! `compile`: a Nori scene and a ray set into a package directory.

use crate::bvh::Layout;
use crate::package::compile::{compile, CompileOpts, RaySpec};
use crate::scene::transform::parse_vec3;
use anyhow::{anyhow, Result};
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum RefKind {
    Embree,
    Double,
}

#[derive(clap::Args)]
pub(super) struct CompileArgs {
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
}

impl CompileArgs {
    pub(super) fn run(self) -> Result<()> {
        if self.spp == 0 {
            return Err(anyhow!("--spp must be at least 1"));
        }
        let light = self
            .light
            .map(|l| parse_vec3(&l).map_err(|e| anyhow!("--light: {e}")))
            .transpose()?;
        let o = CompileOpts {
            scene: self.scene,
            out: self.out,
            rays: RaySpec::parse(&self.rays),
            spp: self.spp,
            seed: self.seed,
            max_leaf_size: self.max_leaf_size,
            layout: self.bvh,
            robust: self.robust,
            double_reference: self.reference == RefKind::Double,
            width: self.width,
            height: self.height,
            count: self.count,
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
        Ok(())
    }
}
