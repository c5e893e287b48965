//! The offset ROM of the A-buffer mask search unit (seed 000, JP2569952B2, Fig. 6 blocks 7
//! "offset reader" and 8 "offset table ROM"; Tables 1 and 2).
//!
//! The seed addresses the table with the raw AND result (`2^(n·m)` words). The golden model
//! (`pixelproc_formats::abuffer`, "Offset ROM (compacted)") compacts it: a first-hit AND
//! result is a non-empty subset of one search line, whose two *end* subpixels are those of
//! its most and least significant set bits. The hardware therefore is
//!
//! 1. two priority selectors that isolate the most and the least significant set bit as
//!    one-hot vectors, in two levels so that no path crosses the whole mask: the mask is cut
//!    into groups of `g = n` bits (a subpixel row); R1 isolates the highest and lowest set
//!    bit inside each group (`x & !(bits above in the group)`, `x & !(bits below)`, each an
//!    OR of at most `g − 1` shifted copies) and marks every bit of a non-empty group; R2
//!    keeps a group's bit only if no non-empty group lies above (below) it;
//! 2. the `n·m`-entry table of 8-bit [`SubOffset`] words, read at both one-hot
//!    addresses as an AND-OR per output bit (bit `b` of the word is set iff the selected
//!    entry has bit `b`: one constant column mask per bit), and `pair = (msb ≠ lsb)`;
//!    in three levels: R3 ORs inside each group, R4 across each quad of four groups
//!    (one LUT4 per word bit and quad), R5 across the quads (two for 8×8, one for 4×4).
//!
//! The output is the golden [`RomWord`] packing, 17 bits: `[7:0]` end 1 (most significant
//! set bit), `[15:8]` end 2 (least significant), `[16]` pair. An all-zero input reads 0
//! (both ends (0, 0), no pair); the search unit only uses the ROM after a hit.
//!
//! Timing: five register stages, each at most a few LUT levels deep. `and_in` is sampled
//! at rising edge `E` into the R1 registers, R2 at `E + 1`, R3 at `E + 2`, R4 at `E + 3`,
//! the word register at `E + 4`; the word shows after it ([`ROM_LATENCY`] = 5). R4 splits
//! what was one stage of two LUT levels (the OR of eight group reads at 8×8), whose
//! registers the placer could spread across the die. `rst` (synchronous) clears every
//! stage.
//!
//! [`SubOffset`]: pixelproc_formats::abuffer::SubOffset
//! [`RomWord`]: pixelproc_formats::abuffer::RomWord

use pixelproc_formats::abuffer::{offset_rom_table, MaskSize, ROM_WORD_BITS};
use rust_hdl::prelude::*;

/// Clocks from `and_in` to `word`.
pub const ROM_LATENCY: usize = 5;

/// Width of the ROM word (the golden `RomWord`).
pub const WORD_BITS: usize = ROM_WORD_BITS as usize;

/// The compacted offset ROM for masks of `B = n·m` bits.
#[derive(LogicBlock)]
pub struct OffsetRom<const B: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// The AND result (first hit) addressing the ROM.
    pub and_in: Signal<In, Bits<B>>,
    /// The ROM word, [`ROM_LATENCY`] clocks after `and_in`.
    pub word: Signal<Out, Bits<WORD_BITS>>,
    /// R1: highest / lowest set bit of each group, and every bit of a non-empty group.
    gmsb_r: DFF<Bits<B>>,
    glsb_r: DFF<Bits<B>>,
    grp_r: DFF<Bits<B>>,
    /// R2: the one-hot highest / lowest set bit.
    hi_r: DFF<Bits<B>>,
    lo_r: DFF<Bits<B>>,
    /// R3: per word bit `b`, bit `i·g` of `p1[b]` (`p2[b]`) is bit `b` of the table entry
    /// group `i` selects for end 1 (end 2); `px_r` bit `i·g`: group `i` holds one end
    /// and not the other. Only those bits are kept; Yosys removes the others (constant 0).
    p1: Vec<DFF<Bits<B>>>,
    p2: Vec<DFF<Bits<B>>>,
    px_r: DFF<Bits<B>>,
    /// R4: the same, ORed over each quad of groups and gathered at the quad's first bit
    /// (bit `q·4g`).
    q1: Vec<DFF<Bits<B>>>,
    q2: Vec<DFF<Bits<B>>>,
    qx_r: DFF<Bits<B>>,
    word_r: DFF<Bits<WORD_BITS>>,
    /// Column masks: entry `b` holds the bit indices whose ROM word has bit `b` set.
    k_col: Vec<Constant<Bits<B>>>,
    /// Shift distances inside a group: 1 .. g − 1.
    k_sh_in: Vec<Constant<Bits<8>>>,
    /// Bits `j` whose bit `j + s` (`s` = `k_sh_in[i]`) is in the same group.
    k_keep_up: Vec<Constant<Bits<B>>>,
    /// Bits `j` whose bit `j − s` is in the same group.
    k_keep_dn: Vec<Constant<Bits<B>>>,
    /// Shift distances between groups: g, 2g, ... below `B`.
    k_sh_grp: Vec<Constant<Bits<8>>>,
    /// Shift distances inside a quad of groups: g, 2g, 3g (those below `B`).
    k_sh_quad: Vec<Constant<Bits<8>>>,
    /// The first bit of every quad of groups.
    k_qfirst: Constant<Bits<B>>,
    /// One-hot word bits `1 << i`, `i = 0..8`.
    k_bit1: Vec<Constant<Bits<WORD_BITS>>>,
    /// One-hot word bits `1 << (i + 8)`, `i = 0..8`.
    k_bit2: Vec<Constant<Bits<WORD_BITS>>>,
    k_pair: Constant<Bits<WORD_BITS>>,
    k_zero_b: Constant<Bits<B>>,
    k_zero_w: Constant<Bits<WORD_BITS>>,
    /// The first bit of every group.
    k_first: Constant<Bits<B>>,
    red: Signal<Local, Bits<B>>,
    above: Signal<Local, Bits<B>>,
    below: Signal<Local, Bits<B>>,
    t1: Signal<Local, Bits<B>>,
    t2: Signal<Local, Bits<B>>,
    w: Signal<Local, Bits<WORD_BITS>>,
}

impl<const B: usize> OffsetRom<B> {
    /// The ROM generated for `size` (`size.bits()` must equal `B`; checked by the callers'
    /// constructors).
    pub fn new(size: MaskSize) -> Self {
        assert_eq!(
            size.bits() as usize,
            B,
            "mask size does not match the block width"
        );
        let rom = offset_rom_table(size);
        let k_col = (0..8)
            .map(|b| {
                let m = rom
                    .iter()
                    .enumerate()
                    .filter(|(_, &w)| (w >> b) & 1 == 1)
                    .fold(0u64, |a, (i, _)| a | (1u64 << i));
                Constant::new(m.to_bits())
            })
            .collect();
        let g = size.n() as usize;
        assert!(
            g >= 2 && B.is_multiple_of(g),
            "group size must divide the mask width"
        );
        let ones = |f: &dyn Fn(usize) -> bool| -> u64 {
            (0..B).filter(|&j| f(j)).fold(0u64, |a, j| a | (1u64 << j))
        };
        let k_sh_in = (1..g)
            .map(|s| Constant::new((s as u64).to_bits()))
            .collect();
        let k_keep_up = (1..g)
            .map(|s| Constant::new(ones(&|j| j % g + s < g).to_bits()))
            .collect();
        let k_keep_dn = (1..g)
            .map(|s| Constant::new(ones(&|j| j % g >= s).to_bits()))
            .collect();
        let k_sh_grp = (1..B / g)
            .map(|t| Constant::new(((t * g) as u64).to_bits()))
            .collect();
        let k_sh_quad = (1..4.min(B / g))
            .map(|t| Constant::new(((t * g) as u64).to_bits()))
            .collect();
        OffsetRom {
            clock: Default::default(),
            rst: Default::default(),
            and_in: Default::default(),
            word: Default::default(),
            gmsb_r: Default::default(),
            glsb_r: Default::default(),
            grp_r: Default::default(),
            hi_r: Default::default(),
            lo_r: Default::default(),
            p1: super::dff_line(8),
            p2: super::dff_line(8),
            px_r: Default::default(),
            q1: super::dff_line(8),
            q2: super::dff_line(8),
            qx_r: Default::default(),
            word_r: Default::default(),
            k_col,
            k_sh_in,
            k_keep_up,
            k_keep_dn,
            k_sh_grp,
            k_sh_quad,
            k_qfirst: Constant::new(ones(&|j| j % (4 * g) == 0).to_bits()),
            k_bit1: (0..8)
                .map(|i| Constant::new((1u64 << i).to_bits()))
                .collect(),
            k_bit2: (0..8)
                .map(|i| Constant::new((1u64 << (i + 8)).to_bits()))
                .collect(),
            k_pair: Constant::new((1u64 << 16).to_bits()),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_w: Constant::new(0u64.to_bits()),
            k_first: Constant::new(ones(&|j| j % g == 0).to_bits()),
            red: Default::default(),
            above: Default::default(),
            below: Default::default(),
            t1: Default::default(),
            t2: Default::default(),
            w: Default::default(),
        }
    }
}

impl<const B: usize> Logic for OffsetRom<B> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, gmsb_r, glsb_r, grp_r, hi_r, lo_r, px_r, qx_r, word_r);
        for b in 0..self.p1.len() {
            self.p1[b].clock.next = self.clock.val();
            self.p2[b].clock.next = self.clock.val();
            self.p1[b].d.next = self.p1[b].q.val();
            self.p2[b].d.next = self.p2[b].q.val();
            self.q1[b].clock.next = self.clock.val();
            self.q2[b].clock.next = self.clock.val();
            self.q1[b].d.next = self.q1[b].q.val();
            self.q2[b].d.next = self.q2[b].q.val();
        }
        // R1: inside each group, above[j] = OR of the group's bits above j, below[j] of
        // those below.
        self.above.next = self.k_zero_b.val();
        self.below.next = self.k_zero_b.val();
        for i in 0..self.k_sh_in.len() {
            self.above.next = self.above.val()
                | ((self.and_in.val() >> self.k_sh_in[i].val()) & self.k_keep_up[i].val());
            self.below.next = self.below.val()
                | ((self.and_in.val() << self.k_sh_in[i].val()) & self.k_keep_dn[i].val());
        }
        self.gmsb_r.d.next = self.and_in.val() & (!self.above.val());
        self.glsb_r.d.next = self.and_in.val() & (!self.below.val());
        self.grp_r.d.next = (self.and_in.val() | self.above.val()) | self.below.val();
        // R2: keep a group's highest (lowest) bit if no group above (below) is non-empty.
        self.above.next = self.k_zero_b.val();
        self.below.next = self.k_zero_b.val();
        for i in 0..self.k_sh_grp.len() {
            self.above.next = self.above.val() | (self.grp_r.q.val() >> self.k_sh_grp[i].val());
            self.below.next = self.below.val() | (self.grp_r.q.val() << self.k_sh_grp[i].val());
        }
        self.hi_r.d.next = self.gmsb_r.q.val() & (!self.above.val());
        self.lo_r.d.next = self.glsb_r.q.val() & (!self.below.val());
        // R3: read the table at both one-hot addresses (AND-OR per word bit), first
        // inside each group (an OR of g bits, gathered at the group's first bit).
        for b in 0..self.k_col.len() {
            self.t1.next = self.hi_r.q.val() & self.k_col[b].val();
            self.red.next = self.t1.val();
            for i in 0..self.k_sh_in.len() {
                self.red.next = self.red.val()
                    | ((self.t1.val() >> self.k_sh_in[i].val()) & self.k_keep_up[i].val());
            }
            self.p1[b].d.next = self.red.val() & self.k_first.val();
            self.t2.next = self.lo_r.q.val() & self.k_col[b].val();
            self.red.next = self.t2.val();
            for i in 0..self.k_sh_in.len() {
                self.red.next = self.red.val()
                    | ((self.t2.val() >> self.k_sh_in[i].val()) & self.k_keep_up[i].val());
            }
            self.p2[b].d.next = self.red.val() & self.k_first.val();
        }
        // pair = (msb ≠ lsb): some group holds exactly one of the two one-hot bits.
        self.t1.next = self.hi_r.q.val() ^ self.lo_r.q.val();
        self.red.next = self.t1.val();
        for i in 0..self.k_sh_in.len() {
            self.red.next = self.red.val()
                | ((self.t1.val() >> self.k_sh_in[i].val()) & self.k_keep_up[i].val());
        }
        self.px_r.d.next = self.red.val() & self.k_first.val();
        // R4: across each quad of groups (bits i·g of a quad gathered at its first bit).
        for b in 0..self.p1.len() {
            self.red.next = self.p1[b].q.val();
            for i in 0..self.k_sh_quad.len() {
                self.red.next = self.red.val() | (self.p1[b].q.val() >> self.k_sh_quad[i].val());
            }
            self.q1[b].d.next = self.red.val() & self.k_qfirst.val();
            self.red.next = self.p2[b].q.val();
            for i in 0..self.k_sh_quad.len() {
                self.red.next = self.red.val() | (self.p2[b].q.val() >> self.k_sh_quad[i].val());
            }
            self.q2[b].d.next = self.red.val() & self.k_qfirst.val();
        }
        self.red.next = self.px_r.q.val();
        for i in 0..self.k_sh_quad.len() {
            self.red.next = self.red.val() | (self.px_r.q.val() >> self.k_sh_quad[i].val());
        }
        self.qx_r.d.next = self.red.val() & self.k_qfirst.val();
        // R5: then across the quads.
        self.w.next = self.k_zero_w.val();
        for b in 0..self.k_bit1.len() {
            if self.q1[b].q.val() != self.k_zero_b.val() {
                self.w.next = self.w.val() | self.k_bit1[b].val();
            }
            if self.q2[b].q.val() != self.k_zero_b.val() {
                self.w.next = self.w.val() | self.k_bit2[b].val();
            }
        }
        if self.qx_r.q.val() != self.k_zero_b.val() {
            self.w.next = self.w.val() | self.k_pair.val();
        }
        self.word_r.d.next = self.w.val();
        if self.rst.val() {
            self.gmsb_r.d.next = self.k_zero_b.val();
            self.glsb_r.d.next = self.k_zero_b.val();
            self.grp_r.d.next = self.k_zero_b.val();
            self.hi_r.d.next = self.k_zero_b.val();
            self.lo_r.d.next = self.k_zero_b.val();
            self.px_r.d.next = self.k_zero_b.val();
            self.qx_r.d.next = self.k_zero_b.val();
            for b in 0..self.p1.len() {
                self.p1[b].d.next = self.k_zero_b.val();
                self.p2[b].d.next = self.k_zero_b.val();
                self.q1[b].d.next = self.k_zero_b.val();
                self.q2[b].d.next = self.k_zero_b.val();
            }
            self.word_r.d.next = self.k_zero_w.val();
        }
        self.word.next = self.word_r.q.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives one value through the stages and returns the word.
    fn read<const B: usize>(rom: &mut OffsetRom<B>, x: u64) -> u32 {
        for _ in 0..ROM_LATENCY {
            rom.and_in.next = x.to_bits();
            rom.clock.next = Clock { clk: true };
            assert!(simulate(rom, 100));
            rom.clock.next = Clock { clk: false };
            assert!(simulate(rom, 100));
        }
        rom.word.val().to_u64() as u32
    }

    #[test]
    fn seed_tables_1_and_2() {
        // Seed 000, Tables 1 and 2 (4×4): 0100H → (+0.375, +0.125) alone; 0842H → ends
        // (−0.375, +0.125) and (+0.125, −0.375). In units of 1/8 px: (+3, +1); (−3, +1),
        // (+1, −3). Word: [3:0] dx1, [7:4] dy1, [11:8] dx2, [15:12] dy2, [16] pair.
        let mut rom = OffsetRom::<16>::new(MaskSize::S4X4);
        rom.connect_all();
        let f = |d: i32| (d as u32) & 0xF;
        let w0100 = f(3) | f(1) << 4 | f(3) << 8 | f(1) << 12;
        assert_eq!(read(&mut rom, 0x0100), w0100);
        let w0842 = f(-3) | f(1) << 4 | f(1) << 8 | f(-3) << 12 | 1 << 16;
        assert_eq!(read(&mut rom, 0x0842), w0842);
        assert_eq!(read(&mut rom, 0), 0);
    }

    #[test]
    fn ends_are_extreme_bits_for_every_pair_8x8() {
        // Independent statement: end 1 is the subpixel of the highest set bit, end 2 of the
        // lowest; subpixel of bit b: column n−1−b%n, row b/n; offset 2c+1−n, 2r+1−m.
        let mut rom = OffsetRom::<64>::new(MaskSize::S8X8);
        rom.connect_all();
        let off = |b: u32| {
            let (c, r) = (7 - b % 8, b / 8);
            let (dx, dy) = (2 * c as i32 - 7, 2 * r as i32 - 7);
            ((dx as u32) & 0xF) | ((dy as u32) & 0xF) << 4
        };
        for hi in (0..64u32).step_by(3) {
            for lo in (0..=hi).step_by(5) {
                let x =
                    (1u64 << hi) | (1u64 << lo) | if hi > lo + 1 { 1u64 << (lo + 1) } else { 0 };
                let want = off(hi) | off(lo) << 8 | ((hi != lo) as u32) << 16;
                assert_eq!(read(&mut rom, x), want, "hi {hi} lo {lo}");
            }
        }
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check(
            "pixelproc_rtl_offset_rom",
            OffsetRom::<16>::new(MaskSize::S4X4),
        );
    }
}
