//! The colour of multi-scanning's visible pieces (seed 002, Nishita & Nakamae, §3: each
//! visible piece of a pixel takes the Gouraud intensity at its midpoint, Q8.12, exact
//! rational rounded half up; the background piece the background colour): per sub-scanline
//! a shaded triangle's colour planes in 64-bit form where they fit ([`ColourRow`]), a
//! piece's whole pixels stepped one pixel at a time, and the 128-bit planes where nothing
//! narrower fits (see the module header of [`super`]).

use super::spans::RowPlane;
use super::walk::{Active, Piece};
use super::{COLOUR_MAX, ONE16};
use crate::raster::divisor::FloorDivisor;
use crate::raster::{floor_div_wide, PlaneStepper, RoundDivStep, RoundDivSteps, RoundDivSteps64};

/// Colours of one piece's parts, left to right: the background, or the polygon's colour
/// at the middle of the part, Q8.12. Parts one pixel wide in a row (the inside of a long
/// piece) have middles one pixel apart, whose colours are stepped with additions.
pub(super) struct PieceColour<'a, 't> {
    src: ColourSource<'a, 't>,
    ynum: i64,
    /// Steppers at the middle `mid`, when set up.
    steps: Option<(ColourSteps, i64)>,
}

/// The three colour planes stepped one pixel at a time along a piece, in 64-bit
/// arithmetic where [`RoundDivSteps::narrow`] proves the steps fit.
enum ColourSteps {
    Wide([RoundDivSteps; 3]),
    Narrow([RoundDivSteps64; 3]),
}

impl ColourSteps {
    /// The current values; then moves one pixel on.
    #[inline]
    fn next(&mut self) -> [i128; 3] {
        fn take<S: PlaneStepper>(st: &mut [S; 3]) -> [i128; 3] {
            let v = st.map(|s| s.value());
            st.iter_mut().for_each(|s| s.advance());
            v
        }
        match self {
            ColourSteps::Wide(st) => take(st),
            ColourSteps::Narrow(st) => take(st),
        }
    }
}

/// Adds `w` times the colours of whole pixels, stepped from `st`, to the sums `dst` (one
/// pixel each); clamped to the range a piece takes when `CLAMP`, which the caller may
/// leave out where it has shown every value inside it.
#[inline]
fn add_stepped<S: PlaneStepper, const CLAMP: bool>(st: &mut [S; 3], dst: &mut [[u64; 3]], w: i64) {
    for sum in dst {
        for (acc, s) in sum.iter_mut().zip(st.iter_mut()) {
            let mut v = s.value() as i64;
            if CLAMP {
                v = v.clamp(0, COLOUR_MAX);
            }
            s.advance();
            *acc += (w * v) as u64;
        }
    }
}

/// Adds `w` times colour `c` to each of the sums `dst`.
#[inline]
fn add_fixed(dst: &mut [[u64; 3]], w: i64, c: [i64; 3]) {
    let wc = c.map(|v| (w * v) as u64);
    for sum in dst {
        for (acc, v) in sum.iter_mut().zip(wc) {
            *acc += v;
        }
    }
}

/// A colour clamped to the range a piece takes (`0..=COLOUR_MAX` per channel).
#[inline]
fn clamp_colour(mut c: [i64; 3]) -> [i64; 3] {
    for v in &mut c {
        *v = (*v).clamp(0, COLOUR_MAX);
    }
    c
}

/// Where a piece's colours come from.
enum ColourSource<'a, 't> {
    /// The same colour for every part: the background, or a flat triangle's colour.
    Fixed([i64; 3]),
    /// A shaded triangle whose colour planes on the line fit the 64-bit form, with the
    /// triangle's steps by one pixel.
    Row(&'a ColourRow, &'t [RoundDivStep; 3]),
    /// A shaded triangle whose colour planes on the line do not fit 64 bits.
    Wide(&'a Active<'t>),
}

/// A shaded triangle's colour planes on one sub-scanline in 64-bit arithmetic, from one
/// reference point `x0`: `at(x) = q + ⌊(r + 2s·(x − x0)) / 2d⌋` per channel, which is
/// [`RowPlane::at`]`(x, 0) = ⌊(2(k + s·x) + d) / 2d⌋` split at `x0` (`q`, `r` the
/// quotient and remainder there). Set up only when every value stays below 2^62 for `x`
/// in the triangle's interval on the line.
#[derive(Clone, Copy, Debug)]
pub(super) struct ColourRow {
    x0: i64,
    q: [i64; 3],
    r: [i64; 3],
    s2: [i64; 3],
    d2: [i64; 3],
    /// `d2` prepared for division by multiplication.
    div: [FloorDivisor; 3],
}

impl ColourRow {
    /// The planes `c` for `x` in `[x0, x1]`, if they fit. (Once per triangle and line:
    /// out of line, so that [`PieceColour::new`] stays small.)
    #[inline(never)]
    fn new(c: &[RowPlane; 3], x0: i64, x1: i64) -> Option<ColourRow> {
        const LIM: i128 = 1 << 62;
        // Bounds under which no product or sum below leaves `i128` (|x| < 2^40,
        // |s| < 2^61, |k| < 2^120), tested with compares instead of checked arithmetic;
        // a plane beyond them fails the 2^62 tests anyway, or takes the 128-bit form.
        if x0.unsigned_abs().max(x1.unsigned_abs()) >= 1 << 40 {
            return None;
        }
        let span = (x1 - x0) as i128;
        let mut out = ColourRow {
            x0,
            q: [0; 3],
            r: [0; 3],
            s2: [0; 3],
            d2: [0; 3],
            div: [c[0].div?.1, c[1].div?.1, c[2].div?.1],
        };
        for (ch, p) in c.iter().enumerate() {
            let d2 = 2 * p.d;
            let s2 = 2 * p.s;
            if p.d <= 0
                || d2 >= LIM
                || p.s.unsigned_abs() >= 1 << 61
                || p.k.unsigned_abs() >= 1 << 120
                || s2.abs() * span + d2 >= LIM
            {
                return None;
            }
            let n = 2 * (p.k + p.s * x0 as i128) + p.d;
            // By the prepared divisor where `n` fits 64 bits (the common case).
            let q = match i64::try_from(n) {
                Ok(n) => out.div[ch].floor(n) as i128,
                Err(_) => floor_div_wide(n, d2),
            };
            if q.abs() >= LIM {
                return None;
            }
            out.q[ch] = q as i64;
            out.r[ch] = (n - q * d2) as i64;
            out.s2[ch] = s2 as i64;
            out.d2[ch] = d2 as i64;
        }
        Some(out)
    }

    /// The three values at `x` (in the interval it was set up for).
    #[inline(always)]
    fn at(&self, x: i64) -> [i64; 3] {
        let dx = x - self.x0;
        let mut v = [0; 3];
        for (ch, v) in v.iter_mut().enumerate() {
            *v = self.q[ch] + self.div[ch].floor(self.r[ch] + self.s2[ch] * dx);
        }
        v
    }

    /// Steppers of the values at `x`, `x + 2^16`, … (inside the interval it was set up
    /// for), from one division per channel: `steps` are the triangle's steps by one pixel
    /// ([`MsTri::cstep`](spans::MsTri), `2s·2^16` over `2d`, the same numerator and
    /// denominator as here). `None` where a step does not fit 64 bits. Every value stays
    /// inside the interval, where [`ColourRow::new`] keeps the numerators below 2^62.
    #[inline]
    fn run(&self, x: i64, steps: &[RoundDivStep; 3]) -> Option<[RoundDivSteps64; 3]> {
        let dx = x - self.x0;
        let at = |ch: usize| {
            let n = self.r[ch] + self.s2[ch] * dx;
            let q = self.div[ch].floor(n);
            steps[ch].narrow_from(self.q[ch] + q, n - q * self.d2[ch])
        };
        Some([at(0)?, at(1)?, at(2)?])
    }
}

impl<'a, 't> PieceColour<'a, 't> {
    /// The colours of piece `pc` on the sub-scanline `ynum`.
    #[inline(always)]
    pub(super) fn new(
        act: &'a [Active<'t>],
        crow: &'a mut [Option<Option<ColourRow>>],
        pc: &Piece,
        ynum: i64,
        bgc: [i64; 3],
    ) -> PieceColour<'a, 't> {
        let src = match (pc.tri >= 0).then(|| &act[pc.slot]) {
            None => ColourSource::Fixed(bgc),
            Some(a) => match a.t.flat {
                Some(c) => ColourSource::Fixed(c),
                None => match crow[pc.slot]
                    .get_or_insert_with(|| ColourRow::new(&Self::planes(a, ynum), a.xl, a.xr))
                {
                    Some(row) => ColourSource::Row(row, &a.t.cstep),
                    None => ColourSource::Wide(a),
                },
            },
        };
        PieceColour {
            src,
            ynum,
            steps: None,
        }
    }

    /// Steppers of `a`'s colour planes from `mid` on, pixel by pixel (one wide division
    /// per channel), in 64 bits where `steps` advances stay inside them.
    #[inline]
    fn wide_steps(&self, a: &Active, mid: i64, steps: u64) -> ColourSteps {
        let c = Self::planes(a, self.ynum);
        let st =
            [0, 1, 2].map(|k| RoundDivSteps::start(c[k].k + c[k].s * mid as i128, &a.t.cstep[k]));
        match st.map(|s| s.narrow(steps)) {
            [Some(r), Some(g), Some(b)] => ColourSteps::Narrow([r, g, b]),
            _ => ColourSteps::Wide(st),
        }
    }

    /// The colour planes of `a` on the sub-scanline `ynum`.
    #[inline]
    fn planes(a: &Active, ynum: i64) -> [RowPlane; 3] {
        let r = &a.t.rows;
        [r[1].row(ynum), r[2].row(ynum), r[3].row(ynum)]
    }

    /// Adds `w` times the colours of whole pixels from `x0` on (parts `[x0 + k·2^16,
    /// x0 + (k + 1)·2^16)`, one per sum of `dst`) to `dst`: the same values as
    /// [`PieceColour::at`] gives each part.
    #[inline]
    pub(super) fn add_whole(&mut self, x0: i64, dst: &mut [[u64; 3]], w: i64) {
        let count = dst.len() as i64;
        if count == 0 {
            // No whole pixel (a piece across one pixel boundary): no steppers to set up.
            return;
        }
        let mid = x0 + ONE16 / 2;
        match self.src {
            ColourSource::Fixed(c) => add_fixed(dst, w, c),
            ColourSource::Row(row, steps) => match row.run(mid, steps) {
                Some(mut st) => {
                    // A row's values are monotone in x, so when the first and the last
                    // middle's lie inside the clamp's range, every one between does. (Not
                    // `RoundDivSteps64::stays_within`, the A-buffer's bound: its magnitude
                    // precondition is not shown for a colour row's steppers, and it is
                    // only sufficient; the last middle's value is exact.)
                    let last = row.at(mid + (count - 1) * ONE16);
                    let inside = |c: [i64; 3]| c.iter().all(|&v| (0..=COLOUR_MAX).contains(&v));
                    if inside(last) && inside(st.map(|s| s.value() as i64)) {
                        add_stepped::<_, false>(&mut st, dst, w)
                    } else {
                        add_stepped::<_, true>(&mut st, dst, w)
                    }
                }
                None => {
                    for (k, sum) in dst.iter_mut().enumerate() {
                        let c = clamp_colour(row.at(mid + k as i64 * ONE16));
                        add_fixed(std::slice::from_mut(sum), w, c);
                    }
                }
            },
            ColourSource::Wide(a) => {
                // Steppers at the first middle, set up once for the run.
                match self.wide_steps(a, mid, count as u64) {
                    ColourSteps::Narrow(mut st) => add_stepped::<_, true>(&mut st, dst, w),
                    ColourSteps::Wide(mut st) => add_stepped::<_, true>(&mut st, dst, w),
                }
            }
        }
    }

    /// The colour of the part `[x0, x1)`; `end` is the piece's end (how far steps go).
    #[inline(always)]
    pub(super) fn at(&mut self, x0: i64, x1: i64, end: i64) -> [i64; 3] {
        let mid = (x0 + x1).div_euclid(2);
        match self.src {
            ColourSource::Fixed(c) => c,
            ColourSource::Row(row, _) => clamp_colour(row.at(mid)),
            ColourSource::Wide(a) => self.at_wide(a, mid, x0, x1, end),
        }
    }

    /// [`PieceColour::at`] for a triangle whose planes do not fit 64 bits (rare: kept out
    /// of line so the common cases stay small).
    #[inline(never)]
    fn at_wide(&mut self, a: &Active, mid: i64, x0: i64, x1: i64, end: i64) -> [i64; 3] {
        let clamp = |v: i128| (v as i64).clamp(0, COLOUR_MAX);
        if let Some((st, m)) = &mut self.steps {
            if *m == mid {
                *m += ONE16;
                return st.next().map(clamp);
            }
        }
        if x1 - x0 == ONE16 && end - x1 >= 2 * ONE16 {
            // More whole parts follow: step from here, in 64 bits where the steps that
            // can follow (one per whole part up to `end`) stay inside them.
            let mut st = self.wide_steps(a, mid, ((end - mid) / ONE16 + 1) as u64);
            let v = st.next().map(clamp);
            self.steps = Some((st, mid + ONE16));
            return v;
        }
        Self::planes(a, self.ynum).map(|p| p.at(mid, 0).clamp(0, COLOUR_MAX))
    }
}

#[cfg(test)]
mod tests {
    use super::super::spans::prepare;
    use super::*;

    /// The 64-bit colour row gives [`RowPlane::at`] everywhere on the interval it was set
    /// up for, and refuses planes that would not fit.
    #[test]
    fn colour_row_equals_the_wide_plane() {
        let mut rng = crate::rng::Lcg64(0x00c0_100e);
        let (mut built, mut refused) = (0, 0);
        for case in 0..3000 {
            let bits = [20u32, 40, 60, 70][case % 4];
            let mut draw = |b: u32| {
                let v = ((rng.step() as i128) << 64 | rng.step() as i128) % (1i128 << b);
                if rng.step() & 1 == 0 {
                    -v
                } else {
                    v
                }
            };
            let planes = [0; 3].map(|_| {
                RowPlane::new(draw(bits + 10), draw(bits.min(44)), draw(bits).abs().max(1))
            });
            let x0 = (draw(26) as i64).abs() - (1 << 20);
            let x1 = x0 + 1 + (draw(22) as i64).abs();
            let Some(row) = ColourRow::new(&planes, x0, x1) else {
                refused += 1;
                continue;
            };
            built += 1;
            let mut xs = vec![x0, x1, (x0 + x1) / 2];
            xs.extend((0..8).map(|_| x0 + (draw(40) as i64).rem_euclid(x1 - x0 + 1)));
            for x in xs {
                assert_eq!(row.at(x), planes.map(|p| p.at(x, 0)), "{planes:?} at {x}");
            }
        }
        assert!(
            built > 1000 && refused > 300,
            "built {built}, refused {refused}"
        );
    }

    /// A run of whole pixels adds to each pixel's sum its weight times the clamped
    /// colour of the plane at the pixel's middle, evaluated here one pixel at a time from
    /// [`RowPlane::at`]; on rows inside the clamp's range, rows crossing either of its
    /// limits, and rows beyond it.
    #[test]
    fn whole_pixels_add_the_clamped_middle_colours() {
        let mut rng = crate::rng::Lcg64(0x0add_3601e);
        let (mut inside, mut crossing) = (0, 0);
        for case in 0..4000 {
            let mut small = |m: u64| (rng.step() % (2 * m + 1)) as i128 - m as i128;
            // Values at `x0` in and around the range `0..=COLOUR_MAX` (about 2^20),
            // moving by up to 2^15 a pixel: some rows cross a limit (into the range or
            // out of it) within a few dozen pixels.
            let x0 = small(1 << 22) as i64;
            let spread = [1 << 18, 3 << 18][case % 2];
            let planes = [0; 3].map(|_| {
                let d = small(1 << 12).abs().max(1);
                let s = small(d as u64 / 2 + 1);
                let k = (COLOUR_MAX as i128 / 2 + small(spread)) * d - s * x0 as i128;
                RowPlane::new(k, s, d)
            });
            let count = (1 + small(30).abs()) as usize;
            let end = x0 + count as i64 * ONE16;
            let Some(row) = ColourRow::new(&planes, x0, end) else {
                continue;
            };
            let steps = planes.map(|p| RoundDivStep::new(p.s * ONE16 as i128, p.d));
            let mut pcol = PieceColour {
                src: ColourSource::Row(&row, &steps),
                ynum: 0,
                steps: None,
            };
            let w = ONE16 * (1 + (case / 2 % 2) as i64);
            let start: Vec<[u64; 3]> = (0..count)
                .map(|_| [0; 3].map(|_| small(1 << 40).unsigned_abs() as u64))
                .collect();
            let mut got = start.clone();
            pcol.add_whole(x0, &mut got, w);
            let mut clamped = false;
            for (k, (g, s0)) in got.iter().zip(&start).enumerate() {
                let mid = x0 + k as i64 * ONE16 + ONE16 / 2;
                let want: [u64; 3] = std::array::from_fn(|ch| {
                    let v = planes[ch].at(mid, 0);
                    clamped |= v != v.clamp(0, COLOUR_MAX);
                    s0[ch] + (w * v.clamp(0, COLOUR_MAX)) as u64
                });
                assert_eq!(*g, want, "{planes:?} from {x0}, pixel {k} of {count}");
            }
            if clamped {
                crossing += 1;
            } else {
                inside += 1;
            }
        }
        assert!(
            inside > 1000 && crossing > 500,
            "{inside} inside, {crossing} clamped"
        );
    }

    /// The whole pixels' steppers of a colour row give each pixel's colour as
    /// [`ColourRow::at`] (so [`RowPlane::at`]) does.
    #[test]
    fn colour_run_steps_equal_the_row() {
        let take = |st: &mut [RoundDivSteps64; 3]| {
            let mut c = [0; 3];
            for (v, s) in c.iter_mut().zip(st.iter_mut()) {
                *v = s.value() as i64;
                s.advance();
            }
            clamp_colour(c)
        };
        let (w, h) = (64u32, 40u32);
        let tris = crate::rng::random_tris(0x0c01_0e55, 60, w, h);
        let mut runs = 0;
        for (k, t) in tris.iter().enumerate() {
            let Some(mt) = prepare(k, t, 8) else { continue };
            for ynum in (mt.ylo / 256..=mt.yhi / 256).step_by(3) {
                let Some((xl, xr)) = mt.interval(ynum, false) else {
                    continue;
                };
                let planes = [1, 2, 3].map(|c| mt.rows[c].row(ynum));
                let Some(row) = ColourRow::new(&planes, xl, xr) else {
                    continue;
                };
                // Whole pixels inside the interval, from the first boundary on.
                let first = xl.div_euclid(ONE16) + 1;
                let Some(mut st) = row.run(first * ONE16 + ONE16 / 2, &mt.cstep) else {
                    continue;
                };
                let mut i = first;
                while (i + 1) * ONE16 <= xr {
                    let mid = i * ONE16 + ONE16 / 2;
                    let want = planes.map(|p| p.at(mid, 0).clamp(0, COLOUR_MAX));
                    assert_eq!(take(&mut st), want, "triangle {k}, line {ynum}, pixel {i}");
                    i += 1;
                    runs += 1;
                }
            }
        }
        assert!(runs > 2000, "{runs} steps");
        // Small denominators, where numerators meet a multiple of the denominator.
        let mut rng = crate::rng::Lcg64(0x5a11_d0e5);
        let mut exact = 0;
        for _ in 0..2000 {
            let mut small = |m: u64| (rng.step() % (2 * m + 1)) as i128 - m as i128;
            let planes = [0; 3]
                .map(|_| RowPlane::new(small(1 << 40), small(1 << 10), small(40).abs().max(1)));
            let x0 = small(1 << 20) as i64;
            let x1 = x0 + 40 * ONE16;
            let Some(row) = ColourRow::new(&planes, x0, x1) else {
                continue;
            };
            let steps = planes.map(|p| RoundDivStep::new(p.s * ONE16 as i128, p.d));
            let mut st = row.run(x0 + ONE16 / 2, &steps).expect("small steps fit");
            for i in 0..39 {
                let mid = x0 + i * ONE16 + ONE16 / 2;
                let want = planes.map(|p| p.at(mid, 0).clamp(0, COLOUR_MAX));
                exact += planes
                    .iter()
                    .filter(|p| (2 * (p.k + p.s * mid as i128) + p.d) % (2 * p.d) == 0)
                    .count();
                assert_eq!(take(&mut st), want, "{planes:?} from {x0}, pixel {i}");
            }
        }
        assert!(exact > 1000, "{exact} exact quotients");
    }
}
