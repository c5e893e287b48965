//! OP spans on the array (seed 001 section 3, "scanline Z-buffer"): for `XL ≤ p ≤ XR`,
//! `Z = (ZL + (p − XL)·dZ) >> 12`; if `Z < ZB` (`Z ≤ ZB` for a decal span) then `ZB := Z`
//! and the intensity register takes `I(p) = clamp((IL + (p − XL)·dI) >> I_FRAC, 0, 255)`;
//! and the shade-channel spans of exact shading in shadow (`docs/shadows.md`), which write
//! shade register `c` where the polygon's span just won. The twin of the processors'
//! depth compare and colour lanes in `rtl::pixel_processor`.

use super::{PixelArray, ProcState, MORE_SHADE};
use pixelproc_formats::{pack_rgb, SpanWord, I_FRAC, MAX_SHADE_CHANNELS, Z_FRAC};

impl PixelArray {
    pub(super) fn op_span(&mut self, w: &SpanWord) {
        let Some((lo, hi)) = self.tile_range(w) else {
            return;
        };
        let off = self.base as i64 + lo as i64 - w.xl as i64;
        let c = accumulators(w, off);
        if in_range(&c, w, hi - lo) {
            self.op_loop(w, lo, hi, Lanes::<false>::new(c, w, c, w));
        } else {
            self.op_loop(w, lo, hi, Wide::<false>::new(c, w, c, w));
        }
    }

    /// [`PixelArray::op_span`] of `w` and [`PixelArray::chan_span`] of its channel-1
    /// copy `sh` (the same columns), in one pass.
    pub(super) fn op_chan_span(&mut self, w: &SpanWord, sh: &SpanWord) {
        debug_assert!(sh.chan == 1 && (w.xl, w.xr) == (sh.xl, sh.xr));
        let Some((lo, hi)) = self.tile_range(w) else {
            return;
        };
        let off = self.base as i64 + lo as i64 - w.xl as i64;
        let (c, d) = (accumulators(w, off), accumulators(sh, off));
        if in_range(&c, w, hi - lo) && in_range(&d, sh, hi - lo) {
            self.op_loop(w, lo, hi, Lanes::<true>::new(c, w, d, sh));
        } else {
            self.op_loop(w, lo, hi, Wide::<true>::new(c, w, d, sh));
        }
    }

    /// The OP span's pass over processors `lo..=hi`: the depth test, and where it passes
    /// `ZB`, the normal class and the intensities `i` holds (the span's, and its
    /// channel-1 copy's if it carries one). `Z` starts at processor `lo` and steps by `dZ`
    /// per processor: identical to the closed form (exact integer sums).
    #[inline(always)]
    fn op_loop<I: Intensities>(&mut self, w: &SpanWord, lo: usize, hi: usize, mut i: I) {
        let mut z = w.zl as i64 + (self.base as i64 + lo as i64 - w.xl as i64) * w.dz;
        for s in &mut self.procs[lo..=hi] {
            let zp = (z >> Z_FRAC) as u32;
            s.won = crate::raster::depth::passes(zp, s.zb, w.decal);
            if s.won {
                s.zb = zp;
                s.nclass = w.nclass;
                i.write(s);
            }
            z += w.dz;
            i.step();
        }
    }

    /// A shade-channel span: shade register `chan` := `I(p)` where WON is set.
    pub(super) fn chan_span(&mut self, w: &SpanWord) {
        let Some((lo, hi)) = self.tile_range(w) else {
            return;
        };
        let ch = w.chan as usize;
        assert!(ch <= MAX_SHADE_CHANNELS as usize, "shade channel {ch}");
        if ch >= 2 && self.more.is_empty() {
            self.more = vec![0; self.procs.len() * MORE_SHADE];
        }
        let off = self.base as i64 + lo as i64 - w.xl as i64;
        let mut c = accumulators(w, off);
        for p in lo..=hi {
            if self.procs[p].won {
                let v = pack_rgb(c.map(|v| (v >> I_FRAC).clamp(0, 255) as u8));
                if ch == 1 {
                    self.procs[p].sh = v;
                } else {
                    self.more[p * MORE_SHADE + ch - 2] = v;
                }
            }
            for (ck, dk) in c.iter_mut().zip(w.di) {
                *ck += dk as i64;
            }
        }
    }
}

/// A span's intensity accumulators `IL + off·dI` at the processor `off` columns right of
/// `XL`.
#[inline]
fn accumulators(w: &SpanWord, off: i64) -> [i64; 3] {
    std::array::from_fn(|k| w.il[k] as i64 + off * w.di[k] as i64)
}

/// Whether every channel's `v >> I_FRAC` stays in 0..=255 over the `n + 1` processors
/// starting at accumulators `c`: the values are linear in the column, so their extremes
/// are the two ends, and `>>` is monotonic.
#[inline]
fn in_range(c: &[i64; 3], w: &SpanWord, n: usize) -> bool {
    (0..3).all(|k| {
        let end = c[k] + n as i64 * w.di[k] as i64;
        let (a, b) = ((c[k].min(end)) >> I_FRAC, (c[k].max(end)) >> I_FRAC);
        a >= 0 && b <= 255
    })
}

/// The intensities an OP span writes as [`PixelArray::op_loop`] walks its processors:
/// the span's `I(p) = clamp((IL + (p − XL)·dI) >> I_FRAC, 0, 255)` and, with `SH`, its
/// channel-1 copy's into `SH`.
trait Intensities {
    /// Writes the current processor's intensities into `s`.
    fn write(&self, s: &mut ProcState);
    /// Moves to the next processor.
    fn step(&mut self);
}

/// The general case: 64-bit accumulators and the clamp.
struct Wide<const SH: bool> {
    c: [i64; 3],
    dc: [i32; 3],
    d: [i64; 3],
    dd: [i32; 3],
}

impl<const SH: bool> Wide<SH> {
    #[inline(always)]
    fn new(c: [i64; 3], w: &SpanWord, d: [i64; 3], sh: &SpanWord) -> Self {
        Wide {
            c,
            dc: w.di,
            d,
            dd: sh.di,
        }
    }
}

impl<const SH: bool> Intensities for Wide<SH> {
    #[inline(always)]
    fn write(&self, s: &mut ProcState) {
        s.rgb = pack_rgb(self.c.map(|v| (v >> I_FRAC).clamp(0, 255) as u8));
        if SH {
            s.sh = pack_rgb(self.d.map(|v| (v >> I_FRAC).clamp(0, 255) as u8));
        }
    }

    #[inline(always)]
    fn step(&mut self) {
        for k in 0..3 {
            self.c[k] += self.dc[k] as i64;
            if SH {
                self.d[k] += self.dd[k] as i64;
            }
        }
    }
}

/// A run where [`in_range`] has shown that no channel's `v >> I_FRAC` leaves 0..=255:
/// the clamp is the identity, and every accumulator value used lies in
/// `0 .. 256 << I_FRAC`, so 32-bit lanes stepped with wrapping adds hold it exactly (only
/// the step past the last processor may wrap, and it is not used). The six lanes (and two
/// idle ones) step together.
struct Lanes<const SH: bool> {
    v: [i32; 8],
    dv: [i32; 8],
}

impl<const SH: bool> Lanes<SH> {
    #[inline(always)]
    fn new(c: [i64; 3], w: &SpanWord, d: [i64; 3], sh: &SpanWord) -> Self {
        let mut l = Lanes {
            v: [c[0] as i32, c[1] as i32, c[2] as i32, 0, 0, 0, 0, 0],
            dv: [w.di[0], w.di[1], w.di[2], 0, 0, 0, 0, 0],
        };
        if SH {
            (l.v[4], l.v[5], l.v[6]) = (d[0] as i32, d[1] as i32, d[2] as i32);
            (l.dv[4], l.dv[5], l.dv[6]) = (sh.di[0], sh.di[1], sh.di[2]);
        }
        l
    }

    #[inline(always)]
    fn pack(&self, k: usize) -> u32 {
        let v = &self.v[k..k + 3];
        ((v[0] >> I_FRAC) as u32) << 16 | ((v[1] >> I_FRAC) as u32) << 8 | (v[2] >> I_FRAC) as u32
    }
}

impl<const SH: bool> Intensities for Lanes<SH> {
    #[inline(always)]
    fn write(&self, s: &mut ProcState) {
        s.rgb = self.pack(0);
        if SH {
            s.sh = self.pack(4);
        }
    }

    #[inline(always)]
    fn step(&mut self) {
        for k in 0..8 {
            self.v[k] = self.v[k].wrapping_add(self.dv[k]);
        }
    }
}
