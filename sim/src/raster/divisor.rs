//! Floor division by a divisor fixed in advance, by one multiplication: the quotient of
//! `i64::div_euclid` for every `i64` numerator, without the hardware divide.
//!
//! The golden model divides by the same denominator many times (a triangle's plane
//! denominator at every depth and colour it evaluates), and a 64-bit `idiv` costs several
//! times a multiply. [`FloorDivisor`] prepares the divisor once (one 128-bit division) and
//! then divides with a 64 × 64 → 128-bit multiply and a shift.
//!
//! **Method** (Granlund and Montgomery, "Division by invariant integers using
//! multiplication", PLDI 1994, theorem 4.2). For `N`-bit unsigned numerators and a divisor
//! `1 ≤ d`, let `ℓ = ⌈log2 d⌉` and `m = ⌊2^(N+ℓ) / d⌋ + 1`. Then
//! `2^(N+ℓ) < m·d ≤ 2^(N+ℓ) + d ≤ 2^(N+ℓ) + 2^ℓ`, and the theorem gives
//! `⌊n / d⌋ = ⌊m·n / 2^(N+ℓ)⌋` for every `0 ≤ n < 2^N`. Here `N = 63` and `d < 2^63`:
//! since `d > 2^(ℓ−1)` (or `d = 1`, `ℓ = 0`), `2^(63+ℓ) / d < 2^64`, and an integer
//! below `2^64` that is at least `2^64 − 1` would need `d ≤ 2^(ℓ−1)`; so `m ≤ 2^64 − 1`
//! fits a `u64`, and `m·n < 2^127`.
//!
//! **Signed numerators.** For `n < 0`, `!n = −n − 1` lies in `[0, 2^63)`, and with
//! `!n = q'·d + r'` (`0 ≤ r' < d`), `n = (−q' − 1)·d + (d − 1 − r')`, whose remainder is
//! in `[0, d)`: `⌊n / d⌋ = −q' − 1 = !q'`. With `s = n >> 63` (all ones for a negative
//! `n`, else 0) both cases are `s ^ ⌊(n ^ s) / d⌋`, without a branch.

use std::num::NonZeroU8;

/// A positive divisor below `2^63`, prepared for [`FloorDivisor::floor`].
///
/// The quotient is taken from the high half of the product only: for `d ≥ 2` (`ℓ ≥ 1`)
/// `⌊m·n / 2^(63+ℓ)⌋ = ⌊⌊m·n / 2^64⌋ / 2^(ℓ−1)⌋`. For `d = 1` (`ℓ = 0`, `m = 2^63 + 1`
/// does not leave the high half alone) the numerator is doubled first and `m = 2^63`:
/// `⌊2n·2^63 / 2^64⌋ = n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct FloorDivisor {
    /// The multiplier `m = ⌊2^(63+ℓ) / d⌋ + 1` (`2^63` for `d = 1`).
    m: u64,
    /// The shift of the numerator before the multiply, `0` (`d ≥ 2`) or `1` (`d = 1`),
    /// plus 64 (a shift count is taken modulo 64; never 0, so an `Option<FloorDivisor>`
    /// takes no more room).
    pre: NonZeroU8,
    /// The shift of the product's high half, `ℓ − 1` (`0` for `d = 1`).
    post: u8,
}

impl FloorDivisor {
    /// The divisor `d`, or `None` unless `0 < d < 2^63`.
    pub(crate) fn new(d: i128) -> Option<FloorDivisor> {
        if d <= 0 || d >= 1 << 63 {
            return None;
        }
        if d == 1 {
            return Some(FloorDivisor {
                m: 1 << 63,
                pre: NonZeroU8::new(64 + 1)?,
                post: 0,
            });
        }
        let d = d as u128;
        // ℓ = ⌈log2 d⌉ ≥ 1.
        let l = 128 - (d - 1).leading_zeros();
        let m = (1u128 << (63 + l)) / d + 1;
        Some(FloorDivisor {
            m: u64::try_from(m).ok()?,
            pre: NonZeroU8::new(64)?,
            post: (l - 1) as u8,
        })
    }

    /// `⌊n / d⌋`, the same as `n.div_euclid(d)`, for every `n`.
    #[inline(always)]
    pub(crate) fn floor(&self, n: i64) -> i64 {
        let s = n >> 63;
        let u = ((n ^ s) as u64).wrapping_shl(self.pre.get() as u32);
        let q = (((u as u128 * self.m as u128) >> 64) as u64) >> self.post;
        s ^ q as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Lcg64;

    fn check(d: i64, n: i64) {
        let fd = FloorDivisor::new(d as i128).unwrap();
        assert_eq!(fd.floor(n), n.div_euclid(d), "{n} / {d}");
    }

    /// Against `div_euclid`: every small divisor with numerators around 0, around its
    /// multiples and at the ends of `i64`; divisors at and beside every power of two and
    /// at the top of the range; random divisors of every size with random numerators.
    #[test]
    fn floor_equals_div_euclid() {
        let ends = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
        for d in 1..=300i64 {
            for n in -1000..=1000 {
                check(d, n);
            }
            for &n in &ends {
                check(d, n);
            }
        }
        let mut ds = vec![i64::MAX, i64::MAX - 1, (1i64 << 62) + 1];
        for b in 1..63 {
            ds.extend([(1i64 << b) - 1, 1i64 << b, (1i64 << b) + 1]);
        }
        let mut rng = Lcg64(0xf100_2d17);
        for b in 1..=63u32 {
            for _ in 0..20 {
                ds.push(((rng.step() >> (64 - b)) as i64).max(1));
            }
        }
        for &d in &ds {
            for &n in &ends {
                check(d, n);
            }
            for k in [-3i64, -2, -1, 0, 1, 2, 3, i64::MAX / d, -(i64::MAX / d)] {
                for e in [-1i64, 0, 1] {
                    if let Some(n) = k.checked_mul(d).and_then(|v| v.checked_add(e)) {
                        check(d, n);
                    }
                }
            }
            for _ in 0..200 {
                check(d, rng.step() as i64);
                check(d, (rng.step() as i64) >> (rng.step() % 64));
            }
        }
    }

    #[test]
    fn refuses_divisors_out_of_range() {
        assert_eq!(std::mem::size_of::<Option<FloorDivisor>>(), 16);
        assert_eq!(FloorDivisor::new(0), None);
        assert_eq!(FloorDivisor::new(-5), None);
        assert_eq!(FloorDivisor::new(1 << 63), None);
        assert!(FloorDivisor::new((1 << 63) - 1).is_some());
    }
}
