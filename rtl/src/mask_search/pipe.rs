//! The pipelined mask search unit (seed 000, JP2569952B2, claim 2 and Fig. 6): one stage
//! per search line, a new mask every clock.

use super::{check, MaskSearchError, SearchBackEnd, SearchStage, BACK_LATENCY, LINE_BITS, PB};
use super::{WORD_BITS, Z_BITS};
use pixelproc_formats::abuffer::{search_mask_table, Corner, MaskSize, SearchFamily};
use rust_hdl::prelude::*;

search_unit! {
    /// The pipelined search unit: one stage per search line, a new mask every clock.
    ///
    /// **Handshake.** Valid-only, fixed latency, no back-pressure (`ready` would be constant 1):
    /// `in_valid` with its mask, corner and plane is sampled at every rising edge. Stage `k`
    /// (`k = 0 .. lines`) holds the mask `k` edges after it was sampled and tests line `k`
    /// unless an earlier line hit; the last stage's outcome enters the back end at the next
    /// edge. A mask sampled at edge `E` shows its result on `out_*` after edge
    /// `E + latency() − 1`, `latency() = lines + 12` (19 for 4×4, 27 for 8×8; `BACK_LATENCY`
    /// = 12): on the `latency()`-th clock counting `E`'s, with `out_valid`.
    /// Result fields are meaningful only with `out_valid`.
    pub struct MaskSearchPipe {
    }
    after_results {
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
}

impl<const B: usize> MaskSearchPipe<B> {
    /// The unit for `size` (`size.bits() == B`) and a search family.
    pub fn new(size: MaskSize, family: SearchFamily) -> Result<Self, MaskSearchError> {
        let lines = check(size, family, B)?;
        let t = Corner::ALL.map(|c| search_mask_table(size, family, c));
        let stages = (0..lines)
            .map(|k| SearchStage::new(t.clone().map(|v| v[k as usize]), k))
            .collect();
        Ok(search_unit_new!(MaskSearchPipe {
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
        }))
    }

    /// Edges from sampling a mask to its result on `out_*`.
    pub fn latency(&self) -> usize {
        self.stages.len() + BACK_LATENCY
    }
}

search_unit_logic! {
    MaskSearchPipe,
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
        // `search_unit_logic!` then forwards the back end's results to `out_*`.
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::{cycle, depth_of, plane_bits, SEED_DEPTHS, SEED_PLANE, SEED_WORD};

    #[test]
    fn seed_worked_example_through_the_pipeline() {
        let mut u = MaskSearchPipe::<16>::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        u.connect_all();
        u.rst.next = true;
        cycle!(u);
        u.rst.next = false;
        u.in_valid.next = true;
        u.in_mask.next = 0xFF73u64.to_bits();
        u.in_zc.next = plane_bits(SEED_PLANE[0]);
        u.in_sx.next = plane_bits(SEED_PLANE[1]);
        u.in_sy.next = plane_bits(SEED_PLANE[2]);
        cycle!(u);
        u.in_valid.next = false;
        for _ in 1..u.latency() {
            assert!(!u.out_valid.val());
            cycle!(u);
        }
        assert!(u.out_valid.val() && u.out_hit.val());
        assert_eq!(u.out_steps.val().to_u64(), 3);
        assert_eq!(u.out_and.val().to_u64(), 0x0842);
        assert_eq!(u.out_rom.val().to_u64(), SEED_WORD);
        assert_eq!(
            [&u.out_zmin, &u.out_zmax].map(|s| depth_of(s.val())),
            SEED_DEPTHS
        );
    }

    #[test]
    fn verilog_passes_yosys() {
        let u = MaskSearchPipe::<16>::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        crate::mask_search::yosys_check("pixelproc_rtl_pipe", u);
    }
}
