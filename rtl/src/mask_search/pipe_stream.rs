//! The pipelined mask search unit as an AXI4-Stream block (seed 000, JP2569952B2, Fig. 6):
//! [`MaskSearchPipe`] with a credit-counted [`ResultFifo`] on its result side.

use super::{check_stream, hit_bit, MaskSearchError, MaskSearchPipe, ResultFifo, BACK_LATENCY};
use super::{LINE_BITS, PB, WORD_BITS, Z_BITS};
use pixelproc_formats::abuffer::{MaskSize, SearchFamily};
use rust_hdl::prelude::*;

/// Slots of the pipelined unit's result FIFO for a pipeline of `lines` stages: the
/// pipeline's latency (`lines + BACK_LATENCY`) plus one edge into the FIFO, one to hand
/// the result over, and one for the credit that does not see the hand-over of its own
/// clock (see [`ResultFifo`]): full rate (one search per clock) while `m_tready` is high.
pub const fn pipe_fifo_depth(lines: usize) -> usize {
    lines + BACK_LATENCY + 3
}

/// The pipelined search unit with AXI4-Stream handshakes on both sides.
///
/// **Slave (input).** `s_tdata` as on
/// [`MaskSearchIterStream`](super::MaskSearchIterStream); accepted at a rising edge with
/// `s_tvalid && s_tready`, `s_tready = credit && !rst` (a FIFO slot is reserved for every
/// search in the pipeline, so the pipeline itself never stalls). `s_tready` is a function
/// of registers and `rst` only.
///
/// **Master (output).** `m_tdata` as on the iterative stream unit, handed over with
/// `m_tvalid && m_tready`, stable while `m_tvalid && !m_tready`, in input order, none lost
/// or repeated. With `m_tready` held high a search accepted at edge `E` is offered from
/// edge `E + latency + 1` (`latency` = 19 for 4×4, 27 for 8×8) and one search is taken
/// per clock.
#[derive(LogicBlock)]
pub struct MaskSearchPipeStream<const B: usize, const IW: usize, const OW: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: pipeline and FIFO empty; `s_tready` low while it is high.
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
    /// The search core.
    pub core: MaskSearchPipe<B>,
    /// The result FIFO.
    pub fifo: ResultFifo<OW>,
    k_hit: Constant<Bits<OW>>,
    l_ready: Signal<Local, Bit>,
    l_word: Signal<Local, Bits<OW>>,
}

impl<const B: usize, const IW: usize, const OW: usize> MaskSearchPipeStream<B, IW, OW> {
    /// The unit for `size` (`size.bits() == B`, `IW`, `OW` the stream widths for `B`) and a
    /// search family.
    pub fn new(size: MaskSize, family: SearchFamily) -> Result<Self, MaskSearchError> {
        check_stream(B, IW, OW)?;
        let core = MaskSearchPipe::new(size, family)?;
        let depth = pipe_fifo_depth(core.stages.len());
        Ok(MaskSearchPipeStream {
            clock: Default::default(),
            rst: Default::default(),
            s_tvalid: Default::default(),
            s_tready: Default::default(),
            s_tdata: Default::default(),
            m_tvalid: Default::default(),
            m_tready: Default::default(),
            m_tdata: Default::default(),
            core,
            fifo: ResultFifo::new(depth),
            k_hit: Constant::new(hit_bit()),
            l_ready: Default::default(),
            l_word: Default::default(),
        })
    }

    /// Edges from accepting a search to its result on the core's ports.
    pub fn latency(&self) -> usize {
        self.core.latency()
    }
}

stream_unit_logic! {
    MaskSearchPipeStream,
    #[hdl_gen]
    fn update(&mut self) {
        self.core.clock.next = self.clock.val();
        self.core.rst.next = self.rst.val();
        self.fifo.clock.next = self.clock.val();
        self.fifo.rst.next = self.rst.val();
        // Input side: a search enters the pipeline exactly on a handshake.
        self.l_ready.next = self.fifo.credit.val() & (!self.rst.val());
        self.s_tready.next = self.l_ready.val();
        self.core.in_valid.next = self.s_tvalid.val() & self.l_ready.val();
        self.fifo.take.next = self.s_tvalid.val() & self.l_ready.val();
        // Output side (`stream_unit_logic!` then connects the words).
        self.fifo.m_tready.next = self.m_tready.val();
        self.m_tvalid.next = self.fifo.m_tvalid.val();
        self.m_tdata.next = self.fifo.m_tdata.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::iter_stream::tests::seed_word;
    use crate::mask_search::{cycle, MaskSearchPipeStream4x4, SEED_WORD};

    #[test]
    fn full_rate_with_a_ready_consumer_and_none_lost_when_it_stalls() {
        let mut u = MaskSearchPipeStream4x4::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        u.connect_all();
        u.rst.next = true;
        cycle!(u);
        u.rst.next = false;
        assert!(simulate(&mut u, 200));
        u.s_tdata.next = seed_word();
        u.m_tready.next = true;
        let (mut sent, mut got) = (0, 0);
        // 100 clocks of input, consumer always ready: one search per clock.
        for t in 0..200 {
            u.s_tvalid.next = t < 100;
            assert!(u.s_tready.val());
            sent += (t < 100) as usize;
            if u.m_tvalid.val() {
                assert_eq!(u.m_tdata.val().get_bits::<17>(212).to_u64(), SEED_WORD);
                got += 1;
            }
            cycle!(u);
        }
        assert_eq!((sent, got), (100, 100));
        // Consumer stalled: exactly the FIFO depth is accepted, then all of it comes out.
        u.m_tready.next = false;
        u.s_tvalid.next = true;
        let mut acc = 0;
        for _ in 0..100 {
            acc += u.s_tready.val() as usize;
            cycle!(u);
        }
        assert_eq!(acc, pipe_fifo_depth(7));
        u.s_tvalid.next = false;
        u.m_tready.next = true;
        let mut out = 0;
        for _ in 0..100 {
            out += u.m_tvalid.val() as usize;
            cycle!(u);
        }
        assert_eq!(out, acc);
    }

    #[test]
    fn verilog_passes_yosys() {
        let u = MaskSearchPipeStream4x4::new(MaskSize::S4X4, SearchFamily::DIAGONAL).unwrap();
        crate::mask_search::yosys_check("pixelproc_rtl_pipe_stream", u);
    }
}
