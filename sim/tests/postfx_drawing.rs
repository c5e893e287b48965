//! Buffers of post-process anti-aliasing written during drawing (seed 004): the
//! second-difference buffer kept by read-modify-write (eq. 4) and the stored normal buffer.

use pixelproc_sim::aa::postfx::{
    detect_edges, detect_edges_from, draw_buffers, NormalSource, SecondDiffSource, StoredNormal,
};
use pixelproc_sim::aa::{render_aa, AaMethod, PostFxParams};
use pixelproc_sim::render::{render_frame, SpanSource};
use pixelproc_sim::rng::Lcg64 as Lcg;
use pixelproc_sim::setup::SnappedTri;

/// Random triangles, many overlapping (overdraw), drawn in this order.
fn scene(seed: u64, n: usize, w: f64, h: f64) -> Vec<SnappedTri> {
    let mut r = Lcg(seed.wrapping_mul(0x9E3779B97F4A7C15) ^ 0x1234);
    let q = |x: f64| (x * 256.0).round() as i32;
    (0..n)
        .map(|_| {
            let (cx, cy) = (r.range(0.0, w), r.range(0.0, h));
            let s = r.range(2.0, w);
            let v = [0, 1, 2].map(|_| [q(cx + r.range(-s, s)), q(cy + r.range(-s, s))]);
            let z = [0, 1, 2].map(|_| r.range(10_000.0, 8_000_000.0) as u32);
            let c = (r.range(0.0, 255.0) * 4096.0) as u32 + 2048;
            SnappedTri {
                v,
                z,
                c: [[c; 3]; 3],
                ..Default::default()
            }
        })
        .collect()
}

#[test]
fn second_differences_kept_during_drawing_equal_those_of_the_final_z_buffer() {
    for seed in 0..12u64 {
        let (w, h) = (40 + 7 * seed as usize, 30 + 5 * seed as usize);
        let tris = scene(seed, 60, w as f64, h as f64);
        let b = draw_buffers(&tris, w as u32, h as u32, 256).unwrap();
        // The golden array's final z-buffer.
        let src = SpanSource::new(&tris, w as u32, h as u32).unwrap();
        let z = render_frame(&src, [0, 0, 0], w, &[]).depth();
        assert_eq!(b.z, z, "seed {seed}: z-buffer");
        assert!(
            b.depth_tests > (w * h) as u64,
            "expected overdraw: {}",
            b.depth_tests as f64 / (w * h) as f64
        );
        // Second differences of the final z, computed here with replicated borders.
        let at = |x: i64, y: i64| {
            z[y.clamp(0, h as i64 - 1) as usize * w + x.clamp(0, w as i64 - 1) as usize] as i64
        };
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                let k = y as usize * w + x as usize;
                let dx = at(x + 1, y) + at(x - 1, y) - 2 * at(x, y);
                let dy = at(x, y + 1) + at(x, y - 1) - 2 * at(x, y);
                assert_eq!(b.d2x[k] as i64, dx, "seed {seed} ({x},{y}) d2x");
                assert_eq!(b.d2y[k] as i64, dy, "seed {seed} ({x},{y}) d2y");
            }
        }
        // Hence bit-identical edge bits and images.
        for zth in [16, 64, 4096] {
            let p = PostFxParams {
                zth,
                ..Default::default()
            };
            let a = detect_edges(&z, w, h, &p);
            let e = detect_edges_from(&b.z, &b.d2x, &b.d2y, None, w, h, &p);
            assert_eq!(a.ex, e.ex);
            assert_eq!(a.ey, e.ey);
            assert!(a.ex.iter().chain(&a.ey).any(|&c| c != 0));
        }
        let p = PostFxParams::default();
        let q = PostFxParams {
            d2_source: SecondDiffSource::DuringDraw,
            ..p
        };
        let fa = render_aa(&tris, w as u32, h as u32, [9, 9, 9], &AaMethod::PostFx(p)).unwrap();
        let fb = render_aa(&tris, w as u32, h as u32, [9, 9, 9], &AaMethod::PostFx(q)).unwrap();
        assert_eq!(fa.rgb, fb.rgb);
        assert_eq!(fa.visible, fb.visible);
    }
}

/// Unit normal of a triangle's depth plane in (x px, y px, z/S), float, nz < 0.
fn float_normal(t: &SnappedTri, s: f64) -> [f64; 3] {
    let p = t.v.map(|v| [v[0] as f64 / 256.0, v[1] as f64 / 256.0]);
    let z = t.z.map(|z| z as f64 / s);
    let a = [p[1][0] - p[0][0], p[1][1] - p[0][1], z[1] - z[0]];
    let b = [p[2][0] - p[0][0], p[2][1] - p[0][1], z[2] - z[0]];
    let mut n = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    if n[2] > 0.0 {
        n = n.map(|c| -c);
    }
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n.map(|c| c / l)
}

#[test]
fn stored_normals_match_the_planes_and_give_the_normal_edges() {
    let s = 256u32;
    for seed in 0..8u64 {
        let (w, h) = (48usize, 40usize);
        let tris = scene(100 + seed, 25, w as f64, h as f64);
        let b = draw_buffers(&tris, w as u32, h as u32, s).unwrap();
        let fl: Vec<[f64; 3]> = (0..w * h)
            .map(|k| match b.visible[k] {
                -1 => [0.0, 0.0, -1.0],
                t => float_normal(&tris[t as usize], s as f64),
            })
            .collect();
        // Two components in Q1.15 (rounded, clamped to ±32767: error < 2^-14) and a sign; the third,
        // recovered as √(1 − nx² − ny²), is within √(3·2^-15) ≈ 0.01 even for planes
        // seen edge-on, where the square root is ill-conditioned.
        for (n, f) in b.normals.iter().zip(&fl) {
            let u = n.unpack();
            for c in 0..2 {
                assert!(
                    (u[c] as f64 / 32768.0 - f[c]).abs() < 4e-5,
                    "{u:?} vs {f:?}"
                );
            }
            assert!(
                (u[2] as f64 / 32768.0 - f[2]).abs() < 0.01,
                "{u:?} vs {f:?}"
            );
        }
        // Normal edges only (z threshold out of reach): an edge exactly where the unit
        // normals' dot product is below cos θ = 0.9 (pairs within 0.01 of it skipped).
        let p = PostFxParams {
            zth: u32::MAX,
            normals: true,
            normal_source: NormalSource::Stored,
            ..Default::default()
        };
        let e = detect_edges_from(&b.z, &b.d2x, &b.d2y, Some(&b.normals), w, h, &p);
        let cos = p.cos_q16 as f64 / 65536.0;
        let mut seen = 0;
        for y in 0..h {
            for x in 0..w {
                let k = y * w + x;
                for (bit, k2, ok) in [(e.ex[k], k + 1, x + 1 < w), (e.ey[k], k + w, y + 1 < h)] {
                    if !ok {
                        assert_eq!(bit, 0);
                        continue;
                    }
                    let d: f64 = (0..3).map(|c| fl[k][c] * fl[k2][c]).sum();
                    if (d - cos).abs() < 0.01 {
                        continue;
                    }
                    assert_eq!(bit != 0, d < cos, "seed {seed} ({x},{y}) dot {d}");
                    if b.visible[k] == b.visible[k2] {
                        assert_eq!(bit, 0);
                    }
                    seen += (bit != 0) as u32;
                }
            }
        }
        assert!(seen > 0);
    }
}

#[test]
fn the_background_normal_is_minus_z() {
    assert_eq!(StoredNormal::BACKGROUND.unpack(), [0, 0, -32768]);
    let n = StoredNormal::of_plane([[0, 0], [256, 0], [0, 256]], [1000; 3], 256).unwrap();
    assert_eq!(n, StoredNormal::BACKGROUND);
}
