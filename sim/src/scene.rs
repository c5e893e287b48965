//! Scene description (serde, JSON) and loading.
//!
//! Two kinds of scene share one file format:
//! - **screen-space**: `{"width", "height", "background", "triangles": [{"v": [[x,y,z]×3],
//!   "color": [r,g,b]}]}`, x right, y down in pixels, z planar per triangle, smaller nearer;
//! - **3-D**: `{"width", "height", "background", "camera": {...}, "lights": [...],
//!   "meshes": [{"obj": "relative/path.obj", "color": [r,g,b]}]}` with Wavefront OBJ meshes.
//!
//! Optional fields (`effects`, per-light `shadows`, area lights, `patterns`, `tag`,
//! `depth_range`) are documented in `docs/scenes.md`.

use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Largest accepted `width` or `height` (the span word's 12-bit XL/XR).
pub const MAX_RESOLUTION: u32 = pixelproc_formats::MAX_SCREEN;

/// A scene as written in the file.
#[derive(Clone, Debug, Deserialize)]
pub struct Scene {
    /// Image width in pixels (1..=4096).
    pub width: u32,
    /// Image height in pixels (1..=4096).
    pub height: u32,
    /// Background colour, linear 0..1.
    #[serde(default)]
    pub background: [f64; 3],
    /// Screen-space triangles (screen-space scene).
    #[serde(default)]
    pub triangles: Vec<ScreenTriangle>,
    /// Screen-space depth range mapped onto the 24-bit depth buffer. Default: the
    /// smallest and largest z of the triangles.
    #[serde(default)]
    pub depth_range: Option<[f64; 2]>,
    /// Camera (3-D scene).
    #[serde(default)]
    pub camera: Option<Camera>,
    /// Point (or area) lights (3-D scene).
    #[serde(default)]
    pub lights: Vec<Light>,
    /// Ambient light level, 0..1 (3-D scene). Default 0.2.
    #[serde(default = "default_ambient")]
    pub ambient: f64,
    /// OBJ meshes (3-D scene).
    #[serde(default)]
    pub meshes: Vec<MeshRef>,
    /// Patterns: coplanar convex polygons drawn on a face of a mesh (3-D scene).
    #[serde(default)]
    pub patterns: Vec<Pattern>,
    /// Effects the scene asks for.
    #[serde(default)]
    pub effects: EffectsSpec,
}

fn default_ambient() -> f64 {
    0.2
}

/// A screen-space triangle.
#[derive(Clone, Debug, Deserialize)]
pub struct ScreenTriangle {
    /// Vertices `[x, y, z]`: pixels, y down; z planar, smaller nearer.
    pub v: [[f64; 3]; 3],
    /// Colour, linear 0..1.
    pub color: [f64; 3],
    /// Per-vertex colours (Gouraud), overriding `color`.
    #[serde(default)]
    pub colors: Option<[[f64; 3]; 3]>,
    /// Object tag (default: the triangle's index + 1, so every triangle is its own object).
    #[serde(default)]
    pub tag: Option<u16>,
    /// Index of the triangle this one is a pattern (decal) on: it takes that triangle's
    /// depth plane and wins depth ties against it.
    #[serde(default)]
    pub pattern_on: Option<usize>,
}

/// Perspective camera.
#[derive(Clone, Debug, Deserialize)]
pub struct Camera {
    /// Eye position.
    pub eye: [f64; 3],
    /// Point looked at.
    pub target: [f64; 3],
    /// Up direction.
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_y_deg: f64,
    /// Near plane distance (default 0.1).
    #[serde(default)]
    pub near: Option<f64>,
    /// Far plane distance (default: fitted to the scene's bounds).
    #[serde(default)]
    pub far: Option<f64>,
}

/// A point light, or an area light sampled by several point lights.
#[derive(Clone, Debug, Deserialize)]
pub struct Light {
    /// Position (the centre, for an area light).
    pub position: [f64; 3],
    /// Intensity multiplier (default 1).
    #[serde(default = "one")]
    pub intensity: f64,
    /// Whether the light casts shadows (default true).
    #[serde(default = "yes")]
    pub shadows: bool,
    /// Area light: radius of a disc facing the scene centre; 0 = point light.
    #[serde(default)]
    pub radius: f64,
    /// Area light: number of point lights sampling the disc (default 8 when radius > 0).
    #[serde(default)]
    pub samples: Option<u32>,
}

fn one() -> f64 {
    1.0
}
fn yes() -> bool {
    true
}

/// A mesh loaded from an OBJ file.
#[derive(Clone, Debug, Deserialize)]
pub struct MeshRef {
    /// OBJ path relative to the scene file.
    pub obj: String,
    /// Colour, linear 0..1.
    pub color: [f64; 3],
    /// Object tag (default: mesh index + 1).
    #[serde(default)]
    pub tag: Option<u16>,
    /// Translation applied after scaling.
    #[serde(default)]
    pub translate: [f64; 3],
    /// Uniform or per-axis scale (default 1).
    #[serde(default)]
    pub scale: Option<[f64; 3]>,
    /// Rotation about +y in degrees, applied after scaling.
    #[serde(default)]
    pub rotate_y_deg: f64,
    /// Whether the mesh casts shadows (default true).
    #[serde(default = "yes")]
    pub casts_shadows: bool,
}

/// A pattern: a convex planar polygon (world space) lying on a face of a mesh.
#[derive(Clone, Debug, Deserialize)]
pub struct Pattern {
    /// Index of the mesh the pattern lies on.
    pub on_mesh: usize,
    /// Convex polygon vertices, world space, on one face of the mesh.
    pub polygon: Vec<[f64; 3]>,
    /// Colour, linear 0..1.
    pub color: [f64; 3],
}

/// Effects requested by the scene. Command-line flags override these.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct EffectsSpec {
    /// Anti-aliasing method and parameters (default: none): a method name or an object
    /// `{"method": ..., parameters}`.
    #[serde(default)]
    pub aa: Option<crate::plan::AaSpec>,
    /// Surfaces may interpenetrate (enables max-depth search in the A-buffer).
    #[serde(default)]
    pub interpenetrating: bool,
    /// Master switch for shadows (default true: every light with `shadows` casts them).
    #[serde(default)]
    pub shadows: Option<bool>,
}

/// Errors while reading a scene.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene {}", path.display())]
    Read {
        /// Path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// JSON syntax or schema error (serde reports line and column).
    #[error("scene {path}")]
    Json {
        /// Path.
        path: String,
        /// Cause.
        source: serde_json::Error,
    },
    /// A mesh file could not be read or parsed.
    #[error("mesh {path}: {msg}")]
    Mesh {
        /// Path.
        path: String,
        /// What went wrong.
        msg: String,
    },
    /// A value is invalid.
    #[error("{0}")]
    Invalid(String),
}

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

/// Where OBJ files come from: the file system (relative to the scene) or embedded text.
pub enum MeshSource {
    /// Paths are relative to this directory.
    Dir(PathBuf),
    /// Embedded files by name.
    Embedded(BTreeMap<String, String>),
}

impl MeshSource {
    fn load(&self, rel: &str) -> Result<String, SceneError> {
        match self {
            MeshSource::Dir(d) => {
                let p = d.join(rel);
                std::fs::read_to_string(&p).map_err(|e| SceneError::Mesh {
                    path: p.display().to_string(),
                    msg: e.to_string(),
                })
            }
            MeshSource::Embedded(m) => m.get(rel).cloned().ok_or_else(|| SceneError::Mesh {
                path: rel.to_string(),
                msg: "no such embedded file".into(),
            }),
        }
    }
}

/// A parsed, validated scene with its meshes loaded.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The scene description.
    pub scene: Scene,
    /// Meshes, in the order of `scene.meshes`.
    pub meshes: Vec<LoadedMesh>,
    /// Display name (file name or built-in name).
    pub name: String,
}

impl LoadedScene {
    /// True for a 3-D (camera) scene.
    pub fn is_3d(&self) -> bool {
        self.scene.camera.is_some()
    }
}

fn finite3(what: &str, v: &[f64; 3]) -> Result<(), SceneError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(SceneError::Invalid(format!(
            "{what} has a NaN or infinite coordinate: {v:?}"
        )))
    }
}

fn colour(what: &str, c: &[f64; 3]) -> Result<(), SceneError> {
    if c.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)) {
        Ok(())
    } else {
        Err(SceneError::Invalid(format!(
            "{what} colour {c:?} is not within 0..1"
        )))
    }
}

/// Parses scene JSON text. `name` is used in messages.
pub fn parse(text: &str, name: &str) -> Result<Scene, SceneError> {
    serde_json::from_str(text).map_err(|e| SceneError::Json {
        path: name.to_string(),
        source: e,
    })
}

/// Validates a scene and loads its meshes.
pub fn load_with(scene: Scene, src: &MeshSource, name: &str) -> Result<LoadedScene, SceneError> {
    let s = &scene;
    if s.width == 0 || s.height == 0 || s.width > MAX_RESOLUTION || s.height > MAX_RESOLUTION {
        return Err(SceneError::Invalid(format!(
            "resolution {}x{} is outside 1x1..{MAX_RESOLUTION}x{MAX_RESOLUTION}",
            s.width, s.height
        )));
    }
    colour("background", &s.background)?;
    if s.camera.is_some() && !s.triangles.is_empty() {
        return Err(SceneError::Invalid(
            "a scene has either screen-space \"triangles\" or a \"camera\" with meshes, not both"
                .into(),
        ));
    }
    if s.camera.is_none() && !s.meshes.is_empty() {
        return Err(SceneError::Invalid("meshes need a \"camera\"".into()));
    }
    for (k, t) in s.triangles.iter().enumerate() {
        for p in &t.v {
            finite3(&format!("triangle {k}"), p)?;
        }
        colour(&format!("triangle {k}"), &t.color)?;
        if let Some(cs) = &t.colors {
            for c in cs {
                colour(&format!("triangle {k}"), c)?;
            }
        }
        if let Some(h) = t.pattern_on {
            if h >= s.triangles.len() || h == k {
                return Err(SceneError::Invalid(format!(
                    "triangle {k}: pattern_on {h} is not another triangle of the scene"
                )));
            }
        }
    }
    if let Some([a, b]) = s.depth_range {
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(SceneError::Invalid(format!(
                "depth_range [{a}, {b}] must be finite and increasing"
            )));
        }
    }
    if let Some(c) = &s.camera {
        finite3("camera eye", &c.eye)?;
        finite3("camera target", &c.target)?;
        finite3("camera up", &c.up)?;
        if !(c.fov_y_deg.is_finite() && c.fov_y_deg > 0.0 && c.fov_y_deg < 179.0) {
            return Err(SceneError::Invalid(format!(
                "camera fov_y_deg {} is outside (0, 179)",
                c.fov_y_deg
            )));
        }
        let near = c.near.unwrap_or(0.1);
        if !(near.is_finite() && near > 0.0) {
            return Err(SceneError::Invalid(format!(
                "camera near {near} must be positive"
            )));
        }
        if let Some(f) = c.far {
            if !(f.is_finite() && f > near) {
                return Err(SceneError::Invalid(format!(
                    "camera far {f} must exceed near {near}"
                )));
            }
        }
    }
    if !(s.ambient.is_finite() && (0.0..=1.0).contains(&s.ambient)) {
        return Err(SceneError::Invalid(format!(
            "ambient {} is not within 0..1",
            s.ambient
        )));
    }
    for (k, l) in s.lights.iter().enumerate() {
        finite3(&format!("light {k}"), &l.position)?;
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if !ok(l.intensity) || !ok(l.radius) {
            return Err(SceneError::Invalid(format!(
                "light {k}: intensity and radius must be finite and non-negative"
            )));
        }
        if let Some(n) = l.samples {
            if !(1..=64).contains(&n) {
                return Err(SceneError::Invalid(format!(
                    "light {k}: samples {n} is outside 1..=64"
                )));
            }
        }
    }
    let mut meshes = Vec::new();
    for (k, m) in s.meshes.iter().enumerate() {
        colour(&format!("mesh {k}"), &m.color)?;
        finite3(&format!("mesh {k} translate"), &m.translate)?;
        let text = src.load(&m.obj)?;
        meshes.push(parse_obj(&text, &m.obj, m)?);
    }
    for (k, p) in s.patterns.iter().enumerate() {
        colour(&format!("pattern {k}"), &p.color)?;
        if p.on_mesh >= s.meshes.len() {
            return Err(SceneError::Invalid(format!(
                "pattern {k}: on_mesh {} does not exist",
                p.on_mesh
            )));
        }
        if p.polygon.len() < 3 {
            return Err(SceneError::Invalid(format!(
                "pattern {k}: a polygon needs at least 3 vertices"
            )));
        }
        for v in &p.polygon {
            finite3(&format!("pattern {k}"), v)?;
        }
    }
    Ok(LoadedScene {
        scene,
        meshes,
        name: name.to_string(),
    })
}

fn parse_obj(text: &str, path: &str, m: &MeshRef) -> Result<LoadedMesh, SceneError> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let mut rd = std::io::BufReader::new(text.as_bytes());
    let (models, _) = tobj::load_obj_buf(&mut rd, &opts, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| SceneError::Mesh {
            path: path.to_string(),
            msg: e.to_string(),
        })?;
    let scale = m.scale.unwrap_or([1.0; 3]);
    let (sin, cos) = m.rotate_y_deg.to_radians().sin_cos();
    let xf = |p: [f64; 3]| {
        let q = [p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]];
        [
            cos * q[0] + sin * q[2] + m.translate[0],
            q[1] + m.translate[1],
            -sin * q[0] + cos * q[2] + m.translate[2],
        ]
    };
    let xn = |n: [f64; 3]| {
        let q = [n[0] / scale[0], n[1] / scale[1], n[2] / scale[2]];
        [cos * q[0] + sin * q[2], q[1], -sin * q[0] + cos * q[2]]
    };
    let mut out = LoadedMesh {
        positions: vec![],
        normals: Some(vec![]),
        triangles: vec![],
    };
    for md in models {
        let mesh = md.mesh;
        let base = out.positions.len() as u32;
        for p in mesh.positions.chunks_exact(3) {
            let v = [p[0] as f64, p[1] as f64, p[2] as f64];
            if !v.iter().all(|x| x.is_finite()) {
                return Err(SceneError::Mesh {
                    path: path.into(),
                    msg: format!("vertex {v:?} is not finite"),
                });
            }
            out.positions.push(xf(v));
        }
        let has_n = mesh.normals.len() == mesh.positions.len();
        match (&mut out.normals, has_n) {
            (Some(ns), true) => {
                for n in mesh.normals.chunks_exact(3) {
                    ns.push(xn([n[0] as f64, n[1] as f64, n[2] as f64]));
                }
            }
            (ns, _) => *ns = None,
        }
        for t in mesh.indices.chunks_exact(3) {
            out.triangles.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    if out.triangles.is_empty() {
        return Err(SceneError::Mesh {
            path: path.into(),
            msg: "no faces".into(),
        });
    }
    Ok(out)
}

/// Loads a scene file; OBJ paths resolve relative to the file's directory.
pub fn load_file(path: &Path) -> Result<LoadedScene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
        path: path.to_path_buf(),
        source: e,
    })?;
    let name = path.display().to_string();
    let scene = parse(&text, &name)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    load_with(scene, &MeshSource::Dir(dir), &name)
}

/// The embedded default scene: boxes and an L-shaped block over a ground plane, one light,
/// and a wall with a window pattern.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/default.json");

fn embedded_meshes() -> BTreeMap<String, String> {
    let files = [
        ("box.obj", include_str!("../../scenes/box.obj")),
        ("ground.obj", include_str!("../../scenes/ground.obj")),
        ("lblock.obj", include_str!("../../scenes/lblock.obj")),
        ("wall.obj", include_str!("../../scenes/wall.obj")),
    ];
    files
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// Loads a built-in scene by name: `default` (the embedded scene) or `boxes` (a procedural
/// 1920×1080 3-D scene of about 10,000 triangles, for benchmarks).
pub fn load_builtin(name: &str) -> Result<LoadedScene, SceneError> {
    match name {
        "default" => {
            let scene = parse(DEFAULT_SCENE, "@default")?;
            load_with(scene, &MeshSource::Embedded(embedded_meshes()), "@default")
        }
        "boxes" => {
            let (json, files) = crate::builtin::boxes_scene();
            let scene = parse(&json, "@boxes")?;
            load_with(scene, &MeshSource::Embedded(files), "@boxes")
        }
        _ => Err(SceneError::Invalid(format!(
            "unknown built-in scene @{name} (known: @default, @boxes)"
        ))),
    }
}
