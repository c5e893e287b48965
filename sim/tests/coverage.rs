//! Independent checks of span setup's pixel-centre coverage: watertightness (every centre
//! of a tiled region covered exactly once), overdraw in the style of a conformance suite,
//! and agreement with a floating-point point-in-triangle test written here.

use pixelproc_sim::setup::{snap_coord, SnappedTri, TriSetup};
use proptest::prelude::*;

const W: u32 = 64;
const H: u32 = 64;

fn tri_q8(v: [[i32; 2]; 3]) -> SnappedTri {
    SnappedTri {
        chan: 0,
        v,
        z: [100, 200, 300],
        c: [[1 << 12; 3]; 3],
        tag: 1,
        host: None,
        nclass: 0,
    }
}

fn snap(p: [f64; 2]) -> [i32; 2] {
    [snap_coord(p[0]).unwrap(), snap_coord(p[1]).unwrap()]
}

/// Adds 0.5 per covering triangle, like a conformance overdraw test.
fn overdraw(tris: &[SnappedTri]) -> Vec<f64> {
    let mut acc = vec![0.0; (W * H) as usize];
    for t in tris {
        let Some(s) = TriSetup::new(t).unwrap() else {
            continue;
        };
        for j in 0..H as i64 {
            if let Some((l, r)) = s.columns(j, W) {
                for i in l..=r {
                    acc[(j as u32 * W + i as u32) as usize] += 0.5;
                }
            }
        }
    }
    acc
}

/// Float edge function sign of point `p` against edge a→b (exact in f64 for Q.8 inputs).
fn edge(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Independent point-in-polygon (convex, either winding): Some(true) strictly inside,
/// Some(false) strictly outside, None on the boundary.
fn inside_convex(poly: &[[f64; 2]], p: [f64; 2]) -> Option<bool> {
    let n = poly.len();
    let e: Vec<f64> = (0..n)
        .map(|i| edge(poly[i], poly[(i + 1) % n], p))
        .collect();
    if e.iter().all(|&x| x > 0.0) || e.iter().all(|&x| x < 0.0) {
        Some(true)
    } else if e.iter().any(|&x| x > 0.0) && e.iter().any(|&x| x < 0.0) {
        Some(false)
    } else {
        None
    }
}

fn q8f(v: [i32; 2]) -> [f64; 2] {
    [v[0] as f64 / 256.0, v[1] as f64 / 256.0]
}

fn check_union(tris: &[SnappedTri], outline: &[[i32; 2]]) {
    let od = overdraw(tris);
    let poly: Vec<[f64; 2]> = outline.iter().map(|&v| q8f(v)).collect();
    for j in 0..H {
        for i in 0..W {
            let c = [i as f64 + 0.5, j as f64 + 0.5];
            let v = od[(j * W + i) as usize];
            assert!(v <= 0.5, "pixel ({i},{j}) covered more than once: {v}");
            match inside_convex(&poly, c) {
                Some(true) => assert_eq!(v, 0.5, "pixel ({i},{j}) inside the union left uncovered"),
                Some(false) => assert_eq!(v, 0.0, "pixel ({i},{j}) outside the union covered"),
                None => {}
            }
        }
    }
}

/// A fan of `n` triangles around `centre` over a convex polygon (a regular n-gon).
fn fan(centre: [f64; 2], radius: f64, n: usize, phase: f64) -> (Vec<SnappedTri>, Vec<[i32; 2]>) {
    let ring: Vec<[i32; 2]> = (0..n)
        .map(|k| {
            let a = phase + k as f64 * std::f64::consts::TAU / n as f64;
            snap([centre[0] + radius * a.cos(), centre[1] + radius * a.sin()])
        })
        .collect();
    let c = snap(centre);
    let tris = (0..n)
        .map(|k| tri_q8([c, ring[k], ring[(k + 1) % n]]))
        .collect();
    (tris, ring)
}

#[test]
fn fans_with_vertices_near_pixel_centres_are_watertight() {
    for (k, &(cx, cy)) in [
        (32.5, 32.5),
        (32.5 + 6e-5, 32.5 - 6e-5),
        (31.0, 30.0),
        (32.5 - 6e-5, 32.5),
    ]
    .iter()
    .enumerate()
    {
        for n in [3, 5, 8, 13, 31] {
            let (tris, ring) = fan([cx, cy], 25.0, n, 0.1 * k as f64);
            check_union(&tris, &ring);
        }
    }
}

#[test]
fn shared_edge_through_pixel_centres_covers_each_once() {
    // Diagonal, horizontal and vertical shared edges passing exactly through centres.
    let sq = [
        snap([8.5, 8.5]),
        snap([40.5, 8.5]),
        snap([40.5, 40.5]),
        snap([8.5, 40.5]),
    ];
    for (a, b) in [(0, 2), (1, 3)] {
        let c = if a == 0 { [1, 3] } else { [0, 2] };
        let tris = vec![
            tri_q8([sq[a], sq[b], sq[c[0]]]),
            tri_q8([sq[a], sq[c[1]], sq[b]]),
        ];
        check_union(&tris, &sq);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A grid of quads split into triangles, interior vertices jittered (some a hair off
    /// pixel centres): the rectangle's every centre covered exactly once.
    #[test]
    fn jittered_grids_are_watertight(
        jit in proptest::collection::vec((-0.49f64..0.49, -0.49f64..0.49, 0u8..4), 49),
        flip in proptest::collection::vec(any::<bool>(), 36),
    ) {
        let n = 6;
        let step = 9.0;
        let mut v = vec![[0i32; 2]; (n + 1) * (n + 1)];
        for y in 0..=n {
            for x in 0..=n {
                let (mut px, mut py) = (4.0 + x as f64 * step, 4.0 + y as f64 * step);
                if x > 0 && x < n && y > 0 && y < n {
                    let (dx, dy, mode) = jit[y * (n + 1) + x];
                    match mode {
                        // Within a hair of a pixel centre.
                        0 => { px = px.floor() + 0.5 + dx * 1.2e-4; py = py.floor() + 0.5 + dy * 1.2e-4; }
                        // Exactly on a pixel centre.
                        1 => { px = px.floor() + 0.5; py = py.floor() + 0.5; }
                        _ => { px += dx * 4.0; py += dy * 4.0; }
                    }
                }
                v[y * (n + 1) + x] = snap([px, py]);
            }
        }
        let mut tris = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let (a, b) = (v[y * (n + 1) + x], v[y * (n + 1) + x + 1]);
                let (c, d) = (v[(y + 1) * (n + 1) + x + 1], v[(y + 1) * (n + 1) + x]);
                if flip[y * n + x] {
                    tris.push(tri_q8([a, b, c]));
                    tris.push(tri_q8([a, c, d]));
                } else {
                    tris.push(tri_q8([a, b, d]));
                    tris.push(tri_q8([b, c, d]));
                }
            }
        }
        let outline = [v[0], v[n], v[(n + 1) * (n + 1) - 1], v[n * (n + 1)]];
        check_union(&tris, &outline);
    }

    /// Coverage agrees with a float point-in-triangle test at every centre not on an edge.
    #[test]
    fn coverage_matches_float_point_in_triangle(
        pts in proptest::collection::vec((-8.0f64..72.0, -8.0f64..72.0), 3),
    ) {
        let v = [snap([pts[0].0, pts[0].1]), snap([pts[1].0, pts[1].1]), snap([pts[2].0, pts[2].1])];
        let t = tri_q8(v);
        let setup = TriSetup::new(&t).unwrap();
        let poly: Vec<[f64; 2]> = v.iter().map(|&p| q8f(p)).collect();
        for j in 0..H as i64 {
            let cols = setup.as_ref().and_then(|s| s.columns(j, W));
            for i in 0..W as i64 {
                let covered = cols.is_some_and(|(l, r)| i >= l && i <= r);
                if let Some(inside) = inside_convex(&poly, [i as f64 + 0.5, j as f64 + 0.5]) {
                    prop_assert_eq!(covered, inside, "pixel ({}, {})", i, j);
                }
            }
        }
    }
}
