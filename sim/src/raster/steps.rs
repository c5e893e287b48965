//! Exact rounded quotients along arithmetic progressions, with additions only: a plane
//! (depth or colour) evaluated at successive pixels or rows, and an edge's column bound
//! on successive scanlines, without a division per step. Every value equals the direct
//! division ([`super::round_div`], [`super::floor_div`]) bit for bit; the span setup of
//! seed 001 section 3 and every method's planes step through these.

use super::floor_div_wide;

/// `⌊(n0 + k·dn) / d⌋` (`d > 0`) for `k = 0, 1, 2, …`, stepped with additions only: the
/// quotient and the remainder (`0 ≤ r < d`) move by the quotient and remainder of `dn`,
/// plus a carry when the remainder reaches `d`. A scanline's column bound on an edge
/// ([`crate::setup::ColumnSteps`]) without a division per row.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FloorSteps {
    q: i64,
    r: i64,
    dq: i64,
    dr: i64,
    d: i64,
}

impl FloorSteps {
    /// Starts at `k = 0` with the step `dn / d` prepared by [`FloorStep::new`]: one
    /// division (none when `d = 1`).
    #[inline]
    pub(crate) fn start(n0: i64, s: &FloorStep) -> FloorSteps {
        let q = if s.d == 1 { n0 } else { n0.div_euclid(s.d) };
        FloorSteps {
            q,
            r: n0 - q * s.d,
            dq: s.dq,
            dr: s.dr,
            d: s.d,
        }
    }

    /// The current value, `⌊(n0 + k·dn) / d⌋`.
    #[inline]
    pub(crate) fn value(&self) -> i64 {
        self.q
    }

    /// Moves to `k + 1`.
    #[inline]
    pub(crate) fn advance(&mut self) {
        // Without a branch: the carry is as likely as not on an edge's rows.
        let r = self.r + self.dr;
        let carry = (r >= self.d) as i64;
        self.q += self.dq + carry;
        self.r = r - carry * self.d;
    }
}

/// The step of a [`FloorSteps`], `dn / d` as a quotient and a remainder, prepared once
/// for steppers that start at many numerators (a triangle's edge, band after band).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FloorStep {
    dq: i64,
    dr: i64,
    d: i64,
}

impl FloorStep {
    /// The step `dn / d`, `d > 0`.
    #[inline]
    pub(crate) fn new(dn: i64, d: i64) -> FloorStep {
        debug_assert!(d > 0);
        let dq = dn.div_euclid(d);
        FloorStep {
            dq,
            dr: dn - dq * d,
            d,
        }
    }
}

/// `round_div(n0 + k·dn, d)` for `k = 0, 1, 2, …`, stepped with additions only: the exact
/// values of [`round_div`] along an arithmetic progression of numerators (a plane evaluated
/// at successive pixels), without a 128-bit division per step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoundDivSteps {
    q: i128,
    r: i128,
    dq: i128,
    dr: i128,
    den: i128,
}

impl RoundDivSteps {
    /// Starts at `k = 0`; `d ≠ 0`.
    #[cfg(test)]
    pub(crate) fn new(n0: i128, dn: i128, d: i128) -> RoundDivSteps {
        RoundDivSteps::start(n0, &RoundDivStep::new(dn, d))
    }

    /// Starts at `k = 0` with a step prepared by [`RoundDivStep::new`]: the same stepper as
    /// `RoundDivSteps::new(n0, dn, d)`, one division fewer.
    #[inline]
    pub(crate) fn start(n0: i128, s: &RoundDivStep) -> RoundDivSteps {
        let n0 = if s.neg { -n0 } else { n0 };
        let num = 2 * n0 + s.den / 2;
        let q = floor_div_wide(num, s.den);
        RoundDivSteps {
            q,
            r: num - q * s.den,
            dq: s.dq,
            dr: s.dr,
            den: s.den,
        }
    }

    /// The current value, `round_div(n0 + k·dn, d)`.
    #[inline]
    pub(crate) fn value(&self) -> i128 {
        self.q
    }

    /// Moves to `k + 1`.
    #[inline]
    pub(crate) fn advance(&mut self) {
        self.step(self.dq, self.dr);
    }

    /// Adds the quotient step `dq` and the remainder step `dr < den`, carrying once if
    /// the remainder reaches `den` (an advance, or a prepared jump).
    #[inline]
    fn step(&mut self, dq: i128, dr: i128) {
        // Without a branch: whether the remainder carries follows no pattern a predictor
        // learns.
        let r = self.r + dr;
        let carry = (r >= self.den) as i128;
        self.q += dq + carry;
        self.r = r - carry * self.den;
    }
}

impl RoundDivSteps {
    /// Bounds of the values after `k0..=k1` advances from here: an advance adds `dq` or
    /// `dq + 1` (the remainder carries at most once), so after `k` advances the value lies
    /// in `[q + k·dq, q + k·(dq + 1)]`, whose ends are linear in `k`.
    #[inline]
    pub(crate) fn bounds(&self, k0: u64, k1: u64) -> (i128, i128) {
        let (k0, k1) = (k0 as i128, k1 as i128);
        let lo = (k0 * self.dq).min(k1 * self.dq);
        let hi = (k0 * (self.dq + 1)).max(k1 * (self.dq + 1));
        (self.q + lo, self.q + hi)
    }

    /// The same stepper in 64-bit arithmetic, if `steps` advances from here cannot leave
    /// it: the remainder and its step stay below the denominator (`< 2^62`, so their sum
    /// fits), and the quotient moves by at most `|dq| + 1` per advance.
    #[inline]
    pub(crate) fn narrow(&self, steps: u64) -> Option<RoundDivSteps64> {
        // `|q| + (|dq| + 1)·(steps + 1) < 2^62`, in `u128` without overflow once `|q|` and
        // `|dq|` are below 2^62 (the sum is at least each of them).
        const LIM: u128 = 1 << 62;
        let (q, dq) = (self.q.unsigned_abs(), self.dq.unsigned_abs());
        let fits = self.den < LIM as i128
            && q < LIM
            && dq < LIM
            && (dq + 1) * (steps as u128 + 1) + q < LIM;
        fits.then_some(RoundDivSteps64 {
            q: self.q as i64,
            r: self.r as i64,
            dq: self.dq as i64,
            dr: self.dr as i64,
            den: self.den as i64,
        })
    }
}

/// A [`RoundDivSteps`] narrowed to 64 bits by [`RoundDivSteps::narrow`]: the same values
/// for as many advances as it was narrowed for.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoundDivSteps64 {
    q: i64,
    r: i64,
    dq: i64,
    dr: i64,
    den: i64,
}

impl RoundDivSteps64 {
    /// Adds the quotient step `dq` and the remainder step `dr < den`, carrying once if
    /// the remainder reaches `den` (an advance, or a prepared jump).
    #[inline]
    fn step(&mut self, dq: i64, dr: i64) {
        // Without a branch, as [`RoundDivSteps`]'s: a depth or colour plane's carry
        // follows no pattern a predictor learns.
        let r = self.r + dr;
        let carry = r >= self.den;
        self.q += dq + carry as i64;
        self.r = std::hint::select_unpredictable(carry, r - self.den, r);
    }

    /// Whether the current value and those of the next `steps` advances all lie in
    /// `lo..=hi` (a sufficient test: `false` can come for a run that stays inside). An
    /// advance adds `dq` or `dq + 1`, so after `k` advances the value lies in
    /// `[q + k·dq, q + k·(dq + 1)]`. `steps` at most what [`RoundDivSteps::narrow`] was
    /// given: it keeps `|q| + (|dq| + 1)·(steps + 1)` below 2^62, so these bounds fit
    /// 64 bits.
    #[inline]
    pub(crate) fn stays_within(&self, steps: u64, lo: i64, hi: i64) -> bool {
        debug_assert!(
            (self.q.unsigned_abs() as u128)
                + (self.dq.unsigned_abs() as u128 + 1) * (steps as u128 + 1)
                < 1 << 62
        );
        let k = steps as i64;
        self.q + k * self.dq.min(0) >= lo && self.q + k * (self.dq + 1).max(0) <= hi
    }
}

/// A stepper of exact rounded quotients ([`RoundDivSteps`] or its narrowed form).
pub(crate) trait PlaneStepper: Copy {
    /// The current value.
    fn value(&self) -> i128;
    /// Moves to the next numerator.
    fn advance(&mut self);
    /// A lower bound of the current value and those of the next `k` advances (an advance
    /// adds `dq` or `dq + 1`). For the narrowed form, `k` at most what it was narrowed
    /// for.
    fn lower(&self, k: u64) -> i128;
    /// `k` advances prepared as one ([`PlaneStepper::jump`]), for this stepper's step.
    type Jump: Copy;
    /// Prepares [`PlaneStepper::jump`] by `k` advances (one division, once per step).
    fn jump_by(&self, k: u64) -> Self::Jump;
    /// Moves on by the advances `j` was prepared for: the same state as that many
    /// [`PlaneStepper::advance`]s. For the narrowed form, within the advances it was
    /// narrowed for.
    fn jump(&mut self, j: &Self::Jump);
}

/// `k` advances of a stepper with step `dq + dr/den` as one: the quotient's step
/// `k·dq + ⌊k·dr / den⌋` and the remainder's `k·dr mod den` (`None` where `k·dr` does not
/// fit). From remainder `r < den`, `r + k·dr = (r + dr_k) + den·⌊k·dr / den⌋` with
/// `r + dr_k < 2·den`, so one more carry at most, as in an advance.
fn jump_steps(k: u64, dq: i128, dr: i128, den: i128) -> Option<(i128, i128)> {
    let total = dr.checked_mul(k as i128)?;
    Some(((k as i128).checked_mul(dq)? + total / den, total % den))
}

impl PlaneStepper for RoundDivSteps {
    #[inline]
    fn value(&self) -> i128 {
        RoundDivSteps::value(self)
    }
    #[inline]
    fn advance(&mut self) {
        RoundDivSteps::advance(self)
    }
    #[inline]
    fn lower(&self, k: u64) -> i128 {
        self.bounds(0, k).0
    }
    /// The jump's steps, or the number of advances to make one by one.
    type Jump = Result<(i128, i128), u64>;
    fn jump_by(&self, k: u64) -> Self::Jump {
        jump_steps(k, self.dq, self.dr, self.den).ok_or(k)
    }
    #[inline]
    fn jump(&mut self, j: &Self::Jump) {
        match *j {
            Ok((dq, dr)) => self.step(dq, dr),
            Err(k) => (0..k).for_each(|_| self.advance()),
        }
    }
}

impl PlaneStepper for RoundDivSteps64 {
    #[inline]
    fn value(&self) -> i128 {
        self.q as i128
    }
    #[inline]
    fn advance(&mut self) {
        self.step(self.dq, self.dr);
    }
    #[inline]
    fn lower(&self, k: u64) -> i128 {
        // Inside 64 bits: `|q| + (|dq| + 1)·(k + 1) < 2^62` for the `k` it was narrowed for.
        (self.q + k as i64 * self.dq.min(0)) as i128
    }
    /// The jump's steps: `dr < den < 2^62` and a jump the narrowing allows keep them
    /// inside 64 bits.
    type Jump = (i64, i64);
    fn jump_by(&self, k: u64) -> Self::Jump {
        let (dq, dr) = jump_steps(k, self.dq as i128, self.dr as i128, self.den as i128)
            .expect("64-bit steps times a block fit 128 bits");
        // `dr < den`; `dq` fits where the narrowing allows the `k` advances.
        let dq = i64::try_from(dq).expect("a jump beyond the narrowed stepper's range");
        (dq, dr as i64)
    }
    #[inline]
    fn jump(&mut self, &(dq, dr): &Self::Jump) {
        self.step(dq, dr);
    }
}

/// The step of a [`RoundDivSteps`] (`dn` over `d ≠ 0`), prepared once for steppers that
/// share it (one plane started on many rows).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoundDivStep {
    dq: i128,
    dr: i128,
    den: i128,
    neg: bool,
}

impl RoundDivStep {
    /// The step `dn / d`, `d ≠ 0`.
    pub(crate) fn new(dn: i128, d: i128) -> RoundDivStep {
        let neg = d < 0;
        let (dn, d) = if neg { (-dn, -d) } else { (dn, d) };
        let (den, step) = (2 * d, 2 * dn);
        let dq = floor_div_wide(step, den);
        RoundDivStep {
            dq,
            dr: step - dq * den,
            den,
            neg,
        }
    }

    /// A 64-bit stepper taking this step from quotient `q` and remainder `r`
    /// (`0 ≤ r < 2d`, the units of [`RoundDivSteps`]), if the step fits 64 bits
    /// (`d > 0`, `2d < 2^62`, so `r` plus the remainder step fits). The caller bounds how
    /// far the quotient goes.
    #[inline]
    pub(crate) fn narrow_from(&self, q: i64, r: i64) -> Option<RoundDivSteps64> {
        const LIM: i128 = 1 << 62;
        debug_assert!(0 <= r as i128 && (r as i128) < self.den);
        (!self.neg && self.den < LIM && self.dq.unsigned_abs() < LIM as u128).then_some(
            RoundDivSteps64 {
                q,
                r,
                dq: self.dq as i64,
                dr: self.dr as i64,
                den: self.den as i64,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::round_div;

    /// The 128-bit reference of [`round_div`].
    fn round_div_wide(n: i128, d: i128) -> i128 {
        let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
        (2 * n + d).div_euclid(2 * d)
    }

    /// [`RoundDivSteps::narrow`] takes a stepper exactly when `den < 2^62` and
    /// `|q| + (|dq| + 1)·(steps + 1) < 2^62` in exact arithmetic (written here with checked
    /// 128-bit operations, overflow meaning "too large"), and the narrowed stepper then
    /// gives the same values: quotients, steps and step counts at, just below and just
    /// above the limit, and far beyond it (up to ±2^126), with `steps` up to `u64::MAX`.
    #[test]
    fn narrowing_takes_exactly_the_steppers_that_fit() {
        const LIM: i128 = 1 << 62;
        let reference = |q: i128, dq: i128, den: i128, steps: u64| -> bool {
            let reach = || {
                (dq.checked_abs()? + 1)
                    .checked_mul(steps as i128 + 1)?
                    .checked_add(q.checked_abs()?)
            };
            den < LIM && reach().is_some_and(|r| r < LIM)
        };
        let mut rng = crate::rng::Lcg64(0x0060_b175);
        let edge = [
            0,
            1,
            LIM - 2,
            LIM - 1,
            LIM,
            LIM + 1,
            1 << 100,
            (1 << 126) - 1,
        ];
        let (mut taken, mut refused) = (0, 0);
        let lim = LIM as u64;
        // On the limit: the reach and the denominator at 2^62 − 1 (taken) and 2^62 (not).
        let exact = [
            (0, 0, 2, lim - 2, true),
            (0, 0, 2, lim - 1, false),
            (1, 0, 2, lim - 3, true),
            (1, 0, 2, lim - 2, false),
            (-(LIM - 3), 1, 2, 0, true),
            (LIM - 2, -1, 2, 0, false),
            (5, 0, LIM - 1, 10, true),
            (5, 0, LIM, 10, false),
        ];
        for (q, dq, den, steps, fits) in exact {
            let st = RoundDivSteps {
                q,
                r: 0,
                dq,
                dr: den - 1,
                den,
            };
            assert_eq!(
                reference(q, dq, den, steps),
                fits,
                "reference {q} {dq} {den}"
            );
            assert_eq!(st.narrow(steps).is_some(), fits, "q {q} dq {dq} den {den}");
        }
        for case in 0..40_000 {
            let mut pick = |spread: u32| -> i128 {
                let v = if rng.step().is_multiple_of(6) {
                    edge[(rng.step() % edge.len() as u64) as usize]
                } else {
                    ((rng.step() as i128) << 64 | rng.step() as i128) % (1i128 << spread)
                };
                if rng.step() & 1 == 0 {
                    -v
                } else {
                    v
                }
            };
            let spread = [8, 20, 30, 40, 61, 62, 63, 100][case % 8];
            let (q, dq) = (pick(spread), pick(spread));
            let den = pick(spread).abs().clamp(1, (1 << 126) - 1);
            let steps = match (case / 8) % 6 {
                0..=2 => rng.step() % 2000,
                3 => u64::MAX - rng.step() % 3,
                4 => (LIM as u64 / ((dq.unsigned_abs() as u64).max(1))).saturating_sub(1),
                _ => rng.step() >> (rng.step() % 64),
            };
            // A stepper with remainder 0 and step remainder below the denominator.
            let st = RoundDivSteps {
                q,
                r: 0,
                dq,
                dr: den - 1,
                den,
            };
            let want = reference(q, dq, den, steps);
            let got = st.narrow(steps);
            assert_eq!(got.is_some(), want, "q {q} dq {dq} den {den} steps {steps}");
            if let Some(mut n) = got {
                taken += 1;
                let mut w = st;
                for _ in 0..steps.min(50) {
                    assert_eq!(n.value(), w.value(), "{st:?}");
                    n.advance();
                    w.advance();
                }
            } else {
                refused += 1;
            }
        }
        assert!(
            taken > 8_000 && refused > 8_000,
            "{taken} taken, {refused} refused"
        );
    }

    /// [`RoundDivSteps::bounds`] holds every value the stepper takes over its range of
    /// advances, on random steppers of either sign and ranges starting anywhere in the
    /// first 30 advances.
    #[test]
    fn bounds_hold_every_value() {
        let mut rng = crate::rng::Lcg64(0x0b0d_5e7a);
        for _ in 0..20_000 {
            let mut draw = |m: i64| (rng.step() % (2 * m as u64 + 1)) as i64 - m;
            let d = draw(1 << 20) as i128;
            let d = if d == 0 { 7 } else { d };
            let st = RoundDivSteps::new(draw(1 << 40) as i128, draw(1 << 24) as i128, d);
            let (k0, k1) = (draw(30).unsigned_abs(), draw(30).unsigned_abs());
            let (k0, k1) = (k0.min(k1), k0.max(k1) + 1);
            let (lo, hi) = st.bounds(k0, k1);
            let mut s = st;
            for k in 0..=k1 {
                if k >= k0 {
                    assert!(
                        lo <= s.value() && s.value() <= hi,
                        "{st:?} {k0}..={k1} at {k}"
                    );
                }
                s.advance();
            }
        }
    }

    /// A prepared jump is the same state as as many advances, and `lower` bounds every
    /// value up to it from below: the 128-bit stepper (with denominators up to 2^124,
    /// where a jump of many advances no longer fits and falls back to advancing) and the
    /// narrowed one, denominators down to a few units (where a jump lands exactly on a
    /// carry), slopes of either sign, jumps of 1 to 64 advances made again and
    /// again.
    #[test]
    fn jumps_equal_advances_and_lower_bounds_them() {
        let mut rng = crate::rng::Lcg64(0x00ab_c0de);
        let (mut narrowed, mut fell_back) = (0, 0);
        for case in 0..20_000 {
            let bits = [3, 20, 40, 61, 90, 124][case % 6];
            let mut draw = |b: u32| {
                let v = ((rng.step() as i128) << 64 | rng.step() as i128) % (1i128 << b);
                if rng.step() & 1 == 0 {
                    -v
                } else {
                    v
                }
            };
            let d = draw(bits).abs().max(1);
            let (n0, dn) = (draw((bits + 6).min(125)), draw(bits));
            let k = 1 + case as u64 % 64;
            let st = RoundDivSteps::new(n0, dn, d);
            let j = st.jump_by(k);
            fell_back += j.is_err() as u32;
            let (mut a, mut b) = (st, st);
            for _ in 0..3 {
                let lo = a.lower(k);
                for _ in 0..k {
                    assert!(lo <= a.value(), "case {case}: {n0} + i·{dn} / {d}");
                    a.advance();
                }
                assert!(lo <= a.value());
                b.jump(&j);
                assert_eq!(
                    (b.q, b.r),
                    (a.q, a.r),
                    "case {case}: {n0} + i·{dn} / {d}, {k}"
                );
            }
            let Some(n) = st.narrow(3 * k) else { continue };
            narrowed += 1;
            let (mut a, mut b) = (n, n);
            let j = n.jump_by(k);
            for _ in 0..3 {
                let lo = a.lower(k);
                for _ in 0..k {
                    assert!(lo <= PlaneStepper::value(&a), "case {case}");
                    a.advance();
                }
                b.jump(&j);
                assert_eq!(
                    (b.q, b.r),
                    (a.q, a.r),
                    "case {case}: {n0} + i·{dn} / {d}, {k}"
                );
            }
        }
        assert!(
            narrowed > 5000 && fell_back > 100,
            "{narrowed} narrowed, {fell_back} fell back"
        );
    }

    /// `stays_within` is never wrong when it says yes: on random steppers (slopes of
    /// either sign, ranges the run starts in, leaves, or touches), every value of the run
    /// lies in the range when it says so; and it says so for most runs that stay well
    /// inside.
    #[test]
    fn stays_within_is_sound() {
        let mut rng = crate::rng::Lcg64(0x57a9_5011);
        let (mut yes, mut inside) = (0, 0);
        for _ in 0..20_000 {
            let mut draw = |m: i64| (rng.step() % (2 * m as u64 + 1)) as i64 - m;
            let d = draw(1 << 20).abs().max(1) as i128;
            let dn = draw(1 << 24) as i128;
            let n0 = draw(1 << 40) as i128;
            let steps = (draw(60).abs() + 1) as u64;
            let Some(mut st) = RoundDivSteps::new(n0, dn, d).narrow(steps) else {
                continue;
            };
            let v0 = PlaneStepper::value(&st) as i64;
            // A range around the start: sometimes generous, sometimes tight.
            let (lo, hi) = (v0 - draw(1 << 12).abs(), v0 + draw(1 << 12).abs());
            let say = st.stays_within(steps, lo, hi);
            let mut all = true;
            for k in 0..=steps as i128 {
                let v = PlaneStepper::value(&st) as i64;
                assert_eq!(v as i128, round_div_wide(n0 + k * dn, d));
                all &= lo <= v && v <= hi;
                st.advance();
            }
            assert!(
                !say || all,
                "{n0} + k·{dn} / {d}, {steps} steps, {lo}..={hi}"
            );
            yes += say as u32;
            inside += all as u32;
        }
        assert!(
            yes > 2000 && inside > yes,
            "{yes} said inside, {inside} inside"
        );
    }

    #[test]
    fn round_div_fast_path_and_steps_match_the_wide_division() {
        let mut rng = crate::rng::Lcg64(0x1234_5678);
        let mut narrowed = 0;
        for k in 0..20_000 {
            // Magnitudes on both sides of the 64-bit fast path's limit.
            let bits = [8, 40, 60, 62, 90][k % 5];
            let mut draw = |b: u32| {
                let v = (rng.step() as i128) << 64 | rng.step() as i128;
                let v = v % (1i128 << b);
                if rng.step() & 1 == 0 {
                    -v
                } else {
                    v
                }
            };
            let (n0, dn, mut d) = (draw(bits), draw(bits.min(60)), draw(bits));
            if d == 0 {
                d = 7;
            }
            assert_eq!(round_div(n0, d), round_div_wide(n0, d), "{n0} / {d}");
            let mut st = RoundDivSteps::new(n0, dn, d);
            let mut st2 = RoundDivSteps::start(n0, &RoundDivStep::new(dn, d));
            // Narrowed for the 8 values checked (7 advances); where it narrows, it must
            // give the same values.
            let mut st3 = st.narrow(7);
            narrowed += st3.is_some() as u32;
            for i in 0..8 {
                if let Some(s3) = &mut st3 {
                    assert_eq!(
                        PlaneStepper::value(s3),
                        round_div_wide(n0 + i * dn, d),
                        "narrowed, {n0} + {i}·{dn} / {d}"
                    );
                    s3.advance();
                }
                assert_eq!(
                    st.value(),
                    round_div_wide(n0 + i * dn, d),
                    "{n0} + {i}·{dn} / {d}"
                );
                assert_eq!(
                    st2.value(),
                    st.value(),
                    "prepared step, {n0} + {i}·{dn} / {d}"
                );
                st.advance();
                st2.advance();
            }
        }
        // The 8- and 40-bit draws (and some 60-bit ones) narrow; the 62- and 90-bit ones
        // must not.
        assert!((8_000..16_000).contains(&narrowed), "{narrowed}");
    }
}
