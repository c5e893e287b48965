//! Fraction masks and the A-buffer coverage AOV against an independent float statement:
//! a subpixel centre is covered when it lies inside the triangle, with the top-left rule
//! for centres exactly on an edge. All coordinates here are dyadic fractions with few bits,
//! so the f64 cross products below are exact and the on-edge test `== 0.0` is exact too.

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::abuffer::{render_abuffer, AbufferParams};
use pixelproc_sim::mask::MaskEdges;
use pixelproc_sim::mask_search::DepthSelect;
use pixelproc_sim::rng::XorShift64Star as Rng;
use pixelproc_sim::setup::SnappedTri;

/// Float point-in-triangle with the top-left rule. `v` in pixels.
fn inside(v: [[f64; 2]; 3], x: f64, y: f64) -> bool {
    // Orient so the signed area is positive (y down: clockwise on screen).
    let area =
        (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[2][0] - v[0][0]) * (v[1][1] - v[0][1]);
    if area == 0.0 {
        return false;
    }
    let v = if area > 0.0 { v } else { [v[0], v[2], v[1]] };
    for k in 0..3 {
        let (p, q) = (v[k], v[(k + 1) % 3]);
        // Cross product of the edge with the point: > 0 on the inner side.
        let e = (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
        if e < 0.0 {
            return false;
        }
        if e == 0.0 {
            // On the edge: kept only on a left edge (going up the screen, q above p) or a
            // top edge (horizontal, going right).
            let left = q[1] < p[1];
            let top = q[1] == p[1] && q[0] > p[0];
            if !(left || top) {
                return false;
            }
        }
    }
    true
}

/// Float coverage of pixel (i, j): bit per subpixel centre, same bit order as the digest
/// (bit = n·row + n − 1 − column). Coordinates are scaled by 2n·256 in x and 2m·256 in y
/// (positive factors keep every sign and the edge classification) so that vertices and
/// subpixel centres are integer-valued floats and the cross products are exact for every
/// grid size, including 3×5.
fn float_mask(t: &SnappedTri, n: u32, m: u32, i: i64, j: i64) -> u64 {
    let (fx, fy) = (2.0 * n as f64, 2.0 * m as f64);
    let v = t.v.map(|p| [p[0] as f64 * fx, p[1] as f64 * fy]);
    let mut mask = 0;
    for r in 0..m {
        for c in 0..n {
            let x = ((2 * n as i64 * i + 2 * c as i64 + 1) * 256) as f64;
            let y = ((2 * m as i64 * j + 2 * r as i64 + 1) * 256) as f64;
            if inside(v, x, y) {
                mask |= 1u64 << (n * r + (n - 1 - c));
            }
        }
    }
    mask
}

/// A Q.8 coordinate in 0..span px; every third one is snapped to a multiple of
/// `grid` (so that edges run through subpixel centres often).
fn coord(rng: &mut Rng, span: i32, grid: i32) -> i32 {
    let v = (rng.next_u64() % (span as u64 * 256)) as i32;
    if rng.next_u64().is_multiple_of(3) {
        v / grid * grid
    } else {
        v
    }
}

fn random_tri(rng: &mut Rng, span: i32, grid: i32, k: u64) -> SnappedTri {
    SnappedTri {
        chan: 0,
        v: [0; 3].map(|_| [coord(rng, span, grid), coord(rng, span, grid)]),
        z: [0; 3].map(|_| 16 + (rng.next_u64() % 1_000_000) as u32),
        c: [0; 3].map(|_| [0; 3].map(|_| (rng.next_u64() % (255 << 12)) as u32)),
        tag: k as u16,
        host: None,
        nclass: 0,
    }
}

#[test]
fn masks_match_float_point_in_triangle() {
    let mut rng = Rng(7);
    for (n, m) in [(4, 4), (8, 8), (3, 5), (2, 1)] {
        let size = MaskSize::new(n, m).unwrap();
        // Grid of subpixel-centre spacing in Q.8 (exact only where 256 divides evenly).
        let grid = (256 / (2 * n.max(m))) as i32;
        for k in 0..300 {
            let t = random_tri(&mut rng, 12, grid.max(1), k);
            let e = match MaskEdges::new(&t, size).unwrap() {
                Some(e) => e,
                None => continue,
            };
            for j in -1..13 {
                let rc = e.row_coverage(j, 14);
                for i in -1..14 {
                    let want = float_mask(&t, n, m, i, j);
                    let got = e.fraction_mask(i, j);
                    assert_eq!(got, want, "{size} tri {:?} pixel ({i},{j})", t.v);
                    // The renderer's row ranges: nothing outside `touched`, full in `full`.
                    if (0..14).contains(&i) {
                        match rc {
                            None => assert_eq!(got, 0),
                            Some(rc) => {
                                if i < rc.touched.0 || i > rc.touched.1 {
                                    assert_eq!(got, 0, "pixel {i} outside {rc:?}");
                                }
                                if let Some((a, b)) = rc.full {
                                    if a <= i && i <= b {
                                        assert_eq!(got, size.full(), "pixel {i} in {rc:?}");
                                    }
                                }
                                if got == size.full() {
                                    let (a, b) = rc.full.expect("full pixel not in full range");
                                    assert!(a <= i && i <= b);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn fan_covers_every_centre_exactly_once() {
    // A rectangle [2, 14] x [3, 13] px split into a fan around a random interior point,
    // through random points on its boundary: the union is the rectangle, every subpixel
    // centre inside it must be covered by exactly one triangle.
    let mut rng = Rng(99);
    for size in [MaskSize::S4X4, MaskSize::S8X8, MaskSize::new(3, 5).unwrap()] {
        for _ in 0..40 {
            let (x0, x1, y0, y1) = (2 * 256, 14 * 256, 3 * 256, 13 * 256);
            let centre = [
                x0 + 1 + (rng.next_u64() % (x1 - x0 - 2) as u64) as i32,
                y0 + 1 + (rng.next_u64() % (y1 - y0 - 2) as u64) as i32,
            ];
            let mut ring = vec![[x0, y0]];
            let r = |rng: &mut Rng, a: i32, b: i32| {
                a + 1 + (rng.next_u64() % (b - a - 1) as u64) as i32
            };
            ring.push([r(&mut rng, x0, x1), y0]);
            ring.push([x1, y0]);
            ring.push([x1, r(&mut rng, y0, y1)]);
            ring.push([x1, y1]);
            ring.push([r(&mut rng, x0, x1), y1]);
            ring.push([x0, y1]);
            ring.push([x0, r(&mut rng, y0, y1)]);
            let tris: Vec<MaskEdges> = (0..ring.len())
                .filter_map(|k| {
                    let t = SnappedTri {
                        v: [centre, ring[k], ring[(k + 1) % ring.len()]],
                        ..Default::default()
                    };
                    MaskEdges::new(&t, size).unwrap()
                })
                .collect();
            for j in 0..16 {
                for i in 0..16 {
                    let inside_rect = (2..14).contains(&i) && (3..13).contains(&j);
                    let mut union = 0u64;
                    for t in &tris {
                        let mk = t.fraction_mask(i, j);
                        assert_eq!(union & mk, 0, "double cover at ({i},{j})");
                        union |= mk;
                    }
                    let want = if inside_rect { size.full() } else { 0 };
                    assert_eq!(union, want, "{size} pixel ({i},{j}) centre {centre:?}");
                }
            }
        }
    }
}

#[test]
fn coverage_aov_matches_float_union() {
    let mut rng = Rng(2024);
    for size in [MaskSize::S4X4, MaskSize::S8X8] {
        let (w, h) = (20u32, 16u32);
        let tris: Vec<SnappedTri> = (0..25).map(|k| random_tri(&mut rng, 20, 16, k)).collect();
        for depth in [DepthSelect::Search, DepthSelect::Exhaustive] {
            let p = AbufferParams {
                size,
                depth,
                ..Default::default()
            };
            let f = render_abuffer(&tris, w, h, [0, 0, 0], &p).unwrap();
            for j in 0..h as i64 {
                for i in 0..w as i64 {
                    let mut union = 0u64;
                    let mut count = 0;
                    for t in &tris {
                        let mk = float_mask(t, size.n(), size.m(), i, j);
                        union |= mk;
                        count += (mk != 0) as u16;
                    }
                    let k = (j * w as i64 + i) as usize;
                    assert_eq!(f.coverage[k] as u32, union.count_ones(), "({i},{j})");
                    assert_eq!(f.fragments[k], count, "({i},{j})");
                    if union == 0 {
                        assert_eq!(&f.rgb[3 * k..3 * k + 3], &[0, 0, 0]);
                    }
                }
            }
        }
    }
}

#[test]
fn full_cover_resolves_to_the_colour_at_the_centre() {
    // One flat-coloured triangle covering the whole 8x8 screen: every pixel is on the fast
    // path and takes the colour exactly; a half-covered pixel blends with the background.
    let c = [[200 << 12, 100 << 12, 0]; 3];
    let t = SnappedTri {
        chan: 0,
        v: [[-2560, -2560], [10240, -2560], [-2560, 10240]],
        z: [1000; 3],
        c,
        tag: 0,
        host: None,
        nclass: 0,
    };
    let f = render_abuffer(&[t], 8, 8, [0, 0, 0], &AbufferParams::default()).unwrap();
    assert!(
        f.rgb.chunks(3).all(|p| p == [200, 100, 0]),
        "{:?}",
        &f.rgb[..24]
    );
    assert_eq!(f.stats.fast_pixels, 64);
    // Left half of pixel column 2 (vertical right edge at x = 2.5 px).
    let t = SnappedTri {
        v: [[0, -2560], [640, -2560], [640, 10240]],
        ..t
    };
    let f = render_abuffer(&[t], 8, 8, [0, 0, 0], &AbufferParams::default()).unwrap();
    let k = (4 * 8 + 2) * 3;
    // 8 of 16 bits: 200·8/16 = 100, 100·8/16 = 50.
    assert_eq!(&f.rgb[k..k + 3], &[100, 50, 0]);
    assert_eq!(f.coverage[4 * 8 + 2], 8);
}
