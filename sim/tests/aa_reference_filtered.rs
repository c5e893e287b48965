//! The filtered exact references (seed-002 Gaussian and cone) checked against an
//! independent brute-force integral: a Gouraud-shaded half-plane edge, integrated per
//! pixel by nested 1000×1000 Simpson quadrature over the filter's disc in coordinates
//! aligned with the edge.

mod aa_common;
use aa_common::*;
use pixelproc_sim::reference::{filtered_reference_image, reference_image, RefFilter};
use pixelproc_sim::setup::SnappedTri;

/// The kernel, written out here: `exp(−r²/(2·0.4²))` or `1 − r` inside radius 1.
fn kernel(f: RefFilter, r: f64) -> f64 {
    if r >= 1.0 {
        return 0.0;
    }
    match f {
        RefFilter::Gauss { sigma } => (-r * r / (2.0 * sigma * sigma)).exp(),
        RefFilter::Cone => 1.0 - r,
        RefFilter::Box => 1.0,
    }
}

/// Composite Simpson over `[a, b]` with `n` (even) intervals.
fn simpson(a: f64, b: f64, n: usize, g: impl Fn(f64) -> f64) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = g(a) + g(b);
    for k in 1..n {
        s += if k % 2 == 1 { 4.0 } else { 2.0 } * g(a + k as f64 * h);
    }
    s * h / 3.0
}

/// `(∫ K, ∫ K·u)` over the part of the unit disc where `u > tau`, with `u = sin φ`,
/// `v = cos φ · sin ψ` (smooth limits: `dA = cos²φ · cos ψ dψ dφ`).
fn cap_integrals(f: RefFilter, tau: f64) -> (f64, f64) {
    let lo = tau.clamp(-1.0, 1.0).asin();
    let half = std::f64::consts::FRAC_PI_2;
    let inner = |phi: f64, w: f64| {
        let (s, c) = phi.sin_cos();
        simpson(-half, half, 1000, |psi| {
            let v = c * psi.sin();
            kernel(f, (s * s + v * v).sqrt()) * c * c * psi.cos()
        }) * w
    };
    let w0 = simpson(lo, half, 1000, |phi| inner(phi, 1.0));
    let w1 = simpson(lo, half, 1000, |phi| inner(phi, phi.sin()));
    (w0, w1)
}

#[test]
fn gouraud_half_plane_matches_a_brute_force_filter_integral() {
    // A huge triangle whose upper edge is the slanted line through (x0, y0) and (x1, y1)
    // (Q.8-exact points); it covers the side below the line (y grows downwards). Vertex
    // intensities differ per channel, so the colour gradient term is exercised.
    let (x0, y0, x1, y1, x2, y2) = (
        -40.0,
        2.0 + 7.0 / 256.0,
        56.0,
        7.0 - 45.0 / 256.0,
        -40.0,
        90.0,
    );
    let rgb = [[250u32, 10, 128], [20, 240, 60], [130, 70, 200]];
    let t = SnappedTri {
        v: [[q8(x0), q8(y0)], [q8(x1), q8(y1)], [q8(x2), q8(y2)]],
        z: [100, 100, 100],
        c: rgb.map(|c| c.map(|v| (v << 12) + 2048)),
        ..Default::default()
    };
    let bg = [30u8, 60, 90];
    let (w, h) = (10u32, 8u32);
    // The affine colour through the three vertices, per channel: (a, b, c) of a·x + b·y + c.
    let det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    let plane = |k: usize| {
        let (v0, v1, v2) = (rgb[0][k] as f64, rgb[1][k] as f64, rgb[2][k] as f64);
        let a = ((v1 - v0) * (y2 - y0) - (v2 - v0) * (y1 - y0)) / det;
        let b = ((x1 - x0) * (v2 - v0) - (x2 - x0) * (v1 - v0)) / det;
        (a, b, v0 - a * x0 - b * y0)
    };
    let planes = [plane(0), plane(1), plane(2)];
    // Unit normal pointing into the covered side, and the line as n·p = d.
    let (ex, ey) = (x1 - x0, y1 - y0);
    let len = (ex * ex + ey * ey).sqrt();
    let n = [-ey / len, ex / len];
    assert!(n[1] > 0.0, "normal points down, into the triangle");
    let d = n[0] * x0 + n[1] * y0;
    for f in [RefFilter::Gauss { sigma: 0.4 }, RefFilter::Cone] {
        let img = filtered_reference_image(&[t], w, h, bg, f);
        let (vol, _) = cap_integrals(f, -1.0);
        for j in 0..h {
            for i in 0..w {
                let c = [i as f64 + 0.5, j as f64 + 0.5];
                // Covered where n·(p − c) > d − n·c.
                let tau = d - (n[0] * c[0] + n[1] * c[1]);
                let (w0, w1) = cap_integrals(f, tau);
                let got = img.image.rgb[(j * w + i) as usize];
                for k in 0..3 {
                    let (a, b, cc) = planes[k];
                    let ic = a * c[0] + b * c[1] + cc;
                    let gn = a * n[0] + b * n[1];
                    let want = (ic * w0 + gn * w1 + bg[k] as f64 * (vol - w0)) / vol;
                    assert!(
                        (got[k] - want).abs() < 1e-4,
                        "{f:?} pixel ({i},{j}) ch {k}: {} vs {want}",
                        got[k]
                    );
                }
            }
        }
        assert!(img.max_quad_err < 1e-6, "{f:?}: {}", img.max_quad_err);
    }
}

#[test]
fn filtered_reference_keeps_the_box_references_areas_and_is_exact_on_flat_regions() {
    let tris = random_scene(5, 12, 24.0, 16.0);
    let b = reference_image(&tris, 24, 16, [0, 0, 0]);
    let g = filtered_reference_image(&tris, 24, 16, [0, 0, 0], RefFilter::Cone);
    assert_eq!(b.covered, g.image.covered);
    assert_eq!(b.dominant, g.image.dominant);
    assert_eq!(b.visible_area, g.image.visible_area);
    // The box filter is the box reference itself.
    let bb = filtered_reference_image(&tris, 24, 16, [0, 0, 0], RefFilter::Box);
    assert_eq!(b.rgb, bb.image.rgb);
    // A flat screen-filling triangle pair: every pixel is exactly its colour.
    let flat = |v: [[f64; 2]; 3]| SnappedTri {
        v: v.map(|p| [q8(p[0]), q8(p[1])]),
        z: [10, 10, 10],
        c: [[(77 << 12) + 2048, (5 << 12) + 2048, (200 << 12) + 2048]; 3],
        ..Default::default()
    };
    let quad = [
        flat([[-3.0, -3.0], [20.0, -3.0], [20.0, 20.0]]),
        flat([[-3.0, -3.0], [20.0, 20.0], [-3.0, 20.0]]),
    ];
    for f in [RefFilter::Gauss { sigma: 0.4 }, RefFilter::Cone] {
        let r = filtered_reference_image(&quad, 8, 8, [255, 255, 255], f);
        for p in &r.image.rgb {
            for (k, want) in [77.0, 5.0, 200.0].iter().enumerate() {
                assert!((p[k] - want).abs() < 1e-9, "{f:?}: {p:?}");
            }
        }
    }
}
