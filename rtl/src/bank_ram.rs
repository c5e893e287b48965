//! One bank of the shading table: 2^[`BANK_BITS`] words of [`ENTRY_W`] bits, one write
//! port and one read port on the same clock, the read registered twice (the word at
//! `read_address` before edge `E` is on `read_data` after edge `E + 1`).
//!
//! This is what a rust-hdl `RAM` (synchronous read) followed by a `DFF` does, and what the
//! shading unit had as each bank and its bank register. It is one block so that the
//! second register can be the block RAM's own output register on an FPGA: Yosys maps the
//! RAM to an ECP5 DP16KD without its output register (`REGMODE = NOREG`) and keeps the
//! following register in the fabric, so the block RAM's slow clock-to-out without that
//! register was the core's critical path (`docs/fpga.md`).
//!
//! The Verilog of the block instantiates the module `pixelproc_bank_ram`, defined once in
//! the exported file ([`GENERIC_VERILOG`], behavioural, appended by
//! [`crate::verilog`]'s export). The ECP5 flow reads `synth/ecp5/pixelproc_bank_ram.v`
//! over it (one DP16KD with `REGMODE_B = "OUTREG"`). The simulation here is the generic
//! module's behaviour.
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clock` | in | 1 | rising edge |
//! | `write_enable`, `write_address`, `write_data` | in | 1, 10, 18 | `mem[write_address] := write_data` at the edge if `write_enable` |
//! | `read_address` | in | 10 | word read at the edge (its old value if written at the same edge) |
//! | `read_data` | out | 18 | the word read one edge earlier (0 at power-on) |

use rust_hdl::prelude::*;

/// Address bits of a bank (2^10 × 18 bits: one ECP5 DP16KD).
pub const BANK_BITS: usize = 10;
/// Width of a word.
pub const ENTRY_W: usize = 18;

/// Name of the Verilog module the block instantiates.
pub const MODULE: &str = "pixelproc_bank_ram";

/// The generic (behavioural) Verilog of `pixelproc_bank_ram`.
pub const GENERIC_VERILOG: &str = include_str!("pixelproc_bank_ram.v");

/// One bank. Build with `Default`.
#[derive(LogicBlock)]
pub struct BankRam {
    /// Clock of both ports.
    pub clock: Signal<In, Clock>,
    /// Write the word at the next rising edge.
    pub write_enable: Signal<In, Bit>,
    /// Word written.
    pub write_address: Signal<In, Bits<BANK_BITS>>,
    /// Value written.
    pub write_data: Signal<In, Bits<ENTRY_W>>,
    /// Word read.
    pub read_address: Signal<In, Bits<BANK_BITS>>,
    /// The word read one edge earlier.
    pub read_data: Signal<Out, Bits<ENTRY_W>>,
    /// Simulation contents (fields the derive skips: their names start with `_`).
    _mem: Vec<Bits<ENTRY_W>>,
    /// The block RAM's read register.
    _word: Bits<ENTRY_W>,
}

impl Default for BankRam {
    fn default() -> Self {
        BankRam {
            clock: Default::default(),
            write_enable: Default::default(),
            write_address: Default::default(),
            write_data: Default::default(),
            read_address: Default::default(),
            read_data: Default::default(),
            _mem: vec![Bits::default(); 1 << BANK_BITS],
            _word: Bits::default(),
        }
    }
}

impl Logic for BankRam {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            // Both registers load their values from before the edge, then the write.
            self.read_data.next = self._word;
            self._word = self._mem[self.read_address.val().index()];
            if self.write_enable.val() {
                let a = self.write_address.val().index();
                self._mem[a] = self.write_data.val();
            }
        }
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Wrapper(Wrapper {
            code: format!(
                "{MODULE} ram(.clock(clock), .write_enable(write_enable), .write_address(write_address), \
                 .write_data(write_data), .read_address(read_address), .read_data(read_data));\n"
            ),
            // Defined once per file by the export, not once per instance.
            cores: String::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(uut: &mut BankRam) {
        uut.clock.next = Clock { clk: true };
        assert!(simulate(uut, 50));
        uut.clock.next = Clock { clk: false };
        assert!(simulate(uut, 50));
    }

    /// Random writes and reads (small address range, so reads often hit words written at
    /// the same edge) against a plain array and two registers: the read is the old
    /// value at the edge, registered twice.
    #[test]
    fn reads_arrive_two_edges_later_with_the_old_value() {
        let mut uut = BankRam::default();
        uut.connect_all();
        let mut model = [0u64; 1 << BANK_BITS];
        let mut word = 0u64;
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for i in 0..3000 {
            crate::xorshift64(&mut x);
            let span = if i % 2 == 0 { 8 } else { 1 << BANK_BITS };
            let (we, wa, wd, ra) = (
                x & 1 == 1,
                (x >> 1) % span,
                (x >> 12) & 0x3ffff,
                (x >> 32) % span,
            );
            uut.write_enable.next = we;
            uut.write_address.next = wa.to_bits();
            uut.write_data.next = wd.to_bits();
            uut.read_address.next = ra.to_bits();
            edge(&mut uut);
            let out = std::mem::replace(&mut word, model[ra as usize]);
            if we {
                model[wa as usize] = wd;
            }
            assert_eq!(uut.read_data.val().index() as u64, out, "step {i}");
        }
    }
}
