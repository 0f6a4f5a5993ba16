//! The loaded scene: one concatenated triangle list (meshes in XML order,
//! faces in OBJ order), plus the camera and point light if the XML has them.

pub mod obj;
pub mod transform;
pub mod xml;

use crate::geom::{Aabb, Tri, D3};
use crate::scene::transform::Mat4;
use std::path::PathBuf;

#[derive(Clone, Debug)]
pub struct Camera {
    pub to_world: Mat4,
    pub fov_deg: f64,
    pub width: u32,
    pub height: u32,
    pub near: f64,
    pub far: f64,
}

#[derive(Clone, Debug)]
pub struct MeshInfo {
    pub file: PathBuf,
    /// Prim number of this mesh's first triangle.
    pub first_prim: usize,
    pub tri_count: usize,
    /// Radiance of the mesh's area emitter (`<emitter type="area">`), if any.
    pub emitter: Option<[f64; 3]>,
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub source: PathBuf,
    pub tris: Vec<Tri>,
    pub meshes: Vec<MeshInfo>,
    pub camera: Option<Camera>,
    pub point_light: Option<D3>,
    pub warnings: Vec<String>,
}

impl Scene {
    pub fn bounds(&self) -> Aabb {
        self.tris
            .iter()
            .fold(Aabb::empty(), |b, t| b.union(&t.bounds()))
    }
}
