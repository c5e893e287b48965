//! The pixel-processor array: `N` [`PixelProcessor`]s in a systolic chain behind a
//! four-stage entry pipeline (seed 001, Matsumoto, sections 1, 3, 4 and 6).
//!
//! # Ports and handshake
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clock` | in | 1 | all registers update on the rising edge |
//! | `rst` | in | 1 | synchronous reset, sent down the chain as a RESET token: `ZB := Z_FAR`, RGB, NCLASS, flags, counter, mask, readout := 0 (readout `ZB := Z_FAR`) |
//! | `cmd_valid` | in | 1 | a command is present; `0` is a NOP |
//! | `cmd_op` | in | 3 | opcode, [`crate::opcodes`] |
//! | `cmd_bg` | in | 24 | argument: background RGB888 for CLEAR_LINE, light bit (`[2:0]`) for LATCH_SHADOW |
//! | `cmd_word` | in | 256 | packed span word (`SpanWord::pack` layout) for SPAN; `XL`/`XR` fields for CHECK |
//! | `tile_base` | in | 12 | first screen column of the tile, sampled with each command |
//! | `rd_addr` | in | 12 | processor index to read out |
//! | `rd_zb`, `rd_rgb`, `rd_dsf`, `rd_fsf`, `rd_count`, `rd_mask`, `rd_nclass`, `rd_sh`, `rd_won` | out | 24, 24, 1, 1, 8, 8, 8, 24, 1 | readout registers of processor `rd_addr` |
//!
//! The array accepts one command on every clock; there is no back-pressure (`ready` is
//! always 1), so a source simply drives `cmd_valid` high for each command.
//!
//! # Latency and the relation to the golden model
//!
//! A command sampled on the input ports at rising edge `E` is applied to processor `p`'s
//! registers at rising edge `E + LATENCY_PROC0 + p` ([`LATENCY_PROC0`] = 6: input
//! register, decode, partial products, partial sums, token register, decision register).
//! So after edge `T`, processor `p` holds the golden `PixelArray` state of processor `p`
//! after the commands sampled at edges `.. ≤ T − 6 − p`. Commands never interact across
//! processors, so this skew is invisible in the result. `rst` is such a command too: a
//! processor holds its power-up values until the RESET token reaches it.
//!
//! # New scanline and readout
//!
//! CLEAR_LINE first copies each processor's registers into its readout registers, then
//! sets `ZB := Z_FAR`, RGB := `cmd_bg`, NCLASS = DSF = FSF = COUNT = MASK := 0. After a
//! line's last command, send the next line's CLEAR_LINE (or a final one); `N + 5` clocks
//! after it was
//! sampled, every processor's readout registers hold the finished line and stay valid
//! until the next CLEAR_LINE reaches them. They are read with `rd_addr`: the value for
//! `rd_addr` sampled at edge `E` selects processor `a` at edge `E + 1` (a select flip-flop
//! in each processor), and `rd_*` show `a`'s readout registers as they were after edge
//! `E + 1` from edge `E + 2` on (address register, select register, output register;
//! an address `>= N` reads 0). The OR of the one selected processor's registers
//! replaces a wide multiplexer, so no address decode sits in the data path. Readout of
//! line `j` thus overlaps the span words of line `j + 1`.
//!
//! # Why a systolic chain
//!
//! `Z(p) = ZL + (p − XL)·dZ` is produced by one 44-bit adder per processor (`+dZ` from
//! one processor to the next, the Super Buffer structure the seed cites) instead of a
//! 38×12-bit multiplier per processor. The only multiplication is the tile offset
//! `max(0, base − XL)·dZ` (a span that started in an earlier tile), done once at the
//! entry with nine 16×16 products (three for Z, two per colour channel) in a pipeline.
//! Every stage is a register-to-register path of one adder, so the clock rate does not
//! depend on `N`; the cost is one token register per processor and `N + 6` clocks of
//! latency.

use crate::colour_lane::DI_W;
use crate::entry_channel::{EntryChannel, IL_W, MUL_W, PROD_W};
use crate::layout::{HeadFields, ReadoutFields, SpanFields, HEAD_W, READOUT_W, SPAN_W};
use crate::mul_reg::MulReg;
use crate::opcodes::*;
use crate::pixel_processor::{PixelProcessor, DI3_W, I3_W, IACC_W, REL_W, ZACC_W};
use pixelproc_formats::regs::{COUNT_BITS, MASK_BITS, RGB_BITS};
use pixelproc_formats::{
    Attr, MAX_SCREEN, SPAN_ATTR, SPAN_DZ, SPAN_NCLASS, SPAN_XL, SPAN_ZL, Z_BITS,
};
/// Width of the span attribute.
const ATTR_W: usize = SPAN_ATTR.width;
use rust_hdl::prelude::*;

/// Processors whose readout registers are gathered into one group register.
pub const READOUT_GROUP: usize = 8;

/// Width of a column number (`XL`, `XR`, `tile_base`, `rd_addr`).
const X_W: usize = SPAN_XL.width;
/// Width of `ZL`.
const ZL_W: usize = SPAN_ZL.width;
/// Width of `dZ`.
const DZ_W: usize = SPAN_DZ.width;
/// Width of the three packed `IL` of a span word.
const IL3_W: usize = 3 * IL_W;
/// Width of the normal class.
const NCLASS_W: usize = SPAN_NCLASS.width;
/// Width of a depth register.
const ZB_W: usize = Z_BITS as usize;
/// Bits of `dZ` above its two low multiplier operands.
const DZ_HI_W: usize = DZ_W - PROD_W;
// A kernel can only take literal bit positions: the operand splits at 16 and 32, the sign
// bit 37 and the weight 2^38 (`dZ`), and the channel strides 20 (`IL`), 21 (`dI`) and 34
// (accumulators) below are these widths.
const _: () = assert!(MUL_W == 16 && DZ_W == 38 && DI_W == 21 && IL_W == 20 && REL_W == 14);

/// Rising edges from sampling a command to its effect on processor 0's registers.
pub const LATENCY_PROC0: usize = 6;

/// The pixel-processor array. Build with [`PixelProcessorArray::new`].
#[derive(LogicBlock)]
pub struct PixelProcessorArray {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// Command valid.
    pub cmd_valid: Signal<In, Bit>,
    /// Command opcode.
    pub cmd_op: Signal<In, Bits<OP_BITS>>,
    /// Background colour for CLEAR_LINE, RGB888.
    pub cmd_bg: Signal<In, Bits<RGB_BITS>>,
    /// Packed span word for SPAN.
    pub cmd_word: Signal<In, Bits<SPAN_W>>,
    /// First screen column of the tile the array is processing.
    pub tile_base: Signal<In, Bits<X_W>>,
    /// Readout address (processor index).
    pub rd_addr: Signal<In, Bits<X_W>>,
    /// Readout: depth.
    pub rd_zb: Signal<Out, Bits<ZB_W>>,
    /// Readout: RGB888.
    pub rd_rgb: Signal<Out, Bits<RGB_BITS>>,
    /// Readout: DSF.
    pub rd_dsf: Signal<Out, Bit>,
    /// Readout: FSF.
    pub rd_fsf: Signal<Out, Bit>,
    /// Readout: shadow count.
    pub rd_count: Signal<Out, Bits<COUNT_BITS>>,
    /// Readout: light mask.
    pub rd_mask: Signal<Out, Bits<MASK_BITS>>,
    /// Readout: normal class.
    pub rd_nclass: Signal<Out, Bits<NCLASS_W>>,
    /// Readout: shade register 1 (RGB888).
    pub rd_sh: Signal<Out, Bits<RGB_BITS>>,
    /// Readout: the WON flag.
    pub rd_won: Signal<Out, Bit>,
    /// The processors, processor 0 (column `tile_base`) first.
    pub procs: Vec<PixelProcessor>,
    // E1: input registers.
    e1_op: DFF<Bits<OP_BITS>>,
    e1_bg: DFF<Bits<RGB_BITS>>,
    e1_word: DFF<Bits<SPAN_W>>,
    e1_base: DFF<Bits<X_W>>,
    /// `base − XL` of the command, registered: the tile offset's subtraction done in
    /// front of E1, so that E2 feeds the multipliers' operand registers through one gate.
    e1_d: DFF<Bits<REL_W>>,
    /// The command in E1 is a SPAN (what `e1_op = SPAN` says, registered on its own).
    e1_span: DFF<Bit>,
    e1_rd: DFF<Bits<X_W>>,
    // E2: decoded word, tile offset m = max(0, base − XL).
    e2_head: DFF<Bits<HEAD_W>>,
    e2_m: DFF<Bits<MUL_W>>,
    e2_zl: DFF<Bits<ZL_W>>,
    e2_dz: DFF<Bits<DZ_W>>,
    // E3: partial products.
    e3_head: DFF<Bits<HEAD_W>>,
    /// `ZL − s·m·2^38` (`s` the sign of dZ): the correction of the signed product
    /// `m·dZ` taken here from E2's fabric registers, so that E4's adds take the DSP
    /// products with nothing in front of them.
    e3_zs: DFF<Bits<ZACC_W>>,
    e3_dz: DFF<Bits<DZ_W>>,
    /// The partial products m·dZ (low, middle, high 16 bits of dZ): operands registered
    /// with E2, products with E3 (on an FPGA the DSP block's own registers).
    mz: [MulReg; 3],
    // E4: two partial sums per quantity.
    e4_head: DFF<Bits<HEAD_W>>,
    e4_dz: DFF<Bits<DZ_W>>,
    e4_za: DFF<Bits<ZACC_W>>,
    e4_zb: DFF<Bits<ZACC_W>>,
    // Readout output registers.
    rd_g: Vec<DFF<Bits<READOUT_W>>>,
    l_grp: Vec<Signal<Local, Bits<READOUT_W>>>,
    k_reset: Constant<Bits<OP_BITS>>,
    k_zero74: Constant<Bits<READOUT_W>>,
    l_rd: Signal<Local, Bits<READOUT_W>>,
    k_nop: Constant<Bits<OP_BITS>>,
    k_span: Constant<Bits<OP_BITS>>,
    k_attr_op: Constant<Bits<ATTR_W>>,
    k_zero16: Constant<Bits<MUL_W>>,
    k_zero38: Constant<Bits<DZ_W>>,
    l_xr: Signal<Local, Bits<REL_W>>,
    l_base: Signal<Local, Bits<REL_W>>,
    /// `base − XL` of the command at the inputs.
    l_d0: Signal<Local, Bits<REL_W>>,
    /// The values E2's `m` and `dZ` registers load (the multipliers' operands).
    l_m1: Signal<Local, Bits<MUL_W>>,
    l_dz1: Signal<Local, Bits<DZ_W>>,
    l_dzmid: Signal<Local, Bits<MUL_W>>,
    l_dzhi: Signal<Local, Bits<MUL_W>>,
    l_head: Signal<Local, Bits<HEAD_W>>,
    k_zero_head: Constant<Bits<HEAD_W>>,
    /// E2..E4 of the red, green and blue channels.
    chans: [EntryChannel; 3],
    l_span: Signal<Local, Bit>,
    l_il3: Signal<Local, Bits<IL3_W>>,
    l_di3: Signal<Local, Bits<DI3_W>>,
    l_ch_i: Signal<Local, Bits<IACC_W>>,
    l_ch_di: Signal<Local, Bits<DI_W>>,
    l_ti: Signal<Local, Bits<I3_W>>,
    l_tdi: Signal<Local, Bits<DI3_W>>,
    k_zero_i3: Constant<Bits<I3_W>>,
    k_zero_di3: Constant<Bits<DI3_W>>,
}

impl PixelProcessorArray {
    /// An array of `width` processors (1 ..= `MAX_SCREEN`), with the span-parity logic in every
    /// processor iff `shadows`.
    pub fn new(width: usize, shadows: bool) -> Result<Self, crate::RtlError> {
        if width == 0 || width > MAX_SCREEN as usize {
            return Err(crate::RtlError::BadWidth(width));
        }
        fn k<const W: usize>(v: u64) -> Constant<Bits<W>> {
            Constant::new(v.to_bits())
        }
        Ok(PixelProcessorArray {
            clock: Default::default(),
            rst: Default::default(),
            cmd_valid: Default::default(),
            cmd_op: Default::default(),
            cmd_bg: Default::default(),
            cmd_word: Default::default(),
            tile_base: Default::default(),
            rd_addr: Default::default(),
            rd_zb: Default::default(),
            rd_rgb: Default::default(),
            rd_dsf: Default::default(),
            rd_fsf: Default::default(),
            rd_count: Default::default(),
            rd_mask: Default::default(),
            rd_nclass: Default::default(),
            rd_sh: Default::default(),
            rd_won: Default::default(),
            procs: (0..width).map(|_| PixelProcessor::new(shadows)).collect(),
            e1_op: Default::default(),
            e1_bg: Default::default(),
            e1_word: Default::default(),
            e1_base: Default::default(),
            e1_d: Default::default(),
            e1_span: Default::default(),
            e1_rd: Default::default(),
            e2_head: Default::default(),
            e2_m: Default::default(),
            e2_zl: Default::default(),
            e2_dz: Default::default(),
            e3_head: Default::default(),
            e3_zs: Default::default(),
            e3_dz: Default::default(),
            mz: Default::default(),
            e4_head: Default::default(),
            e4_dz: Default::default(),
            e4_za: Default::default(),
            e4_zb: Default::default(),
            rd_g: (0..width.div_ceil(READOUT_GROUP))
                .map(|_| Default::default())
                .collect(),
            l_grp: (0..width.div_ceil(READOUT_GROUP))
                .map(|_| Default::default())
                .collect(),
            k_reset: Constant::new(OP_RESET.to_bits()),
            k_zero74: Constant::new(0u64.to_bits()),
            l_rd: Default::default(),
            k_nop: Constant::new(OP_NOP.to_bits()),
            k_span: Constant::new(OP_SPAN.to_bits()),
            k_attr_op: Constant::new((Attr::Op.code() as u64).to_bits()),
            k_zero16: k(0),
            k_zero38: k(0),
            l_xr: Default::default(),
            l_base: Default::default(),
            l_d0: Default::default(),
            l_m1: Default::default(),
            l_dz1: Default::default(),
            l_dzmid: Default::default(),
            l_dzhi: Default::default(),
            l_head: Default::default(),
            k_zero_head: k(0),
            chans: std::array::from_fn(|_| EntryChannel::new()),
            l_span: Default::default(),
            l_il3: Default::default(),
            l_di3: Default::default(),
            l_ch_i: Default::default(),
            l_ch_di: Default::default(),
            l_ti: Default::default(),
            l_tdi: Default::default(),
            k_zero_i3: k(0),
            k_zero_di3: k(0),
        })
    }

    /// Number of processors.
    pub fn width(&self) -> usize {
        self.procs.len()
    }

    /// True if the processors carry the span-parity logic.
    pub fn has_shadows(&self) -> bool {
        self.procs.first().is_some_and(|p| p.has_shadows())
    }
}

impl Logic for PixelProcessorArray {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, e1_op, e1_bg, e1_word, e1_base, e1_d, e1_span, e1_rd, e2_head, e2_m,
            e2_zl, e2_dz, e3_head, e3_zs, e3_dz, e4_head, e4_dz, e4_za, e4_zb
        );
        // ---- E1: register every input.
        self.e1_op.d.next = self.k_nop.val();
        if self.cmd_valid.val() {
            self.e1_op.d.next = self.cmd_op.val();
        }
        if self.rst.val() {
            // Reset travels down the pipeline and the chain as a token.
            self.e1_op.d.next = self.k_reset.val();
        }
        self.e1_bg.d.next = self.cmd_bg.val();
        self.e1_word.d.next = self.cmd_word.val();
        self.e1_base.d.next = self.tile_base.val();
        self.l_d0.next = bit_cast::<REL_W, X_W>(self.tile_base.val())
            - bit_cast::<REL_W, X_W>(self.cmd_word.val().get_value_xl());
        self.e1_d.d.next = self.l_d0.val();
        self.e1_span.d.next =
            self.cmd_valid.val() & (self.cmd_op.val() == self.k_span.val()) & !self.rst.val();
        self.e1_rd.d.next = self.rd_addr.val();
        // ---- E2: decode the span word (fields of `pixelproc_formats::SPAN_FIELDS`).
        self.l_xr.next = bit_cast::<REL_W, X_W>(self.e1_word.q.val().get_value_xr());
        self.l_base.next = bit_cast::<REL_W, X_W>(self.e1_base.q.val());
        self.l_head.next = self.k_zero_head.val();
        self.l_head.next.set_value_op(self.e1_op.q.val());
        self.l_head
            .next
            .set_value_attr(self.e1_word.q.val().get_value_attr());
        self.l_head
            .next
            .set_value_decal(self.e1_word.q.val().get_value_decal());
        self.l_head
            .next
            .set_value_nclass(self.e1_word.q.val().get_value_nclass());
        self.l_head
            .next
            .set_value_chan(self.e1_word.q.val().get_value_chan());
        // XL − base − 1 = −(base − XL) − 1, the complement of `e1_d`.
        self.l_head.next.set_value_rel_l(!self.e1_d.q.val());
        self.l_head
            .next
            .set_value_rel_r(self.l_xr.val() - self.l_base.val());
        self.e2_head.d.next = self.l_head.val();
        self.e2_zl.d.next = self.e1_word.q.val().get_value_zl();
        self.l_dz1.next = self.e1_word.q.val().get_value_dz();
        // Tile offset: the span started `base − XL` columns before this tile.
        self.l_m1.next = self.k_zero16.val();
        if self.e1_span.q.val() & !self.e1_d.q.val().get_bit(13) {
            self.l_m1.next = bit_cast::<MUL_W, REL_W>(self.e1_d.q.val());
        }
        if !self.e1_span.q.val() {
            // No increments; CLEAR_LINE carries the background in the Z accumulator.
            self.l_dz1.next = self.k_zero38.val();
            self.e2_zl.d.next = bit_cast::<ZL_W, RGB_BITS>(self.e1_bg.q.val());
        }
        self.e2_m.d.next = self.l_m1.val();
        self.e2_dz.d.next = self.l_dz1.val();
        // ---- E2..E4 of the colour channels, one block each; their results packed red
        // first for processor 0 (`bit_cast` cannot take the loop index: go through locals).
        self.l_span.next = self.e1_span.q.val();
        self.l_il3.next = self.e1_word.q.val().get_value_il();
        self.l_di3.next = self.e1_word.q.val().get_value_di();
        self.l_ti.next = self.k_zero_i3.val();
        self.l_tdi.next = self.k_zero_di3.val();
        for c in 0..3 {
            self.chans[c].clock.next = self.clock.val();
            self.chans[c].il.next = self.l_il3.val().get_bits::<IL_W>(20 * c);
            self.chans[c].di.next = self.l_di3.val().get_bits::<DI_W>(21 * c);
            self.chans[c].span.next = self.l_span.val();
            self.chans[c].m1.next = self.l_m1.val();
            self.chans[c].m2.next = self.e2_m.q.val();
            self.l_ch_i.next = self.chans[c].i.val();
            self.l_ch_di.next = self.chans[c].o_di.val();
            self.l_ti.next =
                (self.l_ti.val() >> 34) | (bit_cast::<I3_W, IACC_W>(self.l_ch_i.val()) << 68);
            self.l_tdi.next =
                (self.l_tdi.val() >> 21) | (bit_cast::<DI3_W, DI_W>(self.l_ch_di.val()) << 42);
        }
        // ---- E3: partial products m·dZ (3), 16×16 unsigned, of the operands E2 loads
        // (each multiplier registers its own copy with E2 and its product with E3).
        self.e3_head.d.next = self.e2_head.q.val();
        self.e3_zs.d.next = bit_cast::<ZACC_W, ZL_W>(self.e2_zl.q.val());
        if self.e2_dz.q.val().get_bit(37) {
            self.e3_zs.d.next = bit_cast::<ZACC_W, ZL_W>(self.e2_zl.q.val())
                - (bit_cast::<ZACC_W, MUL_W>(self.e2_m.q.val()) << 38);
        }
        self.e3_dz.d.next = self.e2_dz.q.val();
        self.l_dzmid.next = self.l_dz1.val().get_bits::<MUL_W>(16);
        self.l_dzhi.next = bit_cast::<MUL_W, DZ_HI_W>(self.l_dz1.val().get_bits::<DZ_HI_W>(32));
        for k in 0..3 {
            self.mz[k].clock.next = self.clock.val();
            self.mz[k].a.next = self.l_m1.val();
        }
        self.mz[0].b.next = self.l_dz1.val().get_bits::<MUL_W>(0);
        self.mz[1].b.next = self.l_dzmid.val();
        self.mz[2].b.next = self.l_dzhi.val();
        // ---- E4: m·dZ = m·u38 − s·m·2^38 (u38 = dZ as unsigned); the second term is
        // in E3's `e3_zs`, so Z = (ZL − s·m·2^38 + m·u38[0:16]) + m·u38[16:38]·2^16.
        self.e4_head.d.next = self.e3_head.q.val();
        self.e4_dz.d.next = self.e3_dz.q.val();
        self.e4_za.d.next = self.e3_zs.q.val() + bit_cast::<ZACC_W, PROD_W>(self.mz[0].p.val());
        self.e4_zb.d.next = (bit_cast::<ZACC_W, PROD_W>(self.mz[1].p.val()) << 16)
            + (bit_cast::<ZACC_W, PROD_W>(self.mz[2].p.val()) << 32);
        // ---- The systolic chain: E4 feeds processor 0, processor p feeds p + 1.
        for i in 0..self.procs.len() {
            self.procs[i].clock.next = self.clock.val();
        }
        self.procs[0].t_head.next = self.e4_head.q.val();
        // The depth test is `Z <= ZB` for an OP span of a decal.
        self.procs[0].t_le.next = (self.e4_head.q.val().get_value_op() == self.k_span.val())
            & (self.e4_head.q.val().get_value_attr() == self.k_attr_op.val())
            & self.e4_head.q.val().get_value_decal();
        self.procs[0].t_z.next = self.e4_za.q.val() + self.e4_zb.q.val();
        self.procs[0].t_dz.next = self.e4_dz.q.val();
        self.procs[0].t_i.next = self.l_ti.val();
        self.procs[0].t_di.next = self.l_tdi.val();
        for i in 1..self.procs.len() {
            self.procs[i].t_head.next = self.procs[i - 1].o_head.val();
            self.procs[i].t_le.next = self.procs[i - 1].o_le.val();
            self.procs[i].t_z.next = self.procs[i - 1].o_z.val();
            self.procs[i].t_dz.next = self.procs[i - 1].o_dz.val();
            self.procs[i].t_i.next = self.procs[i - 1].o_i.val();
            self.procs[i].t_di.next = self.procs[i - 1].o_di.val();
        }
        // ---- Readout: registered address (E1), per-processor select registered in the
        // processor, then the OR of the (one) selected processor's packed readout
        // registers in groups of READOUT_GROUP processors, one register per group, and
        // the OR of the group registers on the outputs: no path gathers from more than
        // eight processors, whatever N.
        for g in 0..self.rd_g.len() {
            self.rd_g[g].clock.next = self.clock.val();
            self.l_grp[g].next = self.k_zero74.val();
        }
        for i in 0..self.procs.len() {
            self.procs[i].rd_sel.next = self.e1_rd.q.val().index() == i;
            self.l_grp[i / 8].next = self.l_grp[i / 8].val() | self.procs[i].rdo.val();
            // 8: READOUT_GROUP
        }
        for g in 0..self.rd_g.len() {
            self.rd_g[g].d.next = self.l_grp[g].val();
        }
        self.l_rd.next = self.k_zero74.val();
        for g in 0..self.rd_g.len() {
            self.l_rd.next = self.l_rd.val() | self.rd_g[g].q.val();
        }
        self.rd_zb.next = self.l_rd.val().get_value_zb();
        self.rd_rgb.next = self.l_rd.val().get_value_rgb();
        self.rd_dsf.next = self.l_rd.val().get_value_dsf();
        self.rd_fsf.next = self.l_rd.val().get_value_fsf();
        self.rd_count.next = self.l_rd.val().get_value_count();
        self.rd_mask.next = self.l_rd.val().get_value_mask();
        self.rd_nclass.next = self.l_rd.val().get_value_nclass();
        self.rd_sh.next = self.l_rd.val().get_value_sh();
        self.rd_won.next = self.l_rd.val().get_value_won();
    }
}
