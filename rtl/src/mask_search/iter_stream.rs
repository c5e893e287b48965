//! The iterative mask search unit as an AXI4-Stream block (seed 000, JP2569952B2, Fig. 6):
//! [`MaskSearchIter`] with a credit-counted [`ResultFifo`] on its result side.

use super::{check_stream, hit_bit, MaskSearchError, MaskSearchIter, ResultFifo};
use super::{BACK_LATENCY, LINE_BITS, PB, WORD_BITS, Z_BITS};
use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use rust_hdl::prelude::*;

/// Slots of the iterative unit's result FIFO: a search accepted at edge `E` that takes one
/// line is done in the clock after `E`, its result enters the back end at `E + 1`, shows
/// after `E + 1 + BACK_LATENCY − 1`, enters the FIFO one edge later and is handed over the
/// edge after that; plus one for the credit that does not see the hand-over of its own
/// clock (see [`ResultFifo`]).
pub const ITER_FIFO_DEPTH: usize = BACK_LATENCY + 3;

/// The iterative search unit with AXI4-Stream handshakes on both sides.
///
/// **Slave (input).** `s_tdata` is the search ([`stream_in_bits`](super::stream_in_bits),
/// LSB first: `zc[48]`, `sx[48]`, `sy[48]`, `corner[2]`, `mask[B]`). It is accepted at a
/// rising edge with `s_tvalid && s_tready`. `s_tready = ready && credit && !rst`: the core
/// is idle or finishing its search in this clock, and a FIFO slot is reserved for the
/// result. `s_tready` is a function of registers and `rst` only.
///
/// **Master (output).** `m_tdata` is the result
/// ([`stream_out_bits`](super::stream_out_bits), LSB first: `z1`, `z2`, `zmin`, `zmax`
/// (53 each), `rom[17]`, `steps[5]`, `hit`, `and[B]`), handed over at a rising edge with
/// `m_tvalid && m_tready`. While `m_tvalid && !m_tready`, `m_tvalid` and `m_tdata` stay as
/// they are. Results leave in the order the searches were accepted; none is lost or
/// repeated whatever `m_tready` does (the credits bound the results in flight by the FIFO
/// depth, [`ITER_FIFO_DEPTH`]).
///
/// The core's step ports are passed through for observation (the golden
/// `SearchUnit::step` of every clock, as on [`MaskSearchIter`]).
#[derive(LogicBlock)]
pub struct MaskSearchIterStream<const B: usize, const IW: usize, const OW: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: idle, FIFO empty; `s_tready` low while it is high.
    pub rst: Signal<In, Bit>,
    /// AXI4-Stream slave: a search is offered.
    pub s_tvalid: Signal<In, Bit>,
    /// AXI4-Stream slave: the unit takes it at this edge.
    pub s_tready: Signal<Out, Bit>,
    /// AXI4-Stream slave: the search word.
    pub s_tdata: Signal<In, Bits<IW>>,
    /// AXI4-Stream master: a result is offered.
    pub m_tvalid: Signal<Out, Bit>,
    /// AXI4-Stream master: the consumer takes it at this edge.
    pub m_tready: Signal<In, Bit>,
    /// AXI4-Stream master: the result word.
    pub m_tdata: Signal<Out, Bits<OW>>,
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
    /// Step: the mover fires.
    pub moved: Signal<Out, Bit>,
    /// Step: first hit.
    pub hit: Signal<Out, Bit>,
    /// Step: the search ends this clock.
    pub done: Signal<Out, Bit>,
    /// The search core.
    pub core: MaskSearchIter<B>,
    /// The result FIFO.
    pub fifo: ResultFifo<OW>,
    k_hit: Constant<Bits<OW>>,
    l_ready: Signal<Local, Bit>,
    l_word: Signal<Local, Bits<OW>>,
}

impl<const B: usize, const IW: usize, const OW: usize> MaskSearchIterStream<B, IW, OW> {
    /// The unit for `size` (`size.bits() == B`, `IW`, `OW` the stream widths for `B`) and a
    /// search family (the seed's is [`SearchFamily::DIAGONAL`]).
    pub fn new(size: MaskSize, family: SearchFamily) -> Result<Self, MaskSearchError> {
        check_stream(B, IW, OW)?;
        Ok(MaskSearchIterStream {
            clock: Default::default(),
            rst: Default::default(),
            s_tvalid: Default::default(),
            s_tready: Default::default(),
            s_tdata: Default::default(),
            m_tvalid: Default::default(),
            m_tready: Default::default(),
            m_tdata: Default::default(),
            active: Default::default(),
            line: Default::default(),
            search_mask: Default::default(),
            and_result: Default::default(),
            zero: Default::default(),
            moved: Default::default(),
            hit: Default::default(),
            done: Default::default(),
            core: MaskSearchIter::new(size, family)?,
            fifo: ResultFifo::new(ITER_FIFO_DEPTH),
            k_hit: Constant::new(hit_bit()),
            l_ready: Default::default(),
            l_word: Default::default(),
        })
    }
}

stream_unit_logic! {
    MaskSearchIterStream,
    #[hdl_gen]
    fn update(&mut self) {
        self.core.clock.next = self.clock.val();
        self.core.rst.next = self.rst.val();
        self.fifo.clock.next = self.clock.val();
        self.fifo.rst.next = self.rst.val();
        // Input side: the core starts exactly on a handshake. It gates its start with its
        // own `ready`, so `in_valid` does not include it: no path from the core's outputs
        // back into its inputs (which Verilator would flag as a combinational loop, the
        // core's kernel being one block).
        self.l_ready.next = (self.core.ready.val() & self.fifo.credit.val()) & (!self.rst.val());
        self.s_tready.next = self.l_ready.val();
        self.core.in_valid.next =
            (self.s_tvalid.val() & self.fifo.credit.val()) & (!self.rst.val());
        self.fifo.take.next = self.s_tvalid.val() & self.l_ready.val();
        // Output side (`stream_unit_logic!` then connects the words).
        self.fifo.m_tready.next = self.m_tready.val();
        self.m_tvalid.next = self.fifo.m_tvalid.val();
        self.m_tdata.next = self.fifo.m_tdata.val();
        // Step ports.
        self.active.next = self.core.active.val();
        self.line.next = self.core.line.val();
        self.search_mask.next = self.core.search_mask.val();
        self.and_result.next = self.core.and_result.val();
        self.zero.next = self.core.zero.val();
        self.moved.next = self.core.moved.val();
        self.hit.next = self.core.hit.val();
        self.done.next = self.core.done.val();
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mask_search::{cycle, depth_of, plane_bits, MaskSearchIterStream4x4};
    use crate::mask_search::{SEED_DEPTHS, SEED_PLANE, SEED_WORD};

    /// The seed's worked example as a search word.
    pub(crate) fn seed_word<const IW: usize>() -> Bits<IW> {
        let f = |v: i64, at: usize| bit_cast::<IW, PB>(plane_bits(v)) << (at as u64);
        f(SEED_PLANE[0], 0)
            | f(SEED_PLANE[1], 48)
            | f(SEED_PLANE[2], 96)
            | (bit_cast::<IW, 16>(0xFF73u64.to_bits()) << 146u64)
    }

    #[test]
    fn seed_example_waits_for_the_consumer() {
        let mut u = MaskSearchIterStream4x4::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        u.connect_all();
        u.rst.next = true;
        cycle!(u);
        u.rst.next = false;
        assert!(simulate(&mut u, 200));
        assert!(u.s_tready.val() && !u.m_tvalid.val());
        // Two copies of the search back to back, the consumer not ready.
        u.s_tvalid.next = true;
        u.s_tdata.next = seed_word();
        let mut accepted = 0;
        let mut clocks = 0;
        while accepted < 2 {
            accepted += u.s_tready.val() as usize;
            cycle!(u);
            clocks += 1;
        }
        assert_eq!(
            clocks, 4,
            "3 lines each, the second accepted in the first's last clock"
        );
        u.s_tvalid.next = false;
        for _ in 0..20 {
            cycle!(u);
        }
        // Held while not taken, then handed over once each.
        let mut seen = 0;
        for k in 0..6 {
            assert!(u.m_tvalid.val());
            u.m_tready.next = k % 3 == 2;
            assert!(simulate(&mut u, 200));
            let w = u.m_tdata.val();
            assert_eq!(w.get_bits::<17>(212).to_u64(), SEED_WORD);
            assert_eq!(w.get_bits::<5>(229).to_u64(), 3);
            assert!(w.get_bit(234));
            assert_eq!(w.get_bits::<16>(235).to_u64(), 0x0842);
            assert_eq!(depth_of(w.get_bits::<53>(106)), SEED_DEPTHS[0]);
            assert_eq!(depth_of(w.get_bits::<53>(159)), SEED_DEPTHS[1]);
            seen += u.m_tready.val() as usize;
            cycle!(u);
        }
        assert_eq!(seen, 2);
        assert!(!u.m_tvalid.val());
    }

    #[test]
    fn credits_stop_the_input_when_the_consumer_stalls() {
        let mut u = MaskSearchIterStream4x4::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        u.connect_all();
        u.rst.next = true;
        cycle!(u);
        u.rst.next = false;
        assert!(simulate(&mut u, 200));
        u.s_tvalid.next = true;
        u.s_tdata.next = seed_word();
        let mut accepted = 0;
        for _ in 0..200 {
            accepted += u.s_tready.val() as usize;
            cycle!(u);
        }
        assert_eq!(accepted, ITER_FIFO_DEPTH);
    }

    #[test]
    fn verilog_passes_yosys() {
        let u = MaskSearchIterStream4x4::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        crate::mask_search::yosys_check("pixelproc_rtl_iter_stream", u);
    }
}
