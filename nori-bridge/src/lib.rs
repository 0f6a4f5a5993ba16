//! nori-bridge: Nori scenes in; rtaccel memory images, rays and Embree
//! reference hits out; hits back to accuracy reports and images.

// x/y/z loops index several arrays at once; iterators would read worse.
#![allow(clippy::needless_range_loop)]

pub mod bvh;
pub mod bvh_build;
pub mod chart;
pub mod cli;
pub mod compare;
pub mod compile;
pub mod csv_io;
pub mod double_ref;
pub mod embree_dev;
pub mod embree_ref;
pub mod error;
pub mod exact;
pub mod geom;
pub mod hard_cases;
pub mod hard_exact;
pub mod hard_mesh;
pub mod hard_planes;
pub mod hard_score;
pub mod hard_spheres;
pub mod hard_thin;
pub mod image_bin;
pub mod judge;
pub mod needs;
pub mod obj;
pub mod package;
pub mod pareto;
pub mod pixels;
pub mod progress;
pub mod ray;
pub mod ray_gen;
pub mod rays_txt;
pub mod render;
pub mod scene;
pub mod scene_xml;
pub mod sweep_input;
pub mod sweep_md;
pub mod sweep_md_hard;
pub mod sweep_metrics;
pub mod sweep_plot;
pub mod sweep_report;
pub mod sweep_runs;
pub mod sweep_summary;
pub mod transform;
pub mod traverse;
pub mod bench;
