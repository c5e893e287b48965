//! Measures the A-buffer depth-selection variants on generated scenes (the figures of
//! `docs/abuffer.md`). Run: `cargo run --release -p pixelproc-bench --example abuffer_measure`.

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::abuffer::{render_abuffer, AbufferParams};
use pixelproc_sim::mask_search::DepthSelect;
use pixelproc_sim::rng::XorShift64Star as Rng;
use pixelproc_sim::setup::SnappedTri;
use std::time::Instant;

fn q8(x: f64) -> i32 {
    (x * 256.0).round() as i32
}

fn tri(v: [[f64; 2]; 3], z: [f64; 3], rgb: [f64; 3], tag: u16) -> SnappedTri {
    SnappedTri {
        chan: 0,
        v: v.map(|p| p.map(q8)),
        z: z.map(|d| (d.clamp(0.0, 1.0) * 16_000_000.0) as u32 + 16),
        c: [rgb.map(|c| (c * 255.0 * 4096.0) as u32); 3],
        tag,
        host: None,
        nclass: 0,
    }
}

/// Random triangles of every size and orientation, random depth planes.
fn scene_random(rng: &mut Rng, w: f64, h: f64, count: usize) -> Vec<SnappedTri> {
    (0..count)
        .map(|k| {
            let (cx, cy) = (rng.unit() * w, rng.unit() * h);
            let s = 4.0 + rng.unit() * 60.0;
            let v = [0; 3].map(|_| [cx + (rng.unit() - 0.5) * s, cy + (rng.unit() - 0.5) * s]);
            let z = [0; 3].map(|_| rng.unit());
            let rgb = [rng.unit(), rng.unit(), rng.unit()];
            tri(v, z, rgb, k as u16)
        })
        .collect()
}

/// A grid of square objects (two triangles, one tag each) with steep depth planes, stacked
/// in a few nearly coincident layers: fragments of different objects meet inside pixels at
/// close depths, which is where the choice of depth matters.
fn scene_layers(rng: &mut Rng, w: f64, h: f64) -> Vec<SnappedTri> {
    let mut out = Vec::new();
    let mut tag = 0;
    for layer in 0..3 {
        let s = 13.0 + layer as f64 * 4.0;
        let mut y = -(layer as f64) * 3.3;
        while y < h {
            let mut x = -(layer as f64) * 5.1;
            while x < w {
                let z0 = 0.3 + 0.1 * layer as f64 + (rng.unit() - 0.5) * 0.2;
                let (gx, gy) = ((rng.unit() - 0.5) * 0.02, (rng.unit() - 0.5) * 0.02);
                let z = |px: f64, py: f64| z0 + gx * (px - x) + gy * (py - y);
                let rgb = [rng.unit(), rng.unit(), rng.unit()];
                let p = [[x, y], [x + s, y], [x + s, y + s], [x, y + s]];
                for t in [[0, 1, 2], [0, 2, 3]] {
                    let v = t.map(|k| p[k]);
                    out.push(tri(v, v.map(|q| z(q[0], q[1])), rgb, tag));
                }
                tag += 1;
                x += s * 1.3;
            }
            y += s * 1.3;
        }
    }
    out
}

/// Pairs of large triangles that cross in depth (interpenetrating surfaces).
fn scene_cross(rng: &mut Rng, w: f64, h: f64, pairs: usize) -> Vec<SnappedTri> {
    let mut out = Vec::new();
    for k in 0..pairs {
        let (cx, cy) = (rng.unit() * w, rng.unit() * h);
        let s = 20.0 + rng.unit() * 40.0;
        let v1 = [0; 3].map(|_| [cx + (rng.unit() - 0.5) * s, cy + (rng.unit() - 0.5) * s]);
        let v2 = [0; 3].map(|_| [cx + (rng.unit() - 0.5) * s, cy + (rng.unit() - 0.5) * s]);
        // Plane 1 slopes along x, plane 2 against it: they cross near x = cx.
        let z1 = v1.map(|p| 0.5 + (p[0] - cx) * 0.004);
        let z2 = v2.map(|p| 0.5 - (p[0] - cx) * 0.004 + (p[1] - cy) * 0.001);
        out.push(tri(v1, z1, [1.0, 0.2, 0.2], 2 * k as u16));
        out.push(tri(v2, z2, [0.2, 0.2, 1.0], 2 * k as u16 + 1));
    }
    out
}

fn report(name: &str, tris: &[SnappedTri], w: u32, h: u32, inter: bool) {
    for size in [MaskSize::S4X4, MaskSize::S8X8] {
        let p = AbufferParams {
            size,
            depth: DepthSelect::Exhaustive,
            interpenetrating: inter,
            compare_variants: true,
        };
        let f = render_abuffer(tris, w, h, [0, 0, 0], &p).unwrap();
        let s = &f.stats;
        let per = |e: u64| e as f64 / s.sorted_fragments.max(1) as f64;
        let mut times = Vec::new();
        for d in DepthSelect::ALL {
            let p = AbufferParams {
                depth: d,
                compare_variants: false,
                ..p
            };
            let t0 = Instant::now();
            let g = render_abuffer(tris, w, h, [0, 0, 0], &p).unwrap();
            times.push(t0.elapsed().as_secs_f64() * 1e3);
            std::hint::black_box(g);
        }
        println!(
            "| {name} | {size} | {} | {} | {} | {} | {} |",
            tris.len(),
            s.fragments,
            s.multi_pixels,
            s.sorted_fragments,
            s.merges
        );
        for (k, d) in DepthSelect::ALL.iter().enumerate() {
            println!(
                "|   | {:<10} | evals/frag {:.2} | order≠ex {} | visible≠ex {} | rgb≠ex {} | {:.1} ms |",
                d.name(),
                per(s.variant_evals[k]),
                s.order_diff[k],
                s.visible_diff[k],
                s.rgb_diff[k],
                times[k]
            );
        }
    }
}

fn main() {
    let mut rng = Rng(0x5EED_0000);
    println!("| scene | mask | triangles | fragments | multi-fragment pixels | sorted fragments | merges |");
    println!("|---|---|---|---|---|---|---|");
    let (w, h) = (320u32, 240u32);
    let s = scene_random(&mut rng, w as f64, h as f64, 600);
    report("random", &s, w, h, false);
    let s = scene_layers(&mut rng, w as f64, h as f64);
    report("layers", &s, w, h, false);
    let s = scene_cross(&mut rng, w as f64, h as f64, 150);
    report("cross (interpenetrating)", &s, w, h, true);

    // Speed at 1080p with the default options.
    let (w, h) = (1920u32, 1080u32);
    let s = scene_random(&mut rng, w as f64, h as f64, 20_000);
    for size in [MaskSize::S4X4, MaskSize::S8X8] {
        let p = AbufferParams {
            size,
            ..Default::default()
        };
        let t0 = Instant::now();
        let f = render_abuffer(&s, w, h, [0, 0, 0], &p).unwrap();
        println!(
            "1080p random 20000 tris {size} search: {:.0} ms, {} fragments, {} fast pixels, {} multi-fragment pixels, {:.2} evals per sorted fragment",
            t0.elapsed().as_secs_f64() * 1e3,
            f.stats.fragments,
            f.stats.fast_pixels,
            f.stats.multi_pixels,
            f.stats.depth_evals as f64 / f.stats.sorted_fragments.max(1) as f64
        );
    }
}
