//! Stages 6 and 7 of the shading unit on integers: the rounding `(p >> 8) + p[7]` and the
//! clamp, subtraction and floor, step for step as the kernel computes them, with the
//! proofs (and exhaustive tests) that they equal the formula of
//! `pixelproc_formats::core_stream::shade_rgb`.

/// The rounding of stage 7: `(p + 128) >> 8`, as the kernel computes it, `(p >> 8) + p[7]`,
/// with no add before the shift (the product goes into a register straight from the
/// multiplier).
///
/// Why the two are equal for every `p ≥ 0`: write `p = 256·a + b` with `a = p >> 8` and
/// `0 ≤ b = p mod 256 < 256`, so `p[7] = 1` exactly when `b ≥ 128`. Then
/// `p + 128 = 256·a + (b + 128)` with `128 ≤ b + 128 < 384`, so
/// `(p + 128) >> 8 = a + ⌊(b + 128) / 256⌋`, and `⌊(b + 128) / 256⌋` is 1 when `b ≥ 128`
/// and 0 when `b < 128`: it is `p[7]`. (The tests also check it over every product the
/// unit can form.)
pub fn round_q8(p: u32) -> u32 {
    (p >> 8) + ((p >> 7) & 1)
}

/// Stage 7 of one channel on integers, step for step as the kernel does it, from the two
/// products `pf = c·F` and `pd = d·G` (each at most `255 · 511`, so each rounded value is
/// at most 509 and fits the kernel's 9 bits): `max(0, min(round(pf), 255) − round(pd))`.
pub fn stage5(pf: u32, pd: u32) -> u32 {
    stage5_rounded(round_q8(pf) & 0x1ff, round_q8(pd) & 0x1ff)
}

/// The part of [`stage5`] after the rounding, on the two 9-bit rounded values: when bit 8
/// of `lit` is set the clamp gives 255 and the result is `255 − drop = !drop[7:0]` for
/// `drop < 256`, else 0; otherwise the 10-bit difference `lit − drop`, 0 when negative.
fn stage5_rounded(lit: u32, drop: u32) -> u32 {
    let diff = lit.wrapping_sub(drop) & 0x3ff;
    if lit & 0x100 != 0 {
        if drop & 0x100 == 0 {
            !drop & 0xff
        } else {
            0
        }
    } else if diff & 0x200 == 0 {
        diff & 0xff
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::super::PROD_W;
    use super::*;
    use pixelproc_formats::core_stream::FACTOR_BITS;

    /// `(p >> 8) + p[7]` equals `(p + 128) >> 8` for every product the unit can form
    /// (`c·F` and `d·G`, 8-bit by 9-bit: `0 ..= 255 · 511`), and on to the top of the
    /// 18-bit product field.
    #[test]
    fn rounding_without_the_add_is_exact() {
        for p in 0..(1u32 << PROD_W) {
            assert_eq!(round_q8(p), (p + 128) >> 8, "p = {p}");
        }
        // Every product of a channel and a factor, as stage 4 forms it.
        for c in 0..=255u32 {
            for f in 0..(1u32 << FACTOR_BITS) {
                let p = c * f;
                assert!(p < 1 << PROD_W);
                assert_eq!(round_q8(p), (p + 128) >> 8, "c = {c}, f = {f}");
            }
        }
    }

    /// Stage 5's clamp, subtraction and floor without a multiplexer before the
    /// subtraction equal `max(0, min(lit, 255) − drop)` for every pair of 9-bit rounded
    /// values; with `rounding_without_the_add_is_exact` (and `round_q8(255 · 511) < 512`)
    /// this is `shade_rgb`'s channel for every product pair.
    #[test]
    fn stage5_is_the_formula() {
        assert!(round_q8(255 * ((1 << FACTOR_BITS) - 1)) < 512);
        for lit in 0..512u32 {
            for drop in 0..512u32 {
                assert_eq!(
                    stage5_rounded(lit, drop),
                    lit.min(255).saturating_sub(drop),
                    "lit = {lit}, drop = {drop}"
                );
            }
        }
        for c in (0..=255u32).step_by(5) {
            for f in (0..(1u32 << FACTOR_BITS)).step_by(7) {
                for (d, g) in [(0, 0), (c / 2, 511), (c, 256), (200, 77), (255, 511)] {
                    let want = ((c * f + 128) >> 8)
                        .min(255)
                        .saturating_sub((d * g + 128) >> 8);
                    assert_eq!(stage5(c * f, d * g), want);
                }
            }
        }
    }
}
