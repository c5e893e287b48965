//! Buffers written during drawing (seed 004, Sony CN1674049, eqs. 1–4, "normal vector
//! buffer"): the z-buffer, the second-difference buffer kept by read-modify-write, and a
//! stored normal per pixel, from replaying the drawing in scene order with the array's
//! depth test. The replay is a [`SpanSink`] of the raster core.

use crate::aa::AaError;
use crate::raster::{depth, SpanRaster, SpanSink};
use crate::setup::SnappedTri;
use pixelproc_formats::{SpanWord, Z_FAR};

/// One entry of the stored normal buffer: the unit normal of the visible plane in the
/// space (x px, y px, z/S), `S` = [`super::PostFxParams::normal_scale`], as two components in
/// Q1.15 and the sign of the third (seed 004: "two components and a sign suffice").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StoredNormal {
    /// x component, Q1.15.
    pub nx: i16,
    /// y component, Q1.15.
    pub ny: i16,
    /// The z component is negative (always, for a depth plane seen from the front;
    /// kept because the format stores it).
    pub nz_neg: bool,
}

impl StoredNormal {
    /// The background's normal, `(0, 0, −1)`.
    pub const BACKGROUND: StoredNormal = StoredNormal {
        nx: 0,
        ny: 0,
        nz_neg: true,
    };

    /// The three components in Q1.15 (as `i64`), the third recovered as
    /// `±⌊√(2^30 − nx² − ny²)⌋`.
    pub fn unpack(&self) -> [i64; 3] {
        let (x, y) = (self.nx as i64, self.ny as i64);
        let r = ((1i64 << 30) - x * x - y * y).max(0) as u128;
        let z = isqrt(r) as i64;
        [x, y, if self.nz_neg { -z } else { z }]
    }

    /// The unit normal of the plane through three (Q.8 pixel position, 24-bit depth)
    /// points, `∝ (∂z/∂x, ∂z/∂y, −S)`, rounded to Q1.15. `None` for a degenerate triangle.
    pub fn of_plane(v: [[i32; 2]; 3], z: [u32; 3], s: u32) -> Option<StoredNormal> {
        let (e1x, e1y) = ((v[1][0] - v[0][0]) as i128, (v[1][1] - v[0][1]) as i128);
        let (e2x, e2y) = ((v[2][0] - v[0][0]) as i128, (v[2][1] - v[0][1]) as i128);
        let (d1, d2) = (z[1] as i128 - z[0] as i128, z[2] as i128 - z[0] as i128);
        let det = e1x * e2y - e1y * e2x;
        if det == 0 {
            return None;
        }
        let sg = det.signum();
        // (∂z/∂x, ∂z/∂y, −S)·det/256, with the sign making the third component negative.
        let a = sg * 256 * (d1 * e2y - d2 * e1y);
        let b = sg * 256 * (d2 * e1x - d1 * e2x);
        let c = -(s as i128) * det.abs();
        let len = isqrt((a * a + b * b + c * c) as u128) as i128;
        let q = |u: i128| -> i16 {
            // round(u·2^15 / len), clamped to the i16 range.
            (((u << 16) + len).div_euclid(2 * len)).clamp(-32767, 32767) as i16
        };
        Some(StoredNormal {
            nx: q(a),
            ny: q(b),
            nz_neg: c < 0,
        })
    }
}

/// Integer square root `⌊√n⌋`.
fn isqrt(n: u128) -> u128 {
    if n < 2 {
        return n;
    }
    let mut x = (n as f64).sqrt() as u128;
    while x * x > n {
        x -= 1;
    }
    while (x + 1) * (x + 1) <= n {
        x += 1;
    }
    x
}

/// The per-pixel buffers produced during drawing, in scene order with the array's depth
/// test (same span words, `<`, decals `≤`).
#[derive(Clone, Debug)]
pub struct DrawBuffers {
    /// Width.
    pub w: usize,
    /// Height.
    pub h: usize,
    /// 24-bit z-buffer.
    pub z: Vec<u32>,
    /// Visible triangle (input index, −1 background).
    pub visible: Vec<i32>,
    /// `d2x = z(x+1, y) + z(x−1, y) − 2·z(x, y)` (borders replicate), kept up to date by
    /// read-modify-write on every z change (seed eq. 4); 26-bit signed.
    pub d2x: Vec<i32>,
    /// Likewise in y.
    pub d2y: Vec<i32>,
    /// Stored normal of the visible plane.
    pub normals: Vec<StoredNormal>,
    /// Depth tests made.
    pub depth_tests: u64,
    /// Read-modify-writes of the second-difference buffer.
    pub d2_updates: u64,
}

/// Weight of `z(p)` in the second difference at `c` along an axis of length `n` with
/// replicated borders: the sum of the stencil taps `(c−1: +1, c: −2, c+1: +1)` that clamp
/// to `p`.
fn d2_weight(c: i64, p: i64, n: i64) -> i32 {
    let taps: [(i64, i32); 3] = [(c - 1, 1), (c, -2), (c + 1, 1)];
    taps.iter()
        .filter(|tk| tk.0.clamp(0, n - 1) == p)
        .map(|tk| tk.1)
        .sum()
}

/// Draws `tris` in scene order into a z-buffer, maintaining the second-difference buffer
/// (seed 004, eq. 4: when z at a pixel changes from `z0` to `z1`, every second difference
/// whose stencil contains that pixel gets `weight·(z1 − z0)` by read-modify-write) and
/// writing the visible plane's normal at each depth-test pass. The buffers are a
/// [`SpanSink`] of the raster core's span scan conversion.
pub fn draw_buffers(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    normal_scale: u32,
) -> Result<DrawBuffers, AaError> {
    let (w, h) = (width as usize, height as usize);
    let raster = SpanRaster::new(tris, width, height)?;
    let normals = tris
        .iter()
        .map(|t| {
            match &t.host {
                Some(hp) => StoredNormal::of_plane(hp.v, hp.z, normal_scale),
                None => StoredNormal::of_plane(t.v, t.z, normal_scale),
            }
            .unwrap_or(StoredNormal::BACKGROUND)
        })
        .collect();
    let mut sink = DrawSink {
        normals,
        b: DrawBuffers {
            w,
            h,
            z: vec![Z_FAR; w * h],
            visible: vec![-1; w * h],
            d2x: vec![0; w * h],
            d2y: vec![0; w * h],
            normals: vec![StoredNormal::BACKGROUND; w * h],
            depth_tests: 0,
            d2_updates: 0,
        },
    };
    raster.scan(&mut sink);
    Ok(sink.b)
}

/// The draw buffers being written, with each triangle's stored normal.
struct DrawSink {
    normals: Vec<StoredNormal>,
    b: DrawBuffers,
}

impl SpanSink for DrawSink {
    fn span(&mut self, prim: u32, row: u32, sw: &SpanWord) {
        let b = &mut self.b;
        let (w, wi, hi) = (b.w, b.w as i64, b.h as i64);
        let j = row as i64;
        for x in sw.xl as i64..=sw.xr as i64 {
            let i = j as usize * w + x as usize;
            b.depth_tests += 1;
            let z1 = sw.z_at(x);
            if !depth::passes(z1, b.z[i], sw.decal) {
                continue;
            }
            let dz = z1 as i32 - b.z[i] as i32;
            b.z[i] = z1;
            b.visible[i] = prim as i32;
            b.normals[i] = self.normals[prim as usize];
            if dz == 0 {
                continue;
            }
            for c in (x - 1).max(0)..=(x + 1).min(wi - 1) {
                let wt = d2_weight(c, x, wi);
                if wt != 0 {
                    b.d2x[j as usize * w + c as usize] += wt * dz;
                    b.d2_updates += 1;
                }
            }
            for c in (j - 1).max(0)..=(j + 1).min(hi - 1) {
                let wt = d2_weight(c, j, hi);
                if wt != 0 {
                    b.d2y[c as usize * w + x as usize] += wt * dz;
                    b.d2_updates += 1;
                }
            }
        }
    }
}
