//! The span-parity flags (seed 001 section 4, the per-pixel program; section 5, the check
//! span; section 6, the counter and the light mask): SP/EV/IF spans toggle DSF where they
//! lie in front of `ZB`, EV and `Check` OR DSF into FSF, the controls clear the flags and
//! latch FSF. The twin of `rtl::span_parity`. [`PixelArray::step`] applies them to one
//! array, clock by clock; [`RowFlags`] applies a row's shadow commands to the whole row at
//! once, as the renderer does.

use super::{Command, PixelArray, ProcState};
use crate::stream::{RowTiles, VolumeTiles};
use pixelproc_formats::{Attr, SpanWord, Z_FRAC};

/// ZB, DSF and FSF of processors in three separate arrays (a flag is one byte, 0 or 1):
/// while [`RowFlags`] applies shadow commands, which read ZB and change only the flags
/// (and, from FSF, the counter and the light mask), their loops run over contiguous memory
/// instead of over [`ProcState`] records.
#[derive(Clone, Debug, Default)]
struct FlagPlanes {
    zb: Vec<u32>,
    dsf: Vec<u8>,
    fsf: Vec<u8>,
}

impl FlagPlanes {
    /// Copies the processors' ZB and flags in.
    fn load(&mut self, procs: &[ProcState]) {
        self.zb.clear();
        self.zb.extend(procs.iter().map(|s| s.zb));
        self.dsf.clear();
        self.dsf.extend(procs.iter().map(|s| s.dsf as u8));
        self.fsf.clear();
        self.fsf.extend(procs.iter().map(|s| s.fsf as u8));
    }

    /// Copies the flags back out (ZB is never changed here).
    fn store(&self, procs: &mut [ProcState]) {
        for (s, (&d, &f)) in procs.iter_mut().zip(self.dsf.iter().zip(&self.fsf)) {
            s.dsf = d != 0;
            s.fsf = f != 0;
        }
    }

    /// A span word's flag rule on processors `lo..=hi` (`z` its depth at `lo`): IF inverts
    /// DSF everywhere first; then DSF toggles where the span lies in front. (EV's OR is
    /// the caller's: it depends on which processors the word reaches.)
    #[inline]
    fn span(&mut self, w: &SpanWord, range: Option<(usize, usize)>, z: i64) {
        if w.attr == Attr::If {
            self.dsf.iter_mut().for_each(|d| *d ^= 1);
        }
        if let Some((lo, hi)) = range {
            toggle_in_front(&self.zb[lo..=hi], &mut self.dsf[lo..=hi], z, w.dz);
        }
    }

    /// `FSF := FSF ∨ DSF` on processors `lo..hi`.
    #[inline]
    fn absorb(&mut self, lo: usize, hi: usize) {
        let (fsf, dsf) = (&mut self.fsf[lo..hi], &self.dsf[lo..hi]);
        fsf.iter_mut().zip(dsf).for_each(|(s, d)| *s |= d);
    }

    /// The controls that read FSF into `procs`: `AccumulateShadow` (counter) and
    /// `LatchShadow` (light mask); the others are not handled here.
    #[inline]
    fn latch(&self, c: &Command, procs: &mut [ProcState]) {
        match *c {
            Command::AccumulateShadow => {
                for (s, &b) in procs.iter_mut().zip(&self.fsf) {
                    s.count = s.count.saturating_add(b);
                }
            }
            Command::LatchShadow { bit } => {
                for (s, &b) in procs.iter_mut().zip(&self.fsf) {
                    s.mask |= b << (bit & 7);
                }
            }
            _ => unreachable!("not a latching control"),
        }
    }
}

/// `DSF := ¬DSF` where `Z(p) = (z + k·dz) >> Z_FRAC` (as 32 bits) lies in front of `ZB`,
/// for the `k`-th processor of `zb` and `dsf`: the range test of an SP/EV/IF span.
#[inline]
fn toggle_in_front(zb: &[u32], dsf: &mut [u8], mut z: i64, dz: i64) {
    for (d, &b) in dsf.iter_mut().zip(zb) {
        *d ^= (((z >> Z_FRAC) as u32) < b) as u8;
        z += dz;
    }
}

/// Whether `c` only reads ZB and changes the shadow flags, the counter or the light mask
/// (SP, EV and IF spans and the shadow controls): the commands [`RowFlags::run`] takes.
pub fn is_flag_command(c: &Command) -> bool {
    match c {
        Command::Span(w) => w.attr != Attr::Op,
        Command::ClearFlags
        | Command::AccumulateShadow
        | Command::LatchShadow { .. }
        | Command::Check { .. }
        | Command::Nop => true,
        Command::ClearLine { .. } => false,
    }
}

/// A screen row's shadow commands applied to the whole row at once, with the result of
/// feeding its tiles of `n` processors the commands a [`crate::stream::TileRouter`] picks
/// for each (the way [`crate::render::render_frame`] feeds them): a span toggles DSF on
/// its columns; an EV span ORs DSF into FSF on the tiles the router sends it to (its own,
/// and those a span of its volume touched since the last EV or `Check`, or every tile
/// after an IF span); a `Check` on its own columns; the controls on every processor.
/// ZB and the flags are copied into separate arrays (a byte per flag), so each span's
/// depth test is one vectorisable pass over contiguous memory instead of one per tile.
#[derive(Debug, Default)]
pub struct RowFlags {
    planes: FlagPlanes,
    /// The tiles the current volume touched (the router's choice for EV).
    vol: VolumeTiles,
}

impl RowFlags {
    /// Applies `cmds` (each [`is_flag_command`]) to `row`, the processors of screen columns
    /// `0 .. row.len()` after the row's polygon spans, tiles of `n` processors.
    ///
    /// Only the tiles a span or a `Check` reaches (every tile after an IF span) can have
    /// their flags changed by more than the controls; those are copied into the separate
    /// arrays, and the controls act on the other processors in place.
    pub fn run(&mut self, row: &mut [ProcState], cmds: &[Command], n: usize) {
        assert!(n > 0, "tile width must be positive");
        let w = row.len();
        if w == 0 {
            return;
        }
        let tiles = w.div_ceil(n);
        self.vol.start(tiles);
        // The router's tiles of a column range (`TileRouter::route`).
        let row_tiles = RowTiles::new(n, tiles);
        let tile_range = |xl: u16, xr: u16| row_tiles.span(xl, xr);
        // The processors `r0..r1` of the tiles any span or check reaches: those from the
        // tile of the least first column to that of the greatest last column among the
        // ranges that reach a tile (a column's tile grows with the column), every tile
        // after an IF span.
        let on_tiles = tiles * n;
        let (mut lo, mut hi) = (u16::MAX, 0u16);
        for c in cmds {
            let (xl, xr) = match *c {
                Command::Span(ref sw) if sw.attr == Attr::If => (0, u16::MAX),
                Command::Span(ref sw) => (sw.xl, sw.xr),
                Command::Check { xl, xr } => (xl, xr),
                _ => continue,
            };
            if xl <= xr && (xl as usize) < on_tiles {
                (lo, hi) = (lo.min(xl), hi.max(xr));
            }
        }
        let (r0, r1) = match tile_range(lo, hi) {
            Some((ta, tb)) => (ta * n, ((tb + 1) * n).min(w)),
            None => (0, 0),
        };
        let (inner, outer) = (r0..r1, [0..r0, r1..w]);
        self.planes.load(&row[inner.clone()]);
        // A span's or check's columns on the row, as indices into the planes.
        let cols = |xl: u16, xr: u16| {
            let hi = (xr as usize).min(w - 1);
            (xl as usize <= hi).then(|| (xl as usize - r0, hi - r0))
        };
        for c in cmds {
            let f = &mut self.planes;
            match *c {
                Command::Span(ref sw) => {
                    let range = cols(sw.xl, sw.xr);
                    let lo = range.map_or(0, |r| r.0 + r0) as i64;
                    f.span(sw, range, sw.zl as i64 + (lo - sw.xl as i64) * sw.dz);
                    match sw.attr {
                        Attr::Sp => {
                            if let Some((a, b)) = tile_range(sw.xl, sw.xr) {
                                self.vol.touch(a, b);
                            }
                        }
                        Attr::If => self.vol.touch_all(),
                        Attr::Ev => {
                            // The processors of tiles `a..=b` (those on the screen).
                            let or_tiles = |f: &mut FlagPlanes, a: usize, b: usize| {
                                f.absorb(a * n - r0, ((b + 1) * n).min(w) - r0)
                            };
                            if self.vol.all() {
                                or_tiles(f, 0, tiles - 1);
                            } else {
                                for &t in self.vol.marked() {
                                    or_tiles(f, t, t);
                                }
                                if let Some((a, b)) = tile_range(sw.xl, sw.xr) {
                                    or_tiles(f, a, b);
                                }
                            }
                            self.vol.reset();
                        }
                        Attr::Op => unreachable!("an OP span is not a flag command"),
                    }
                }
                Command::Check { xl, xr } => {
                    if let Some((lo, hi)) = cols(xl, xr) {
                        f.absorb(lo, hi + 1);
                    }
                    self.vol.reset();
                }
                Command::ClearFlags => {
                    f.dsf.fill(0);
                    f.fsf.fill(0);
                    for o in &outer {
                        for s in &mut row[o.clone()] {
                            (s.dsf, s.fsf) = (false, false);
                        }
                    }
                }
                Command::AccumulateShadow | Command::LatchShadow { .. } => {
                    f.latch(c, &mut row[inner.clone()]);
                    for o in &outer {
                        latch_in_place(c, &mut row[o.clone()]);
                    }
                }
                Command::Nop => {}
                Command::ClearLine { .. } => panic!("ClearLine is not a flag command"),
            }
        }
        self.planes.store(&mut row[inner]);
    }
}

/// `AccumulateShadow` (`count := count + FSF`, saturating) or `LatchShadow { bit }`
/// (`mask := mask | FSF << bit`) on the processors `procs`, from their own FSF.
pub(super) fn latch_in_place(c: &Command, procs: &mut [ProcState]) {
    match *c {
        Command::AccumulateShadow => {
            for s in procs {
                s.count = s.count.saturating_add(s.fsf as u8);
            }
        }
        Command::LatchShadow { bit } => {
            for s in procs {
                s.mask |= (s.fsf as u8) << (bit & 7);
            }
        }
        _ => unreachable!("not a latching control"),
    }
}

impl PixelArray {
    pub(super) fn shadow_span(&mut self, w: &SpanWord) {
        if w.attr == Attr::If {
            for s in &mut self.procs {
                s.dsf = !s.dsf;
            }
        }
        if let Some((lo, hi)) = self.tile_range(w) {
            let base = self.base as i64;
            let mut z = w.zl as i64 + (base + lo as i64 - w.xl as i64) * w.dz;
            for s in &mut self.procs[lo..=hi] {
                if ((z >> Z_FRAC) as u32) < s.zb {
                    s.dsf = !s.dsf;
                }
                z += w.dz;
            }
        }
        if w.attr == Attr::Ev {
            for s in &mut self.procs {
                s.fsf |= s.dsf;
            }
        }
    }
}
