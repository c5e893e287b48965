//! One colour channel of a pixel processor (seed 001, Matsumoto, section 3: the
//! intensity is interpolated along the span like the depth, one adder per processor).
//!
//! The processor holds the token's three intensity accumulators and increments; each
//! [`ColourLane`] takes one channel's pair and produces the accumulator for the next
//! column (`i + dI` with `dI` sign-extended, if `step`) and the channel value the
//! processor would write, `clamp(i >> 12, 0, 255)`. Purely combinational: the registers
//! stay in the processor, so the lane adds no latency.

use crate::pixel_processor::IACC_W;
use pixelproc_formats::{INTENSITY_FRAC_BITS, SPAN_DI_R};
use rust_hdl::prelude::*;

/// Width of one `dI` channel.
pub(crate) const DI_W: usize = SPAN_DI_R.width;
/// Width of one colour channel.
pub(crate) const CH_W: usize = 8;
/// Bits of an intensity accumulator above the 8-bit channel (`[IACC_W−2:20]`): any set
/// bit means `>= 256.0`.
const OVER_W: usize = IACC_W - CH_W - INTENSITY_FRAC_BITS as usize - 1;
// A kernel can only take literal bit positions: the sign bits 20 (`dI`) and 33
// (accumulator) and the channel slices at 12 and 20 below are these widths.
const _: () = assert!(DI_W == 21 && IACC_W == 34 && OVER_W == 13 && INTENSITY_FRAC_BITS == 12);

/// One colour channel's step and clamp. Build with [`ColourLane::new`].
#[derive(LogicBlock)]
pub struct ColourLane {
    /// Intensity accumulator at this column, Q22.12 two's complement.
    pub i: Signal<In, Bits<IACC_W>>,
    /// Increment `dI`, Q9.12 two's complement.
    pub di: Signal<In, Bits<DI_W>>,
    /// The span has reached this column (`col >= XL`): step the accumulator.
    pub step: Signal<In, Bit>,
    /// Accumulator for the next column: `i + dI` if `step`, else `i`.
    pub o_i: Signal<Out, Bits<IACC_W>>,
    /// The channel value: negative -> 0, `>= 256.0` -> 255, else bits `[19:12]`.
    pub ch: Signal<Out, Bits<CH_W>>,
    di_x: Signal<Local, Bits<IACC_W>>,
    k_sext: Constant<Bits<IACC_W>>,
    k_zero_over: Constant<Bits<OVER_W>>,
    k_max: Constant<Bits<CH_W>>,
    k_zero: Constant<Bits<CH_W>>,
}

impl ColourLane {
    /// A lane with its constants set.
    pub fn new() -> Self {
        ColourLane {
            i: Default::default(),
            di: Default::default(),
            step: Default::default(),
            o_i: Default::default(),
            ch: Default::default(),
            di_x: Default::default(),
            k_sext: Constant::new((((1u64 << IACC_W) - 1) ^ ((1u64 << DI_W) - 1)).to_bits()),
            k_zero_over: Constant::new(0u64.to_bits()),
            k_max: Constant::new(((1u64 << CH_W) - 1).to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
        }
    }
}

impl Default for ColourLane {
    fn default() -> Self {
        Self::new()
    }
}

impl Logic for ColourLane {
    #[hdl_gen]
    fn update(&mut self) {
        // Sign-extended increment.
        self.di_x.next = bit_cast::<IACC_W, DI_W>(self.di.val());
        if self.di.val().get_bit(20) {
            self.di_x.next = self.di_x.val() | self.k_sext.val();
        }
        self.o_i.next = self.i.val();
        if self.step.val() {
            self.o_i.next = self.i.val() + self.di_x.val();
        }
        self.ch.next = self.i.val().get_bits::<CH_W>(12);
        if self.i.val().get_bits::<OVER_W>(20) != self.k_zero_over.val() {
            self.ch.next = self.k_max.val();
        }
        if self.i.val().get_bit(33) {
            self.ch.next = self.k_zero.val();
        }
    }
}
