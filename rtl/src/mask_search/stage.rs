//! One stage of the pipelined mask search unit (seed 000, JP2569952B2, Fig. 6 blocks 3 to
//! 6 for one search line).

use super::{LINE_BITS, PB};
use rust_hdl::prelude::*;

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

/// One stage of [`MaskSearchPipe`](super::MaskSearchPipe): tests line `k` (a constant) for the mask in its
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
    /// The stage testing line `line`, whose search masks per corner code are `masks`.
    pub(crate) fn new(masks: [u64; 4], line: u32) -> Self {
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
        // Without an earlier hit the AND result so far is 0 (stage 0 gets 0, a stage only
        // loads a non-zero result together with `found`), so this line's AND result is
        // passed on whether it is zero or not: `o_and` does not wait for the zero detector.
        if self.test.val() {
            self.o_steps.next = self.k_steps.val();
            self.o_and.next = self.and_v.val();
            if self.and_v.val() != self.k_zero_b.val() {
                self.o_found.next = true;
            }
        }
        self.o_zc.next = self.zc_r.q.val();
        self.o_sx.next = self.sx_r.q.val();
        self.o_sy.next = self.sy_r.q.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::cycle;

    #[test]
    fn a_stage_tests_its_line_unless_an_earlier_one_hit() {
        // Line 2 of the 4×4 diagonal family from the top-left corner is 0842H.
        let mut u = SearchStage::<16>::new([0x0842, 0x1111, 0x2222, 0x4444], 2);
        u.connect_all();
        u.i_valid.next = true;
        u.i_mask.next = 0xFF73u64.to_bits();
        u.i_steps.next = 2u64.to_bits();
        cycle!(u);
        assert!(u.o_valid.val() && u.o_found.val());
        assert_eq!(
            (u.o_and.val().to_u64(), u.o_steps.val().to_u64()),
            (0x0842, 3)
        );
        assert_eq!(u.probe().mask, 0xFF73);
        u.i_found.next = true;
        u.i_and.next = 0x0001u64.to_bits();
        u.i_steps.next = 1u64.to_bits();
        cycle!(u);
        assert_eq!(
            (u.o_and.val().to_u64(), u.o_steps.val().to_u64()),
            (0x0001, 1)
        );
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check(
            "pixelproc_rtl_stage",
            SearchStage::<16>::new([0x0842, 0x1111, 0x2222, 0x4444], 2),
        );
    }
}
