//! The reference side: what the hardware's answers are judged against.
//! Embree 3 (device, scene, throughput bench), a brute-force f64 tracer for
//! small scenes, and the f64 ray/triangle evaluation that judges both.

pub mod bench;
pub mod device;
pub mod double;
pub mod embree;
pub mod exact;
