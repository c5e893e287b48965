//! The output side of the stream search units: a result FIFO with a credit counter, so a
//! fixed- or variable-latency search core gets AXI4-Stream back-pressure without a stall
//! signal through its pipeline.

use rust_hdl::prelude::*;

/// Width of the credit counter (depths up to 63).
const COUNT_BITS: usize = 6;

/// Result FIFO with credits, `depth` slots of `W` bits.
///
/// **Credits.** `count` is the number of searches accepted on the input side (`take`) and
/// not yet handed over on the output side (`m_tvalid && m_tready`): those in the core plus
/// those in the FIFO. `credit = count < depth`; the unit accepts a search only with a
/// credit, so every result the core produces finds a free slot (the FIFO never
/// overflows, whatever `m_tready` does). `credit` is a function of registers only (no
/// path from `m_tready`). With `depth = latency + 3` (accept edge to core result, one
/// edge into the FIFO, one to hand it over, one because `credit` does not see the
/// hand-over of the same clock) a core that takes one search per clock runs at full rate
/// while `m_tready` stays high.
///
/// **FIFO.** `depth` registers with one-hot write and read pointers (rotating rings) and a
/// full bit per slot: `m_tvalid` is the read slot's full bit, `m_tdata` its register, both
/// stable until the hand-over. A result (`i_valid`, `i_data`) is written at the next edge.
#[derive(LogicBlock)]
pub struct ResultFifo<const W: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset: empty, no credit used.
    pub rst: Signal<In, Bit>,
    /// A search is accepted by the core at this edge (uses a credit).
    pub take: Signal<In, Bit>,
    /// A credit is free: the core may accept a search.
    pub credit: Signal<Out, Bit>,
    /// A result from the core, written at this edge.
    pub i_valid: Signal<In, Bit>,
    /// The result word.
    pub i_data: Signal<In, Bits<W>>,
    /// AXI4-Stream master: a result is offered.
    pub m_tvalid: Signal<Out, Bit>,
    /// AXI4-Stream master: the consumer takes it at this edge.
    pub m_tready: Signal<In, Bit>,
    /// AXI4-Stream master: the result word.
    pub m_tdata: Signal<Out, Bits<W>>,
    slots: Vec<DFF<Bits<W>>>,
    full: Vec<DFF<Bit>>,
    wsel: Vec<DFF<Bit>>,
    rsel: Vec<DFF<Bit>>,
    count: DFF<Bits<COUNT_BITS>>,
    k_depth: Constant<Bits<COUNT_BITS>>,
    k_one: Constant<Bits<COUNT_BITS>>,
    k_zero: Constant<Bits<COUNT_BITS>>,
    k_zero_w: Constant<Bits<W>>,
    pop: Signal<Local, Bit>,
    l_valid: Signal<Local, Bit>,
    l_data: Signal<Local, Bits<W>>,
    l_wlast: Signal<Local, Bit>,
    l_rlast: Signal<Local, Bit>,
}

impl<const W: usize> ResultFifo<W> {
    /// Largest depth the credit counter supports.
    pub const MAX_DEPTH: usize = (1 << COUNT_BITS) - 1;

    /// A FIFO of `depth` slots (clamped to `2..=MAX_DEPTH`).
    pub fn new(depth: usize) -> Self {
        let depth = depth.clamp(2, Self::MAX_DEPTH);
        ResultFifo {
            clock: Default::default(),
            rst: Default::default(),
            take: Default::default(),
            credit: Default::default(),
            i_valid: Default::default(),
            i_data: Default::default(),
            m_tvalid: Default::default(),
            m_tready: Default::default(),
            m_tdata: Default::default(),
            slots: super::dff_line(depth),
            full: super::dff_line(depth),
            wsel: super::dff_line(depth),
            rsel: super::dff_line(depth),
            count: Default::default(),
            k_depth: Constant::new((depth as u64).to_bits()),
            k_one: Constant::new(1u64.to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
            k_zero_w: Constant::new(0u64.to_bits()),
            pop: Default::default(),
            l_valid: Default::default(),
            l_data: Default::default(),
            l_wlast: Default::default(),
            l_rlast: Default::default(),
        }
    }

    /// Number of slots.
    pub fn depth(&self) -> usize {
        self.slots.len()
    }
}

impl<const W: usize> Logic for ResultFifo<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, count);
        for i in 0..self.slots.len() {
            self.slots[i].clock.next = self.clock.val();
            self.slots[i].d.next = self.slots[i].q.val();
            self.full[i].clock.next = self.clock.val();
            self.full[i].d.next = self.full[i].q.val();
            self.wsel[i].clock.next = self.clock.val();
            self.wsel[i].d.next = self.wsel[i].q.val();
            self.rsel[i].clock.next = self.clock.val();
            self.rsel[i].d.next = self.rsel[i].q.val();
        }
        // The read slot (one-hot), and the last pointer bits for the ring rotation.
        self.l_valid.next = false;
        self.l_data.next = self.k_zero_w.val();
        self.l_wlast.next = false;
        self.l_rlast.next = false;
        for i in 0..self.slots.len() {
            if self.rsel[i].q.val() {
                self.l_valid.next = self.full[i].q.val();
                self.l_data.next = self.slots[i].q.val();
            }
            self.l_wlast.next = self.wsel[i].q.val();
            self.l_rlast.next = self.rsel[i].q.val();
        }
        self.m_tvalid.next = self.l_valid.val();
        self.m_tdata.next = self.l_data.val();
        self.pop.next = self.l_valid.val() & self.m_tready.val();
        self.credit.next = self.count.q.val() < self.k_depth.val();
        // Credits.
        if self.take.val() & (!self.pop.val()) {
            self.count.d.next = self.count.q.val() + self.k_one.val();
        }
        if self.pop.val() & (!self.take.val()) {
            self.count.d.next = self.count.q.val() - self.k_one.val();
        }
        // Write: the write slot, then the pointer moves on.
        if self.i_valid.val() {
            for i in 0..self.slots.len() {
                if self.wsel[i].q.val() {
                    self.slots[i].d.next = self.i_data.val();
                    self.full[i].d.next = true;
                }
            }
            self.wsel[0].d.next = self.l_wlast.val();
            for i in 1..self.slots.len() {
                self.wsel[i].d.next = self.wsel[i - 1].q.val();
            }
        }
        // Read: the slot is freed, the pointer moves on (a slot is never written and read
        // in the same clock: a written slot was empty, a read one full).
        if self.pop.val() {
            for i in 0..self.slots.len() {
                if self.rsel[i].q.val() {
                    self.full[i].d.next = false;
                }
            }
            self.rsel[0].d.next = self.l_rlast.val();
            for i in 1..self.slots.len() {
                self.rsel[i].d.next = self.rsel[i - 1].q.val();
            }
        }
        if self.rst.val() {
            self.count.d.next = self.k_zero.val();
            for i in 0..self.slots.len() {
                self.full[i].d.next = false;
                self.wsel[i].d.next = false;
                self.rsel[i].d.next = false;
            }
            self.wsel[0].d.next = true;
            self.rsel[0].d.next = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::cycle;

    /// Writes results on a random pattern while reading on another, taking a credit per
    /// write as a core with no latency would; every value comes out once, in order.
    #[test]
    fn random_traffic_keeps_order_and_never_overflows() {
        let mut u = ResultFifo::<20>::new(5);
        u.connect_all();
        u.rst.next = true;
        cycle!(u);
        u.rst.next = false;
        let mut rng = 0x1234_5678_9abc_def1u64;
        let mut next = || crate::xorshift64(&mut rng);
        let (mut sent, mut got, mut held) = (0u64, 0u64, None::<u64>);
        for _ in 0..5000 {
            let r = next();
            let write = r & 1 == 1 && u.credit.val();
            u.take.next = write;
            u.i_valid.next = write;
            u.i_data.next = sent.to_bits();
            u.m_tready.next = r & 6 != 0;
            if let Some(h) = held {
                // Data stable while valid and not taken.
                assert!(u.m_tvalid.val());
                assert_eq!(u.m_tdata.val().to_u64(), h);
            }
            held = None;
            if u.m_tvalid.val() {
                if r & 6 != 0 {
                    assert_eq!(u.m_tdata.val().to_u64(), got);
                    got += 1;
                } else {
                    held = Some(u.m_tdata.val().to_u64());
                }
            }
            if write {
                sent += 1;
            }
            cycle!(u);
        }
        assert!(got > 1000 && sent - got <= 5, "sent {sent} got {got}");
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check("pixelproc_rtl_result_fifo", ResultFifo::<20>::new(5));
    }
}
