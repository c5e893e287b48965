//! Golden model of the scanline pixel-processor array (seed 001, Matsumoto).
//!
//! The hardware of seed 001 section 1 is "one scanline's worth of pixel processors":
//! processor `p` of a tile based at `base` owns screen column `base + p` and holds a depth
//! register `ZB`, an intensity register, and the shadow flags DSF and FSF (section 4) plus
//! the per-pixel counter of section 6. A screen line wider than the array is processed in
//! tiles: the same span words are fed once per tile.
//!
//! The per-clock interface is [`PixelArray::step`]: one [`Command`] in, processor state
//! after. It is the reference the RTL twin (`rtl::pixel_array`) is compared against, clock
//! by clock. [`PixelArray::run_line`] and [`crate::render`] are built on `step`.
//!
//! Rules, each from the seed:
//! - OP span (section 3, "scanline Z-buffer"): for `XL ≤ p ≤ XR`, `Z = (ZL + (p − XL)·dZ) >>
//!   12`; if `Z < ZB` (or `Z ≤ ZB` for a decal span) then `ZB := Z`, `I := I(p)`.
//! - SP/EV/IF span (section 4, the Pascal-like program): if `attr = IF` then `DSF := ¬DSF`
//!   on every processor; if `XL ≤ p ≤ XR` and `Z < ZB` then `DSF := ¬DSF`; if `attr = EV`
//!   then afterwards `FSF := FSF ∨ DSF`. Z and intensity registers are never touched.
//! - Counter (section 6, extended light source): `AccumulateShadow` adds FSF to the
//!   per-pixel counter; `ClearFlags` starts the next point light with DSF = FSF = 0.
//! - Several lights (section 6): `LatchShadow { bit }` records FSF in the pixel's light
//!   mask; the OP write also stores the span's normal class, which with the mask indexes
//!   the attenuation table at readout (`crate::shadow::FactorTable`).
//! - Software form (section 5): `Check { xl, xr }` replaces EV, checking only its range.
//! - Exact shading in shadow (this project's extension, `docs/shadows.md`): an OP span with
//!   `chan = 0` also records in WON whether it passed; the span words with `chan = c ≥ 1`
//!   that follow it (same `XL`, `XR`) do no depth test and write shade register `c`
//!   (`I(p)`, clamped like the intensity) where WON is set. Register 1 is the state's `sh`;
//!   registers 2.. are [`PixelArray::shade_regs`].
//!
//! The OP and shade-channel spans are in `op_span`, the shadow flags (and [`RowFlags`], a
//! row's shadow commands applied to the whole row at once) in `span_parity`, as the RTL
//! has its processors and its span-parity block.

use pixelproc_formats::{Attr, SpanWord, MAX_SHADE_CHANNELS, Z_FAR};

mod op_span;
mod span_parity;

use span_parity::latch_in_place;
pub use span_parity::{is_flag_command, BandFlags, RowFlags};

/// One clock's input to the array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Start a new scanline: `ZB := Z_FAR`, intensity := `bg` (packed RGB888), flags and
    /// counters cleared.
    ClearLine {
        /// Background colour, `{R, G, B}` packed as by `pixelproc_formats::pack_rgb`.
        bg: u32,
    },
    /// Expand one span word.
    Span(SpanWord),
    /// Start the shadow volumes of the next point light: `DSF := 0; FSF := 0`.
    ClearFlags,
    /// End of one sample of an area light: `count := count + FSF` (saturating at 255).
    AccumulateShadow,
    /// End of a point light's volumes: `mask := mask | (FSF << bit)` (seed 001 §6, several
    /// lights: which lights shadow the pixel).
    LatchShadow {
        /// The light's bit in the mask, 0..7.
        bit: u8,
    },
    /// The software form of seed 001 §5: instead of EV, a dummy check span after a
    /// volume's spans; `FSF := FSF ∨ DSF` only for `XL ≤ p ≤ XR`.
    Check {
        /// First pixel checked.
        xl: u16,
        /// Last pixel checked.
        xr: u16,
    },
    /// No operation (a bubble).
    Nop,
}

/// The registers of one pixel processor: the record shared with the RTL probes, defined
/// once in `pixelproc_formats::regs`.
pub use pixelproc_formats::regs::ProcState;

/// A row of `width` pixel processors owning screen columns `base .. base + width`.
#[derive(Clone, Debug)]
pub struct PixelArray {
    base: u32,
    procs: Vec<ProcState>,
    /// Shade registers 2..=`MAX_SHADE_CHANNELS` per processor (allocated on first use).
    more: Vec<u32>,
}

/// Shade registers per processor beyond the first (kept outside [`ProcState`]).
pub const MORE_SHADE: usize = MAX_SHADE_CHANNELS as usize - 1;

impl PixelArray {
    /// An array of `width` processors for the tile starting at column `base`.
    pub fn new(width: usize, base: u32) -> PixelArray {
        assert!(width > 0, "array width must be positive");
        PixelArray {
            base,
            procs: vec![
                ProcState {
                    zb: Z_FAR,
                    ..Default::default()
                };
                width
            ],
            more: Vec::new(),
        }
    }

    /// Shade registers 2..=[`MAX_SHADE_CHANNELS`] of each processor ([`MORE_SHADE`] per
    /// processor, processor 0 first), or an empty slice if no span has written one since
    /// the array was built.
    pub fn shade_regs(&self) -> &[u32] {
        &self.more
    }

    /// Number of processors.
    pub fn width(&self) -> usize {
        self.procs.len()
    }

    /// First screen column of the current tile.
    pub fn base(&self) -> u32 {
        self.base
    }

    /// Moves the array to the tile starting at `base` (state is kept; send `ClearLine`).
    pub fn set_base(&mut self, base: u32) {
        self.base = base;
    }

    /// Processor states, processor 0 first.
    pub fn state(&self) -> &[ProcState] {
        &self.procs
    }

    /// One clock: apply `cmd` to every processor.
    pub fn step(&mut self, cmd: &Command) {
        match *cmd {
            Command::ClearLine { bg } => {
                for s in &mut self.procs {
                    *s = ProcState {
                        zb: Z_FAR,
                        rgb: bg,
                        ..Default::default()
                    };
                }
                self.more.fill(0);
            }
            Command::ClearFlags => {
                for s in &mut self.procs {
                    s.dsf = false;
                    s.fsf = false;
                }
            }
            Command::AccumulateShadow | Command::LatchShadow { .. } => {
                latch_in_place(cmd, &mut self.procs)
            }
            Command::Check { xl, xr } => {
                if let Some((lo, hi)) = self.columns(xl, xr) {
                    for s in &mut self.procs[lo..=hi] {
                        s.fsf |= s.dsf;
                    }
                }
            }
            Command::Nop => {}
            Command::Span(ref w) => self.step_span(w),
        }
    }

    /// One clock with a span word: the same as `step(&Command::Span(*w))`, without
    /// copying the word.
    #[inline]
    pub fn step_span(&mut self, w: &SpanWord) {
        match w.attr {
            Attr::Op if w.chan == 0 => self.op_span(w),
            Attr::Op => self.chan_span(w),
            _ => self.shadow_span(w),
        }
    }

    /// Two clocks, span words `a` then `b`: the same as `step_span(a)` then
    /// `step_span(b)`. When `b` is the shade-channel 1 copy of the polygon span `a` (the
    /// same columns), both are applied in one pass over the processors: where `a` wins,
    /// `b` writes `SH`, which is what `b`'s clock does after `a`'s.
    #[inline]
    pub fn step_span_pair(&mut self, a: &SpanWord, b: &SpanWord) {
        if a.attr == Attr::Op
            && a.chan == 0
            && b.attr == Attr::Op
            && b.chan == 1
            && (a.xl, a.xr) == (b.xl, b.xr)
        {
            self.op_chan_span(a, b);
        } else {
            self.step_span(a);
            self.step_span(b);
        }
    }

    /// The processor index range `[lo, hi]` a span covers in this tile, if any.
    #[inline]
    fn tile_range(&self, w: &SpanWord) -> Option<(usize, usize)> {
        self.columns(w.xl, w.xr)
    }

    /// The processor index range `[lo, hi]` of screen columns `xl..=xr` in this tile, if
    /// any.
    #[inline]
    fn columns(&self, xl: u16, xr: u16) -> Option<(usize, usize)> {
        let lo = (xl as i64).max(self.base as i64);
        let hi = (xr as i64).min(self.base as i64 + self.procs.len() as i64 - 1);
        (lo <= hi).then(|| {
            (
                (lo - self.base as i64) as usize,
                (hi - self.base as i64) as usize,
            )
        })
    }

    /// Runs a whole scanline through the current tile: `ClearLine`, then each command.
    pub fn run_line<'a>(&mut self, bg: u32, cmds: impl IntoIterator<Item = &'a Command>) {
        self.step(&Command::ClearLine { bg });
        for c in cmds {
            self.step(c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pixelproc_formats::{pack_rgb, I_FRAC, Z_FRAC};

    fn op(xl: u16, xr: u16, z: u32, dz: i64, rgb: [u32; 3]) -> Command {
        Command::Span(SpanWord {
            xl,
            xr,
            zl: (z as u64) << Z_FRAC,
            dz,
            il: rgb.map(|c| c << I_FRAC),
            ..Default::default()
        })
    }

    #[test]
    fn op_span_depth_test_keeps_nearest() {
        let mut a = PixelArray::new(8, 0);
        a.run_line(
            0,
            &[
                op(0, 7, 1000, 0, [255, 0, 0]),
                op(2, 5, 500, 0, [0, 255, 0]),
                op(0, 7, 800, 0, [0, 0, 255]),
            ],
        );
        let rgb: Vec<u32> = a.state().iter().map(|s| s.rgb).collect();
        assert_eq!(
            rgb,
            vec![0xff, 0xff, 0xff00, 0xff00, 0xff00, 0xff00, 0xff, 0xff]
        );
        assert_eq!(a.state()[3].zb, 500);
        assert_eq!(a.state()[0].zb, 800);
    }

    /// A pair of words is the two clocks in order, whether or not it is applied in one
    /// pass (a channel-1 copy with the same columns) or not (other columns, channel,
    /// attribute), on tiles the words overlap or miss, decals included.
    #[test]
    fn span_pair_is_two_clocks() {
        let mut rng = crate::rng::Lcg64(0xfa11_0b1e);
        let mut fused = 0;
        for round in 0..2_000 {
            let mut r = |m: u64| rng.step() % m;
            let base = [0, 8, 16][round % 3];
            let word = |r: &mut dyn FnMut(u64) -> u64| {
                let xl = r(28) as u16;
                SpanWord {
                    attr: Attr::Op,
                    xl,
                    xr: xl + r(8) as u16,
                    zl: r(1 << 30) + (1 << 20),
                    dz: r(1 << 16) as i64 - (1 << 15),
                    il: [0; 3].map(|_| r(1 << 20) as u32),
                    di: [0; 3].map(|_| r(1 << 14) as i32 - (1 << 13)),
                    decal: r(4) == 0,
                    nclass: r(8) as u8,
                    ..Default::default()
                }
            };
            let mut a0 = PixelArray::new(16, base);
            // Some earlier state: depths, WON flags and shade registers.
            for _ in 0..3 {
                let w = word(&mut r);
                a0.step_span(&w);
                a0.step_span(&SpanWord {
                    chan: 1 + r(2) as u8,
                    ..word(&mut r)
                });
            }
            let a = word(&mut r);
            let mut b = SpanWord {
                chan: 1,
                ..word(&mut r)
            };
            match r(5) {
                0 | 1 => (b.xl, b.xr) = (a.xl, a.xr),
                2 => b.chan = 2,
                3 => b.attr = Attr::Sp,
                _ => {}
            }
            fused += ((b.xl, b.xr, b.chan, b.attr) == (a.xl, a.xr, 1, Attr::Op)) as u32;
            let (mut one, mut two) = (a0.clone(), a0);
            one.step_span_pair(&a, &b);
            two.step_span(&a);
            two.step_span(&b);
            assert_eq!(one.state(), two.state(), "round {round}: {a:?} {b:?}");
            assert_eq!(one.shade_regs(), two.shade_regs(), "round {round}");
        }
        assert!(fused > 500, "{fused}");
    }

    /// OP spans and their channel-1 copies, paired (one pass) and alone, against the
    /// module header's rules written out here per processor: `Z = (ZL + (p − XL)·dZ) >> 12`,
    /// `I(p) = clamp((IL + (p − XL)·dI) >> I_FRAC, 0, 255)`, the copy writing `SH` where
    /// the span won. Intensities start near 0, mid-range and near 255 with slopes of
    /// either sign, so runs that stay inside the range, touch its ends and leave it all
    /// occur, on tiles that cut the spans.
    #[test]
    fn op_spans_follow_the_closed_form() {
        let mut rng = crate::rng::Lcg64(0x0c1a_3b5e);
        let (mut inside, mut outside) = (0, 0);
        for round in 0..3_000 {
            let mut r = |m: u64| rng.step() % m;
            let base = [0u32, 8, 16][round % 3];
            let word = |r: &mut dyn FnMut(u64) -> u64, chan: u8| {
                let xl = r(28) as u16;
                let one = 1i64 << I_FRAC;
                let il = [0; 3].map(|_| {
                    let start = [0, 128, 255][r(3) as usize] * one + r(one as u64) as i64;
                    (start - one / 2).max(0) as u32
                });
                let di = [0; 3].map(|_| r(16 * one as u64) as i32 - 8 * one as i32);
                SpanWord {
                    attr: Attr::Op,
                    xl,
                    xr: xl + r(10) as u16,
                    zl: r(1 << 30) + (1 << 20),
                    dz: r(1 << 16) as i64 - (1 << 15),
                    il,
                    di,
                    decal: r(4) == 0,
                    nclass: r(8) as u8,
                    chan,
                    ..Default::default()
                }
            };
            let mut a0 = PixelArray::new(16, base);
            let earlier = word(&mut r, 0);
            a0.step_span(&earlier);
            let a = word(&mut r, 0);
            let b = SpanWord {
                xl: a.xl,
                xr: a.xr,
                ..word(&mut r, 1)
            };
            // The rules, per processor.
            let at = |w: &SpanWord, k: usize, x: i64| {
                (w.il[k] as i64 + (x - w.xl as i64) * w.di[k] as i64) >> I_FRAC
            };
            let colour =
                |w: &SpanWord, x: i64| pack_rgb([0, 1, 2].map(|k| at(w, k, x).clamp(0, 255) as u8));
            let mut want = a0.state().to_vec();
            let mut leaves = false;
            for (p, st) in want.iter_mut().enumerate() {
                let x = base as i64 + p as i64;
                if x < a.xl as i64 || x > a.xr as i64 {
                    continue;
                }
                leaves |= (0..3).any(|k| !(0..=255).contains(&at(&a, k, x)));
                leaves |= (0..3).any(|k| !(0..=255).contains(&at(&b, k, x)));
                let z = ((a.zl as i64 + (x - a.xl as i64) * a.dz) >> Z_FRAC) as u32;
                st.won = if a.decal { z <= st.zb } else { z < st.zb };
                if st.won {
                    st.zb = z;
                    st.nclass = a.nclass;
                    st.rgb = colour(&a, x);
                    st.sh = colour(&b, x);
                }
            }
            if leaves {
                outside += 1;
            } else {
                inside += 1;
            }
            let (mut one, mut two) = (a0.clone(), a0);
            one.step_span_pair(&a, &b);
            assert_eq!(one.state(), &want[..], "round {round}: {a:?} {b:?}");
            two.step_span(&a);
            two.step_span(&b);
            assert_eq!(two.state(), &want[..], "round {round}: {a:?} {b:?}");
        }
        assert!(
            inside > 300 && outside > 300,
            "{inside} inside, {outside} outside"
        );
    }

    #[test]
    fn tiles_see_absolute_columns() {
        let mut a = PixelArray::new(4, 4);
        a.run_line(7, &[op(2, 5, 10, 1 << Z_FRAC, [1, 2, 3])]);
        let s = a.state();
        assert_eq!((s[0].zb, s[1].zb, s[2].zb), (12, 13, Z_FAR));
        assert_eq!(s[2].rgb, 7);
    }

    #[test]
    fn parity_program_of_section_4() {
        // Surface at depth 100 on 0..7; a volume whose front face covers 2..5 at depth 50
        // and back face covers 2..5 at depth 150 (behind the surface): pixels 2..5 shadowed.
        let mut a = PixelArray::new(8, 0);
        let sp = |attr, z| {
            Command::Span(SpanWord {
                attr,
                xl: 2,
                xr: 5,
                zl: (z as u64) << Z_FRAC,
                ..Default::default()
            })
        };
        a.run_line(
            0,
            &[
                op(0, 7, 100, 0, [9, 9, 9]),
                Command::ClearFlags,
                sp(Attr::Sp, 50),
                sp(Attr::Ev, 150),
            ],
        );
        let f: Vec<bool> = a.state().iter().map(|s| s.fsf).collect();
        assert_eq!(f, vec![false, false, true, true, true, true, false, false]);
        // Z and intensity untouched by shadow spans.
        assert!(a.state().iter().all(|s| s.zb == 100 && s.rgb == 0x090909));
        // IF inverts every pixel: a viewer inside the volume sees only the back face.
        let mut b = PixelArray::new(8, 0);
        b.run_line(
            0,
            &[
                op(0, 7, 100, 0, [9, 9, 9]),
                sp(Attr::If, 150),
                Command::Span(SpanWord {
                    attr: Attr::Ev,
                    xl: 1,
                    xr: 0,
                    ..Default::default()
                }),
            ],
        );
        assert!(b.state().iter().all(|s| s.fsf));
    }
}
