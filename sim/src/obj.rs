//! Wavefront OBJ meshes: a line check in front of `tobj`, then the mesh transform.
//!
//! `tobj` parses the geometry; it silently skips statements it does not know, and its errors
//! carry no line number. The check here runs first, on the same text:
//! - `v` lines must hold 3 coordinates (4 with the optional `w`, 6 or 7 with vertex
//!   colours), each a finite number; an error names the mesh, the line and the vertex;
//! - statements outside the geometric subset (`v vt vn vp f l p o g s usemtl mtllib`) are
//!   counted and reported once as a warning, with the first such line.
//!
//! The transform (scale, rotation about +y, translation) must leave every vertex within
//! [`MAX_WORLD_COORD`]: a scene whose coordinates overflow would otherwise fit an infinite
//! far plane and render the background only.

use crate::scene::{MeshRef, SceneError};

/// Largest accepted world-space coordinate magnitude (after a mesh's transform; also for
/// the camera, lights and patterns). Far beyond any sensible scene, far below where the
/// projection and the fitted far plane lose their precision.
pub const MAX_WORLD_COORD: f64 = 1e9;

/// Triangles of one loaded mesh, world space after its transform.
#[derive(Clone, Debug)]
pub struct LoadedMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Vertex normals (same length as positions) when the OBJ has them.
    pub normals: Option<Vec<[f64; 3]>>,
    /// Triangle vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

const KNOWN: &[&str] = &[
    "v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s", "usemtl", "mtllib",
];

/// What the line check found besides errors.
#[derive(Clone, Debug, Default)]
pub struct ObjNotes {
    /// Statements that were not understood and skipped.
    pub skipped_lines: usize,
    /// The first of them: (line number, text).
    pub first_skipped: Option<(usize, String)>,
}

fn mesh_err(path: &str, msg: String) -> SceneError {
    SceneError::Mesh {
        path: path.to_string(),
        msg,
    }
}

/// Checks every statement of `text`; see the module header.
pub fn check_lines(text: &str, path: &str) -> Result<ObjNotes, SceneError> {
    let mut notes = ObjNotes::default();
    let mut vertex = 0usize;
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        let mut it = line.split_whitespace();
        let Some(kw) = it.next() else { continue };
        if kw == "v" {
            vertex += 1;
            let coords: Vec<&str> = it.collect();
            if !matches!(coords.len(), 3 | 4 | 6 | 7) {
                return Err(mesh_err(
                    path,
                    format!(
                        "line {}: vertex {vertex} has {} numbers; expected x y z [w] or x y z r g b",
                        i + 1,
                        coords.len()
                    ),
                ));
            }
            for c in &coords {
                match c.parse::<f64>() {
                    Ok(x) if x.is_finite() && x.abs() < f32::MAX as f64 => {}
                    _ => {
                        return Err(mesh_err(
                            path,
                            format!(
                                "line {}: vertex {vertex} coordinate `{}` is not finite",
                                i + 1,
                                shorten(c)
                            ),
                        ))
                    }
                }
            }
        } else if !KNOWN.contains(&kw) {
            notes.skipped_lines += 1;
            if notes.first_skipped.is_none() {
                notes.first_skipped = Some((i + 1, shorten(line)));
            }
        }
    }
    Ok(notes)
}

/// At most 40 characters of `s`, for messages.
fn shorten(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        format!("{}…", s.chars().take(40).collect::<String>())
    }
}

/// Parses an OBJ text and applies the mesh's transform. `label` names the mesh in messages.
pub fn parse_obj(
    text: &str,
    label: &str,
    m: &MeshRef,
) -> Result<(LoadedMesh, ObjNotes), SceneError> {
    let notes = check_lines(text, label)?;
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let mut rd = std::io::BufReader::new(text.as_bytes());
    let (models, _) = tobj::load_obj_buf(&mut rd, &opts, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| mesh_err(label, e.to_string()))?;
    let xf = Transform::new(m);
    let mut out = LoadedMesh {
        positions: vec![],
        normals: Some(vec![]),
        triangles: vec![],
    };
    for md in models {
        let mesh = md.mesh;
        let base = out.positions.len() as u32;
        for p in mesh.positions.chunks_exact(3) {
            let w = xf.point([p[0] as f64, p[1] as f64, p[2] as f64]);
            if !w
                .iter()
                .all(|x| x.is_finite() && x.abs() <= MAX_WORLD_COORD)
            {
                return Err(mesh_err(
                    label,
                    format!(
                        "vertex {} lands at {w:?} after scale/rotate_y_deg/translate, outside ±{MAX_WORLD_COORD:e}",
                        out.positions.len() + 1
                    ),
                ));
            }
            out.positions.push(w);
        }
        let has_n = mesh.normals.len() == mesh.positions.len();
        match (&mut out.normals, has_n) {
            (Some(ns), true) => {
                for n in mesh.normals.chunks_exact(3) {
                    ns.push(xf.normal([n[0] as f64, n[1] as f64, n[2] as f64]));
                }
            }
            (ns, _) => *ns = None,
        }
        for t in mesh.indices.chunks_exact(3) {
            out.triangles.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    if out.triangles.is_empty() {
        return Err(mesh_err(label, "no faces".into()));
    }
    Ok((out, notes))
}

/// A mesh's placement: scale, then rotation about +y, then translation.
struct Transform {
    scale: [f64; 3],
    sin: f64,
    cos: f64,
    translate: [f64; 3],
}

impl Transform {
    fn new(m: &MeshRef) -> Transform {
        let (sin, cos) = m.rotate_y_deg.to_radians().sin_cos();
        Transform {
            scale: m.scale.unwrap_or([1.0; 3]),
            sin,
            cos,
            translate: m.translate,
        }
    }

    fn point(&self, p: [f64; 3]) -> [f64; 3] {
        let (s, t) = (self.scale, self.translate);
        let q = [p[0] * s[0], p[1] * s[1], p[2] * s[2]];
        [
            self.cos * q[0] + self.sin * q[2] + t[0],
            q[1] + t[1],
            -self.sin * q[0] + self.cos * q[2] + t[2],
        ]
    }

    fn normal(&self, n: [f64; 3]) -> [f64; 3] {
        let s = self.scale;
        let q = [n[0] / s[0], n[1] / s[1], n[2] / s[2]];
        [
            self.cos * q[0] + self.sin * q[2],
            q[1],
            -self.sin * q[0] + self.cos * q[2],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_lines_are_checked_with_line_numbers() {
        let e = check_lines("v 0 0 0\nv 1 2\n", "m.obj")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 2") && e.contains("vertex 2 has 2 numbers"),
            "{e}"
        );
        let e = check_lines("# c\nv 0 nan 0\n", "m.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("`nan`"), "{e}");
        let e = check_lines("v 0 1e999 0\n", "m.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("is not finite"), "{e}");
        assert!(check_lines("v 0 0 0 1\nv 0 0 0 1 0 0\n", "m.obj").is_ok());
    }

    #[test]
    fn unknown_statements_are_counted_once() {
        let n = check_lines("v 0 0 0\nfoo 1\nbar\nf 1 1 1\nfoo 2\n", "m.obj").unwrap();
        assert_eq!(n.skipped_lines, 3);
        assert_eq!(n.first_skipped, Some((2, "foo 1".to_string())));
    }
}
