//! End-to-end checks of the non-anti-aliased renderer on screen-space scenes, against an
//! independent floating-point visibility computation written here, plus a regression
//! image of the embedded default scene.

use pixelproc_sim::pipeline::render;
use pixelproc_sim::plan::{Effects, Overrides};
use pixelproc_sim::scene::{self, LoadedScene, MeshSource};
use proptest::prelude::*;

fn load(json: &str) -> LoadedScene {
    let s = scene::parse(json, "test").unwrap();
    scene::load_with(s, &MeshSource::Dir(".".into()), "test").unwrap()
}

fn render_rgb(ls: &LoadedScene, array_width: usize) -> Vec<u8> {
    let ov = Overrides {
        array_width: Some(array_width),
        ..Default::default()
    };
    let fx = Effects::resolve(ls, &ov).unwrap();
    render(ls, &fx).unwrap().image.data
}

#[derive(Clone, Debug)]
struct Tri {
    v: [[f64; 3]; 3],
    color: [f64; 3],
}

fn scene_json(w: u32, h: u32, tris: &[Tri]) -> String {
    let ts: Vec<String> = tris
        .iter()
        .map(|t| {
            format!(
                r#"{{"v":[[{},{},{}],[{},{},{}],[{},{},{}]],"color":[{},{},{}]}}"#,
                t.v[0][0],
                t.v[0][1],
                t.v[0][2],
                t.v[1][0],
                t.v[1][1],
                t.v[1][2],
                t.v[2][0],
                t.v[2][1],
                t.v[2][2],
                t.color[0],
                t.color[1],
                t.color[2]
            )
        })
        .collect();
    format!(
        r#"{{"width":{w},"height":{h},"background":[0,0,0],"triangles":[{}]}}"#,
        ts.join(",")
    )
}

/// Barycentric depth of `t` at `p` if `p` is strictly inside with a margin (pixels).
fn depth_inside(t: &Tri, p: [f64; 2], margin: f64) -> Option<f64> {
    let [a, b, c] = t.v;
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if area.abs() < 1e-9 {
        return None;
    }
    let e = |u: [f64; 3], v: [f64; 3]| {
        let len = ((v[0] - u[0]).powi(2) + (v[1] - u[1]).powi(2)).sqrt();
        ((v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0])) / area.signum() / len
    };
    let (ea, eb, ec) = (e(b, c), e(c, a), e(a, b));
    if ea.min(eb).min(ec) <= margin {
        return None;
    }
    let w0 = ((b[0] - p[0]) * (c[1] - p[1]) - (c[0] - p[0]) * (b[1] - p[1])) / area;
    let w1 = ((c[0] - p[0]) * (a[1] - p[1]) - (a[0] - p[0]) * (c[1] - p[1])) / area;
    Some(w0 * a[2] + w1 * b[2] + (1.0 - w0 - w1) * c[2])
}

/// "Clearly" means farther than 0.01 px from every edge: the float test uses the
/// unsnapped vertices, which snapping moves by up to 1/512 px.
/// For every pixel whose centre lies clearly inside at least one triangle and whose nearest
/// such triangle is clearly nearest, the pixel has that triangle's 8-bit colour; pixels
/// clearly outside every triangle keep the background.
fn check_visibility(w: u32, h: u32, tris: &[Tri], rgb: &[u8]) -> Result<usize, String> {
    let mut checked = 0;
    for j in 0..h {
        for i in 0..w {
            let p = [i as f64 + 0.5, j as f64 + 0.5];
            let mut hits: Vec<(f64, usize)> = tris
                .iter()
                .enumerate()
                .filter_map(|(k, t)| depth_inside(t, p, 1e-2).map(|z| (z, k)))
                .collect();
            let near_edge = tris
                .iter()
                .any(|t| depth_inside(t, p, -1e-2).is_some() && depth_inside(t, p, 1e-2).is_none());
            if near_edge {
                continue;
            }
            hits.sort_by(|a, b| a.0.total_cmp(&b.0));
            let px = &rgb[((j * w + i) * 3) as usize..][..3];
            match hits.as_slice() {
                [] if px != [0, 0, 0] => {
                    return Err(format!("pixel ({i},{j}) outside all triangles has {px:?}"))
                }
                [] => {}
                [(z0, k), rest @ ..] if rest.first().is_none_or(|(z1, _)| z1 - z0 > 2.0) => {
                    let c = tris[*k].color.map(|c| (c * 255.0).round() as u8);
                    if px != c {
                        return Err(format!(
                            "pixel ({i},{j}): nearest triangle {k} is {c:?}, got {px:?}"
                        ));
                    }
                }
                _ => continue,
            }
            checked += 1;
        }
    }
    Ok(checked)
}

/// The triangles as the renderer sees them after the documented snapping step: x, y
/// rounded to 1/256 px (ties away from zero), z mapped affinely from the scene's z range
/// onto the 24-bit geometry range `16 ..= 2^24 − 17` and rounded. Depths are then compared
/// in 24-bit units: a thin, nearly edge-on triangle's plane is ill-conditioned, and
/// snapping its vertices by 1/512 px can move its depth elsewhere by far more than any
/// tolerance on the unsnapped z would allow.
fn snapped(tris: &[Tri]) -> Vec<Tri> {
    let zs = tris.iter().flat_map(|t| t.v.iter().map(|p| p[2]));
    let lo = zs.clone().fold(f64::INFINITY, f64::min);
    let hi = zs.fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 1.0, lo + 1.0)
    };
    let (gmin, gmax) = (16.0, (1u32 << 24) as f64 - 17.0);
    tris.iter()
        .map(|t| Tri {
            v: t.v.map(|p| {
                [
                    (p[0] * 256.0).round() / 256.0,
                    (p[1] * 256.0).round() / 256.0,
                    (gmin + ((p[2] - lo) / (hi - lo) * (gmax - gmin)).round()),
                ]
            }),
            color: t.color,
        })
        .collect()
}

fn arb_tri() -> impl Strategy<Value = Tri> {
    (
        proptest::collection::vec((-10.0f64..90.0, -10.0f64..70.0, 0.0f64..1.0), 3),
        proptest::collection::vec(0.0f64..=1.0, 3),
    )
        .prop_map(|(v, c)| Tri {
            v: [
                [v[0].0, v[0].1, v[0].2],
                [v[1].0, v[1].1, v[1].2],
                [v[2].0, v[2].1, v[2].2],
            ],
            color: [c[0], c[1], c[2]],
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Overlapping and interpenetrating random triangles: visible colour per pixel equals
    /// the float ray cast's, at every array width (tiling must not change a bit).
    #[test]
    fn visible_surface_matches_float_reference(tris in proptest::collection::vec(arb_tri(), 1..12)) {
        let (w, h) = (80, 60);
        let ls = load(&scene_json(w, h, &tris));
        let rgb = render_rgb(&ls, 64);
        let r = check_visibility(w, h, &snapped(&tris), &rgb);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
        for aw in [1, 7, 80] {
            prop_assert_eq!(&render_rgb(&ls, aw), &rgb, "array width {} changed the image", aw);
        }
    }
}

#[test]
fn colours_round_to_nearest_8_bit_level() {
    // 0.5·255 = 127.5 rounds up; 1/255·k is exact.
    let tris = [
        Tri {
            v: [[0.0, 0.0, 0.5], [16.0, 0.0, 0.5], [0.0, 16.0, 0.5]],
            color: [0.5, 1.0 / 255.0, 1.0],
        },
        Tri {
            v: [[16.0, 0.0, 0.6], [16.0, 16.0, 0.6], [0.0, 16.0, 0.6]],
            color: [0.2, 0.0, 0.998],
        },
    ];
    let ls = load(&scene_json(16, 16, &tris));
    let rgb = render_rgb(&ls, 64);
    assert_eq!(&rgb[..3], &[128, 1, 255]);
    let last = rgb.len() - 3;
    assert_eq!(&rgb[last..], &[51, 0, 254]);
    assert!(check_visibility(16, 16, &snapped(&tris), &rgb).unwrap() > 200);
}

#[test]
fn degenerate_triangles_render_nothing() {
    let tris = [
        Tri {
            v: [[1.0, 1.0, 0.1], [5.0, 5.0, 0.2], [9.0, 9.0, 0.3]],
            color: [1.0, 1.0, 1.0],
        },
        Tri {
            v: [[3.0, 3.0, 0.1], [3.0, 3.0, 0.2], [3.0, 3.0, 0.3]],
            color: [1.0, 1.0, 1.0],
        },
    ];
    let ls = load(&scene_json(12, 12, &tris));
    assert!(render_rgb(&ls, 64).iter().all(|&b| b == 0));
}

#[test]
fn gouraud_intensity_follows_the_plane() {
    // Red ramps 0 → 1 across 256 px: every covered pixel within one level of the float value.
    let json = r#"{"width":256,"height":4,"background":[0,0,0],"triangles":[
        {"v":[[0,0,0],[256,0,0],[0,256,0]],"color":[0,0,0],"colors":[[0,0,0],[1,0,0],[0,0,0]]}]}"#;
    let ls = load(json);
    let rgb = render_rgb(&ls, 64);
    for i in 0..250u32 {
        let expect = (i as f64 + 0.5) / 256.0 * 255.0;
        let got = rgb[(i * 3) as usize] as f64;
        assert!((got - expect).abs() <= 1.0, "column {i}: {got} vs {expect}");
    }
}

/// Regression guard: the embedded default scene's image, stored as PNG. Correctness comes
/// from the checks above; this catches unintended changes. Set PIXELPROC_BLESS=1 to rewrite
/// it after an intended change (and say why in the commit).
#[test]
fn default_scene_regression_image() {
    let ls = scene::load_builtin("default").unwrap();
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    let img = render(&ls, &fx).unwrap().image;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/default.png");
    if std::env::var_os("PIXELPROC_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        image::save_buffer(
            &path,
            &img.data,
            img.width,
            img.height,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
    }
    let golden = image::open(&path)
        .expect("golden image (run with PIXELPROC_BLESS=1 to create)")
        .to_rgb8();
    assert_eq!((golden.width(), golden.height()), (img.width, img.height));
    let diff = golden
        .as_raw()
        .iter()
        .zip(&img.data)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(diff, 0, "{diff} bytes differ from tests/golden/default.png");
}
