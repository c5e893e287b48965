//! `pixelproc bench --all-methods`: the cost of every anti-aliasing method at its default
//! setting, and of shadows, relative to the plain frame of the same scene.
//!
//! Scenes are generated in code at 1920×1080 ([`bench_scenes`]): a few large triangles
//! (`large`), the built-in `@boxes` city (about 10k small triangles, hundreds of shadow
//! volumes), and two tessellated grids with the same coverage and 10× apart in triangle
//! count (`grid-1k`, `grid-10k`), which show whether a method's cost grows linearly with
//! the work (spans, fragments) rather than with the triangles per row; then five harder
//! scenes ([`hard_scenes`]: high depth complexity, long shadow volumes, large closed
//! casters, thousands of volumes, non-convex casters with a volume per face).
//!
//! Every case of a scene is rendered once as a warm-up, then the cases are timed in turn,
//! `runs` rounds (interleaved, so a busy machine slows every case alike); the table gives
//! each case's median wall time through the whole pipeline
//! ([`pixelproc_sim::pipeline::render`]), its ratio to the plain frame, the time per unit
//! of work the method counts (span word, fragment, shadow span word, sub-scanline piece,
//! sample), and the peak resident memory of one render (Linux: the high-water mark is
//! reset before each case; elsewhere not measured). Large buffers are fresh mappings in
//! every render (glibc), so neither times nor peaks depend on the order of the cases; the
//! one exception, the shadow command lists the renderer keeps from frame to frame (at
//! most 118 MB, `pixelproc_sim::render::release_shadow_lists`), is released before each
//! case's warm-up, which measures its peak, and refilled by it.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::time::Instant;

use pixelproc_sim::pipeline::{render, AaReport, RenderOutput};
use pixelproc_sim::plan::{AaKind, AaSpec, Effects, MultiscanSpec, Overrides, SsaaSpec};
use pixelproc_sim::rng::Lcg64;
use pixelproc_sim::scene::{self, LoadedScene, MeshSource};

/// One timed configuration.
#[derive(Clone, Debug)]
pub struct Case {
    /// Short name (`plain`, `shadows`, `abuffer`, …).
    pub name: &'static str,
    /// What the case renders.
    pub about: &'static str,
    /// The overrides that select it.
    pub overrides: Overrides,
}

/// The cases: plain, shadows (every light of the scene), then each anti-aliasing method at
/// its default setting without shadows (multi-scanning with n = 4, supersampling 2×2: the
/// settings the performance targets name).
pub fn cases() -> Vec<Case> {
    let aa = |kind: AaKind| Some(AaSpec::default_for(kind));
    let no_shadows = |aa: Option<AaSpec>| Overrides {
        aa: aa.or(Some(AaSpec::None)),
        no_shadows: true,
        ..Default::default()
    };
    vec![
        Case {
            name: "plain",
            about: "no AA, no shadows",
            overrides: no_shadows(None),
        },
        Case {
            name: "shadows",
            about: "no AA, the scene's lights",
            overrides: Overrides {
                aa: Some(AaSpec::None),
                ..Default::default()
            },
        },
        Case {
            name: "abuffer",
            about: "A-buffer 4x4, depth search",
            overrides: no_shadows(aa(AaKind::Abuffer)),
        },
        Case {
            name: "multiscan",
            about: "multi-scanning n=4, box",
            overrides: no_shadows(Some(AaSpec::Multiscan(MultiscanSpec {
                subscanlines: 4,
                ..Default::default()
            }))),
        },
        Case {
            name: "corner",
            about: "corner sampling, 1 spp",
            overrides: no_shadows(aa(AaKind::Corner)),
        },
        Case {
            name: "ssaa",
            about: "supersampling 2x2",
            overrides: no_shadows(Some(AaSpec::Ssaa(SsaaSpec { ssaa: 2 }))),
        },
        Case {
            name: "postfx",
            about: "post-process, defaults",
            overrides: no_shadows(aa(AaKind::PostFx)),
        },
    ]
}

/// A generated scene: its JSON and its OBJ files by name.
pub type GenScene = (String, BTreeMap<String, String>);

/// A ground quad and `n` boxes on it at 1080p, one light: the scene JSON and its OBJ files.
fn box_scene(boxes: &[([f64; 3], [f64; 3], f64)]) -> GenScene {
    let files = ground_and_box();
    let mut meshes = vec![
        r#"{"obj": "ground.obj", "color": [0.55, 0.6, 0.5], "casts_shadows": false}"#.to_string(),
    ];
    for (k, (t, s, r)) in boxes.iter().enumerate() {
        let c = 0.3 + 0.1 * (k % 6) as f64;
        meshes.push(format!(
            r#"{{"obj": "box.obj", "color": [{c:.2}, 0.45, 0.7], "translate": [{}, {}, {}], "scale": [{}, {}, {}], "rotate_y_deg": {r}}}"#,
            t[0], t[1], t[2], s[0], s[1], s[2]
        ));
    }
    (scene_json(&meshes), files)
}

/// A unit box (−0.5..0.5, 0..1, −0.5..0.5) as an OBJ.
fn box_obj() -> String {
    let mut s = String::new();
    for (x, y, z) in [
        (-0.5, 0.0, -0.5),
        (0.5, 0.0, -0.5),
        (0.5, 1.0, -0.5),
        (-0.5, 1.0, -0.5),
        (-0.5, 0.0, 0.5),
        (0.5, 0.0, 0.5),
        (0.5, 1.0, 0.5),
        (-0.5, 1.0, 0.5),
    ] {
        let _ = writeln!(s, "v {x} {y} {z}");
    }
    for f in [
        [1, 4, 3, 2],
        [5, 6, 7, 8],
        [1, 2, 6, 5],
        [4, 8, 7, 3],
        [1, 5, 8, 4],
        [2, 3, 7, 6],
    ] {
        let _ = writeln!(s, "f {} {} {} {}", f[0], f[1], f[2], f[3]);
    }
    s
}

/// The scene JSON around a list of mesh entries: 1920×1080, the `@boxes` camera and light.
fn scene_json(meshes: &[String]) -> String {
    scene_json_at(
        ([0.0, 14.0, 22.0], [0.0, 0.0, -6.0], 50.0),
        [12.0, 30.0, 14.0],
        meshes,
    )
}

/// The scene JSON around a list of mesh entries at 1920×1080: camera (eye, target,
/// vertical field of view in degrees) and one point light.
fn scene_json_at(
    (eye, target, fov): ([f64; 3], [f64; 3], f64),
    light: [f64; 3],
    meshes: &[String],
) -> String {
    let v = |p: [f64; 3]| format!("[{}, {}, {}]", p[0], p[1], p[2]);
    format!(
        r#"{{"width": 1920, "height": 1080, "background": [0.5, 0.65, 0.85],
  "camera": {{"eye": {}, "target": {}, "up": [0, 1, 0], "fov_y_deg": {fov}}},
  "lights": [{{"position": {}}}],
  "meshes": [{}]}}"#,
        v(eye),
        v(target),
        v(light),
        meshes.join(",\n")
    )
}

/// A mesh entry of `obj` with a colour, placement and whether it casts shadows.
fn mesh_entry(obj: &str, c: [f64; 3], t: [f64; 3], sc: [f64; 3], rot: f64, casts: bool) -> String {
    format!(
        r#"{{"obj": "{obj}", "color": [{:.2}, {:.2}, {:.2}], "translate": [{}, {}, {}], "scale": [{}, {}, {}], "rotate_y_deg": {rot}, "casts_shadows": {casts}}}"#,
        c[0], c[1], c[2], t[0], t[1], t[2], sc[0], sc[1], sc[2]
    )
}

/// `forest`: 400 thin boxes up to 9 high on a wide ground, seen from eye height under a
/// light 8 high and far to the side: many boxes overlap in every pixel row, and the taller
/// ones reach above the light, so their shadow volumes open upward and cover much of the
/// screen (hundreds of long volumes, high depth complexity).
fn forest_scene() -> GenScene {
    let mut rng = Lcg64(0x00f0_2e57);
    let mut meshes = vec![ground_entry([0.4, 0.5, 0.3])];
    for k in 0..400 {
        let (x, z, h) = (
            rng.range(-25.0, 25.0),
            rng.range(-40.0, 5.0),
            rng.range(2.0, 9.0),
        );
        let c = [0.5, 0.35 + 0.1 * (k % 3) as f64, 0.2];
        meshes.push(mesh_entry(
            "box.obj",
            c,
            [x, 0.0, z],
            [0.3, h, 0.3],
            rng.range(0.0, 90.0),
            true,
        ));
    }
    let json = scene_json_at(
        ([0.0, 1.6, 12.0], [0.0, 2.5, -10.0], 60.0),
        [30.0, 8.0, 10.0],
        &meshes,
    );
    (json, ground_and_box())
}

/// `spheres`: six closed spheres of 8,192 triangles each (an octahedron subdivided five
/// times) on the ground: large closed convex casters, each one shadow volume.
fn spheres_scene() -> GenScene {
    let mut files = ground_and_box();
    files.insert("sphere.obj".to_string(), sphere_obj(5));
    let mut meshes = vec![ground_entry([0.6, 0.6, 0.6])];
    for k in 0..6 {
        let t = [-5.0 + 2.0 * k as f64, 1.2, -2.0 - 1.5 * (k % 2) as f64];
        let c = [0.2 + 0.12 * k as f64, 0.4, 0.8 - 0.1 * k as f64];
        meshes.push(mesh_entry("sphere.obj", c, t, [1.2; 3], 0.0, true));
    }
    let json = scene_json_at(
        ([0.0, 4.0, 10.0], [0.0, 1.0, -1.0], 50.0),
        [-6.0, 10.0, 6.0],
        &meshes,
    );
    (json, files)
}

/// `closeup`: the camera a step away from eight large boxes standing one behind the
/// other, each wider than the view: a few large triangles, most pixels behind five or
/// more of them.
fn closeup_scene() -> GenScene {
    let mut meshes = vec![ground_entry([0.5, 0.5, 0.45])];
    for k in 0..8 {
        let t = [0.5 * (k % 3) as f64 - 0.5, 0.0, -1.5 - 1.5 * k as f64];
        let c = [0.8, 0.3 + 0.06 * k as f64, 0.2];
        let sc = [24.0 + 4.0 * k as f64, 1.6 + 0.9 * k as f64, 0.6];
        let rot = 8.0 * (k % 4) as f64 - 12.0;
        meshes.push(mesh_entry("box.obj", c, t, sc, rot, true));
    }
    let json = scene_json_at(
        ([0.3, 1.0, 2.5], [0.0, 1.0, -3.0], 70.0),
        [2.0, 6.0, 4.0],
        &meshes,
    );
    (json, ground_and_box())
}

/// `shards`: 3,000 small triangles floating over the ground, each its own open occluder,
/// so each casts its own shadow volume (thousands of volumes).
fn shards_scene() -> GenScene {
    let mut rng = Lcg64(0x0054_a2d5);
    let mut obj = String::new();
    for k in 0..3000 {
        let c = [
            rng.range(-10.0, 10.0),
            rng.range(0.5, 6.0),
            rng.range(-15.0, 5.0),
        ];
        for _ in 0..3 {
            let p = c.map(|x| x + rng.range(-0.4, 0.4));
            let _ = writeln!(obj, "v {} {} {}", p[0], p[1], p[2]);
        }
        let _ = writeln!(obj, "f {} {} {}", 3 * k + 1, 3 * k + 2, 3 * k + 3);
    }
    let mut files = ground_and_box();
    files.insert("shards.obj".to_string(), obj);
    let meshes = [
        ground_entry([0.6, 0.6, 0.55]),
        mesh_entry("shards.obj", [0.8, 0.4, 0.3], [0.0; 3], [1.0; 3], 0.0, true),
    ];
    let json = scene_json_at(
        ([0.0, 4.0, 14.0], [0.0, 2.0, -4.0], 55.0),
        [4.0, 20.0, 8.0],
        &meshes,
    );
    (json, files)
}

/// `tori`: six tori of 4,096 triangles each, lying 2.5 units over the ground (each turned
/// about the vertical, so their tessellations differ on screen): closed casters that are
/// not convex, so each face towards the light casts its own volume (12,040 volumes,
/// 5.7 M shadow span words; `docs/shadows.md`).
fn tori_scene() -> GenScene {
    let mut files = ground_and_box();
    files.insert("torus.obj".to_string(), torus_obj(64, 32, 2.0, 0.7));
    let mut meshes = vec![ground_entry([0.55, 0.6, 0.5])];
    for k in 0..6 {
        let t = [-10.0 + 4.0 * k as f64, 2.5, -6.0 - 3.0 * (k % 2) as f64];
        let c = [0.7, 0.35 + 0.08 * k as f64, 0.3];
        meshes.push(mesh_entry(
            "torus.obj",
            c,
            t,
            [1.0; 3],
            30.0 * k as f64,
            true,
        ));
    }
    let json = scene_json_at(
        ([0.0, 6.0, 14.0], [0.0, 1.0, -5.0], 60.0),
        [10.0, 20.0, 10.0],
        &meshes,
    );
    (json, files)
}

/// A torus about the y axis (ring radius `big`, tube radius `small`), `nu × nv` quads
/// split in two triangles wound outward, vertices shared.
fn torus_obj(nu: usize, nv: usize, big: f64, small: f64) -> String {
    let mut s = String::new();
    for i in 0..nu {
        for j in 0..nv {
            let u = std::f64::consts::TAU * i as f64 / nu as f64;
            let v = std::f64::consts::TAU * j as f64 / nv as f64;
            let ring = big + small * v.cos();
            let _ = writeln!(
                s,
                "v {} {} {}",
                ring * u.cos(),
                small * v.sin(),
                ring * u.sin()
            );
        }
    }
    let at = |i: usize, j: usize| (i % nu) * nv + j % nv + 1;
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            let _ = writeln!(s, "f {a} {c} {b}\nf {a} {d} {c}");
        }
    }
    s
}

/// The ground quad's mesh entry in colour `c`, casting no shadow.
fn ground_entry(c: [f64; 3]) -> String {
    mesh_entry("ground.obj", c, [0.0; 3], [1.0; 3], 0.0, false)
}

/// The 80 × 80 ground quad and the unit box as OBJ files.
fn ground_and_box() -> BTreeMap<String, String> {
    let mut files = BTreeMap::new();
    files.insert(
        "ground.obj".to_string(),
        "v -40 0 -40\nv 40 0 -40\nv 40 0 40\nv -40 0 40\nf 1 4 3 2\n".to_string(),
    );
    files.insert("box.obj".to_string(), box_obj());
    files
}

/// A unit sphere: the octahedron's eight faces each split in four `level` times, the
/// new vertices pushed onto the sphere (8 · 4^level triangles, outward winding).
fn sphere_obj(level: u32) -> String {
    let mut tris: Vec<[[f64; 3]; 3]> = Vec::new();
    for s in 0..8 {
        let sg = |b: usize| if s >> b & 1 == 0 { 1.0 } else { -1.0 };
        let (x, y, z) = ([sg(0), 0.0, 0.0], [0.0, sg(1), 0.0], [0.0, 0.0, sg(2)]);
        tris.push(if sg(0) * sg(1) * sg(2) > 0.0 {
            [x, y, z]
        } else {
            [x, z, y]
        });
    }
    let mid = |a: [f64; 3], b: [f64; 3]| {
        let m = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        m.map(|c| c / l)
    };
    for _ in 0..level {
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let mut s = String::new();
    for t in &tris {
        for p in t {
            let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
        }
    }
    for k in 0..tris.len() {
        let _ = writeln!(s, "f {} {} {}", 3 * k + 1, 3 * k + 2, 3 * k + 3);
    }
    s
}

/// A `q × q` grid of quads (2q² triangles) over the same ground square, gently
/// undulating so that neighbouring triangles differ in depth and shade, and three boxes on
/// it that cast shadows: the coverage is the same for every `q`.
fn grid_scene(q: usize) -> GenScene {
    let mut obj = String::new();
    let size = 36.0;
    for j in 0..=q {
        for i in 0..=q {
            let (u, v) = (i as f64 / q as f64, j as f64 / q as f64);
            let (x, z) = (size * (u - 0.5), size * (v - 0.5) - 6.0);
            let y = 0.4 * (x * 0.7).sin() * (z * 0.5).cos();
            let _ = writeln!(obj, "v {x} {y} {z}");
        }
    }
    for j in 0..q {
        for i in 0..q {
            let a = j * (q + 1) + i + 1;
            let _ = writeln!(obj, "f {} {} {} {}", a, a + 1, a + q + 2, a + q + 1);
        }
    }
    let (mut json, mut files) = box_scene(&[
        ([-6.0, 0.0, -4.0], [3.0, 5.0, 3.0], 20.0),
        ([5.0, 0.0, -8.0], [4.0, 7.0, 2.5], -35.0),
        ([0.0, 0.0, 2.0], [2.5, 3.0, 2.5], 60.0),
    ]);
    files.insert("grid.obj".to_string(), obj);
    json = json.replace(
        r#"{"obj": "ground.obj", "color": [0.55, 0.6, 0.5], "casts_shadows": false}"#,
        r#"{"obj": "grid.obj", "color": [0.55, 0.6, 0.5], "casts_shadows": false}"#,
    );
    (json, files)
}

/// The benchmark scenes: the [`target_scenes`] the issue's targets were set on, then the
/// [`hard_scenes`].
pub fn bench_scenes() -> Result<Vec<LoadedScene>, scene::SceneError> {
    let mut out = target_scenes()?;
    out.extend(hard_scenes()?);
    Ok(out)
}

/// `large` (a ground and eight big boxes: a few large triangles), `boxes` (the built-in
/// city), `grid-1k` and `grid-10k` (same coverage, 10× the triangles).
pub fn target_scenes() -> Result<Vec<LoadedScene>, scene::SceneError> {
    let mut out = embedded(target_scene_files())?;
    out.insert(1, scene::load_builtin("boxes")?);
    Ok(out)
}

/// The generated [`target_scenes`] as files (`large`, `grid-1k`, `grid-10k`; the city is
/// the built-in `@boxes`): name, scene JSON, and the OBJ files it names.
pub fn target_scene_files() -> [(&'static str, GenScene); 3] {
    let large = box_scene(&[
        ([-9.0, 0.0, -10.0], [5.0, 8.0, 5.0], 15.0),
        ([-2.0, 0.0, -14.0], [6.0, 11.0, 4.0], -20.0),
        ([6.0, 0.0, -9.0], [4.0, 6.0, 7.0], 40.0),
        ([12.0, 0.0, -16.0], [5.0, 12.0, 5.0], 5.0),
        ([-13.0, 0.0, -3.0], [3.0, 4.0, 3.0], -50.0),
        ([1.0, 0.0, -3.0], [3.5, 3.0, 3.5], 30.0),
        ([9.0, 0.0, 0.0], [3.0, 5.0, 3.0], 65.0),
        ([-5.0, 0.0, 4.0], [2.5, 2.0, 2.5], -10.0),
    ]);
    [
        ("large", large),
        ("grid-1k", grid_scene(22)),
        ("grid-10k", grid_scene(71)),
    ]
}

/// Scenes added after the targets were met on the [`target_scenes`], where they are not:
/// `forest`, `spheres`, `closeup`, `shards` and `tori` (see their functions).
pub fn hard_scenes() -> Result<Vec<LoadedScene>, scene::SceneError> {
    embedded(hard_scene_files())
}

/// The [`hard_scenes`] as files: name, scene JSON, and the OBJ files it names (for
/// rendering them with `pixelproc render`, or with a build that predates them).
pub fn hard_scene_files() -> [(&'static str, GenScene); 5] {
    [
        ("forest", forest_scene()),
        ("spheres", spheres_scene()),
        ("closeup", closeup_scene()),
        ("shards", shards_scene()),
        ("tori", tori_scene()),
    ]
}

/// Scenes given as JSON and their OBJ files, loaded.
fn embedded<const N: usize>(
    scenes: [(&str, GenScene); N],
) -> Result<Vec<LoadedScene>, scene::SceneError> {
    scenes
        .into_iter()
        .map(|(name, (json, files))| {
            let s = scene::parse(&json, name)?;
            scene::load_with(s, &MeshSource::Embedded(files), name)
        })
        .collect()
}

/// One measured case of one scene.
#[derive(Clone, Debug)]
pub struct Measured {
    /// Scene name.
    pub scene: String,
    /// Triangles fed to setup.
    pub triangles: usize,
    /// The case.
    pub case: &'static str,
    /// Median wall time, milliseconds.
    pub median_ms: f64,
    /// Ratio to the scene's plain frame.
    pub ratio: f64,
    /// The work the case counts, and its unit.
    pub work: (u64, &'static str),
    /// Peak resident memory of one render of the case, MiB (Linux).
    pub peak_mib: Option<f64>,
}

impl Measured {
    /// Nanoseconds per unit of work: for `shadows`, of the time added to the plain frame.
    pub fn ns_per_unit(&self, plain_ms: f64) -> f64 {
        let ms = if self.case == "shadows" {
            self.median_ms - plain_ms
        } else {
            self.median_ms
        };
        ms * 1e6 / self.work.0.max(1) as f64
    }
}

/// The unit of work a case counts: span words (plain), shadow span words (shadows),
/// fragments (A-buffer), visible pieces on sub-scanlines (multi-scanning), samples
/// written (the sampling methods and the post-process).
fn work(case: &str, out: &RenderOutput) -> (u64, &'static str) {
    match (case, &out.aa) {
        ("shadows", _) => (out.shadow.span_words, "shadow span"),
        (_, Some(AaReport::Abuffer(s))) => (s.fragments, "fragment"),
        ("multiscan", Some(AaReport::Other(s))) => (s.samples_written, "piece"),
        (_, Some(AaReport::Other(s))) => (s.samples_written, "sample"),
        _ => (out.span_words, "span word"),
    }
}

/// Resets the process's peak resident set size (Linux `clear_refs`); `false` elsewhere.
fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// The process's peak resident set size since the last reset, MiB (Linux).
fn peak_mib() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Makes every large allocation a fresh mapping, returned to the system when freed
/// (glibc: a fixed `M_MMAP_THRESHOLD` of 128 KiB, its default, which turns off the
/// threshold's dynamic growth). Without it glibc raises the threshold after a case frees a
/// large buffer, and later cases reuse that heap memory without page faults: a case's time
/// would depend on which cases ran before it (the plain frame of the `large` scene
/// measured 23–41 ms in interleaved runs of one binary). With it, every timed render
/// pays for its memory as a one-render process does. Elsewhere a no-op. (The `pixelproc`
/// program maps blocks of 4 MiB and more itself, fresh every time, in huge pages where
/// the system offers them: its `alloc.rs`; this setting covers the smaller ones.)
fn fresh_allocations() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only changes a malloc tuning parameter; it is called before the
    // renders start and has no memory-safety preconditions.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
    }
}

/// Renders every case of every scene `runs` times (after one warm-up render each, which
/// also measures the peak memory) and returns the medians. `progress` is told each scene.
/// Sets the allocator so that each render allocates as a fresh process would
/// (`fresh_allocations`).
pub fn run_all_methods(
    scenes: &[LoadedScene],
    runs: usize,
    mut progress: impl FnMut(&str),
) -> anyhow::Result<Vec<Measured>> {
    crate::timing::check_runs(runs).map_err(anyhow::Error::msg)?;
    fresh_allocations();
    let cases = cases();
    let mut out = Vec::new();
    for ls in scenes {
        progress(&ls.name);
        let fx: Vec<Effects> = cases
            .iter()
            .map(|c| Effects::resolve(ls, &c.overrides))
            .collect::<Result<_, _>>()?;
        let mut first = Vec::new();
        for f in &fx {
            let measured = reset_peak();
            let o = render(ls, f)?;
            first.push((o, if measured { peak_mib() } else { None }));
        }
        let mut times = vec![Vec::new(); cases.len()];
        for _ in 0..runs {
            for (k, f) in fx.iter().enumerate() {
                let t0 = Instant::now();
                render(ls, f)?;
                times[k].push(t0.elapsed().as_secs_f64() * 1e3);
            }
        }
        let med: Vec<f64> = times
            .into_iter()
            .map(|mut v| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            })
            .collect();
        for (k, c) in cases.iter().enumerate() {
            out.push(Measured {
                scene: ls.name.clone(),
                triangles: first[k].0.triangles,
                case: c.name,
                median_ms: med[k],
                ratio: med[k] / med[0],
                work: work(c.name, &first[k].0),
                peak_mib: first[k].1,
            });
        }
    }
    Ok(out)
}

/// The results as a Markdown table, plus the growth from `grid-1k` to `grid-10k` per case.
pub fn table(rows: &[Measured]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| scene | tris | case | median ms | × plain | work | ns / unit | peak MiB |"
    );
    let _ = writeln!(s, "|---|---:|---|---:|---:|---:|---:|---:|");
    let plain = |scene: &str| {
        rows.iter()
            .find(|r| r.scene == scene && r.case == "plain")
            .map_or(f64::NAN, |r| r.median_ms)
    };
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} | {:.2} | {} {} | {:.1} | {} |",
            r.scene,
            r.triangles,
            r.case,
            r.median_ms,
            r.ratio,
            r.work.0,
            r.work.1,
            r.ns_per_unit(plain(&r.scene)),
            r.peak_mib.map_or("—".to_string(), |m| format!("{m:.0}")),
        );
    }
    let find = |scene: &str, case: &str| {
        rows.iter()
            .find(|r| r.scene == scene && r.case == case)
            .map(|r| r.median_ms)
    };
    let (t1, t10) = (
        rows.iter()
            .find(|r| r.scene == "grid-1k")
            .map(|r| r.triangles),
        rows.iter()
            .find(|r| r.scene == "grid-10k")
            .map(|r| r.triangles),
    );
    if let (Some(t1), Some(t10)) = (t1, t10) {
        let _ = writeln!(
            s,
            "\nGrowth from grid-1k ({t1} triangles) to grid-10k ({t10}, {:.1}×), same coverage:\n",
            t10 as f64 / t1.max(1) as f64
        );
        let _ = writeln!(s, "| case | grid-1k ms | grid-10k ms | growth |");
        let _ = writeln!(s, "|---|---:|---:|---:|");
        for c in cases() {
            if let (Some(a), Some(b)) = (find("grid-1k", c.name), find("grid-10k", c.name)) {
                let _ = writeln!(s, "| {} | {a:.1} | {b:.1} | {:.2}× |", c.name, b / a);
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tori's mesh is closed, wound outward and not convex, as `tori` needs: every
    /// edge is in exactly two faces, once in each direction; the signed volume (sum of
    /// the faces' tetrahedra with the origin) is within 1 % of the smooth torus's
    /// 2π²·R·r²; and the hole's centre (the origin, on the axis) lies inside the hull of
    /// the vertices but outside the solid (a convex solid would contain it).
    #[test]
    fn the_torus_is_closed_outward_and_not_convex() {
        let (big, small) = (2.0, 0.7);
        let obj = torus_obj(64, 32, big, small);
        let mut v: Vec<[f64; 3]> = Vec::new();
        let mut f: Vec<[usize; 3]> = Vec::new();
        for line in obj.lines() {
            let w: Vec<&str> = line.split_whitespace().collect();
            match w[0] {
                "v" => v.push([1, 2, 3].map(|k| w[k].parse().unwrap())),
                "f" => f.push([1, 2, 3].map(|k| w[k].parse::<usize>().unwrap() - 1)),
                _ => panic!("unexpected line {line}"),
            }
        }
        assert_eq!((v.len(), f.len()), (64 * 32, 2 * 64 * 32));
        let mut edges = std::collections::HashMap::new();
        for t in &f {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a}->{b} used {n} times in one direction");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}->{b} has no twin");
        }
        let vol: f64 = f
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| v[i]);
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum();
        let smooth = 2.0 * std::f64::consts::PI.powi(2) * big * small * small;
        assert!(
            (vol / smooth - 1.0).abs() < 0.01,
            "volume {vol} against {smooth}"
        );
        // A ray from (0, 0.01, 0.013), next to the origin, along +x (off the vertices,
        // which lie on the x axis) crosses the surface twice (the tube at x ≈ 1.3 and
        // x ≈ 2.7): an even count, so the hole is outside the solid, though the vertices
        // surround it.
        let crossings = f
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| v[i]);
                // Whether the ray's line meets the triangle: its (y, z) point inside the
                // triangle projected along x.
                let s = |p: [f64; 3], q: [f64; 3]| {
                    (p[1] - 0.01) * (q[2] - 0.013) - (p[2] - 0.013) * (q[1] - 0.01)
                };
                let (u, w, x) = (s(b, c), s(c, a), s(a, b));
                (u > 0.0 && w > 0.0 && x > 0.0) || (u < 0.0 && w < 0.0 && x < 0.0)
            })
            .filter(|t| t.iter().any(|&i| v[i][0] > 0.0))
            .count();
        assert_eq!(crossings, 2, "the +x axis crosses the surface twice");
    }
}
