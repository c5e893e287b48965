//! The iterative mask search unit (seed 000, JP2569952B2, claim 2 and Fig. 6 blocks 3 to 6):
//! one search line per clock, the seed's flowchart.

use super::{check, MaskGen, MaskSearchError, SearchBackEnd, LINE_BITS, PB, WORD_BITS, Z_BITS};
use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use rust_hdl::prelude::*;

search_unit! {
    /// The iterative search unit: one search line per clock (the seed's flowchart).
    ///
    /// **Handshake.** `ready` is high when the unit is idle or finishing its search in this
    /// clock (`done`). A start (`in_valid`, with `in_mask`, `in_corner`, `in_zc/sx/sy`) is
    /// accepted at a rising edge where `ready` is high (it is ignored otherwise), so searches
    /// follow each other without a gap: a search of `s` lines occupies `s` clocks.
    ///
    /// **Step ports** (combinational from the state registers, Moore): after the accepting
    /// edge the unit shows line 0, after each further edge the next line, exactly the golden
    /// `SearchUnit::step` output of that clock (all zero when idle).
    ///
    /// **Result ports**: the clock that shows `done` is sampled into the back end; `out_*`
    /// show the result [`BACK_LATENCY`](super::BACK_LATENCY) = 12 clocks later (after edge `t + 12` for a `done`
    /// shown after edge `t`), `out_valid` for one clock. Result fields are meaningful only
    /// with `out_valid`.
    pub struct MaskSearchIter {
        /// A start is accepted at the next edge.
        pub ready: Signal<Out, Bit>,
        /// Step: a search is running.
        pub active: Signal<Out, Bit>,
        /// Step: line index tested.
        pub line: Signal<Out, Bits<LINE_BITS>>,
        /// Step: the search mask of that line.
        pub search_mask: Signal<Out, Bits<B>>,
        /// Step: fraction mask AND search mask.
        pub and_result: Signal<Out, Bits<B>>,
        /// Step: zero detector.
        pub zero: Signal<Out, Bit>,
        /// Step: the mover fires (next line follows).
        pub moved: Signal<Out, Bit>,
        /// Step: first hit.
        pub hit: Signal<Out, Bit>,
        /// Step: the search ends this clock.
        pub done: Signal<Out, Bit>,
    }
    after_results {
        /// The back end.
        pub back: SearchBackEnd<B>,
        running_r: DFF<Bit>,
        line_r: DFF<Bits<LINE_BITS>>,
        mask_r: DFF<Bits<B>>,
        corner_r: DFF<Bits<2>>,
        zc_r: DFF<Bits<PB>>,
        sx_r: DFF<Bits<PB>>,
        sy_r: DFF<Bits<PB>>,
        /// The search mask generator (Fig. 6 block 3).
        sm_gen: MaskGen<B>,
        k_last: Constant<Bits<LINE_BITS>>,
        k_one_l: Constant<Bits<LINE_BITS>>,
        k_zero_l: Constant<Bits<LINE_BITS>>,
        k_zero_b: Constant<Bits<B>>,
        k_zero_p: Constant<Bits<PB>>,
        k_zero_c: Constant<Bits<2>>,
        and_v: Signal<Local, Bits<B>>,
        nz: Signal<Local, Bit>,
        last: Signal<Local, Bit>,
    }
}

impl<const B: usize> MaskSearchIter<B> {
    /// The unit for `size` (`size.bits() == B`) and a search family (the seed's is
    /// [`SearchFamily::DIAGONAL`]).
    pub fn new(size: MaskSize, family: SearchFamily) -> Result<Self, MaskSearchError> {
        let lines = check(size, family, B)? as usize;
        Ok(search_unit_new!(MaskSearchIter {
            ready: Default::default(),
            active: Default::default(),
            line: Default::default(),
            search_mask: Default::default(),
            and_result: Default::default(),
            zero: Default::default(),
            moved: Default::default(),
            hit: Default::default(),
            done: Default::default(),
            back: SearchBackEnd::new(size),
            running_r: Default::default(),
            line_r: Default::default(),
            mask_r: Default::default(),
            corner_r: Default::default(),
            zc_r: Default::default(),
            sx_r: Default::default(),
            sy_r: Default::default(),
            sm_gen: MaskGen::new(size, family),
            k_last: Constant::new((lines as u64 - 1).to_bits()),
            k_one_l: Constant::new(1u64.to_bits()),
            k_zero_l: Constant::new(0u64.to_bits()),
            k_zero_b: Constant::new(0u64.to_bits()),
            k_zero_p: Constant::new(0u64.to_bits()),
            k_zero_c: Constant::new(0u64.to_bits()),
            and_v: Default::default(),
            nz: Default::default(),
            last: Default::default(),
        }))
    }

    /// Number of search lines (the longest search, in clocks).
    pub fn lines(&self) -> usize {
        self.sm_gen.lines()
    }
}

search_unit_logic! {
    MaskSearchIter,
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, running_r, line_r, mask_r, corner_r, zc_r, sx_r, sy_r);
        self.back.clock.next = self.clock.val();
        self.back.rst.next = self.rst.val();
        // Search mask generator: table[corner][line].
        self.sm_gen.line.next = self.line_r.q.val();
        self.sm_gen.corner.next = self.corner_r.q.val();
        // AND unit, zero detector, last line.
        self.and_v.next = self.mask_r.q.val() & self.sm_gen.mask.val();
        self.nz.next = self.and_v.val() != self.k_zero_b.val();
        self.last.next = self.line_r.q.val() == self.k_last.val();
        self.active.next = self.running_r.q.val();
        self.line.next = self.k_zero_l.val();
        self.search_mask.next = self.k_zero_b.val();
        self.and_result.next = self.k_zero_b.val();
        if self.running_r.q.val() {
            self.line.next = self.line_r.q.val();
            self.search_mask.next = self.sm_gen.mask.val();
            self.and_result.next = self.and_v.val();
        }
        self.zero.next = self.running_r.q.val() & (!self.nz.val());
        self.hit.next = self.running_r.q.val() & self.nz.val();
        self.moved.next = (self.running_r.q.val() & (!self.nz.val())) & (!self.last.val());
        self.done.next = self.running_r.q.val() & (self.nz.val() | self.last.val());
        self.ready.next = (!self.running_r.q.val()) | self.done.val();
        // Mover and end of search.
        if self.done.val() {
            self.running_r.d.next = false;
        }
        if self.moved.val() {
            self.line_r.d.next = self.line_r.q.val() + self.k_one_l.val();
        }
        // Start.
        if self.in_valid.val() & self.ready.val() {
            self.running_r.d.next = true;
            self.line_r.d.next = self.k_zero_l.val();
            self.mask_r.d.next = self.in_mask.val();
            self.corner_r.d.next = self.in_corner.val();
            self.zc_r.d.next = self.in_zc.val();
            self.sx_r.d.next = self.in_sx.val();
            self.sy_r.d.next = self.in_sy.val();
        }
        if self.rst.val() {
            self.running_r.d.next = false;
            self.line_r.d.next = self.k_zero_l.val();
            self.mask_r.d.next = self.k_zero_b.val();
            self.corner_r.d.next = self.k_zero_c.val();
            self.zc_r.d.next = self.k_zero_p.val();
            self.sx_r.d.next = self.k_zero_p.val();
            self.sy_r.d.next = self.k_zero_p.val();
        }
        // Back end: the finishing clock's result.
        self.back.i_valid.next = self.done.val();
        self.back.i_hit.next = self.hit.val();
        self.back.i_steps.next = self.line_r.q.val() + self.k_one_l.val();
        // and_v is 0 unless this line hits (and the back end only keeps it with done).
        self.back.i_and.next = self.and_v.val();
        self.back.i_zc.next = self.zc_r.q.val();
        self.back.i_sx.next = self.sx_r.q.val();
        self.back.i_sy.next = self.sy_r.q.val();
        // `search_unit_logic!` then forwards the back end's results to `out_*`.
    }
}

#[cfg(test)]
mod tests {
    use super::super::BACK_LATENCY;
    use super::*;

    fn clock<B: Block>(u: &mut B, rise: impl Fn(&mut B)) {
        rise(u);
        assert!(simulate(u, 200));
    }

    fn cycle_iter(u: &mut MaskSearchIter<16>, start: Option<(u64, u8, [i64; 3])>) {
        u.in_valid.next = start.is_some();
        if let Some((m, c, p)) = start {
            u.in_mask.next = m.to_bits();
            u.in_corner.next = (c as u64).to_bits();
            u.in_zc.next = (p[0] as u64 & ((1 << 48) - 1)).to_bits();
            u.in_sx.next = (p[1] as u64 & ((1 << 48) - 1)).to_bits();
            u.in_sy.next = (p[2] as u64 & ((1 << 48) - 1)).to_bits();
        }
        clock(u, |u| u.clock.next = Clock { clk: true });
        clock(u, |u| u.clock.next = Clock { clk: false });
    }

    fn z(v: Bits<Z_BITS>) -> i64 {
        ((v.to_u64() << 11) as i64) >> 11
    }

    #[test]
    fn seed_worked_example_through_the_iterative_unit() {
        // Seed 000, 4×4: a mask whose anti-diagonal c + r = 2 is covered and lines 0 and 1
        // are empty, searched from the top-left: lines 0 (bit 3) and 1 (bits 7, 2) give 0,
        // line 2 gives 0842H, whose ends are (−0.375, +0.125) and (+0.125, −0.375), i.e.
        // (−3, +1) and (+1, −3) in 1/8 px. Plane z = 1000 + 3·dx − 5·dy (Q.12): depths
        // 1000 − 9 − 5 = 986 and 1000 + 3 + 15 = 1018.
        let mut u = MaskSearchIter::<16>::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        u.connect_all();
        u.rst.next = true;
        cycle_iter(&mut u, None);
        u.rst.next = false;
        assert!(u.ready.val() && !u.active.val());
        let plane = [1000 << 12, 3 << 12, -5 << 12];
        cycle_iter(&mut u, Some((0xFF73, 0, plane)));
        let mut seen = Vec::new();
        for _ in 0..3 {
            seen.push((
                u.line.val().to_u64(),
                u.search_mask.val().to_u64(),
                u.and_result.val().to_u64(),
                u.zero.val(),
                u.done.val(),
            ));
            cycle_iter(&mut u, None);
        }
        assert_eq!(
            seen,
            vec![
                (0, 0x0008, 0, true, false),
                (1, 0x0084, 0, true, false),
                (2, 0x0842, 0x0842, false, true)
            ]
        );
        assert!(!u.active.val() && u.ready.val());
        // The result shows BACK_LATENCY clocks after the done clock.
        for _ in 0..BACK_LATENCY - 1 {
            assert!(!u.out_valid.val());
            cycle_iter(&mut u, None);
        }
        assert!(u.out_valid.val() && u.out_hit.val());
        let f = |d: i32| (d as u64) & 0xF;
        let want = f(-3) | f(1) << 4 | f(1) << 8 | f(-3) << 12 | 1 << 16;
        assert_eq!(u.out_rom.val().to_u64(), want);
        assert_eq!(u.out_steps.val().to_u64(), 3);
        assert_eq!(
            [&u.out_z1, &u.out_z2, &u.out_zmin, &u.out_zmax].map(|s| z(s.val())),
            [986 << 12, 1018 << 12, 986 << 12, 1018 << 12]
        );
        cycle_iter(&mut u, None);
        assert!(!u.out_valid.val());
    }

    #[test]
    fn verilog_passes_yosys() {
        let u = MaskSearchIter::<16>::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        crate::mask_search::yosys_check("pixelproc_rtl_iter", u);
    }
}
