//! The shared back end of both search unit variants (seed 000, JP2569952B2, Fig. 6 blocks
//! 7, 8 and 10): offset ROM, depth calculator and the result registers.

use super::{dff_line, DepthCalc, OffsetRom, BACK_LATENCY, DEPTH_LATENCY, IN_LATENCY, LINE_BITS};
use super::{PB, ROM_LATENCY, WORD_BITS, Z_BITS};
use pixelproc_formats::abuffer::MaskSize;
use rust_hdl::prelude::*;

search_block! {
    /// The shared back end: a search result (sampled every clock into the input registers)
    /// goes through the offset ROM and the depth calculator; the result ports show it
    /// [`BACK_LATENCY`] = 12 clocks later (1 input register, 5 ROM, 6 depth).
    ///
    /// On `i_hit = 0` (empty mask) `i_and` is 0, the ROM reads 0 (offsets (0, 0), no pair) and
    /// every depth is `zc`, the golden fallback for a fragment without a hit.
    pub struct SearchBackEnd {
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
    }
    after_results {
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
}

impl<const B: usize> SearchBackEnd<B> {
    /// The back end for `size` (`size.bits() == B`).
    pub fn new(size: MaskSize) -> Self {
        // The kernel reads the last registers by literal index.
        const _: () = assert!(
            IN_LATENCY == 1 && ROM_LATENCY == 5 && DEPTH_LATENCY == 6 && BACK_LATENCY == 12
        );
        search_block_new!(SearchBackEnd {
            i_valid: Default::default(),
            i_hit: Default::default(),
            i_steps: Default::default(),
            i_and: Default::default(),
            i_zc: Default::default(),
            i_sx: Default::default(),
            i_sy: Default::default(),
            rom: OffsetRom::new(size),
            depth: DepthCalc::new(),
            valid_d: dff_line(BACK_LATENCY),
            hit_d: dff_line(BACK_LATENCY),
            steps_d: dff_line(BACK_LATENCY),
            and_d: dff_line(BACK_LATENCY),
            zc_d: dff_line(IN_LATENCY + ROM_LATENCY),
            sx_d: dff_line(IN_LATENCY + ROM_LATENCY),
            sy_d: dff_line(IN_LATENCY + ROM_LATENCY),
            word_d: dff_line(DEPTH_LATENCY),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_p: Constant::new(0u64.to_bits()),
            k_zero_l: Constant::new(0u64.to_bits()),
            k_zero_w: Constant::new(0u64.to_bits()),
        })
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
        // Plane: IN_LATENCY + ROM_LATENCY registers, aligned with the ROM word.
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
        // The ROM reads the registered AND result (the input register, `and_d[0]`).
        self.rom.and_in.next = self.and_d[0].q.val();
        self.depth.word.next = self.rom.word.val();
        // Every signal crossing a module boundary is written exactly once per evaluation
        // (no default-then-override): an intermediate value on a port that feeds back
        // into the writer's inputs makes event-driven simulators (Icarus) loop at zero
        // delay. Hence literal indices of the last registers (checked in `new`).
        self.depth.zc.next = self.zc_d[5].q.val();
        self.depth.sx.next = self.sx_d[5].q.val();
        self.depth.sy.next = self.sy_d[5].q.val();
        self.out_valid.next = self.valid_d[11].q.val();
        self.out_hit.next = self.hit_d[11].q.val();
        self.out_steps.next = self.steps_d[11].q.val();
        self.out_and.next = self.and_d[11].q.val();
        self.out_rom.next = self.word_d[5].q.val();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::{cycle, depth_of, plane_bits, SEED_DEPTHS, SEED_PLANE, SEED_WORD};

    #[test]
    fn a_result_shows_back_latency_clocks_later() {
        let mut u = SearchBackEnd::<16>::new(MaskSize::S4X4);
        u.connect_all();
        u.i_valid.next = true;
        u.i_hit.next = true;
        u.i_steps.next = 3u64.to_bits();
        u.i_and.next = 0x0842u64.to_bits();
        u.i_zc.next = plane_bits(SEED_PLANE[0]);
        u.i_sx.next = plane_bits(SEED_PLANE[1]);
        u.i_sy.next = plane_bits(SEED_PLANE[2]);
        cycle!(u);
        u.i_valid.next = false;
        u.i_and.next = 0u64.to_bits();
        for _ in 1..BACK_LATENCY {
            assert!(!u.out_valid.val());
            cycle!(u);
        }
        assert!(u.out_valid.val() && u.out_hit.val());
        assert_eq!(u.out_steps.val().to_u64(), 3);
        assert_eq!(u.out_and.val().to_u64(), 0x0842);
        assert_eq!(u.out_rom.val().to_u64(), SEED_WORD);
        assert_eq!(depth_of(u.out_zmin.val()), SEED_DEPTHS[0]);
        assert_eq!(depth_of(u.out_zmax.val()), SEED_DEPTHS[1]);
        cycle!(u);
        assert!(!u.out_valid.val());
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check(
            "pixelproc_rtl_back_end",
            SearchBackEnd::<16>::new(MaskSize::S4X4),
        );
    }
}
