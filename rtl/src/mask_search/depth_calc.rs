//! The depth calculator of the mask search unit (seed 000, JP2569952B2, Fig. 6 block 10):
//! `z = zc + sx·dx + sy·dy` at the one or two end offsets of a ROM word, with min and max.

use super::{ShiftAdd, PB, WORD_BITS, Z_BITS};
use rust_hdl::prelude::*;

/// The depth calculator: `z = zc + sx·dx + sy·dy` at both ends of a ROM word, then min
/// and max. `dx`, `dy` are the word's 4-bit two's-complement fields, so each product is a
/// shift-and-add of the slope (`d = −8·d3 + 4·d2 + 2·d1 + d0`, one [`ShiftAdd`] per
/// product), no multiplier.
///
/// Pipeline ([`DEPTH_LATENCY`](super::DEPTH_LATENCY) = 4 register stages, one adder
/// level each): D1 the two partial sums per product (`d0·s + 2·d1·s`, `4·d2·s − 8·d3·s`),
/// D2 the products (both inside the [`ShiftAdd`] blocks), D3
/// `zc + px + py` (carry-save then one adder), D4 the compare `z1 − z2 < 0` and min/max.
/// Inputs sampled at edge `E` show on the outputs after edge `E + 3`.
#[derive(LogicBlock)]
pub struct DepthCalc {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// Plane depth at the pixel centre, Q.12, 48-bit two's complement.
    pub zc: Signal<In, Bits<PB>>,
    /// Depth change per `1/(2n)` px in x.
    pub sx: Signal<In, Bits<PB>>,
    /// Depth change per `1/(2m)` px in y.
    pub sy: Signal<In, Bits<PB>>,
    /// ROM word (end 1 `[7:0]`, end 2 `[15:8]`, pair `[16]`).
    pub word: Signal<In, Bits<WORD_BITS>>,
    /// Depth at end 1.
    pub z1: Signal<Out, Bits<Z_BITS>>,
    /// Depth at end 2 (equal to `z1` when the word has no pair).
    pub z2: Signal<Out, Bits<Z_BITS>>,
    /// `min(z1, z2)` (signed).
    pub zmin: Signal<Out, Bits<Z_BITS>>,
    /// `max(z1, z2)` (signed).
    pub zmax: Signal<Out, Bits<Z_BITS>>,
    zc_1: DFF<Bits<Z_BITS>>,
    zc_2: DFF<Bits<Z_BITS>>,
    z1_3: DFF<Bits<Z_BITS>>,
    z2_3: DFF<Bits<Z_BITS>>,
    z1_r: DFF<Bits<Z_BITS>>,
    z2_r: DFF<Bits<Z_BITS>>,
    zmin_r: DFF<Bits<Z_BITS>>,
    zmax_r: DFF<Bits<Z_BITS>>,
    /// The products (stages D1 and D2) of end 1 (`sx·dx`, `sy·dy`) and end 2.
    mx1: ShiftAdd,
    my1: ShiftAdd,
    mx2: ShiftAdd,
    my2: ShiftAdd,
    k_sext: Constant<Bits<Z_BITS>>,
    k_zero: Constant<Bits<Z_BITS>>,
    k_one: Constant<Bits<8>>,
    zce: Signal<Local, Bits<Z_BITS>>,
    sxe: Signal<Local, Bits<Z_BITS>>,
    sye: Signal<Local, Bits<Z_BITS>>,
    cs_s: Signal<Local, Bits<Z_BITS>>,
    cs_c: Signal<Local, Bits<Z_BITS>>,
    diff: Signal<Local, Bits<Z_BITS>>,
}

impl Default for DepthCalc {
    fn default() -> Self {
        Self::new()
    }
}

impl DepthCalc {
    /// A depth calculator.
    pub fn new() -> Self {
        DepthCalc {
            clock: Default::default(),
            rst: Default::default(),
            zc: Default::default(),
            sx: Default::default(),
            sy: Default::default(),
            word: Default::default(),
            z1: Default::default(),
            z2: Default::default(),
            zmin: Default::default(),
            zmax: Default::default(),
            zc_1: Default::default(),
            zc_2: Default::default(),
            z1_3: Default::default(),
            z2_3: Default::default(),
            z1_r: Default::default(),
            z2_r: Default::default(),
            zmin_r: Default::default(),
            zmax_r: Default::default(),
            mx1: Default::default(),
            my1: Default::default(),
            mx2: Default::default(),
            my2: Default::default(),
            k_sext: Constant::new(((1u64 << Z_BITS) - (1u64 << PB)).to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
            k_one: Constant::new(1u64.to_bits()),
            zce: Default::default(),
            sxe: Default::default(),
            sye: Default::default(),
            cs_s: Default::default(),
            cs_c: Default::default(),
            diff: Default::default(),
        }
    }
}

impl Logic for DepthCalc {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, zc_1, zc_2, z1_3, z2_3, z1_r, z2_r, zmin_r, zmax_r);
        // Sign extension 48 -> 53 bits (bit 47 = PB - 1; a literal, since a named
        // constant would leak into the Verilog by name).
        self.zce.next = bit_cast::<Z_BITS, PB>(self.zc.val());
        if self.zc.val().get_bit(47) {
            self.zce.next = self.zce.val() | self.k_sext.val();
        }
        self.sxe.next = bit_cast::<Z_BITS, PB>(self.sx.val());
        if self.sx.val().get_bit(47) {
            self.sxe.next = self.sxe.val() | self.k_sext.val();
        }
        self.sye.next = bit_cast::<Z_BITS, PB>(self.sy.val());
        if self.sy.val().get_bit(47) {
            self.sye.next = self.sye.val() | self.k_sext.val();
        }
        // D1, D2: the products. End 1: dx = word[3:0], dy = word[7:4]; end 2: [11:8],
        // [15:12].
        self.mx1.clock.next = self.clock.val();
        self.my1.clock.next = self.clock.val();
        self.mx2.clock.next = self.clock.val();
        self.my2.clock.next = self.clock.val();
        self.mx1.rst.next = self.rst.val();
        self.my1.rst.next = self.rst.val();
        self.mx2.rst.next = self.rst.val();
        self.my2.rst.next = self.rst.val();
        self.mx1.s.next = self.sxe.val();
        self.mx1.d.next = self.word.val().get_bits::<4>(0);
        self.my1.s.next = self.sye.val();
        self.my1.d.next = self.word.val().get_bits::<4>(4);
        self.mx2.s.next = self.sxe.val();
        self.mx2.d.next = self.word.val().get_bits::<4>(8);
        self.my2.s.next = self.sye.val();
        self.my2.d.next = self.word.val().get_bits::<4>(12);
        self.zc_1.d.next = self.zce.val();
        self.zc_2.d.next = self.zc_1.q.val();
        // D3: zc + px + py, carry-save then one adder.
        self.cs_s.next = (self.zc_2.q.val() ^ self.mx1.p.val()) ^ self.my1.p.val();
        self.cs_c.next = (((self.zc_2.q.val() & self.mx1.p.val())
            | (self.zc_2.q.val() & self.my1.p.val()))
            | (self.mx1.p.val() & self.my1.p.val()))
            << self.k_one.val();
        self.z1_3.d.next = self.cs_s.val() + self.cs_c.val();
        self.cs_s.next = (self.zc_2.q.val() ^ self.mx2.p.val()) ^ self.my2.p.val();
        self.cs_c.next = (((self.zc_2.q.val() & self.mx2.p.val())
            | (self.zc_2.q.val() & self.my2.p.val()))
            | (self.mx2.p.val() & self.my2.p.val()))
            << self.k_one.val();
        self.z2_3.d.next = self.cs_s.val() + self.cs_c.val();
        // D4: signed compare (|z| < 2^51, so z1 − z2 does not overflow 53 bits).
        self.diff.next = self.z1_3.q.val() - self.z2_3.q.val();
        self.z1_r.d.next = self.z1_3.q.val();
        self.z2_r.d.next = self.z2_3.q.val();
        self.zmin_r.d.next = self.z2_3.q.val();
        self.zmax_r.d.next = self.z1_3.q.val();
        if self.diff.val().get_bit(52) {
            self.zmin_r.d.next = self.z1_3.q.val();
            self.zmax_r.d.next = self.z2_3.q.val();
        }
        if self.rst.val() {
            self.zc_1.d.next = self.k_zero.val();
            self.zc_2.d.next = self.k_zero.val();
            self.z1_3.d.next = self.k_zero.val();
            self.z2_3.d.next = self.k_zero.val();
            self.z1_r.d.next = self.k_zero.val();
            self.z2_r.d.next = self.k_zero.val();
            self.zmin_r.d.next = self.k_zero.val();
            self.zmax_r.d.next = self.k_zero.val();
        }
        self.z1.next = self.z1_r.q.val();
        self.z2.next = self.z2_r.q.val();
        self.zmin.next = self.zmin_r.q.val();
        self.zmax.next = self.zmax_r.q.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::{cycle, depth_of, plane_bits, DEPTH_LATENCY};
    use crate::mask_search::{SEED_DEPTHS, SEED_PLANE, SEED_WORD};

    #[test]
    fn seed_word_gives_both_end_depths() {
        let mut u = DepthCalc::new();
        u.connect_all();
        u.zc.next = plane_bits(SEED_PLANE[0]);
        u.sx.next = plane_bits(SEED_PLANE[1]);
        u.sy.next = plane_bits(SEED_PLANE[2]);
        u.word.next = SEED_WORD.to_bits();
        // Settle before the first edge, as inputs driven from registers are in the units
        // (the products come through sub-blocks, one evaluation pass later).
        assert!(simulate(&mut u, 200));
        for _ in 0..DEPTH_LATENCY {
            cycle!(u);
        }
        let [lo, hi] = SEED_DEPTHS;
        assert_eq!(
            [&u.z1, &u.z2, &u.zmin, &u.zmax].map(|s| depth_of(s.val())),
            [lo, hi, lo, hi]
        );
        u.rst.next = true;
        cycle!(u);
        u.rst.next = false;
        assert_eq!(
            depth_of(u.zmax.val()),
            0,
            "reset clears the result registers"
        );
        for _ in 0..DEPTH_LATENCY {
            cycle!(u);
        }
        assert_eq!(depth_of(u.zmax.val()), hi);
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check("pixelproc_rtl_depth_calc", DepthCalc::new());
    }
}
