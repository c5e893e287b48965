//! The scenes of the sweep: the built-in generated set ([`builtin_scenes`]) and folders of
//! scene files ([`load_scene_dir`]), both as snapped screen-space triangles.
//!
//! The generated scenes draw from the shared seeded generator
//! ([`pixelproc_sim::rng::XorShift64Star`]), so they stay byte-identical across releases.

use std::path::{Path, PathBuf};

use pixelproc_formats::{Z_GEOM_MAX, Z_GEOM_MIN};
use pixelproc_sim::rng::XorShift64Star;
use pixelproc_sim::setup::{HostPlane, SnappedTri};

use crate::{io_err, TradeoffError};

mod city;
pub use city::{city_1080p, city_scene, CITY_HEIGHT, CITY_WIDTH};

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

/// The draws the generators make, on top of the shared xorshift64* sequence.
struct Rng(XorShift64Star);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0.unit()
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    fn sign(&mut self) -> f64 {
        if self.0.next_u64() & 1 == 0 {
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
        chan: 0,
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

/// A quad face: corners, colour, and depth plane `z0 + gx·x + gy·y`.
type Face = ([[f64; 2]; 4], [f64; 3], f64, f64, f64);

/// Faces with shadow regions drawn as darker coplanar decals (patterns on the faces, as the
/// multi-scanning paper draws them): shadow boundaries are edges between two surfaces of
/// identical depth, so only the decal rule decides visibility.
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

/// A scene generator: screen size in pixels and the seeded draws give the triangles.
type Gen = fn(f64, &mut Rng) -> Vec<SnappedTri>;

/// One entry of the built-in set.
struct Builtin {
    /// Short name.
    name: &'static str,
    /// What the scene exercises.
    about: &'static str,
    /// The generator.
    gen: Gen,
    /// Swap x and y after generating (a near-horizontal scene becomes near-vertical).
    transposed: bool,
    /// The scene has interpenetrating surfaces.
    interpenetrating: bool,
}

/// The full built-in set, in report order.
const BUILTIN: [Builtin; 10] = [
    Builtin {
        name: "ordinary",
        about: "40 random Gouraud triangles in separate depth layers",
        gen: scene_ordinary,
        transposed: false,
        interpenetrating: false,
    },
    Builtin {
        name: "mesh",
        about: "a jittered 10×10 grid mesh, one object (shared edges)",
        gen: scene_mesh,
        transposed: false,
        interpenetrating: false,
    },
    Builtin {
        name: "slivers",
        about: "36 needles 0.1–1.5 px wide at random angles",
        gen: scene_slivers,
        transposed: false,
        interpenetrating: false,
    },
    Builtin {
        name: "near-horizontal",
        about: "bands with edge slopes 1/96–1/6 from horizontal",
        gen: scene_near_horizontal,
        transposed: false,
        interpenetrating: false,
    },
    Builtin {
        name: "near-vertical",
        about: "the near-horizontal scene transposed",
        gen: scene_near_horizontal,
        transposed: true,
        interpenetrating: false,
    },
    Builtin {
        name: "thin-horizontal",
        about: "bars 0.25–1 px high, 0.5–1.5 px apart, slopes ≤ 1/40",
        gen: scene_thin_horizontal,
        transposed: false,
        interpenetrating: false,
    },
    Builtin {
        name: "thin-vertical",
        about: "the thin-horizontal scene transposed",
        gen: scene_thin_horizontal,
        transposed: true,
        interpenetrating: false,
    },
    Builtin {
        name: "interpenetrating",
        about: "14 pairs of triangles whose planes cross",
        gen: scene_interpenetrating,
        transposed: false,
        interpenetrating: true,
    },
    Builtin {
        name: "coplanar",
        about: "8 overlapping triangles 2–300 depth units apart, tilted",
        gen: scene_coplanar,
        transposed: false,
        interpenetrating: false,
    },
    Builtin {
        name: "shadows",
        about: "faces with darker coplanar decal triangles as shadow regions",
        gen: scene_shadows,
        transposed: false,
        interpenetrating: false,
    },
];

/// The built-in scene set, `size × size` pixels each (160 for the full sweep; the quick set
/// uses two 40×40 scenes).
pub fn builtin_scenes(quick: bool) -> Vec<TestScene> {
    let size = if quick { 40 } else { 160 };
    let pick: &[usize] = if quick {
        &[0, 5]
    } else {
        &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]
    };
    pick.iter()
        .map(|&k| {
            let b = &BUILTIN[k];
            let tr = b.transposed;
            // Same seed for a scene and its transpose.
            let seed = 0x9E37_79B9_7F4A_7C15 ^ ((k as u64 - tr as u64) * 0x1000_0001);
            let mut rng = Rng(XorShift64Star(seed));
            let mut tris = (b.gen)(size as f64, &mut rng);
            if tr {
                transpose(&mut tris);
            }
            TestScene {
                name: b.name.into(),
                about: b.about.into(),
                width: size,
                height: size,
                bg: [20, 24, 32],
                tris,
                interpenetrating: b.interpenetrating,
            }
        })
        .collect()
}

/// Loads every `*.json` scene file of `dir` (sorted by name). Screen-space and 3-D scenes
/// both go through the front end ([`pixelproc_sim::frontend::project`]); the sweep sees the
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
        let ls = pixelproc_sim::scene::load_file(&f)?;
        for w in &ls.warnings {
            eprintln!("warning: {w}");
        }
        let pr = pixelproc_sim::frontend::project(&ls)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// FNV-1a over every field of every triangle of the scenes.
    fn fingerprint(scenes: &[TestScene]) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: i64| {
            for b in x.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for s in scenes {
            eat(s.tris.len() as i64);
            for t in &s.tris {
                t.v.iter().flatten().for_each(|&x| eat(x as i64));
                t.z.iter().for_each(|&x| eat(x as i64));
                t.c.iter().flatten().for_each(|&x| eat(x as i64));
                eat(t.tag as i64);
                eat(t.nclass as i64);
                match &t.host {
                    None => eat(-1),
                    Some(p) => {
                        p.v.iter().flatten().for_each(|&x| eat(x as i64));
                        p.z.iter().for_each(|&x| eat(x as i64));
                    }
                }
            }
        }
        h
    }

    #[test]
    fn generated_scenes_stay_byte_identical() {
        // Pinned values: a change here changes every figure of docs/accuracy.md.
        assert_eq!(
            fingerprint(&builtin_scenes(false)),
            3_616_060_329_856_846_689
        );
        assert_eq!(
            fingerprint(&builtin_scenes(true)),
            3_726_205_885_842_190_706
        );
    }

    #[test]
    fn city_scene_is_drawn_at_1080p_with_thousands_of_triangles() {
        let a = city_1080p();
        assert_eq!((a.width, a.height), (1920, 1080));
        // The same seed gives the same triangles.
        assert_eq!(
            fingerprint(std::slice::from_ref(&a)),
            fingerprint(&[city_1080p()])
        );
        assert!(a.tris.len() >= 2000, "{} triangles", a.tris.len());
        let area = |t: &SnappedTri| {
            let [p, q, r] = t.v.map(|v| [v[0] as f64 / 256.0, v[1] as f64 / 256.0]);
            ((q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1])).abs() / 2.0
        };
        let tiny = a.tris.iter().filter(|t| area(t) < 1.0).count();
        assert!(tiny >= 10, "{tiny} triangles under one pixel");
        // Nearer is smaller depth: the ground's bottom edge is nearer than its far edge,
        // and a building's front face lies in front of the ground behind it.
        let ground = &a.tris[2];
        assert!(ground.z[2] < ground.z[0], "{:?}", ground.z);
        // The quick city is the same world on a tenth of the screen.
        let q = city_scene(true);
        assert_eq!((q.width, q.height), (192, 108));
        assert!(q.tris.len() > 100);
    }
}
