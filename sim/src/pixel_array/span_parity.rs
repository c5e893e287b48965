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
        store_flags(procs, &self.dsf, &self.fsf);
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
        latch_from(c, procs, &self.fsf);
    }
}

/// The flags `dsf` and `fsf` (a byte each) into `procs`.
fn store_flags(procs: &mut [ProcState], dsf: &[u8], fsf: &[u8]) {
    for (s, (&d, &f)) in procs.iter_mut().zip(dsf.iter().zip(fsf)) {
        s.dsf = d != 0;
        s.fsf = f != 0;
    }
}

/// `AccumulateShadow` (`count := count + FSF`, saturating) or `LatchShadow { bit }` (`mask
/// := mask | FSF << bit`) on `procs`, from the flags `fsf` (a byte each).
#[inline]
fn latch_from(c: &Command, procs: &mut [ProcState], fsf: &[u8]) {
    match *c {
        Command::AccumulateShadow => {
            for (s, &b) in procs.iter_mut().zip(fsf) {
                s.count = s.count.saturating_add(b);
            }
        }
        Command::LatchShadow { bit } => {
            for (s, &b) in procs.iter_mut().zip(fsf) {
                s.mask |= b << (bit & 7);
            }
        }
        _ => unreachable!("not a latching control"),
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

/// The shadow flags of a band of rows, applied volume by volume rather than command by
/// command: what [`RowFlags::run`] makes of a light sample's commands on each row
/// (`ClearFlags`, each volume's SP words ended by IF/EV or a `Check`, then the sample's
/// latching control), without the commands. ZB and the flags of all the band's rows are
/// held in separate arrays (`n` rows of `width`, a byte per flag).
///
/// Why the result is the same: a volume's words only toggle DSF (the IF's inversion of
/// the whole row included), and toggles commute, so they may come in any order before the
/// volume's end. The end ORs DSF into FSF, by [`RowFlags::run`] on the tiles the router
/// picks, here on the columns of the volume's words on the row (the whole row with IF):
/// both take in every pixel whose DSF changed since the last OR, and on any other pixel
/// `FSF ∨ DSF = FSF` already (after each end, `FSF ≥ DSF` everywhere: `ClearFlags` sets
/// both to 0 and every toggle is followed by an end that ORs its pixel).
#[derive(Debug, Default)]
pub struct BandFlags {
    planes: FlagPlanes,
    width: usize,
    /// Per row: the current volume's words so far, and the least first and greatest last
    /// column of those that may toggle (not [`BandFlags::count_behind`]'s).
    open: Vec<(u32, u16, u16)>,
    /// The columns `lo..hi` outside which every row's flags are 0 (since the last clear,
    /// no ended volume's word reached them and no IF inverted them).
    cols: (usize, usize),
    /// The greatest ZB over all the band's rows on runs of columns, for
    /// [`BandFlags::zb_max`]: level `k` (at `k·blocks`) holds, for each block `i` of
    /// [`ZB_BLOCK`] columns, the greatest on blocks `i .. i + 2^k`.
    zb_max: Vec<u32>,
    /// Blocks of [`ZB_BLOCK`] columns on a row; 0 until the table is made (on the first
    /// [`BandFlags::behind`] after [`BandFlags::load`]).
    blocks: usize,
    /// The least of the blocks' greatest ZB: no [`BandFlags::zb_max`] is less.
    zb_least_block: u32,
    /// The greatest ZB per column over the band's rows (the table's source).
    zb_cols: Vec<i32>,
}

/// Columns per block of [`BandFlags::zb_max`]'s table.
const ZB_BLOCK: usize = 8;

/// A row's current volume before its first word.
const NO_WORDS: (u32, u16, u16) = (0, u16::MAX, 0);

impl BandFlags {
    /// Takes ZB of the band `band` (whole rows of `width` processors, after their polygon
    /// spans, with DSF and FSF clear as `ClearLine` leaves them); the flags start at 0.
    pub fn load(&mut self, band: &[ProcState], width: usize) {
        assert!(
            width > 0 && band.len().is_multiple_of(width),
            "whole rows of {width}"
        );
        debug_assert!(band.iter().all(|s| !s.dsf && !s.fsf), "flags not clear");
        self.width = width;
        let p = &mut self.planes;
        p.zb.clear();
        p.zb.extend(band.iter().map(|s| s.zb));
        p.dsf.clear();
        p.dsf.resize(band.len(), 0);
        p.fsf.clear();
        p.fsf.resize(band.len(), 0);
        self.open.clear();
        self.open.resize(band.len() / width, NO_WORDS);
        self.cols = (0, 0);
        self.blocks = 0;
    }

    /// Fills [`BandFlags::zb_max`]'s table from the band's ZB: the greatest per column,
    /// per block of columns, then per run of `2^k` blocks.
    fn zb_max_table(&mut self) {
        let (w, t, cols) = (self.width, &mut self.zb_max, &mut self.zb_cols);
        cols.clear();
        cols.resize(w, 0);
        // As i32, whose greatest of two vectorises without SSE4.1: ZB ≤ Z_FAR < 2^24 (it
        // starts there and only ever takes a smaller depth).
        debug_assert!(self
            .planes
            .zb
            .iter()
            .all(|&z| z <= pixelproc_formats::Z_FAR));
        for row in self.planes.zb.chunks_exact(w) {
            for (m, &z) in cols.iter_mut().zip(row) {
                *m = (*m).max(z as i32);
            }
        }
        let n = w.div_ceil(ZB_BLOCK);
        self.blocks = n;
        t.clear();
        t.extend(
            cols.chunks(ZB_BLOCK)
                .map(|c| c.iter().fold(0, |m, &z| m.max(z as u32))),
        );
        self.zb_least_block = t.iter().fold(u32::MAX, |m, &z| m.min(z));
        let mut run = 1;
        while 2 * run <= n {
            let k = t.len() - n;
            for i in 0..n {
                let far = t[k + (i + run).min(n - 1)];
                t.push(t[k + i].max(far));
            }
            run *= 2;
        }
    }

    /// At least the greatest ZB on columns `lo..=hi` (`lo ≤ hi < width`) of the band's
    /// rows: a word whose depth is at least this on every pixel toggles none of them.
    pub fn zb_max(&mut self, lo: usize, hi: usize) -> u32 {
        self.make_table();
        self.zb_max_of(lo, hi)
    }

    /// Whether a word on columns `lo..=hi` whose depth (`Z >> Z_FRAC`) is at least
    /// `depth` on every pixel lies behind ZB there on all the band's rows, so toggles
    /// nothing ([`BandFlags::zb_max`], looked up only when its least value allows).
    #[inline]
    pub fn behind(&mut self, lo: usize, hi: usize, depth: i64) -> bool {
        self.make_table();
        depth >= self.zb_least_block as i64 && depth >= self.zb_max_of(lo, hi) as i64
    }

    /// Makes [`BandFlags::zb_max`]'s table, the first time it is needed after a load.
    #[inline]
    fn make_table(&mut self) {
        if self.blocks == 0 {
            self.zb_max_table();
        }
    }

    /// [`BandFlags::zb_max`] from the table.
    #[inline]
    fn zb_max_of(&self, lo: usize, hi: usize) -> u32 {
        debug_assert!(lo <= hi && hi < self.width, "columns {lo}..={hi}");
        let (a, b) = (lo / ZB_BLOCK, hi / ZB_BLOCK);
        // Two runs of 2^k blocks that together cover blocks a..=b exactly.
        let k = (b - a + 1).ilog2() as usize;
        let level = k * self.blocks;
        let t = &self.zb_max;
        t[level + a].max(t[level + b + 1 - (1 << k)])
    }

    /// The band's rows.
    pub fn rows(&self) -> usize {
        self.open.len()
    }

    /// Each row's range of the columns that may hold a flag, as indices into the planes
    /// (the iterator holds copies, so the planes may be changed while it runs).
    fn dirty(&self) -> impl Iterator<Item = std::ops::Range<usize>> + use<> {
        let ((lo, hi), w) = (self.cols, self.width);
        (0..self.rows()).map(move |r| r * w + lo..r * w + hi)
    }

    /// `ClearFlags` on every row: `DSF := 0; FSF := 0`.
    pub fn clear(&mut self) {
        for k in self.dirty() {
            self.planes.dsf[k.clone()].fill(0);
            self.planes.fsf[k].fill(0);
        }
        self.cols = (0, 0);
    }

    /// Takes columns `lo..hi` into the range that may hold flags.
    #[inline]
    fn reach(&mut self, lo: usize, hi: usize) {
        self.cols = if self.cols.0 == self.cols.1 {
            (lo, hi)
        } else {
            (self.cols.0.min(lo), self.cols.1.max(hi))
        };
    }

    /// An SP word of the current volume on row `r` of the band: `DSF := ¬DSF` on its
    /// columns where it lies in front of ZB. Its columns are on the row (`xl ≤ xr <
    /// width`, as a shadow polygon's words are made).
    #[inline]
    pub fn toggle(&mut self, r: usize, w: &SpanWord) {
        let (xl, xr) = (w.xl as usize, w.xr as usize);
        debug_assert!(xl <= xr && xr < self.width, "columns {xl}..={xr}");
        let o = &mut self.open[r];
        *o = (o.0 + 1, o.1.min(w.xl), o.2.max(w.xr));
        let (a, b) = (r * self.width + xl, r * self.width + xr);
        toggle_in_front(
            &self.planes.zb[a..=b],
            &mut self.planes.dsf[a..=b],
            w.zl as i64,
            w.dz,
        );
    }

    /// An SP word of the current volume on row `r` of the band that lies behind ZB on
    /// every pixel, so toggles nothing: counted as [`BandFlags::toggle`] counts it, but
    /// it neither changes a flag nor widens the columns its volume's end takes in (on
    /// them `FSF ∨ DSF = FSF` already, as on every pixel no word toggled).
    #[inline]
    pub fn count_behind(&mut self, r: usize) {
        self.open[r].0 += 1;
    }

    /// Ends the current volume on row `r` and tells how many words it had there (those
    /// [`BandFlags::count_behind`] counted included). With
    /// `inside` (the row's first span is IF) DSF is inverted on the whole row and FSF
    /// takes DSF on the whole row; otherwise FSF takes DSF on the words' columns (nothing
    /// without words).
    pub fn end_volume(&mut self, r: usize, inside: bool) -> u32 {
        let (made, lo, hi) = std::mem::replace(&mut self.open[r], NO_WORDS);
        let row = r * self.width;
        let (a, b) = if inside {
            let dsf = &mut self.planes.dsf[row..row + self.width];
            dsf.iter_mut().for_each(|d| *d ^= 1);
            self.reach(0, self.width);
            (0, self.width)
        } else if lo <= hi {
            self.reach(lo as usize, hi as usize + 1);
            (lo as usize, hi as usize + 1)
        } else {
            // No word, or only words behind ZB ([`BandFlags::count_behind`]).
            return made;
        };
        self.planes.absorb(row + a, row + b);
        made
    }

    /// The sample's latching control `c` (`AccumulateShadow` or `LatchShadow`) on the
    /// band's processors, from FSF (only where it may be 1: elsewhere it changes nothing).
    pub fn latch(&self, c: &Command, band: &mut [ProcState]) {
        for k in self.dirty() {
            latch_from(c, &mut band[k.clone()], &self.planes.fsf[k]);
        }
    }

    /// Writes the flags back into the band's processors (ZB is never changed here): only
    /// where they may be 1, since elsewhere they are 0 and the processors' are clear.
    pub fn store(&self, band: &mut [ProcState]) {
        for k in self.dirty() {
            store_flags(
                &mut band[k.clone()],
                &self.planes.dsf[k.clone()],
                &self.planes.fsf[k],
            );
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Lcg64;

    /// [`BandFlags::zb_max`] is the greatest ZB over the band's rows on exactly the
    /// blocks of [`ZB_BLOCK`] columns that hold columns `lo..=hi` (so at least the
    /// greatest on the columns themselves), and [`BandFlags::behind`] compares with it:
    /// every column range of random bands, by a search of the processors.
    #[test]
    fn zb_max_is_the_greatest_on_the_blocks_of_the_columns() {
        let mut rng = Lcg64(0x2b_3a7);
        let mut r = |m: u64| rng.step() % m;
        let mut flags = BandFlags::default();
        for case in 0..60 {
            let (w, n) = (1 + r(70) as usize, 1 + r(17) as usize);
            // Small depths (many ties) or any up to Z_FAR.
            let top = if case % 2 == 0 {
                9
            } else {
                pixelproc_formats::Z_FAR as u64 + 1
            };
            let band: Vec<ProcState> = (0..w * n)
                .map(|_| ProcState {
                    zb: r(top) as u32,
                    ..Default::default()
                })
                .collect();
            flags.load(&band, w);
            for lo in 0..w {
                for hi in lo..w {
                    let cols = lo / ZB_BLOCK * ZB_BLOCK..((hi / ZB_BLOCK + 1) * ZB_BLOCK).min(w);
                    let want = (0..n)
                        .flat_map(|j| band[j * w + cols.start..j * w + cols.end].iter())
                        .map(|s| s.zb)
                        .max()
                        .unwrap();
                    assert_eq!(
                        flags.zb_max(lo, hi),
                        want,
                        "case {case}: {lo}..={hi} of {w}"
                    );
                    for d in [want as i64 - 1, want as i64, want as i64 + 1] {
                        assert_eq!(flags.behind(lo, hi, d), d >= want as i64, "{lo}..={hi}");
                    }
                }
            }
        }
    }

    /// [`BandFlags`], volume by volume, leaves every processor as [`RowFlags::run`] leaves
    /// it after the same commands row by row: random ZB, counters and masks, flags clear
    /// (as `ClearLine` leaves them); one to three light samples, each `ClearFlags`,
    /// volumes of up to four SP words a row (none on some rows) on the whole row or a part
    /// of it, the near plane inside some (the row's first word made IF, or an empty IF),
    /// each ended by EV (the last word, or an empty EV after an IF or no word) or a
    /// `Check` of the words' columns (the whole line with IF), then `AccumulateShadow` or
    /// `LatchShadow`; tile widths 1..40, for the tiles `RowFlags` routes EV to.
    #[test]
    fn band_flags_leave_what_row_flags_leave() {
        let mut rng = Lcg64(0x5a11_f1a9);
        let mut r = |m: u64| rng.step() % m;
        let (mut toggled, mut shadowed) = (0, 0);
        for case in 0..1_500 {
            let (w, n, tile) = (1 + r(90) as usize, 1 + r(5) as usize, 1 + r(40) as usize);
            let check = case % 3 == 0;
            // The columns the words may reach: the whole row, or a part of it.
            let c0 = if case % 2 == 0 { 0 } else { r(w as u64) as u16 };
            let c1 = c0 + 1 + r((w - c0 as usize) as u64) as u16;
            let mut band: Vec<ProcState> = (0..w * n)
                .map(|_| ProcState {
                    zb: r(600) as u32,
                    count: r(256) as u8,
                    mask: r(256) as u8,
                    ..Default::default()
                })
                .collect();
            let mut want = band.clone();
            let mut cmds = vec![Vec::new(); n];
            let mut flags = BandFlags::default();
            flags.load(&band, w);
            for _ in 0..1 + r(3) {
                let end = match r(3) {
                    0 => Command::AccumulateShadow,
                    _ => Command::LatchShadow { bit: r(8) as u8 },
                };
                flags.clear();
                cmds.iter_mut().for_each(|c| c.push(Command::ClearFlags));
                for _ in 0..1 + r(6) {
                    let inside = r(6) == 0;
                    for (row, out) in cmds.iter_mut().enumerate() {
                        let words = [0, 0, 1, 1, 2, 3, 4][r(7) as usize];
                        if words == 0 && !inside {
                            continue;
                        }
                        let start = out.len();
                        for _ in 0..words {
                            let xl = c0 + r((c1 - c0) as u64) as u16;
                            let xr = (xl + r(12) as u16).min(c1 - 1);
                            let sw = SpanWord {
                                attr: Attr::Sp,
                                xl,
                                xr,
                                zl: (r(600) << Z_FRAC) + r(1 << Z_FRAC),
                                dz: r(40 << Z_FRAC) as i64 - (20 << Z_FRAC),
                                ..Default::default()
                            };
                            flags.toggle(row, &sw);
                            out.push(Command::Span(sw));
                        }
                        assert_eq!(flags.end_volume(row, inside), words as u32);
                        let span = |c: &Command| match c {
                            Command::Span(s) => Some((s.xl, s.xr)),
                            _ => None,
                        };
                        let lo = out[start..].iter().filter_map(span).map(|s| s.0).min();
                        let hi = out[start..].iter().filter_map(span).map(|s| s.1).max();
                        let empty = SpanWord {
                            xl: 1,
                            xr: 0,
                            ..Default::default()
                        };
                        if inside {
                            match out.get_mut(start) {
                                Some(Command::Span(s)) => s.attr = Attr::If,
                                _ => out.push(Command::Span(SpanWord {
                                    attr: Attr::If,
                                    ..empty
                                })),
                            }
                        }
                        if check {
                            let (xl, xr) = match (inside, lo, hi) {
                                (false, Some(lo), Some(hi)) => (lo, hi),
                                _ => (0, w as u16 - 1),
                            };
                            out.push(Command::Check { xl, xr });
                        } else {
                            let own = out.len() > start;
                            match out.last_mut() {
                                Some(Command::Span(s)) if own && s.attr == Attr::Sp => {
                                    s.attr = Attr::Ev
                                }
                                _ => out.push(Command::Span(SpanWord {
                                    attr: Attr::Ev,
                                    ..empty
                                })),
                            }
                        }
                    }
                }
                flags.latch(&end, &mut band);
                cmds.iter_mut().for_each(|c| c.push(end));
            }
            flags.store(&mut band);
            let mut rf = RowFlags::default();
            for (row, c) in want.chunks_mut(w).zip(&cmds) {
                rf.run(row, c, tile);
            }
            assert_eq!(band, want, "case {case}: width {w}, rows {n}, tile {tile}");
            toggled += want.iter().filter(|s| s.dsf).count();
            shadowed += want.iter().filter(|s| s.fsf).count();
        }
        assert!(
            toggled > 10_000 && shadowed > 10_000,
            "{toggled} {shadowed}"
        );
    }
}
