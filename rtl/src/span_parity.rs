//! Span-parity shadow logic of one pixel processor (seed 001, Matsumoto, section 4 and
//! the area-light extension of section 6).
//!
//! Implements, for the processor owning screen column `col`:
//!
//! ```text
//! IF attr = IF THEN DSF := NOT DSF                                  (every pixel)
//! IF (XL <= col < XR + 1) AND (Z < ZB) THEN DSF := NOT DSF           (range test, depth test)
//! IF attr = EV THEN FSF := FSF OR DSF                                (end of one volume)
//! ClearFlags:        DSF := 0; FSF := 0                              (next point light)
//! AccumulateShadow:  COUNT := min(COUNT + FSF, 255)                  (area light, section 6)
//! ClearLine / rst:   DSF := 0; FSF := 0; COUNT := 0
//! ```
//!
//! **Range test.** The span word's `XR` is inclusive; the test is the half-open interval
//! `[XL, XR + 1)`. The paper's caution (two shadow spans of one volume meeting at `X2`
//! must not both count `X2`) is met by the span generator, which emits the half-open
//! shadow span `(Xl, Xr − 1)` as `XL = Xl, XR = Xr − 1`; this block tests exactly the
//! interval the word encodes, bit-exactly like the golden model. The test is done on the
//! two running differences the systolic token carries (see `pixel_array`):
//! `rel_l = XL − col − 1` and `rel_r = XR − col` (14-bit two's complement); the column
//! is covered iff `rel_l < 0` and `rel_r >= 0`, i.e. two sign bits, no comparator.
//!
//! **Depth test.** `z` is the token's depth accumulator `ZL + (col − XL)·dZ` modulo
//! `2^44` (Q32.12); the golden model compares `((z >> 12) as u32) < ZB`, which is
//! `z[43:36] == 0 && z[35:12] < ZB`.
//!
//! Ports (all registered state, latency 1): inputs are sampled at the rising edge of
//! `clock`; `dsf`, `fsf`, `count` show the registers. `rst` is a synchronous reset.

use crate::opcodes::*;
use rust_hdl::prelude::*;

/// The DSF/FSF flags and the shadow counter of one pixel processor.
#[derive(LogicBlock)]
pub struct SpanParity {
    /// Clock; every register updates on its rising edge.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: clears DSF, FSF and COUNT.
    pub rst: Signal<In, Bit>,
    /// Opcode of the token at this processor (see [`crate::opcodes`]).
    pub op: Signal<In, Bits<3>>,
    /// Span attribute (`0` OP, `1` SP, `2` EV, `3` IF).
    pub attr: Signal<In, Bits<2>>,
    /// `XL − col − 1`, 14-bit two's complement.
    pub rel_l: Signal<In, Bits<14>>,
    /// `XR − col`, 14-bit two's complement.
    pub rel_r: Signal<In, Bits<14>>,
    /// Depth accumulator at this column, Q32.12 modulo 2^44.
    pub z: Signal<In, Bits<44>>,
    /// The processor's depth buffer value.
    pub zb: Signal<In, Bits<24>>,
    /// Shadow decision flag.
    pub dsf: Signal<Out, Bit>,
    /// Final shadow flag.
    pub fsf: Signal<Out, Bit>,
    /// Number of point lights shadowing this pixel (saturating).
    pub count: Signal<Out, Bits<8>>,
    dsf_r: DFF<Bit>,
    fsf_r: DFF<Bit>,
    count_r: DFF<Bits<8>>,
    k_clear_line: Constant<Bits<3>>,
    k_span: Constant<Bits<3>>,
    k_clear_flags: Constant<Bits<3>>,
    k_accumulate: Constant<Bits<3>>,
    k_attr_op: Constant<Bits<2>>,
    k_attr_ev: Constant<Bits<2>>,
    k_attr_if: Constant<Bits<2>>,
    k_zero8: Constant<Bits<8>>,
    k_one8: Constant<Bits<8>>,
    k_max8: Constant<Bits<8>>,
    covered: Signal<Local, Bit>,
    z_lt: Signal<Local, Bit>,
    flip: Signal<Local, Bit>,
}

impl Default for SpanParity {
    fn default() -> Self {
        SpanParity {
            clock: Default::default(),
            rst: Default::default(),
            op: Default::default(),
            attr: Default::default(),
            rel_l: Default::default(),
            rel_r: Default::default(),
            z: Default::default(),
            zb: Default::default(),
            dsf: Default::default(),
            fsf: Default::default(),
            count: Default::default(),
            dsf_r: Default::default(),
            fsf_r: Default::default(),
            count_r: Default::default(),
            k_clear_line: Constant::new(OP_CLEAR_LINE.to_bits()),
            k_span: Constant::new(OP_SPAN.to_bits()),
            k_clear_flags: Constant::new(OP_CLEAR_FLAGS.to_bits()),
            k_accumulate: Constant::new(OP_ACCUMULATE.to_bits()),
            k_attr_op: Constant::new(0u64.to_bits()),
            k_attr_ev: Constant::new(2u64.to_bits()),
            k_attr_if: Constant::new(3u64.to_bits()),
            k_zero8: Constant::new(0u64.to_bits()),
            k_one8: Constant::new(1u64.to_bits()),
            k_max8: Constant::new(255u64.to_bits()),
            covered: Default::default(),
            z_lt: Default::default(),
            flip: Default::default(),
        }
    }
}

impl Logic for SpanParity {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, dsf_r, fsf_r, count_r);
        // Half-open range test on the two running differences (sign bits only).
        self.covered.next = self.rel_l.val().get_bit(13) & (!self.rel_r.val().get_bit(13));
        // Z < ZB exactly as the golden model's `((z >> 12) as u32) < zb`.
        self.z_lt.next = (self.z.val().get_bits::<8>(36) == self.k_zero8.val())
            & (self.z.val().get_bits::<24>(12) < self.zb.val());
        self.flip.next = self.covered.val() & self.z_lt.val();
        if (self.op.val() == self.k_span.val()) & (self.attr.val() != self.k_attr_op.val()) {
            if self.attr.val() == self.k_attr_if.val() {
                self.flip.next = !self.flip.val();
            }
            self.dsf_r.d.next = self.dsf_r.q.val() ^ self.flip.val();
            if self.attr.val() == self.k_attr_ev.val() {
                self.fsf_r.d.next = self.fsf_r.q.val() | (self.dsf_r.q.val() ^ self.flip.val());
            }
        }
        if self.op.val() == self.k_clear_flags.val() {
            self.dsf_r.d.next = false;
            self.fsf_r.d.next = false;
        }
        if (self.op.val() == self.k_accumulate.val())
            & self.fsf_r.q.val()
            & (self.count_r.q.val() != self.k_max8.val())
        {
            self.count_r.d.next = self.count_r.q.val() + self.k_one8.val();
        }
        if (self.op.val() == self.k_clear_line.val()) | self.rst.val() {
            self.dsf_r.d.next = false;
            self.fsf_r.d.next = false;
            self.count_r.d.next = self.k_zero8.val();
        }
        self.dsf.next = self.dsf_r.q.val();
        self.fsf.next = self.fsf_r.q.val();
        self.count.next = self.count_r.q.val();
    }
}

impl SpanParity {
    /// Current `(DSF, FSF, COUNT)` registers (for testbenches).
    pub fn probe(&self) -> (bool, bool, u8) {
        (
            self.dsf_r.q.val(),
            self.fsf_r.q.val(),
            self.count_r.q.val().to_u8(),
        )
    }
}
