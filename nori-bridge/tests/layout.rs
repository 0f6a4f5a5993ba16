//! Layout invariants of the memory image on every shipped scene and on
//! seeded random triangle soups, and the byte format round trip.

mod common;
use common::*;
use nori_bridge::bvh::Bvh;
use nori_bridge::geom::{Aabb, Tri};
use nori_bridge::image_bin::Image;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Checks DFS order (left = i+1, right > i, every node reached exactly
/// once), boxes (leaf = exact bounds of its triangles, inner = exact union
/// of children, so children lie inside parents), leaf slots covering every
/// slot exactly once, every prim exactly once, and the header depth.
fn check_layout(what: &str, tris: &[Tri], img: &Image) {
    let n = img.nodes.len();
    let mut visited = vec![false; n];
    let mut slot_seen = vec![false; img.tris.len()];
    let mut next_slot = 0u32;
    // Pre-order walk: the walk's visiting order must be 0,1,2,... exactly.
    let mut order = Vec::with_capacity(n);
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        assert!(
            i < n && !visited[i],
            "{what}: node {i} out of range or reached twice"
        );
        visited[i] = true;
        order.push(i);
        let node = img.nodes[i];
        if node.is_leaf() {
            let (first, count) = (node.word1, node.count());
            assert!(
                count >= 1 && count <= img.max_leaf_size,
                "{what}: leaf {i} holds {count} (max {})",
                img.max_leaf_size
            );
            assert_eq!(
                first, next_slot,
                "{what}: leaf {i} slots are not in leaf order"
            );
            next_slot += count;
            let mut b = Aabb::empty();
            for s in first..first + count {
                assert!(!slot_seen[s as usize], "{what}: slot {s} in two leaves");
                slot_seen[s as usize] = true;
                b = b.union(&img.tris[s as usize].tri.bounds());
            }
            assert_eq!(
                node.bounds, b,
                "{what}: leaf {i} box is not the exact bounds of its triangles"
            );
        } else {
            let r = node.word1 as usize;
            assert!(node.axis() < 3, "{what}: node {i} axis {}", node.axis());
            assert!(r > i + 1 && r < n, "{what}: node {i} right child {r}");
            let (lb, rb) = (img.nodes[i + 1].bounds, img.nodes[r].bounds);
            assert!(
                node.bounds.contains(&lb) && node.bounds.contains(&rb),
                "{what}: node {i} does not contain its children"
            );
            assert_eq!(
                node.bounds,
                lb.union(&rb),
                "{what}: node {i} box is not the union of its children"
            );
            stack.push(r);
            stack.push(i + 1);
        }
    }
    assert_eq!(
        order,
        (0..n).collect::<Vec<_>>(),
        "{what}: nodes are not in depth-first order"
    );
    assert!(
        slot_seen.iter().all(|&s| s),
        "{what}: some slot is in no leaf"
    );
    check_tri_records(what, tris, img);
    assert_eq!(
        img.bvh_depth,
        Bvh::compute_depth(&img.nodes),
        "{what}: header depth"
    );
}

#[test]
fn shipped_scenes_satisfy_layout_invariants() {
    for name in SHIPPED {
        let scene = load(name);
        for leaf in [1, 4, 8] {
            let (_, img) = build(&scene, leaf);
            check_layout(&format!("{name} leaf {leaf}"), &scene.tris, &img);
        }
    }
}

#[test]
fn random_soups_satisfy_layout_invariants() {
    let seed = 7;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for n in [1, 2, 3, 5, 17, 100, 1000, 5000] {
        let tris = random_soup(&mut rng, n);
        for leaf in [1, 2, 4, 32] {
            let bvh = nori_bridge::bvh_build::build_bvh(&device(), &tris, leaf).unwrap();
            check_layout(
                &format!("soup seed {seed} n {n} leaf {leaf}"),
                &tris,
                &Image::from_bvh(&bvh, &tris),
            );
        }
    }
}

#[test]
fn image_bytes_round_trip_and_header() {
    let scene = load("multi-mesh");
    let (_, img) = build(&scene, 4);
    let b = img.to_bytes();
    assert_eq!(&b[0..8], b"RTACCEL\0");
    let u = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    assert_eq!(u(8), 3);
    assert_eq!(u(12) as usize, img.nodes.len());
    assert_eq!(u(16) as usize, scene.tris.len());
    assert_eq!(u(20), 64);
    assert_eq!(u(24) % 64, 0);
    assert!(
        u(24) as usize >= 64 + 32 * img.nodes.len()
            && (u(24) as usize) < 64 + 32 * img.nodes.len() + 64
    );
    assert_eq!((u(28), u(32), u(36)), (32, 64, 4));
    assert_eq!(u(44), 0, "layout word: nori");
    assert!(
        b[48..64].iter().all(|&x| x == 0),
        "reserved header bytes must be zero"
    );
    assert_eq!(b.len(), u(24) as usize + 64 * scene.tris.len());
    // node 0 = root box = scene bounds
    let f = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    let root = scene.bounds();
    assert_eq!([f(72), f(76), f(80)], root.min);
    assert_eq!([f(84), f(88), f(92)], root.max);
    let back = Image::parse(&b).unwrap();
    assert_eq!(back.nodes, img.nodes);
    assert_eq!(back.tris, img.tris);
    assert_eq!(back.bvh_depth, img.bvh_depth);
    // the padding of every triangle record (bytes 44-63) is zero
    let t0 = u(24) as usize;
    assert!((0..scene.tris.len()).all(|i| (44..64).step_by(4).all(|k| u(t0 + 64 * i + k) == 0)));
}

#[test]
fn leaf_size_outside_embree_limit_is_an_error() {
    let scene = load("icosphere");
    for bad in [0, 33] {
        let e = nori_bridge::bvh_build::build_bvh(&device(), &scene.tris, bad).unwrap_err();
        assert!(
            format!("{e:#}").contains(&format!("--max-leaf-size {bad}")),
            "{e:#}"
        );
    }
}
