//! The search unit against an independent brute-force statement of the first hit.
//!
//! Statement (seed 000, claim 1, written here without the unit's tables): number the
//! subpixels of an n×m pixel by column c (0 left) and row r (0 top), bit = n·r + (n−1−c)
//! (the seed's 4×4 order: 4·row + 3 − column). From a start corner measure c', r' (distance
//! in subpixels from the corner's column and row). Line k of family (p, q) is every subpixel
//! with p·c' + q·r' = k. The first hit is the smallest k holding a covered subpixel; the
//! search takes k + 1 steps; the AND result is the covered subpixels of that line; end 1 is
//! the one lowest on screen (largest row, then smallest column), end 2 the one highest
//! (smallest row, then largest column); each is reported as its centre's offset from the
//! pixel centre in units of 1/(2n), 1/(2m) px: (2c + 1 − n, 2r + 1 − m).

use pixelproc_formats::abuffer::{Corner, MaskSize, SearchFamily, SubOffset};
use pixelproc_sim::mask_search::{SearchTables, SearchUnit};
use pixelproc_sim::rng::XorShift64Star;

/// (AND result, end 1, end 2), ends as offsets in half-subpixel units.
type Hit = (u64, (i32, i32), (i32, i32));

struct Brute {
    steps: u32,
    lines: Vec<u64>, // search mask of each step taken
    hit: Option<Hit>,
}

fn brute(n: i32, m: i32, p: i32, q: i32, mask: u64, right: bool, bottom: bool) -> Brute {
    let kmax = p * (n - 1) + q * (m - 1);
    let mut lines = Vec::new();
    for k in 0..=kmax {
        let mut line = 0u64;
        let mut pts = Vec::new();
        for r in 0..m {
            for c in 0..n {
                let cd = if right { n - 1 - c } else { c };
                let rd = if bottom { m - 1 - r } else { r };
                if p * cd + q * rd == k {
                    let bit = 1u64 << (n * r + (n - 1 - c));
                    line |= bit;
                    if mask & bit != 0 {
                        pts.push((c, r, bit));
                    }
                }
            }
        }
        lines.push(line);
        if !pts.is_empty() {
            let and: u64 = pts.iter().map(|t| t.2).fold(0, |a, b| a | b);
            let low = pts.iter().max_by_key(|t| (t.1, -t.0)).unwrap();
            let high = pts.iter().min_by_key(|t| (t.1, -t.0)).unwrap();
            let off = |t: &(i32, i32, u64)| (2 * t.0 + 1 - n, 2 * t.1 + 1 - m);
            return Brute {
                steps: k as u32 + 1,
                lines,
                hit: Some((and, off(low), off(high))),
            };
        }
    }
    Brute {
        steps: kmax as u32 + 1,
        lines,
        hit: None,
    }
}

fn o(x: SubOffset) -> (i32, i32) {
    (x.dx as i32, x.dy as i32)
}

/// Checks one search step by step against the statement.
fn check(t: &SearchTables, unit: &mut SearchUnit, mask: u64, corner: Corner) {
    let s = t.size();
    let f = t.family();
    let b = brute(
        s.n() as i32,
        s.m() as i32,
        f.p as i32,
        f.q as i32,
        mask,
        corner.right(),
        corner.bottom(),
    );
    unit.start(mask, corner);
    for k in 0..b.steps {
        let out = unit.step();
        assert!(out.active);
        assert_eq!(out.line, k);
        assert_eq!(
            out.search_mask, b.lines[k as usize],
            "mask {mask:x} {corner:?} line {k}"
        );
        assert_eq!(out.and_result, mask & b.lines[k as usize]);
        let last = k + 1 == b.steps;
        match (&b.hit, last) {
            (Some((and, e1, e2)), true) => {
                assert!(out.hit && out.done && !out.zero && !out.moved);
                assert_eq!(out.and_result, *and);
                let w = t.offset_rom(out.and_result);
                assert_eq!(
                    (o(w.end1), o(w.end2)),
                    (*e1, *e2),
                    "mask {mask:x} {corner:?}"
                );
                assert_eq!(w.pair, e1 != e2);
            }
            (None, true) => assert!(out.zero && out.done && !out.hit && !out.moved),
            (_, false) => assert!(out.zero && out.moved && !out.done && !out.hit),
        }
    }
    assert!(!unit.step().active, "unit must be idle after the search");
}

#[test]
fn every_4x4_mask_from_every_corner() {
    let t = SearchTables::new(MaskSize::S4X4, SearchFamily::DIAGONAL);
    let mut unit = SearchUnit::new(&t);
    let mut hits = 0u32;
    for mask in 0..=0xFFFFu64 {
        for corner in Corner::ALL {
            check(&t, &mut unit, mask, corner);
            hits += (mask != 0) as u32;
        }
    }
    assert_eq!(hits, 65535 * 4);
}

#[test]
fn seed_vectors_through_the_statement() {
    // The statement itself reproduces the seed's Tables 1 and 2 (units of 1/8 px).
    let b = brute(4, 4, 1, 1, 0x0842, false, false);
    assert_eq!(b.hit, Some((0x0842, (-3, 1), (1, -3))));
    let b = brute(4, 4, 1, 1, 0x0100, true, true);
    assert_eq!(b.hit.map(|h| (h.0, h.1)), Some((0x0100, (3, 1))));
}

#[test]
fn random_8x8_masks_every_family() {
    let mut rng = XorShift64Star(0x9E37_79B9_7F4A_7C15);
    let fams = [(1, 1), (1, 0), (0, 1), (2, 1), (1, 2)];
    for (p, q) in fams {
        let t = SearchTables::new(MaskSize::S8X8, SearchFamily { p, q });
        let mut unit = SearchUnit::new(&t);
        for k in 0..20_000 {
            // Vary density: AND of 0..3 random words keeps sparse masks common.
            let mut mask = rng.next_u64();
            for _ in 0..k % 4 {
                mask &= rng.next_u64();
            }
            if k % 7 == 0 {
                mask &= rng.next_u64() & rng.next_u64() & rng.next_u64();
            }
            check(&t, &mut unit, mask, Corner::from_code(k as u8));
        }
    }
}

#[test]
fn other_sizes_and_families() {
    let mut rng = XorShift64Star(12345);
    for (n, m) in [(4, 2), (2, 4), (3, 5), (8, 4), (1, 1), (5, 3)] {
        let size = MaskSize::new(n, m).unwrap();
        for (p, q) in [(1, 1), (1, 0), (0, 1), (2, 1), (1, 2)] {
            let t = SearchTables::new(size, SearchFamily { p, q });
            let mut unit = SearchUnit::new(&t);
            for k in 0..2_000 {
                let mask = rng.next_u64() & rng.next_u64() & size.full();
                check(&t, &mut unit, mask, Corner::from_code(k as u8));
            }
        }
    }
}
