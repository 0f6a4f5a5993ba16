//! Wavefront OBJ loading through tobj. tobj triangulates every polygon as a
//! fan (v0,vi,vi+1) in face order, so the triangle numbering is: faces in
//! file order, each n-gon giving n-2 consecutive triangles. Materials are not
//! loaded (a missing .mtl is therefore never an error).

use crate::error::{at_line, in_file};
use crate::geom::{to32, Tri};
use crate::scene::transform::Mat4;
use anyhow::{Context, Result};
use std::path::Path;

/// Load `path`, transform each vertex by `to_world` in f64 and round once to
/// f32. Rejects an unreadable file, a bad face, NaN/infinite coordinates
/// (before or after the transform) and an OBJ without any triangle.
pub fn load_obj(path: &Path, to_world: &Mat4) -> Result<Vec<Tri>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read OBJ file", path.display()))?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::BufReader::new(text.as_bytes());
    let loaded = tobj::load_obj_buf(&mut reader, &opts, |_| Err(tobj::LoadError::OpenFileFailed));
    let models = match loaded {
        Ok((models, _materials_ignored)) => models,
        Err(e) => return Err(locate_face_error(path, &text, e).into()),
    };
    let mut tris = Vec::new();
    for model in &models {
        let pos = &model.mesh.positions;
        for face in model.mesh.indices.chunks_exact(3) {
            let mut v = [[0.0f32; 3]; 3];
            for (k, &i) in face.iter().enumerate() {
                let i = i as usize;
                let p = [
                    pos[3 * i] as f64,
                    pos[3 * i + 1] as f64,
                    pos[3 * i + 2] as f64,
                ];
                if !p.iter().all(|c| c.is_finite()) {
                    return Err(locate_bad_vertex(path, &text).into());
                }
                let q = to32(to_world.point(p));
                if !q.iter().all(|c| c.is_finite()) {
                    return Err(in_file(
                        path,
                        format!("vertex {p:?} is not finite after the toWorld transform: {q:?}"),
                    )
                    .into());
                }
                v[k] = q;
            }
            tris.push(Tri { v });
        }
    }
    if tris.is_empty() {
        return Err(in_file(
            path,
            "empty mesh: no triangle (faces need at least 3 vertices)",
        )
        .into());
    }
    Ok(tris)
}

/// tobj reports face errors without a line; find the first bad `f` line.
fn locate_face_error(path: &Path, text: &str, e: tobj::LoadError) -> crate::error::InputError {
    let mut vertex_count: i64 = 0;
    for (n, line) in text.lines().enumerate() {
        let mut toks = line.split_whitespace();
        match toks.next() {
            Some("v") => {
                vertex_count += 1;
                let coords: Vec<&str> = toks.take(3).collect();
                if coords.len() < 3 || coords.iter().any(|c| c.parse::<f64>().is_err()) {
                    return at_line(
                        path,
                        n + 1,
                        format!("vertex '{}' needs 3 numbers", line.trim()),
                    );
                }
            }
            Some("f") => {
                for tok in toks {
                    let first = tok.split('/').next().unwrap_or("");
                    let Ok(i) = first.parse::<i64>() else {
                        return at_line(
                            path,
                            n + 1,
                            format!("face vertex '{tok}' is not an index"),
                        );
                    };
                    let ok = (i >= 1 && i <= vertex_count) || (i < 0 && -i <= vertex_count);
                    if !ok {
                        return at_line(
                            path,
                            n + 1,
                            format!(
                            "face index {i} out of range: {vertex_count} vertices defined so far"),
                        );
                    }
                }
            }
            _ => {}
        }
    }
    in_file(path, format!("OBJ parse error: {e}"))
}

fn locate_bad_vertex(path: &Path, text: &str) -> crate::error::InputError {
    for (n, line) in text.lines().enumerate() {
        let mut toks = line.split_whitespace();
        if toks.next() == Some("v") {
            for tok in toks.take(3) {
                if tok.parse::<f64>().map(|x| !x.is_finite()).unwrap_or(false) {
                    return at_line(
                        path,
                        n + 1,
                        format!("vertex coordinate '{tok}' is not finite"),
                    );
                }
            }
        }
    }
    in_file(path, "a vertex coordinate is not finite")
}
