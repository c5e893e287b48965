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

use crate::input::{self, InputError, ReadPolicy};
use crate::obj::{self, MAX_WORLD_COORD};
use crate::strict_json::{self, fields_of, FieldLister, StrictError};

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
    /// Area light: radius of a horizontal disc facing down (−y); 0 = point light.
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
    /// The scene file could not be opened or read.
    #[error("cannot read scene {}", path.display())]
    Read {
        /// Path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// A file is refused by the input rules (not a regular file, too large, not UTF-8,
    /// outside the sandbox), or a mesh file could not be read.
    #[error(transparent)]
    Input(#[from] InputError),
    /// JSON syntax, shape or type error, or (when strict) an unknown key.
    #[error("scene {path}")]
    Json {
        /// Path.
        path: String,
        /// Cause.
        source: StrictError,
    },
    /// Unknown keys in a scene read strictly.
    #[error("scene {path}: {}", keys.join("; "))]
    UnknownKeys {
        /// Path.
        path: String,
        /// One line per key.
        keys: Vec<String>,
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

pub use crate::obj::LoadedMesh;

/// Where OBJ files come from: the file system (relative to the scene) or embedded text.
pub enum MeshSource {
    /// Paths are relative to this directory; files are read under the default
    /// [`ReadPolicy`] (regular files, size limit, no sandbox).
    Dir(PathBuf),
    /// Paths are relative to this directory, read under the given policy.
    DirWith(PathBuf, ReadPolicy),
    /// Embedded files by name.
    Embedded(BTreeMap<String, String>),
}

impl MeshSource {
    fn load(&self, rel: &str) -> Result<String, SceneError> {
        let from_dir = |d: &Path, pol: &ReadPolicy| {
            let p = input::resolve_in_sandbox(d, rel, pol)?;
            Ok(input::read_text(&p, pol)?)
        };
        match self {
            MeshSource::Dir(d) => from_dir(d, &ReadPolicy::default()),
            MeshSource::DirWith(d, pol) => from_dir(d, pol),
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
    /// Things that did not stop loading but may be mistakes (unknown keys, skipped OBJ
    /// statements), one line each. The CLI prints them; `--strict` makes them errors.
    pub warnings: Vec<String>,
}

impl LoadedScene {
    /// True for a 3-D (camera) scene.
    pub fn is_3d(&self) -> bool {
        self.scene.camera.is_some()
    }
}

fn invalid(msg: String) -> SceneError {
    SceneError::Invalid(msg)
}

/// A world-space point: finite and within [`MAX_WORLD_COORD`].
fn world3(what: &str, v: &[f64; 3]) -> Result<(), SceneError> {
    if v.iter()
        .all(|x| x.is_finite() && x.abs() <= MAX_WORLD_COORD)
    {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what} {v:?} must be finite and within ±{MAX_WORLD_COORD:e}"
        )))
    }
}

fn finite3(what: &str, v: &[f64; 3]) -> Result<(), SceneError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what} has a NaN or infinite coordinate: {v:?}"
        )))
    }
}

fn colour(what: &str, c: &[f64; 3]) -> Result<(), SceneError> {
    if c.iter().all(|x| x.is_finite() && (0.0..=1.0).contains(x)) {
        Ok(())
    } else {
        Err(invalid(format!("{what} colour {c:?} is not within 0..1")))
    }
}

/// Which object each path of the scene format holds, for "did you mean" suggestions.
const SCHEMA: &[(&str, FieldLister)] = &[
    ("", fields_of::<Scene>),
    ("triangles[]", fields_of::<ScreenTriangle>),
    ("camera", fields_of::<Camera>),
    ("lights[]", fields_of::<Light>),
    ("meshes[]", fields_of::<MeshRef>),
    ("patterns[]", fields_of::<Pattern>),
    ("effects", fields_of::<EffectsSpec>),
];

/// Parses scene JSON text leniently: unknown keys are returned as warnings (one line each,
/// with the closest known key). `name` is used in messages.
pub fn parse_with_warnings(text: &str, name: &str) -> Result<(Scene, Vec<String>), SceneError> {
    let (scene, unknown) =
        strict_json::parse::<Scene>(text, SCHEMA).map_err(|e| SceneError::Json {
            path: name.to_string(),
            source: e,
        })?;
    Ok((scene, unknown.iter().map(|k| k.to_string()).collect()))
}

/// Parses scene JSON text strictly: an unknown key is an error. `name` is used in messages.
pub fn parse(text: &str, name: &str) -> Result<Scene, SceneError> {
    let (scene, keys) = parse_with_warnings(text, name)?;
    if keys.is_empty() {
        Ok(scene)
    } else {
        Err(SceneError::UnknownKeys {
            path: name.to_string(),
            keys,
        })
    }
}

fn check_resolution(s: &Scene) -> Result<(), SceneError> {
    if s.width == 0 || s.height == 0 || s.width > MAX_RESOLUTION || s.height > MAX_RESOLUTION {
        return Err(invalid(format!(
            "resolution {}x{} is outside 1x1..{MAX_RESOLUTION}x{MAX_RESOLUTION}",
            s.width, s.height
        )));
    }
    Ok(())
}

fn check_triangles(s: &Scene) -> Result<(), SceneError> {
    for (k, t) in s.triangles.iter().enumerate() {
        for p in &t.v {
            finite3(&format!("triangles[{k}].v"), p)?;
        }
        colour(&format!("triangles[{k}]"), &t.color)?;
        if let Some(cs) = &t.colors {
            for c in cs {
                colour(&format!("triangles[{k}].colors"), c)?;
            }
        }
        if let Some(h) = t.pattern_on {
            if h >= s.triangles.len() || h == k {
                return Err(invalid(format!(
                    "triangles[{k}].pattern_on {h} is not another triangle of the scene"
                )));
            }
        }
    }
    if let Some([a, b]) = s.depth_range {
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(invalid(format!(
                "depth_range [{a:?}, {b:?}] must be finite and increasing"
            )));
        }
    }
    Ok(())
}

/// The camera must define a view: eye ≠ target, and `up` not zero nor parallel to the
/// view direction (either leaves the view basis undefined and renders nothing).
fn check_camera(c: &Camera) -> Result<(), SceneError> {
    world3("camera.eye", &c.eye)?;
    world3("camera.target", &c.target)?;
    finite3("camera.up", &c.up)?;
    let d = [0, 1, 2].map(|i| c.target[i] - c.eye[i]);
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let dl = len(d);
    if dl == 0.0 || !dl.is_finite() {
        return Err(invalid(
            "camera.target equals camera.eye: the view direction is undefined".into(),
        ));
    }
    let ul = len(c.up);
    if ul == 0.0 || !ul.is_finite() {
        return Err(invalid(format!(
            "camera.up {:?} must be a non-zero direction",
            c.up
        )));
    }
    let u = c.up;
    let cross = [
        d[1] * u[2] - d[2] * u[1],
        d[2] * u[0] - d[0] * u[2],
        d[0] * u[1] - d[1] * u[0],
    ];
    // sin of the angle between up and the view direction; below ~0.06° there is no
    // usable right vector.
    if len(cross) / (dl * ul) < 1e-3 {
        return Err(invalid(format!(
            "camera.up {:?} is parallel to the view direction (target − eye)",
            c.up
        )));
    }
    if !(c.fov_y_deg.is_finite() && c.fov_y_deg > 0.0 && c.fov_y_deg < 179.0) {
        return Err(invalid(format!(
            "camera.fov_y_deg {:?} is outside (0, 179)",
            c.fov_y_deg
        )));
    }
    let near = c.near.unwrap_or(0.1);
    if !(near.is_finite() && near > 0.0) {
        return Err(invalid(format!("camera.near {near:?} must be positive")));
    }
    if let Some(f) = c.far {
        if !(f.is_finite() && f > near) {
            return Err(invalid(format!(
                "camera.far {f:?} must exceed camera.near {near:?}"
            )));
        }
    }
    Ok(())
}

fn check_lights(s: &Scene) -> Result<(), SceneError> {
    if !(s.ambient.is_finite() && (0.0..=1.0).contains(&s.ambient)) {
        return Err(invalid(format!(
            "ambient {:?} is not within 0..1",
            s.ambient
        )));
    }
    for (k, l) in s.lights.iter().enumerate() {
        world3(&format!("lights[{k}].position"), &l.position)?;
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if !ok(l.intensity) || !ok(l.radius) || l.radius > MAX_WORLD_COORD {
            return Err(invalid(format!(
                "lights[{k}]: intensity and radius must be finite and non-negative"
            )));
        }
        if let Some(n) = l.samples {
            if !(1..=64).contains(&n) {
                return Err(invalid(format!(
                    "lights[{k}].samples {n} is outside 1..=64"
                )));
            }
        }
    }
    Ok(())
}

fn check_mesh_ref(k: usize, m: &MeshRef) -> Result<(), SceneError> {
    colour(&format!("meshes[{k}]"), &m.color)?;
    world3(&format!("meshes[{k}].translate"), &m.translate)?;
    if let Some(sc) = &m.scale {
        if !sc
            .iter()
            .all(|x| x.is_finite() && *x != 0.0 && x.abs() <= MAX_WORLD_COORD)
        {
            return Err(invalid(format!(
                "meshes[{k}].scale {sc:?} must be non-zero, finite and within ±{MAX_WORLD_COORD:e}"
            )));
        }
    }
    if !m.rotate_y_deg.is_finite() {
        return Err(invalid(format!("meshes[{k}].rotate_y_deg must be finite")));
    }
    Ok(())
}

fn check_patterns(s: &Scene) -> Result<(), SceneError> {
    for (k, p) in s.patterns.iter().enumerate() {
        colour(&format!("patterns[{k}]"), &p.color)?;
        if p.on_mesh >= s.meshes.len() {
            return Err(invalid(format!(
                "patterns[{k}].on_mesh {} does not exist",
                p.on_mesh
            )));
        }
        if p.polygon.len() < 3 {
            return Err(invalid(format!(
                "patterns[{k}]: a polygon needs at least 3 vertices"
            )));
        }
        for v in &p.polygon {
            world3(&format!("patterns[{k}].polygon"), v)?;
        }
    }
    Ok(())
}

/// Validates a scene and loads its meshes.
pub fn load_with(scene: Scene, src: &MeshSource, name: &str) -> Result<LoadedScene, SceneError> {
    let s = &scene;
    check_resolution(s)?;
    colour("background", &s.background)?;
    if s.camera.is_some() && !s.triangles.is_empty() {
        return Err(invalid(
            "a scene has either screen-space \"triangles\" or a \"camera\" with meshes, not both"
                .into(),
        ));
    }
    if s.camera.is_none() && !s.meshes.is_empty() {
        return Err(invalid("meshes need a \"camera\"".into()));
    }
    check_triangles(s)?;
    if let Some(c) = &s.camera {
        check_camera(c)?;
    }
    check_lights(s)?;
    let mut meshes = Vec::new();
    let mut warnings = Vec::new();
    for (k, m) in s.meshes.iter().enumerate() {
        check_mesh_ref(k, m)?;
        let text = src.load(&m.obj)?;
        let label = format!("meshes[{k}] ({})", m.obj);
        let (mesh, notes) = obj::parse_obj(&text, &label, m)?;
        if let Some((line, first)) = notes.first_skipped {
            warnings.push(format!(
                "mesh {label}: {} statement(s) not understood and skipped (first: line {line} `{first}`)",
                notes.skipped_lines
            ));
        }
        meshes.push(mesh);
    }
    check_patterns(s)?;
    Ok(LoadedScene {
        scene,
        meshes,
        name: name.to_string(),
        warnings,
    })
}

/// The folder a scene file's OBJ paths are relative to (`.` for a bare file name); also
/// the `--sandbox` root.
pub fn scene_folder(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Loads a scene file under the default [`ReadPolicy`]; OBJ paths resolve relative to the
/// file's directory.
pub fn load_file(path: &Path) -> Result<LoadedScene, SceneError> {
    load_file_with(path, &ReadPolicy::default())
}

/// Loads a scene file under `policy`. Unknown keys become warnings on the returned scene.
pub fn load_file_with(path: &Path, policy: &ReadPolicy) -> Result<LoadedScene, SceneError> {
    let text = input::read_text(path, policy).map_err(|e| match e {
        InputError::Io { path, source } => SceneError::Read { path, source },
        e => SceneError::Input(e),
    })?;
    let name = path.display().to_string();
    let (scene, unknown) = parse_with_warnings(&text, &name)?;
    let dir = scene_folder(path);
    let mut ls = load_with(scene, &MeshSource::DirWith(dir, policy.clone()), &name)?;
    let mut warnings: Vec<String> = unknown
        .into_iter()
        .map(|k| format!("scene {name}: {k}"))
        .collect();
    warnings.append(&mut ls.warnings);
    ls.warnings = warnings;
    Ok(ls)
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
