//! Nori XML scenes. Accepted: <scene>, <camera type="perspective">, <mesh
//! type="obj">, <emitter type="point"> (its position is the shadow-ray
//! light). Other Nori tags are accepted and ignored; an unknown tag is a
//! warning naming it. Mesh paths are relative to the XML file's folder.

use crate::error::at_line;
use crate::scene::obj::load_obj;
use crate::scene::transform::{parse_floats, parse_vec3, Mat4};
use crate::scene::{Camera, MeshInfo, Scene};
use anyhow::{Context, Result};
use roxmltree::{Document, Node};
use std::path::Path;

const IGNORED: &[&str] = &[
    "bsdf",
    "emitter",
    "integrator",
    "sampler",
    "rfilter",
    "medium",
    "phase",
];
const PARAMS: &[&str] = &[
    "float",
    "integer",
    "string",
    "boolean",
    "point",
    "vector",
    "color",
    "transform",
];

pub fn load_scene(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read scene file", path.display()))?;
    let doc = Document::parse(&text).map_err(|e| {
        let p = e.pos();
        at_line(
            path,
            p.row as usize,
            format!("malformed XML (column {}): {e}", p.col),
        )
    })?;
    let ctx = Ctx { path, doc: &doc };
    let root = doc.root_element();
    if root.tag_name().name() != "scene" {
        return Err(ctx.err(
            root,
            format!(
                "root element is <{}>, expected <scene>",
                root.tag_name().name()
            ),
        ));
    }
    let base = path.parent().unwrap_or(Path::new("."));
    let mut scene = Scene {
        source: path.to_path_buf(),
        tris: Vec::new(),
        meshes: Vec::new(),
        camera: None,
        point_light: None,
        warnings: Vec::new(),
    };
    for el in root.children().filter(|n| n.is_element()) {
        if matches!(el.tag_name().name(), "camera" | "mesh") {
            ctx.warn_unknown_children(el, &mut scene.warnings);
        }
        match el.tag_name().name() {
            "camera" => scene.camera = Some(ctx.camera(el)?),
            "mesh" => {
                let (file, to_world) = ctx.mesh(el, base)?;
                let tris = load_obj(&file, &to_world).with_context(|| {
                    format!("{}:{}: in this <mesh>", path.display(), ctx.line(el))
                })?;
                let emitter = ctx.area_emitter(el)?;
                scene.meshes.push(MeshInfo {
                    file,
                    first_prim: scene.tris.len(),
                    tri_count: tris.len(),
                    emitter,
                });
                scene.tris.extend(tris);
            }
            "emitter" if el.attribute("type") == Some("point") => {
                if let Some(p) = ctx.param(el, "point", "position") {
                    scene.point_light = Some(ctx.vec3(p)?);
                }
            }
            name if IGNORED.contains(&name) || PARAMS.contains(&name) => {}
            name => scene.warnings.push(format!(
                "{}:{}: warning: unknown tag <{name}> ignored",
                path.display(),
                ctx.line(el)
            )),
        }
    }
    if scene.tris.is_empty() {
        return Err(ctx.err(root, "the scene has no <mesh>".to_string()));
    }
    Ok(scene)
}

struct Ctx<'a, 'b> {
    path: &'a Path,
    doc: &'a Document<'b>,
}

impl Ctx<'_, '_> {
    fn line(&self, n: Node) -> usize {
        self.doc.text_pos_at(n.range().start).row as usize
    }

    /// Children of <camera>/<mesh> other than parameters and Nori's nested
    /// objects get a warning naming them.
    fn warn_unknown_children(&self, el: Node, warnings: &mut Vec<String>) {
        for c in el.children().filter(|n| n.is_element()) {
            let name = c.tag_name().name();
            if !PARAMS.contains(&name) && !IGNORED.contains(&name) {
                warnings.push(format!(
                    "{}:{}: warning: unknown tag <{name}> in <{}> ignored",
                    self.path.display(),
                    self.line(c),
                    el.tag_name().name()
                ));
            }
        }
    }

    fn err(&self, n: Node, msg: String) -> anyhow::Error {
        at_line(self.path, self.line(n), msg).into()
    }

    fn attr<'n>(&self, n: Node<'n, '_>, name: &str) -> Result<&'n str> {
        n.attribute(name).ok_or_else(|| {
            self.err(
                n,
                format!("<{}> needs a '{name}' attribute", n.tag_name().name()),
            )
        })
    }

    fn param<'n, 'i>(&self, el: Node<'n, 'i>, tag: &str, name: &str) -> Option<Node<'n, 'i>> {
        el.children().find(|c| {
            c.is_element() && c.tag_name().name() == tag && c.attribute("name") == Some(name)
        })
    }

    fn number(&self, n: Node) -> Result<f64> {
        let v = self.attr(n, "value")?;
        match v.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.err(n, format!("value '{v}' is not a finite number"))),
        }
    }

    fn vec3(&self, n: Node) -> Result<[f64; 3]> {
        parse_vec3(self.attr(n, "value")?).map_err(|m| self.err(n, m))
    }

    fn camera(&self, el: Node) -> Result<Camera> {
        let kind = self.attr(el, "type")?;
        if kind != "perspective" {
            return Err(self.err(
                el,
                format!("camera type '{kind}' is not supported (only 'perspective')"),
            ));
        }
        let float = |name: &str, default: f64| -> Result<f64> {
            self.param(el, "float", name)
                .map_or(Ok(default), |n| self.number(n))
        };
        let size = |name: &str, default: u32| -> Result<u32> {
            let Some(n) = self.param(el, "integer", name) else {
                return Ok(default);
            };
            let v = self.attr(n, "value")?;
            match v.trim().parse::<u32>() {
                Ok(x) if x > 0 && x <= 1 << 16 => Ok(x),
                _ => Err(self.err(
                    n,
                    format!("camera {name} '{v}' must be an integer in 1..=65536"),
                )),
            }
        };
        let cam = Camera {
            to_world: self.transform_param(el, "toWorld")?,
            fov_deg: float("fov", 30.0)?,
            width: size("width", 1280)?,
            height: size("height", 720)?,
            near: float("nearClip", 1e-4)?,
            far: float("farClip", 1e4)?,
        };
        if !(cam.fov_deg > 0.0 && cam.fov_deg < 180.0 && cam.near > 0.0 && cam.near < cam.far) {
            return Err(self.err(
                el,
                format!(
                    "camera fov {} must be in (0,180) and 0 < nearClip {} < farClip {}",
                    cam.fov_deg, cam.near, cam.far
                ),
            ));
        }
        Ok(cam)
    }

    /// A mesh's `<emitter type="area">` radiance (Nori's `radiance` colour), if it has one.
    fn area_emitter(&self, el: Node) -> Result<Option<[f64; 3]>> {
        let Some(e) = el
            .children()
            .find(|c| c.is_element() && c.tag_name().name() == "emitter")
        else {
            return Ok(None);
        };
        if e.attribute("type") != Some("area") {
            return Ok(None);
        }
        let c = self.param(e, "color", "radiance").ok_or_else(|| {
            self.err(
                e,
                "<emitter type=\"area\"> needs <color name=\"radiance\">".into(),
            )
        })?;
        Ok(Some(self.vec3(c)?))
    }

    fn mesh(&self, el: Node, base: &Path) -> Result<(std::path::PathBuf, Mat4)> {
        let kind = self.attr(el, "type")?;
        if kind != "obj" {
            return Err(self.err(
                el,
                format!("mesh type '{kind}' is not supported (only 'obj')"),
            ));
        }
        let f = self
            .param(el, "string", "filename")
            .ok_or_else(|| self.err(el, "<mesh> needs <string name=\"filename\">".into()))?;
        let file = base.join(self.attr(f, "value")?);
        Ok((file, self.transform_param(el, "toWorld")?))
    }

    fn transform_param(&self, el: Node, name: &str) -> Result<Mat4> {
        match self.param(el, "transform", name) {
            Some(t) => self.transform(t),
            None => Ok(Mat4::identity()),
        }
    }

    /// Nori's order: each child left-multiplies the running matrix.
    pub fn transform(&self, t: Node) -> Result<Mat4> {
        let mut m = Mat4::identity();
        for c in t.children().filter(|n| n.is_element()) {
            let step = match c.tag_name().name() {
                "translate" => Mat4::translate(self.vec3(c)?),
                "scale" => Mat4::scale(self.vec3(c)?),
                "rotate" => {
                    let axis = parse_vec3(self.attr(c, "axis")?).map_err(|e| self.err(c, e))?;
                    let angle = self.attr(c, "angle")?;
                    let deg = angle
                        .trim()
                        .parse::<f64>()
                        .map_err(|_| self.err(c, format!("angle '{angle}' is not a number")))?;
                    if axis == [0.0; 3] {
                        return Err(self.err(c, "rotate axis is zero".into()));
                    }
                    Mat4::rotate(axis, deg)
                }
                "matrix" => {
                    let v = parse_floats(self.attr(c, "value")?).map_err(|e| self.err(c, e))?;
                    let arr: [f64; 16] = v.try_into().map_err(|v: Vec<f64>| {
                        self.err(c, format!("matrix needs 16 numbers, got {}", v.len()))
                    })?;
                    Mat4::from_rows(&arr)
                }
                "lookat" => {
                    let g = |a: &str| -> Result<[f64; 3]> {
                        parse_vec3(self.attr(c, a)?).map_err(|e| self.err(c, e))
                    };
                    Mat4::lookat(g("origin")?, g("target")?, g("up")?)
                }
                other => return Err(self.err(c, format!("unknown transform element <{other}>"))),
            };
            m = step.mul(&m);
        }
        if m.m.iter().flatten().any(|x| !x.is_finite()) {
            return Err(self.err(
                t,
                "transform is not finite (degenerate lookat or rotate?)".into(),
            ));
        }
        Ok(m)
    }
}

#[cfg(test)]
#[path = "xml_tests.rs"]
mod tests;
