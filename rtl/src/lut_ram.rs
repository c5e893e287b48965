//! A RAM with one synchronous write port and one asynchronous (combinational) read port:
//! distributed "LUT" RAM (ECP5 `TRELLIS_DPR16X4`, Xilinx `RAM32M`/`RAM64M`, Intel MLAB).
//!
//! rust-hdl's own `RAM` widget registers its read port, so the address of a read has to be
//! chosen a clock ahead: a FIFO that must hold its head then re-reads it, and the decision
//! to advance sits in front of the address of every RAM slice. With an asynchronous read,
//! the reader keeps its own output register and holds it with a clock enable, while the
//! RAM's address comes straight from a pointer register (`stream_fifo`).
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `write_clock` | in | 1 | rising edge writes |
//! | `write_enable`, `write_address`, `write_data` | in | 1, `A`, `D` | `mem[write_address] := write_data` at the edge if `write_enable` |
//! | `read_address` | in | `A` | word to read |
//! | `read_data` | out | `D` | `mem[read_address]`, combinationally (after a write to that word, its new value) |
//!
//! The contents start at zero in simulation and are undefined in hardware until written.

use rust_hdl::prelude::*;

/// `2^A` words of `D`, written on `write_clock`, read combinationally.
#[derive(LogicBlock)]
pub struct LutRam<D: Synth, const A: usize> {
    /// Write clock.
    pub write_clock: Signal<In, Clock>,
    /// Write the word at the next rising edge.
    pub write_enable: Signal<In, Bit>,
    /// Word written.
    pub write_address: Signal<In, Bits<A>>,
    /// Value written.
    pub write_data: Signal<In, D>,
    /// Word read.
    pub read_address: Signal<In, Bits<A>>,
    /// `mem[read_address]`.
    pub read_data: Signal<Out, D>,
    /// Simulation contents (a field the derive skips: its name starts with `_`).
    _mem: Vec<D>,
}

impl<D: Synth, const A: usize> Default for LutRam<D, A> {
    fn default() -> Self {
        assert!(A >= 1 && A < 16, "LutRam: 1 <= A < 16");
        LutRam {
            write_clock: Default::default(),
            write_enable: Default::default(),
            write_address: Default::default(),
            write_data: Default::default(),
            read_address: Default::default(),
            read_data: Default::default(),
            _mem: vec![D::default(); 1 << A],
        }
    }
}

impl<D: Synth, const A: usize> Logic for LutRam<D, A> {
    fn update(&mut self) {
        if self.write_clock.pos_edge() && self.write_enable.val() {
            let a = self.write_address.val().index();
            self._mem[a] = self.write_data.val();
        }
        self.read_data.next = self._mem[self.read_address.val().index()];
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        // The read goes through a continuous assignment (sensitive to the word's contents,
        // not only to the address) into the `output reg` rust-hdl declares.
        Verilog::Custom(format!(
            "\
reg [{msb}:0] mem [0:{last}];
wire [{msb}:0] read_word = mem[read_address];

always @(*) read_data = read_word;

always @(posedge write_clock) begin
   if (write_enable) begin
      mem[write_address] <= write_data;
   end
end
",
            msb = D::BITS - 1,
            last = (1usize << A) - 1,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type R = LutRam<Bits<8>, 3>;

    fn edge(uut: &mut R) {
        uut.write_clock.next = Clock { clk: true };
        assert!(simulate(uut, 50));
        uut.write_clock.next = Clock { clk: false };
        assert!(simulate(uut, 50));
    }

    /// Random writes and reads against a plain array: a read returns the last value
    /// written to its word, the same clock a write lands, and nothing else moves.
    #[test]
    fn reads_return_the_last_write() {
        let mut uut = R::default();
        uut.connect_all();
        let mut model = [0u64; 8];
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..2000 {
            crate::xorshift64(&mut x);
            let (we, wa, wd, ra) = (x & 1 == 1, (x >> 1) & 7, (x >> 4) & 0xff, (x >> 12) & 7);
            uut.write_enable.next = we;
            uut.write_address.next = wa.to_bits();
            uut.write_data.next = wd.to_bits();
            uut.read_address.next = ra.to_bits();
            assert!(simulate(&mut uut, 50));
            assert_eq!(uut.read_data.val().index() as u64, model[ra as usize]);
            edge(&mut uut);
            if we {
                model[wa as usize] = wd;
            }
            assert!(simulate(&mut uut, 50));
            assert_eq!(uut.read_data.val().index() as u64, model[ra as usize]);
        }
    }
}
