//! The quantized layouts 4q and 8q (docs/memory-format.md, "Quantized wide
//! node"): for every node of every shipped scene, the stored box, decoded
//! as the hardware decodes it (one FP32 add per plane), contains the exact
//! box of the triangles below the slot, and the decode rounds nothing; the
//! bytes read back to the same nodes; and the f32 walk of a quantized image
//! gives, ray by ray, the hits of the same-K FP32 image (only the tie rule
//! of tests/wide_trace.rs may separate them).

mod common;
use common::*;
use nori_bridge::bvh::quant::{self, QuantNode};
use nori_bridge::bvh::{Layout, Slot};
use nori_bridge::geom::Aabb;
use nori_bridge::image_bin::Image;
use nori_bridge::mt_walk;

const PAIRS: [(Layout, Layout); 2] = [
    (Layout::Wide4, Layout::Quant4),
    (Layout::Wide8, Layout::Quant8),
];

/// The exact box below every used slot, from the triangle records (f32
/// min/max: exact), indexed like `img.nodes`.
fn exact_boxes(img: &Image) -> Vec<Option<Aabb>> {
    let k = img.layout.records_per_node();
    let mut out = vec![None; img.nodes.len()];
    // A child's index is always above its parent's: fill from the last node.
    for n in (0..img.node_count()).rev() {
        for i in 0..k {
            out[n * k + i] = match img.nodes[n * k + i].slot() {
                Slot::Leaf { first, count } => Some(
                    img.tris[first as usize..(first + count) as usize]
                        .iter()
                        .fold(Aabb::empty(), |b, r| b.union(&r.tri.bounds())),
                ),
                Slot::Inner { node } => {
                    assert!(node as usize > n, "node {n}: child {node} not after it");
                    let c = node as usize * k;
                    Some(
                        out[c..c + k]
                            .iter()
                            .flatten()
                            .fold(Aabb::empty(), |b, x| b.union(x)),
                    )
                }
                _ => None,
            };
        }
    }
    out
}

#[test]
fn every_stored_box_contains_its_exact_box() {
    for name in SHIPPED {
        let scene = load(name);
        for (_, layout) in PAIRS {
            let what = format!("{name} --bvh {layout}");
            let (_, built) = build_as(&scene, 4, layout);
            let bytes = built.to_bytes();
            let nb = layout.node_bytes();
            assert_eq!(
                u32::from_le_bytes(bytes[28..32].try_into().unwrap()) as usize,
                nb,
                "{what}: header nodeBytes"
            );
            assert_eq!(
                bytes.len(),
                nori_bridge::image_bin::align_up(64 + nb * built.node_count())
                    + 64 * built.tris.len(),
                "{what}: file size"
            );
            let img = Image::parse(&bytes).unwrap_or_else(|e| panic!("{what}: {e:#}"));
            assert!(
                img.nodes == built.nodes && img.quant == built.quant && img.to_bytes() == bytes,
                "{what}: bytes do not read back"
            );
            check_tri_records(&what, &scene.tris, &img);
            // The same tree in the same (breadth-first) order as the FP32 layout of the same K: only the boxes differ.
            let wide = PAIRS.iter().find(|p| p.1 == layout).unwrap().0;
            let (_, fp32) = build_as(&scene, 4, wide);
            let refs = |i: &Image| {
                i.nodes
                    .iter()
                    .map(|s| (s.word0, s.word1))
                    .collect::<Vec<_>>()
            };
            assert!(
                refs(&img) == refs(&fp32) && img.tris == fp32.tris,
                "{what}: records or triangle order differ from --bvh {wide}'s"
            );
            let exact = exact_boxes(&img);
            let k = layout.records_per_node();
            let (mut slots, mut growth) = (0usize, 0f64);
            for (n, q) in img.quant.iter().enumerate() {
                for i in 0..k {
                    let Some(want) = exact[n * k + i] else {
                        continue;
                    };
                    let got = img.nodes[n * k + i].bounds;
                    assert_eq!(
                        got,
                        q.decoded(i),
                        "{what}: node {n} slot {i}: image box is not the decoded box"
                    );
                    assert!(
                        got.contains(&want),
                        "{what}: node {n} slot {i}: stored {got:?} does not contain exact {want:?}"
                    );
                    exact_decode(q, i).unwrap_or_else(|e| panic!("{what}: node {n} slot {i}: {e}"));
                    slots += 1;
                    growth += got.area64() / want.area64().max(f64::MIN_POSITIVE) - 1.0;
                }
            }
            assert_eq!(
                slots,
                img.nodes.iter().filter(|s| s.slot() != Slot::Empty).count(),
                "{what}: every used slot checked"
            );
            println!("{what}: {} nodes of {nb} bytes, {slots} child boxes all contain their exact box; mean area growth {:.1}%",
                img.node_count(), 100.0 * growth / slots as f64);
        }
    }
}

/// The FP32 add of the decode rounds nothing: each plane equals
/// origin + q 2^(e-127) computed exactly (f64 holds it: both terms have
/// at most 24 significant bits within 2^24 steps of 2^(e-127)).
fn exact_decode(q: &QuantNode, i: usize) -> Result<(), String> {
    for a in 0..3 {
        let e = q.exp[a];
        if !(quant::EXP_MIN..=quant::EXP_MAX).contains(&e) {
            return Err(format!("axis {a}: exponent {e}"));
        }
        for (qq, got) in [
            (q.lo[i][a], quant::plane(q.origin[a], q.lo[i][a], e)),
            (q.hi[i][a], quant::plane(q.origin[a], q.hi[i][a], e)),
        ] {
            let exact = q.origin[a] as f64 + qq as f64 * 2f64.powi(e as i32 - 127);
            if got as f64 != exact {
                return Err(format!(
                    "axis {a}: {} + {qq} 2^{} = {exact} decodes to {got}",
                    q.origin[a],
                    e as i32 - 127
                ));
            }
        }
    }
    Ok(())
}

#[test]
fn quantized_walks_equal_the_fp32_walks_ray_by_ray() {
    for (n, name) in SHIPPED.iter().enumerate() {
        let seed = 70 + n as u64;
        let scene = load(name);
        let rays = walk_rays(name, seed);
        for (wide, quant) in PAIRS {
            let ((_, wimg), (_, qimg)) = (build_as(&scene, 4, wide), build_as(&scene, 4, quant));
            let (want, _) = mt_walk::trace_all(&wimg, &rays);
            let (got, stats) = mt_walk::trace_all(&qimg, &rays);
            let what = format!("{name} --bvh {quant} seed {seed}");
            assert!(
                stats.max_stack <= qimg.bvh_depth as usize,
                "{what}: stack {} > bvhDepth {}",
                stats.max_stack,
                qimg.bvh_depth
            );
            let hits = want[..RAYS].iter().filter(|h| h.hit).count();
            assert!(
                hits > RAYS / 10,
                "{what}: only {hits} hits, the ray set is too easy"
            );
            let mut ties = 0;
            for (r, (ray, (g, w))) in rays.iter().zip(got.iter().zip(&want)).enumerate() {
                if ray.shadow {
                    assert_eq!(g.hit, w.hit, "{what}: shadow ray {r} {ray:?}");
                } else if g != w {
                    tie(ray, (g, &qimg), (w, &wimg)).unwrap_or_else(|| {
                        panic!("{what}: ray {r} {ray:?}: {g:?} vs --bvh {wide} {w:?} is no tie")
                    });
                    ties += 1;
                }
            }
            println!("{what}: {} rays equal to --bvh {wide} but {ties} ties; largest stack {} (bvhDepth {})", rays.len(), stats.max_stack, qimg.bvh_depth);
        }
    }
}

/// A scale exponent the hardware would flag is refused when reading,
/// naming the node and slot.
#[test]
fn a_bad_scale_exponent_is_refused() {
    let scene = load("cornell-box");
    let (_, img) = build_as(&scene, 4, Layout::Quant4);
    let mut b = img.to_bytes();
    b[64 + 13] = 0; // node 0, y exponent
    let err = format!("{:#}", Image::parse(&b).unwrap_err());
    assert!(
        err.contains("node 0 slot 0") && err.contains("non-finite box"),
        "{err}"
    );
}
