//! A `W`-bit adder with a gated second operand: `s = a + (en ? b : 0)` modulo 2^W,
//! combinational. The token of a pixel processor steps its depth and its three intensity
//! accumulators with it (`Z + dZ`, `I + dI` once the span has reached the column).
//!
//! Written as `if en { a + b } else { a }` in a kernel, this is an adder followed by a
//! multiplexer, and on an ECP5 Yosys maps the multiplexer (or an AND in front of the
//! adder) to a LUT4 per bit beside the carry chain: 146 LUT4 per processor. The gate fits
//! in the carry chain's own LUTs instead: each half of a CCU2C computes its propagate
//! bit with a LUT4 of four inputs, of which an adder uses two.
//!
//! The Verilog of the block instantiates the module `pixelproc_gated_add` (parameter
//! `W`), defined once in the exported file ([`GENERIC_VERILOG`], behavioural, appended by
//! [`crate::verilog`]'s export). The ECP5 flow reads `synth/ecp5/pixelproc_gated_add.v`
//! over it: one CCU2C per two bits, the propagate LUT `A ^ (B & D)` with the gate on `D`
//! (the LUT's fastest input), the generate bit `A` (which is the carry wherever the
//! propagate bit is 0). The simulation here is the generic module's behaviour.
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `a` | in | W | first operand |
//! | `b` | in | W | second operand, added when `en` is 1 |
//! | `en` | in | 1 | gate of `b` |
//! | `s` | out | W | `a + (en ? b : 0)` modulo 2^W |

use rust_hdl::prelude::*;

/// Name of the Verilog module the block instantiates.
pub const MODULE: &str = "pixelproc_gated_add";

/// The generic (behavioural) Verilog of `pixelproc_gated_add`.
pub const GENERIC_VERILOG: &str = include_str!("pixelproc_gated_add.v");

/// One gated adder of `W` bits. Build with `Default`.
#[derive(LogicBlock, Default)]
pub struct GatedAdd<const W: usize> {
    /// First operand.
    pub a: Signal<In, Bits<W>>,
    /// Second operand, added when `en` is 1.
    pub b: Signal<In, Bits<W>>,
    /// Gate of `b`.
    pub en: Signal<In, Bit>,
    /// `a + (en ? b : 0)` modulo 2^W.
    pub s: Signal<Out, Bits<W>>,
}

impl<const W: usize> Logic for GatedAdd<W> {
    fn update(&mut self) {
        self.s.next = if self.en.val() {
            self.a.val() + self.b.val()
        } else {
            self.a.val()
        };
    }

    fn connect(&mut self) {
        self.s.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Wrapper(Wrapper {
            code: format!("{MODULE} #(.W({W})) add(.a(a), .b(b), .en(en), .s(s));\n"),
            // Defined once per file by the export, not once per instance.
            cores: String::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random operands with the extremes among them, both gates: the sum wraps modulo
    /// 2^W, and a closed gate passes `a` through.
    #[test]
    fn sums_wrap_and_the_gate_passes_a() {
        let mut uut = GatedAdd::<44>::default();
        uut.connect_all();
        let mask = (1u64 << 44) - 1;
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for i in 0..2000 {
            crate::xorshift64(&mut x);
            let (a, b) = match i % 4 {
                0 => (mask, 1),
                1 => (mask, mask),
                _ => (x & mask, (x >> 7) & mask),
            };
            let en = i % 3 != 0;
            uut.a.next = a.to_bits();
            uut.b.next = b.to_bits();
            uut.en.next = en;
            assert!(simulate(&mut uut, 10));
            let want = if en { (a + b) & mask } else { a };
            assert_eq!(uut.s.val().to_u64(), want, "a {a:#x} b {b:#x} en {en}");
        }
    }
}
