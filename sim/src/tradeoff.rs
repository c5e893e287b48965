//! The accuracy/time trade-off sweep behind `pixelproc tradeoff` (see `docs/accuracy.md`).
//!
//! Every anti-aliasing method of [`crate::aa`] with every setting of the sweep
//! ([`sweep_settings`]) renders every scene of a set ([`builtin_scenes`], or a folder of
//! scene files, [`load_scene_dir`]). Each image is judged against the exact box-filtered
//! reference of [`crate::reference`]: RMSE and maximum error on the 0..255 scale, and the
//! pixels whose visible surface (the triangle with the largest visible area) differs from
//! the reference's. Cost is the median wall-clock time of `runs` renders on **one thread**,
//! the depth evaluations and sample-memory reads per pixel the methods count themselves,
//! and the shade levels a long near-horizontal / near-vertical edge gets
//! ([`crate::aa::edge_shade_levels`]).
//!
//! Outputs ([`write_outputs`]): a CSV per setting, a CSV per setting and scene, a
//! Markdown report, a PNG chart of error against time with the Pareto frontier marked, and
//! a montage of difference heat maps for one scene.
//!
//! Threads: timed renders run one at a time inside a rayon pool of one thread, so methods
//! whose inner loops use rayon are timed sequentially and timings compare. Untimed work
//! (reference images, the accuracy render, A-buffer variant comparison) uses the global
//! pool; its results do not depend on the thread count.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_formats::{Z_GEOM_MAX, Z_GEOM_MIN};
use thiserror::Error;

use crate::aa::{
    edge_shade_levels, render_aa, AaError, AaMethod, CornerParams, Filter, MultiscanParams,
    Pattern, PostFxParams,
};
use crate::abuffer::{render_abuffer, AbufferParams};
use crate::mask_search::DepthSelect;
use crate::reference::{reference_image, RefImage};
use crate::setup::{HostPlane, SnappedTri};

/// Errors of the trade-off sweep.
#[derive(Debug, Error)]
pub enum TradeoffError {
    /// Reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// A scene file could not be loaded.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// A scene could not be projected.
    #[error("{0}: {1}")]
    Front(String, crate::frontend::FrontError),
    /// A method failed on a scene.
    #[error("{method} on {scene}: {source}")]
    Render {
        /// Setting label.
        method: String,
        /// Scene name.
        scene: String,
        /// Cause.
        source: AaError,
    },
    /// The scene folder holds no scene.
    #[error("no scene files (*.json) in {0}")]
    NoScenes(String),
    /// A bad option.
    #[error("{0}")]
    Option(String),
    /// Drawing the chart or the heat maps failed.
    #[error("drawing {0}")]
    Plot(String),
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> TradeoffError + '_ {
    move |source| TradeoffError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// One scene of the set: screen-space snapped triangles in scene order.
#[derive(Clone, Debug)]
pub struct TestScene {
    /// Short name (file stem for a folder scene).
    pub name: String,
    /// What the scene exercises.
    pub about: String,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Background, RGB8.
    pub bg: [u8; 3],
    /// Triangles in scene order.
    pub tris: Vec<SnappedTri>,
    /// The scene declares interpenetrating surfaces (A-buffer: search the max depth too).
    pub interpenetrating: bool,
}

/// One setting of the sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    /// Method family (`none`, `multiscan`, `abuffer`, `corner`, `d3d4x`, `grid2x2`,
    /// `postfx`, `ssaa`).
    pub method: String,
    /// The setting within the family, e.g. `n=3 box`.
    pub setting: String,
    /// The method with its parameters (for the A-buffer, `interpenetrating` is taken from
    /// each scene).
    pub aa: AaMethod,
}

fn setting(aa: AaMethod) -> Setting {
    let (method, setting) = match &aa {
        AaMethod::None => ("none".to_string(), "1 sample".to_string()),
        AaMethod::Multiscan(p) => (
            "multiscan".into(),
            format!(
                "n={} {}",
                p.subscanlines,
                format!("{:?}", p.filter).to_lowercase()
            ),
        ),
        AaMethod::Abuffer(p) => ("abuffer".into(), format!("{} {}", p.size, p.depth.name())),
        AaMethod::Corner(p) => match p.pattern {
            Pattern::Corner => (
                "corner".into(),
                if p.centre {
                    "2 spp (+centre)".into()
                } else {
                    "1 spp".into()
                },
            ),
            Pattern::D3d4x => ("d3d4x".into(), "4 spp".into()),
            Pattern::Grid2x2 => ("grid2x2".into(), "4 spp".into()),
        },
        AaMethod::PostFx(p) => (
            "postfx".into(),
            if *p == PostFxParams::default() {
                "default".into()
            } else {
                p.label()
            },
        ),
        AaMethod::Ssaa { k } => ("ssaa".into(), format!("k={k} ({}x{})", k, k)),
    };
    let setting = if setting.is_empty() {
        "default".into()
    } else {
        setting
    };
    Setting {
        method,
        setting,
        aa,
    }
}

/// The settings of the sweep. Full: none; multiscan n ∈ {1,2,3,4,6,8,12} × {box, gauss};
/// A-buffer 4×4 and 8×8 × {center, search, slope, exhaustive}; corner sampling with 1 and
/// 2 samples per pixel; D3D 4× and ordered 2×2; post-process; supersampling k ∈ {2,3,4,8}.
/// Quick: a subset for tests (none, multiscan n ∈ {1,4,12} box, A-buffer 4×4 search,
/// corner 1 spp, post-process, ssaa k ∈ {2,8}).
pub fn sweep_settings(quick: bool) -> Vec<Setting> {
    let mut m = vec![AaMethod::None];
    let ns: &[u32] = if quick {
        &[1, 4, 12]
    } else {
        &[1, 2, 3, 4, 6, 8, 12]
    };
    let filters: &[Filter] = if quick {
        &[Filter::Box]
    } else {
        &[Filter::Box, Filter::Gauss]
    };
    for &f in filters {
        for &n in ns {
            m.push(AaMethod::Multiscan(MultiscanParams::new(n, f)));
        }
    }
    let sizes: &[MaskSize] = if quick {
        &[MaskSize::S4X4]
    } else {
        &[MaskSize::S4X4, MaskSize::S8X8]
    };
    let depths: &[DepthSelect] = if quick {
        &[DepthSelect::Search]
    } else {
        &DepthSelect::ALL
    };
    for &size in sizes {
        for &depth in depths {
            m.push(AaMethod::Abuffer(AbufferParams {
                size,
                depth,
                interpenetrating: false,
                compare_variants: false,
            }));
        }
    }
    m.push(AaMethod::Corner(CornerParams::new(Pattern::Corner, false)));
    if !quick {
        m.push(AaMethod::Corner(CornerParams::new(Pattern::Corner, true)));
        m.push(AaMethod::Corner(CornerParams::new(Pattern::D3d4x, false)));
        m.push(AaMethod::Corner(CornerParams::new(Pattern::Grid2x2, false)));
    }
    m.push(AaMethod::PostFx(PostFxParams::default()));
    // k = 3 as well: the multi-scanning paper compares against 3×3 supersampling.
    let ks: &[u32] = if quick { &[2, 8] } else { &[2, 3, 4, 8] };
    for &k in ks {
        m.push(AaMethod::Ssaa { k });
    }
    m.into_iter().map(setting).collect()
}

// ---------------------------------------------------------------------------------------
// Built-in scene set
// ---------------------------------------------------------------------------------------

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    fn sign(&mut self) -> f64 {
        if self.next() & 1 == 0 {
            1.0
        } else {
            -1.0
        }
    }
    fn colour(&mut self) -> [f64; 3] {
        [
            self.range(0.15, 1.0),
            self.range(0.15, 1.0),
            self.range(0.15, 1.0),
        ]
    }
}

fn q8(x: f64) -> i32 {
    (x * 256.0).round() as i32
}

/// Depth on 0..1 to the 24-bit geometry range.
fn zq(z: f64) -> u32 {
    (Z_GEOM_MIN as f64 + z.clamp(0.0, 1.0) * (Z_GEOM_MAX - Z_GEOM_MIN) as f64).round() as u32
}

/// Colour on 0..1 to Q8.12 with the +2048 rounding offset (`docs/formats.md`).
fn cq(c: f64) -> u32 {
    (c.clamp(0.0, 1.0) * 255.0 * 4096.0).floor() as u32 + 2048
}

/// A triangle with a depth function and per-vertex colours.
fn tri_f(v: [[f64; 2]; 3], z: impl Fn([f64; 2]) -> f64, c: [[f64; 3]; 3], tag: u16) -> SnappedTri {
    SnappedTri {
        v: v.map(|p| [q8(p[0]), q8(p[1])]),
        z: v.map(|p| zq(z(p))),
        c: c.map(|k| k.map(cq)),
        tag,
        host: None,
        nclass: 0,
    }
}

/// Flat-coloured triangle on the plane `z`.
fn flat(v: [[f64; 2]; 3], z: impl Fn([f64; 2]) -> f64, c: [f64; 3], tag: u16) -> SnappedTri {
    tri_f(v, z, [c; 3], tag)
}

/// A convex quad `p0 p1 p2 p3` as two triangles on the plane `z`.
fn quad(
    p: [[f64; 2]; 4],
    z: impl Fn([f64; 2]) -> f64 + Copy,
    c: [f64; 3],
    tag: u16,
) -> [SnappedTri; 2] {
    [
        flat([p[0], p[1], p[2]], z, c, tag),
        flat([p[0], p[2], p[3]], z, c, tag),
    ]
}

/// A far background covering the whole screen, with a gentle colour gradient.
fn backdrop(s: f64) -> [SnappedTri; 2] {
    let z = |_: [f64; 2]| 0.98;
    let (a, b) = ([0.18, 0.2, 0.28], [0.3, 0.26, 0.2]);
    let p = [
        [-2.0, -2.0],
        [s + 2.0, -2.0],
        [s + 2.0, s + 2.0],
        [-2.0, s + 2.0],
    ];
    [
        tri_f([p[0], p[1], p[2]], z, [a, a, b], 0),
        tri_f([p[0], p[2], p[3]], z, [a, b, b], 0),
    ]
}

fn transpose(tris: &mut [SnappedTri]) {
    for t in tris {
        for v in &mut t.v {
            v.swap(0, 1);
        }
        if let Some(h) = &mut t.host {
            for v in &mut h.v {
                v.swap(0, 1);
            }
        }
    }
}

fn scene_ordinary(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    let n = 40;
    for k in 0..n {
        let (cx, cy) = (rng.range(0.0, s), rng.range(0.0, s));
        let r = rng.range(4.0, s / 5.0);
        let v = [0; 3].map(|_| [cx + rng.range(-r, r), cy + rng.range(-r, r)]);
        // Separate depth layers with gentle slopes: ordinary, non-interpenetrating.
        let z0 = 0.1 + 0.8 * rng.unit();
        let (gx, gy) = (rng.range(-1e-4, 1e-4), rng.range(-1e-4, 1e-4));
        let c = [rng.colour(), rng.colour(), rng.colour()];
        out.push(tri_f(
            v,
            move |p| z0 + gx * (p[0] - cx) + gy * (p[1] - cy),
            c,
            k + 1,
        ));
    }
    out
}

fn scene_mesh(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    let g = 10usize;
    let (lo, hi) = (0.08 * s, 0.92 * s);
    let cell = (hi - lo) / g as f64;
    let mut pts = vec![[0.0; 2]; (g + 1) * (g + 1)];
    for j in 0..=g {
        for i in 0..=g {
            let jitter = if i == 0 || j == 0 || i == g || j == g {
                0.0
            } else {
                0.35 * cell
            };
            pts[j * (g + 1) + i] = [
                lo + i as f64 * cell + rng.range(-jitter, jitter),
                lo + j as f64 * cell + rng.range(-jitter, jitter),
            ];
        }
    }
    let c0 = s / 2.0;
    let z = move |p: [f64; 2]| {
        let d = ((p[0] - c0).powi(2) + (p[1] - c0).powi(2)) / (s * s);
        0.2 + 0.6 * d
    };
    let col = move |p: [f64; 2]| {
        let u = p[0] / s;
        let v = p[1] / s;
        [0.3 + 0.6 * u, 0.25 + 0.5 * (1.0 - v), 0.4 + 0.5 * (u * v)]
    };
    for j in 0..g {
        for i in 0..g {
            let a = pts[j * (g + 1) + i];
            let b = pts[j * (g + 1) + i + 1];
            let c = pts[(j + 1) * (g + 1) + i + 1];
            let d = pts[(j + 1) * (g + 1) + i];
            for t in [[a, b, c], [a, c, d]] {
                // One object: every triangle of the mesh shares tag 1.
                out.push(tri_f(t, z, t.map(col), 1));
            }
        }
    }
    out
}

fn scene_slivers(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    for k in 0..36 {
        let p = [rng.range(0.0, s), rng.range(0.0, s)];
        let th = rng.range(0.0, std::f64::consts::TAU);
        let (d, n) = ([th.cos(), th.sin()], [-th.sin(), th.cos()]);
        let len = rng.range(0.3 * s, 0.9 * s);
        let w = rng.range(0.1, 1.5);
        let tip = [p[0] + len * d[0], p[1] + len * d[1]];
        let v = [
            p,
            [tip[0] + 0.5 * w * n[0], tip[1] + 0.5 * w * n[1]],
            [tip[0] - 0.5 * w * n[0], tip[1] - 0.5 * w * n[1]],
        ];
        let z0 = 0.1 + 0.8 * rng.unit();
        out.push(flat(v, move |_| z0, rng.colour(), k + 1));
    }
    out
}

/// Horizontal bands whose top and bottom edges have slopes between 1/96 and 1/6.
fn scene_near_horizontal(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    let mut y = 3.0;
    let mut k = 1;
    while y < s - 6.0 {
        let h = rng.range(4.0, 10.0);
        let s1 = rng.sign() * rng.range(1.0 / 96.0, 1.0 / 6.0);
        let s2 = rng.sign() * rng.range(1.0 / 96.0, 1.0 / 6.0);
        let (x0, x1) = (-2.0, s + 2.0);
        let ym = y + h / 2.0;
        let p = [
            [x0, ym - h / 2.0 + s1 * (x0 - s / 2.0)],
            [x1, ym - h / 2.0 + s1 * (x1 - s / 2.0)],
            [x1, ym + h / 2.0 + s2 * (x1 - s / 2.0)],
            [x0, ym + h / 2.0 + s2 * (x0 - s / 2.0)],
        ];
        let z0 = 0.1 + 0.8 * rng.unit();
        let (gx, gy) = (rng.range(-1e-4, 1e-4), rng.range(-1e-4, 1e-4));
        let z = move |q: [f64; 2]| z0 + gx * q[0] + gy * q[1];
        // Skip a band whose slopes cross inside the screen (a bow tie is not convex).
        let left_h = p[3][1] - p[0][1];
        let right_h = p[2][1] - p[1][1];
        if left_h > 0.5 && right_h > 0.5 {
            out.extend(quad(p, z, rng.colour(), k));
        }
        k += 1;
        y += h * 0.8;
    }
    out
}

/// Thin bars side by side: heights 0.25..1 px, gaps 0.5..1.5 px, slopes up to 1/40.
fn scene_thin_horizontal(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    let cols = [[1.0, 1.0, 1.0], [1.0, 0.35, 0.2], [0.3, 1.0, 0.4]];
    let heights = [0.25, 0.5, 0.75, 1.0];
    let gaps = [0.5, 1.0, 1.5];
    let mut y = 2.0;
    let mut k = 0usize;
    while y < s - 3.0 {
        let h = heights[k % heights.len()];
        let g = gaps[(k / heights.len()) % gaps.len()];
        let slope = rng.sign() * rng.range(1.0 / 200.0, 1.0 / 40.0);
        let (x0, x1) = (6.0, s - 6.0);
        let yc = |x: f64| y + slope * (x - s / 2.0);
        let p = [
            [x0, yc(x0)],
            [x1, yc(x1)],
            [x1, yc(x1) + h],
            [x0, yc(x0) + h],
        ];
        let z0 = 0.2 + 0.6 * rng.unit();
        out.extend(quad(p, move |_| z0, cols[k % 3], k as u16 + 1));
        y += h + g;
        k += 1;
    }
    out
}

/// Pairs of large triangles whose depth planes cross (interpenetrating surfaces).
fn scene_interpenetrating(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    for k in 0..14u16 {
        let (cx, cy) = (rng.range(0.0, s), rng.range(0.0, s));
        let r = rng.range(0.1 * s, 0.3 * s);
        let v1 = [0; 3].map(|_| [cx + rng.range(-r, r), cy + rng.range(-r, r)]);
        let v2 = [0; 3].map(|_| [cx + rng.range(-r, r), cy + rng.range(-r, r)]);
        let z0 = 0.2 + 0.6 * rng.unit();
        let (a, b) = (rng.range(0.001, 0.004), rng.range(-0.002, 0.002));
        out.push(flat(
            v1,
            move |p| z0 + a * (p[0] - cx),
            [1.0, 0.3, 0.25],
            2 * k + 1,
        ));
        out.push(flat(
            v2,
            move |p| z0 - a * (p[0] - cx) + b * (p[1] - cy),
            [0.25, 0.35, 1.0],
            2 * k + 2,
        ));
    }
    out
}

/// Overlapping large triangles on nearly the same plane: depths a few to a few hundred
/// 24-bit units apart with slightly different tilts, so which one is in front changes
/// along lines across the screen.
fn scene_coplanar(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    let unit = 1.0 / (Z_GEOM_MAX - Z_GEOM_MIN) as f64;
    for k in 0..8u16 {
        let (cx, cy) = (rng.range(0.2 * s, 0.8 * s), rng.range(0.2 * s, 0.8 * s));
        let r = rng.range(0.3 * s, 0.6 * s);
        let v = [0; 3].map(|_| [cx + rng.range(-r, r), cy + rng.range(-r, r)]);
        let off = rng.range(2.0, 300.0) * unit;
        let (tx, ty) = (rng.range(-3.0, 3.0) * unit, rng.range(-3.0, 3.0) * unit);
        let z = move |p: [f64; 2]| {
            0.5 + 0.0005 * p[0] + 0.0002 * p[1] + off + tx * (p[0] - cx) + ty * (p[1] - cy)
        };
        out.push(flat(v, z, rng.colour(), k + 1));
    }
    out
}

/// Faces with shadow regions drawn as darker coplanar decals (patterns on the faces, as the
/// multi-scanning paper draws them): shadow boundaries are edges between two surfaces of
/// identical depth, so only the decal rule decides visibility.
/// A quad face: corners, colour, and depth plane `z0 + gx·x + gy·y`.
type Face = ([[f64; 2]; 4], [f64; 3], f64, f64, f64);

fn scene_shadows(s: f64, rng: &mut Rng) -> Vec<SnappedTri> {
    let mut out = backdrop(s).to_vec();
    // Floor, a wall and two faces of a box, each a quad on its own plane.
    let faces: [Face; 4] = [
        (
            [[0.0, 0.55 * s], [s, 0.5 * s], [s, s], [0.0, s]],
            [0.75, 0.72, 0.6],
            0.6,
            0.0,
            -0.002,
        ),
        (
            [
                [0.05 * s, 0.05 * s],
                [0.7 * s, 0.1 * s],
                [0.7 * s, 0.55 * s],
                [0.05 * s, 0.58 * s],
            ],
            [0.6, 0.7, 0.85],
            0.7,
            0.001,
            0.0,
        ),
        (
            [
                [0.45 * s, 0.45 * s],
                [0.7 * s, 0.4 * s],
                [0.72 * s, 0.8 * s],
                [0.47 * s, 0.85 * s],
            ],
            [0.9, 0.5, 0.3],
            0.3,
            0.0005,
            0.0003,
        ),
        (
            [
                [0.7 * s, 0.4 * s],
                [0.85 * s, 0.47 * s],
                [0.86 * s, 0.84 * s],
                [0.72 * s, 0.8 * s],
            ],
            [0.8, 0.42, 0.25],
            0.31,
            -0.001,
            0.0003,
        ),
    ];
    for (tag, (p, col, z0, gx, gy)) in (1..).zip(faces) {
        let z = move |q: [f64; 2]| z0 + gx * q[0] + gy * q[1];
        let hosts = quad(p, z, col, tag);
        let dark = col.map(|c| c * 0.35);
        out.extend(hosts);
        for h in hosts {
            // Shadow polygons: triangles inside the host triangle (barycentric), decals
            // on the host's plane.
            let hv = h.v.map(|v| [v[0] as f64 / 256.0, v[1] as f64 / 256.0]);
            for _ in 0..3 {
                let v = [0; 3].map(|_| {
                    let (mut a, mut b) = (rng.unit(), rng.unit());
                    if a + b > 1.0 {
                        (a, b) = (1.0 - a, 1.0 - b);
                    }
                    let c = 1.0 - a - b;
                    [
                        a * hv[0][0] + b * hv[1][0] + c * hv[2][0],
                        a * hv[0][1] + b * hv[1][1] + c * hv[2][1],
                    ]
                });
                let mut d = flat(v, z, dark, tag);
                d.host = Some(HostPlane { v: h.v, z: h.z });
                out.push(d);
            }
        }
    }
    out
}

/// The built-in scene set, `size × size` pixels each (160 for the full sweep; the quick set
/// uses two 40×40 scenes).
pub fn builtin_scenes(quick: bool) -> Vec<TestScene> {
    type Gen = fn(f64, &mut Rng) -> Vec<SnappedTri>;
    let all: [(&str, &str, Gen, bool, bool); 10] = [
        (
            "ordinary",
            "40 random Gouraud triangles in separate depth layers",
            scene_ordinary,
            false,
            false,
        ),
        (
            "mesh",
            "a jittered 10×10 grid mesh, one object (shared edges)",
            scene_mesh,
            false,
            false,
        ),
        (
            "slivers",
            "36 needles 0.1–1.5 px wide at random angles",
            scene_slivers,
            false,
            false,
        ),
        (
            "near-horizontal",
            "bands with edge slopes 1/96–1/6 from horizontal",
            scene_near_horizontal,
            false,
            false,
        ),
        (
            "near-vertical",
            "the near-horizontal scene transposed",
            scene_near_horizontal,
            true,
            false,
        ),
        (
            "thin-horizontal",
            "bars 0.25–1 px high, 0.5–1.5 px apart, slopes ≤ 1/40",
            scene_thin_horizontal,
            false,
            false,
        ),
        (
            "thin-vertical",
            "the thin-horizontal scene transposed",
            scene_thin_horizontal,
            true,
            false,
        ),
        (
            "interpenetrating",
            "14 pairs of triangles whose planes cross",
            scene_interpenetrating,
            false,
            true,
        ),
        (
            "coplanar",
            "8 overlapping triangles 2–300 depth units apart, tilted",
            scene_coplanar,
            false,
            false,
        ),
        (
            "shadows",
            "faces with darker coplanar decal triangles as shadow regions",
            scene_shadows,
            false,
            false,
        ),
    ];
    let size = if quick { 40 } else { 160 };
    let pick: &[usize] = if quick {
        &[0, 5]
    } else {
        &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]
    };
    pick.iter()
        .map(|&k| {
            let (name, about, gen, tr, inter) = all[k];
            // Same seed for a scene and its transpose.
            let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ ((k as u64 - tr as u64) * 0x1000_0001));
            let mut tris = gen(size as f64, &mut rng);
            if tr {
                transpose(&mut tris);
            }
            TestScene {
                name: name.into(),
                about: about.into(),
                width: size,
                height: size,
                bg: [20, 24, 32],
                tris,
                interpenetrating: inter,
            }
        })
        .collect()
}

/// Loads every `*.json` scene file of `dir` (sorted by name). Screen-space and 3-D scenes
/// both go through the front end ([`crate::frontend::project`]); the sweep sees the
/// snapped screen-space triangles, so the exact reference applies to both (it judges
/// anti-aliasing of the projected triangles; shadows of 3-D scenes are not drawn).
pub fn load_scene_dir(dir: &Path) -> Result<Vec<TestScene>, TradeoffError> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(io_err(dir))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(TradeoffError::NoScenes(dir.display().to_string()));
    }
    let mut out = Vec::new();
    for f in files {
        let ls = crate::scene::load_file(&f)?;
        let pr = crate::frontend::project(&ls)
            .map_err(|e| TradeoffError::Front(f.display().to_string(), e))?;
        let bg = ls
            .scene
            .background
            .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
        out.push(TestScene {
            name: f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            about: if ls.is_3d() {
                "3-D scene, projected (no shadows)".into()
            } else {
                "screen-space scene".into()
            },
            width: ls.scene.width,
            height: ls.scene.height,
            bg,
            tris: pr.tris,
            interpenetrating: ls.scene.effects.interpenetrating,
        });
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// Measurement
// ---------------------------------------------------------------------------------------

/// Measurements of one setting on one scene.
#[derive(Clone, Debug)]
pub struct SceneResult {
    /// Scene name.
    pub scene: String,
    /// Median CPU time of one frame on one thread, seconds (the rendering thread's own
    /// CPU clock: insensitive to other processes on the machine; wall clock where the
    /// platform has no thread clock).
    pub seconds: f64,
    /// Median wall-clock time of the same runs, seconds.
    pub wall_seconds: f64,
    /// Depth evaluations.
    pub depth_evals: u64,
    /// Sample-memory reads of the resolve.
    pub sample_reads: u64,
    /// Pixels.
    pub pixels: u64,
    /// Sum of squared channel errors against the reference.
    pub sq_err: f64,
    /// Largest channel error.
    pub max_err: f64,
    /// Pixels whose visible surface differs from the reference's dominant surface.
    pub wrong_visible: u64,
    /// Of those, pixels where the reference's dominant surface covers at least 3/4 of the
    /// pixel (a clear majority: not a near-tie at an edge).
    pub wrong_visible_clear: u64,
}

impl SceneResult {
    /// RMSE over all channels of all pixels.
    pub fn rmse(&self) -> f64 {
        (self.sq_err / (3 * self.pixels).max(1) as f64).sqrt()
    }
}

/// One row of the result: a setting with its per-scene results and totals.
#[derive(Clone, Debug)]
pub struct Row {
    /// The setting.
    pub setting: Setting,
    /// Per scene, in scene order.
    pub scenes: Vec<SceneResult>,
    /// Shade levels on a near-horizontal and a near-vertical edge.
    pub shade_levels: (usize, usize),
}

impl Row {
    fn sum<T: std::iter::Sum<T>>(&self, f: impl Fn(&SceneResult) -> T) -> T {
        self.scenes.iter().map(f).sum()
    }
    /// Mean over scenes of the per-scene median frame time (thread CPU time),
    /// milliseconds.
    pub fn ms_per_frame(&self) -> f64 {
        1e3 * self.sum(|s| s.seconds) / self.scenes.len().max(1) as f64
    }
    /// The same for wall-clock time.
    pub fn wall_ms_per_frame(&self) -> f64 {
        1e3 * self.sum(|s| s.wall_seconds) / self.scenes.len().max(1) as f64
    }
    /// Depth evaluations per pixel over the whole set.
    pub fn evals_per_pixel(&self) -> f64 {
        self.sum(|s| s.depth_evals) as f64 / self.sum(|s| s.pixels).max(1) as f64
    }
    /// Sample-memory reads per pixel over the whole set.
    pub fn reads_per_pixel(&self) -> f64 {
        self.sum(|s| s.sample_reads) as f64 / self.sum(|s| s.pixels).max(1) as f64
    }
    /// RMSE pooled over every channel of every pixel of the set.
    pub fn rmse(&self) -> f64 {
        (self.sum(|s| s.sq_err) / (3 * self.sum(|s| s.pixels)).max(1) as f64).sqrt()
    }
    /// Largest channel error over the set.
    pub fn max_err(&self) -> f64 {
        self.scenes.iter().map(|s| s.max_err).fold(0.0, f64::max)
    }
    /// Wrong-visible-surface pixels over the set.
    pub fn wrong_visible(&self) -> u64 {
        self.sum(|s| s.wrong_visible)
    }
    /// Wrong-visible-surface pixels where the reference has a clear majority surface.
    pub fn wrong_visible_clear(&self) -> u64 {
        self.sum(|s| s.wrong_visible_clear)
    }
}

/// How often each A-buffer depth variant orders a pixel's fragments differently from the
/// exhaustive search, per mask size (summed over the scene set).
#[derive(Clone, Debug)]
pub struct VariantRow {
    /// Mask size.
    pub size: MaskSize,
    /// Pixels with two or more fragments.
    pub multi_pixels: u64,
    /// Fragments in those pixels.
    pub sorted_fragments: u64,
    /// Per variant ([`DepthSelect::ALL`] order): depth evaluations.
    pub evals: [u64; 4],
    /// Per variant: pixels packed in a different order from exhaustive.
    pub order_diff: [u64; 4],
    /// Per variant: pixels whose visible subpixels differ from exhaustive.
    pub visible_diff: [u64; 4],
    /// Per variant: pixels whose colour differs from exhaustive.
    pub rgb_diff: [u64; 4],
}

/// Options of [`run_sweep`].
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Timed runs per setting and scene (median reported), after one untimed render.
    pub runs: usize,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// The whole result.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// Scenes (names, sizes, descriptions).
    pub scenes: Vec<(String, String, u32, u32, usize)>,
    /// One row per setting, in sweep order.
    pub rows: Vec<Row>,
    /// A-buffer variant comparison.
    pub variants: Vec<VariantRow>,
    /// Timed runs per measurement.
    pub runs: usize,
    /// Logical cores of the machine.
    pub cores: usize,
    /// The scene of the heat maps, with the reference and each setting's image.
    pub heat: Option<HeatData>,
}

/// Images of one scene for the heat maps.
#[derive(Clone, Debug)]
pub struct HeatData {
    /// Scene name.
    pub scene: String,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Reference, f64 RGB.
    pub reference: Vec<[f64; 3]>,
    /// Per setting (sweep order): RGB8.
    pub images: Vec<Vec<u8>>,
}

fn with_scene(aa: &AaMethod, sc: &TestScene) -> AaMethod {
    match aa {
        AaMethod::Abuffer(p) => AaMethod::Abuffer(AbufferParams {
            interpenetrating: sc.interpenetrating,
            ..*p
        }),
        m => m.clone(),
    }
}

fn judge(r: &RefImage, rgb: &[u8], visible: Option<&Vec<i32>>) -> (f64, f64, u64, u64) {
    let mut sq = 0.0;
    let mut mx: f64 = 0.0;
    for (k, c) in r.rgb.iter().enumerate() {
        for ch in 0..3 {
            let d = rgb[3 * k + ch] as f64 - c[ch];
            sq += d * d;
            mx = mx.max(d.abs());
        }
    }
    let (mut wrong, mut clear) = (0, 0);
    if let Some(v) = visible {
        for (k, (&a, &b)) in v.iter().zip(&r.dominant).enumerate() {
            if a != b {
                wrong += 1;
                if r.dominant_area[k] >= 0.75 {
                    clear += 1;
                }
            }
        }
    }
    (sq, mx, wrong, clear)
}

/// CPU time consumed by the calling thread, seconds.
#[cfg(unix)]
fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant.
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (r == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// No thread clock: the caller falls back to wall-clock time.
#[cfg(not(unix))]
fn thread_cpu_seconds() -> Option<f64> {
    None
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs every setting on every scene. `heat_scene` names the scene whose images are kept
/// for the heat maps (default: `thin-horizontal` if present, else the first scene).
pub fn run_sweep(
    scenes: &[TestScene],
    settings: &[Setting],
    opts: &SweepOptions,
    heat_scene: Option<&str>,
) -> Result<Sweep, TradeoffError> {
    if opts.runs == 0 {
        return Err(TradeoffError::Option("--runs must be at least 1".into()));
    }
    if scenes.is_empty() {
        return Err(TradeoffError::Option("no scenes".into()));
    }
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| TradeoffError::Option(format!("thread pool: {e}")))?;
    let heat_name = heat_scene
        .map(str::to_string)
        .or_else(|| {
            scenes
                .iter()
                .find(|s| s.name == "thin-horizontal")
                .map(|s| s.name.clone())
        })
        .unwrap_or_else(|| scenes[0].name.clone());
    let total = (scenes.len() * (settings.len() + 1)) as u64;
    let bar = if opts.progress {
        let b = indicatif::ProgressBar::new(total);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:40}] {pos}/{len} {msg}",
            )
            .map_err(|e| TradeoffError::Option(e.to_string()))?
            .progress_chars("=> "),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let mut rows: Vec<Row> = settings
        .iter()
        .map(|s| {
            let shade = (
                edge_shade_levels(&s.aa, false).unwrap_or(0),
                edge_shade_levels(&s.aa, true).unwrap_or(0),
            );
            Row {
                setting: s.clone(),
                scenes: Vec::new(),
                shade_levels: shade,
            }
        })
        .collect();
    let mut variants: Vec<VariantRow> = [MaskSize::S4X4, MaskSize::S8X8]
        .into_iter()
        .map(|size| VariantRow {
            size,
            multi_pixels: 0,
            sorted_fragments: 0,
            evals: [0; 4],
            order_diff: [0; 4],
            visible_diff: [0; 4],
            rgb_diff: [0; 4],
        })
        .collect();
    let mut heat = None;
    for sc in scenes {
        bar.set_message(format!("{}: reference", sc.name));
        let r = reference_image(&sc.tris, sc.width, sc.height, sc.bg);
        for v in &mut variants {
            let p = AbufferParams {
                size: v.size,
                depth: DepthSelect::Exhaustive,
                interpenetrating: sc.interpenetrating,
                compare_variants: true,
            };
            let f = render_abuffer(&sc.tris, sc.width, sc.height, sc.bg, &p).map_err(|e| {
                TradeoffError::Render {
                    method: format!("abuffer {} compare", v.size),
                    scene: sc.name.clone(),
                    source: match e {
                        crate::abuffer::AbufferError::Setup(s) => AaError::Setup(s),
                        crate::abuffer::AbufferError::ScreenTooLarge(w, h) => AaError::Screen(w, h),
                    },
                }
            })?;
            let st = &f.stats;
            v.multi_pixels += st.multi_pixels;
            v.sorted_fragments += st.sorted_fragments;
            for k in 0..4 {
                v.evals[k] += st.variant_evals[k];
                v.order_diff[k] += st.order_diff[k];
                v.visible_diff[k] += st.visible_diff[k];
                v.rgb_diff[k] += st.rgb_diff[k];
            }
        }
        bar.inc(1);
        let mut images = Vec::new();
        for row in rows.iter_mut() {
            bar.set_message(format!(
                "{}: {} {}",
                sc.name, row.setting.method, row.setting.setting
            ));
            let aa = with_scene(&row.setting.aa, sc);
            let err = |source| TradeoffError::Render {
                method: format!("{} {}", row.setting.method, row.setting.setting),
                scene: sc.name.clone(),
                source,
            };
            // Untimed render for the accuracy figures (any thread count: same image).
            let f = render_aa(&sc.tris, sc.width, sc.height, sc.bg, &aa).map_err(err)?;
            let (sq_err, max_err, wrong, clear) = judge(&r, &f.rgb, f.visible.as_ref());
            let mut times = Vec::with_capacity(opts.runs);
            let mut walls = Vec::with_capacity(opts.runs);
            for _ in 0..opts.runs {
                let t = one.install(|| {
                    let (c0, t0) = (thread_cpu_seconds(), Instant::now());
                    let g = render_aa(&sc.tris, sc.width, sc.height, sc.bg, &aa);
                    let (c1, dt) = (thread_cpu_seconds(), t0.elapsed().as_secs_f64());
                    std::hint::black_box(&g);
                    g.map(|_| (c0.zip(c1).map_or(dt, |(a, b)| b - a), dt))
                });
                let (cpu, wall) = t.map_err(err)?;
                times.push(cpu);
                walls.push(wall);
            }
            row.scenes.push(SceneResult {
                scene: sc.name.clone(),
                seconds: median(times),
                wall_seconds: median(walls),
                depth_evals: f.stats.depth_evals,
                sample_reads: f.stats.sample_reads,
                pixels: f.stats.pixels,
                sq_err,
                max_err,
                wrong_visible: wrong,
                wrong_visible_clear: clear,
            });
            if sc.name == heat_name {
                images.push(f.rgb);
            }
            bar.inc(1);
        }
        if sc.name == heat_name {
            heat = Some(HeatData {
                scene: sc.name.clone(),
                width: sc.width,
                height: sc.height,
                reference: r.rgb.clone(),
                images,
            });
        }
    }
    bar.finish_and_clear();
    Ok(Sweep {
        scenes: scenes
            .iter()
            .map(|s| {
                (
                    s.name.clone(),
                    s.about.clone(),
                    s.width,
                    s.height,
                    s.tris.len(),
                )
            })
            .collect(),
        rows,
        variants,
        runs: opts.runs,
        cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        heat,
    })
}

/// Indices of the points on the Pareto frontier of `(time, error)` (both minimised): no
/// other point is at most as slow and at most as wrong and better in one of the two.
/// Sorted by time.
pub fn pareto_frontier(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let (ti, ei) = points[i];
            !points
                .iter()
                .enumerate()
                .any(|(j, &(tj, ej))| j != i && tj <= ti && ej <= ei && (tj < ti || ej < ei))
        })
        .collect();
    idx.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    idx
}

// ---------------------------------------------------------------------------------------
// Outputs
// ---------------------------------------------------------------------------------------

/// Files written by [`write_outputs`].
#[derive(Clone, Debug)]
pub struct Written {
    /// Per-setting CSV.
    pub csv: PathBuf,
    /// Per-setting-and-scene CSV.
    pub scenes_csv: PathBuf,
    /// Markdown report.
    pub markdown: PathBuf,
    /// Error-against-time chart.
    pub chart: PathBuf,
    /// Heat-map montage (if a heat-map scene was kept).
    pub heatmap: Option<PathBuf>,
}

/// The CSV header of the per-setting file.
pub const CSV_HEADER: &str = "method,setting,ms_per_frame,wall_ms_per_frame,depth_evals_per_px,reads_per_px,rmse,max_err,wrong_visible,wrong_visible_clear,shade_levels_h,shade_levels_v,pareto";

fn points(sw: &Sweep) -> Vec<(f64, f64)> {
    sw.rows
        .iter()
        .map(|r| (r.ms_per_frame(), r.rmse()))
        .collect()
}

/// The per-setting CSV text.
pub fn csv(sw: &Sweep) -> String {
    let front = pareto_frontier(&points(sw));
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for (k, r) in sw.rows.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.2},{},{},{},{},{}",
            r.setting.method,
            r.setting.setting,
            r.ms_per_frame(),
            r.wall_ms_per_frame(),
            r.evals_per_pixel(),
            r.reads_per_pixel(),
            r.rmse(),
            r.max_err(),
            r.wrong_visible(),
            r.wrong_visible_clear(),
            r.shade_levels.0,
            r.shade_levels.1,
            front.contains(&k) as u8
        );
    }
    s
}

/// The per-setting-and-scene CSV text.
pub fn scenes_csv(sw: &Sweep) -> String {
    let mut s = String::from(
        "method,setting,scene,ms_per_frame,wall_ms_per_frame,depth_evals_per_px,reads_per_px,rmse,max_err,wrong_visible,wrong_visible_clear\n",
    );
    for r in &sw.rows {
        for sc in &r.scenes {
            let px = sc.pixels.max(1) as f64;
            let _ = writeln!(
                s,
                "{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.2},{},{}",
                r.setting.method,
                r.setting.setting,
                sc.scene,
                sc.seconds * 1e3,
                sc.wall_seconds * 1e3,
                sc.depth_evals as f64 / px,
                sc.sample_reads as f64 / px,
                sc.rmse(),
                sc.max_err,
                sc.wrong_visible,
                sc.wrong_visible_clear
            );
        }
    }
    s
}

/// The Markdown report. `command` is the command line that produced it.
pub fn markdown(sw: &Sweep, command: &str) -> String {
    let front = pareto_frontier(&points(sw));
    let mut s = String::new();
    let px: u64 = sw.rows.first().map_or(0, |r| r.sum(|s| s.pixels));
    let _ = writeln!(s, "# Anti-aliasing trade-off\n");
    let _ = writeln!(
        s,
        "Command: `{command}`. Machine: {} logical cores; every timed render ran alone on \
         one thread (a one-thread rayon pool); `ms/frame` is that thread's CPU time, the \
         median of {} runs per scene averaged over the {} scenes (`wall` is wall-clock \
         time of the same runs, which other load on the machine inflates). Errors are on the 0..255 scale against the exact \
         box-filtered reference, pooled over all {px} pixels of the set; they are \
         deterministic, times are not.\n",
        sw.cores,
        sw.runs,
        sw.scenes.len()
    );
    let _ = writeln!(
        s,
        "## Scenes\n\n| scene | size | triangles | what |\n|---|---|---|---|"
    );
    for (n, a, w, h, t) in &sw.scenes {
        let _ = writeln!(s, "| {n} | {w}×{h} | {t} | {a} |");
    }
    let _ = writeln!(
        s,
        "\n## All settings\n\n`wrong vis.`: pixels whose visible surface (largest area) \
         differs from the reference's; `clear`: of those, pixels where the reference's \
         surface covers ≥ 3/4 of the pixel. `levels h/v`: distinct shades along a long \
         near-horizontal / near-vertical edge. `frontier`: on the Pareto frontier of \
         RMSE against time.\n"
    );
    let _ = writeln!(
        s,
        "| method | setting | ms/frame | wall | depth evals/px | reads/px | RMSE | max err | wrong vis. | clear | levels h/v | frontier |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|"
    );
    for (k, r) in sw.rows.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} | {:.1} | {} | {} | {}/{} | {} |",
            r.setting.method,
            r.setting.setting,
            r.ms_per_frame(),
            r.wall_ms_per_frame(),
            r.evals_per_pixel(),
            r.reads_per_pixel(),
            r.rmse(),
            r.max_err(),
            r.wrong_visible(),
            r.wrong_visible_clear(),
            r.shade_levels.0,
            r.shade_levels.1,
            if front.contains(&k) { "●" } else { "" }
        );
    }
    let _ = writeln!(s, "\n## Pareto frontier (fastest first)\n");
    for &k in &front {
        let r = &sw.rows[k];
        let _ = writeln!(
            s,
            "- {} {}: {:.2} ms/frame, RMSE {:.3}",
            r.setting.method,
            r.setting.setting,
            r.ms_per_frame(),
            r.rmse()
        );
    }
    let _ = writeln!(s, "\n## RMSE per scene\n");
    let mut head = String::from("| method | setting |");
    let mut rule = String::from("|---|---|");
    for (n, ..) in &sw.scenes {
        let _ = write!(head, " {n} |");
        rule.push_str("---:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    for r in &sw.rows {
        let _ = write!(s, "| {} | {} |", r.setting.method, r.setting.setting);
        for sc in &r.scenes {
            let _ = write!(s, " {:.3} |", sc.rmse());
        }
        s.push('\n');
    }
    let _ = writeln!(
        s,
        "\n## Wrong visible surface per scene (all / clear majority)\n"
    );
    let _ = writeln!(s, "{head}\n{rule}");
    for r in &sw.rows {
        let _ = write!(s, "| {} | {} |", r.setting.method, r.setting.setting);
        for sc in &r.scenes {
            let _ = write!(s, " {}/{} |", sc.wrong_visible, sc.wrong_visible_clear);
        }
        s.push('\n');
    }
    if !sw.variants.is_empty() {
        let _ = writeln!(
            s,
            "\n## A-buffer depth variants against the exhaustive search\n\n\
             Pixels with two or more fragments are where a fragment's depth is chosen. \
             `order≠`: pixels whose packing order differs from exhaustive; `visible≠`: whose \
             visible subpixels differ; `colour≠`: whose resolved colour differs.\n\n\
             | mask | multi-fragment pixels | variant | evals/sorted fragment | order≠ | visible≠ | colour≠ |\n|---|---:|---|---:|---:|---:|---:|"
        );
        for v in &sw.variants {
            for (k, d) in DepthSelect::ALL.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {:.2} | {} | {} | {} |",
                    v.size,
                    v.multi_pixels,
                    d.name(),
                    v.evals[k] as f64 / v.sorted_fragments.max(1) as f64,
                    v.order_diff[k],
                    v.visible_diff[k],
                    v.rgb_diff[k]
                );
            }
        }
    }
    s
}

fn family_colour(method: &str) -> plotters::style::RGBColor {
    use plotters::style::RGBColor;
    match method {
        "none" => RGBColor(0, 0, 0),
        "multiscan" => RGBColor(31, 119, 180),
        "abuffer" => RGBColor(214, 39, 40),
        "corner" => RGBColor(44, 160, 44),
        "d3d4x" => RGBColor(148, 103, 189),
        "grid2x2" => RGBColor(140, 86, 75),
        "postfx" => RGBColor(255, 127, 14),
        "ssaa" => RGBColor(23, 190, 207),
        _ => RGBColor(127, 127, 127),
    }
}

fn register_font() -> Result<(), TradeoffError> {
    use plotters::style::FontStyle;
    plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| TradeoffError::Plot("font".into()))?;
    plotters::style::register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold())
        .map_err(|_| TradeoffError::Plot("font".into()))
}

fn plot_err<E: std::fmt::Debug>(what: &str) -> impl Fn(E) -> TradeoffError + '_ {
    move |e| TradeoffError::Plot(format!("{what}: {e:?}"))
}

fn save_rgb(path: &Path, buf: &[u8], w: u32, h: u32) -> Result<(), TradeoffError> {
    image::save_buffer_with_format(
        path,
        buf,
        w,
        h,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| TradeoffError::Plot(format!("{}: {e}", path.display())))
}

/// Draws RMSE against time (log–log), one colour per method family, the Pareto frontier
/// as a line with its points labelled. Returns the PNG's RGB8 pixels.
pub fn chart(sw: &Sweep, width: u32, height: u32) -> Result<Vec<u8>, TradeoffError> {
    use plotters::prelude::*;
    register_font()?;
    let pts = points(sw);
    let front = pareto_frontier(&pts);
    let mut buf = vec![255u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err("chart"))?;
        let fold = |f: fn(f64, f64) -> f64, init: f64, sel: fn(&(f64, f64)) -> f64| {
            pts.iter().map(sel).fold(init, f)
        };
        let (t0, t1) = (
            fold(f64::min, f64::INFINITY, |p| p.0).max(1e-6),
            fold(f64::max, 0.0, |p| p.0).max(1e-5),
        );
        let (e0, e1) = (
            fold(f64::min, f64::INFINITY, |p| p.1).max(1e-3),
            fold(f64::max, 0.0, |p| p.1).max(1e-2),
        );
        let mut ch = ChartBuilder::on(&root)
            .caption(
                "RMSE against the exact reference vs time per frame (one thread)",
                ("sans-serif", 22),
            )
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (t0 / 1.3..t1 * 1.3).log_scale(),
                (e0 / 1.3..e1 * 1.3).log_scale(),
            )
            .map_err(plot_err("chart"))?;
        ch.configure_mesh()
            .x_desc("ms per frame (thread CPU time, median, one thread; log scale)")
            .y_desc("RMSE, 0..255 scale (log scale)")
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(plot_err("mesh"))?;
        let mut families: Vec<String> = Vec::new();
        for r in &sw.rows {
            if !families.contains(&r.setting.method) {
                families.push(r.setting.method.clone());
            }
        }
        for fam in &families {
            let c = family_colour(fam);
            let series: Vec<(f64, f64)> = sw
                .rows
                .iter()
                .zip(&pts)
                .filter(|(r, _)| &r.setting.method == fam)
                .map(|(_, p)| *p)
                .collect();
            ch.draw_series(series.iter().map(|&p| Circle::new(p, 5, c.filled())))
                .map_err(plot_err("points"))?
                .label(fam.as_str())
                .legend(move |(x, y)| Circle::new((x + 8, y), 5, c.filled()));
        }
        let line: Vec<(f64, f64)> = front.iter().map(|&k| pts[k]).collect();
        ch.draw_series(LineSeries::new(line.clone(), BLACK.stroke_width(2)))
            .map_err(plot_err("frontier"))?
            .label("Pareto frontier")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
        ch.draw_series(
            line.iter()
                .map(|&p| Circle::new(p, 8, BLACK.stroke_width(2))),
        )
        .map_err(plot_err("frontier"))?;
        for &k in &front {
            let r = &sw.rows[k];
            let label = format!("{} {}", r.setting.method, r.setting.setting);
            ch.draw_series(std::iter::once(
                EmptyElement::at(pts[k])
                    + Text::new(
                        label,
                        (10, -4),
                        ("sans-serif", 13).into_font().color(&BLACK),
                    ),
            ))
            .map_err(plot_err("labels"))?;
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(plot_err("legend"))?;
        root.present().map_err(plot_err("chart"))?;
    }
    Ok(buf)
}

/// Maps an absolute error on 0..255 to a colour: black (0) → red → yellow → white (≥ 64).
fn heat_colour(e: f64) -> [u8; 3] {
    let t = (e / 64.0).clamp(0.0, 1.0) * 3.0;
    let c = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [c(t), c(t - 1.0), c(t - 2.0)]
}

/// A montage of difference heat maps for the kept scene: per setting, the largest channel
/// error against the reference per pixel (black 0, red, yellow, white ≥ 64), the tiles
/// labelled. Returns (RGB8, width, height).
pub fn heat_montage(sw: &Sweep) -> Result<Option<(Vec<u8>, u32, u32)>, TradeoffError> {
    use plotters::prelude::*;
    let Some(h) = &sw.heat else { return Ok(None) };
    register_font()?;
    let scale = if h.width <= 128 { 2 } else { 1 };
    let (tw, th) = (h.width * scale, h.height * scale);
    let label_h = 18;
    let cols = 8u32;
    let n = h.images.len() as u32;
    let rows = n.div_ceil(cols);
    let pad = 6;
    let (w, hh) = (
        cols * (tw + pad) + pad,
        rows * (th + label_h + pad) + pad + 24,
    );
    let mut buf = vec![255u8; (w * hh * 3) as usize];
    for (k, img) in h.images.iter().enumerate() {
        let (cx, cy) = (k as u32 % cols, k as u32 / cols);
        let (ox, oy) = (
            pad + cx * (tw + pad),
            24 + pad + cy * (th + label_h + pad) + label_h,
        );
        for y in 0..th {
            for x in 0..tw {
                let p = ((y / scale) * h.width + x / scale) as usize;
                let e = (0..3)
                    .map(|ch| (img[3 * p + ch] as f64 - h.reference[p][ch]).abs())
                    .fold(0.0, f64::max);
                let o = (((oy + y) * w + ox + x) * 3) as usize;
                buf[o..o + 3].copy_from_slice(&heat_colour(e));
            }
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, hh)).into_drawing_area();
        root.draw(&Text::new(
            format!(
                "|error| per pixel on scene '{}' (black 0, red 21, yellow 43, white ≥ 64 of 255)",
                h.scene
            ),
            (pad as i32, 4),
            ("sans-serif", 16).into_font().color(&BLACK),
        ))
        .map_err(plot_err("heat title"))?;
        for (k, row) in sw.rows.iter().enumerate() {
            let (cx, cy) = (k as u32 % cols, k as u32 / cols);
            let (ox, oy) = (pad + cx * (tw + pad), 24 + pad + cy * (th + label_h + pad));
            root.draw(&Text::new(
                format!("{} {}", row.setting.method, row.setting.setting),
                (ox as i32, oy as i32 + 2),
                ("sans-serif", 12).into_font().color(&BLACK),
            ))
            .map_err(plot_err("heat labels"))?;
        }
        root.present().map_err(plot_err("heat"))?;
    }
    Ok(Some((buf, w, hh)))
}

/// Writes `tradeoff.csv`, `tradeoff_scenes.csv`, `tradeoff.md`, `tradeoff.png` and
/// `heatmap.png` into `dir` (created if needed).
pub fn write_outputs(sw: &Sweep, dir: &Path, command: &str) -> Result<Written, TradeoffError> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    let w = Written {
        csv: dir.join("tradeoff.csv"),
        scenes_csv: dir.join("tradeoff_scenes.csv"),
        markdown: dir.join("tradeoff.md"),
        chart: dir.join("tradeoff.png"),
        heatmap: sw.heat.as_ref().map(|_| dir.join("heatmap.png")),
    };
    std::fs::write(&w.csv, csv(sw)).map_err(io_err(&w.csv))?;
    std::fs::write(&w.scenes_csv, scenes_csv(sw)).map_err(io_err(&w.scenes_csv))?;
    std::fs::write(&w.markdown, markdown(sw, command)).map_err(io_err(&w.markdown))?;
    let (cw, chh) = (1100, 760);
    save_rgb(&w.chart, &chart(sw, cw, chh)?, cw, chh)?;
    if let (Some(p), Some((buf, mw, mh))) = (&w.heatmap, heat_montage(sw)?) {
        save_rgb(p, &buf, mw, mh)?;
    }
    Ok(w)
}

/// Options of [`run_tradeoff`] (the `pixelproc tradeoff` command).
#[derive(Clone, Debug)]
pub struct TradeoffOptions {
    /// A folder of scene files instead of the built-in set.
    pub scenes_dir: Option<PathBuf>,
    /// Output folder.
    pub out_dir: PathBuf,
    /// Timed runs per setting and scene.
    pub runs: usize,
    /// The small subset (tests, CI).
    pub quick: bool,
    /// Progress bar on stderr.
    pub progress: bool,
    /// The command line, recorded in the report.
    pub command: String,
}

/// Runs the sweep and writes every output. Returns the result and the files written.
pub fn run_tradeoff(o: &TradeoffOptions) -> Result<(Sweep, Written), TradeoffError> {
    let scenes = match &o.scenes_dir {
        Some(d) => load_scene_dir(d)?,
        None => builtin_scenes(o.quick),
    };
    let settings = sweep_settings(o.quick);
    let sw = run_sweep(
        &scenes,
        &settings,
        &SweepOptions {
            runs: o.runs,
            progress: o.progress,
        },
        None,
    )?;
    let w = write_outputs(&sw, &o.out_dir, &o.command)?;
    Ok((sw, w))
}
