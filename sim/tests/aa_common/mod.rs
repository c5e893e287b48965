#![allow(dead_code)]
use pixelproc_sim::setup::{HostPlane, SnappedTri};

/// The shared deterministic generator (64-bit LCG, top 53 bits).
pub use pixelproc_sim::rng::Lcg64 as Lcg;

pub fn q8(x: f64) -> i32 {
    (x * 256.0).round() as i32
}

/// A random scene of `n` triangles on a `w × h` screen: varied sizes (some thin slivers),
/// flat or Gouraud colours, random planar depths (so some interpenetrate), and a few
/// decals lying on their host triangle.
pub fn random_scene(seed: u64, n: usize, w: f64, h: f64) -> Vec<SnappedTri> {
    let mut r = Lcg(seed.wrapping_mul(0x9E3779B97F4A7C15) ^ 0x1234_5678);
    let mut out = Vec::new();
    for k in 0..n {
        let (cx, cy) = (r.range(-2.0, w + 2.0), r.range(-2.0, h + 2.0));
        let s = if k % 5 == 0 {
            r.range(1.0, 4.0)
        } else {
            r.range(3.0, w / 2.5)
        };
        let v = [0, 1, 2].map(|_| [q8(cx + r.range(-s, s)), q8(cy + r.range(-s, s))]);
        let z = [0, 1, 2].map(|_| r.range(10_000.0, 2_000_000.0) as u32);
        let base = [0, 1, 2].map(|_| r.range(0.0, 255.0));
        let c = [0, 1, 2].map(|_| {
            [0, 1, 2].map(|ch| {
                let g = if k % 3 == 0 {
                    r.range(-40.0, 40.0)
                } else {
                    0.0
                };
                (((base[ch] + g).clamp(0.0, 255.0)) * 4096.0).floor() as u32 + 2048
            })
        });
        let t = SnappedTri {
            chan: 0,
            v,
            z,
            c,
            tag: k as u16,
            host: None,
            nclass: 0,
        };
        out.push(t);
        if k % 7 == 3 {
            // A decal inside this triangle: shrink it towards its centroid.
            let gx = (v[0][0] + v[1][0] + v[2][0]) / 3;
            let gy = (v[0][1] + v[1][1] + v[2][1]) / 3;
            let dv = v.map(|p| [gx + (p[0] - gx) / 2, gy + (p[1] - gy) / 2]);
            out.push(SnappedTri {
                chan: 0,
                v: dv,
                z,
                c: [[(200 << 12) + 2048, (30 << 12) + 2048, (30 << 12) + 2048]; 3],
                tag: k as u16,
                host: Some(HostPlane { v, z }),
                nclass: 0,
            });
        }
    }
    out
}
