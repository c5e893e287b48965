//! One pixel processor of the scanline array (seed 001, Matsumoto, section 1 "one
//! scanline's worth of pixel processors", section 3 "scanline Z-buffer", section 6
//! "several lights").
//!
//! Processor `p` owns screen column `col = base + p`. It holds the depth register `ZB`
//! (24 bits), the intensity register (RGB888), the normal class of the visible surface
//! (`NCLASS`, 8 bits), optionally a [`SpanParity`] block (DSF, FSF, COUNT, MASK; only
//! when the scene has shadows), and readout registers that keep the previous scanline's
//! values.
//!
//! **Systolic token.** Commands reach the processor as a *token* in its token register
//! (stage A, loaded from the `t_*` ports at every rising edge). In the cycle the token
//! sits in that register the processor drives the token for processor `p + 1` on the
//! `o_*` ports:
//! - `o_rel_l = rel_l − 1`, `o_rel_r = rel_r − 1` (the running range differences
//!   `XL − col − 1` and `XR − col`),
//! - `o_z = z + dZ`, `o_i_c = i_c + dI_c` if `col >= XL`, else unchanged,
//!
//! so a token holding `ZL + max(0, col − XL)·dZ` at column `col` holds the same quantity
//! at column `col + 1`: one adder per quantity per processor, no multiplier.
//!
//! **Decide, then write (two stages).** In stage A the processor also *decides*: range
//! test, `Z < ZB` / `Z <= ZB`, intensity clamp. The decision is registered (stage B) and
//! applied at the next edge: `ZB`, RGB, `NCLASS`, the parity flags. A token directly
//! behind another one must see the `ZB` its predecessor is about to write (the bypass),
//! so back-to-back spans at one processor are exact. ZB can take one of three values by
//! the time the token reaches stage B: the ZB held now, the depth stage B is writing now,
//! or `Z_FAR` (stage B holds CLEAR_LINE or RESET). Stage A compares `Z` with each of them,
//! straight from flip-flops, and registers the three results as they leave the carry
//! chains; stage B selects one with two registered flags of the token ahead (it wrote;
//! it was CLEAR_LINE or RESET) and ANDs it with the registered rest of the condition
//! (OP span, channel 0, covered, `z[43:36] = 0`) into the write enable. Nothing sits
//! between a compare and its register, and the write enable is one LUT level from
//! flip-flops. `Z < ZB` and `Z <= ZB` share one carry chain: `{Z, 1} < {ZB, 1}` and
//! `{Z, 0} < {ZB, 1}`, the low bit from the token's `le` flag (an OP span of a decal),
//! decoded once at the array's entry and carried from processor to processor. ZB takes
//! the write at once (the bypass needs it); RGB and NCLASS take it one edge later from
//! stage C (`w_c`, `rgb_c`, `ncl_c`), so their clock enable is one flip-flop rather than
//! the write decision; the line capture and [`PixelProcessor::probe`] read the stage-C
//! values while such a write is pending.
//!
//! **OP span** (`op = SPAN`, `attr = OP`): if `XL <= col <= XR` and `Z < ZB` (`Z <= ZB`
//! for a decal span), `ZB := Z`, `RGB := clamp(I >> 12, 0, 255)` per channel,
//! `NCLASS := nclass`, where `Z = z[35:12]` and the test is the golden
//! `((z >> 12) as u32) < ZB` (so `z[43:36]` must be zero).
//!
//! **Widths.** `z` is Q32.12 modulo 2^44: every value the golden model compares is
//! `(ZL + k·dZ) >> 12` truncated to 32 bits with `0 <= k < 4096`, i.e. bits `[43:12]`.
//! `i_c` is Q22.12 two's complement, 34 bits: `|k·dI| < 2^32` and `IL < 2^20`, so the
//! covered values never wrap and the clamp sees their true sign.
//!
//! **Shade channel** (exact shading in shadow; only with shadows): an OP span with
//! `chan = 0` also stores in `WON` whether it passed (where it covers the processor); an
//! OP span with `chan = 1` does no depth test and writes `SH := clamp(I >> 12)` where
//! `WON` is set; `chan ≥ 2` spans do nothing here (the core has one shade register). The
//! two updates use the registered decision (stage B), so a channel span directly behind
//! its polygon's span sees the `WON` that span wrote.
//!
//! **Other commands.** CLEAR_LINE carries the background in `z[23:0]`, LATCH_SHADOW its
//! light bit in `z[2:0]`, CHECK its range in `rel_l`/`rel_r`. RESET (the `rst` input,
//! travelling down the chain as a token so that no net fans out to every processor) sets
//! `ZB := Z_FAR`, everything else to 0, readout `ZB` to `Z_FAR`.
//!
//! Latency: state registers update two rising edges after the token register is loaded.

use crate::colour_lane::{ColourLane, CH_W, DI_W};
use crate::layout::{HeadFields, ReadoutFields, HEAD_W, READOUT_W};
use crate::opcodes::*;
use crate::span_parity::SpanParity;
use pixelproc_formats::regs::{ProcState, COUNT_BITS, MASK_BITS, RGB_BITS};
use pixelproc_formats::{
    Attr, DEPTH_FRAC_BITS, INTENSITY_FRAC_BITS, SPAN_ATTR, SPAN_DZ, SPAN_NCLASS, SPAN_XL, Z_BITS,
    Z_FAR,
};
use rust_hdl::prelude::*;

/// The registers of one processor as read by a testbench: the golden model's record,
/// defined once in `pixelproc_formats::regs`, so RTL and golden states compare directly.
pub type ProcRegs = ProcState;

/// Width of the running range differences `XL − col − 1`, `XR − col` (two's complement,
/// one bit above a column number and a sign bit).
pub const REL_W: usize = SPAN_XL.width + 2;
/// Width of the depth accumulator: Q32.12 modulo 2^44.
pub const ZACC_W: usize = 32 + DEPTH_FRAC_BITS as usize;
/// Width of an intensity accumulator: Q22.12 two's complement.
pub const IACC_W: usize = 22 + INTENSITY_FRAC_BITS as usize;
/// Width of `dZ`.
const DZ_W: usize = SPAN_DZ.width;
/// Width of the span attribute.
const ATTR_W: usize = SPAN_ATTR.width;
/// Width of the normal class.
const NCLASS_W: usize = SPAN_NCLASS.width;
/// Width of a depth register.
const ZB_W: usize = Z_BITS as usize;
/// A depth with the compare's tie bit below it.
const ZB2_W: usize = ZB_W + 1;
/// Width of the three packed intensity accumulators of a token.
pub const I3_W: usize = 3 * IACC_W;
/// Width of the three packed `dI` of a token.
pub const DI3_W: usize = 3 * DI_W;
// A kernel can only take literal bit positions: the sign bits 37 (`dZ`) and 13 (range),
// the depth slice at 12 and the channel strides 34 and 21 below are these widths.
const _: () = assert!(DZ_W == 38 && DI_W == 21 && REL_W == 14 && IACC_W == 34 && ZACC_W == 44);

/// One pixel processor. `shadows = false` builds it without the parity block: DSF, FSF,
/// COUNT and MASK then read 0 and shadow commands do nothing.
#[derive(LogicBlock)]
pub struct PixelProcessor {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Token in: the header ([`HeadFields`]: opcode, RESET included; attribute; decal
    /// flag; normal class; `XL − col − 1`; `XR − col`).
    pub t_head: Signal<In, Bits<HEAD_W>>,
    /// Token in: depth accumulator, Q32.12 mod 2^44 (the argument of CLEAR_LINE and
    /// LATCH_SHADOW in bits 23:0).
    pub t_z: Signal<In, Bits<ZACC_W>>,
    /// Token in: `dZ`, Q26.12 two's complement.
    pub t_dz: Signal<In, Bits<DZ_W>>,
    /// Token in: the red, green and blue accumulators (Q22.12 two's complement), red in
    /// the low [`IACC_W`] bits.
    pub t_i: Signal<In, Bits<I3_W>>,
    /// Token in: `dI` red, green, blue (Q9.12 two's complement), red in the low bits.
    pub t_di: Signal<In, Bits<DI3_W>>,
    /// Token in: the depth test is `Z <= ZB` (an OP span of a decal), else `Z < ZB`:
    /// decoded once at the array's entry and carried along, so that no decode of the
    /// header sits in front of the compare's carry chain.
    pub t_le: Signal<In, Bit>,
    /// Readout select (this processor is addressed), registered here.
    pub rd_sel: Signal<In, Bit>,
    /// Readout registers, packed `{WON, SH, NCLASS, MASK, ZB, RGB, DSF, FSF, COUNT}` (99 bits), if
    /// selected at the last edge, else 0 (the array ORs all processors' values).
    pub rdo: Signal<Out, Bits<READOUT_W>>,
    /// Token out (for processor `p + 1`): the header with `rel_l − 1`, `rel_r − 1`.
    pub o_head: Signal<Out, Bits<HEAD_W>>,
    /// Token out: depth accumulator for the next column.
    pub o_z: Signal<Out, Bits<ZACC_W>>,
    /// Token out: `dZ`.
    pub o_dz: Signal<Out, Bits<DZ_W>>,
    /// Token out: the three accumulators for the next column.
    pub o_i: Signal<Out, Bits<I3_W>>,
    /// Token out: `dI`, the three channels.
    pub o_di: Signal<Out, Bits<DI3_W>>,
    /// Token out: the `Z <= ZB` flag.
    pub o_le: Signal<Out, Bit>,
    /// The shadow logic: one element with shadows, none without.
    pub parity: Vec<SpanParity>,
    tok_head: DFF<Bits<HEAD_W>>,
    l_rel_l: Signal<Local, Bits<REL_W>>,
    l_rel_r: Signal<Local, Bits<REL_W>>,
    tok_z: DFF<Bits<ZACC_W>>,
    tok_dz: DFF<Bits<DZ_W>>,
    tok_i: DFF<Bits<I3_W>>,
    tok_di: DFF<Bits<DI3_W>>,
    tok_le: DFF<Bit>,
    /// Step and clamp of the red, green and blue channels.
    lanes: [ColourLane; 3],
    /// The opcode in stage B, for the span-parity block (its CLEAR_LINE and RESET also
    /// arrive decoded: `b_clr`, `b_rst`), held inverted (`op ^ 0b111`). A register of the
    /// opcode itself samples what the next processor's token register samples, and
    /// synthesis merges the two into one flip-flop placed between the processors; the
    /// inversion is free (it folds into the LUTs on either side).
    b_op: DFF<Bits<OP_BITS>>,
    k_op_inv: Constant<Bits<OP_BITS>>,
    b_attr: DFF<Bits<ATTR_W>>,
    b_covered: DFF<Bit>,
    /// The depth test registered three ways (see "Decide, then write"): against the held
    /// ZB, against the depth stage B is writing, against `Z_FAR`.
    b_p_held: DFF<Bit>,
    b_p_new: DFF<Bit>,
    b_p_far: DFF<Bit>,
    /// Which of the three applies: the token ahead wrote (`b_sel_new`), the token ahead
    /// was CLEAR_LINE or RESET (`b_sel_far`).
    b_sel_new: DFF<Bit>,
    b_sel_far: DFF<Bit>,
    /// Stage B holds CLEAR_LINE (`b_clr`) or RESET (`b_rst`), decoded in stage A, so the
    /// wide registers' enables (capture, colour, the far select) come straight from
    /// flip-flops of this processor.
    b_clr: DFF<Bit>,
    b_rst: DFF<Bit>,
    /// An OP span of channel 0 that covers the column with `z[43:36] = 0`: it writes if
    /// it passes the depth test.
    b_gate: DFF<Bit>,
    b_hi_ok: DFF<Bit>,
    b_z: DFF<Bits<ZB_W>>,
    b_rgb: DFF<Bits<RGB_BITS>>,
    b_nclass: DFF<Bits<NCLASS_W>>,
    b_won_upd: DFF<Bit>,
    b_sh_write: DFF<Bit>,
    won_r: DFF<Bit>,
    sh_r: DFF<Bits<RGB_BITS>>,
    k_shade: Constant<Bit>,
    k_chan0: Constant<Bits<4>>,
    k_chan1: Constant<Bits<4>>,
    is_op_span: Signal<Local, Bit>,
    zb_r: DFF<Bits<ZB_W>>,
    rgb_r: DFF<Bits<RGB_BITS>>,
    nclass_r: DFF<Bits<NCLASS_W>>,
    /// Stage C: stage B wrote at the last edge (`w_c`), with the RGB and NCLASS it wrote
    /// (`rgb_c`, `ncl_c`); RGB and NCLASS take them at the next edge (see "Decide, then
    /// write").
    w_c: DFF<Bit>,
    rgb_c: DFF<Bits<RGB_BITS>>,
    ncl_c: DFF<Bits<NCLASS_W>>,
    /// RGB and NCLASS as the processor's state has them: the stage C values while a
    /// write is pending there.
    l_rgb_now: Signal<Local, Bits<RGB_BITS>>,
    l_ncl_now: Signal<Local, Bits<NCLASS_W>>,
    /// The readout registers, as the packed readout word.
    cap_r: DFF<Bits<READOUT_W>>,
    l_cap: Signal<Local, Bits<READOUT_W>>,
    k_cap_reset: Constant<Bits<READOUT_W>>,
    rdsel_r: DFF<Bit>,
    k_zero_rd: Constant<Bits<READOUT_W>>,
    k_clear_line: Constant<Bits<OP_BITS>>,
    k_span: Constant<Bits<OP_BITS>>,
    k_reset: Constant<Bits<OP_BITS>>,
    k_attr_op: Constant<Bits<ATTR_W>>,
    k_zfar: Constant<Bits<ZB_W>>,
    k_zero8: Constant<Bits<CH_W>>,
    k_zero24: Constant<Bits<RGB_BITS>>,
    k_zero_i3: Constant<Bits<I3_W>>,
    k_one14: Constant<Bits<REL_W>>,
    k_sext_z: Constant<Bits<ZACC_W>>,
    dz_x: Signal<Local, Bits<ZACC_W>>,
    right_of_xl: Signal<Local, Bit>,
    covered: Signal<Local, Bit>,
    zv: Signal<Local, Bits<ZB_W>>,
    z_hi_ok: Signal<Local, Bit>,
    zb_next: Signal<Local, Bits<ZB_W>>,
    /// `Z ≤ ZB` is the test (an OP span of a decal), else `Z < ZB` (the token's flag).
    le_mode: Signal<Local, Bit>,
    /// `{Z, ¬le_mode}` and `{ZB, 1}`, `{ZB_B, 1}`: `Z < ZB` iff `{Z, 1} < {ZB, 1}` and
    /// `Z ≤ ZB` iff `{Z, 0} < {ZB, 1}`, so one carry chain serves both tests.
    zv2: Signal<Local, Bits<ZB2_W>>,
    zb2_held: Signal<Local, Bits<ZB2_W>>,
    zb2_new: Signal<Local, Bits<ZB2_W>>,
    k_one25: Constant<Bits<ZB2_W>>,
    /// Stage B: the selected depth test, and the write enable of the state registers.
    pass_b: Signal<Local, Bit>,
    write_b: Signal<Local, Bit>,
    l_i: Signal<Local, Bits<I3_W>>,
    l_rgb: Signal<Local, Bits<RGB_BITS>>,
    l_lane_i: Signal<Local, Bits<IACC_W>>,
    l_lane_ch: Signal<Local, Bits<CH_W>>,
    dsf_now: Signal<Local, Bit>,
    fsf_now: Signal<Local, Bit>,
    count_now: Signal<Local, Bits<COUNT_BITS>>,
    mask_now: Signal<Local, Bits<MASK_BITS>>,
}

impl PixelProcessor {
    /// A processor, with the span-parity block iff `shadows`.
    pub fn new(shadows: bool) -> Self {
        let parity = if shadows {
            vec![SpanParity::default()]
        } else {
            Vec::new()
        };
        PixelProcessor {
            clock: Default::default(),
            t_head: Default::default(),
            t_z: Default::default(),
            t_dz: Default::default(),
            t_i: Default::default(),
            t_di: Default::default(),
            t_le: Default::default(),
            rd_sel: Default::default(),
            rdo: Default::default(),
            o_head: Default::default(),
            o_z: Default::default(),
            o_dz: Default::default(),
            o_i: Default::default(),
            o_di: Default::default(),
            o_le: Default::default(),
            parity,
            tok_head: Default::default(),
            l_rel_l: Default::default(),
            l_rel_r: Default::default(),
            tok_z: Default::default(),
            tok_dz: Default::default(),
            tok_i: Default::default(),
            tok_di: Default::default(),
            tok_le: Default::default(),
            lanes: std::array::from_fn(|_| ColourLane::new()),
            b_op: Default::default(),
            k_op_inv: Constant::new(((1u64 << OP_BITS) - 1).to_bits()),
            b_attr: Default::default(),
            b_covered: Default::default(),
            b_p_held: Default::default(),
            b_p_new: Default::default(),
            b_p_far: Default::default(),
            b_sel_new: Default::default(),
            b_sel_far: Default::default(),
            b_clr: Default::default(),
            b_rst: Default::default(),
            b_gate: Default::default(),
            b_hi_ok: Default::default(),
            b_z: Default::default(),
            b_rgb: Default::default(),
            b_nclass: Default::default(),
            b_won_upd: Default::default(),
            b_sh_write: Default::default(),
            won_r: Default::default(),
            sh_r: Default::default(),
            k_shade: Constant::new(shadows),
            k_chan0: Constant::new(0u64.to_bits()),
            k_chan1: Constant::new(1u64.to_bits()),
            is_op_span: Default::default(),
            zb_r: Default::default(),
            rgb_r: Default::default(),
            nclass_r: Default::default(),
            w_c: Default::default(),
            rgb_c: Default::default(),
            ncl_c: Default::default(),
            l_rgb_now: Default::default(),
            l_ncl_now: Default::default(),
            cap_r: Default::default(),
            l_cap: Default::default(),
            k_cap_reset: Constant::new(
                ProcState {
                    zb: Z_FAR,
                    ..Default::default()
                }
                .pack_readout()
                .to_bits(),
            ),
            rdsel_r: Default::default(),
            k_zero_rd: Constant::new(0u64.to_bits()),
            k_clear_line: Constant::new(OP_CLEAR_LINE.to_bits()),
            k_span: Constant::new(OP_SPAN.to_bits()),
            k_reset: Constant::new(OP_RESET.to_bits()),
            k_attr_op: Constant::new((Attr::Op.code() as u64).to_bits()),
            k_zfar: Constant::new((Z_FAR as u64).to_bits()),
            k_zero8: Constant::new(0u64.to_bits()),
            k_zero24: Constant::new(0u64.to_bits()),
            k_zero_i3: Constant::new(0u64.to_bits()),
            k_one14: Constant::new(1u64.to_bits()),
            k_sext_z: Constant::new((((1u64 << ZACC_W) - 1) ^ ((1u64 << DZ_W) - 1)).to_bits()),
            dz_x: Default::default(),
            right_of_xl: Default::default(),
            covered: Default::default(),
            zv: Default::default(),
            z_hi_ok: Default::default(),
            zb_next: Default::default(),
            le_mode: Default::default(),
            zv2: Default::default(),
            zb2_held: Default::default(),
            zb2_new: Default::default(),
            k_one25: Constant::new(1u64.to_bits()),
            pass_b: Default::default(),
            write_b: Default::default(),
            l_i: Default::default(),
            l_rgb: Default::default(),
            l_lane_i: Default::default(),
            l_lane_ch: Default::default(),
            dsf_now: Default::default(),
            fsf_now: Default::default(),
            count_now: Default::default(),
            mask_now: Default::default(),
        }
    }

    /// True if this processor has the span-parity block.
    pub fn has_shadows(&self) -> bool {
        !self.parity.is_empty()
    }

    /// Current state registers (for testbenches).
    pub fn probe(&self) -> ProcRegs {
        let (dsf, fsf, count, mask) = match self.parity.first() {
            Some(p) => p.probe(),
            None => (false, false, 0, 0),
        };
        ProcRegs {
            zb: self.zb_r.q.val().to_u32(),
            rgb: self.l_rgb_now.val().to_u32(),
            dsf,
            fsf,
            count,
            mask,
            nclass: self.l_ncl_now.val().to_u8(),
            sh: self.sh_r.q.val().to_u32(),
            won: self.won_r.q.val(),
        }
    }

    /// Current readout registers (for testbenches).
    pub fn probe_capture(&self) -> ProcRegs {
        let w = self.cap_r.q.val();
        let lo = w.get_bits::<64>(0).to_u64() as u128;
        let hi = w.get_bits::<{ READOUT_W - 64 }>(64).to_u64() as u128;
        ProcState::unpack_readout((hi << 64) | lo)
    }
}

impl Logic for PixelProcessor {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, tok_head, tok_z, tok_dz, tok_i, tok_di, tok_le, b_op, b_attr, b_covered,
            b_p_held, b_p_new, b_p_far, b_sel_new, b_sel_far, b_clr, b_rst, b_gate, b_hi_ok, b_z,
            b_rgb, b_nclass, zb_r, rgb_r, nclass_r, w_c, rgb_c, ncl_c, cap_r, rdsel_r, b_won_upd,
            b_sh_write, won_r, sh_r
        );
        // ---- Stage A: the token register, loaded every clock.
        self.tok_head.d.next = self.t_head.val();
        self.l_rel_l.next = self.tok_head.q.val().get_value_rel_l();
        self.l_rel_r.next = self.tok_head.q.val().get_value_rel_r();
        self.tok_z.d.next = self.t_z.val();
        self.tok_dz.d.next = self.t_dz.val();
        self.tok_i.d.next = self.t_i.val();
        self.tok_di.d.next = self.t_di.val();
        self.tok_le.d.next = self.t_le.val();
        // Sign-extended increments.
        self.dz_x.next = bit_cast::<ZACC_W, DZ_W>(self.tok_dz.q.val());
        if self.tok_dz.q.val().get_bit(37) {
            self.dz_x.next = self.dz_x.val() | self.k_sext_z.val();
        }
        // Range test: col >= XL iff XL − col − 1 < 0; col <= XR iff XR − col >= 0.
        self.right_of_xl.next = self.l_rel_l.val().get_bit(13);
        self.covered.next = self.right_of_xl.val() & (!self.l_rel_r.val().get_bit(13));
        // Colour channels (red first): the next column's accumulators, packed back in
        // channel order, and the clamped channel values as RGB888.
        self.l_i.next = self.k_zero_i3.val();
        self.l_rgb.next = self.k_zero24.val();
        for c in 0..3 {
            self.lanes[c].i.next = self.tok_i.q.val().get_bits::<IACC_W>(34 * c);
            self.lanes[c].di.next = self.tok_di.q.val().get_bits::<DI_W>(21 * c);
            self.lanes[c].step.next = self.right_of_xl.val();
            // (`bit_cast` cannot take the loop index: go through locals.)
            self.l_lane_i.next = self.lanes[c].o_i.val();
            self.l_lane_ch.next = self.lanes[c].ch.val();
            self.l_i.next =
                (self.l_i.val() >> 34) | (bit_cast::<I3_W, IACC_W>(self.l_lane_i.val()) << 68);
            self.l_rgb.next =
                (self.l_rgb.val() << 8) | bit_cast::<RGB_BITS, CH_W>(self.l_lane_ch.val());
        }
        self.o_i.next = self.l_i.val();
        // Token for the next processor.
        self.o_head.next = self.tok_head.q.val();
        self.o_head
            .next
            .set_value_rel_l(self.l_rel_l.val() - self.k_one14.val());
        self.o_head
            .next
            .set_value_rel_r(self.l_rel_r.val() - self.k_one14.val());
        self.o_dz.next = self.tok_dz.q.val();
        self.o_di.next = self.tok_di.q.val();
        self.o_le.next = self.tok_le.q.val();
        self.o_z.next = self.tok_z.q.val();
        if self.right_of_xl.val() {
            self.o_z.next = self.tok_z.q.val() + self.dz_x.val();
        }
        // ---- Stage B: select the depth test registered at the last edge, then apply the
        // decision. `zb_next` is the value ZB takes at the coming edge.
        self.pass_b.next = self.b_p_held.q.val();
        if self.b_sel_new.q.val() {
            self.pass_b.next = self.b_p_new.q.val();
        }
        if self.b_sel_far.q.val() {
            self.pass_b.next = self.b_p_far.q.val();
        }
        self.write_b.next = self.b_gate.q.val() & self.pass_b.val();
        // Shade channel: WON after a polygon span, SH from a channel-1 span where WON.
        if self.b_won_upd.q.val() & self.k_shade.val() {
            self.won_r.d.next = self.write_b.val();
        }
        if self.b_sh_write.q.val() & self.won_r.q.val() & self.k_shade.val() {
            self.sh_r.d.next = self.b_rgb.q.val();
        }
        self.zb_next.next = self.zb_r.q.val();
        if self.write_b.val() {
            self.zb_next.next = self.b_z.q.val();
        }
        // RGB and NCLASS one edge later, from stage C: their clock enable is a flip-flop,
        // not the write decision (whose fan-out to 56 registers was a critical path).
        self.w_c.d.next = self.write_b.val();
        self.rgb_c.d.next = self.b_rgb.q.val();
        self.ncl_c.d.next = self.b_nclass.q.val();
        if self.w_c.q.val() {
            self.rgb_r.d.next = self.rgb_c.q.val();
            self.nclass_r.d.next = self.ncl_c.q.val();
        }
        self.l_rgb_now.next = self.rgb_r.q.val();
        self.l_ncl_now.next = self.nclass_r.q.val();
        if self.w_c.q.val() {
            self.l_rgb_now.next = self.rgb_c.q.val();
            self.l_ncl_now.next = self.ncl_c.q.val();
        }
        // Shadow logic (absent without shadows: flags, counter and mask read 0).
        self.dsf_now.next = false;
        self.fsf_now.next = false;
        self.count_now.next = self.k_zero8.val();
        self.mask_now.next = self.k_zero8.val();
        for i in 0..self.parity.len() {
            self.parity[i].clock.next = self.clock.val();
            self.parity[i].rst.next = self.b_rst.q.val();
            self.parity[i].op.next = self.b_op.q.val() ^ self.k_op_inv.val();
            self.parity[i].attr.next = self.b_attr.q.val();
            self.parity[i].covered.next = self.b_covered.q.val();
            self.parity[i].z_lt.next = self.pass_b.val() & self.b_hi_ok.q.val();
            self.parity[i].light.next = self.b_rgb.q.val().get_bits::<3>(0);
            self.dsf_now.next = self.parity[i].dsf.val();
            self.fsf_now.next = self.parity[i].fsf.val();
            self.count_now.next = self.parity[i].count.val();
            self.mask_now.next = self.parity[i].mask.val();
        }
        // New scanline: copy the finished line into the readout registers (the fields of
        // `pixelproc_formats::regs::READOUT_FIELDS`), then clear.
        self.l_cap.next = self.k_zero_rd.val();
        self.l_cap.next.set_value_nclass(self.l_ncl_now.val());
        self.l_cap.next.set_value_mask(self.mask_now.val());
        self.l_cap.next.set_value_zb(self.zb_r.q.val());
        self.l_cap.next.set_value_rgb(self.l_rgb_now.val());
        self.l_cap.next.set_value_dsf(self.dsf_now.val());
        self.l_cap.next.set_value_fsf(self.fsf_now.val());
        self.l_cap.next.set_value_count(self.count_now.val());
        self.l_cap.next.set_value_sh(self.sh_r.q.val());
        self.l_cap.next.set_value_won(self.won_r.q.val());
        if self.b_clr.q.val() {
            self.won_r.d.next = false;
            self.sh_r.d.next = self.k_zero24.val();
            self.cap_r.d.next = self.l_cap.val();
            self.zb_next.next = self.k_zfar.val();
            self.rgb_r.d.next = self.b_rgb.q.val();
            self.nclass_r.d.next = self.k_zero8.val();
        }
        if self.b_rst.q.val() {
            self.won_r.d.next = false;
            self.sh_r.d.next = self.k_zero24.val();
            self.zb_next.next = self.k_zfar.val();
            self.rgb_r.d.next = self.k_zero24.val();
            self.nclass_r.d.next = self.k_zero8.val();
            self.cap_r.d.next = self.k_cap_reset.val();
        }
        self.zb_r.d.next = self.zb_next.val();
        // ---- Stage A, decision: the golden `((z >> 12) as u32) < ZB` (or `<=` for a
        // decal's OP span), against each value ZB can hold when this token reaches stage
        // B: the held ZB, the depth stage B is writing now, `Z_FAR` after CLEAR_LINE or
        // RESET. Each compare runs straight from flip-flops and is registered; stage B
        // picks one with the registered state of the token ahead (the bypass), so no
        // multiplexer or gate sits between a carry chain and its register.
        self.zv.next = self.tok_z.q.val().get_bits::<ZB_W>(12);
        self.z_hi_ok.next = self.tok_z.q.val().get_bits::<CH_W>(36) == self.k_zero8.val();
        self.is_op_span.next = (self.tok_head.q.val().get_value_op() == self.k_span.val())
            & (self.tok_head.q.val().get_value_attr() == self.k_attr_op.val());
        self.le_mode.next = self.tok_le.q.val();
        self.zv2.next = bit_cast::<ZB2_W, ZB_W>(self.zv.val()) << 1;
        if !self.le_mode.val() {
            self.zv2.next = self.zv2.val() | self.k_one25.val();
        }
        self.zb2_held.next = (bit_cast::<ZB2_W, ZB_W>(self.zb_r.q.val()) << 1) | self.k_one25.val();
        self.zb2_new.next = (bit_cast::<ZB2_W, ZB_W>(self.b_z.q.val()) << 1) | self.k_one25.val();
        self.b_p_held.d.next = self.zv2.val() < self.zb2_held.val();
        self.b_p_new.d.next = self.zv2.val() < self.zb2_new.val();
        // `Z < Z_FAR` iff `Z ≠ Z_FAR`; `Z <= Z_FAR` always.
        self.b_p_far.d.next = self.le_mode.val() | (self.zv.val() != self.k_zfar.val());
        self.b_sel_new.d.next = self.write_b.val();
        self.b_sel_far.d.next = self.b_clr.q.val() | self.b_rst.q.val();
        self.b_hi_ok.d.next = self.z_hi_ok.val();
        self.b_op.d.next = self.tok_head.q.val().get_value_op() ^ self.k_op_inv.val();
        self.b_clr.d.next = self.tok_head.q.val().get_value_op() == self.k_clear_line.val();
        self.b_rst.d.next = self.tok_head.q.val().get_value_op() == self.k_reset.val();
        self.b_attr.d.next = self.tok_head.q.val().get_value_attr();
        self.b_covered.d.next = self.covered.val();
        self.b_gate.d.next = self.is_op_span.val()
            & (self.tok_head.q.val().get_value_chan() == self.k_chan0.val())
            & self.covered.val()
            & self.z_hi_ok.val();
        self.b_won_upd.d.next = self.is_op_span.val()
            & (self.tok_head.q.val().get_value_chan() == self.k_chan0.val())
            & self.covered.val();
        self.b_sh_write.d.next = self.is_op_span.val()
            & (self.tok_head.q.val().get_value_chan() == self.k_chan1.val())
            & self.covered.val();
        self.b_z.d.next = self.zv.val();
        self.b_nclass.d.next = self.tok_head.q.val().get_value_nclass();
        self.b_rgb.d.next = self.l_rgb.val();
        if self.tok_head.q.val().get_value_op() != self.k_span.val() {
            // CLEAR_LINE's background, LATCH_SHADOW's bit.
            self.b_rgb.d.next = self.tok_z.q.val().get_bits::<RGB_BITS>(0);
        }
        // ---- Outputs.
        self.rdsel_r.d.next = self.rd_sel.val();
        self.rdo.next = self.k_zero_rd.val();
        if self.rdsel_r.q.val() {
            self.rdo.next = self.cap_r.q.val();
        }
    }
}
