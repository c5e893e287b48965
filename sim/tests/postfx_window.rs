//! The 5-line window of post-process anti-aliasing (seed 004: "to separate overlapping or
//! close edges, look at two lines above and two below"): two close parallel edges are
//! judged against the exact box-filtered reference.

use pixelproc_sim::aa::{render_aa, AaMethod, PostFxParams};
use pixelproc_sim::reference::reference_image;
use pixelproc_sim::setup::SnappedTri;

const WHITE: [u32; 3] = [(255 << 12) + 2048; 3];

fn q(x: f64) -> i32 {
    (x * 256.0).round() as i32
}

/// A quad (two triangles, one plane, constant depth) with corners in order.
fn quad(p: [[f64; 2]; 4], z: u32, transpose: bool) -> Vec<SnappedTri> {
    let p = p.map(|c| if transpose { [c[1], c[0]] } else { c });
    [[0, 1, 2], [0, 2, 3]]
        .iter()
        .map(|ix| SnappedTri {
            v: ix.map(|i: usize| [q(p[i][0]), q(p[i][1])]),
            z: [z; 3],
            c: [WHITE; 3],
            ..Default::default()
        })
        .collect()
}

/// Upper object above `y = y0 − x/16`; with `second`, a lower object below the parallel
/// line one pixel further down (a one-pixel background gap between two close edges).
fn scene(y0: f64, second: bool, transpose: bool) -> Vec<SnappedTri> {
    let e = |x: f64, d: f64| y0 + d - x / 16.0;
    let mut t = quad(
        [
            [-8.0, -8.0],
            [72.0, -8.0],
            [72.0, e(72.0, 0.0)],
            [-8.0, e(-8.0, 0.0)],
        ],
        1000,
        transpose,
    );
    if second {
        t.extend(quad(
            [
                [-8.0, e(-8.0, 1.0)],
                [72.0, e(72.0, 1.0)],
                [72.0, 30.0],
                [-8.0, 30.0],
            ],
            2000,
            transpose,
        ));
    }
    t
}

fn rmse(tris: &[SnappedTri], window: bool, transpose: bool) -> (f64, Vec<u8>) {
    let (w, h) = if transpose { (24, 64) } else { (64, 24) };
    let p = PostFxParams {
        window,
        ..Default::default()
    };
    let f = render_aa(tris, w, h, [0, 0, 0], &AaMethod::PostFx(p)).unwrap();
    let r = reference_image(tris, w, h, [0, 0, 0]);
    (r.rmse(&f.rgb), f.rgb)
}

#[test]
fn close_parallel_edges_need_the_five_line_window() {
    for transpose in [false, true] {
        for y0 in [8.3, 8.55, 8.8] {
            let tris = scene(y0, true, transpose);
            let (on, _) = rmse(&tris, true, transpose);
            let (off, _) = rmse(&tris, false, transpose);
            let (w, h) = if transpose { (24, 64) } else { (64, 24) };
            let none = render_aa(&tris, w, h, [0, 0, 0], &AaMethod::None).unwrap();
            let base = reference_image(&tris, w, h, [0, 0, 0]).rmse(&none.rgb);
            println!(
                "transpose={transpose} y0={y0}: none {base:.3}, 3 lines {off:.3}, 5 lines {on:.3}"
            );
            assert!(on < 0.8 * off, "window {on} vs 3-line {off}");
            assert!(on < 0.6 * base, "window {on} vs no AA {base}");
        }
    }
}

#[test]
fn an_isolated_edge_is_blended_the_same_with_or_without_the_window() {
    for transpose in [false, true] {
        for y0 in [8.3, 8.55, 8.8] {
            let tris = scene(y0, false, transpose);
            let (on, a) = rmse(&tris, true, transpose);
            let (_, b) = rmse(&tris, false, transpose);
            assert_eq!(a, b);
            // And the isolated staircase is well anti-aliased (exact reference).
            let (w, h) = if transpose { (24, 64) } else { (64, 24) };
            let none = render_aa(&tris, w, h, [0, 0, 0], &AaMethod::None).unwrap();
            let base = reference_image(&tris, w, h, [0, 0, 0]).rmse(&none.rgb);
            assert!(on < 0.4 * base, "rmse {on} vs no AA {base}");
        }
    }
}
