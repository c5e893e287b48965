//! The depth-test rule of the pixel-processor array (seed 001, section 3, "scanline
//! Z-buffer"; decals after seed 001's pattern handling): a new value `Z` replaces the
//! stored `ZB` when `Z < ZB`, or `Z ≤ ZB` for a decal (pattern) span, so that among
//! ordinary surfaces the earlier in scene order wins a tie and a decal wins a tie against
//! its host face (and a later decal against an earlier one).
//!
//! Every point-sampled consumer (the array, the visibility probe, the post-process draw
//! buffers, the lattice sampler) calls [`passes`]. Methods that order surfaces instead of
//! testing them in draw order (multi-scanning's walk, the A-buffer's packing) use
//! [`tie_front`], the order-free form of the same rule.

/// The array's depth test: does a value `z` of a span (a decal span if `decal`) replace
/// the stored `zb`?
#[inline]
pub fn passes<T: PartialOrd>(z: T, zb: T, decal: bool) -> bool {
    if decal {
        z <= zb
    } else {
        z < zb
    }
}

/// At equal depth, is surface `a` in front of surface `b`? Each is `(decal, scene index)`.
/// The outcome of [`passes`] for the two drawn in scene order: a decal beats a non-decal,
/// the later of two decals wins, the earlier of two non-decals.
#[inline]
pub fn tie_front(a: (bool, i64), b: (bool, i64)) -> bool {
    match (a.0, b.0) {
        (true, false) => true,
        (false, true) => false,
        (true, true) => a.1 > b.1,
        (false, false) => a.1 < b.1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tie_front_is_passes_in_draw_order() {
        for ad in [false, true] {
            for bd in [false, true] {
                for (ai, bi) in [(0i64, 1i64), (1, 0)] {
                    // At equal depth the later-drawn surface replaces the earlier one
                    // exactly when it passes the test.
                    let later_wins = passes(5, 5, if ai > bi { ad } else { bd });
                    let a_front = later_wins == (ai > bi);
                    assert_eq!(tie_front((ad, ai), (bd, bi)), a_front, "{ad} {bd} {ai}");
                }
            }
        }
    }
}
