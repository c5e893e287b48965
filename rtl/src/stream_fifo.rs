//! A first-word-fall-through stream FIFO on one RAM with a combinational read port
//! ([`crate::lut_ram::SlicedLutRam`]) and its own head register, with valid/ready handshakes on
//! both sides (AXI4-Stream rules: a beat moves on a rising edge where
//! `valid` and `ready` are both 1; `out_data` is stable while `out_valid` and not
//! `out_ready`).
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clock` | in | 1 | rising edge |
//! | `rst` | in | 1 | synchronous: empties the FIFO; `in_ready` is 0 while it is 1 |
//! | `in_valid`, `in_data`, `in_ready` | in, in, out | 1, `W`, 1 | write side |
//! | `out_valid`, `out_data`, `out_ready` | out, out, in | 1, `W`, 1 | read side |
//! | `level` | out | `A1` | entries held, the presented one included (0 ..= 2^`A`) |
//! | `fetching`, `next_tag` | out, out | 1, [`TAG_BITS`] | the head register loads the RAM's entry at `rd` at the next edge (`fetch` below); `next_tag` is that entry's low bits |
//!
//! # Behaviour, one rising edge (the golden twin is `pixelproc_sim::core_model::Fifo`)
//!
//! Registers: write pointer `wr`, read pointer `rd` (both `A + 1` bits: an `A`-bit
//! address and a wrap bit), the head register `head` (`out_data`) and `dv` (`head` holds
//! the head entry). With `pop = dv ∧ out_ready`, `fetch = (wr ≠ rd) ∧ (¬dv ∨ pop)`,
//! `push = in_valid ∧ in_ready`:
//! - the RAM reads address `rd` (always: the address comes from registers equal to the
//!   pointer, one copy per RAM slice), and `head := mem[rd]` if `fetch`, else `head`
//!   holds (a clock enable);
//! - `rd += fetch`, `dv := fetch ∨ (dv ∧ ¬pop)`, `wr += push`, `mem[wr] := in_data` if
//!   `push` (or at every edge, pushed or not: see "Writing at every edge");
//! - `level = wr − rd + dv`, `in_ready = ¬rst ∧ level ≠ 2^A`;
//! - with `rst`, every register but `head` is cleared instead (the FIFO is empty after
//!   the edge). Inside, the push that advances `wr` and writes the RAM is `in_valid ∧
//!   level ≠ 2^A`, without `rst`: `rst` overrides the pointer, and a slot written under
//!   `rst` holds no entry, so on the ports this is the push above.
//!
//! `level` is read from a register, `lv`, kept equal to `wr − rd + dv` after every edge:
//! `+1` on a push without a pop, `−1` on a pop without a push, unchanged otherwise
//! (`level' = level + push − pop`), `0` after `rst`. `level ≠ 2^A` is read from another,
//! `full`, kept equal to `level = 2^A`: `full := lv = 2^A − 1` on a push without a pop,
//! `0` on a pop without a push, unchanged otherwise. So no pointer arithmetic sits
//! between the pointers and the write enable, nor between the pointers and `full` (the
//! difference `wr − rd + dv` in front of `full`'s compare was the core's critical path at
//! two placement seeds, `docs/fpga.md`). Likewise `wr ≠ rd` is read from a register,
//! `ne`, kept equal to it after every edge: `1` after a push, `0` after a fetch without a
//! push from `wr = rd + 1` (read as `lv − dv = 1` from the two registers, not from the
//! pointers), unchanged otherwise (and `0` after `rst`); so the fetch decision, the head
//! register's clock enable, reads a flip-flop instead of comparing the pointers.
//!
//! The RAM is a [`crate::lut_ram::SlicedLutRam`]: cut by data bits into
//! [`StreamFifo::with_slices`] slices (one by default; 8 for the core's 261-bit command
//! FIFO), each with its own registered copy of the read and write addresses, loaded with
//! the pointers' next values. A copy drives the address pins of its slice only, instead
//! of one pointer register driving every LUT RAM primitive of the word.
//!
//! **Writing at every edge** ([`StreamFifo::writing_every_edge`], the core's command
//! FIFO; otherwise the RAM is written on a push). The RAM's write enable is constant 1:
//! `mem[wr]` takes `in_data` at every edge, and only `wr`'s increment says whether the
//! beat was taken. The slot at `wr` holds no entry the FIFO still owes: the entries are the slots `rd ..
//! wr − 1` (and the head register), and `wr` is among them only when `wr − rd = 2^A`,
//! which needs `2^A` entries in the RAM with `dv = 0`; but `dv = 0` with `wr ≠ rd` lasts
//! one clock (the fetch), so the RAM never fills behind an empty head register (and if it
//! did, that edge's fetch reads the slot before the write lands). A slot written without
//! a push is written again by the push that makes it an entry. So no flag or reset sits
//! in front of the write enables of the RAM's LUT RAM primitives (130 of them in the
//! core's command FIFO): `full` and `rst` into those enables, through the push decision,
//! were the core's worst paths at N = 8 and N = 32 (`docs/fpga.md`).
//!
//! A beat written at edge `E` is presented (`out_valid`) from edge `E + 1` on if the FIFO
//! was empty; in steady state one beat moves on each side on every edge. The head entry
//! stays in the RAM until popped (it counts in `level`), so a push never writes a fetched
//! slot; written at every edge, the RAM may overwrite that slot while the FIFO is full,
//! which no read sees (the head register holds the entry).
//!
//! Earlier the head register was the RAM's own registered read port, which had to re-read
//! `rd − 1` to hold: the choice of address then depended on `out_ready`, and that choice
//! fanned out to the address of every RAM slice (the core's critical path, `docs/fpga.md`).
//! The pointer copies and `ne` came next, for the same path. The behaviour on the ports,
//! cycle for cycle, is the same.

use crate::lut_ram::SlicedLutRam;
use rust_hdl::prelude::*;

/// Width of [`StreamFifo::next_tag`]: the low bits of the entry a fetch loads. They are
/// read from a RAM of their own (`tag_ram`, written with the same data bits at the same
/// address as the FIFO's RAM): a second reader of the FIFO's RAM beside the head register
/// led Yosys 0.23's `memory_dff` to leave most of the head register's bits without a
/// driver in generic synthesis (`synth`; `synth_ecp5` was not affected).
pub const TAG_BITS: usize = 2;
// (Two, not one: rust-hdl declares a one-bit vector without a range, and a slice or an
// index of it is not Verilog.)

/// The FIFO: `W` data bits, `2^A` entries, `A1 = A + 1` (pointer width). Each pointer is
/// held as an `A`-bit address and a wrap bit, so the RAM addresses need no truncation.
#[derive(LogicBlock)]
pub struct StreamFifo<const W: usize, const A: usize, const A1: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// Write side: a beat is offered.
    pub in_valid: Signal<In, Bit>,
    /// Write side: the beat.
    pub in_data: Signal<In, Bits<W>>,
    /// Write side: the FIFO takes the beat at the next edge if `in_valid`.
    pub in_ready: Signal<Out, Bit>,
    /// Read side: `out_data` holds the head entry.
    pub out_valid: Signal<Out, Bit>,
    /// Read side: the head entry.
    pub out_data: Signal<Out, Bits<W>>,
    /// Read side: the consumer takes the head entry at the next edge if `out_valid`.
    pub out_ready: Signal<In, Bit>,
    /// Entries held.
    pub level: Signal<Out, Bits<A1>>,
    /// Read side: the head register loads the RAM's entry at the read pointer at the next
    /// edge (a *fetch*: the
    /// RAM holds an entry and the head register is empty or being popped). A consumer
    /// that keeps its own registers about the head entry loads them on the same edge.
    pub fetching: Signal<Out, Bit>,
    /// Read side: the low [`TAG_BITS`] bits of the entry a fetch loads into the head
    /// register (the RAM's read at the read pointer), for a consumer that decodes the
    /// entry a clock ahead (the core's command beats keep their frame flag there).
    pub next_tag: Signal<Out, Bits<TAG_BITS>>,
    ram: SlicedLutRam<Bits<W>, A>,
    /// A copy of every entry's low [`TAG_BITS`] bits, written and read with `ram`, for
    /// `next_tag` (see [`TAG_BITS`]).
    tag_ram: SlicedLutRam<Bits<TAG_BITS>, A>,
    head: DFF<Bits<W>>,
    wa: DFF<Bits<A>>,
    ww: DFF<Bit>,
    ra: DFF<Bits<A>>,
    rw: DFF<Bit>,
    dv: DFF<Bit>,
    full: DFF<Bit>,
    ne: DFF<Bit>,
    lv: DFF<Bits<A1>>,
    l_pop: Signal<Local, Bit>,
    l_fetch: Signal<Local, Bit>,
    l_push: Signal<Local, Bit>,
    l_ra_inc: Signal<Local, Bits<A>>,
    l_ra_next: Signal<Local, Bits<A>>,
    l_wa_next: Signal<Local, Bits<A>>,
    l_one: Signal<Local, Bit>,
    k_one: Constant<Bits<A1>>,
    k_two: Constant<Bits<A1>>,
    k_zero: Constant<Bits<A1>>,
    k_almost: Constant<Bits<A1>>,
    k_one_a: Constant<Bits<A>>,
    k_zero_a: Constant<Bits<A>>,
    k_last_a: Constant<Bits<A>>,
    /// The RAM is written at every edge ([`StreamFifo::writing_every_edge`]).
    k_every_edge: Constant<Bit>,
}

impl<const W: usize, const A: usize, const A1: usize> Default for StreamFifo<W, A, A1> {
    fn default() -> Self {
        Self::with_slices(1)
    }
}

impl<const W: usize, const A: usize, const A1: usize> StreamFifo<W, A, A1> {
    /// A FIFO whose RAM is cut into `slices` slices by data bits, each with its own copy
    /// of the pointers ([`SlicedLutRam`]); `Default` is one slice.
    pub fn with_slices(slices: usize) -> Self {
        assert!(
            A1 == A + 1 && A >= 1 && A < 16 && W >= TAG_BITS,
            "StreamFifo needs A1 = A + 1 and at least TAG_BITS data bits"
        );
        StreamFifo {
            clock: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_data: Default::default(),
            in_ready: Default::default(),
            out_valid: Default::default(),
            out_data: Default::default(),
            out_ready: Default::default(),
            level: Default::default(),
            fetching: Default::default(),
            next_tag: Default::default(),
            ram: SlicedLutRam::new(slices),
            tag_ram: SlicedLutRam::new(1),
            head: Default::default(),
            wa: Default::default(),
            ww: Default::default(),
            ra: Default::default(),
            rw: Default::default(),
            dv: Default::default(),
            full: Default::default(),
            ne: Default::default(),
            lv: Default::default(),
            l_pop: Default::default(),
            l_fetch: Default::default(),
            l_push: Default::default(),
            l_ra_inc: Default::default(),
            l_ra_next: Default::default(),
            l_wa_next: Default::default(),
            l_one: Default::default(),
            k_one: Constant::new(1u64.to_bits()),
            k_two: Constant::new(2u64.to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
            k_almost: Constant::new(((1u64 << A) - 1).to_bits()),
            k_one_a: Constant::new(1u64.to_bits()),
            k_zero_a: Constant::new(0u64.to_bits()),
            k_last_a: Constant::new(((1u64 << A) - 1).to_bits()),
            k_every_edge: Constant::new(false),
        }
    }

    /// The same FIFO with its RAM written at every edge (see "Writing at every edge"):
    /// for data from ports, every bit of which changes. (A data bit that is constant, as
    /// in a word with spare bits, makes a RAM column that is written with a constant at
    /// every edge; Yosys 0.23 then removes the column and leaves its read bit undriven.)
    pub fn writing_every_edge(mut self) -> Self {
        self.k_every_edge = Constant::new(true);
        self
    }

    /// Number of entries.
    pub const DEPTH: usize = 1 << A;

    /// The write pointer, read pointer (`wrap << A | address`) and head-valid registers
    /// (for testbenches).
    pub fn probe(&self) -> (u32, u32, bool) {
        let p = |a: &DFF<Bits<A>>, w: &DFF<Bit>| a.q.val().index() as u32 | (w.q.val() as u32) << A;
        (
            p(&self.wa, &self.ww),
            p(&self.ra, &self.rw),
            self.dv.q.val(),
        )
    }
}

impl<const W: usize, const A: usize, const A1: usize> Logic for StreamFifo<W, A, A1> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, head, wa, ww, ra, rw, dv, full, ne, lv);
        self.ram.clock.next = self.clock.val();
        self.tag_ram.clock.next = self.clock.val();
        self.level.next = self.lv.q.val();
        self.in_ready.next = !self.full.q.val() & !self.rst.val();
        self.l_pop.next = self.dv.q.val() & self.out_ready.val();
        self.l_fetch.next = self.ne.q.val() & (!self.dv.q.val() | self.l_pop.val());
        // `rst` is left out of the push: its block at the end sets every register a push
        // changes, and a RAM write under `rst` lands in a slot that holds no entry. So
        // `rst` reaches the pointers and flags as their last select only, not through the
        // push into the write enables and the address copies' increments (the harness's
        // reset → the push → the write-address copy was the core's worst path at N = 32,
        // `docs/fpga.md`).
        self.l_push.next = self.in_valid.val() & !self.full.q.val();
        if self.l_push.val() & !self.l_pop.val() {
            self.full.d.next = self.lv.q.val() == self.k_almost.val();
            self.lv.d.next = self.lv.q.val() + self.k_one.val();
        }
        if !self.l_push.val() & self.l_pop.val() {
            self.full.d.next = false;
            self.lv.d.next = self.lv.q.val() - self.k_one.val();
        }
        // Read side: the RAM's address registers load the pointer's next value, so
        // they read `mem[rd]` as the pointer register does.
        self.l_ra_inc.next = self.ra.q.val() + self.k_one_a.val();
        self.l_ra_next.next = self.ra.q.val();
        if self.l_fetch.val() {
            self.head.d.next = self.ram.read_data.val();
            self.l_ra_next.next = self.l_ra_inc.val();
            if self.ra.q.val() == self.k_last_a.val() {
                self.rw.d.next = !self.rw.q.val();
            }
        }
        self.dv.d.next = self.l_fetch.val() | (self.dv.q.val() & !self.l_pop.val());
        self.out_valid.next = self.dv.q.val();
        self.out_data.next = self.head.q.val();
        self.fetching.next = self.l_fetch.val();
        self.next_tag.next = self.tag_ram.read_data.val();
        // `ne = (wr != rd)`: a push leaves an entry behind the read pointer; a fetch
        // without a push empties the RAM part iff it held one entry, `wr - rd = 1`, read
        // from registers: `wr - rd = lv - dv` (`lv` is `wr - rd + dv` after every edge),
        // so `wr - rd = 1` is `lv = 2` with `dv`, `lv = 1` without: two compares with
        // constants instead of an increment of the read pointer and a compare with the
        // write pointer (that carry chain in front of `ne` was the core's critical path at
        // every placement seed of N = 8 with shadows, `docs/fpga.md`).
        self.l_one.next = self.lv.q.val() == self.k_one.val();
        if self.dv.q.val() {
            self.l_one.next = self.lv.q.val() == self.k_two.val();
        }
        if self.l_fetch.val() & !self.l_push.val() & self.l_one.val() {
            self.ne.d.next = false;
        }
        if self.l_push.val() {
            self.ne.d.next = true;
        }
        // Write side.
        self.ram.write_data.next = self.in_data.val();
        self.ram.write_enable.next = self.l_push.val() | self.k_every_edge.val();
        self.l_wa_next.next = self.wa.q.val();
        if self.l_push.val() {
            self.l_wa_next.next = self.wa.q.val() + self.k_one_a.val();
            if self.wa.q.val() == self.k_last_a.val() {
                self.ww.d.next = !self.ww.q.val();
            }
        }
        if self.rst.val() {
            self.l_wa_next.next = self.k_zero_a.val();
            self.ww.d.next = false;
            self.l_ra_next.next = self.k_zero_a.val();
            self.rw.d.next = false;
            self.dv.d.next = false;
            self.full.d.next = false;
            self.ne.d.next = false;
            self.lv.d.next = self.k_zero.val();
        }
        self.wa.d.next = self.l_wa_next.val();
        self.ra.d.next = self.l_ra_next.val();
        self.ram.next_write_address.next = self.l_wa_next.val();
        self.ram.next_read_address.next = self.l_ra_next.val();
        self.tag_ram.write_data.next = self.in_data.val().get_bits::<TAG_BITS>(0);
        self.tag_ram.write_enable.next = self.l_push.val() | self.k_every_edge.val();
        self.tag_ram.next_write_address.next = self.l_wa_next.val();
        self.tag_ram.next_read_address.next = self.l_ra_next.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::VecDeque;

    /// The data of beat `n`: a hash, so that every slice of the RAM sees its own bits.
    fn beat(n: u64, bits: usize) -> u64 {
        n.wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(17) & ((1u64 << bits) - 1)
    }

    /// Random valid and ready patterns: every beat comes out once, in order, data stable
    /// while stalled, the level matches a queue model, and the non-empty flag equals
    /// `wr != rd` after every edge; on every fetch, `next_tag` is the low bits of the beat
    /// presented after the edge.
    fn no_beat_lost<const W: usize, const A: usize, const A1: usize>(
        slices: usize,
        seed: u64,
        every_edge: bool,
    ) {
        let mut uut = StreamFifo::<W, A, A1>::with_slices(slices);
        if every_edge {
            uut = uut.writing_every_edge();
        }
        uut.connect_all();
        let edge = |uut: &mut StreamFifo<W, A, A1>| {
            uut.clock.next = Clock { clk: true };
            assert!(simulate(uut, 50));
            uut.clock.next = Clock { clk: false };
            assert!(simulate(uut, 50));
        };
        let mut seed = seed;
        let mut rnd = || crate::xorshift64(&mut seed);
        uut.rst.next = true;
        edge(&mut uut);
        uut.rst.next = false;
        let (mut next_in, mut next_out) = (0u64, 0u64);
        let mut model: VecDeque<u64> = VecDeque::new();
        let mut held: Option<u64> = None;
        let (mut empty_clocks, mut full_clocks) = (0, 0);
        let mut fetches = 0;
        for i in 0..4000 {
            let r = rnd();
            // Phases of mostly filling and mostly draining, so the FIFO runs full and
            // empty often.
            let valid = if (i / 200) % 2 == 0 {
                r & 3 != 0
            } else {
                r & 3 == 0
            };
            let ready = (r >> 2) & 3 == 0 || (r >> 8) & 1 == 1;
            // A reset now and then, in any state.
            let rst = (r >> 12) & 255 == 0;
            uut.rst.next = rst;
            uut.in_valid.next = valid;
            uut.in_data.next = beat(next_in, W).to_bits();
            uut.out_ready.next = ready;
            assert!(simulate(&mut uut, 50));
            let (wr, rd, dv) = uut.probe();
            assert_eq!(uut.ne.q.val(), wr != rd, "clock {i}: ne, wr {wr}, rd {rd}");
            assert_eq!(uut.level.val().index(), model.len(), "clock {i}");
            assert_eq!(uut.out_valid.val(), dv);
            let in_ready = uut.in_ready.val();
            assert_eq!(in_ready, !rst && model.len() < (1 << A));
            if !(valid && in_ready) {
                // A beat not taken carries other data (the RAM is written at every edge:
                // what it writes without a push must never reach the output).
                uut.in_data.next = (r.rotate_left(17) & ((1 << W) - 1)).to_bits();
                assert!(simulate(&mut uut, 50));
            }
            full_clocks += (model.len() == 1 << A) as u32;
            empty_clocks += (wr == rd && !dv) as u32;
            let out_valid = uut.out_valid.val();
            if out_valid {
                let d = uut.out_data.val().to_u64();
                assert_eq!(d, beat(next_out, W), "clock {i}");
                if let Some(h) = held {
                    assert_eq!(h, d, "data changed while stalled");
                }
                held = if ready { None } else { Some(d) };
            }
            if rst {
                model.clear();
                held = None;
                next_out = next_in;
            } else {
                if out_valid && ready {
                    model.pop_front();
                    next_out += 1;
                }
                if valid && in_ready {
                    model.push_back(next_in);
                    next_in += 1;
                }
            }
            // The look-ahead: on a fetch, `next_tag` is the low bits of the beat the head
            // register presents after the edge.
            let look = (!rst && uut.fetching.val()).then(|| uut.next_tag.val().to_u64());
            edge(&mut uut);
            if let Some(tag) = look {
                assert!(uut.out_valid.val(), "clock {i}: a fetch presents a beat");
                let low = uut.out_data.val().to_u64() & ((1 << TAG_BITS) - 1);
                assert_eq!(low, tag, "clock {i}: next_tag");
                fetches += 1;
            }
        }
        assert!(fetches > 1000, "{fetches} fetches");
        assert!(next_in > 1000, "the pattern moved {next_in} beats");
        assert!(
            full_clocks > 100 && empty_clocks > 100,
            "{full_clocks} {empty_clocks}"
        );
    }

    #[test]
    fn no_beat_lost_duplicated_or_reordered() {
        for every_edge in [false, true] {
            no_beat_lost::<8, 2, 3>(1, 0x1234_5678_9abc_def1, every_edge);
            no_beat_lost::<8, 2, 3>(2, 0x0fed_cba9_8765_4321, every_edge);
        }
    }

    /// The same with a RAM of several slices and a deeper FIFO (wrap of the pointers).
    #[test]
    fn sliced_ram_keeps_every_beat() {
        for (slices, seed) in [(1, 11), (3, 12), (6, 13)] {
            no_beat_lost::<24, 3, 4>(slices, seed, false);
            no_beat_lost::<24, 3, 4>(slices, seed, true);
        }
    }
}
