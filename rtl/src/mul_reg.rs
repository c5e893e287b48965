//! An unsigned 16 × 16 bit multiplier with registered operands and a registered product:
//! the operands at `a` and `b` before edge `E` are multiplied, and the product is on `p`
//! after edge `E + 1`.
//!
//! This is what a pair of operand `DFF`s, a `*` and a product `DFF` do, and what the
//! entry pipeline's and the shading step's multipliers were. It is one block so that both
//! registers can be the DSP block's own on an FPGA: Yosys maps a `*` between fabric
//! registers to an ECP5 MULT18X18D without its registers, and the path from an operand
//! register through the routing, the multiplier and the routing to the product register
//! was the core's critical path (`docs/fpga.md`).
//!
//! The Verilog of the block instantiates the module `pixelproc_mul_reg`, defined once in
//! the exported file ([`GENERIC_VERILOG`], behavioural, appended by [`crate::verilog`]'s
//! export). The ECP5 flow reads `synth/ecp5/pixelproc_mul_reg.v` over it (one MULT18X18D
//! with its input and output registers). The simulation here is the generic module's
//! behaviour.
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clock` | in | 1 | rising edge |
//! | `a`, `b` | in | 16, 16 | operands, registered at the edge |
//! | `p` | out | 32 | the product of the operands registered one edge earlier (0 at power-on) |

use rust_hdl::prelude::*;

/// Width of an operand.
pub const OPERAND_W: usize = 16;
/// Width of the product.
pub const PRODUCT_W: usize = 2 * OPERAND_W;

/// Name of the Verilog module the block instantiates.
pub const MODULE: &str = "pixelproc_mul_reg";

/// The generic (behavioural) Verilog of `pixelproc_mul_reg`.
pub const GENERIC_VERILOG: &str = include_str!("pixelproc_mul_reg.v");

/// One multiplier. Build with `Default`.
#[derive(LogicBlock, Default)]
pub struct MulReg {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// First operand.
    pub a: Signal<In, Bits<OPERAND_W>>,
    /// Second operand.
    pub b: Signal<In, Bits<OPERAND_W>>,
    /// The product of the operands registered at the last edge.
    pub p: Signal<Out, Bits<PRODUCT_W>>,
    /// The operand registers (fields the derive skips: their names start with `_`).
    _a: u64,
    _b: u64,
}

impl Logic for MulReg {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            // Both stages load their values from before the edge.
            self.p.next = (self._a * self._b).to_bits();
            self._a = self.a.val().to_u64();
            self._b = self.b.val().to_u64();
        }
    }

    fn connect(&mut self) {
        self.p.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Wrapper(Wrapper {
            code: format!("{MODULE} mul(.clock(clock), .a(a), .b(b), .p(p));\n"),
            // Defined once per file by the export, not once per instance.
            cores: String::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(uut: &mut MulReg) {
        uut.clock.next = Clock { clk: true };
        assert!(simulate(uut, 50));
        uut.clock.next = Clock { clk: false };
        assert!(simulate(uut, 50));
    }

    /// Random operands, the extremes among them: the product of the operands applied
    /// before edge `E` is on `p` after edge `E + 1`, and 0 before any operand arrived.
    #[test]
    fn products_arrive_two_edges_later() {
        let mut uut = MulReg::default();
        uut.connect_all();
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut applied: Vec<(u64, u64)> = Vec::new();
        for i in 0..2000 {
            crate::xorshift64(&mut x);
            let (a, b) = match i % 5 {
                0 => (0xffff, 0xffff),
                1 => (x & 0xffff, 0xffff),
                _ => (x & 0xffff, (x >> 16) & 0xffff),
            };
            uut.a.next = a.to_bits();
            uut.b.next = b.to_bits();
            edge(&mut uut);
            applied.push((a, b));
            let want = if i == 0 {
                0
            } else {
                let (pa, pb) = applied[i - 1];
                pa * pb
            };
            assert_eq!(uut.p.val().to_u64(), want, "edge {i}");
        }
    }
}
