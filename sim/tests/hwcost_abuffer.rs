//! The A-buffer's hardware model (`hwcost::abuffer`) against the golden search unit
//! (`mask_search::SearchUnit`, the RTL's step-for-step twin): clocks per search on every
//! 4×4 mask and corner and on random 8×8 masks, by hand on small cases, and a whole
//! frame's searches against the unit's own step counters and the renderer's statistics.

use pixelproc_formats::abuffer::{Corner, MaskSize, SearchFamily};
use pixelproc_sim::abuffer::{render_abuffer, search_stream, AbufferParams};
use pixelproc_sim::hwcost::abuffer::{
    diagonal_steps, lines, search_cycles, search_cycles_of_totals, SearchKind, BACK_LATENCY,
};
use pixelproc_sim::mask_search::{DepthSelect, SearchTables, SearchUnit};
use pixelproc_sim::rng::XorShift64Star;

const CORNERS: [Corner; 4] = [
    Corner::TopLeft,
    Corner::TopRight,
    Corner::BottomLeft,
    Corner::BottomRight,
];

#[test]
fn steps_per_search_equal_the_search_unit_on_every_4x4_mask() {
    let t = SearchTables::new(MaskSize::S4X4, SearchFamily::DIAGONAL);
    let mut unit = SearchUnit::new(&t);
    for mask in 0..=0xFFFFu64 {
        for c in CORNERS {
            let want = unit.run(mask, c).steps;
            assert_eq!(
                diagonal_steps(MaskSize::S4X4, mask, c),
                want,
                "{mask:#06x} {c:?}"
            );
        }
    }
}

#[test]
fn steps_per_search_equal_the_search_unit_on_random_8x8_masks() {
    let t = SearchTables::new(MaskSize::S8X8, SearchFamily::DIAGONAL);
    let mut unit = SearchUnit::new(&t);
    let mut rng = XorShift64Star(0x5EED);
    for k in 0..20_000 {
        // Sparse masks too, so that late hits and empty masks occur.
        let r = rng.next_u64();
        let mask = if k % 3 == 0 {
            r & rng.next_u64() & rng.next_u64()
        } else {
            r
        };
        for c in CORNERS {
            let want = unit.run(mask, c).steps;
            assert_eq!(
                diagonal_steps(MaskSize::S8X8, mask, c),
                want,
                "{mask:#018x} {c:?}"
            );
        }
    }
}

/// Hand-counted (bit index = 4·row + (3 − column), seed 000's worked example): the full
/// mask hits on line 0 from any corner (1 clock); `0x0001` is (column 3, row 0), the
/// top-right subpixel: 1 clock from the top-right corner, 4 from the top-left (lines
/// 0..=3), 7 from the bottom-left; the empty mask tests all 7 lines; the seed's `0842H`
/// (one anti-diagonal, c + r = 2 from the top-left) hits on line 2: 3 clocks.
#[test]
fn steps_by_hand() {
    let s = MaskSize::S4X4;
    assert_eq!(lines(s), 7);
    assert_eq!(lines(MaskSize::S8X8), 15);
    assert_eq!(diagonal_steps(s, 0xFFFF, Corner::BottomRight), 1);
    assert_eq!(diagonal_steps(s, 0x0001, Corner::TopRight), 1);
    assert_eq!(diagonal_steps(s, 0x0001, Corner::TopLeft), 4);
    assert_eq!(diagonal_steps(s, 0x0001, Corner::BottomLeft), 7);
    assert_eq!(diagonal_steps(s, 0, Corner::TopLeft), 7);
    assert_eq!(diagonal_steps(s, 0x0842, Corner::TopLeft), 3);
    // Iterative: searches back to back, the last result BACK_LATENCY after its last step.
    // 1 input register + 5 ROM stages + 6 depth stages (`docs/rtl_mask_search.md`).
    assert_eq!(BACK_LATENCY, 12);
    assert_eq!(search_cycles(SearchKind::Iterative, [1, 4, 7], 7), 12 + 12);
    // Pipelined: one per clock, the last of three accepted on the third clock, its result on
    // the 7 + 12 = 19th clock counting that one (`docs/rtl_mask_search.md`).
    assert_eq!(search_cycles(SearchKind::Pipelined, [1], 7), 19);
    assert_eq!(search_cycles(SearchKind::Pipelined, [1], 15), 27);
    assert_eq!(search_cycles(SearchKind::Pipelined, [1, 4, 7], 7), 21);
    assert_eq!(search_cycles(SearchKind::Iterative, [], 7), 0);
}

/// A whole frame: the model's clocks per search over every search the renderer runs equal
/// the search unit's own step counts, and their sum is the renderer's `search_steps`.
#[test]
fn a_frames_searches_match_the_unit_and_the_renderer() {
    let mut ls = pixelproc_sim::scene::load_builtin("default").unwrap();
    ls.scene.width = 160;
    ls.scene.height = 90;
    let proj = pixelproc_sim::frontend::project(&ls).unwrap();
    let tris = proj.array_tris();
    for (size, inter) in [(MaskSize::S4X4, false), (MaskSize::S8X8, true)] {
        let reqs = search_stream(&tris, 160, 90, size, inter).unwrap();
        assert!(reqs.len() > 100, "{} searches", reqs.len());
        let t = SearchTables::new(size, SearchFamily::DIAGONAL);
        let mut unit = SearchUnit::new(&t);
        let unit_steps: Vec<u32> = reqs
            .iter()
            .map(|r| unit.run(r.mask, r.corner).steps)
            .collect();
        let model_steps: Vec<u32> = reqs
            .iter()
            .map(|r| diagonal_steps(size, r.mask, r.corner))
            .collect();
        assert_eq!(model_steps, unit_steps);
        let p = AbufferParams {
            size,
            depth: DepthSelect::Search,
            interpenetrating: inter,
            compare_variants: false,
        };
        let st = render_abuffer(&tris, 160, 90, [0, 0, 0], &p).unwrap().stats;
        let total: u64 = unit_steps.iter().map(|&s| s as u64).sum();
        assert_eq!(st.search_steps, total);
        assert_eq!(st.sorted_fragments * (1 + inter as u64), reqs.len() as u64);
        for kind in [SearchKind::Iterative, SearchKind::Pipelined] {
            assert_eq!(
                search_cycles_of_totals(kind, reqs.len() as u64, st.search_steps, lines(size)),
                search_cycles(kind, model_steps.iter().copied(), lines(size)),
            );
        }
    }
}

/// The A-buffer's frame by hand on a 4×2 screen: a far triangle over everything and a near
/// one over x < 2.75 (constant depths, different planes: no merge). Fragments: 8 far + 6
/// near = 14; pixels 0..=2 of each row hold two, so 12 searches, each hitting on line 0
/// (every mask holds the top-left subpixel: full masks, and the near one's columns 0..=2
/// at x = 2.125..2.625). Iterative: 12 clocks + 12 = 24; pipelined: 11 + 7 + 12 = 30;
/// both above the 14 fragments and 8 pixels. `center` searches nothing: 14.
#[test]
fn a_small_frame_by_hand() {
    use pixelproc_sim::hwcost::abuffer::cost;
    use pixelproc_sim::hwcost::{Frame, HwConfig};
    use pixelproc_sim::setup::SnappedTri;
    let tri = |v: [[f64; 2]; 3], z: u32| SnappedTri {
        v: v.map(|p| [(p[0] * 256.0) as i32, (p[1] * 256.0) as i32]),
        z: [z; 3],
        c: [[(100 << 12) + 2048; 3]; 3],
        ..Default::default()
    };
    let tris = vec![
        tri([[-1.0, -1.0], [12.0, -1.0], [-1.0, 12.0]], 5000),
        tri([[2.75, -10.0], [2.75, 10.0], [-20.0, 0.0]], 1000),
    ];
    let frame = Frame {
        tris: &tris,
        width: 4,
        height: 2,
    };
    let cfg = HwConfig::DEFAULT;
    let p = |depth| AbufferParams {
        size: MaskSize::S4X4,
        depth,
        interpenetrating: false,
        compare_variants: false,
    };
    let c = |depth, kind| cost(&frame, &cfg, &p(depth), kind).unwrap();
    let it = c(DepthSelect::Search, SearchKind::Iterative);
    assert_eq!((it.samples, it.cycles), (14, 24));
    assert_eq!(c(DepthSelect::Search, SearchKind::Pipelined).cycles, 30);
    assert_eq!(c(DepthSelect::Center, SearchKind::Pipelined).cycles, 14);
}
