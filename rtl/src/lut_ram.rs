//! A RAM with one synchronous write port and one asynchronous (combinational) read port:
//! distributed "LUT" RAM (ECP5 `TRELLIS_DPR16X4`, Xilinx `RAM32M`/`RAM64M`, Intel MLAB),
//! cut by data bits into slices that each hold their own copy of the address registers
//! ([`SlicedLutRam`]).
//!
//! rust-hdl's own `RAM` widget registers its read port, so the address of a read has to be
//! chosen a clock ahead: a FIFO that must hold its head then re-reads it, and the decision
//! to advance sits in front of the address of every RAM slice. With an asynchronous read,
//! the reader keeps its own output register and holds it with a clock enable, while the
//! RAM's address comes from registers equal to the reader's pointer (`stream_fifo`).

use rust_hdl::prelude::*;

/// Bit ranges `[lo, hi)` of the slices of a `bits`-wide word cut into `slices` pieces:
/// whole nibbles (the width of an ECP5 `TRELLIS_DPR16X4`), as even as they go, the wider
/// slices last. Panics unless `1 <= slices <= ceil(bits / 4)`.
pub fn slice_bounds(bits: usize, slices: usize) -> Vec<(usize, usize)> {
    let nibbles = bits.div_ceil(4);
    assert!(
        slices >= 1 && slices <= nibbles,
        "SlicedLutRam: 1 <= slices <= ceil({bits} / 4)"
    );
    let edge = |s: usize| (4 * (s * nibbles / slices)).min(bits);
    (0..slices).map(|s| (edge(s), edge(s + 1))).collect()
}

/// A LUT RAM cut by data bits into slices, each slice with its own registers holding
/// the read address and the write address. The addresses are registered inside the block:
/// the ports take the address of the *next* clock (the value the caller's own pointer
/// register is about to load), so each slice's copy equals the caller's pointer.
///
/// A pointer register that addresses every LUT RAM primitive of a wide word fans out to
/// all of them (the core's command beat, 260 bits then, × 32 words: 130 `TRELLIS_DPR16X4`s and their 2:1 multiplexers),
/// and that net's routing was the core's critical path (`docs/fpga.md`). With a copy per
/// slice, each copy drives only its slice. The copies carry `(* keep *)` in the Verilog
/// (on each slice's `always` block: on the registers alone Yosys still merges them), so
/// synthesis does not merge the equal registers back into one.
///
/// # Ports
///
/// | port | dir | width | meaning |
/// |---|---|---|---|
/// | `clock` | in | 1 | rising edge: the write, then every slice's address registers load |
/// | `write_enable`, `write_data` | in | 1, `D` | `mem[wa] := write_data` at the edge if `write_enable`, `wa` the write address registered at the edge before |
/// | `next_write_address`, `next_read_address` | in | `A`, `A` | loaded into every slice's `wa`, `ra` at the edge |
/// | `read_data` | out | `D` | `mem[ra]`, combinationally (after a write to that word, its new value) |
///
/// The address registers start at 0; the contents start at zero in simulation and are
/// undefined in hardware until written. The simulation keeps one copy of each address
/// (the copies are equal by construction); the slices exist in the Verilog, whose own
/// test simulates them (`testbench/tests/sliced_lut_ram.rs`).
#[derive(LogicBlock)]
pub struct SlicedLutRam<D: Synth, const A: usize> {
    /// Clock of the write and of the address registers.
    pub clock: Signal<In, Clock>,
    /// Write the word at the next rising edge.
    pub write_enable: Signal<In, Bit>,
    /// Value written.
    pub write_data: Signal<In, D>,
    /// The write address after the next rising edge.
    pub next_write_address: Signal<In, Bits<A>>,
    /// The read address after the next rising edge.
    pub next_read_address: Signal<In, Bits<A>>,
    /// `mem[ra]`.
    pub read_data: Signal<Out, D>,
    /// Simulation contents and address registers (fields the derive skips: their names
    /// start with `_`).
    _mem: Vec<D>,
    _wa: Bits<A>,
    _ra: Bits<A>,
    _slices: usize,
}

impl<D: Synth, const A: usize> Default for SlicedLutRam<D, A> {
    fn default() -> Self {
        Self::new(1)
    }
}

impl<D: Synth, const A: usize> SlicedLutRam<D, A> {
    /// A RAM of `2^A` words of `D` in `slices` slices ([`slice_bounds`]).
    pub fn new(slices: usize) -> Self {
        assert!(A >= 1 && A < 16, "SlicedLutRam: 1 <= A < 16");
        slice_bounds(D::BITS, slices);
        SlicedLutRam {
            clock: Default::default(),
            write_enable: Default::default(),
            write_data: Default::default(),
            next_write_address: Default::default(),
            next_read_address: Default::default(),
            read_data: Default::default(),
            _mem: vec![D::default(); 1 << A],
            _wa: Bits::default(),
            _ra: Bits::default(),
            _slices: slices,
        }
    }

    /// Number of slices.
    pub fn slices(&self) -> usize {
        self._slices
    }

    /// Verilog names of slice `s`'s registers: (read address, write address, memory).
    pub fn slice_names(s: usize) -> (String, String, String) {
        (format!("ra_{s}"), format!("wa_{s}"), format!("mem_{s}"))
    }
}

impl<D: Synth, const A: usize> Logic for SlicedLutRam<D, A> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            // The write goes to the address registered at the edge before; then the
            // address registers load.
            if self.write_enable.val() {
                self._mem[self._wa.index()] = self.write_data.val();
            }
            self._wa = self.next_write_address.val();
            self._ra = self.next_read_address.val();
        }
        self.read_data.next = self._mem[self._ra.index()];
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        use std::fmt::Write as _;
        let bounds = slice_bounds(D::BITS, self._slices);
        let (aw, amsb, last) = (A, A - 1, (1usize << A) - 1);
        let mut decl = String::new();
        let mut init = String::new();
        let mut regs = String::new();
        let mut writes = String::new();
        for (s, &(lo, hi)) in bounds.iter().enumerate() {
            let (ra, wa, mem) = Self::slice_names(s);
            let msb = hi - lo - 1;
            let _ = write!(
                decl,
                "\
// slice {s}: bits {top}:{lo}, with its own copies of the two addresses
(* keep *) reg [{amsb}:0] {ra};
(* keep *) reg [{amsb}:0] {wa};
reg [{msb}:0] {mem} [0:{last}];
wire [{msb}:0] rd_{s} = {mem}[{ra}];
",
                top = hi - 1,
            );
            let _ = writeln!(init, "   {ra} = {aw}'d0;\n   {wa} = {aw}'d0;");
            let _ = writeln!(
                regs,
                "(* keep *) always @(posedge clock) begin\n   {ra} <= next_read_address;\n   {wa} <= next_write_address;\nend"
            );
            let _ = writeln!(
                writes,
                "      {mem}[{wa}] <= write_data[{top}:{lo}];",
                top = hi - 1
            );
        }
        let word = (0..bounds.len())
            .rev()
            .map(|s| format!("rd_{s}"))
            .collect::<Vec<_>>()
            .join(", ");
        // The read goes through continuous assignments (sensitive to the words' contents,
        // not only to the addresses) into the `output reg` rust-hdl declares. `keep` on
        // each slice's address process marks its flip-flops (Yosys gives the process's
        // attributes to the cells it makes), which is what stops `opt_merge` from merging
        // the equal copies; `keep` on the registers alone does not.
        Verilog::Custom(format!(
            "\
{decl}
initial begin
{init}end

always @(*) read_data = {{{word}}};

{regs}
always @(posedge clock) begin
   if (write_enable) begin
{writes}   end
end
"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type S = SlicedLutRam<Bits<12>, 3>;

    fn clock(uut: &mut S) {
        uut.clock.next = Clock { clk: true };
        assert!(simulate(uut, 50));
        uut.clock.next = Clock { clk: false };
        assert!(simulate(uut, 50));
    }

    /// The slices are whole nibbles, as even as they go, and cover the word once.
    #[test]
    fn slices_are_whole_nibbles_covering_the_word() {
        assert_eq!(slice_bounds(12, 1), vec![(0, 12)]);
        assert_eq!(slice_bounds(12, 3), vec![(0, 4), (4, 8), (8, 12)]);
        assert_eq!(slice_bounds(10, 3), vec![(0, 4), (4, 8), (8, 10)]);
        let b = slice_bounds(260, 8);
        assert_eq!(b.len(), 8);
        assert_eq!((b[0].0, b[7].1), (0, 260));
        for w in b.windows(2) {
            assert_eq!(w[0].1, w[1].0);
        }
        for &(lo, hi) in &b {
            assert!(
                lo % 4 == 0 && (hi - lo == 32 || hi - lo == 36),
                "{lo}..{hi}"
            );
        }
    }

    #[test]
    #[should_panic(expected = "slices")]
    fn more_slices_than_nibbles_is_refused() {
        slice_bounds(8, 3);
    }

    /// Random writes and reads against a plain array and two address registers: the
    /// write lands at the write address given one edge earlier, the read shows the word
    /// at the read address given one edge earlier, including a write at the same edge.
    #[test]
    fn sliced_reads_and_writes_follow_the_registered_addresses() {
        for slices in [1, 2, 3] {
            let mut uut = S::new(slices);
            assert_eq!(uut.slices(), slices);
            uut.connect_all();
            let mut model = [0u64; 8];
            let (mut wa, mut ra) = (0usize, 0usize);
            let mut x = 0x2545_f491_4f6c_dd1du64 ^ slices as u64;
            for i in 0..3000 {
                crate::xorshift64(&mut x);
                let (we, nwa, wd, nra) = (
                    x & 1 == 1,
                    ((x >> 1) & 7) as usize,
                    (x >> 4) & 0xfff,
                    ((x >> 16) & 7) as usize,
                );
                uut.write_enable.next = we;
                uut.next_write_address.next = (nwa as u64).to_bits();
                uut.write_data.next = wd.to_bits();
                uut.next_read_address.next = (nra as u64).to_bits();
                assert!(simulate(&mut uut, 50));
                assert_eq!(uut.read_data.val().index() as u64, model[ra], "step {i}");
                clock(&mut uut);
                if we {
                    model[wa] = wd;
                }
                (wa, ra) = (nwa, nra);
                assert_eq!(uut.read_data.val().index() as u64, model[ra], "step {i}");
            }
        }
    }

    /// The Verilog names each slice's registers as [`SlicedLutRam::slice_names`] says,
    /// keeps the address copies, and writes each slice's bits.
    #[test]
    fn verilog_has_one_memory_and_two_kept_address_copies_per_slice() {
        let uut = S::new(3);
        let Verilog::Custom(v) = uut.hdl() else {
            panic!("custom Verilog expected")
        };
        for (s, (lo, hi)) in slice_bounds(12, 3).into_iter().enumerate() {
            let (ra, wa, mem) = S::slice_names(s);
            assert!(v.contains(&format!("(* keep *) reg [2:0] {ra};")), "{v}");
            assert!(v.contains(&format!("(* keep *) reg [2:0] {wa};")), "{v}");
            assert!(
                v.contains(&format!("{mem}[{wa}] <= write_data[{}:{lo}];", hi - 1)),
                "{v}"
            );
            assert!(
                v.contains(&format!("wire [3:0] rd_{s} = {mem}[{ra}];")),
                "{v}"
            );
        }
        assert!(v.contains("read_data = {rd_2, rd_1, rd_0};"), "{v}");
    }
}
