//! The shading step of seed 001 (Matsumoto, section 2: "correct the intensity and store
//! it in the frame buffer"; section 6 for the table indexed by the normal class and the
//! light mask or counter), on the core's readout path.
//!
//! Each pixel read out of the array passes through nine registers. The shading table
//! (2^15 × 18 bits holding `{G, F}`, written through `tw_*`, indexed by
//! `{NCLASS, MASK[2:0], COUNT[3:0]}`: `pixelproc_formats::core_stream::SHADE_ADDR_FIELDS`)
//! is [`BANKS`] banks of 2^[`BANK_BITS`] entries ([`crate::bank_ram::BankRam`], one ECP5
//! DP16KD each), all read with the low address bits. Stage 0 registers the readout word as
//! it arrives: it comes from the array's readout group registers, which sit with their
//! processors all over the die, and at N = 16, 32 and 64 that route straight into the
//! banks' address pins was the core's critical path on an ECP5 (`docs/fpga.md`). Stage 1
//! registers it again and reads every bank; stage 2 registers every bank's output (inside
//! the bank: on an ECP5 the block RAM's own output register), and per
//! channel `d = max(0, c − s)` (`c` a colour channel, `s` the same channel of shade
//! register `SH`), and whether the pixel is background (`ZB = Z_FAR`, a flag carried to
//! stage 3); stage 2b registers every bank's entry again, in the fabric (from the
//! block RAMs' output registers, spread along the die's block RAM rows, the route to each
//! group's select was the core's critical path at N = 8 to 32 on an ECP5); stage 3 picks,
//! in each group of 8 banks, the entry of the addressed
//! bank, and decides the override below; stage 4 picks the addressed group's entry,
//! applies the override and loads `F`, `G` and each channel's `c` and `d` into the
//! multipliers' operand registers; stage 5 registers the raw products `c·F` and `d·G`
//! ([`crate::mul_reg::MulReg`]: on an ECP5 both registers are the MULT18X18D's own, and
//! nothing sits after the multiplier: the `+ 128` of the rounding behind it was once the
//! critical path, 9.6–10.3 ns); stage 6 rounds them into fabric registers,
//! `(p + 128) >> 8` computed as `(p >> 8) + p[7]` (the same number for every `p ≥ 0`:
//! [`round_q8`]; from the DSP blocks' output registers the route alone took 2.8 ns, too
//! long for the rounding and the subtraction behind it); stage 7 forms
//! `max(0, min(round(c·F), 255) − round(d·G))`: the clamp, the
//! subtraction and the floor at 0, with the clamp decided beside the subtraction rather
//! than before it ([`stage5`]). No step is longer than one block RAM read, one 8-way
//! multiplexer, one 4-way multiplexer, one multiply, one increment, or one subtraction and
//! one multiplexer (a single 2^15-entry RAM put the block RAMs' read, their 32-way output
//! multiplexer and the override in one clock: 12.1 ns on an ECP5; the 32-way multiplexer
//! alone in one clock, from block RAMs spread over the die, 8.5 ns). This is the seed's
//! factor `F` (table mode, `G = 0`) or the
//! exact removal of the shadowed share `G` of light 0 (exact mode, `F = 256`). A
//! background pixel (`ZB = Z_FAR`) and every pixel of a unit built without shading keep
//! their colour. This is `pixelproc_formats::core_stream::shade_rgb`, the golden model's
//! `pixelproc_sim::shadow::shade_row`.
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clock` | in | 1 | rising edge |
//! | `rst` | in | 1 | synchronous: no pixel leaves for the next nine edges |
//! | `in_valid`, `in_word`, `in_meta` | in | 1, 99, 2 | a pixel: readout word, and two flags carried along |
//! | `tw_en`, `tw_addr`, `tw_data` | in | 1, 15, 18 | table write `{G, F}` (ignored without shading); a write on these before edge `E` is in its bank at edge `E + 1` |
//! | `out_valid`, `out_word`, `out_meta` | out | 1, 99, 2 | the pixel nine edges later, its RGB shaded |
//!
//! Latency: a pixel on the inputs before edge `E` is on the outputs after edge `E + 8`
//! ([`LATENCY`] edges).
//!
//! # Table writes
//!
//! A write is registered on its way to the banks ([`TW_DELAY`] = 1 edge): edge `E` loads
//! one write-enable flip-flop per bank, already decoded from the address's top bits, and
//! the address and data into one of [`TW_GROUPS`] copies, one per group of
//! [`BANKS`]` / `[`TW_GROUPS`] banks; edge `E + 1` writes the bank. A copy loads whenever
//! `tw_addr`'s group bits name its group, whether `tw_en` is set or not: its clock enable
//! is two address bits, not the write decode, and the copies differ in it, so synthesis
//! keeps them apart. A write's bank is written with the address and data loaded at the
//! same edge as its enable; what a copy loads without a write is never written. Each bank's write
//! enable comes straight from a flip-flop and each address and data bit drives 8 banks,
//! not 32: on an ECP5 the decode of the input FIFO's head beat in front of all 32 block
//! RAMs' write ports was the core's critical path (`docs/fpga.md`). A pixel entering stage
//! 1 at edge `E + 1` reads the old word (a bank reads the old value of a word written at
//! the same edge), one entering at `E + 2` or later the new one.

use crate::bank_ram::BankRam;
use crate::layout::{ReadoutFields, ReadoutLowFields, ShadeAddrFields, READOUT_W};
use crate::mul_reg::MulReg;
use pixelproc_formats::core_stream::{FACTOR_BITS, SHADE_ADDR_BITS};
use pixelproc_formats::Z_FAR;
use rust_hdl::prelude::*;

mod arith;
pub use arith::{round_q8, stage5};

/// Width of the meta flags carried beside each pixel.
pub const META_W: usize = 2;

/// Rising edges from a pixel on the inputs to the same pixel on the outputs
/// (`pixelproc_formats::core_stream::SHADE_STAGES`, which the golden core model uses).
pub const LATENCY: usize = pixelproc_formats::core_stream::SHADE_STAGES;
const _: () = assert!(LATENCY == 9);

/// Address bits of one table bank (2^10 × 18 bits: one ECP5 DP16KD).
pub const BANK_BITS: usize = crate::bank_ram::BANK_BITS;
// The kernel spells the bank number's offset in the address as the literal 10.
const _: () = assert!(BANK_BITS == 10);
/// Number of table banks.
pub const BANKS: usize = 1 << (SHADE_ADDR_BITS - BANK_BITS);
/// Width of the bank number (the table address's top bits).
const HI_W: usize = SHADE_ADDR_BITS - BANK_BITS;
/// Edges a table write spends in the unit's write registers before its bank takes it
/// (`pixelproc_formats::core_stream::TABLE_WRITE_DELAY`, which the golden core model uses).
pub const TW_DELAY: usize = pixelproc_formats::core_stream::TABLE_WRITE_DELAY;
const _: () = assert!(TW_DELAY == 1);
/// Copies of the write address and data registers, each driving one group of banks.
pub const TW_GROUPS: usize = 4;
/// Width of the group number (the bank number's top bits).
const GROUP_W: usize = 2;
// The kernel spells bank `8·g + j` of group `g` with the literal 8, and the group number's
// offset in the address as the literal 13.
const _: () = assert!(TW_GROUPS == 1 << GROUP_W && BANKS == TW_GROUPS << 3);
const _: () = assert!(BANK_BITS + HI_W - GROUP_W == 13);

/// Width of one product field (`c·F ≤ 255 · 511 < 2^17`). The kernel spells it as the
/// literal 18 (a kernel takes literal widths and offsets).
const PROD_W: usize = 18;
const _: () = assert!(PROD_W == 18);
const _: () = assert!(255 * ((1 << FACTOR_BITS) - 1) < 1 << PROD_W);

/// The shading unit. Build with [`ShadeUnit::new`].
#[derive(LogicBlock)]
pub struct ShadeUnit {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: empties the nine stages.
    pub rst: Signal<In, Bit>,
    /// A pixel is on `in_word`.
    pub in_valid: Signal<In, Bit>,
    /// The pixel's readout word.
    pub in_word: Signal<In, Bits<READOUT_W>>,
    /// Flags carried along unchanged.
    pub in_meta: Signal<In, Bits<META_W>>,
    /// Table write enable.
    pub tw_en: Signal<In, Bit>,
    /// Table write address.
    pub tw_addr: Signal<In, Bits<SHADE_ADDR_BITS>>,
    /// Table write data: `{G, F}`, each Q0.8 (F in the low bits).
    pub tw_data: Signal<In, Bits<ENTRY_W>>,
    /// The shaded pixel is on `out_word`.
    pub out_valid: Signal<Out, Bit>,
    /// The readout word with its RGB shaded.
    pub out_word: Signal<Out, Bits<READOUT_W>>,
    /// The flags.
    pub out_meta: Signal<Out, Bits<META_W>>,
    banks: Vec<BankRam>,
    tw_we: Vec<DFF<Bit>>,
    tw_a: Vec<DFF<Bits<BANK_BITS>>>,
    tw_d: Vec<DFF<Bits<ENTRY_W>>>,
    /// Stage 0: the pixel as it arrives, registered before anything reads it.
    s0_v: DFF<Bit>,
    s0_word: DFF<Bits<READOUT_W>>,
    s0_meta: DFF<Bits<META_W>>,
    s1_v: DFF<Bit>,
    s1_word: DFF<Bits<READOUT_W>>,
    s1_meta: DFF<Bits<META_W>>,
    s1_hi: DFF<Bits<HI_W>>,
    s2_v: DFF<Bit>,
    s2_word: DFF<Bits<READOUT_W>>,
    s2_meta: DFF<Bits<META_W>>,
    s2_hi: DFF<Bits<HI_W>>,
    s2_d: DFF<Bits<24>>,
    /// The pixel is background (`ZB = Z_FAR`), decided in stage 2 and carried to stage
    /// 3's override.
    s2_far: DFF<Bit>,
    /// Stage 2b: every bank's entry again, in a fabric register beside its block RAM,
    /// and the pixel with it.
    s2b_e: Vec<DFF<Bits<ENTRY_W>>>,
    s2b_v: DFF<Bit>,
    s2b_word: DFF<Bits<READOUT_W>>,
    s2b_meta: DFF<Bits<META_W>>,
    s2b_hi: DFF<Bits<HI_W>>,
    s2b_d: DFF<Bits<24>>,
    s2b_far: DFF<Bit>,
    s3_v: DFF<Bit>,
    s3_word: DFF<Bits<READOUT_W>>,
    s3_meta: DFF<Bits<META_W>>,
    s3_d: DFF<Bits<24>>,
    /// Stage 3: the entry of the addressed bank within each group of 8, the group bits,
    /// and whether the override applies.
    s3_e: Vec<DFF<Bits<ENTRY_W>>>,
    s3_grp: DFF<Bits<GROUP_W>>,
    s3_over: DFF<Bit>,
    s4_v: DFF<Bit>,
    s4_word: DFF<Bits<READOUT_W>>,
    s4_meta: DFF<Bits<META_W>>,
    /// The products c·F and d·G per channel: operands registered with stage 4, products
    /// with stage 5 (on an FPGA the DSP block's own registers).
    mf: Vec<MulReg>,
    md: Vec<MulReg>,
    s5_v: DFF<Bit>,
    s5_word: DFF<Bits<READOUT_W>>,
    s5_meta: DFF<Bits<META_W>>,
    s6_v: DFF<Bit>,
    s6_word: DFF<Bits<READOUT_W>>,
    s6_meta: DFF<Bits<META_W>>,
    /// Stage 6: the rounded products `round(c·F)`, `round(d·G)` per channel (9 bits each,
    /// red in the low bits), in the fabric: the route from the DSP blocks' output
    /// registers to the rounding was 2.8 ns, too long to put the subtraction behind it too.
    s6_lit: DFF<Bits<27>>,
    s6_drop: DFF<Bits<27>>,
    l_lits: Signal<Local, Bits<27>>,
    l_drops: Signal<Local, Bits<27>>,
    s7_v: DFF<Bit>,
    s7_word: DFF<Bits<READOUT_W>>,
    s7_meta: DFF<Bits<META_W>>,
    l_eg: Signal<Local, Bits<ENTRY_W>>,
    l_pf: Signal<Local, Bits<{ 3 * PROD_W }>>,
    l_pd: Signal<Local, Bits<{ 3 * PROD_W }>>,
    l_p: Signal<Local, Bits<32>>,
    l_dd: Signal<Local, Bits<24>>,
    l_rgb3: Signal<Local, Bits<24>>,
    l_q: Signal<Local, Bits<PROD_W>>,
    l_addr: Signal<Local, Bits<SHADE_ADDR_BITS>>,
    l_e: Signal<Local, Bits<ENTRY_W>>,
    l_f: Signal<Local, Bits<16>>,
    l_g: Signal<Local, Bits<16>>,
    l_rgb: Signal<Local, Bits<24>>,
    l_sh: Signal<Local, Bits<24>>,
    l_ch: Signal<Local, Bits<8>>,
    l_sc: Signal<Local, Bits<8>>,
    l_d: Signal<Local, Bits<8>>,
    l_lit: Signal<Local, Bits<9>>,
    l_drop: Signal<Local, Bits<9>>,
    l_diff: Signal<Local, Bits<10>>,
    l_out: Signal<Local, Bits<24>>,
    l_word: Signal<Local, Bits<READOUT_W>>,
    k_on: Constant<Bit>,
    k_zero_e: Constant<Bits<ENTRY_W>>,
    k_far: Constant<Bits<24>>,
    k_one: Constant<Bits<16>>,
    k_zero_addr: Constant<Bits<SHADE_ADDR_BITS>>,
    k_zero24: Constant<Bits<24>>,
    k_zero16: Constant<Bits<16>>,
    k_zero8: Constant<Bits<8>>,
    k_zero54: Constant<Bits<{ 3 * PROD_W }>>,
    k_zero27: Constant<Bits<27>>,
    k_zero32: Constant<Bits<32>>,
}

/// Width of a table entry `{G, F}`.
pub const ENTRY_W: usize = 2 * FACTOR_BITS;
const _: () = assert!(ENTRY_W == crate::bank_ram::ENTRY_W);
const _: () = assert!(FACTOR_BITS == 9);

impl ShadeUnit {
    /// A unit that shades (`shading`) or passes colours through with the same latency;
    /// without shading it has no table and no multipliers, and the table-write ports are
    /// unused.
    pub fn new(shading: bool) -> ShadeUnit {
        // Without shading the pixel only needs the latency: no table, no multipliers
        // (as instances, synthesis could not remove them; the colour is passed through).
        let (banks, groups, channels) = if shading {
            (BANKS, TW_GROUPS, 3)
        } else {
            (0, 0, 0)
        };
        ShadeUnit {
            clock: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_word: Default::default(),
            in_meta: Default::default(),
            tw_en: Default::default(),
            tw_addr: Default::default(),
            tw_data: Default::default(),
            out_valid: Default::default(),
            out_word: Default::default(),
            out_meta: Default::default(),
            banks: (0..banks).map(|_| Default::default()).collect(),
            tw_we: (0..banks).map(|_| Default::default()).collect(),
            tw_a: (0..groups).map(|_| Default::default()).collect(),
            tw_d: (0..groups).map(|_| Default::default()).collect(),
            s0_v: Default::default(),
            s0_word: Default::default(),
            s0_meta: Default::default(),
            s1_v: Default::default(),
            s1_word: Default::default(),
            s1_meta: Default::default(),
            s1_hi: Default::default(),
            s2_v: Default::default(),
            s2_word: Default::default(),
            s2_meta: Default::default(),
            s2_hi: Default::default(),
            s2_d: Default::default(),
            s2_far: Default::default(),
            s2b_e: (0..banks).map(|_| Default::default()).collect(),
            s2b_v: Default::default(),
            s2b_word: Default::default(),
            s2b_meta: Default::default(),
            s2b_hi: Default::default(),
            s2b_d: Default::default(),
            s2b_far: Default::default(),
            s3_v: Default::default(),
            s3_word: Default::default(),
            s3_meta: Default::default(),
            s3_d: Default::default(),
            s3_e: (0..groups).map(|_| Default::default()).collect(),
            s3_grp: Default::default(),
            s3_over: Default::default(),
            s4_v: Default::default(),
            s4_word: Default::default(),
            s4_meta: Default::default(),
            mf: (0..channels).map(|_| Default::default()).collect(),
            md: (0..channels).map(|_| Default::default()).collect(),
            s5_v: Default::default(),
            s5_word: Default::default(),
            s5_meta: Default::default(),
            s6_v: Default::default(),
            s6_word: Default::default(),
            s6_meta: Default::default(),
            s6_lit: Default::default(),
            s6_drop: Default::default(),
            l_lits: Default::default(),
            l_drops: Default::default(),
            s7_v: Default::default(),
            s7_word: Default::default(),
            s7_meta: Default::default(),
            l_eg: Default::default(),
            l_pf: Default::default(),
            l_pd: Default::default(),
            l_p: Default::default(),
            l_dd: Default::default(),
            l_rgb3: Default::default(),
            l_q: Default::default(),
            l_addr: Default::default(),
            l_e: Default::default(),
            l_f: Default::default(),
            l_g: Default::default(),
            l_rgb: Default::default(),
            l_sh: Default::default(),
            l_ch: Default::default(),
            l_sc: Default::default(),
            l_d: Default::default(),
            l_lit: Default::default(),
            l_drop: Default::default(),
            l_diff: Default::default(),
            l_out: Default::default(),
            l_word: Default::default(),
            k_on: Constant::new(shading),
            k_zero_e: Constant::new(0u64.to_bits()),
            k_far: Constant::new((Z_FAR as u64).to_bits()),
            k_one: Constant::new(256u64.to_bits()),
            k_zero_addr: Constant::new(0u64.to_bits()),
            k_zero24: Constant::new(0u64.to_bits()),
            k_zero16: Constant::new(0u64.to_bits()),
            k_zero8: Constant::new(0u64.to_bits()),
            k_zero54: Constant::new(0u64.to_bits()),
            k_zero27: Constant::new(0u64.to_bits()),
            k_zero32: Constant::new(0u64.to_bits()),
        }
    }
}

impl Logic for ShadeUnit {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, s0_v, s0_word, s0_meta, s1_v, s1_word, s1_meta, s1_hi, s2_v, s2_word,
            s2_meta, s2_hi, s2_d, s2_far, s2b_v, s2b_word, s2b_meta, s2b_hi, s2b_d, s2b_far, s3_v,
            s3_word, s3_meta, s3_d, s3_grp, s3_over, s4_v, s4_word, s4_meta, s5_v, s5_word,
            s5_meta, s6_v, s6_word, s6_meta, s6_lit, s6_drop, s7_v, s7_word, s7_meta
        );
        // ---- Stage 0: register the pixel as it arrives (the core's readout word comes
        // from the array's group registers, spread over the die with the processors: this
        // register ends that route, and the banks' address starts from it).
        self.s0_v.d.next = self.in_valid.val();
        self.s0_word.d.next = self.in_word.val();
        self.s0_meta.d.next = self.in_meta.val();
        // ---- Stage 1: register the pixel again, read every bank at the low address bits.
        self.l_addr.next = self.k_zero_addr.val();
        self.l_addr
            .next
            .set_value_scount(self.s0_word.q.val().get_value_count_lo());
        self.l_addr
            .next
            .set_value_smask(self.s0_word.q.val().get_value_mask_lo());
        self.l_addr
            .next
            .set_value_snclass(self.s0_word.q.val().get_value_nclass());
        // Table writes, registered once (module header): a decoded write enable per bank,
        // the address and data per group of banks, loaded whenever `tw_addr` names the
        // group, write or not (the bank writes only with its enable, and a write's
        // address and data are the ones loaded at the edge that loads its enable).
        for i in 0..self.tw_we.len() {
            self.tw_we[i].clock.next = self.clock.val();
            self.tw_we[i].d.next = self.tw_en.val()
                & self.k_on.val()
                & (self.tw_addr.val().get_bits::<HI_W>(10).index() == i);
        }
        for g in 0..self.tw_a.len() {
            self.tw_a[g].clock.next = self.clock.val();
            self.tw_d[g].clock.next = self.clock.val();
            self.tw_a[g].d.next = self.tw_a[g].q.val();
            self.tw_d[g].d.next = self.tw_d[g].q.val();
            if self.tw_addr.val().get_bits::<GROUP_W>(13).index() == g {
                self.tw_a[g].d.next = self.tw_addr.val().get_bits::<BANK_BITS>(0);
                self.tw_d[g].d.next = self.tw_data.val();
            }
        }
        for g in 0..self.tw_a.len() {
            for j in 0..8 {
                self.banks[8 * g + j].clock.next = self.clock.val();
                self.banks[8 * g + j].write_enable.next = self.tw_we[8 * g + j].q.val();
                self.banks[8 * g + j].write_address.next = self.tw_a[g].q.val();
                self.banks[8 * g + j].write_data.next = self.tw_d[g].q.val();
                self.banks[8 * g + j].read_address.next =
                    self.l_addr.val().get_bits::<BANK_BITS>(0);
            }
        }
        self.s1_v.d.next = self.s0_v.q.val();
        self.s1_word.d.next = self.s0_word.q.val();
        self.s1_meta.d.next = self.s0_meta.q.val();
        self.s1_hi.d.next = self.l_addr.val().get_bits::<HI_W>(10);
        // ---- Stage 2: every bank's entry, registered inside the bank (`BankRam`: on an
        // ECP5 the block RAM's output register); per channel d = max(0, c − s).
        self.l_rgb.next = self.s1_word.q.val().get_value_rgb();
        self.l_sh.next = self.s1_word.q.val().get_value_sh();
        self.l_dd.next = self.k_zero24.val();
        for c in 0..3 {
            self.l_ch.next = self.l_rgb.val().get_bits::<8>(8 * c);
            self.l_sc.next = self.l_sh.val().get_bits::<8>(8 * c);
            self.l_d.next = self.k_zero8.val();
            if self.l_ch.val() > self.l_sc.val() {
                self.l_d.next = self.l_ch.val() - self.l_sc.val();
            }
            self.l_dd.next = (self.l_dd.val() >> 8) | (bit_cast::<24, 8>(self.l_d.val()) << 16);
        }
        self.s2_v.d.next = self.s1_v.q.val();
        self.s2_word.d.next = self.s1_word.q.val();
        self.s2_meta.d.next = self.s1_meta.q.val();
        self.s2_hi.d.next = self.s1_hi.q.val();
        self.s2_d.d.next = self.l_dd.val();
        // The background test for stage 3's override, two stages early: the word does
        // not change on its way, and the 24-bit compare in front of `s3_over`, from the
        // wide stage 2b register, was among the core's worst paths at N = 8, 16 and 32
        // on an ECP5 (`docs/fpga.md`).
        self.s2_far.d.next = self.s1_word.q.val().get_value_zb() == self.k_far.val();
        // ---- Stage 2b: every bank's entry into a fabric register (the route from a block
        // RAM's output register to its group's 8-way select was the core's critical path
        // at N = 16 and 32 on an ECP5, `docs/fpga.md`), the pixel alongside.
        for b in 0..self.s2b_e.len() {
            self.s2b_e[b].clock.next = self.clock.val();
            self.s2b_e[b].d.next = self.banks[b].read_data.val();
        }
        self.s2b_v.d.next = self.s2_v.q.val();
        self.s2b_word.d.next = self.s2_word.q.val();
        self.s2b_meta.d.next = self.s2_meta.q.val();
        self.s2b_hi.d.next = self.s2_hi.q.val();
        self.s2b_d.d.next = self.s2_d.q.val();
        self.s2b_far.d.next = self.s2_far.q.val();
        // ---- Stage 3: within each group of 8 banks the addressed bank's entry (a 32-way
        // multiplexer in one clock, from block RAMs spread over the die, was the core's
        // critical path), the group bits, and whether the override (background, or no
        // shading) applies.
        // (Driven outside the loops too: without shading they do not run.)
        self.l_eg.next = self.k_zero_e.val();
        for g in 0..self.s3_e.len() {
            self.s3_e[g].clock.next = self.clock.val();
            self.l_eg.next = self.k_zero_e.val();
            for j in 0..8 {
                if self.s2b_hi.q.val().get_bits::<3>(0).index() == j {
                    self.l_eg.next = self.s2b_e[8 * g + j].q.val();
                }
            }
            self.s3_e[g].d.next = self.l_eg.val();
        }
        self.s3_grp.d.next = self.s2b_hi.q.val().get_bits::<GROUP_W>(3);
        self.s3_over.d.next = !self.k_on.val() | self.s2b_far.q.val();
        self.s3_v.d.next = self.s2b_v.q.val();
        self.s3_word.d.next = self.s2b_word.q.val();
        self.s3_meta.d.next = self.s2b_meta.q.val();
        self.s3_d.d.next = self.s2b_d.q.val();
        // ---- Stage 4: the addressed group's entry, `F` and `G` (or the override), into
        // the multipliers' operand registers with each channel's `c` and `d`.
        self.l_e.next = self.k_zero_e.val();
        for g in 0..self.s3_e.len() {
            if self.s3_grp.q.val().index() == g {
                self.l_e.next = self.s3_e[g].q.val();
            }
        }
        self.l_f.next = bit_cast::<16, FACTOR_BITS>(self.l_e.val().get_bits::<FACTOR_BITS>(0));
        self.l_g.next = bit_cast::<16, FACTOR_BITS>(
            self.l_e.val().get_bits::<FACTOR_BITS>(9), // a kernel takes literal offsets: FACTOR_BITS
        );
        if self.s3_over.q.val() {
            self.l_f.next = self.k_one.val();
            self.l_g.next = self.k_zero16.val();
        }
        self.l_rgb3.next = self.s3_word.q.val().get_value_rgb();
        self.l_pf.next = self.k_zero54.val();
        self.l_pd.next = self.k_zero54.val();
        self.l_p.next = self.k_zero32.val();
        for c in 0..self.mf.len() {
            self.mf[c].clock.next = self.clock.val();
            self.md[c].clock.next = self.clock.val();
            self.l_ch.next = self.l_rgb3.val().get_bits::<8>(8 * c);
            self.mf[c].a.next = bit_cast::<16, 8>(self.l_ch.val());
            self.mf[c].b.next = self.l_f.val();
            self.l_sc.next = self.s3_d.q.val().get_bits::<8>(8 * c);
            self.md[c].a.next = bit_cast::<16, 8>(self.l_sc.val());
            self.md[c].b.next = self.l_g.val();
            // ---- Stage 5: the raw products c·F and d·G (rounded in stage 7), registered
            // inside the multipliers. (A kernel's loop index cannot go into a function's
            // arguments: via `l_p`.)
            self.l_p.next = self.mf[c].p.val();
            self.l_pf.next = (self.l_pf.val() >> 18)
                | (bit_cast::<54, 18>(self.l_p.val().get_bits::<18>(0)) << 36);
            self.l_p.next = self.md[c].p.val();
            self.l_pd.next = (self.l_pd.val() >> 18)
                | (bit_cast::<54, 18>(self.l_p.val().get_bits::<18>(0)) << 36);
        }
        self.s4_v.d.next = self.s3_v.q.val();
        self.s4_word.d.next = self.s3_word.q.val();
        self.s4_meta.d.next = self.s3_meta.q.val();
        self.s5_v.d.next = self.s4_v.q.val();
        self.s5_word.d.next = self.s4_word.q.val();
        self.s5_meta.d.next = self.s4_meta.q.val();
        // ---- Stage 6, per channel: round each product p to (p >> 8) + p[7]
        // (= (p + 128) >> 8: `round_q8`), 9 bits wide (p < 2^17).
        self.s6_v.d.next = self.s5_v.q.val();
        self.s6_word.d.next = self.s5_word.q.val();
        self.s6_meta.d.next = self.s5_meta.q.val();
        self.l_lits.next = self.k_zero27.val();
        self.l_drops.next = self.k_zero27.val();
        for c in 0..3 {
            // (A kernel's loop index cannot go into a function's arguments: via `l_q`.)
            self.l_q.next = self.l_pf.val().get_bits::<18>(18 * c);
            self.l_lit.next =
                self.l_q.val().get_bits::<9>(8) + bit_cast::<9, 1>(self.l_q.val().get_bits::<1>(7));
            self.l_lits.next =
                (self.l_lits.val() >> 9) | (bit_cast::<27, 9>(self.l_lit.val()) << 18);
            self.l_q.next = self.l_pd.val().get_bits::<18>(18 * c);
            self.l_drop.next =
                self.l_q.val().get_bits::<9>(8) + bit_cast::<9, 1>(self.l_q.val().get_bits::<1>(7));
            self.l_drops.next =
                (self.l_drops.val() >> 9) | (bit_cast::<27, 9>(self.l_drop.val()) << 18);
        }
        self.s6_lit.d.next = self.l_lits.val();
        self.s6_drop.d.next = self.l_drops.val();
        // ---- Stage 7, per channel (`stage5`, the same steps on integers, after the
        // rounding): lit = min(round(pf), 255), drop = round(pd), out = max(0, lit − drop).
        // The clamp is not a multiplexer before the subtraction: bit 8 of round(pf) says lit
        // is 255, and then out = 255 − drop = !drop[7:0] when drop < 256, else 0; otherwise
        // out is the 10-bit difference round(pf) − drop floored at 0. One short carry chain
        // and one multiplexer.
        self.l_out.next = self.k_zero24.val();
        for c in 0..3 {
            self.l_lit.next = self.s6_lit.q.val().get_bits::<9>(9 * c);
            self.l_drop.next = self.s6_drop.q.val().get_bits::<9>(9 * c);
            self.l_diff.next =
                bit_cast::<10, 9>(self.l_lit.val()) - bit_cast::<10, 9>(self.l_drop.val());
            self.l_d.next = self.k_zero8.val();
            if self.l_lit.val().get_bit(8) {
                if !self.l_drop.val().get_bit(8) {
                    self.l_d.next = !self.l_drop.val().get_bits::<8>(0);
                }
            } else if !self.l_diff.val().get_bit(9) {
                self.l_d.next = self.l_diff.val().get_bits::<8>(0);
            }
            self.l_out.next = (self.l_out.val() >> 8) | (bit_cast::<24, 8>(self.l_d.val()) << 16);
        }
        if !self.k_on.val() {
            // No shading: the colour passes unchanged (as `F = 256`, `G = 0` would give).
            self.l_out.next = self.s6_word.q.val().get_value_rgb();
        }
        self.l_word.next = self.s6_word.q.val();
        self.l_word.next.set_value_rgb(self.l_out.val());
        self.s7_v.d.next = self.s6_v.q.val();
        self.s7_word.d.next = self.l_word.val();
        self.s7_meta.d.next = self.s6_meta.q.val();
        self.out_valid.next = self.s7_v.q.val();
        self.out_word.next = self.s7_word.q.val();
        self.out_meta.next = self.s7_meta.q.val();
        if self.rst.val() {
            self.s0_v.d.next = false;
            self.s1_v.d.next = false;
            self.s2_v.d.next = false;
            self.s2b_v.d.next = false;
            self.s3_v.d.next = false;
            self.s4_v.d.next = false;
            self.s5_v.d.next = false;
            self.s6_v.d.next = false;
            self.s7_v.d.next = false;
        }
    }
}

#[cfg(test)]
mod tests;
