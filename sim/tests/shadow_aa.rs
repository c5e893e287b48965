//! Anti-aliased shadows under every method, against an independent float ray cast written
//! here: per pixel, 16×16 rays through the pixel square find the visible triangle and
//! whether a shadow ray from the hit point to the light is blocked by a casting triangle.
//! The shadowed fraction is the share of the 256 samples in shadow (background samples
//! count as lit).
//!
//! Checked: the shadow AOV under each method (the shadowed fraction in the method's
//! weights, 0..=255) is exactly 0 or 255 away from shadow boundaries and agrees with the
//! ray cast; its error on boundary pixels falls as the method's parameter rises
//! (supersampling k, multi-scanning n, A-buffer mask size); and the image's shadowed
//! interior keeps the colour of the array's own render.

use glam::DVec3;
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::aa::{AaMethod, CornerParams, Filter, MultiscanParams, Pattern};
use pixelproc_sim::abuffer::AbufferParams;
use pixelproc_sim::pipeline::{render, RenderOutput};
use pixelproc_sim::plan::{Aov, Effects, Overrides};
use pixelproc_sim::scene::LoadedScene;

mod cast_common;
use cast_common::{hit, load, world, Cam, Tri};

/// Rays per pixel along each axis.
const RAYS: usize = 16;

/// A box floating above the ground, turned so its shadow edges are oblique on screen, one
/// point light.
fn scene() -> LoadedScene {
    load(
        r#"{"width": 96, "height": 64, "background": [0.5, 0.6, 0.8], "ambient": 0.2,
  "camera": {"eye": [0, 7, 9], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50},
  "lights": [{"position": [4, 8, 2], "intensity": 0.7}],
  "meshes": [
    {"obj": "ground.obj", "color": [0.8, 0.7, 0.6]},
    {"obj": "box.obj", "color": [0.3, 0.5, 0.9], "translate": [-0.5, 1.6, 0.5], "scale": [2, 1.2, 1.6], "rotate_y_deg": 27}
  ]}"#,
    )
}

/// Whether the visible point along the ray from the eye through `(x, y)` is in shadow.
fn shadowed_at(cam: &Cam, tris: &[Tri], light: DVec3, x: f64, y: f64) -> bool {
    let d = cam.ray_at(x, y);
    let near = tris
        .iter()
        .enumerate()
        .filter_map(|(k, t)| hit(cam.eye, d, &t.p).filter(|&u| u > 1e-6).map(|u| (u, k)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    let Some((u, k)) = near else { return false };
    let p = cam.eye + d * u;
    let to = light - p;
    let dist = to.length();
    let dl = to / dist;
    tris.iter().enumerate().any(|(k2, t)| {
        k2 != k && t.casts && hit(p, dl, &t.p).is_some_and(|v| v > 1e-7 && v < dist - 1e-7)
    })
}

/// The ray-cast shadowed fraction of every pixel, 0..=1.
fn ray_cast_fraction(ls: &LoadedScene) -> Vec<f64> {
    let cam = Cam::new(ls);
    let tris = world(ls);
    let light = DVec3::from(ls.scene.lights[0].position);
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let mut out = vec![0.0; w * h];
    for j in 0..h {
        for i in 0..w {
            let mut n = 0;
            for b in 0..RAYS {
                for a in 0..RAYS {
                    let x = i as f64 + (a as f64 + 0.5) / RAYS as f64;
                    let y = j as f64 + (b as f64 + 0.5) / RAYS as f64;
                    n += shadowed_at(&cam, &tris, light, x, y) as usize;
                }
            }
            out[j * w + i] = n as f64 / (RAYS * RAYS) as f64;
        }
    }
    out
}

fn render_with(ls: &LoadedScene, aa: AaMethod) -> RenderOutput {
    let ov = Overrides {
        aovs: vec![Aov::Shadow],
        ..Default::default()
    };
    let mut fx = Effects::resolve(ls, &ov).unwrap();
    fx.aa = aa;
    render(ls, &fx).unwrap()
}

fn shadow_aov(out: &RenderOutput) -> &[u8] {
    &out.aovs
        .iter()
        .find(|(a, _)| *a == Aov::Shadow)
        .unwrap()
        .1
        .data
}

/// Pixels on a shadow boundary (the ray-cast fraction is neither 0 nor 1), and pixels
/// whose 3×3 neighbourhood is wholly lit or wholly shadowed.
fn classify(rc: &[f64], w: usize, h: usize) -> (Vec<usize>, Vec<usize>) {
    let (mut edge, mut interior) = (Vec::new(), Vec::new());
    for j in 0..h {
        for i in 0..w {
            let k = j * w + i;
            if rc[k] > 0.0 && rc[k] < 1.0 {
                edge.push(k);
            } else if i > 0 && j > 0 && i + 1 < w && j + 1 < h {
                let same =
                    (0..3).all(|dy| (0..3).all(|dx| rc[(j + dy - 1) * w + i + dx - 1] == rc[k]));
                if same {
                    interior.push(k);
                }
            }
        }
    }
    (edge, interior)
}

/// Mean absolute error of the shadow AOV on the boundary pixels, in units of the full
/// fraction; also asserts the interior is exact.
fn aov_error(out: &RenderOutput, rc: &[f64], w: usize, h: usize, what: &str) -> f64 {
    let f = shadow_aov(out);
    let (edge, interior) = classify(rc, w, h);
    assert!(
        edge.len() > 60 && interior.len() > 2000,
        "{what}: {} edge, {} interior",
        edge.len(),
        interior.len()
    );
    for &k in &interior {
        let want = (rc[k] * 255.0) as u8;
        assert_eq!(
            f[k],
            want,
            "{what}: interior pixel {k} ({}, {})",
            k % w,
            k / w
        );
    }
    edge.iter()
        .map(|&k| (f[k] as f64 / 255.0 - rc[k]).abs())
        .sum::<f64>()
        / edge.len() as f64
}

fn abuffer(n: u32) -> AaMethod {
    AaMethod::Abuffer(AbufferParams {
        size: MaskSize::new(n, n).unwrap(),
        ..Default::default()
    })
}

#[test]
fn shadowed_fraction_error_falls_as_each_methods_parameter_rises() {
    let ls = scene();
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let rc = ray_cast_fraction(&ls);
    if let Some(dir) = std::env::var_os("SHADOW_AA_DUMP") {
        let dir = std::path::PathBuf::from(dir);
        let img: Vec<u8> = rc.iter().map(|f| (f * 255.0) as u8).collect();
        std::fs::write(
            dir.join("rc.pgm"),
            [format!("P5 {w} {h} 255\n").into_bytes(), img].concat(),
        )
        .unwrap();
        let out = render_with(&ls, AaMethod::None);
        std::fs::write(
            dir.join("aov.pgm"),
            [
                format!("P5 {w} {h} 255\n").into_bytes(),
                shadow_aov(&out).to_vec(),
            ]
            .concat(),
        )
        .unwrap();
        std::fs::write(
            dir.join("img.ppm"),
            [
                format!("P6 {w} {h} 255\n").into_bytes(),
                out.image.data.clone(),
            ]
            .concat(),
        )
        .unwrap();
    }
    let series: [(&str, Vec<AaMethod>); 3] = [
        (
            "ssaa k = 1, 2, 4, 8",
            [1, 2, 4, 8].map(|k| AaMethod::Ssaa { k }).to_vec(),
        ),
        (
            "multiscan n = 1, 2, 4, 8",
            [1, 2, 4, 8]
                .map(|n| AaMethod::Multiscan(MultiscanParams::new(n, Filter::Box)))
                .to_vec(),
        ),
        ("a-buffer mask 2, 4, 8", [2, 4, 8].map(abuffer).to_vec()),
    ];
    let centre = aov_error(&render_with(&ls, AaMethod::None), &rc, w, h, "none");
    for (what, methods) in series {
        let errs: Vec<f64> = methods
            .iter()
            .map(|m| aov_error(&render_with(&ls, m.clone()), &rc, w, h, &m.label()))
            .collect();
        eprintln!("{what}: {errs:.4?} (centre sample {centre:.4})");
        for p in errs.windows(2) {
            assert!(p[1] < p[0], "{what}: error rose {errs:?}");
        }
        // The finest setting is far better than one sample per pixel.
        assert!(
            *errs.last().unwrap() < centre / 3.0,
            "{what}: {errs:?} vs centre {centre}"
        );
    }
    // Post-processing blends across shadow boundaries found as edges between pixels of
    // different shadow state: better than the centre sample it starts from.
    let m = AaMethod::PostFx(Default::default());
    let e = aov_error(&render_with(&ls, m.clone()), &rc, w, h, &m.label());
    eprintln!("{}: {e:.4}", m.label());
    assert!(e < centre * 0.75, "{}: {e} vs centre {centre}", m.label());
    // Corner sampling, D3D 4× and the 2×2 grid take 4 samples a pixel: better than one.
    for pat in [Pattern::Corner, Pattern::D3d4x, Pattern::Grid2x2] {
        let m = AaMethod::Corner(CornerParams::new(pat, false));
        let e = aov_error(&render_with(&ls, m.clone()), &rc, w, h, &m.label());
        eprintln!("{}: {e:.4}", m.label());
        assert!(e < centre * 0.75, "{}: {e} vs centre {centre}", m.label());
    }
}

#[test]
fn anti_aliased_shadow_interiors_keep_the_arrays_colour() {
    let ls = scene();
    let (w, h) = (ls.scene.width as usize, ls.scene.height as usize);
    let rc = ray_cast_fraction(&ls);
    let (_, interior) = classify(&rc, w, h);
    let plain = render_with(&ls, AaMethod::None);
    // Away from object edges too: the ray through every pixel of the 3×3 neighbourhood's
    // centre hits the ground.
    let cam = Cam::new(&ls);
    let tris = world(&ls);
    let on_ground = |i: usize, j: usize| {
        let d = cam.ray(i, j);
        tris.iter()
            .filter_map(|t| {
                hit(cam.eye, d, &t.p)
                    .filter(|&u| u > 1e-6)
                    .map(|u| (u, t.ground))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .is_some_and(|(_, g)| g)
    };
    let shadowed: Vec<usize> = interior
        .into_iter()
        .filter(|&k| rc[k] == 1.0)
        .filter(|&k| {
            let (i, j) = (k % w, k / w);
            (0..3).all(|dy| (0..3).all(|dx| on_ground(i + dx - 1, j + dy - 1)))
        })
        .collect();
    assert!(
        shadowed.len() > 40,
        "{} shadowed interior pixels",
        shadowed.len()
    );
    for m in [
        AaMethod::Ssaa { k: 4 },
        AaMethod::Multiscan(MultiscanParams::new(4, Filter::Box)),
        abuffer(4),
        AaMethod::Corner(CornerParams::new(Pattern::Corner, false)),
    ] {
        let out = render_with(&ls, m.clone());
        for &k in &shadowed {
            // Interior pixels away from object edges: the method's lit colour and the
            // array's differ by rounding only, and so do the shaded ones.
            let (a, b) = (
                &out.image.data[3 * k..3 * k + 3],
                &plain.image.data[3 * k..3 * k + 3],
            );
            for c in 0..3 {
                assert!(
                    (a[c] as i32 - b[c] as i32).abs() <= 2,
                    "{}: pixel {k} {a:?} vs array {b:?}",
                    m.label()
                );
            }
        }
    }
}
