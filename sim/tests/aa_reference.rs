//! The exact reference checked against independent geometry.

mod aa_common;
use aa_common::*;
use pixelproc_sim::reference::reference_image;
use pixelproc_sim::setup::{HostPlane, SnappedTri};

fn flat(v: [[f64; 2]; 3], z: [u32; 3], rgb: [u32; 3]) -> SnappedTri {
    SnappedTri {
        v: v.map(|p| [q8(p[0]), q8(p[1])]),
        z,
        c: [rgb.map(|c| (c << 12) + 2048); 3],
        ..Default::default()
    }
}

#[test]
fn single_triangle_pixel_areas_sum_to_its_shoelace_area() {
    let mut r = Lcg(7);
    for _ in 0..20 {
        let v = [0, 1, 2].map(|_| [r.range(0.5, 23.5), r.range(0.5, 15.5)]);
        let t = flat(v, [100, 100, 100], [255, 255, 255]);
        // The snapped vertices, from the raw Q.8 integers.
        let p = t.v.map(|q| [q[0] as f64 / 256.0, q[1] as f64 / 256.0]);
        let shoelace = 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
                .abs();
        let img = reference_image(&[t], 24, 16, [0, 0, 0]);
        let sum: f64 = img.covered.iter().sum();
        assert!((sum - shoelace).abs() < 1e-9, "{sum} vs {shoelace}");
        assert!((img.visible_area[0] - shoelace).abs() < 1e-9);
        // White on black: every pixel's value is 255·coverage.
        for (c, rgb) in img.covered.iter().zip(&img.rgb) {
            assert!((rgb[0] - 255.0 * c).abs() < 1e-9);
        }
    }
}

/// `∫_{x0}^{x0+1} clamp(m·x + c − y0, 0, 1) dx`, exactly, by splitting at the kinks.
fn below_line_coverage(m: f64, c: f64, x0: f64, y0: f64) -> f64 {
    let f = |x: f64| (m * x + c - y0).clamp(0.0, 1.0);
    let mut xs = vec![x0, x0 + 1.0];
    for target in [0.0, 1.0] {
        if m != 0.0 {
            let x = (target + y0 - c) / m;
            if x > x0 && x < x0 + 1.0 {
                xs.push(x);
            }
        }
    }
    xs.sort_by(f64::total_cmp);
    // f is linear between consecutive kinks: trapezoid rule is exact there.
    xs.windows(2)
        .map(|w| 0.5 * (f(w[0]) + f(w[1])) * (w[1] - w[0]))
        .sum()
}

#[test]
fn half_plane_edge_has_the_analytic_coverage() {
    // A huge triangle whose upper edge is y = m·x + c (Q.8-exact end points); the region
    // covered is below the line (y grows downwards, so "covered" = y > line).
    let (x0, x1) = (-64.0, 96.0);
    let (y0, y1) = (3.0 + 7.0 / 256.0, 11.0 - 45.0 / 256.0);
    let m = (y1 - y0) / (x1 - x0);
    let c = y0 - m * x0;
    let t = flat(
        [[x0, y0], [x1, y1], [x0, 200.0]],
        [50, 50, 50],
        [255, 255, 255],
    );
    let img = reference_image(&[t], 32, 16, [0, 0, 0]);
    for j in 0..16 {
        for i in 0..32 {
            // Covered = y from line to bottom = 1 − (part of pixel above the line).
            let above = below_line_coverage(m, c, i as f64, j as f64);
            let want = 1.0 - above;
            let got = img.covered[j * 32 + i];
            assert!((got - want).abs() < 1e-9, "({i},{j}) {got} vs {want}");
        }
    }
}

#[test]
fn interpenetrating_quads_split_at_their_intersection_line() {
    // A: z = 1000 + 100x (red), B: z = 1850 − 100x (blue): equal at x = 4.25.
    let quad = |z0: u32, z1: u32, rgb: [u32; 3]| {
        [
            flat([[0.0, 0.0], [8.0, 0.0], [8.0, 8.0]], [z0, z1, z1], rgb),
            flat([[0.0, 0.0], [8.0, 8.0], [0.0, 8.0]], [z0, z1, z0], rgb),
        ]
    };
    let mut tris = quad(1000, 1800, [255, 0, 0]).to_vec();
    tris.extend(quad(1850, 1050, [0, 0, 255]));
    let img = reference_image(&tris, 8, 8, [0, 255, 0]);
    for j in 0..8 {
        for i in 0..8 {
            let red = (4.25 - i as f64).clamp(0.0, 1.0);
            let rgb = img.rgb[j * 8 + i];
            assert!((rgb[0] - 255.0 * red).abs() < 1e-9, "({i},{j}) {rgb:?}");
            assert!((rgb[2] - 255.0 * (1.0 - red)).abs() < 1e-9);
            assert!(rgb[1].abs() < 1e-9);
        }
    }
    // 4.25 columns of red: A's two triangles share 4.25·8 = 34 px².
    assert!((img.visible_area[0] + img.visible_area[1] - 34.0).abs() < 1e-9);
    assert!(matches!(img.dominant[4], 2 | 3), "B covers ¾ of column 4");
}

#[test]
fn decal_wins_over_its_host_at_equal_depth() {
    let host = flat(
        [[0.0, 0.0], [16.0, 0.0], [0.0, 16.0]],
        [500, 900, 1300],
        [0, 0, 255],
    );
    let mut decal = flat(
        [[2.0, 2.0], [6.0, 2.0], [2.0, 6.0]],
        [0, 0, 0],
        [255, 255, 255],
    );
    decal.z = [500, 500, 500]; // ignored: the host plane is used
    decal.host = Some(HostPlane {
        v: host.v,
        z: host.z,
    });
    let img = reference_image(&[host, decal], 16, 16, [0, 0, 0]);
    assert!((img.visible_area[1] - 8.0).abs() < 1e-9);
    assert!((img.visible_area[0] - (128.0 - 8.0)).abs() < 1e-9);
}
