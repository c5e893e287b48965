//! Measures the 1080p scene alone: triangle sizes, the time of each exact reference, of
//! each setting's render (once, all cores) and of its hardware model at N = 64, and writes
//! the box reference as a PNG.
//!
//! `cargo run --release -p pixelproc-bench --example city_measure [out.png]`

use std::time::Instant;

use pixelproc_bench::scenes::city_1080p;
use pixelproc_bench::{reference_filter, sweep_settings, HwConfig};
use pixelproc_sim::aa::render_aa;
use pixelproc_sim::hwcost::{method_cost, Frame};
use pixelproc_sim::reference::{filtered_reference_image, reference_image, RefFilter};

fn main() {
    let sc = city_1080p();
    let area = |t: &pixelproc_sim::setup::SnappedTri| {
        let f = |k: usize| [t.v[k][0] as f64 / 256.0, t.v[k][1] as f64 / 256.0];
        let (a, b, c) = (f(0), f(1), f(2));
        ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs() / 2.0
    };
    let small = sc.tris.iter().filter(|t| area(t) < 4.0).count();
    let tiny = sc.tris.iter().filter(|t| area(t) < 1.0).count();
    println!(
        "{}: {}x{}, {} triangles, {} under 4 px², {} under 1 px²",
        sc.name,
        sc.width,
        sc.height,
        sc.tris.len(),
        small,
        tiny
    );
    let t = Instant::now();
    let r = reference_image(&sc.tris, sc.width, sc.height, sc.bg);
    println!("box reference: {:.1} s", t.elapsed().as_secs_f64());
    if let Some(p) = std::env::args().nth(1) {
        image::save_buffer(&p, &r.rgb8(), sc.width, sc.height, image::ColorType::Rgb8).unwrap();
    }
    let settings = sweep_settings(false);
    let mut done = Vec::new();
    for s in &settings {
        let f = reference_filter(&s.aa);
        if f != RefFilter::Box && !done.contains(&f) {
            let t = Instant::now();
            let g = filtered_reference_image(&sc.tris, sc.width, sc.height, sc.bg, f);
            println!(
                "{f:?} reference: {:.1} s (quadrature error ≤ {:.1e})",
                t.elapsed().as_secs_f64(),
                g.max_quad_err
            );
            done.push(f);
        }
    }
    let cfg = HwConfig::DEFAULT;
    let frame = Frame {
        tris: &sc.tris,
        width: sc.width,
        height: sc.height,
    };
    for s in &settings {
        let t = Instant::now();
        let img = render_aa(&sc.tris, sc.width, sc.height, sc.bg, &s.aa).unwrap();
        let tr = t.elapsed().as_secs_f64();
        let rmse = r.rmse(&img.rgb);
        let t = Instant::now();
        let c = method_cost(&s.aa, &frame, &cfg).unwrap();
        println!(
            "{} {}: render {:.2} s, RMSE vs box {:.3}, hw {} cycles ({:.2} s to model)",
            s.method,
            s.setting,
            tr,
            rmse,
            c.cycles,
            t.elapsed().as_secs_f64()
        );
    }
}
