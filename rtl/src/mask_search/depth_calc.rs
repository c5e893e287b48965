//! The depth calculator of the mask search unit (seed 000, JP2569952B2, Fig. 6 block 10):
//! `z = zc + sx·dx + sy·dy` at the one or two end offsets of a ROM word, with min and max.

use super::{PB, WORD_BITS, Z_BITS};
use rust_hdl::prelude::*;

/// The depth calculator: `z = zc + sx·dx + sy·dy` at both ends of a ROM word, then min
/// and max. `dx`, `dy` are the word's 4-bit two's-complement fields, so each product is a
/// shift-and-add of the slope (`d = −8·d3 + 4·d2 + 2·d1 + d0`), no multiplier.
///
/// Pipeline ([`DEPTH_LATENCY`] = 4 register stages, one adder level each): D1 the two
/// partial sums per product (`d0·s + 2·d1·s`, `4·d2·s − 8·d3·s`), D2 the products, D3
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
    xa1: DFF<Bits<Z_BITS>>,
    xb1: DFF<Bits<Z_BITS>>,
    ya1: DFF<Bits<Z_BITS>>,
    yb1: DFF<Bits<Z_BITS>>,
    xa2: DFF<Bits<Z_BITS>>,
    xb2: DFF<Bits<Z_BITS>>,
    ya2: DFF<Bits<Z_BITS>>,
    yb2: DFF<Bits<Z_BITS>>,
    zc_1: DFF<Bits<Z_BITS>>,
    px1: DFF<Bits<Z_BITS>>,
    py1: DFF<Bits<Z_BITS>>,
    px2: DFF<Bits<Z_BITS>>,
    py2: DFF<Bits<Z_BITS>>,
    zc_2: DFF<Bits<Z_BITS>>,
    z1_3: DFF<Bits<Z_BITS>>,
    z2_3: DFF<Bits<Z_BITS>>,
    z1_r: DFF<Bits<Z_BITS>>,
    z2_r: DFF<Bits<Z_BITS>>,
    zmin_r: DFF<Bits<Z_BITS>>,
    zmax_r: DFF<Bits<Z_BITS>>,
    k_sext: Constant<Bits<Z_BITS>>,
    k_zero: Constant<Bits<Z_BITS>>,
    k_one: Constant<Bits<8>>,
    k_two: Constant<Bits<8>>,
    k_three: Constant<Bits<8>>,
    zce: Signal<Local, Bits<Z_BITS>>,
    sxe: Signal<Local, Bits<Z_BITS>>,
    sye: Signal<Local, Bits<Z_BITS>>,
    t0: Signal<Local, Bits<Z_BITS>>,
    t1: Signal<Local, Bits<Z_BITS>>,
    t2: Signal<Local, Bits<Z_BITS>>,
    t3: Signal<Local, Bits<Z_BITS>>,
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
            xa1: Default::default(),
            xb1: Default::default(),
            ya1: Default::default(),
            yb1: Default::default(),
            xa2: Default::default(),
            xb2: Default::default(),
            ya2: Default::default(),
            yb2: Default::default(),
            zc_1: Default::default(),
            px1: Default::default(),
            py1: Default::default(),
            px2: Default::default(),
            py2: Default::default(),
            zc_2: Default::default(),
            z1_3: Default::default(),
            z2_3: Default::default(),
            z1_r: Default::default(),
            z2_r: Default::default(),
            zmin_r: Default::default(),
            zmax_r: Default::default(),
            k_sext: Constant::new(((1u64 << Z_BITS) - (1u64 << PB)).to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
            k_one: Constant::new(1u64.to_bits()),
            k_two: Constant::new(2u64.to_bits()),
            k_three: Constant::new(3u64.to_bits()),
            zce: Default::default(),
            sxe: Default::default(),
            sye: Default::default(),
            t0: Default::default(),
            t1: Default::default(),
            t2: Default::default(),
            t3: Default::default(),
            cs_s: Default::default(),
            cs_c: Default::default(),
            diff: Default::default(),
        }
    }
}

impl Logic for DepthCalc {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, xa1, xb1, ya1, yb1, xa2, xb2, ya2, yb2, zc_1, px1, py1, px2, py2, zc_2,
            z1_3, z2_3, z1_r, z2_r, zmin_r, zmax_r
        );
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
        // D1: partial sums. End 1: dx = word[3:0], dy = word[7:4]; end 2: [11:8], [15:12].
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(0) {
            self.t0.next = self.sxe.val();
        }
        if self.word.val().get_bit(1) {
            self.t1.next = self.sxe.val() << self.k_one.val();
        }
        if self.word.val().get_bit(2) {
            self.t2.next = self.sxe.val() << self.k_two.val();
        }
        if self.word.val().get_bit(3) {
            self.t3.next = self.sxe.val() << self.k_three.val();
        }
        self.xa1.d.next = self.t0.val() + self.t1.val();
        self.xb1.d.next = self.t2.val() - self.t3.val();
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(4) {
            self.t0.next = self.sye.val();
        }
        if self.word.val().get_bit(5) {
            self.t1.next = self.sye.val() << self.k_one.val();
        }
        if self.word.val().get_bit(6) {
            self.t2.next = self.sye.val() << self.k_two.val();
        }
        if self.word.val().get_bit(7) {
            self.t3.next = self.sye.val() << self.k_three.val();
        }
        self.ya1.d.next = self.t0.val() + self.t1.val();
        self.yb1.d.next = self.t2.val() - self.t3.val();
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(8) {
            self.t0.next = self.sxe.val();
        }
        if self.word.val().get_bit(9) {
            self.t1.next = self.sxe.val() << self.k_one.val();
        }
        if self.word.val().get_bit(10) {
            self.t2.next = self.sxe.val() << self.k_two.val();
        }
        if self.word.val().get_bit(11) {
            self.t3.next = self.sxe.val() << self.k_three.val();
        }
        self.xa2.d.next = self.t0.val() + self.t1.val();
        self.xb2.d.next = self.t2.val() - self.t3.val();
        self.t0.next = self.k_zero.val();
        self.t1.next = self.k_zero.val();
        self.t2.next = self.k_zero.val();
        self.t3.next = self.k_zero.val();
        if self.word.val().get_bit(12) {
            self.t0.next = self.sye.val();
        }
        if self.word.val().get_bit(13) {
            self.t1.next = self.sye.val() << self.k_one.val();
        }
        if self.word.val().get_bit(14) {
            self.t2.next = self.sye.val() << self.k_two.val();
        }
        if self.word.val().get_bit(15) {
            self.t3.next = self.sye.val() << self.k_three.val();
        }
        self.ya2.d.next = self.t0.val() + self.t1.val();
        self.yb2.d.next = self.t2.val() - self.t3.val();
        self.zc_1.d.next = self.zce.val();
        // D2: products.
        self.px1.d.next = self.xa1.q.val() + self.xb1.q.val();
        self.py1.d.next = self.ya1.q.val() + self.yb1.q.val();
        self.px2.d.next = self.xa2.q.val() + self.xb2.q.val();
        self.py2.d.next = self.ya2.q.val() + self.yb2.q.val();
        self.zc_2.d.next = self.zc_1.q.val();
        // D3: zc + px + py, carry-save then one adder.
        self.cs_s.next = (self.zc_2.q.val() ^ self.px1.q.val()) ^ self.py1.q.val();
        self.cs_c.next = (((self.zc_2.q.val() & self.px1.q.val())
            | (self.zc_2.q.val() & self.py1.q.val()))
            | (self.px1.q.val() & self.py1.q.val()))
            << self.k_one.val();
        self.z1_3.d.next = self.cs_s.val() + self.cs_c.val();
        self.cs_s.next = (self.zc_2.q.val() ^ self.px2.q.val()) ^ self.py2.q.val();
        self.cs_c.next = (((self.zc_2.q.val() & self.px2.q.val())
            | (self.zc_2.q.val() & self.py2.q.val()))
            | (self.px2.q.val() & self.py2.q.val()))
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
            self.xa1.d.next = self.k_zero.val();
            self.xb1.d.next = self.k_zero.val();
            self.ya1.d.next = self.k_zero.val();
            self.yb1.d.next = self.k_zero.val();
            self.xa2.d.next = self.k_zero.val();
            self.xb2.d.next = self.k_zero.val();
            self.ya2.d.next = self.k_zero.val();
            self.yb2.d.next = self.k_zero.val();
            self.zc_1.d.next = self.k_zero.val();
            self.px1.d.next = self.k_zero.val();
            self.py1.d.next = self.k_zero.val();
            self.px2.d.next = self.k_zero.val();
            self.py2.d.next = self.k_zero.val();
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
