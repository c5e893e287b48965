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
//! test, `Z < ZB` / `Z <= ZB`, intensity clamp. The decision is registered (stage B,
//! 64 flip-flops) and applied at the next edge: `ZB`, RGB, `NCLASS`, the parity flags.
//! The depth compare therefore drives one flip-flop instead of the enables of 56 state
//! flip-flops. A token directly behind another one sees the `ZB` its predecessor is about
//! to write: stage A compares against `zb_next`, the value `ZB` takes at the coming edge
//! (the bypass), so back-to-back spans at one processor are exact.
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
//! **Other commands.** CLEAR_LINE carries the background in `z[23:0]`, LATCH_SHADOW its
//! light bit in `z[2:0]`, CHECK its range in `rel_l`/`rel_r`. RESET (the `rst` input,
//! travelling down the chain as a token so that no net fans out to every processor) sets
//! `ZB := Z_FAR`, everything else to 0, readout `ZB` to `Z_FAR`.
//!
//! Latency: state registers update two rising edges after the token register is loaded.

use crate::opcodes::*;
use crate::span_parity::SpanParity;
use pixelproc_formats::Z_FAR;
use rust_hdl::prelude::*;

/// The registers of one processor as read by a testbench.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ProcRegs {
    /// Depth buffer.
    pub zb: u32,
    /// RGB888.
    pub rgb: u32,
    /// Shadow decision flag (0 without shadows).
    pub dsf: bool,
    /// Final shadow flag (0 without shadows).
    pub fsf: bool,
    /// Shadow counter (0 without shadows).
    pub count: u8,
    /// Light mask (0 without shadows).
    pub mask: u8,
    /// Normal class of the visible surface.
    pub nclass: u8,
}

/// One pixel processor. `shadows = false` builds it without the parity block: DSF, FSF,
/// COUNT and MASK then read 0 and shadow commands do nothing.
#[derive(LogicBlock)]
pub struct PixelProcessor {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Token in: opcode (RESET included).
    pub t_op: Signal<In, Bits<3>>,
    /// Token in: span attribute.
    pub t_attr: Signal<In, Bits<2>>,
    /// Token in: decal flag (depth test passes on equality).
    pub t_decal: Signal<In, Bit>,
    /// Token in: normal class of the span's surface.
    pub t_nclass: Signal<In, Bits<8>>,
    /// Token in: `XL − col − 1` (14-bit two's complement).
    pub t_rel_l: Signal<In, Bits<14>>,
    /// Token in: `XR − col` (14-bit two's complement).
    pub t_rel_r: Signal<In, Bits<14>>,
    /// Token in: depth accumulator, Q32.12 mod 2^44 (the argument of CLEAR_LINE and
    /// LATCH_SHADOW in bits 23:0).
    pub t_z: Signal<In, Bits<44>>,
    /// Token in: `dZ`, Q26.12 two's complement.
    pub t_dz: Signal<In, Bits<38>>,
    /// Token in: red accumulator, Q22.12 two's complement.
    pub t_ir: Signal<In, Bits<34>>,
    /// Token in: green accumulator.
    pub t_ig: Signal<In, Bits<34>>,
    /// Token in: blue accumulator.
    pub t_ib: Signal<In, Bits<34>>,
    /// Token in: `dI` red, Q9.12 two's complement.
    pub t_dir: Signal<In, Bits<21>>,
    /// Token in: `dI` green.
    pub t_dig: Signal<In, Bits<21>>,
    /// Token in: `dI` blue.
    pub t_dib: Signal<In, Bits<21>>,
    /// Readout select (this processor is addressed), registered here.
    pub rd_sel: Signal<In, Bit>,
    /// Readout registers, packed `{NCLASS, MASK, ZB, RGB, DSF, FSF, COUNT}` (74 bits), if
    /// selected at the last edge, else 0 (the array ORs all processors' values).
    pub rdo: Signal<Out, Bits<74>>,
    /// Token out (for processor `p + 1`): opcode.
    pub o_op: Signal<Out, Bits<3>>,
    /// Token out: attribute.
    pub o_attr: Signal<Out, Bits<2>>,
    /// Token out: decal.
    pub o_decal: Signal<Out, Bit>,
    /// Token out: normal class.
    pub o_nclass: Signal<Out, Bits<8>>,
    /// Token out: `rel_l − 1`.
    pub o_rel_l: Signal<Out, Bits<14>>,
    /// Token out: `rel_r − 1`.
    pub o_rel_r: Signal<Out, Bits<14>>,
    /// Token out: depth accumulator for the next column.
    pub o_z: Signal<Out, Bits<44>>,
    /// Token out: `dZ`.
    pub o_dz: Signal<Out, Bits<38>>,
    /// Token out: red accumulator for the next column.
    pub o_ir: Signal<Out, Bits<34>>,
    /// Token out: green accumulator.
    pub o_ig: Signal<Out, Bits<34>>,
    /// Token out: blue accumulator.
    pub o_ib: Signal<Out, Bits<34>>,
    /// Token out: `dI` red.
    pub o_dir: Signal<Out, Bits<21>>,
    /// Token out: `dI` green.
    pub o_dig: Signal<Out, Bits<21>>,
    /// Token out: `dI` blue.
    pub o_dib: Signal<Out, Bits<21>>,
    /// The shadow logic: one element with shadows, none without.
    pub parity: Vec<SpanParity>,
    tok_op: DFF<Bits<3>>,
    tok_attr: DFF<Bits<2>>,
    tok_decal: DFF<Bit>,
    tok_nclass: DFF<Bits<8>>,
    tok_rel_l: DFF<Bits<14>>,
    tok_rel_r: DFF<Bits<14>>,
    tok_z: DFF<Bits<44>>,
    tok_dz: DFF<Bits<38>>,
    tok_ir: DFF<Bits<34>>,
    tok_ig: DFF<Bits<34>>,
    tok_ib: DFF<Bits<34>>,
    tok_dir: DFF<Bits<21>>,
    tok_dig: DFF<Bits<21>>,
    tok_dib: DFF<Bits<21>>,
    b_op: DFF<Bits<3>>,
    b_attr: DFF<Bits<2>>,
    b_covered: DFF<Bit>,
    b_zlt: DFF<Bit>,
    b_write: DFF<Bit>,
    b_z: DFF<Bits<24>>,
    b_rgb: DFF<Bits<24>>,
    b_nclass: DFF<Bits<8>>,
    zb_r: DFF<Bits<24>>,
    rgb_r: DFF<Bits<24>>,
    nclass_r: DFF<Bits<8>>,
    capzb_r: DFF<Bits<24>>,
    caprgb_r: DFF<Bits<24>>,
    capdsf_r: DFF<Bit>,
    capfsf_r: DFF<Bit>,
    capcount_r: DFF<Bits<8>>,
    capmask_r: DFF<Bits<8>>,
    capnclass_r: DFF<Bits<8>>,
    rdsel_r: DFF<Bit>,
    k_zero74: Constant<Bits<74>>,
    k_bit8: Constant<Bits<74>>,
    k_bit9: Constant<Bits<74>>,
    k_clear_line: Constant<Bits<3>>,
    k_span: Constant<Bits<3>>,
    k_reset: Constant<Bits<3>>,
    k_attr_op: Constant<Bits<2>>,
    k_zfar: Constant<Bits<24>>,
    k_zero8: Constant<Bits<8>>,
    k_zero13: Constant<Bits<13>>,
    k_ff8: Constant<Bits<8>>,
    k_zero24: Constant<Bits<24>>,
    k_one14: Constant<Bits<14>>,
    k_sext_z: Constant<Bits<44>>,
    k_sext_i: Constant<Bits<34>>,
    dz_x: Signal<Local, Bits<44>>,
    dir_x: Signal<Local, Bits<34>>,
    dig_x: Signal<Local, Bits<34>>,
    dib_x: Signal<Local, Bits<34>>,
    right_of_xl: Signal<Local, Bit>,
    covered: Signal<Local, Bit>,
    zv: Signal<Local, Bits<24>>,
    z_hi_ok: Signal<Local, Bit>,
    z_lt: Signal<Local, Bit>,
    z_pass: Signal<Local, Bit>,
    zb_next: Signal<Local, Bits<24>>,
    ch_r: Signal<Local, Bits<8>>,
    ch_g: Signal<Local, Bits<8>>,
    ch_b: Signal<Local, Bits<8>>,
    dsf_now: Signal<Local, Bit>,
    fsf_now: Signal<Local, Bit>,
    count_now: Signal<Local, Bits<8>>,
    mask_now: Signal<Local, Bits<8>>,
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
            t_op: Default::default(),
            t_attr: Default::default(),
            t_decal: Default::default(),
            t_nclass: Default::default(),
            t_rel_l: Default::default(),
            t_rel_r: Default::default(),
            t_z: Default::default(),
            t_dz: Default::default(),
            t_ir: Default::default(),
            t_ig: Default::default(),
            t_ib: Default::default(),
            t_dir: Default::default(),
            t_dig: Default::default(),
            t_dib: Default::default(),
            rd_sel: Default::default(),
            rdo: Default::default(),
            o_op: Default::default(),
            o_attr: Default::default(),
            o_decal: Default::default(),
            o_nclass: Default::default(),
            o_rel_l: Default::default(),
            o_rel_r: Default::default(),
            o_z: Default::default(),
            o_dz: Default::default(),
            o_ir: Default::default(),
            o_ig: Default::default(),
            o_ib: Default::default(),
            o_dir: Default::default(),
            o_dig: Default::default(),
            o_dib: Default::default(),
            parity,
            tok_op: Default::default(),
            tok_attr: Default::default(),
            tok_decal: Default::default(),
            tok_nclass: Default::default(),
            tok_rel_l: Default::default(),
            tok_rel_r: Default::default(),
            tok_z: Default::default(),
            tok_dz: Default::default(),
            tok_ir: Default::default(),
            tok_ig: Default::default(),
            tok_ib: Default::default(),
            tok_dir: Default::default(),
            tok_dig: Default::default(),
            tok_dib: Default::default(),
            b_op: Default::default(),
            b_attr: Default::default(),
            b_covered: Default::default(),
            b_zlt: Default::default(),
            b_write: Default::default(),
            b_z: Default::default(),
            b_rgb: Default::default(),
            b_nclass: Default::default(),
            zb_r: Default::default(),
            rgb_r: Default::default(),
            nclass_r: Default::default(),
            capzb_r: Default::default(),
            caprgb_r: Default::default(),
            capdsf_r: Default::default(),
            capfsf_r: Default::default(),
            capcount_r: Default::default(),
            capmask_r: Default::default(),
            capnclass_r: Default::default(),
            rdsel_r: Default::default(),
            k_zero74: Constant::new(0u64.to_bits()),
            k_bit8: Constant::new(256u64.to_bits()),
            k_bit9: Constant::new(512u64.to_bits()),
            k_clear_line: Constant::new(OP_CLEAR_LINE.to_bits()),
            k_span: Constant::new(OP_SPAN.to_bits()),
            k_reset: Constant::new(OP_RESET.to_bits()),
            k_attr_op: Constant::new(0u64.to_bits()),
            k_zfar: Constant::new((Z_FAR as u64).to_bits()),
            k_zero8: Constant::new(0u64.to_bits()),
            k_zero13: Constant::new(0u64.to_bits()),
            k_ff8: Constant::new(255u64.to_bits()),
            k_zero24: Constant::new(0u64.to_bits()),
            k_one14: Constant::new(1u64.to_bits()),
            k_sext_z: Constant::new((((1u64 << 44) - 1) ^ ((1u64 << 38) - 1)).to_bits()),
            k_sext_i: Constant::new((((1u64 << 34) - 1) ^ ((1u64 << 21) - 1)).to_bits()),
            dz_x: Default::default(),
            dir_x: Default::default(),
            dig_x: Default::default(),
            dib_x: Default::default(),
            right_of_xl: Default::default(),
            covered: Default::default(),
            zv: Default::default(),
            z_hi_ok: Default::default(),
            z_lt: Default::default(),
            z_pass: Default::default(),
            zb_next: Default::default(),
            ch_r: Default::default(),
            ch_g: Default::default(),
            ch_b: Default::default(),
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
            rgb: self.rgb_r.q.val().to_u32(),
            dsf,
            fsf,
            count,
            mask,
            nclass: self.nclass_r.q.val().to_u8(),
        }
    }

    /// Current readout registers (for testbenches).
    pub fn probe_capture(&self) -> ProcRegs {
        ProcRegs {
            zb: self.capzb_r.q.val().to_u32(),
            rgb: self.caprgb_r.q.val().to_u32(),
            dsf: self.capdsf_r.q.val(),
            fsf: self.capfsf_r.q.val(),
            count: self.capcount_r.q.val().to_u8(),
            mask: self.capmask_r.q.val().to_u8(),
            nclass: self.capnclass_r.q.val().to_u8(),
        }
    }
}

impl Logic for PixelProcessor {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clock,
            tok_op,
            tok_attr,
            tok_decal,
            tok_nclass,
            tok_rel_l,
            tok_rel_r,
            tok_z,
            tok_dz,
            tok_ir,
            tok_ig,
            tok_ib,
            tok_dir,
            tok_dig,
            tok_dib,
            b_op,
            b_attr,
            b_covered,
            b_zlt,
            b_write,
            b_z,
            b_rgb,
            b_nclass,
            zb_r,
            rgb_r,
            nclass_r,
            capzb_r,
            caprgb_r,
            capdsf_r,
            capfsf_r,
            capcount_r,
            capmask_r,
            capnclass_r,
            rdsel_r
        );
        // ---- Stage A: the token register, loaded every clock.
        self.tok_op.d.next = self.t_op.val();
        self.tok_attr.d.next = self.t_attr.val();
        self.tok_decal.d.next = self.t_decal.val();
        self.tok_nclass.d.next = self.t_nclass.val();
        self.tok_rel_l.d.next = self.t_rel_l.val();
        self.tok_rel_r.d.next = self.t_rel_r.val();
        self.tok_z.d.next = self.t_z.val();
        self.tok_dz.d.next = self.t_dz.val();
        self.tok_ir.d.next = self.t_ir.val();
        self.tok_ig.d.next = self.t_ig.val();
        self.tok_ib.d.next = self.t_ib.val();
        self.tok_dir.d.next = self.t_dir.val();
        self.tok_dig.d.next = self.t_dig.val();
        self.tok_dib.d.next = self.t_dib.val();
        // Sign-extended increments.
        self.dz_x.next = bit_cast::<44, 38>(self.tok_dz.q.val());
        if self.tok_dz.q.val().get_bit(37) {
            self.dz_x.next = self.dz_x.val() | self.k_sext_z.val();
        }
        self.dir_x.next = bit_cast::<34, 21>(self.tok_dir.q.val());
        if self.tok_dir.q.val().get_bit(20) {
            self.dir_x.next = self.dir_x.val() | self.k_sext_i.val();
        }
        self.dig_x.next = bit_cast::<34, 21>(self.tok_dig.q.val());
        if self.tok_dig.q.val().get_bit(20) {
            self.dig_x.next = self.dig_x.val() | self.k_sext_i.val();
        }
        self.dib_x.next = bit_cast::<34, 21>(self.tok_dib.q.val());
        if self.tok_dib.q.val().get_bit(20) {
            self.dib_x.next = self.dib_x.val() | self.k_sext_i.val();
        }
        // Range test: col >= XL iff XL − col − 1 < 0; col <= XR iff XR − col >= 0.
        self.right_of_xl.next = self.tok_rel_l.q.val().get_bit(13);
        self.covered.next = self.right_of_xl.val() & (!self.tok_rel_r.q.val().get_bit(13));
        // Token for the next processor.
        self.o_op.next = self.tok_op.q.val();
        self.o_attr.next = self.tok_attr.q.val();
        self.o_decal.next = self.tok_decal.q.val();
        self.o_nclass.next = self.tok_nclass.q.val();
        self.o_rel_l.next = self.tok_rel_l.q.val() - self.k_one14.val();
        self.o_rel_r.next = self.tok_rel_r.q.val() - self.k_one14.val();
        self.o_dz.next = self.tok_dz.q.val();
        self.o_dir.next = self.tok_dir.q.val();
        self.o_dig.next = self.tok_dig.q.val();
        self.o_dib.next = self.tok_dib.q.val();
        self.o_z.next = self.tok_z.q.val();
        self.o_ir.next = self.tok_ir.q.val();
        self.o_ig.next = self.tok_ig.q.val();
        self.o_ib.next = self.tok_ib.q.val();
        if self.right_of_xl.val() {
            self.o_z.next = self.tok_z.q.val() + self.dz_x.val();
            self.o_ir.next = self.tok_ir.q.val() + self.dir_x.val();
            self.o_ig.next = self.tok_ig.q.val() + self.dig_x.val();
            self.o_ib.next = self.tok_ib.q.val() + self.dib_x.val();
        }
        // ---- Stage B: apply the decision registered at the last edge. `zb_next` is the
        // value ZB takes at the coming edge.
        self.zb_next.next = self.zb_r.q.val();
        if self.b_write.q.val() {
            self.zb_next.next = self.b_z.q.val();
            self.rgb_r.d.next = self.b_rgb.q.val();
            self.nclass_r.d.next = self.b_nclass.q.val();
        }
        // Shadow logic (absent without shadows: flags, counter and mask read 0).
        self.dsf_now.next = false;
        self.fsf_now.next = false;
        self.count_now.next = self.k_zero8.val();
        self.mask_now.next = self.k_zero8.val();
        for i in 0..self.parity.len() {
            self.parity[i].clock.next = self.clock.val();
            self.parity[i].rst.next = self.b_op.q.val() == self.k_reset.val();
            self.parity[i].op.next = self.b_op.q.val();
            self.parity[i].attr.next = self.b_attr.q.val();
            self.parity[i].covered.next = self.b_covered.q.val();
            self.parity[i].z_lt.next = self.b_zlt.q.val();
            self.parity[i].light.next = self.b_rgb.q.val().get_bits::<3>(0);
            self.dsf_now.next = self.parity[i].dsf.val();
            self.fsf_now.next = self.parity[i].fsf.val();
            self.count_now.next = self.parity[i].count.val();
            self.mask_now.next = self.parity[i].mask.val();
        }
        // New scanline: copy the finished line into the readout registers, then clear.
        if self.b_op.q.val() == self.k_clear_line.val() {
            self.capzb_r.d.next = self.zb_r.q.val();
            self.caprgb_r.d.next = self.rgb_r.q.val();
            self.capdsf_r.d.next = self.dsf_now.val();
            self.capfsf_r.d.next = self.fsf_now.val();
            self.capcount_r.d.next = self.count_now.val();
            self.capmask_r.d.next = self.mask_now.val();
            self.capnclass_r.d.next = self.nclass_r.q.val();
            self.zb_next.next = self.k_zfar.val();
            self.rgb_r.d.next = self.b_rgb.q.val();
            self.nclass_r.d.next = self.k_zero8.val();
        }
        if self.b_op.q.val() == self.k_reset.val() {
            self.zb_next.next = self.k_zfar.val();
            self.rgb_r.d.next = self.k_zero24.val();
            self.nclass_r.d.next = self.k_zero8.val();
            self.capzb_r.d.next = self.k_zfar.val();
            self.caprgb_r.d.next = self.k_zero24.val();
            self.capdsf_r.d.next = false;
            self.capfsf_r.d.next = false;
            self.capcount_r.d.next = self.k_zero8.val();
            self.capmask_r.d.next = self.k_zero8.val();
            self.capnclass_r.d.next = self.k_zero8.val();
        }
        self.zb_r.d.next = self.zb_next.val();
        // ---- Stage A, decision: depth test against the next-state ZB (bypass), golden
        // `((z >> 12) as u32) < ZB` (or `<=` for decals); intensity clamp.
        self.zv.next = self.tok_z.q.val().get_bits::<24>(12);
        self.z_hi_ok.next = self.tok_z.q.val().get_bits::<8>(36) == self.k_zero8.val();
        self.z_lt.next = self.zv.val() < self.zb_next.val();
        self.z_pass.next = self.z_lt.val();
        if self.tok_decal.q.val() {
            self.z_pass.next = self.zv.val() <= self.zb_next.val();
        }
        // Intensity clamp: negative -> 0, >= 256.0 -> 255, else bits [19:12].
        self.ch_r.next = self.tok_ir.q.val().get_bits::<8>(12);
        if self.tok_ir.q.val().get_bits::<13>(20) != self.k_zero13.val() {
            self.ch_r.next = self.k_ff8.val();
        }
        if self.tok_ir.q.val().get_bit(33) {
            self.ch_r.next = self.k_zero8.val();
        }
        self.ch_g.next = self.tok_ig.q.val().get_bits::<8>(12);
        if self.tok_ig.q.val().get_bits::<13>(20) != self.k_zero13.val() {
            self.ch_g.next = self.k_ff8.val();
        }
        if self.tok_ig.q.val().get_bit(33) {
            self.ch_g.next = self.k_zero8.val();
        }
        self.ch_b.next = self.tok_ib.q.val().get_bits::<8>(12);
        if self.tok_ib.q.val().get_bits::<13>(20) != self.k_zero13.val() {
            self.ch_b.next = self.k_ff8.val();
        }
        if self.tok_ib.q.val().get_bit(33) {
            self.ch_b.next = self.k_zero8.val();
        }
        self.b_op.d.next = self.tok_op.q.val();
        self.b_attr.d.next = self.tok_attr.q.val();
        self.b_covered.d.next = self.covered.val();
        self.b_zlt.d.next = self.z_lt.val() & self.z_hi_ok.val();
        self.b_write.d.next = (self.tok_op.q.val() == self.k_span.val())
            & (self.tok_attr.q.val() == self.k_attr_op.val())
            & self.covered.val()
            & self.z_pass.val()
            & self.z_hi_ok.val();
        self.b_z.d.next = self.zv.val();
        self.b_nclass.d.next = self.tok_nclass.q.val();
        self.b_rgb.d.next = (bit_cast::<24, 8>(self.ch_r.val()) << 16)
            | (bit_cast::<24, 8>(self.ch_g.val()) << 8)
            | bit_cast::<24, 8>(self.ch_b.val());
        if self.tok_op.q.val() != self.k_span.val() {
            // CLEAR_LINE's background, LATCH_SHADOW's bit.
            self.b_rgb.d.next = self.tok_z.q.val().get_bits::<24>(0);
        }
        // ---- Outputs.
        self.rdsel_r.d.next = self.rd_sel.val();
        self.rdo.next = self.k_zero74.val();
        if self.rdsel_r.q.val() {
            self.rdo.next = (bit_cast::<74, 8>(self.capnclass_r.q.val()) << 66)
                | (bit_cast::<74, 8>(self.capmask_r.q.val()) << 58)
                | (bit_cast::<74, 24>(self.capzb_r.q.val()) << 34)
                | (bit_cast::<74, 24>(self.caprgb_r.q.val()) << 10)
                | (bit_cast::<74, 8>(self.capcount_r.q.val()));
            if self.capdsf_r.q.val() {
                self.rdo.next = self.rdo.val() | self.k_bit9.val();
            }
            if self.capfsf_r.q.val() {
                self.rdo.next = self.rdo.val() | self.k_bit8.val();
            }
        }
    }
}
