//! Wide layouts (K = 2, 4, 8) of the memory image on every shipped scene
//! and on seeded random soups: breadth-first node order, slot order, exact
//! boxes, triangles in the same node order, the stack bound recomputed from
//! the bytes, header fields, and a clear error for a malformed layout word.
//!
//! Node order is pinned breadth first (nori-bridge wrote depth-first
//! pre-order before): the system's node store preloads the first bytes of the node
//! array (docs/node-store.md), and breadth-first order puts the top levels
//! there, which every ray reads (85% of the dragon's camera-ray node reads
//! from a 1 MiB store against 30% in pre-order).

mod common;
use common::*;
use nori_bridge::bvh::{Bvh, Layout, Slot};
use nori_bridge::geom::{Aabb, Tri};
use nori_bridge::image_bin::Image;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const WIDE: [Layout; 3] = [Layout::Wide2, Layout::Wide4, Layout::Wide8];

/// What the slots of node `n` and everything below them hold.
#[derive(Clone, Copy)]
struct Below {
    bounds: Aabb,
    /// The stack bound of the subtree: (used slots - 1) summed along its
    /// worst path from `n` (the contract's definition, recomputed here).
    stack: u32,
    /// Wide nodes on its longest path.
    depth: u32,
}

/// Walks the image with a FIFO queue from the root and checks that it is
/// breadth first: the m-th node the walk meets is node m, so each inner
/// child index is the next unused one, and each leaf starts at the next
/// triangle slot (triangles in the same order). Returns the root's `Below`,
/// computed from the last node up (a child's index is above its parent's).
fn walk(what: &str, img: &Image) -> Below {
    let n_nodes = img.node_count();
    let (mut met, mut next_slot) = (1usize, 0u32); // node 0, the root, is met first
    for n in 0..n_nodes {
        assert!(
            n < met,
            "{what}: node {n} is reached from no node before it"
        );
        let slots = img.wide_node(n);
        let used = slots.iter().take_while(|s| s.slot() != Slot::Empty).count();
        assert!(
            slots[used..].iter().all(|s| s.slot() == Slot::Empty),
            "{what}: node {n}: a used slot follows an empty one"
        );
        for s in &slots[used..] {
            assert_eq!(
                (s.word1, s.bounds.min, s.bounds.max),
                (0, [0.0; 3], [0.0; 3]),
                "{what}: node {n}: empty slot not zero"
            );
        }
        assert!(
            used >= 2 || n == 0,
            "{what}: node {n} has {used} used slots"
        );
        for (i, s) in slots[..used].iter().enumerate() {
            match s.slot() {
                Slot::Leaf { first, count } => {
                    assert!(
                        count >= 1 && count <= img.max_leaf_size,
                        "{what}: node {n} slot {i}: leaf of {count}"
                    );
                    assert_eq!(
                        first, next_slot,
                        "{what}: node {n} slot {i}: leaf triangles not in breadth-first leaf order"
                    );
                    next_slot += count;
                }
                Slot::Inner { node } => {
                    assert_eq!(node as usize, met, "{what}: node {n} slot {i}: child {node} is not the next in breadth-first order");
                    met += 1;
                }
                other => panic!("{what}: node {n} slot {i}: {other:?}"),
            }
        }
    }
    assert_eq!(
        met, n_nodes,
        "{what}: not every node reached once in breadth-first order"
    );
    assert_eq!(
        next_slot as usize,
        img.tris.len(),
        "{what}: leaves do not cover every triangle slot"
    );
    let mut below: Vec<Option<Below>> = vec![None; n_nodes];
    for n in (0..n_nodes).rev() {
        let slots = img.wide_node(n);
        let (mut bounds, mut stack, mut depth, mut used) = (Aabb::empty(), 0, 0, 0u32);
        for (i, s) in slots.iter().enumerate() {
            let b = match s.slot() {
                Slot::Leaf { first, count } => img.tris[first as usize..(first + count) as usize]
                    .iter()
                    .fold(Aabb::empty(), |b, r| b.union(&r.tri.bounds())),
                Slot::Inner { node } => {
                    let sub = below[node as usize].expect("child below its parent");
                    stack = stack.max(sub.stack);
                    depth = depth.max(sub.depth);
                    sub.bounds
                }
                _ => continue,
            };
            assert_eq!(
                s.bounds, b,
                "{what}: node {n} slot {i}: box is not the exact bounds of the triangles below"
            );
            bounds = bounds.union(&b);
            used += 1;
        }
        below[n] = Some(Below {
            bounds,
            stack: used.saturating_sub(1) + stack,
            depth: 1 + depth,
        });
    }
    below[0].unwrap()
}

/// Every invariant of a wide image built from `tris` by `bvh`.
fn check_wide(what: &str, tris: &[Tri], bvh: &Bvh, img: &Image) {
    let root = walk(what, img);
    check_tri_records(what, tris, img);
    let scene = tris.iter().fold(Aabb::empty(), |b, t| b.union(&t.bounds()));
    assert_eq!(
        root.bounds, scene,
        "{what}: root slots do not cover the scene"
    );
    assert_eq!(
        img.bvh_depth, root.stack,
        "{what}: header bvhDepth is not the stack bound"
    );
    assert_eq!(bvh.tree_depth, root.depth, "{what}: tree depth");
}

#[test]
fn shipped_scenes_satisfy_wide_invariants() {
    for name in SHIPPED {
        let scene = load(name);
        for layout in WIDE {
            for leaf in [1, 4, 8] {
                let (bvh, img) = build_as(&scene, leaf, layout);
                let what = format!("{name} --bvh {layout} leaf {leaf}");
                check_wide(&what, &scene.tris, &bvh, &img);
                let back =
                    Image::parse(&img.to_bytes()).unwrap_or_else(|e| panic!("{what}: {e:#}"));
                assert_eq!(
                    (back.layout, back.nodes, back.tris, back.bvh_depth),
                    (img.layout, img.nodes, img.tris, img.bvh_depth),
                    "{what}: round trip"
                );
            }
        }
    }
}

/// K = 2 is Embree's binary tree, so its node count, stack bound and leaves
/// are those of nori (one wide node per nori inner node; the root-is-leaf case
/// still has a root node).
#[test]
fn wide2_is_the_nori_tree() {
    for name in SHIPPED {
        let scene = load(name);
        let (nori, nori_img) = build_as(&scene, 4, Layout::Nori);
        let (wide, wide_img) = build_as(&scene, 4, Layout::Wide2);
        let inner = nori.nodes.iter().filter(|n| !n.is_leaf()).count();
        assert_eq!(wide.node_count(), inner.max(1), "{name}");
        assert_eq!(
            (wide.depth, wide.tree_depth),
            (nori.depth, nori.depth),
            "{name}"
        );
        // The same leaves (as sets of prims), though stored in breadth-first order, not nori's depth-first one.
        let leaves = |img: &Image, layout: Layout| {
            let mut v: Vec<Vec<u32>> = (0..img.nodes.len())
                .filter_map(|r| match (layout, img.nodes[r].slot()) {
                    (Layout::Nori, _) if img.nodes[r].is_leaf() => {
                        Some((img.nodes[r].word1, img.nodes[r].count()))
                    }
                    (Layout::Wide2, Slot::Leaf { first, count }) => Some((first, count)),
                    _ => None,
                })
                .map(|(first, count)| {
                    let mut p: Vec<u32> = img.tris[first as usize..(first + count) as usize]
                        .iter()
                        .map(|t| t.prim)
                        .collect();
                    p.sort();
                    p
                })
                .collect();
            v.sort();
            v
        };
        assert_eq!(
            leaves(&wide_img, Layout::Wide2),
            leaves(&nori_img, Layout::Nori),
            "{name}: leaves differ from nori's"
        );
        assert_eq!(wide.mean_children(), 2.0, "{name}");
    }
}

/// Includes one-triangle scenes: the root is one node with the leaf in
/// slot 0 (one used slot, stack bound 0).
#[test]
fn random_soups_satisfy_wide_invariants() {
    let seed = 17;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut root_is_leaf = 0;
    for n in [1, 2, 3, 5, 9, 17, 100, 1000, 5000] {
        let tris = random_soup(&mut rng, n);
        for layout in WIDE {
            for leaf in [1, 2, 4, 32] {
                let bvh =
                    nori_bridge::bvh_build::build_layout(&device(), &tris, leaf, layout).unwrap();
                let img = Image::from_bvh(&bvh, &tris);
                check_wide(
                    &format!("soup seed {seed} n {n} --bvh {layout} leaf {leaf}"),
                    &tris,
                    &bvh,
                    &img,
                );
                if img.nodes[1].slot() == Slot::Empty {
                    root_is_leaf += 1;
                    assert_eq!(
                        img.bvh_depth, 0,
                        "seed {seed} n {n}: root-is-leaf stack bound"
                    );
                }
            }
        }
    }
    assert!(
        root_is_leaf >= WIDE.len() * 4,
        "seed {seed}: the one-triangle soups must give a root that is a leaf"
    );
}

#[test]
fn wide_header_fields() {
    let scene = load("multi-mesh");
    for layout in WIDE {
        let (_, img) = build_as(&scene, 4, layout);
        let b = img.to_bytes();
        let u = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
        let k = layout.word();
        assert_eq!((u(8), u(44)), (3, k), "version, layout");
        assert_eq!(
            u(12) as usize,
            img.nodes.len() / k as usize,
            "nodeCount counts wide nodes"
        );
        assert_eq!((u(28), u(32)), (32 * k, 64), "nodeBytes = 32 K");
        assert_eq!(
            u(24) as usize,
            (64 + 32 * img.nodes.len()).div_ceil(64) * 64,
            "triOffset"
        );
        assert_eq!(u(40), img.bvh_depth);
        assert!(
            b[48..64].iter().all(|&x| x == 0),
            "reserved header bytes must be zero"
        );
        // Node i starts at 64 + 32 K i: whole 64-byte bursts, 64-byte aligned.
        assert_eq!((32 * k) % 64, 0);
    }
}

#[test]
fn malformed_layout_word_names_the_file_and_the_value() {
    let scene = load("cornell-box");
    let dir = tempfile::tempdir().unwrap();
    let (_, img) = build_as(&scene, 4, Layout::Wide4);
    for (bad, needle) in [(3u32, "header layout 3"), (16, "header layout 16")] {
        let mut b = img.to_bytes();
        b[44..48].copy_from_slice(&bad.to_le_bytes());
        let p = dir.path().join(format!("layout{bad}.bin"));
        std::fs::write(&p, &b).unwrap();
        let e = format!("{:#}", Image::read(&p).unwrap_err());
        assert!(e.contains(p.to_str().unwrap()) && e.contains(needle), "{e}");
    }
    // A wide image whose nodeBytes disagrees with its layout word.
    let mut b = img.to_bytes();
    b[44..48].copy_from_slice(&8u32.to_le_bytes());
    let e = format!("{:#}", Image::parse(&b).unwrap_err());
    assert!(e.contains("record sizes 128/64 differ from 256/64"), "{e}");
    // A slot whose word0 is no slot kind.
    let mut b = img.to_bytes();
    b[64 + 32..64 + 36].copy_from_slice(&5u32.to_le_bytes());
    let e = format!("{:#}", Image::parse(&b).unwrap_err());
    assert!(e.contains("node 0 slot 1: word0 0x00000005"), "{e}");
}
