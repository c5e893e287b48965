//! The pass structure of the methods without RTL of their own (`hwcost::{multiscan,
//! sampling, postfx}`), hand-counted on an empty 16×2 screen with N = 8, where every
//! tile-line is readout-bound: TILE 0 issues at clock 3, TILE 1 at 4, every later TILE or
//! END `5 + L` clocks after the one before (L: the pixels of the tile-line two back), and
//! the last pixel is out `4 + L + 14` clocks after END (3 readout registers, 9 shading
//! stages, 2 through the output FIFO).

use pixelproc_sim::aa::{CornerParams, Filter, MultiscanParams, Pattern, PostFxParams};
use pixelproc_sim::hwcost::{method_cost, Frame, HwConfig};

fn cycles(m: &pixelproc_sim::aa::AaMethod) -> u64 {
    let frame = Frame {
        tris: &[],
        width: 16,
        height: 2,
    };
    method_cost(m, &frame, &HwConfig::new(8, 100.0).unwrap())
        .unwrap()
        .cycles
}

/// No AA: 2 rows × 2 tile-lines of 8. TILEs at 3, 4, 17, 30; END at 43; out at 43 + 26.
#[test]
fn plain_by_hand() {
    assert_eq!(cycles(&pixelproc_sim::aa::AaMethod::None), 69);
}

/// 2×2 supersampling: 2 sample rows of 32 per pixel row, 16 tile-lines of 8. TILE t ≥ 1
/// at 4 + 13(t − 1), so TILE 15 at 186, END at 199, out at 199 + 26 = 225.
#[test]
fn ssaa_by_hand() {
    assert_eq!(cycles(&pixelproc_sim::aa::AaMethod::Ssaa { k: 2 }), 225);
}

/// Multi-scanning, box, n = 2: 2 sub-scanlines per row and the bottom edge, 5 rows of 16,
/// 10 tile-lines: TILE 9 at 108, END at 121, out at 147.
#[test]
fn multiscan_box_by_hand() {
    let m = pixelproc_sim::aa::AaMethod::Multiscan(MultiscanParams::new(2, Filter::Box));
    assert_eq!(cycles(&m), 147);
}

/// Multi-scanning, Gaussian, n = 2: n·H + n − 1 = 5 sub-scanlines, the same as the box.
#[test]
fn multiscan_gauss_by_hand() {
    let m = pixelproc_sim::aa::AaMethod::Multiscan(MultiscanParams::new(2, Filter::Gauss));
    assert_eq!(cycles(&m), 147);
}

/// Corner sampling, 1 spp: per corner row 9 even corners (tile-lines of 8 and 1) and 8
/// odd ones (8); 3 corner rows: pixels per tile-line 8, 1, 8 three times. TILEs at 3, 4,
/// 17, 23, 36, 49, 55, 68, 81; END at 87; out at 87 + 4 + 8 + 14 = 113.
#[test]
fn corner_by_hand() {
    let m = pixelproc_sim::aa::AaMethod::Corner(CornerParams::new(Pattern::Corner, false));
    assert_eq!(cycles(&m), 113);
}

/// Post-process: the scan-out pass (16·2 + 2·16 = 64 clocks) and the array's 69 clocks
/// overlap, so the frame is 69.
#[test]
fn postfx_by_hand() {
    let m = pixelproc_sim::aa::AaMethod::PostFx(PostFxParams::default());
    assert_eq!(cycles(&m), 69);
}
