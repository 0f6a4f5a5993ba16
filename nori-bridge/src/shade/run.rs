//! `nori-bridge shade`: both images (hit source and Embree), their
//! difference, the montage and shade.json.

use super::montage::{diff, montage};
use super::{radiance, secondary, to_rgb8, Integrator, ShadeOpts};
use crate::package::Package;
use crate::ray::csv_io::read_hits;
use crate::ray::Hit;
use crate::scene::xml::load_scene;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

pub struct ShadeArgs {
    pub package: PathBuf,
    pub hits: PathBuf,
    pub opts: ShadeOpts,
    pub secondary: Option<PathBuf>,
    pub secondary_hits: Option<PathBuf>,
    pub source: String,
    pub out_dir: PathBuf,
}

pub fn shade(a: &ShadeArgs) -> Result<()> {
    let pkg = Package::load(&a.package)?;
    let scene = load_scene(Path::new(&pkg.manifest.source_scene))
        .with_context(|| format!("{}: its source scene", a.package.display()))?;
    let (w, h) = (
        pkg.manifest.width.unwrap_or(0),
        pkg.manifest.height.unwrap_or(0),
    );
    let mine = read_hits(&a.hits)?;
    // The secondary rays come from the hit source's camera hits; Embree
    // answers those same rays (its own camera hits give the normals and
    // emission of its image), so the two images differ only where answers do.
    let sec = secondary(&scene, &pkg, &mine, &a.opts)?;
    let (mine2, theirs2): (Vec<bool>, Vec<bool>) = if sec.is_empty() {
        (Vec::new(), Vec::new())
    } else {
        let (Some(sp), Some(sh)) = (&a.secondary, &a.secondary_hits) else {
            bail!("--integrator {:?} needs --secondary and --secondary-hits (make them with shade-rays)", a.opts.integrator);
        };
        let spkg = Package::load(sp)?;
        if spkg.rays.len() != sec.len() {
            bail!("{}: {} rays, but these hits make {} secondary rays (same --samples and --seed as shade-rays?)", sp.display(), spkg.rays.len(), sec.len());
        }
        let blocked = |v: &[Hit]| v.iter().map(|x| x.hit).collect::<Vec<_>>();
        (blocked(&read_hits(sh)?), blocked(&spkg.reference))
    };
    let gamma = if a.opts.integrator == Integrator::Ao {
        1.0
    } else {
        2.2
    };
    let img_a = to_rgb8(
        &radiance(&scene, &pkg, &mine, &sec, &mine2, &a.opts)?,
        w,
        h,
        gamma,
    );
    let img_e = to_rgb8(
        &radiance(&scene, &pkg, &pkg.reference, &sec, &theirs2, &a.opts)?,
        w,
        h,
        gamma,
    );
    let (img_d, differ) = diff(&img_a, &img_e);
    let prim_differ = mine
        .iter()
        .zip(&pkg.reference)
        .filter(|(x, y)| x.hit != y.hit || (x.hit && x.prim != y.prim))
        .count();
    let sec_differ = mine2.iter().zip(&theirs2).filter(|(x, y)| x != y).count();
    let name = match a.opts.integrator {
        Integrator::Normals => "normals",
        Integrator::Ao => "ao",
        Integrator::Direct => "direct",
    };
    let m = montage(
        &[(&format!("{} ({name})", a.source), &img_a), ("Embree", &img_e), (&format!("difference: {differ} px"), &img_d)],
        &format!("{w}x{h}, {} camera rays, {} secondary; answers differing: {prim_differ} camera, {sec_differ} secondary", mine.len(), sec.len()),
    )?;
    std::fs::create_dir_all(&a.out_dir)
        .with_context(|| format!("{}: cannot create", a.out_dir.display()))?;
    for (f, img) in [
        ("accel.png", &img_a),
        ("embree.png", &img_e),
        ("diff.png", &img_d),
        ("montage.png", &m),
    ] {
        let p = a.out_dir.join(f);
        img.save(&p)
            .with_context(|| format!("{}: cannot write PNG", p.display()))?;
    }
    let js = serde_json::json!({
        "integrator": name, "source": a.source, "width": w, "height": h, "samples": a.opts.samples, "seed": a.opts.seed,
        "camera_rays": mine.len(), "secondary_rays": sec.len(),
        "pixels_differing": differ, "camera_answers_differing": prim_differ, "secondary_answers_differing": sec_differ,
    });
    std::fs::write(
        a.out_dir.join("shade.json"),
        serde_json::to_string_pretty(&js)?,
    )?;
    println!("shade: {} -> {}/montage.png ({differ} pixels differ from Embree's image; answers differing: {prim_differ} camera, {sec_differ} secondary)",
        name, a.out_dir.display());
    Ok(())
}
