//! BVH construction with Embree's SAH builder (rtcBuildBVH, binned SAH at
//! MEDIUM quality: no spatial splits, so each triangle lands in exactly one
//! leaf) with the layout's branching factor. The builder's tree is copied
//! out as a `Tree` (children in the order Embree gives them); flatten.rs
//! lays it out with boxes recomputed from the f32 vertices.

use crate::bvh::flatten::{flatten, Tree};
use crate::bvh::{Bvh, Layout};
use crate::geom::Tri;
use crate::reference::device::Device;
use anyhow::{bail, Result};
use embree::sys;
use std::os::raw::{c_uint, c_void};

/// Embree's per-leaf limit for rtcBuildBVH.
pub const MAX_LEAF_LIMIT: u32 = 32;

/// The widest node any layout asks for (Layout::Wide8).
const MAX_BRANCHING: usize = 8;

/// Deepest tree we accept (Embree's maxDepth argument as we pass it).
const MAX_DEPTH: usize = 1024;

#[repr(C)]
struct BInner {
    is_leaf: u32,
    count: u32,
    children: [*const c_void; MAX_BRANCHING],
}

#[repr(C)]
struct BLeaf {
    is_leaf: u32,
    count: u32,
    // followed by `count` u32 prim numbers
}

unsafe extern "C" fn create_node(
    alloc: sys::RTCThreadLocalAllocator,
    n: c_uint,
    _: *mut c_void,
) -> *mut c_void {
    assert!(
        n as usize <= MAX_BRANCHING,
        "Embree asked for a node of {n} children"
    );
    let p = sys::rtcThreadLocalAlloc(alloc, std::mem::size_of::<BInner>(), 16) as *mut BInner;
    p.write(BInner {
        is_leaf: 0,
        count: n,
        children: [std::ptr::null(); MAX_BRANCHING],
    });
    p as *mut c_void
}

unsafe extern "C" fn set_children(
    node: *mut c_void,
    ch: *mut *mut c_void,
    n: c_uint,
    _: *mut c_void,
) {
    let node = &mut *(node as *mut BInner);
    node.count = n;
    for i in 0..n as usize {
        node.children[i] = *ch.add(i);
    }
}

unsafe extern "C" fn set_bounds(
    _: *mut c_void,
    _: *mut *const sys::RTCBounds,
    _: c_uint,
    _: *mut c_void,
) {
    // Boxes are recomputed from the exact f32 vertices when flattening.
}

unsafe extern "C" fn create_leaf(
    alloc: sys::RTCThreadLocalAllocator,
    prims: *const sys::RTCBuildPrimitive,
    n: usize,
    _: *mut c_void,
) -> *mut c_void {
    let bytes = std::mem::size_of::<BLeaf>() + 4 * n;
    let p = sys::rtcThreadLocalAlloc(alloc, bytes, 16) as *mut BLeaf;
    p.write(BLeaf {
        is_leaf: 1,
        count: n as u32,
    });
    let ids = (p as *mut u8).add(std::mem::size_of::<BLeaf>()) as *mut u32;
    for i in 0..n {
        ids.add(i).write((*prims.add(i)).primID);
    }
    p as *mut c_void
}

/// The nori layout (what the tests of version 1 build).
pub fn build_bvh(device: &Device, tris: &[Tri], max_leaf_size: u32) -> Result<Bvh> {
    build_layout(device, tris, max_leaf_size, Layout::Nori)
}

pub fn build_layout(
    device: &Device,
    tris: &[Tri],
    max_leaf_size: u32,
    layout: Layout,
) -> Result<Bvh> {
    let tree = build_tree(device, tris, max_leaf_size, layout.branching())?;
    flatten(&tree, tris, max_leaf_size, layout)
}

/// Embree's tree with at most `branching` children per inner node.
pub fn build_tree(
    device: &Device,
    tris: &[Tri],
    max_leaf_size: u32,
    branching: u32,
) -> Result<Tree> {
    if !(1..=MAX_LEAF_LIMIT).contains(&max_leaf_size) {
        bail!("--max-leaf-size {max_leaf_size} must be in 1..={MAX_LEAF_LIMIT} (Embree's builder limit)");
    }
    if tris.len() >= (1usize << 31) {
        bail!(
            "{} triangles exceed the 31-bit index fields of the format",
            tris.len()
        );
    }
    let mut prims: Vec<sys::RTCBuildPrimitive> = tris
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let b = t.bounds();
            sys::RTCBuildPrimitive {
                lower_x: b.min[0],
                lower_y: b.min[1],
                lower_z: b.min[2],
                geomID: 0,
                upper_x: b.max[0],
                upper_y: b.max[1],
                upper_z: b.max[2],
                primID: i as u32,
            }
        })
        .collect();
    unsafe {
        let handle = sys::rtcNewBVH(device.raw());
        let args = sys::RTCBuildArguments {
            byteSize: std::mem::size_of::<sys::RTCBuildArguments>(),
            buildQuality: sys::RTCBuildQuality::MEDIUM,
            buildFlags: sys::RTCBuildFlags::NONE,
            maxBranchingFactor: branching,
            maxDepth: MAX_DEPTH as u32,
            sahBlockSize: 1,
            minLeafSize: 1,
            maxLeafSize: max_leaf_size,
            traversalCost: 1.0,
            intersectionCost: 1.0,
            bvh: handle,
            primitives: prims.as_mut_ptr(),
            primitiveCount: prims.len(),
            primitiveArrayCapacity: prims.len(),
            createNode: Some(create_node),
            setNodeChildren: Some(set_children),
            setNodeBounds: Some(set_bounds),
            createLeaf: Some(create_leaf),
            splitPrimitive: None,
            buildProgress: None,
            userPtr: std::ptr::null_mut(),
        };
        let root = sys::rtcBuildBVH(&args);
        let result = if root.is_null() {
            Err(anyhow::anyhow!(
                "Embree's rtcBuildBVH failed: {:?}",
                device.error()
            ))
        } else {
            copy_tree(root, 0)
        };
        sys::rtcReleaseBVH(handle);
        result
    }
}

/// Copy the builder's nodes (allocated in the BVH's memory, freed with it)
/// into an owned tree.
unsafe fn copy_tree(p: *const c_void, level: usize) -> Result<Tree> {
    if level > MAX_DEPTH {
        bail!("BVH deeper than {MAX_DEPTH} levels");
    }
    if *(p as *const u32) == 1 {
        let leaf = &*(p as *const BLeaf);
        let ids = (p as *const u8).add(std::mem::size_of::<BLeaf>()) as *const u32;
        return Ok(Tree::Leaf(
            (0..leaf.count as usize).map(|i| *ids.add(i)).collect(),
        ));
    }
    let inner = &*(p as *const BInner);
    let kids = inner.children[..inner.count as usize]
        .iter()
        .map(|&c| copy_tree(c, level + 1));
    Ok(Tree::Inner(kids.collect::<Result<_>>()?))
}
