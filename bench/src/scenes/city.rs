//! The 1080p scene of the sweep, `city-1080p`: a seeded city seen through a pinhole
//! camera, drawn at its true 1920×1080 (not scaled from the 160×160 set like the others).

use pixelproc_sim::rng::XorShift64Star;
use pixelproc_sim::setup::SnappedTri;

use super::{cq, q8, tri_f, zq, Rng, TestScene};

/// The 1080p scene's size: drawn at its true size, not scaled from the 160×160 set.
pub const CITY_WIDTH: u32 = 1920;
/// See [`CITY_WIDTH`].
pub const CITY_HEIGHT: u32 = 1080;

/// A pinhole camera over a ground plane for the 1080p scene: world `Y` up, looking along
/// `+Z` from height [`Camera::height`], no tilt.
struct Camera {
    /// Focal length, pixels.
    f: f64,
    /// Principal point (the horizon is the row `cy`).
    cx: f64,
    cy: f64,
    /// Eye height above the ground.
    height: f64,
    /// Depths mapped to the geometry range: `near` → 0, `far` → 0.99.
    near: f64,
    far: f64,
}

impl Camera {
    /// Screen position of a world point (`z > 0`).
    fn screen(&self, p: [f64; 3]) -> [f64; 2] {
        [
            self.cx + self.f * p[0] / p[2],
            self.cy - self.f * (p[1] - self.height) / p[2],
        ]
    }
    /// Depth on 0..1: affine in `1/z`, so it is planar in screen space on every planar
    /// face (as the renderer interpolates it).
    fn depth(&self, z: f64) -> f64 {
        0.99 * (1.0 / self.near - 1.0 / z) / (1.0 / self.near - 1.0 / self.far)
    }
}

/// A triangle with explicit vertex depths (0..1) and colours.
fn tri_z(v: [[f64; 2]; 3], z: [f64; 3], c: [[f64; 3]; 3], tag: u16) -> SnappedTri {
    SnappedTri {
        chan: 0,
        v: v.map(|p| [q8(p[0]), q8(p[1])]),
        z: z.map(zq),
        c: c.map(|k| k.map(cq)),
        tag,
        host: None,
        nclass: 0,
    }
}

/// A planar world quad `p0 p1 p2 p3` (convex, in order) through `cam` as two triangles,
/// each vertex's colour `col` fogged towards `fog` with distance.
fn world_quad(
    cam: &Camera,
    p: [[f64; 3]; 4],
    col: [f64; 3],
    fog: [f64; 3],
    tag: u16,
) -> [SnappedTri; 2] {
    let s = p.map(|q| cam.screen(q));
    let z = p.map(|q| cam.depth(q[2]));
    let c = p.map(|q| {
        let t = (q[2] / cam.far).clamp(0.0, 1.0).sqrt() * 0.7;
        [0, 1, 2].map(|k| col[k] * (1.0 - t) + fog[k] * t)
    });
    [
        tri_z(
            [s[0], s[1], s[2]],
            [z[0], z[1], z[2]],
            [c[0], c[1], c[2]],
            tag,
        ),
        tri_z(
            [s[0], s[2], s[3]],
            [z[0], z[2], z[3]],
            [c[0], c[2], c[3]],
            tag,
        ),
    ]
}

/// The 1080p scene: a city of box buildings over a ground plane under a sky, seen through a
/// pinhole camera, with thin lamp posts along the streets. Thousands of triangles, from
/// screen-filling faces near the camera to buildings a few pixels across at the horizon
/// and posts under a pixel wide. Every face is planar, so its screen-space depth (affine
/// in `1/z`) is exactly what the renderer interpolates.
/// `width`×`height` is the screen: the field of view is the same at every size (the
/// focal length scales with the width), so a smaller screen shows the same city.
fn scene_city(width: u32, height: u32, rng: &mut Rng) -> Vec<SnappedTri> {
    let (w, h) = (width as f64, height as f64);
    let cam = Camera {
        f: 1100.0 * w / 1920.0,
        cx: w / 2.0,
        cy: 0.36 * h,
        height: 12.0,
        near: 4.0,
        far: 1000.0,
    };
    let sky = [0.55, 0.66, 0.82];
    let mut out = Vec::new();
    // Sky: a far backdrop over the whole screen, lighter towards the horizon.
    let zs = |_: [f64; 2]| 0.995;
    let (top, hor) = ([0.32, 0.45, 0.7], sky);
    let p = [
        [-2.0, -2.0],
        [w + 2.0, -2.0],
        [w + 2.0, h + 2.0],
        [-2.0, h + 2.0],
    ];
    out.push(tri_f([p[0], p[1], p[2]], zs, [top, top, hor], 0));
    out.push(tri_f([p[0], p[2], p[3]], zs, [top, hor, hor], 0));
    // Ground from the far plane's row to the bottom: depth affine in screen y.
    let y_far = cam.cy + cam.f * cam.height / cam.far;
    let z_at = |y: f64| cam.depth(cam.f * cam.height / (y - cam.cy));
    let (g_far, g_near) = ([0.42, 0.44, 0.4], [0.3, 0.33, 0.26]);
    let g = [
        [-2.0, y_far],
        [w + 2.0, y_far],
        [w + 2.0, h + 2.0],
        [-2.0, h + 2.0],
    ];
    let gz = g.map(|q| z_at(q[1]));
    out.push(tri_z(
        [g[0], g[1], g[2]],
        [gz[0], gz[1], gz[2]],
        [g_far, g_far, g_near],
        1,
    ));
    out.push(tri_z(
        [g[0], g[2], g[3]],
        [gz[0], gz[2], gz[3]],
        [g_far, g_near, g_near],
        1,
    ));
    // Buildings on blocks between streets: rows of lots at depths 20..700.
    let mut tag: u16 = 2;
    let inside = |q: [f64; 2]| q[0] >= 0.0 && q[0] <= w && q[1] >= 0.0 && q[1] <= h;
    let mut z0 = 20.0;
    while z0 < 700.0 {
        let depth = 6.0 + 0.02 * z0;
        let mut x = -0.9 * z0;
        while x < 0.9 * z0 {
            let bw = rng.range(3.0, 9.0) * (1.0 + z0 / 300.0);
            let (x0, x1) = (x, x + bw);
            x += bw + rng.range(0.5, 3.0);
            // A street along the view axis.
            if x0 < 5.0 && x1 > -5.0 {
                continue;
            }
            let (za, zb) = (z0 + rng.range(0.0, 2.0), z0 + depth * rng.range(0.5, 1.0));
            // As tall as fits on the screen at the front face.
            let cap = cam.height + cam.cy * za / cam.f - 0.5;
            let bh = rng.range(4.0, 45.0).min(cap);
            let corners = [[x0, 0.0, za], [x1, 0.0, za], [x0, bh, za], [x1, bh, za]];
            if !corners.iter().all(|&c| inside(cam.screen(c))) {
                continue;
            }
            let base = rng.range(0.35, 0.85);
            let tint = [0, 1, 2].map(|_| base * rng.range(0.85, 1.1));
            let shade = |k: f64| tint.map(|c| (c * k).min(1.0));
            // Front face (toward the camera).
            out.extend(world_quad(
                &cam,
                [[x0, bh, za], [x1, bh, za], [x1, 0.0, za], [x0, 0.0, za]],
                shade(1.0),
                sky,
                tag,
            ));
            // The side face the camera sees (none for a building straddling the axis).
            let side = if x0 > 0.0 {
                Some(x0)
            } else if x1 < 0.0 {
                Some(x1)
            } else {
                None
            };
            if let Some(sx) = side {
                out.extend(world_quad(
                    &cam,
                    [[sx, bh, za], [sx, bh, zb], [sx, 0.0, zb], [sx, 0.0, za]],
                    shade(0.7),
                    sky,
                    tag,
                ));
            }
            // The roof, seen from above when lower than the eye.
            if bh < cam.height - 0.5 {
                out.extend(world_quad(
                    &cam,
                    [[x0, bh, zb], [x1, bh, zb], [x1, bh, za], [x0, bh, za]],
                    shade(1.2),
                    sky,
                    tag,
                ));
            }
            tag = tag.wrapping_add(1).max(2);
        }
        z0 += depth + rng.range(6.0, 12.0);
    }
    // Lamp posts 0.15 wide along both kerbs of the street: at 1920×1080 (focal length
    // 1100 px) under a pixel wide beyond 165 units.
    let mut z = 12.0;
    while z < 500.0 {
        for sx in [-4.2, 4.2] {
            let ph = rng.range(5.0, 7.0);
            let p = [
                [sx, ph, z],
                [sx + 0.15, ph, z],
                [sx + 0.15, 0.0, z],
                [sx, 0.0, z],
            ];
            if p.iter().all(|&c| inside(cam.screen(c))) {
                out.extend(world_quad(&cam, p, [0.12, 0.12, 0.14], sky, tag));
                tag = tag.wrapping_add(1).max(2);
            }
        }
        z += rng.range(6.0, 14.0);
    }
    out
}

/// The 1080p scene of the sweep (`city-1080p`, [`CITY_WIDTH`]×[`CITY_HEIGHT`], drawn at
/// that size): see `scene_city`. Generated from its own seed; it is not part of
/// [`builtin_scenes`](super::builtin_scenes), so the ten scenes of the set and their figures are unchanged.
pub fn city_1080p() -> TestScene {
    city_scene(false)
}

/// The city scene at 1920×1080, or for the quick set (tests) the same city on a
/// 192×108 screen (`city-quick`).
pub fn city_scene(quick: bool) -> TestScene {
    let (w, h, name) = if quick {
        (CITY_WIDTH / 10, CITY_HEIGHT / 10, "city-quick")
    } else {
        (CITY_WIDTH, CITY_HEIGHT, "city-1080p")
    };
    let mut rng = Rng(XorShift64Star(0xC17F_1080_5EED_0001));
    TestScene {
        name: name.into(),
        about: "box buildings over a ground plane under a sky, in perspective; lamp posts under a pixel wide".into(),
        width: w,
        height: h,
        bg: [20, 24, 32],
        tris: scene_city(w, h, &mut rng),
        interpenetrating: false,
    }
}
