//! `nori-bridge compile`: scene -> package.

use crate::bvh::build::build_layout;
use crate::bvh::Layout;
use crate::geom::{len64, sub64, to64, D3};
use crate::memory::Image;
use crate::package::*;
use crate::ray::csv_io::{write_hits, write_rays};
use crate::ray::{generate, txt, Hit, Ray};
use crate::reference::device::Device;
use crate::reference::double::trace_double;
use crate::reference::embree::EmbreeScene;
use crate::scene::{xml, Scene};
use anyhow::{bail, Context, Result};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

#[derive(Clone, Debug, PartialEq)]
pub enum RaySpec {
    Primary,
    Shadow,
    Ao,
    Random,
    File(PathBuf),
}

impl RaySpec {
    pub fn parse(s: &str) -> RaySpec {
        match s {
            "primary" => RaySpec::Primary,
            "shadow" => RaySpec::Shadow,
            "ao" => RaySpec::Ao,
            "random" => RaySpec::Random,
            f => RaySpec::File(PathBuf::from(f)),
        }
    }
    fn name(&self) -> &'static str {
        match self {
            RaySpec::Primary => "primary",
            RaySpec::Shadow => "shadow",
            RaySpec::Ao => "ao",
            RaySpec::Random => "random",
            RaySpec::File(_) => "file",
        }
    }
}

#[derive(Clone, Debug)]
pub struct CompileOpts {
    pub scene: PathBuf,
    pub out: PathBuf,
    pub rays: RaySpec,
    pub spp: u32,
    pub seed: u64,
    pub max_leaf_size: u32,
    /// Node layout of image.bin (`--bvh`).
    pub layout: Layout,
    pub robust: bool,
    pub double_reference: bool,
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub count: usize,
    pub light: Option<D3>,
}

pub fn compile(o: &CompileOpts) -> Result<Manifest> {
    let t0 = Instant::now();
    let mut tm = Timings::default();
    let mut scene = xml::load_scene(&o.scene)?;
    for w in &scene.warnings {
        eprintln!("{w}");
    }
    if let Some(cam) = scene.camera.as_mut() {
        cam.width = o.width.unwrap_or(cam.width);
        cam.height = o.height.unwrap_or(cam.height);
        if cam.width == 0 || cam.height == 0 {
            bail!("camera size {}x{} must be positive", cam.width, cam.height);
        }
    }
    tm.load = t0.elapsed().as_secs_f64();
    let device = Arc::new(Device::new(2)?);
    let t = Instant::now();
    let bvh = build_layout(&device, &scene.tris, o.max_leaf_size, o.layout)?;
    tm.bvh_build = t.elapsed().as_secs_f64();
    let t = Instant::now();
    std::fs::create_dir_all(&o.out)
        .with_context(|| format!("{}: cannot create package directory", o.out.display()))?;
    let image = Image::from_bvh(&bvh, &scene.tris);
    image.write(&o.out.join("image.bin"))?;
    let needs = needs::compute(&scene.tris, &bvh);
    write_json(&o.out.join("scene.json"), &needs)?;
    tm.image_write = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let embree = EmbreeScene::new(device.clone(), &scene.tris, o.robust)?;
    tm.reference_scene = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let (rays, ao_pixels) = make_rays(o, &scene, &embree)?;
    tm.rays = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let reference = with_progress("reference", &rays, |chunk| {
        if o.double_reference {
            trace_double(&scene.tris, chunk)
        } else {
            Ok(embree.trace(chunk))
        }
    })?;
    tm.reference = t.elapsed().as_secs_f64();
    write_rays(&o.out.join("rays.csv"), &rays)?;
    write_hits(&o.out.join("reference.csv"), &reference)?;
    if let Some(p) = &ao_pixels {
        crate::compare::pixels::write_ao_pixels(
            &o.out.join(crate::compare::pixels::AO_PIXELS_FILE),
            p,
        )?;
    }
    tm.total = t0.elapsed().as_secs_f64();

    let cam = scene.camera.as_ref().filter(|_| o.rays == RaySpec::Primary);
    let mut m = Manifest {
        format_version: crate::memory::VERSION,
        tool: format!("nori-bridge {}", env!("CARGO_PKG_VERSION")),
        source_scene: o.scene.display().to_string(),
        ray_kind: o.rays.name().into(),
        ray_file: match &o.rays {
            RaySpec::File(f) => Some(f.display().to_string()),
            _ => None,
        },
        seed: o.seed,
        spp: o.spp,
        width: cam.map(|c| c.width),
        height: cam.map(|c| c.height),
        ao_image: scene
            .camera
            .as_ref()
            .filter(|_| ao_pixels.is_some())
            .map(|c| ImageSize {
                width: c.width,
                height: c.height,
            }),
        counts: Counts {
            triangles: scene.tris.len(),
            nodes: bvh.node_count(),
            rays: rays.len(),
            reference_hits: reference.iter().filter(|h| h.hit).count(),
        },
        build: BuildParams {
            builder: format!(
                "Embree 3 rtcBuildBVH, binned SAH, MEDIUM quality, branching {}",
                o.layout.branching()
            ),
            layout: o.layout.name().into(),
            max_leaf_size: o.max_leaf_size,
            traversal_cost: 1.0,
            intersection_cost: 1.0,
        },
        reference: ReferenceParams {
            kind: if o.double_reference {
                "double"
            } else {
                "embree"
            }
            .into(),
            robust: o.robust,
        },
        files: Vec::new(),
        timings_seconds: tm,
    };
    let extra = ao_pixels
        .as_ref()
        .map(|_| crate::compare::pixels::AO_PIXELS_FILE);
    for name in FILES
        .iter()
        .filter(|n| **n != "package.json")
        .chain(extra.iter())
    {
        let bytes = std::fs::metadata(o.out.join(name))?.len();
        m.files.push(FileEntry {
            name: name.to_string(),
            bytes: Some(bytes),
        });
    }
    m.files.push(FileEntry {
        name: "package.json".into(),
        bytes: None,
    });
    write_json(&o.out.join("package.json"), &m)?;
    Ok(m)
}

/// The rays, and for AO rays the pixel of each (see compare/pixels.rs).
fn make_rays(
    o: &CompileOpts,
    scene: &Scene,
    embree: &EmbreeScene,
) -> Result<(Vec<Ray>, Option<Vec<u32>>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed);
    let bounds = scene.bounds();
    let primary = |rng: &mut ChaCha8Rng| -> Result<(Vec<Ray>, Vec<Hit>)> {
        let cam = scene.camera.as_ref().with_context(|| {
            format!(
                "{}: --rays {} needs a <camera>",
                o.scene.display(),
                o.rays.name()
            )
        })?;
        let rays = generate::primary(cam, o.spp, rng);
        let hits = embree.trace(&rays);
        Ok((rays, hits))
    };
    Ok(match &o.rays {
        RaySpec::Primary => (primary(&mut rng)?.0, None),
        RaySpec::Shadow => {
            let light = o.light.or(scene.point_light).with_context(|| format!(
                "{}: --rays shadow needs a point light: add <emitter type=\"point\"> with <point name=\"position\"> or pass --light x,y,z", o.scene.display()))?;
            let (r, h) = primary(&mut rng)?;
            (generate::shadow(&scene.tris, &r, &h, light), None)
        }
        RaySpec::Ao => {
            let (r, h) = primary(&mut rng)?;
            let diag = len64(sub64(to64(bounds.max), to64(bounds.min)));
            let rays = generate::ambient_occlusion(&scene.tris, &r, &h, o.spp, diag, &mut rng);
            (
                rays,
                Some(crate::compare::pixels::ao_pixels(&h, o.spp, o.spp)),
            )
        }
        RaySpec::Random => (
            generate::random(&scene.tris, &bounds, o.count, &mut rng),
            None,
        ),
        RaySpec::File(f) => (txt::read_rays_txt(f)?, None),
    })
}

/// Trace in chunks so the progress line (crate::progress) can advance.
fn with_progress(
    what: &'static str,
    rays: &[Ray],
    f: impl Fn(&[Ray]) -> Result<Vec<Hit>>,
) -> Result<Vec<Hit>> {
    let mut pb = crate::progress::bar(rays.len() as u64, what);
    let mut out = Vec::with_capacity(rays.len());
    for chunk in rays.chunks(1 << 15) {
        out.extend(f(chunk)?);
        pb.inc(chunk.len() as u64);
    }
    pb.finish_and_clear();
    Ok(out)
}

pub fn write_json<T: serde::Serialize>(path: &std::path::Path, v: &T) -> Result<()> {
    let s = serde_json::to_string_pretty(v)? + "\n";
    std::fs::write(path, s).with_context(|| format!("{}: cannot write", path.display()))
}
