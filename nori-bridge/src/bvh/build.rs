//! BVH construction with Embree's SAH builder (rtcBuildBVH, binned SAH at
//! MEDIUM quality: no spatial splits, so each triangle lands in exactly one
//! leaf), then flattening into our depth-first layout with boxes recomputed
//! from the f32 vertices.

use crate::bvh::{Bvh, Node, LEAF_BIT};
use crate::geom::{Aabb, Tri};
use crate::reference::device::Device;
use anyhow::{bail, Result};
use embree::sys;
use std::os::raw::{c_uint, c_void};

/// Embree's per-leaf limit for rtcBuildBVH.
pub const MAX_LEAF_LIMIT: u32 = 32;

#[repr(C)]
struct BInner {
    is_leaf: u32,
    children: [*const c_void; 2],
}

#[repr(C)]
struct BLeaf {
    is_leaf: u32,
    count: u32,
    // followed by `count` u32 prim numbers
}

unsafe extern "C" fn create_node(alloc: sys::RTCThreadLocalAllocator, n: c_uint, _: *mut c_void) -> *mut c_void {
    debug_assert_eq!(n, 2);
    let p = sys::rtcThreadLocalAlloc(alloc, std::mem::size_of::<BInner>(), 16) as *mut BInner;
    p.write(BInner { is_leaf: 0, children: [std::ptr::null(); 2] });
    p as *mut c_void
}

unsafe extern "C" fn set_children(node: *mut c_void, ch: *mut *mut c_void, n: c_uint, _: *mut c_void) {
    let node = &mut *(node as *mut BInner);
    for i in 0..n as usize {
        node.children[i] = *ch.add(i);
    }
}

unsafe extern "C" fn set_bounds(_: *mut c_void, _: *mut *const sys::RTCBounds, _: c_uint, _: *mut c_void) {
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
    p.write(BLeaf { is_leaf: 1, count: n as u32 });
    let ids = (p as *mut u8).add(std::mem::size_of::<BLeaf>()) as *mut u32;
    for i in 0..n {
        ids.add(i).write((*prims.add(i)).primID);
    }
    p as *mut c_void
}

pub fn build_bvh(device: &Device, tris: &[Tri], max_leaf_size: u32) -> Result<Bvh> {
    if !(1..=MAX_LEAF_LIMIT).contains(&max_leaf_size) {
        bail!("--max-leaf-size {max_leaf_size} must be in 1..={MAX_LEAF_LIMIT} (Embree's builder limit)");
    }
    if tris.len() >= (1usize << 31) {
        bail!("{} triangles exceed the 31-bit index fields of the format", tris.len());
    }
    let mut prims: Vec<sys::RTCBuildPrimitive> = tris
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let b = t.bounds();
            sys::RTCBuildPrimitive {
                lower_x: b.min[0], lower_y: b.min[1], lower_z: b.min[2], geomID: 0,
                upper_x: b.max[0], upper_y: b.max[1], upper_z: b.max[2], primID: i as u32,
            }
        })
        .collect();
    unsafe {
        let handle = sys::rtcNewBVH(device.raw());
        let args = sys::RTCBuildArguments {
            byteSize: std::mem::size_of::<sys::RTCBuildArguments>(),
            buildQuality: sys::RTCBuildQuality::MEDIUM,
            buildFlags: sys::RTCBuildFlags::NONE,
            maxBranchingFactor: 2,
            maxDepth: 1024,
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
            Err(anyhow::anyhow!("Embree's rtcBuildBVH failed: {:?}", device.error()))
        } else {
            let mut f = Flattener { tris, nodes: Vec::new(), slot_prim: Vec::new() };
            f.emit(root, 0).map(|depth| Bvh { nodes: f.nodes, slot_prim: f.slot_prim, depth, max_leaf_size })
        };
        sys::rtcReleaseBVH(handle);
        result
    }
}

struct Flattener<'a> {
    tris: &'a [Tri],
    nodes: Vec<Node>,
    slot_prim: Vec<u32>,
}

impl Flattener<'_> {
    /// Emit the subtree at `p` in depth-first order; returns its stack depth.
    unsafe fn emit(&mut self, p: *const c_void, level: u32) -> Result<u32> {
        if level > 1024 {
            bail!("BVH deeper than 1024 levels");
        }
        let me = self.nodes.len();
        self.nodes.push(Node { word0: 0, word1: 0, bounds: Aabb::empty() });
        if *(p as *const u32) == 1 {
            let leaf = &*(p as *const BLeaf);
            let ids = (p as *const u8).add(std::mem::size_of::<BLeaf>()) as *const u32;
            let first = self.slot_prim.len() as u32;
            let mut b = Aabb::empty();
            for i in 0..leaf.count as usize {
                let prim = *ids.add(i);
                b = b.union(&self.tris[prim as usize].bounds());
                self.slot_prim.push(prim);
            }
            self.nodes[me] = Node { word0: LEAF_BIT | leaf.count, word1: first, bounds: b };
            return Ok(0);
        }
        let inner = &*(p as *const BInner);
        let dl = self.emit(inner.children[0], level + 1)?;
        let right = self.nodes.len();
        let dr = self.emit(inner.children[1], level + 1)?;
        let (lb, rb) = (self.nodes[me + 1].bounds, self.nodes[right].bounds);
        self.nodes[me] = Node { word0: split_axis(&lb, &rb), word1: right as u32, bounds: lb.union(&rb) };
        Ok(1 + dl.max(dr))
    }
}

/// The axis along which the children's box centres lie farthest apart.
/// Traversal only uses it to pick which child to visit first.
fn split_axis(l: &Aabb, r: &Aabb) -> u32 {
    let gap = |k: usize| ((r.min[k] + r.max[k]) as f64 - (l.min[k] + l.max[k]) as f64).abs();
    (0..3).max_by(|&a, &b| gap(a).total_cmp(&gap(b))).unwrap() as u32
}
