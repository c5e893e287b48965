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
//! LatchShadow{bit}:  MASK := MASK OR (FSF << bit)                    (several lights, section 6)
//! Check{xl, xr}:     IF XL <= col < XR + 1 THEN FSF := FSF OR DSF    (software form, section 5)
//! ClearLine / rst:   DSF := 0; FSF := 0; COUNT := 0; MASK := 0
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
//! The processor evaluates the range test (`covered`, from the sign bits of the running
//! differences) and hands it over with the opcode and attribute.
//!
//! **Depth test.** The processor computes `z_lt`, the golden model's
//! `((z >> 12) as u32) < ZB` on the token's depth accumulator, one clock ahead (see
//! `pixel_processor`), so this block holds no comparator of its own.
//!
//! Ports (all registered state, latency 1): inputs are sampled at the rising edge of
//! `clock`; `dsf`, `fsf`, `count`, `mask` show the registers. `rst` is a synchronous
//! reset.

use crate::opcodes::*;
use rust_hdl::prelude::*;

/// The DSF/FSF flags, the shadow counter and the light mask of one pixel processor.
#[derive(LogicBlock)]
pub struct SpanParity {
    /// Clock; every register updates on its rising edge.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: clears DSF, FSF, COUNT and MASK.
    pub rst: Signal<In, Bit>,
    /// Opcode of the command acting on this processor (see [`crate::opcodes`]).
    pub op: Signal<In, Bits<3>>,
    /// Span attribute (`0` OP, `1` SP, `2` EV, `3` IF).
    pub attr: Signal<In, Bits<2>>,
    /// The column lies in `[XL, XR + 1)` of the span word (or check range).
    pub covered: Signal<In, Bit>,
    /// `Z < ZB` at this column (golden `((z >> 12) as u32) < ZB`).
    pub z_lt: Signal<In, Bit>,
    /// Light bit for LATCH_SHADOW, 0..7.
    pub light: Signal<In, Bits<3>>,
    /// Shadow decision flag.
    pub dsf: Signal<Out, Bit>,
    /// Final shadow flag.
    pub fsf: Signal<Out, Bit>,
    /// Number of point lights shadowing this pixel (saturating).
    pub count: Signal<Out, Bits<8>>,
    /// Which point lights shadow this pixel, one bit per light.
    pub mask: Signal<Out, Bits<8>>,
    dsf_r: DFF<Bit>,
    fsf_r: DFF<Bit>,
    count_r: DFF<Bits<8>>,
    mask_r: DFF<Bits<8>>,
    k_clear_line: Constant<Bits<3>>,
    k_span: Constant<Bits<3>>,
    k_clear_flags: Constant<Bits<3>>,
    k_accumulate: Constant<Bits<3>>,
    k_latch: Constant<Bits<3>>,
    k_check: Constant<Bits<3>>,
    k_attr_op: Constant<Bits<2>>,
    k_attr_ev: Constant<Bits<2>>,
    k_attr_if: Constant<Bits<2>>,
    k_zero8: Constant<Bits<8>>,
    k_one8: Constant<Bits<8>>,
    k_max8: Constant<Bits<8>>,
    flip: Signal<Local, Bit>,
}

impl Default for SpanParity {
    fn default() -> Self {
        SpanParity {
            clock: Default::default(),
            rst: Default::default(),
            op: Default::default(),
            attr: Default::default(),
            covered: Default::default(),
            z_lt: Default::default(),
            light: Default::default(),
            dsf: Default::default(),
            fsf: Default::default(),
            count: Default::default(),
            mask: Default::default(),
            dsf_r: Default::default(),
            fsf_r: Default::default(),
            count_r: Default::default(),
            mask_r: Default::default(),
            k_clear_line: Constant::new(OP_CLEAR_LINE.to_bits()),
            k_span: Constant::new(OP_SPAN.to_bits()),
            k_clear_flags: Constant::new(OP_CLEAR_FLAGS.to_bits()),
            k_accumulate: Constant::new(OP_ACCUMULATE.to_bits()),
            k_latch: Constant::new(OP_LATCH_SHADOW.to_bits()),
            k_check: Constant::new(OP_CHECK.to_bits()),
            k_attr_op: Constant::new(0u64.to_bits()),
            k_attr_ev: Constant::new(2u64.to_bits()),
            k_attr_if: Constant::new(3u64.to_bits()),
            k_zero8: Constant::new(0u64.to_bits()),
            k_one8: Constant::new(1u64.to_bits()),
            k_max8: Constant::new(255u64.to_bits()),
            flip: Default::default(),
        }
    }
}

impl Logic for SpanParity {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, dsf_r, fsf_r, count_r, mask_r);
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
        if (self.op.val() == self.k_check.val()) & self.covered.val() {
            self.fsf_r.d.next = self.fsf_r.q.val() | self.dsf_r.q.val();
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
        if (self.op.val() == self.k_latch.val()) & self.fsf_r.q.val() {
            self.mask_r.d.next = self.mask_r.q.val() | (self.k_one8.val() << self.light.val());
        }
        if (self.op.val() == self.k_clear_line.val()) | self.rst.val() {
            self.dsf_r.d.next = false;
            self.fsf_r.d.next = false;
            self.count_r.d.next = self.k_zero8.val();
            self.mask_r.d.next = self.k_zero8.val();
        }
        self.dsf.next = self.dsf_r.q.val();
        self.fsf.next = self.fsf_r.q.val();
        self.count.next = self.count_r.q.val();
        self.mask.next = self.mask_r.q.val();
    }
}

impl SpanParity {
    /// Current `(DSF, FSF, COUNT, MASK)` registers (for testbenches).
    pub fn probe(&self) -> (bool, bool, u8, u8) {
        (
            self.dsf_r.q.val(),
            self.fsf_r.q.val(),
            self.count_r.q.val().to_u8(),
            self.mask_r.q.val().to_u8(),
        )
    }
}
