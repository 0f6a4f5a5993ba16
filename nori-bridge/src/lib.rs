//! nori-bridge: Nori scenes in; rtaccel memory images, rays and Embree
//! reference hits out; hits back to accuracy reports and images.
//!
//! The data path reads in one direction: `scene` (XML, OBJ, transforms) ->
//! `bvh` (Embree's builder, flattened) -> `memory` (image.bin and the f32
//! walk of it) -> `package` (compile: image, rays, reference, scene.json)
//! -> `compare` (judge hits against the reference, render). `ray` holds
//! rays, hits and their files; `reference` Embree and the f64 judge;
//! `sweep` and `hard` the precision-sweep report and the hard-case suite.

// x/y/z loops index several arrays at once; iterators would read worse.
#![allow(clippy::needless_range_loop)]

pub mod bvh;
pub mod cli;
pub mod compare;
pub mod error;
pub mod geom;
pub mod hard;
pub mod memory;
pub mod package;
pub mod progress;
pub mod ray;
pub mod reference;
pub mod regress;
pub mod scene;
pub mod shade;
pub mod sweep;

// The flat module paths of the layout before the folders, kept for the
// integration tests and any outside caller.
pub use bvh::build as bvh_build;
pub use compare::{judge, pixels, render};
pub use memory as image_bin;
pub use memory::mt_walk;
pub use package::{compile, needs};
pub use ray::{csv_io, generate as ray_gen, txt as rays_txt};
pub use reference::{device as embree_dev, double as double_ref, embree as embree_ref, exact};
pub use scene::{obj, transform, xml as scene_xml};
