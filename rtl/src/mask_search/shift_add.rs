//! One product of the depth calculator (seed 000, JP2569952B2, Fig. 6 block 10): a plane
//! slope times a 4-bit two's-complement subpixel offset, as a shift-and-add.
//!
//! `d = −8·d3 + 4·d2 + 2·d1 + d0`, so `d·s = lo + hi` with `lo = d0·s + 2·d1·s` and
//! `hi = 4·d2·s − 8·d3·s`: two partial sums, each one adder, no multiplier. Two register
//! stages, the D1 and D2 of [`DepthCalc`](super::DepthCalc): D1 holds `lo` and `hi`, D2
//! their sum. `s` and `d` sampled at edge `E` show as `p` after edge `E + 1`; `rst`
//! (synchronous) clears both stages.

use super::Z_BITS;
use rust_hdl::prelude::*;

/// The product `d·s`, two register stages.
#[derive(LogicBlock)]
pub struct ShiftAdd {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// The slope `s`, 53-bit two's complement.
    pub s: Signal<In, Bits<Z_BITS>>,
    /// The offset `d`, 4-bit two's complement.
    pub d: Signal<In, Bits<4>>,
    /// `d·s` (modulo `2^53`), two clocks after `s` and `d`.
    pub p: Signal<Out, Bits<Z_BITS>>,
    lo_r: DFF<Bits<Z_BITS>>,
    hi_r: DFF<Bits<Z_BITS>>,
    p_r: DFF<Bits<Z_BITS>>,
    k_zero: Constant<Bits<Z_BITS>>,
    k_one: Constant<Bits<8>>,
    k_two: Constant<Bits<8>>,
    k_three: Constant<Bits<8>>,
    t0: Signal<Local, Bits<Z_BITS>>,
    t1: Signal<Local, Bits<Z_BITS>>,
    t2: Signal<Local, Bits<Z_BITS>>,
    t3: Signal<Local, Bits<Z_BITS>>,
}

impl Default for ShiftAdd {
    fn default() -> Self {
        ShiftAdd {
            clock: Default::default(),
            rst: Default::default(),
            s: Default::default(),
            d: Default::default(),
            p: Default::default(),
            lo_r: Default::default(),
            hi_r: Default::default(),
            p_r: Default::default(),
            k_zero: Constant::new(0u64.to_bits()),
            k_one: Constant::new(1u64.to_bits()),
            k_two: Constant::new(2u64.to_bits()),
            k_three: Constant::new(3u64.to_bits()),
            t0: Default::default(),
            t1: Default::default(),
            t2: Default::default(),
            t3: Default::default(),
        }
    }
}

impl Logic for ShiftAdd {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, lo_r, hi_r, p_r);
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.d.val().get_bit(0) {
            self.t0.next = self.s.val();
        }
        if self.d.val().get_bit(1) {
            self.t1.next = self.s.val() << self.k_one.val();
        }
        if self.d.val().get_bit(2) {
            self.t2.next = self.s.val() << self.k_two.val();
        }
        if self.d.val().get_bit(3) {
            self.t3.next = self.s.val() << self.k_three.val();
        }
        self.lo_r.d.next = self.t0.val() + self.t1.val();
        self.hi_r.d.next = self.t2.val() - self.t3.val();
        self.p_r.d.next = self.lo_r.q.val() + self.hi_r.q.val();
        if self.rst.val() {
            self.lo_r.d.next = self.k_zero.val();
            self.hi_r.d.next = self.k_zero.val();
            self.p_r.d.next = self.k_zero.val();
        }
        self.p.next = self.p_r.q.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::cycle;

    #[test]
    fn the_product_is_right_for_every_offset() {
        let mask = (1u64 << Z_BITS) - 1;
        let mut u = ShiftAdd::default();
        u.connect_all();
        for s in [
            0i64,
            1,
            -1,
            12345 << 12,
            -(7 << 40),
            (1 << 47) - 1,
            -(1 << 47),
        ] {
            for d in -8i64..8 {
                u.s.next = (s as u64 & mask).to_bits();
                u.d.next = (d as u64 & 0xF).to_bits();
                assert!(simulate(&mut u, 100));
                cycle!(u);
                cycle!(u);
                let p = u.p.val().to_u64();
                assert_eq!(p, (d * s) as u64 & mask, "s = {s}, d = {d}");
            }
        }
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check("pixelproc_rtl_shift_add", ShiftAdd::default());
    }
}
