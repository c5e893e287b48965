//! Prints RMSE against the exact reference, visible-surface errors, cost counters and
//! time for every anti-aliasing setting on a few generated scenes.
//!
//! `cargo run --release -p pixelproc-bench --example aa_measure [size] [triangles]`

use pixelproc_sim::aa::{
    edge_shade_levels, render_aa, AaMethod, CornerParams, Filter, MultiscanParams, Pattern,
    PostFxParams,
};
use pixelproc_sim::reference::reference_image;
use pixelproc_sim::rng::Lcg64 as Lcg;
use pixelproc_sim::setup::SnappedTri;

fn scene(seed: u64, n: usize, w: f64, h: f64) -> Vec<SnappedTri> {
    let mut r = Lcg(seed.wrapping_mul(0x9E3779B97F4A7C15) ^ 0x5555);
    let q = |x: f64| (x * 256.0).round() as i32;
    (0..n)
        .map(|k| {
            let (cx, cy) = (r.range(0.0, w), r.range(0.0, h));
            let s = if k % 5 == 0 {
                r.range(1.0, 4.0)
            } else {
                r.range(3.0, w / 5.0)
            };
            let v = [0, 1, 2].map(|_| [q(cx + r.range(-s, s)), q(cy + r.range(-s, s))]);
            let z = [0, 1, 2].map(|_| r.range(10_000.0, 2_000_000.0) as u32);
            let col = [0, 1, 2].map(|_| (r.range(0.0, 255.0) * 4096.0).floor() as u32 + 2048);
            SnappedTri {
                chan: 0,
                v,
                z,
                c: [col; 3],
                tag: k as u16,
                host: None,
                nclass: 0,
            }
        })
        .collect()
}

/// Every method and setting the example measures.
fn methods() -> Vec<AaMethod> {
    let mut methods = vec![AaMethod::None];
    for f in [Filter::Box, Filter::Gauss] {
        for n in [1, 2, 3, 4, 6, 8, 12] {
            methods.push(AaMethod::Multiscan(MultiscanParams::new(n, f)));
        }
    }
    methods.push(AaMethod::Multiscan(MultiscanParams::new(3, Filter::Cone)));
    for (p, c) in [
        (Pattern::Corner, false),
        (Pattern::Corner, true),
        (Pattern::D3d4x, false),
        (Pattern::Grid2x2, false),
    ] {
        methods.push(AaMethod::Corner(CornerParams::new(p, c)));
    }
    methods.push(AaMethod::PostFx(PostFxParams::default()));
    for k in [2, 4, 8, 16] {
        methods.push(AaMethod::Ssaa { k });
    }
    methods
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let size = *args.first().unwrap_or(&256) as u32;
    let ntri = *args.get(1).unwrap_or(&100);
    let methods = methods();
    for seed in 1..=2u64 {
        let tris = scene(seed, ntri, size as f64, size as f64);
        let bg = [20, 30, 40];
        let t0 = std::time::Instant::now();
        let r = reference_image(&tris, size, size, bg);
        println!(
            "scene {seed}: {size}x{size}, {ntri} triangles, reference {:.2} s",
            t0.elapsed().as_secs_f64()
        );
        let edge: Vec<bool> = r.edge_mask();
        println!(
            "{:<28} {:>7} {:>7} {:>7} {:>9} {:>8} {:>8}",
            "method", "rmse", "rmse_e", "wrongV", "zevals/px", "reads/px", "ms"
        );
        for m in &methods {
            let f = render_aa(&tris, size, size, bg, m).expect("render");
            let wrong = f.visible.as_ref().map_or(0, |v| {
                v.iter().zip(&r.dominant).filter(|(a, b)| a != b).count()
            });
            println!(
                "{:<28} {:>7.3} {:>7.3} {:>7} {:>9.2} {:>8.3} {:>8.1}",
                m.label(),
                r.rmse(&f.rgb),
                r.rmse_masked(&f.rgb, |k| edge[k]),
                wrong,
                f.stats.depth_evals_per_pixel(),
                f.stats.reads_per_pixel(),
                1000.0 * f.stats.seconds
            );
        }
    }
    println!("shade levels on a near-horizontal / near-vertical edge:");
    for m in &methods {
        println!(
            "{:<28} {:>3} {:>3}",
            m.label(),
            edge_shade_levels(m, false).unwrap(),
            edge_shade_levels(m, true).unwrap()
        );
    }
    println!("pattern metrics (levels h/v, edge-coverage RMS error):");
    for (p, c) in [
        (Pattern::Corner, false),
        (Pattern::Corner, true),
        (Pattern::D3d4x, false),
        (Pattern::Grid2x2, false),
    ] {
        let cp = CornerParams::new(p, c);
        let pm = pixelproc_sim::aa::corner::pattern_metrics(&cp);
        println!(
            "{:<28} {:>3} {:>3} {:>8.4}",
            cp.label(),
            pm.levels_horizontal,
            pm.levels_vertical,
            pm.edge_error_rms
        );
    }
}
