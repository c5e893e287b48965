//! The A-buffer mask search unit with its offset ROM and depth calculator (seed 000,
//! JP2569952B2, claim 2 and Fig. 6), in two variants.
//!
//! Blocks of Fig. 6 and where they are here: the start corner (2) is an input (the caller
//! picks it from the slope signs, `Corner::of_min`); the search mask generator (3) is a
//! generated constant table per corner and line (`search_mask_table`, line `k` of family
//! `(p, q)` is `{(c, r) : p·c' + q·r' = k}`, the seed's diagonal band is `(1, 1)`); the AND
//! unit (4), zero detector (5) and mover (6) are the per-line logic; the offset reader (7)
//! and ROM (8) are [`OffsetRom`] (compacted, see its module); the depth calculator (10)
//! is [`DepthCalc`], `z = zc + sx·dx + sy·dy` evaluated at the one or two end offsets with
//! min and max.
//!
//! * [`MaskSearchIter`]: one search line per clock, the seed's flowchart. Its step ports
//!   (`active`, `line`, `search_mask`, `and_result`, `zero`, `moved`, `hit`, `done`) are
//!   exactly the golden `SearchUnit::step` output of every clock.
//! * [`MaskSearchPipe`]: one stage per search line, a new mask accepted every clock.
//!
//! Both feed the same back end ([`SearchBackEnd`]: ROM, depth calculator, result
//! registers). All arithmetic is on `Bits` (two's complement modulo `2^53`); formats are
//! those of `pixelproc_formats::abuffer`: masks in its bit order, corner code (bit 0 right,
//! bit 1 bottom), plane fields Q.12 48-bit two's complement, ROM word 17 bits, depths Q.12
//! 53-bit two's complement. Every register has a synchronous reset (`rst`, to zero).
//! `docs/rtl_mask_search.md` gives ports, handshakes, latencies and synthesis figures.

use crate::offset_rom::{OffsetRom, ROM_LATENCY, WORD_BITS};
use pixelproc_formats::abuffer::{search_mask_table, Corner, MaskSize, SearchFamily, PLANE_BITS};
use rust_hdl::prelude::*;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Width of a plane field (`zc`, `sx`, `sy`) on the ports.
pub const PB: usize = PLANE_BITS as usize;
/// Width of a computed depth: `|zc| + 7|sx| + 7|sy| < 15·2^47 < 2^51`, plus sign and one
/// bit of headroom for the min/max difference.
pub const Z_BITS: usize = 53;
const _: () = assert!(
    PB == 48 && Z_BITS == 53,
    "DepthCalc uses literal bit 47 and 52"
);
/// Width of the line index and of the step count.
pub const LINE_BITS: usize = 5;
/// Clocks through the depth calculator.
pub const DEPTH_LATENCY: usize = 4;
/// Clocks from a search result (the clock its last line is tested) to the result ports.
pub const BACK_LATENCY: usize = ROM_LATENCY + DEPTH_LATENCY;

/// Why a search unit cannot be built.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum MaskSearchError {
    /// The mask size does not match the block's mask width `B`.
    #[error("mask size {size} has {bits} subpixels, the block is built for {width}")]
    Width {
        /// The size asked for.
        size: MaskSize,
        /// Its subpixel count.
        bits: u32,
        /// The block's `B`.
        width: usize,
    },
    /// The family has more lines than the 5-bit line counter holds.
    #[error("search family ({p}, {q}) has {lines} lines for {size}; at most 31 supported")]
    TooManyLines {
        /// Column weight.
        p: u8,
        /// Row weight.
        q: u8,
        /// Mask size.
        size: MaskSize,
        /// Lines needed.
        lines: u32,
    },
    /// Verilog export is built for 4×4 (`B = 16`) and 8×8 (`B = 64`) masks only.
    #[error("no Verilog export for mask size {0} (4x4 and 8x8 are built)")]
    NoExport(MaskSize),
    /// Writing a file failed.
    #[error("writing Verilog: {0}")]
    Io(String),
}

fn check(size: MaskSize, family: SearchFamily, b: usize) -> Result<u32, MaskSearchError> {
    if size.bits() as usize != b {
        return Err(MaskSearchError::Width {
            size,
            bits: size.bits(),
            width: b,
        });
    }
    let lines = family.lines(size);
    if lines > 31 {
        return Err(MaskSearchError::TooManyLines {
            p: family.p,
            q: family.q,
            size,
            lines,
        });
    }
    Ok(lines)
}

/// The two architectures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// One search line per clock ([`MaskSearchIter`]).
    Iterative,
    /// One stage per line, one mask per clock ([`MaskSearchPipe`]).
    Pipelined,
}

impl Variant {
    /// Both variants.
    pub const ALL: [Variant; 2] = [Variant::Iterative, Variant::Pipelined];
    /// Short name (`iter`, `pipe`).
    pub fn name(self) -> &'static str {
        match self {
            Variant::Iterative => "iter",
            Variant::Pipelined => "pipe",
        }
    }
}

/// The depth calculator: `z = zc + sx·dx + sy·dy` at both ends of a ROM word, then min
/// and max. `dx`, `dy` are the word's 4-bit two's-complement fields, so each product is a
/// shift-and-add of the slope (`d = −8·d3 + 4·d2 + 2·d1 + d0`), no multiplier.
///
/// Pipeline ([`DEPTH_LATENCY`] = 4 register stages, one adder level each): D1 the two
/// partial sums per product (`d0·s + 2·d1·s`, `4·d2·s − 8·d3·s`), D2 the products, D3
/// `zc + px + py` (carry-save then one adder), D4 the compare `z1 − z2 < 0` and min/max.
/// Inputs sampled at edge `E` show on the outputs after edge `E + 3`.
#[derive(LogicBlock)]
pub struct DepthCalc {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// Plane depth at the pixel centre, Q.12, 48-bit two's complement.
    pub zc: Signal<In, Bits<PB>>,
    /// Depth change per `1/(2n)` px in x.
    pub sx: Signal<In, Bits<PB>>,
    /// Depth change per `1/(2m)` px in y.
    pub sy: Signal<In, Bits<PB>>,
    /// ROM word (end 1 `[7:0]`, end 2 `[15:8]`, pair `[16]`).
    pub word: Signal<In, Bits<WORD_BITS>>,
    /// Depth at end 1.
    pub z1: Signal<Out, Bits<Z_BITS>>,
    /// Depth at end 2 (equal to `z1` when the word has no pair).
    pub z2: Signal<Out, Bits<Z_BITS>>,
    /// `min(z1, z2)` (signed).
    pub zmin: Signal<Out, Bits<Z_BITS>>,
    /// `max(z1, z2)` (signed).
    pub zmax: Signal<Out, Bits<Z_BITS>>,
    xa1: DFF<Bits<Z_BITS>>,
    xb1: DFF<Bits<Z_BITS>>,
    ya1: DFF<Bits<Z_BITS>>,
    yb1: DFF<Bits<Z_BITS>>,
    xa2: DFF<Bits<Z_BITS>>,
    xb2: DFF<Bits<Z_BITS>>,
    ya2: DFF<Bits<Z_BITS>>,
    yb2: DFF<Bits<Z_BITS>>,
    zc_1: DFF<Bits<Z_BITS>>,
    px1: DFF<Bits<Z_BITS>>,
    py1: DFF<Bits<Z_BITS>>,
    px2: DFF<Bits<Z_BITS>>,
    py2: DFF<Bits<Z_BITS>>,
    zc_2: DFF<Bits<Z_BITS>>,
    z1_3: DFF<Bits<Z_BITS>>,
    z2_3: DFF<Bits<Z_BITS>>,
    z1_r: DFF<Bits<Z_BITS>>,
    z2_r: DFF<Bits<Z_BITS>>,
    zmin_r: DFF<Bits<Z_BITS>>,
    zmax_r: DFF<Bits<Z_BITS>>,
    k_sext: Constant<Bits<Z_BITS>>,
    k_zero: Constant<Bits<Z_BITS>>,
    k_one: Constant<Bits<8>>,
    k_two: Constant<Bits<8>>,
    k_three: Constant<Bits<8>>,
    zce: Signal<Local, Bits<Z_BITS>>,
    sxe: Signal<Local, Bits<Z_BITS>>,
    sye: Signal<Local, Bits<Z_BITS>>,
    t0: Signal<Local, Bits<Z_BITS>>,
    t1: Signal<Local, Bits<Z_BITS>>,
    t2: Signal<Local, Bits<Z_BITS>>,
    t3: Signal<Local, Bits<Z_BITS>>,
    cs_s: Signal<Local, Bits<Z_BITS>>,
    cs_c: Signal<Local, Bits<Z_BITS>>,
    diff: Signal<Local, Bits<Z_BITS>>,
}

impl Default for DepthCalc {
    fn default() -> Self {
        Self::new()
    }
}

impl DepthCalc {
    /// A depth calculator.
    pub fn new() -> Self {
        DepthCalc {
            clock: Default::default(),
            rst: Default::default(),
            zc: Default::default(),
            sx: Default::default(),
            sy: Default::default(),
            word: Default::default(),
            z1: Default::default(),
            z2: Default::default(),
            zmin: Default::default(),
            zmax: Default::default(),
            xa1: Default::default(),
            xb1: Default::default(),
            ya1: Default::default(),
            yb1: Default::default(),
            xa2: Default::default(),
            xb2: Default::default(),
            ya2: Default::default(),
            yb2: Default::default(),
            zc_1: Default::default(),
            px1: Default::default(),
            py1: Default::default(),
            px2: Default::default(),
            py2: Default::default(),
            zc_2: Default::default(),
            z1_3: Default::default(),
            z2_3: Default::default(),
            z1_r: Default::default(),
            z2_r: Default::default(),
            zmin_r: Default::default(),
            zmax_r: Default::default(),
            k_sext: Constant::new(((1u64 << Z_BITS) - (1u64 << PB)).to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
            k_one: Constant::new(1u64.to_bits()),
            k_two: Constant::new(2u64.to_bits()),
            k_three: Constant::new(3u64.to_bits()),
            zce: Default::default(),
            sxe: Default::default(),
            sye: Default::default(),
            t0: Default::default(),
            t1: Default::default(),
            t2: Default::default(),
            t3: Default::default(),
            cs_s: Default::default(),
            cs_c: Default::default(),
            diff: Default::default(),
        }
    }
}

impl Logic for DepthCalc {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, xa1, xb1, ya1, yb1, xa2, xb2, ya2, yb2, zc_1, px1, py1, px2, py2, zc_2,
            z1_3, z2_3, z1_r, z2_r, zmin_r, zmax_r
        );
        // Sign extension 48 -> 53 bits (bit 47 = PB - 1; a literal, since a named
        // constant would leak into the Verilog by name).
        self.zce.next = bit_cast::<Z_BITS, PB>(self.zc.val());
        if self.zc.val().get_bit(47) {
            self.zce.next = self.zce.val() | self.k_sext.val();
        }
        self.sxe.next = bit_cast::<Z_BITS, PB>(self.sx.val());
        if self.sx.val().get_bit(47) {
            self.sxe.next = self.sxe.val() | self.k_sext.val();
        }
        self.sye.next = bit_cast::<Z_BITS, PB>(self.sy.val());
        if self.sy.val().get_bit(47) {
            self.sye.next = self.sye.val() | self.k_sext.val();
        }
        // D1: partial sums. End 1: dx = word[3:0], dy = word[7:4]; end 2: [11:8], [15:12].
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(0) {
            self.t0.next = self.sxe.val();
        }
        if self.word.val().get_bit(1) {
            self.t1.next = self.sxe.val() << self.k_one.val();
        }
        if self.word.val().get_bit(2) {
            self.t2.next = self.sxe.val() << self.k_two.val();
        }
        if self.word.val().get_bit(3) {
            self.t3.next = self.sxe.val() << self.k_three.val();
        }
        self.xa1.d.next = self.t0.val() + self.t1.val();
        self.xb1.d.next = self.t2.val() - self.t3.val();
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(4) {
            self.t0.next = self.sye.val();
        }
        if self.word.val().get_bit(5) {
            self.t1.next = self.sye.val() << self.k_one.val();
        }
        if self.word.val().get_bit(6) {
            self.t2.next = self.sye.val() << self.k_two.val();
        }
        if self.word.val().get_bit(7) {
            self.t3.next = self.sye.val() << self.k_three.val();
        }
        self.ya1.d.next = self.t0.val() + self.t1.val();
        self.yb1.d.next = self.t2.val() - self.t3.val();
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(8) {
            self.t0.next = self.sxe.val();
        }
        if self.word.val().get_bit(9) {
            self.t1.next = self.sxe.val() << self.k_one.val();
        }
        if self.word.val().get_bit(10) {
            self.t2.next = self.sxe.val() << self.k_two.val();
        }
        if self.word.val().get_bit(11) {
            self.t3.next = self.sxe.val() << self.k_three.val();
        }
        self.xa2.d.next = self.t0.val() + self.t1.val();
        self.xb2.d.next = self.t2.val() - self.t3.val();
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(12) {
            self.t0.next = self.sye.val();
        }
        if self.word.val().get_bit(13) {
            self.t1.next = self.sye.val() << self.k_one.val();
        }
        if self.word.val().get_bit(14) {
            self.t2.next = self.sye.val() << self.k_two.val();
        }
        if self.word.val().get_bit(15) {
            self.t3.next = self.sye.val() << self.k_three.val();
        }
        self.ya2.d.next = self.t0.val() + self.t1.val();
        self.yb2.d.next = self.t2.val() - self.t3.val();
        self.zc_1.d.next = self.zce.val();
        // D2: products.
        self.px1.d.next = self.xa1.q.val() + self.xb1.q.val();
        self.py1.d.next = self.ya1.q.val() + self.yb1.q.val();
        self.px2.d.next = self.xa2.q.val() + self.xb2.q.val();
        self.py2.d.next = self.ya2.q.val() + self.yb2.q.val();
        self.zc_2.d.next = self.zc_1.q.val();
        // D3: zc + px + py, carry-save then one adder.
        self.cs_s.next = (self.zc_2.q.val() ^ self.px1.q.val()) ^ self.py1.q.val();
        self.cs_c.next = (((self.zc_2.q.val() & self.px1.q.val())
            | (self.zc_2.q.val() & self.py1.q.val()))
            | (self.px1.q.val() & self.py1.q.val()))
            << self.k_one.val();
        self.z1_3.d.next = self.cs_s.val() + self.cs_c.val();
        self.cs_s.next = (self.zc_2.q.val() ^ self.px2.q.val()) ^ self.py2.q.val();
        self.cs_c.next = (((self.zc_2.q.val() & self.px2.q.val())
            | (self.zc_2.q.val() & self.py2.q.val()))
            | (self.px2.q.val() & self.py2.q.val()))
            << self.k_one.val();
        self.z2_3.d.next = self.cs_s.val() + self.cs_c.val();
        // D4: signed compare (|z| < 2^51, so z1 − z2 does not overflow 53 bits).
        self.diff.next = self.z1_3.q.val() - self.z2_3.q.val();
        self.z1_r.d.next = self.z1_3.q.val();
        self.z2_r.d.next = self.z2_3.q.val();
        self.zmin_r.d.next = self.z2_3.q.val();
        self.zmax_r.d.next = self.z1_3.q.val();
        if self.diff.val().get_bit(52) {
            self.zmin_r.d.next = self.z1_3.q.val();
            self.zmax_r.d.next = self.z2_3.q.val();
        }
        if self.rst.val() {
            self.xa1.d.next = self.k_zero.val();
            self.xb1.d.next = self.k_zero.val();
            self.ya1.d.next = self.k_zero.val();
            self.yb1.d.next = self.k_zero.val();
            self.xa2.d.next = self.k_zero.val();
            self.xb2.d.next = self.k_zero.val();
            self.ya2.d.next = self.k_zero.val();
            self.yb2.d.next = self.k_zero.val();
            self.zc_1.d.next = self.k_zero.val();
            self.px1.d.next = self.k_zero.val();
            self.py1.d.next = self.k_zero.val();
            self.px2.d.next = self.k_zero.val();
            self.py2.d.next = self.k_zero.val();
            self.zc_2.d.next = self.k_zero.val();
            self.z1_3.d.next = self.k_zero.val();
            self.z2_3.d.next = self.k_zero.val();
            self.z1_r.d.next = self.k_zero.val();
            self.z2_r.d.next = self.k_zero.val();
            self.zmin_r.d.next = self.k_zero.val();
            self.zmax_r.d.next = self.k_zero.val();
        }
        self.z1.next = self.z1_r.q.val();
        self.z2.next = self.z2_r.q.val();
        self.zmin.next = self.zmin_r.q.val();
        self.zmax.next = self.zmax_r.q.val();
    }
}

/// The shared back end: a search result (sampled every clock) goes through the offset ROM
/// and the depth calculator; the result ports show it [`BACK_LATENCY`] = 6 clocks later.
///
/// On `i_hit = 0` (empty mask) `i_and` is 0, the ROM reads 0 (offsets (0, 0), no pair) and
/// every depth is `zc`, the golden fallback for a fragment without a hit.
#[derive(LogicBlock)]
pub struct SearchBackEnd<const B: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// A search finished this clock.
    pub i_valid: Signal<In, Bit>,
    /// It found a non-zero AND result.
    pub i_hit: Signal<In, Bit>,
    /// Steps (lines tested) it took.
    pub i_steps: Signal<In, Bits<LINE_BITS>>,
    /// The first non-zero AND result (0 if none).
    pub i_and: Signal<In, Bits<B>>,
    /// Plane `zc`.
    pub i_zc: Signal<In, Bits<PB>>,
    /// Plane `sx`.
    pub i_sx: Signal<In, Bits<PB>>,
    /// Plane `sy`.
    pub i_sy: Signal<In, Bits<PB>>,
    /// Result valid.
    pub out_valid: Signal<Out, Bit>,
    /// Result: hit (mask not empty).
    pub out_hit: Signal<Out, Bit>,
    /// Result: steps.
    pub out_steps: Signal<Out, Bits<LINE_BITS>>,
    /// Result: first non-zero AND result.
    pub out_and: Signal<Out, Bits<B>>,
    /// Result: ROM word.
    pub out_rom: Signal<Out, Bits<WORD_BITS>>,
    /// Result: depth at end 1.
    pub out_z1: Signal<Out, Bits<Z_BITS>>,
    /// Result: depth at end 2.
    pub out_z2: Signal<Out, Bits<Z_BITS>>,
    /// Result: min depth.
    pub out_zmin: Signal<Out, Bits<Z_BITS>>,
    /// Result: max depth.
    pub out_zmax: Signal<Out, Bits<Z_BITS>>,
    rom: OffsetRom<B>,
    depth: DepthCalc,
    valid_d: Vec<DFF<Bit>>,
    hit_d: Vec<DFF<Bit>>,
    steps_d: Vec<DFF<Bits<LINE_BITS>>>,
    and_d: Vec<DFF<Bits<B>>>,
    zc_d: Vec<DFF<Bits<PB>>>,
    sx_d: Vec<DFF<Bits<PB>>>,
    sy_d: Vec<DFF<Bits<PB>>>,
    word_d: Vec<DFF<Bits<WORD_BITS>>>,
    k_zero_b: Constant<Bits<B>>,
    k_zero_p: Constant<Bits<PB>>,
    k_zero_l: Constant<Bits<LINE_BITS>>,
    k_zero_w: Constant<Bits<WORD_BITS>>,
}

impl<const B: usize> SearchBackEnd<B> {
    /// The back end for `size` (`size.bits() == B`).
    pub fn new(size: MaskSize) -> Self {
        // The kernel reads the last registers by literal index.
        const _: () = assert!(ROM_LATENCY == 2 && DEPTH_LATENCY == 4 && BACK_LATENCY == 6);
        SearchBackEnd {
            clock: Default::default(),
            rst: Default::default(),
            i_valid: Default::default(),
            i_hit: Default::default(),
            i_steps: Default::default(),
            i_and: Default::default(),
            i_zc: Default::default(),
            i_sx: Default::default(),
            i_sy: Default::default(),
            out_valid: Default::default(),
            out_hit: Default::default(),
            out_steps: Default::default(),
            out_and: Default::default(),
            out_rom: Default::default(),
            out_z1: Default::default(),
            out_z2: Default::default(),
            out_zmin: Default::default(),
            out_zmax: Default::default(),
            rom: OffsetRom::new(size),
            depth: DepthCalc::new(),
            valid_d: dff_line(BACK_LATENCY),
            hit_d: dff_line(BACK_LATENCY),
            steps_d: dff_line(BACK_LATENCY),
            and_d: dff_line(BACK_LATENCY),
            zc_d: dff_line(ROM_LATENCY),
            sx_d: dff_line(ROM_LATENCY),
            sy_d: dff_line(ROM_LATENCY),
            word_d: dff_line(DEPTH_LATENCY),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_p: Constant::new(0u64.to_bits()),
            k_zero_l: Constant::new(0u64.to_bits()),
            k_zero_w: Constant::new(0u64.to_bits()),
        }
    }
}

impl<const B: usize> Logic for SearchBackEnd<B> {
    #[hdl_gen]
    fn update(&mut self) {
        self.rom.clock.next = self.clock.val();
        self.rom.rst.next = self.rst.val();
        self.depth.clock.next = self.clock.val();
        self.depth.rst.next = self.rst.val();
        // Result metadata: BACK_LATENCY registers.
        for i in 0..self.valid_d.len() {
            self.valid_d[i].clock.next = self.clock.val();
            self.hit_d[i].clock.next = self.clock.val();
            self.steps_d[i].clock.next = self.clock.val();
            self.and_d[i].clock.next = self.clock.val();
        }
        self.valid_d[0].d.next = self.i_valid.val();
        self.hit_d[0].d.next = self.i_hit.val();
        self.steps_d[0].d.next = self.i_steps.val();
        self.and_d[0].d.next = self.i_and.val();
        for i in 1..self.valid_d.len() {
            self.valid_d[i].d.next = self.valid_d[i - 1].q.val();
            self.hit_d[i].d.next = self.hit_d[i - 1].q.val();
            self.steps_d[i].d.next = self.steps_d[i - 1].q.val();
            self.and_d[i].d.next = self.and_d[i - 1].q.val();
        }
        // Plane: ROM_LATENCY registers, aligned with the ROM word.
        for i in 0..self.zc_d.len() {
            self.zc_d[i].clock.next = self.clock.val();
            self.sx_d[i].clock.next = self.clock.val();
            self.sy_d[i].clock.next = self.clock.val();
        }
        self.zc_d[0].d.next = self.i_zc.val();
        self.sx_d[0].d.next = self.i_sx.val();
        self.sy_d[0].d.next = self.i_sy.val();
        for i in 1..self.zc_d.len() {
            self.zc_d[i].d.next = self.zc_d[i - 1].q.val();
            self.sx_d[i].d.next = self.sx_d[i - 1].q.val();
            self.sy_d[i].d.next = self.sy_d[i - 1].q.val();
        }
        // ROM word: DEPTH_LATENCY registers, aligned with the depths.
        for i in 0..self.word_d.len() {
            self.word_d[i].clock.next = self.clock.val();
        }
        self.word_d[0].d.next = self.rom.word.val();
        for i in 1..self.word_d.len() {
            self.word_d[i].d.next = self.word_d[i - 1].q.val();
        }
        self.rom.and_in.next = self.i_and.val();
        self.depth.word.next = self.rom.word.val();
        // Every signal crossing a module boundary is written exactly once per evaluation
        // (no default-then-override): an intermediate value on a port that feeds back
        // into the writer's inputs makes event-driven simulators (Icarus) loop at zero
        // delay. Hence literal indices of the last registers (checked in `new`).
        self.depth.zc.next = self.zc_d[1].q.val();
        self.depth.sx.next = self.sx_d[1].q.val();
        self.depth.sy.next = self.sy_d[1].q.val();
        self.out_valid.next = self.valid_d[5].q.val();
        self.out_hit.next = self.hit_d[5].q.val();
        self.out_steps.next = self.steps_d[5].q.val();
        self.out_and.next = self.and_d[5].q.val();
        self.out_rom.next = self.word_d[3].q.val();
        self.out_z1.next = self.depth.z1.val();
        self.out_z2.next = self.depth.z2.val();
        self.out_zmin.next = self.depth.zmin.val();
        self.out_zmax.next = self.depth.zmax.val();
        if self.rst.val() {
            for i in 0..self.valid_d.len() {
                self.valid_d[i].d.next = false;
                self.hit_d[i].d.next = false;
                self.steps_d[i].d.next = self.k_zero_l.val();
                self.and_d[i].d.next = self.k_zero_b.val();
            }
            for i in 0..self.zc_d.len() {
                self.zc_d[i].d.next = self.k_zero_p.val();
                self.sx_d[i].d.next = self.k_zero_p.val();
                self.sy_d[i].d.next = self.k_zero_p.val();
            }
            for i in 0..self.word_d.len() {
                self.word_d[i].d.next = self.k_zero_w.val();
            }
        }
    }
}

/// `n` default registers.
fn dff_line<T: Synth>(n: usize) -> Vec<DFF<T>> {
    (0..n).map(|_| DFF::default()).collect()
}

/// Search masks of every line for the four corners, as constants.
fn mask_constants<const B: usize>(
    size: MaskSize,
    family: SearchFamily,
) -> [Vec<Constant<Bits<B>>>; 4] {
    Corner::ALL.map(|c| {
        search_mask_table(size, family, c)
            .into_iter()
            .map(|m| Constant::new(m.to_bits()))
            .collect()
    })
}

/// The iterative search unit: one search line per clock (the seed's flowchart).
///
/// **Handshake.** `ready` is high when the unit is idle or finishing its search in this
/// clock (`done`). A start (`in_valid`, with `in_mask`, `in_corner`, `in_zc/sx/sy`) is
/// accepted at a rising edge where `ready` is high (it is ignored otherwise), so searches
/// follow each other without a gap: a search of `s` lines occupies `s` clocks.
///
/// **Step ports** (combinational from the state registers, Moore): after the accepting
/// edge the unit shows line 0, after each further edge the next line, exactly the golden
/// `SearchUnit::step` output of that clock (all zero when idle).
///
/// **Result ports**: the clock that shows `done` is sampled into the back end; `out_*`
/// show the result [`BACK_LATENCY`] = 6 clocks later (after edge `t + 6` for a `done`
/// shown after edge `t`), `out_valid` for one clock. Result fields are meaningful only
/// with `out_valid`.
#[derive(LogicBlock)]
pub struct MaskSearchIter<const B: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: idle, every register 0.
    pub rst: Signal<In, Bit>,
    /// Start a search (accepted when `ready`).
    pub in_valid: Signal<In, Bit>,
    /// Fraction mask.
    pub in_mask: Signal<In, Bits<B>>,
    /// Start corner code (bit 0 right, bit 1 bottom).
    pub in_corner: Signal<In, Bits<2>>,
    /// Plane `zc`, Q.12, 48-bit two's complement.
    pub in_zc: Signal<In, Bits<PB>>,
    /// Plane `sx`.
    pub in_sx: Signal<In, Bits<PB>>,
    /// Plane `sy`.
    pub in_sy: Signal<In, Bits<PB>>,
    /// A start is accepted at the next edge.
    pub ready: Signal<Out, Bit>,
    /// Step: a search is running.
    pub active: Signal<Out, Bit>,
    /// Step: line index tested.
    pub line: Signal<Out, Bits<LINE_BITS>>,
    /// Step: the search mask of that line.
    pub search_mask: Signal<Out, Bits<B>>,
    /// Step: fraction mask AND search mask.
    pub and_result: Signal<Out, Bits<B>>,
    /// Step: zero detector.
    pub zero: Signal<Out, Bit>,
    /// Step: the mover fires (next line follows).
    pub moved: Signal<Out, Bit>,
    /// Step: first hit.
    pub hit: Signal<Out, Bit>,
    /// Step: the search ends this clock.
    pub done: Signal<Out, Bit>,
    /// Result valid (one clock).
    pub out_valid: Signal<Out, Bit>,
    /// Result: the mask was not empty.
    pub out_hit: Signal<Out, Bit>,
    /// Result: lines tested.
    pub out_steps: Signal<Out, Bits<LINE_BITS>>,
    /// Result: first non-zero AND result (0 if none).
    pub out_and: Signal<Out, Bits<B>>,
    /// Result: ROM word.
    pub out_rom: Signal<Out, Bits<WORD_BITS>>,
    /// Result: depth at end 1 (`zc` without hit), Q.12, 53-bit two's complement.
    pub out_z1: Signal<Out, Bits<Z_BITS>>,
    /// Result: depth at end 2.
    pub out_z2: Signal<Out, Bits<Z_BITS>>,
    /// Result: min depth.
    pub out_zmin: Signal<Out, Bits<Z_BITS>>,
    /// Result: max depth.
    pub out_zmax: Signal<Out, Bits<Z_BITS>>,
    /// The back end.
    pub back: SearchBackEnd<B>,
    running_r: DFF<Bit>,
    line_r: DFF<Bits<LINE_BITS>>,
    mask_r: DFF<Bits<B>>,
    corner_r: DFF<Bits<2>>,
    zc_r: DFF<Bits<PB>>,
    sx_r: DFF<Bits<PB>>,
    sy_r: DFF<Bits<PB>>,
    k_sm0: Vec<Constant<Bits<B>>>,
    k_sm1: Vec<Constant<Bits<B>>>,
    k_sm2: Vec<Constant<Bits<B>>>,
    k_sm3: Vec<Constant<Bits<B>>>,
    k_line: Vec<Constant<Bits<LINE_BITS>>>,
    k_last: Constant<Bits<LINE_BITS>>,
    k_one_l: Constant<Bits<LINE_BITS>>,
    k_zero_l: Constant<Bits<LINE_BITS>>,
    k_zero_b: Constant<Bits<B>>,
    k_zero_p: Constant<Bits<PB>>,
    k_zero_c: Constant<Bits<2>>,
    sm: Signal<Local, Bits<B>>,
    and_v: Signal<Local, Bits<B>>,
    nz: Signal<Local, Bit>,
    last: Signal<Local, Bit>,
}

impl<const B: usize> MaskSearchIter<B> {
    /// The unit for `size` (`size.bits() == B`) and a search family (the seed's is
    /// [`SearchFamily::DIAGONAL`]).
    pub fn new(size: MaskSize, family: SearchFamily) -> Result<Self, MaskSearchError> {
        let lines = check(size, family, B)? as usize;
        let [k_sm0, k_sm1, k_sm2, k_sm3] = mask_constants::<B>(size, family);
        Ok(MaskSearchIter {
            clock: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_mask: Default::default(),
            in_corner: Default::default(),
            in_zc: Default::default(),
            in_sx: Default::default(),
            in_sy: Default::default(),
            ready: Default::default(),
            active: Default::default(),
            line: Default::default(),
            search_mask: Default::default(),
            and_result: Default::default(),
            zero: Default::default(),
            moved: Default::default(),
            hit: Default::default(),
            done: Default::default(),
            out_valid: Default::default(),
            out_hit: Default::default(),
            out_steps: Default::default(),
            out_and: Default::default(),
            out_rom: Default::default(),
            out_z1: Default::default(),
            out_z2: Default::default(),
            out_zmin: Default::default(),
            out_zmax: Default::default(),
            back: SearchBackEnd::new(size),
            running_r: Default::default(),
            line_r: Default::default(),
            mask_r: Default::default(),
            corner_r: Default::default(),
            zc_r: Default::default(),
            sx_r: Default::default(),
            sy_r: Default::default(),
            k_sm0,
            k_sm1,
            k_sm2,
            k_sm3,
            k_line: (0..lines as u64)
                .map(|k| Constant::new(k.to_bits()))
                .collect(),
            k_last: Constant::new((lines as u64 - 1).to_bits()),
            k_one_l: Constant::new(1u64.to_bits()),
            k_zero_l: Constant::new(0u64.to_bits()),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_p: Constant::new(0u64.to_bits()),
            k_zero_c: Constant::new(0u64.to_bits()),
            sm: Default::default(),
            and_v: Default::default(),
            nz: Default::default(),
            last: Default::default(),
        })
    }

    /// Number of search lines (the longest search, in clocks).
    pub fn lines(&self) -> usize {
        self.k_line.len()
    }
}

impl<const B: usize> Logic for MaskSearchIter<B> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, running_r, line_r, mask_r, corner_r, zc_r, sx_r, sy_r);
        self.back.clock.next = self.clock.val();
        self.back.rst.next = self.rst.val();
        // Search mask generator: table[corner][line].
        self.sm.next = self.k_zero_b.val();
        for k in 0..self.k_line.len() {
            if self.line_r.q.val() == self.k_line[k].val() {
                if self.corner_r.q.val().get_bit(1) {
                    if self.corner_r.q.val().get_bit(0) {
                        self.sm.next = self.k_sm3[k].val();
                    } else {
                        self.sm.next = self.k_sm2[k].val();
                    }
                } else if self.corner_r.q.val().get_bit(0) {
                    self.sm.next = self.k_sm1[k].val();
                } else {
                    self.sm.next = self.k_sm0[k].val();
                }
            }
        }
        // AND unit, zero detector, last line.
        self.and_v.next = self.mask_r.q.val() & self.sm.val();
        self.nz.next = self.and_v.val() != self.k_zero_b.val();
        self.last.next = self.line_r.q.val() == self.k_last.val();
        self.active.next = self.running_r.q.val();
        self.line.next = self.k_zero_l.val();
        self.search_mask.next = self.k_zero_b.val();
        self.and_result.next = self.k_zero_b.val();
        if self.running_r.q.val() {
            self.line.next = self.line_r.q.val();
            self.search_mask.next = self.sm.val();
            self.and_result.next = self.and_v.val();
        }
        self.zero.next = self.running_r.q.val() & (!self.nz.val());
        self.hit.next = self.running_r.q.val() & self.nz.val();
        self.moved.next = (self.running_r.q.val() & (!self.nz.val())) & (!self.last.val());
        self.done.next = self.running_r.q.val() & (self.nz.val() | self.last.val());
        self.ready.next = (!self.running_r.q.val()) | self.done.val();
        // Mover and end of search.
        if self.done.val() {
            self.running_r.d.next = false;
        }
        if self.moved.val() {
            self.line_r.d.next = self.line_r.q.val() + self.k_one_l.val();
        }
        // Start.
        if self.in_valid.val() & self.ready.val() {
            self.running_r.d.next = true;
            self.line_r.d.next = self.k_zero_l.val();
            self.mask_r.d.next = self.in_mask.val();
            self.corner_r.d.next = self.in_corner.val();
            self.zc_r.d.next = self.in_zc.val();
            self.sx_r.d.next = self.in_sx.val();
            self.sy_r.d.next = self.in_sy.val();
        }
        if self.rst.val() {
            self.running_r.d.next = false;
            self.line_r.d.next = self.k_zero_l.val();
            self.mask_r.d.next = self.k_zero_b.val();
            self.corner_r.d.next = self.k_zero_c.val();
            self.zc_r.d.next = self.k_zero_p.val();
            self.sx_r.d.next = self.k_zero_p.val();
            self.sy_r.d.next = self.k_zero_p.val();
        }
        // Back end: the finishing clock's result.
        self.back.i_valid.next = self.done.val();
        self.back.i_hit.next = self.hit.val();
        self.back.i_steps.next = self.line_r.q.val() + self.k_one_l.val();
        // and_v is 0 unless this line hits (and the back end only keeps it with done).
        self.back.i_and.next = self.and_v.val();
        self.back.i_zc.next = self.zc_r.q.val();
        self.back.i_sx.next = self.sx_r.q.val();
        self.back.i_sy.next = self.sy_r.q.val();
        self.out_valid.next = self.back.out_valid.val();
        self.out_hit.next = self.back.out_hit.val();
        self.out_steps.next = self.back.out_steps.val();
        self.out_and.next = self.back.out_and.val();
        self.out_rom.next = self.back.out_rom.val();
        self.out_z1.next = self.back.out_z1.val();
        self.out_z2.next = self.back.out_z2.val();
        self.out_zmin.next = self.back.out_zmin.val();
        self.out_zmax.next = self.back.out_zmax.val();
    }
}

/// Registers of one pipeline stage, as read by testbenches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct StageProbe {
    /// A mask occupies the stage.
    pub valid: bool,
    /// Its fraction mask.
    pub mask: u64,
    /// Its start corner code.
    pub corner: u8,
    /// A line before this stage's hit.
    pub found: bool,
    /// The first non-zero AND result so far (0 if none).
    pub and_result: u64,
    /// Lines tested so far (up to the hit).
    pub steps: u32,
    /// Plane `zc`, `sx`, `sy` (raw 48-bit fields).
    pub plane: [u64; 3],
}

/// One stage of [`MaskSearchPipe`]: tests line `k` (a constant) for the mask in its
/// registers, unless an earlier line already hit.
#[derive(LogicBlock)]
pub struct SearchStage<const B: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// From the previous stage: valid.
    pub i_valid: Signal<In, Bit>,
    /// From the previous stage: mask.
    pub i_mask: Signal<In, Bits<B>>,
    /// From the previous stage: corner.
    pub i_corner: Signal<In, Bits<2>>,
    /// From the previous stage: hit found.
    pub i_found: Signal<In, Bit>,
    /// From the previous stage: AND result of the hit.
    pub i_and: Signal<In, Bits<B>>,
    /// From the previous stage: steps.
    pub i_steps: Signal<In, Bits<LINE_BITS>>,
    /// From the previous stage: plane `zc`.
    pub i_zc: Signal<In, Bits<PB>>,
    /// From the previous stage: plane `sx`.
    pub i_sx: Signal<In, Bits<PB>>,
    /// From the previous stage: plane `sy`.
    pub i_sy: Signal<In, Bits<PB>>,
    /// To the next stage: valid.
    pub o_valid: Signal<Out, Bit>,
    /// To the next stage: mask.
    pub o_mask: Signal<Out, Bits<B>>,
    /// To the next stage: corner.
    pub o_corner: Signal<Out, Bits<2>>,
    /// To the next stage: hit found (here or earlier).
    pub o_found: Signal<Out, Bit>,
    /// To the next stage: AND result of the hit.
    pub o_and: Signal<Out, Bits<B>>,
    /// To the next stage: steps.
    pub o_steps: Signal<Out, Bits<LINE_BITS>>,
    /// To the next stage: plane `zc`.
    pub o_zc: Signal<Out, Bits<PB>>,
    /// To the next stage: plane `sx`.
    pub o_sx: Signal<Out, Bits<PB>>,
    /// To the next stage: plane `sy`.
    pub o_sy: Signal<Out, Bits<PB>>,
    valid_r: DFF<Bit>,
    mask_r: DFF<Bits<B>>,
    corner_r: DFF<Bits<2>>,
    found_r: DFF<Bit>,
    and_r: DFF<Bits<B>>,
    steps_r: DFF<Bits<LINE_BITS>>,
    zc_r: DFF<Bits<PB>>,
    sx_r: DFF<Bits<PB>>,
    sy_r: DFF<Bits<PB>>,
    k_sm0: Constant<Bits<B>>,
    k_sm1: Constant<Bits<B>>,
    k_sm2: Constant<Bits<B>>,
    k_sm3: Constant<Bits<B>>,
    k_steps: Constant<Bits<LINE_BITS>>,
    k_zero_b: Constant<Bits<B>>,
    k_zero_p: Constant<Bits<PB>>,
    k_zero_l: Constant<Bits<LINE_BITS>>,
    k_zero_c: Constant<Bits<2>>,
    sm: Signal<Local, Bits<B>>,
    and_v: Signal<Local, Bits<B>>,
    test: Signal<Local, Bit>,
}

impl<const B: usize> SearchStage<B> {
    fn new(masks: [u64; 4], line: u32) -> Self {
        SearchStage {
            clock: Default::default(),
            rst: Default::default(),
            i_valid: Default::default(),
            i_mask: Default::default(),
            i_corner: Default::default(),
            i_found: Default::default(),
            i_and: Default::default(),
            i_steps: Default::default(),
            i_zc: Default::default(),
            i_sx: Default::default(),
            i_sy: Default::default(),
            o_valid: Default::default(),
            o_mask: Default::default(),
            o_corner: Default::default(),
            o_found: Default::default(),
            o_and: Default::default(),
            o_steps: Default::default(),
            o_zc: Default::default(),
            o_sx: Default::default(),
            o_sy: Default::default(),
            valid_r: Default::default(),
            mask_r: Default::default(),
            corner_r: Default::default(),
            found_r: Default::default(),
            and_r: Default::default(),
            steps_r: Default::default(),
            zc_r: Default::default(),
            sx_r: Default::default(),
            sy_r: Default::default(),
            k_sm0: Constant::new(masks[0].to_bits()),
            k_sm1: Constant::new(masks[1].to_bits()),
            k_sm2: Constant::new(masks[2].to_bits()),
            k_sm3: Constant::new(masks[3].to_bits()),
            k_steps: Constant::new((line as u64 + 1).to_bits()),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_p: Constant::new(0u64.to_bits()),
            k_zero_l: Constant::new(0u64.to_bits()),
            k_zero_c: Constant::new(0u64.to_bits()),
            sm: Default::default(),
            and_v: Default::default(),
            test: Default::default(),
        }
    }

    /// The stage registers.
    pub fn probe(&self) -> StageProbe {
        StageProbe {
            valid: self.valid_r.q.val(),
            mask: self.mask_r.q.val().to_u64(),
            corner: self.corner_r.q.val().to_u64() as u8,
            found: self.found_r.q.val(),
            and_result: self.and_r.q.val().to_u64(),
            steps: self.steps_r.q.val().to_u64() as u32,
            plane: [
                self.zc_r.q.val().to_u64(),
                self.sx_r.q.val().to_u64(),
                self.sy_r.q.val().to_u64(),
            ],
        }
    }
}

impl<const B: usize> Logic for SearchStage<B> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, valid_r, mask_r, corner_r, found_r, and_r, steps_r, zc_r, sx_r, sy_r
        );
        self.valid_r.d.next = self.i_valid.val();
        self.mask_r.d.next = self.i_mask.val();
        self.corner_r.d.next = self.i_corner.val();
        self.found_r.d.next = self.i_found.val();
        self.and_r.d.next = self.i_and.val();
        self.steps_r.d.next = self.i_steps.val();
        self.zc_r.d.next = self.i_zc.val();
        self.sx_r.d.next = self.i_sx.val();
        self.sy_r.d.next = self.i_sy.val();
        if self.rst.val() {
            self.valid_r.d.next = false;
            self.mask_r.d.next = self.k_zero_b.val();
            self.corner_r.d.next = self.k_zero_c.val();
            self.found_r.d.next = false;
            self.and_r.d.next = self.k_zero_b.val();
            self.steps_r.d.next = self.k_zero_l.val();
            self.zc_r.d.next = self.k_zero_p.val();
            self.sx_r.d.next = self.k_zero_p.val();
            self.sy_r.d.next = self.k_zero_p.val();
        }
        // Search mask of this line for the corner.
        if self.corner_r.q.val().get_bit(1) {
            if self.corner_r.q.val().get_bit(0) {
                self.sm.next = self.k_sm3.val();
            } else {
                self.sm.next = self.k_sm2.val();
            }
        } else if self.corner_r.q.val().get_bit(0) {
            self.sm.next = self.k_sm1.val();
        } else {
            self.sm.next = self.k_sm0.val();
        }
        self.and_v.next = self.mask_r.q.val() & self.sm.val();
        // This line is tested iff no earlier line hit.
        self.test.next = !self.found_r.q.val();
        self.o_valid.next = self.valid_r.q.val();
        self.o_mask.next = self.mask_r.q.val();
        self.o_corner.next = self.corner_r.q.val();
        self.o_found.next = self.found_r.q.val();
        self.o_and.next = self.and_r.q.val();
        self.o_steps.next = self.steps_r.q.val();
        if self.test.val() {
            self.o_steps.next = self.k_steps.val();
            if self.and_v.val() != self.k_zero_b.val() {
                self.o_found.next = true;
                self.o_and.next = self.and_v.val();
            }
        }
        self.o_zc.next = self.zc_r.q.val();
        self.o_sx.next = self.sx_r.q.val();
        self.o_sy.next = self.sy_r.q.val();
    }
}

/// The pipelined search unit: one stage per search line, a new mask every clock.
///
/// **Handshake.** Valid-only, fixed latency, no back-pressure (`ready` would be constant 1):
/// `in_valid` with its mask, corner and plane is sampled at every rising edge. Stage `k`
/// (`k = 0 .. lines`) holds the mask `k` edges after it was sampled and tests line `k`
/// unless an earlier line hit; the last stage's outcome enters the back end at the next
/// edge. A mask sampled at edge `E` shows its result on `out_*` after edge
/// `E + latency()`, `latency() = lines + 6` (13 for 4×4, 21 for 8×8), with `out_valid`.
/// Result fields are meaningful only with `out_valid`.
#[derive(LogicBlock)]
pub struct MaskSearchPipe<const B: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: every register 0 (pipeline empty).
    pub rst: Signal<In, Bit>,
    /// A mask is present.
    pub in_valid: Signal<In, Bit>,
    /// Fraction mask.
    pub in_mask: Signal<In, Bits<B>>,
    /// Start corner code.
    pub in_corner: Signal<In, Bits<2>>,
    /// Plane `zc`.
    pub in_zc: Signal<In, Bits<PB>>,
    /// Plane `sx`.
    pub in_sx: Signal<In, Bits<PB>>,
    /// Plane `sy`.
    pub in_sy: Signal<In, Bits<PB>>,
    /// Result valid.
    pub out_valid: Signal<Out, Bit>,
    /// Result: the mask was not empty.
    pub out_hit: Signal<Out, Bit>,
    /// Result: lines the iterative search would test.
    pub out_steps: Signal<Out, Bits<LINE_BITS>>,
    /// Result: first non-zero AND result (0 if none).
    pub out_and: Signal<Out, Bits<B>>,
    /// Result: ROM word.
    pub out_rom: Signal<Out, Bits<WORD_BITS>>,
    /// Result: depth at end 1.
    pub out_z1: Signal<Out, Bits<Z_BITS>>,
    /// Result: depth at end 2.
    pub out_z2: Signal<Out, Bits<Z_BITS>>,
    /// Result: min depth.
    pub out_zmin: Signal<Out, Bits<Z_BITS>>,
    /// Result: max depth.
    pub out_zmax: Signal<Out, Bits<Z_BITS>>,
    /// The search stages, line `k` in stage `k`.
    pub stages: Vec<SearchStage<B>>,
    /// The back end.
    pub back: SearchBackEnd<B>,
    k_zero_b: Constant<Bits<B>>,
    k_zero_l: Constant<Bits<LINE_BITS>>,
    k_zero_p: Constant<Bits<PB>>,
    l_valid: Signal<Local, Bit>,
    l_hit: Signal<Local, Bit>,
    l_steps: Signal<Local, Bits<LINE_BITS>>,
    l_and: Signal<Local, Bits<B>>,
    l_zc: Signal<Local, Bits<PB>>,
    l_sx: Signal<Local, Bits<PB>>,
    l_sy: Signal<Local, Bits<PB>>,
}

impl<const B: usize> MaskSearchPipe<B> {
    /// The unit for `size` (`size.bits() == B`) and a search family.
    pub fn new(size: MaskSize, family: SearchFamily) -> Result<Self, MaskSearchError> {
        let lines = check(size, family, B)?;
        let t = Corner::ALL.map(|c| search_mask_table(size, family, c));
        let stages = (0..lines)
            .map(|k| SearchStage::new(t.clone().map(|v| v[k as usize]), k))
            .collect();
        Ok(MaskSearchPipe {
            clock: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_mask: Default::default(),
            in_corner: Default::default(),
            in_zc: Default::default(),
            in_sx: Default::default(),
            in_sy: Default::default(),
            out_valid: Default::default(),
            out_hit: Default::default(),
            out_steps: Default::default(),
            out_and: Default::default(),
            out_rom: Default::default(),
            out_z1: Default::default(),
            out_z2: Default::default(),
            out_zmin: Default::default(),
            out_zmax: Default::default(),
            stages,
            back: SearchBackEnd::new(size),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_l: Constant::new(0u64.to_bits()),
            k_zero_p: Constant::new(0u64.to_bits()),
            l_valid: Default::default(),
            l_hit: Default::default(),
            l_steps: Default::default(),
            l_and: Default::default(),
            l_zc: Default::default(),
            l_sx: Default::default(),
            l_sy: Default::default(),
        })
    }

    /// Edges from sampling a mask to its result on `out_*`.
    pub fn latency(&self) -> usize {
        self.stages.len() + BACK_LATENCY
    }
}

impl<const B: usize> Logic for MaskSearchPipe<B> {
    #[hdl_gen]
    fn update(&mut self) {
        for i in 0..self.stages.len() {
            self.stages[i].clock.next = self.clock.val();
            self.stages[i].rst.next = self.rst.val();
        }
        self.back.clock.next = self.clock.val();
        self.back.rst.next = self.rst.val();
        self.stages[0].i_valid.next = self.in_valid.val();
        self.stages[0].i_mask.next = self.in_mask.val();
        self.stages[0].i_corner.next = self.in_corner.val();
        self.stages[0].i_found.next = false;
        self.stages[0].i_and.next = self.k_zero_b.val();
        self.stages[0].i_steps.next = self.k_zero_l.val();
        self.stages[0].i_zc.next = self.in_zc.val();
        self.stages[0].i_sx.next = self.in_sx.val();
        self.stages[0].i_sy.next = self.in_sy.val();
        for i in 1..self.stages.len() {
            self.stages[i].i_valid.next = self.stages[i - 1].o_valid.val();
            self.stages[i].i_mask.next = self.stages[i - 1].o_mask.val();
            self.stages[i].i_corner.next = self.stages[i - 1].o_corner.val();
            self.stages[i].i_found.next = self.stages[i - 1].o_found.val();
            self.stages[i].i_and.next = self.stages[i - 1].o_and.val();
            self.stages[i].i_steps.next = self.stages[i - 1].o_steps.val();
            self.stages[i].i_zc.next = self.stages[i - 1].o_zc.val();
            self.stages[i].i_sx.next = self.stages[i - 1].o_sx.val();
            self.stages[i].i_sy.next = self.stages[i - 1].o_sy.val();
        }
        // The last stage feeds the back end (loop over locals: last write wins; each
        // back-end port is then written once, see `SearchBackEnd`).
        self.l_valid.next = false;
        self.l_hit.next = false;
        self.l_steps.next = self.k_zero_l.val();
        self.l_and.next = self.k_zero_b.val();
        self.l_zc.next = self.k_zero_p.val();
        self.l_sx.next = self.k_zero_p.val();
        self.l_sy.next = self.k_zero_p.val();
        for i in 0..self.stages.len() {
            self.l_valid.next = self.stages[i].o_valid.val();
            self.l_hit.next = self.stages[i].o_found.val();
            self.l_steps.next = self.stages[i].o_steps.val();
            self.l_and.next = self.stages[i].o_and.val();
            self.l_zc.next = self.stages[i].o_zc.val();
            self.l_sx.next = self.stages[i].o_sx.val();
            self.l_sy.next = self.stages[i].o_sy.val();
        }
        self.back.i_valid.next = self.l_valid.val();
        self.back.i_hit.next = self.l_hit.val();
        self.back.i_steps.next = self.l_steps.val();
        self.back.i_and.next = self.l_and.val();
        self.back.i_zc.next = self.l_zc.val();
        self.back.i_sx.next = self.l_sx.val();
        self.back.i_sy.next = self.l_sy.val();
        self.out_valid.next = self.back.out_valid.val();
        self.out_hit.next = self.back.out_hit.val();
        self.out_steps.next = self.back.out_steps.val();
        self.out_and.next = self.back.out_and.val();
        self.out_rom.next = self.back.out_rom.val();
        self.out_z1.next = self.back.out_z1.val();
        self.out_z2.next = self.back.out_z2.val();
        self.out_zmin.next = self.back.out_zmin.val();
        self.out_zmax.next = self.back.out_zmax.val();
    }
}

/// Verilog module name of a variant for a size, e.g. `mask_search_pipe_4x4`.
pub fn module_name(variant: Variant, size: MaskSize) -> String {
    format!("mask_search_{}_{}x{}", variant.name(), size.n(), size.m())
}

fn export_block<T: Block>(mut block: T, name: &str) -> String {
    block.connect_all();
    let v = generate_verilog(&block);
    format!(
        "// Generated by pixelproc-rtl from the RustHDL block `{name}`; do not edit.\n{}",
        crate::verilog::rename_top(&v, name)
    )
}

/// Self-contained Verilog of one variant for 4×4 or 8×8 masks (seed diagonal family):
/// `(module name, text)`. The module is [`module_name`]; sub-modules are `name$...`.
pub fn mask_search_verilog(
    variant: Variant,
    size: MaskSize,
) -> Result<(String, String), MaskSearchError> {
    let name = module_name(variant, size);
    let fam = SearchFamily::DIAGONAL;
    let text = match (variant, size.bits()) {
        (Variant::Iterative, 16) => export_block(MaskSearchIter::<16>::new(size, fam)?, &name),
        (Variant::Iterative, 64) => export_block(MaskSearchIter::<64>::new(size, fam)?, &name),
        (Variant::Pipelined, 16) => export_block(MaskSearchPipe::<16>::new(size, fam)?, &name),
        (Variant::Pipelined, 64) => export_block(MaskSearchPipe::<64>::new(size, fam)?, &name),
        _ => return Err(MaskSearchError::NoExport(size)),
    };
    Ok((name, text))
}

/// Writes both variants for 4×4 and 8×8 into `dir` (`mask_search_{iter,pipe}_{4x4,8x8}.v`,
/// each self-contained); returns the paths.
pub fn write_mask_search_verilog(dir: &Path) -> Result<Vec<PathBuf>, MaskSearchError> {
    let io = |e: std::io::Error| MaskSearchError::Io(e.to_string());
    std::fs::create_dir_all(dir).map_err(io)?;
    let mut out = Vec::new();
    for size in [MaskSize::S4X4, MaskSize::S8X8] {
        for v in Variant::ALL {
            let (name, text) = mask_search_verilog(v, size)?;
            let p = dir.join(format!("{name}.v"));
            std::fs::write(&p, text).map_err(io)?;
            out.push(p);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clock<B: Block>(u: &mut B, rise: impl Fn(&mut B)) {
        rise(u);
        assert!(simulate(u, 200));
    }

    fn cycle_iter(u: &mut MaskSearchIter<16>, start: Option<(u64, u8, [i64; 3])>) {
        u.in_valid.next = start.is_some();
        if let Some((m, c, p)) = start {
            u.in_mask.next = m.to_bits();
            u.in_corner.next = (c as u64).to_bits();
            u.in_zc.next = (p[0] as u64 & ((1 << 48) - 1)).to_bits();
            u.in_sx.next = (p[1] as u64 & ((1 << 48) - 1)).to_bits();
            u.in_sy.next = (p[2] as u64 & ((1 << 48) - 1)).to_bits();
        }
        clock(u, |u| u.clock.next = Clock { clk: true });
        clock(u, |u| u.clock.next = Clock { clk: false });
    }

    fn z(v: Bits<Z_BITS>) -> i64 {
        ((v.to_u64() << 11) as i64) >> 11
    }

    #[test]
    fn seed_worked_example_through_the_iterative_unit() {
        // Seed 000, 4×4: a mask whose anti-diagonal c + r = 2 is covered and lines 0 and 1
        // are empty, searched from the top-left: lines 0 (bit 3) and 1 (bits 7, 2) give 0,
        // line 2 gives 0842H, whose ends are (−0.375, +0.125) and (+0.125, −0.375), i.e.
        // (−3, +1) and (+1, −3) in 1/8 px. Plane z = 1000 + 3·dx − 5·dy (Q.12): depths
        // 1000 − 9 − 5 = 986 and 1000 + 3 + 15 = 1018.
        let mut u = MaskSearchIter::<16>::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        u.connect_all();
        u.rst.next = true;
        cycle_iter(&mut u, None);
        u.rst.next = false;
        assert!(u.ready.val() && !u.active.val());
        let plane = [1000 << 12, 3 << 12, -5 << 12];
        cycle_iter(&mut u, Some((0xFF73, 0, plane)));
        let mut seen = Vec::new();
        for _ in 0..3 {
            seen.push((
                u.line.val().to_u64(),
                u.search_mask.val().to_u64(),
                u.and_result.val().to_u64(),
                u.zero.val(),
                u.done.val(),
            ));
            cycle_iter(&mut u, None);
        }
        assert_eq!(
            seen,
            vec![
                (0, 0x0008, 0, true, false),
                (1, 0x0084, 0, true, false),
                (2, 0x0842, 0x0842, false, true)
            ]
        );
        assert!(!u.active.val() && u.ready.val());
        // The result shows BACK_LATENCY clocks after the done clock.
        for _ in 0..BACK_LATENCY - 1 {
            assert!(!u.out_valid.val());
            cycle_iter(&mut u, None);
        }
        assert!(u.out_valid.val() && u.out_hit.val());
        let f = |d: i32| (d as u64) & 0xF;
        let want = f(-3) | f(1) << 4 | f(1) << 8 | f(-3) << 12 | 1 << 16;
        assert_eq!(u.out_rom.val().to_u64(), want);
        assert_eq!(u.out_steps.val().to_u64(), 3);
        assert_eq!(
            [&u.out_z1, &u.out_z2, &u.out_zmin, &u.out_zmax].map(|s| z(s.val())),
            [986 << 12, 1018 << 12, 986 << 12, 1018 << 12]
        );
        cycle_iter(&mut u, None);
        assert!(!u.out_valid.val());
    }

    #[test]
    fn sizes_are_checked() {
        assert!(matches!(
            MaskSearchIter::<16>::new(MaskSize::S8X8, SearchFamily::DIAGONAL),
            Err(MaskSearchError::Width { .. })
        ));
        assert!(matches!(
            MaskSearchPipe::<64>::new(MaskSize::S8X8, SearchFamily { p: 3, q: 3 }),
            Err(MaskSearchError::TooManyLines { .. })
        ));
        let p = MaskSearchPipe::<64>::new(MaskSize::S8X8, SearchFamily::DIAGONAL).unwrap();
        assert_eq!(p.latency(), 15 + 6);
        assert!(mask_search_verilog(Variant::Pipelined, MaskSize::new(4, 2).unwrap()).is_err());
    }
}
