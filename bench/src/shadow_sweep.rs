//! The trade-off on shadow boundaries: 3-D scenes whose shadows are real shadow volumes
//! (seed 001, run through the whole pipeline), judged against a float ray cast.
//!
//! For each scene and setting the renderer's shadow AOV — the shadowed fraction of each
//! pixel in the method's own weights (`docs/shadows.md`) — is compared with the fraction of
//! `RAYS × RAYS` rays per pixel whose visible point cannot see the light, cast here in f64
//! against the scene's world triangles (nothing from the volumes, the front end or span
//! setup). An area light is the disc of point samples the scene defines
//! ([`pixelproc_sim::shadow::light_samples`]): a ray's shadowed share is the share of those
//! points it cannot see. Reported per setting, averaged over the scenes: the RMSE of the
//! fraction over every pixel (0..255 scale), the mean absolute error on boundary pixels
//! (where the ray-cast fraction is strictly between 0 and 1), and the median CPU time of the
//! whole render on one thread (front end, array, shadow passes, the method).

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use glam::DVec3;
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::aa::{AaMethod, CornerParams, Filter, MultiscanParams, Pattern};
use pixelproc_sim::abuffer::AbufferParams;
use pixelproc_sim::pipeline::render;
use pixelproc_sim::plan::{Aov, Effects, Overrides};
use pixelproc_sim::scene::{self, LoadedScene, MeshSource};
use pixelproc_sim::shadow::light_samples;
use rayon::prelude::*;

use crate::timing::{median, one_thread_pool, thread_cpu_seconds};
use crate::{io_err, TradeoffError};

/// Rays per pixel along each axis of the reference.
pub const RAYS: usize = 16;

const BOX: &str = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\nv -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
const GROUND: &str = "v -6 0 -6\nv 6 0 -6\nv 6 0 6\nv -6 0 6\nf 1 4 3\nf 1 3 2\n";
const LBLOCK: &str = "v 0 0 -0.4\nv 2 0 -0.4\nv 2 0.6 -0.4\nv 0.6 0.6 -0.4\nv 0.6 1.8 -0.4\nv 0 1.8 -0.4\nv 0 0 0.4\nv 2 0 0.4\nv 2 0.6 0.4\nv 0.6 0.6 0.4\nv 0.6 1.8 0.4\nv 0 1.8 0.4\nf 7 8 9 10\nf 7 10 11 12\nf 4 3 2 1\nf 6 5 4 1\nf 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n";
const POLE: &str = "v -0.1 0 -0.1\nv 0.1 0 -0.1\nv 0.1 3 -0.1\nv -0.1 3 -0.1\nv -0.1 0 0.1\nv 0.1 0 0.1\nv 0.1 3 0.1\nv -0.1 3 0.1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";

/// One 3-D scene of the shadow trade-off.
pub struct ShadowScene {
    /// Name.
    pub name: String,
    /// The loaded scene.
    pub scene: LoadedScene,
}

fn load(name: &str, json: &str) -> LoadedScene {
    let files: BTreeMap<String, String> = [
        ("box.obj", BOX),
        ("ground.obj", GROUND),
        ("lblock.obj", LBLOCK),
        ("pole.obj", POLE),
    ]
    .into_iter()
    .map(|(a, b)| (a.to_string(), b.to_string()))
    .collect();
    let parsed = scene::parse(json, name).expect("built-in shadow scene parses");
    scene::load_with(parsed, &MeshSource::Embedded(files), name)
        .expect("built-in shadow scene loads")
}

/// The built-in shadow scenes: a turned box over a casting ground (point light), an L block
/// under an area light (penumbra), thin poles with a low light (long, narrow shadows).
/// `quick`: the first one at a smaller size.
pub fn shadow_scenes(quick: bool) -> Vec<ShadowScene> {
    let (w, h) = if quick { (96, 64) } else { (160, 112) };
    let head = |light: &str| {
        format!(
            r#""width": {w}, "height": {h}, "background": [0.5, 0.6, 0.8], "ambient": 0.2,
  "camera": {{"eye": [0, 7, 9], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50}},
  "lights": [{light}]"#
        )
    };
    let mut v = vec![ShadowScene {
        name: "box-point".into(),
        scene: load(
            "box-point",
            &format!(
                r#"{{{}, "meshes": [
    {{"obj": "ground.obj", "color": [0.8, 0.7, 0.6]}},
    {{"obj": "box.obj", "color": [0.3, 0.5, 0.9], "translate": [-0.5, 1.6, 0.5], "scale": [2, 1.2, 1.6], "rotate_y_deg": 27}}]}}"#,
                head(r#"{"position": [4, 8, 2], "intensity": 0.7}"#)
            ),
        ),
    }];
    if quick {
        return v;
    }
    v.push(ShadowScene {
        name: "lblock-area".into(),
        scene: load(
            "lblock-area",
            &format!(
                r#"{{{}, "meshes": [
    {{"obj": "ground.obj", "color": [0.7, 0.75, 0.6], "casts_shadows": false}},
    {{"obj": "lblock.obj", "color": [0.9, 0.4, 0.3], "translate": [-1, 0.3, 0], "scale": [1.5, 1.5, 1.5], "rotate_y_deg": -20}}]}}"#,
                head(r#"{"position": [3, 7, 3], "intensity": 0.7, "radius": 1.2, "samples": 16}"#)
            ),
        ),
    });
    v.push(ShadowScene {
        name: "poles-low-light".into(),
        scene: load(
            "poles-low-light",
            &format!(
                r#"{{{}, "meshes": [
    {{"obj": "ground.obj", "color": [0.75, 0.75, 0.7], "casts_shadows": false}},
    {{"obj": "pole.obj", "color": [0.3, 0.3, 0.8], "translate": [-2, 0, 1]}},
    {{"obj": "pole.obj", "color": [0.3, 0.3, 0.8], "translate": [0, 0, 0], "rotate_y_deg": 30}},
    {{"obj": "pole.obj", "color": [0.3, 0.3, 0.8], "translate": [2, 0, -1], "rotate_y_deg": 60}}]}}"#,
                head(r#"{"position": [7, 3, 4], "intensity": 0.8}"#)
            ),
        ),
    });
    v
}

/// A world triangle of the ray cast.
struct Tri {
    p: [DVec3; 3],
    casts: bool,
}

/// Two-sided ray–triangle distance (Möller–Trumbore).
fn hit(o: DVec3, d: DVec3, t: &[DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = o - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then(|| e2.dot(q) / det)
}

/// The ray-cast shadowed fraction per pixel, 0..=1, of the scene's first light.
pub fn ray_cast_fraction(ls: &LoadedScene) -> Vec<f64> {
    let mut tris = Vec::new();
    for (m, mr) in ls.meshes.iter().zip(&ls.scene.meshes) {
        for t in &m.triangles {
            tris.push(Tri {
                p: t.map(|i| DVec3::from(m.positions[i as usize])),
                casts: mr.casts_shadows,
            });
        }
    }
    let light = light_samples(&ls.scene.lights[0]);
    let c = ls.scene.camera.as_ref().expect("3-D scene");
    let eye = DVec3::from(c.eye);
    let fwd = (DVec3::from(c.target) - eye).normalize();
    let right = fwd.cross(DVec3::from(c.up)).normalize();
    let up = right.cross(fwd);
    let th = (c.fov_y_deg.to_radians() / 2.0).tan();
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let aspect = w as f64 / h as f64;
    let sample = |sx: f64, sy: f64| -> f64 {
        let x = (sx / w as f64 * 2.0 - 1.0) * th * aspect;
        let y = (1.0 - sy / h as f64 * 2.0) * th;
        let d = (fwd + right * x + up * y).normalize();
        let near = tris
            .iter()
            .enumerate()
            .filter_map(|(k, t)| hit(eye, d, &t.p).filter(|&u| u > 1e-6).map(|u| (u, k)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((u, k)) = near else { return 0.0 };
        let p = eye + d * u;
        let hidden = light
            .iter()
            .filter(|&&l| {
                let to = l - p;
                let dist = to.length();
                let dl = to / dist;
                tris.iter().enumerate().any(|(k2, t)| {
                    k2 != k
                        && t.casts
                        && hit(p, dl, &t.p).is_some_and(|v| v > 1e-7 && v < dist - 1e-7)
                })
            })
            .count();
        hidden as f64 / light.len() as f64
    };
    (0..w * h)
        .into_par_iter()
        .map(|k| {
            let (i, j) = ((k % w) as f64, (k / w) as f64);
            let mut s = 0.0;
            for b in 0..RAYS {
                for a in 0..RAYS {
                    s += sample(
                        i + (a as f64 + 0.5) / RAYS as f64,
                        j + (b as f64 + 0.5) / RAYS as f64,
                    );
                }
            }
            s / (RAYS * RAYS) as f64
        })
        .collect()
}

/// The settings of the shadow trade-off: each method's parameter series.
pub fn shadow_settings(quick: bool) -> Vec<AaMethod> {
    let ms = |n| AaMethod::Multiscan(MultiscanParams::new(n, Filter::Box));
    let ab = |n| {
        AaMethod::Abuffer(AbufferParams {
            size: MaskSize::new(n, n).expect("mask size in range"),
            ..Default::default()
        })
    };
    if quick {
        return vec![
            AaMethod::None,
            ms(1),
            ms(4),
            ab(4),
            AaMethod::Ssaa { k: 2 },
            AaMethod::Ssaa { k: 4 },
            AaMethod::PostFx(Default::default()),
        ];
    }
    let mut v = vec![AaMethod::None];
    v.extend([1, 2, 4, 8].map(ms));
    v.extend([2, 4, 8].map(ab));
    v.extend(
        [Pattern::Corner, Pattern::D3d4x, Pattern::Grid2x2]
            .map(|p| AaMethod::Corner(CornerParams::new(p, false))),
    );
    v.push(AaMethod::PostFx(Default::default()));
    v.extend([2, 4, 8].map(|k| AaMethod::Ssaa { k }));
    v
}

/// One setting's result, averaged over the scenes.
#[derive(Clone, Debug)]
pub struct ShadowRow {
    /// The method's label.
    pub label: String,
    /// RMSE of the shadowed fraction over every pixel, 0..255 scale.
    pub rmse: f64,
    /// Mean absolute error of the fraction on boundary pixels, 0..1.
    pub boundary_mae: f64,
    /// Median CPU time of the whole render on one thread, ms.
    pub ms: f64,
    /// Per scene: (name, rmse, boundary error, ms).
    pub per_scene: Vec<(String, f64, f64, f64)>,
}

/// Renders `ls` with `aa` and its shadows; returns the shadow AOV.
fn shadow_aov(ls: &LoadedScene, aa: &AaMethod) -> Result<Vec<u8>, TradeoffError> {
    let ov = Overrides {
        aovs: vec![Aov::Shadow],
        ..Default::default()
    };
    let err = |e: String| TradeoffError::Option(format!("{}: {}: {e}", ls.name, aa.label()));
    let mut fx = Effects::resolve(ls, &ov).map_err(|e| err(e.to_string()))?;
    fx.aa = aa.clone();
    let out = render(ls, &fx).map_err(|e| err(e.to_string()))?;
    out.aovs
        .into_iter()
        .find(|(a, _)| *a == Aov::Shadow)
        .map(|(_, img)| img.data)
        .ok_or_else(|| err("no shadow AOV".into()))
}

/// Runs the shadow trade-off: every setting on every scene, `runs` timed renders each.
/// With `progress`, one line per setting on stderr.
pub fn run_shadow_sweep(
    scenes: &[ShadowScene],
    settings: &[AaMethod],
    runs: usize,
    progress: bool,
) -> Result<Vec<ShadowRow>, TradeoffError> {
    let one = one_thread_pool()?;
    if progress {
        eprintln!(
            "shadow trade-off: ray-casting {} scenes ({RAYS}x{RAYS} rays per pixel)",
            scenes.len()
        );
    }
    let refs: Vec<Vec<f64>> = scenes.iter().map(|s| ray_cast_fraction(&s.scene)).collect();
    let mut rows = Vec::new();
    for (k, aa) in settings.iter().enumerate() {
        if progress {
            eprintln!(
                "shadow trade-off: {} ({}/{})",
                aa.label(),
                k + 1,
                settings.len()
            );
        }
        let mut per_scene = Vec::new();
        for (sc, rc) in scenes.iter().zip(&refs) {
            let f = shadow_aov(&sc.scene, aa)?;
            let mut sq = 0.0;
            let (mut be, mut bn) = (0.0, 0usize);
            for (&g, &r) in f.iter().zip(rc) {
                let d = g as f64 - 255.0 * r;
                sq += d * d;
                if r > 0.0 && r < 1.0 {
                    be += (g as f64 / 255.0 - r).abs();
                    bn += 1;
                }
            }
            let mut times = Vec::new();
            for _ in 0..runs.max(1) {
                let t = one.install(|| {
                    let (c0, t0) = (thread_cpu_seconds(), Instant::now());
                    let r = shadow_aov(&sc.scene, aa).map(|v| std::hint::black_box(v.len()));
                    let dt = t0.elapsed().as_secs_f64();
                    r.map(|_| thread_cpu_seconds().zip(c0).map_or(dt, |(b, a)| b - a))
                })?;
                times.push(t * 1e3);
            }
            per_scene.push((
                sc.name.clone(),
                (sq / f.len() as f64).sqrt(),
                if bn > 0 { be / bn as f64 } else { 0.0 },
                median(times),
            ));
        }
        let n = per_scene.len().max(1) as f64;
        rows.push(ShadowRow {
            label: aa.label(),
            rmse: per_scene.iter().map(|s| s.1).sum::<f64>() / n,
            boundary_mae: per_scene.iter().map(|s| s.2).sum::<f64>() / n,
            ms: per_scene.iter().map(|s| s.3).sum::<f64>() / n,
            per_scene,
        });
    }
    Ok(rows)
}

/// The Markdown table of the shadow trade-off.
pub fn shadow_markdown(rows: &[ShadowRow], scenes: &[ShadowScene]) -> String {
    let mut s = String::from(
        "## Shadow boundaries against a ray cast\n\nShadowed fraction (the shadow AOV) \
         against a float ray cast with 16×16 rays per pixel, averaged over the scenes: ",
    );
    s += &scenes
        .iter()
        .map(|x| {
            format!(
                "`{}` ({}×{})",
                x.name, x.scene.scene.width, x.scene.scene.height
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    s += ".\n\n| setting | RMSE (0..255) | boundary error (0..1) | ms/frame (CPU, 1 thread) |\n|---|---:|---:|---:|\n";
    for r in rows {
        s += &format!(
            "| {} | {:.2} | {:.4} | {:.1} |\n",
            r.label, r.rmse, r.boundary_mae, r.ms
        );
    }
    s
}

/// The per-scene CSV of the shadow trade-off.
pub fn shadow_csv(rows: &[ShadowRow]) -> String {
    let mut s = String::from("setting,scene,rmse,boundary_mae,ms\n");
    for r in rows {
        for (name, rmse, b, ms) in &r.per_scene {
            s += &format!("{},{name},{rmse:.4},{b:.5},{ms:.3}\n", r.label);
        }
    }
    s
}

/// Writes `shadows.md` and `shadows.csv` into `dir`; returns their paths.
pub fn write_shadow_outputs(
    rows: &[ShadowRow],
    scenes: &[ShadowScene],
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>, TradeoffError> {
    let md = dir.join("shadows.md");
    let csv = dir.join("shadows.csv");
    std::fs::write(&md, shadow_markdown(rows, scenes)).map_err(io_err(&md))?;
    std::fs::write(&csv, shadow_csv(rows)).map_err(io_err(&csv))?;
    Ok(vec![md, csv])
}
