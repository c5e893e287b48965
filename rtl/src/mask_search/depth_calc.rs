//! The depth calculator of the mask search unit (seed 000, JP2569952B2, Fig. 6 block 10):
//! `z = zc + sx·dx + sy·dy` at the one or two end offsets of a ROM word, with min and max.

use super::{PB, WORD_BITS, Z_BITS};
use rust_hdl::prelude::*;

/// Low half of a split 53-bit add (bits 0..27); the high half is bits 27..53.
const LO: usize = 27;
/// High half width.
const HI: usize = Z_BITS - LO;
const _: () = assert!(LO == 27 && HI == 26, "the kernel uses literal 27 and 26");

/// The depth calculator: `z = zc + sx·dx + sy·dy` at both ends of a ROM word, then min
/// and max. `dx`, `dy` are the word's 4-bit two's-complement fields, so `d·s = d0·s +
/// 2·d1·s + 4·d2·s − 8·d3·s`: each end is the sum of nine shifted terms (`zc`, four of
/// `sx`, four of `sy`; the `−8·d3·s` term as `!(s << 3)` plus a carry-in `d3`), no
/// multiplier.
///
/// Every carry chain is at most 28 bits long (for the clock: a 53-bit chain alone takes
/// about 2.7 ns on ECP5). Pipeline ([`DEPTH_LATENCY`](super::DEPTH_LATENCY) = 6 register
/// stages):
/// - D1: the terms and one carry-save level, 9 → 6 vectors per end (the ROM word's
///   offset bits each drive 53 term bits, so this stage keeps one logic level after
///   that wide fan-out);
/// - D2: three more carry-save levels, 6 → 4 → 3 → 2 (sum `s`, carry `k`);
/// - D3: the low 27 bits `s + k` with their carry-out (a 28-bit add);
/// - D4: the high 26 bits with that carry-in, so `z1`, `z2` are complete; beside it the
///   borrow of `z1 − z2` in the low 27 bits;
/// - D5: the high 26 bits of `z1 − z2` with that borrow-in give its sign (`|z| < 2^51`,
///   so the 53-bit difference does not overflow and bit 52 is the signed compare);
/// - D6: min and max selected by the sign.
///
/// Inputs sampled at edge `E` show on the outputs after edge `E + 5`. A carry-in `c` into
/// the high half is the carry of a 27-bit add `{a, 1} + {b, c}` (bit 0 is `1 + c`, so bits
/// `[26:1]` are `a + b + c`); a borrow-in likewise `{a, 0} − {b, c}`.
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
    // D1: six carry-save vectors per end.
    e1_a: DFF<Bits<Z_BITS>>,
    e1_b: DFF<Bits<Z_BITS>>,
    e1_c: DFF<Bits<Z_BITS>>,
    e1_d: DFF<Bits<Z_BITS>>,
    e1_e: DFF<Bits<Z_BITS>>,
    e1_f: DFF<Bits<Z_BITS>>,
    e2_a: DFF<Bits<Z_BITS>>,
    e2_b: DFF<Bits<Z_BITS>>,
    e2_c: DFF<Bits<Z_BITS>>,
    e2_d: DFF<Bits<Z_BITS>>,
    e2_e: DFF<Bits<Z_BITS>>,
    e2_f: DFF<Bits<Z_BITS>>,
    // D2: sum and carry per end.
    e1_s: DFF<Bits<Z_BITS>>,
    e1_k: DFF<Bits<Z_BITS>>,
    e2_s: DFF<Bits<Z_BITS>>,
    e2_k: DFF<Bits<Z_BITS>>,
    // D3: low sum with carry-out (bit 27), high halves of sum and carry.
    e1_lo: DFF<Bits<28>>,
    e1_hs: DFF<Bits<HI>>,
    e1_hk: DFF<Bits<HI>>,
    e2_lo: DFF<Bits<28>>,
    e2_hs: DFF<Bits<HI>>,
    e2_hk: DFF<Bits<HI>>,
    // D4: the depths and the low borrow of z1 − z2.
    z1_4: DFF<Bits<Z_BITS>>,
    z2_4: DFF<Bits<Z_BITS>>,
    bw_4: DFF<Bit>,
    // D5: the depths and z1 < z2.
    z1_5: DFF<Bits<Z_BITS>>,
    z2_5: DFF<Bits<Z_BITS>>,
    lt_5: DFF<Bit>,
    // D6: results.
    z1_r: DFF<Bits<Z_BITS>>,
    z2_r: DFF<Bits<Z_BITS>>,
    zmin_r: DFF<Bits<Z_BITS>>,
    zmax_r: DFF<Bits<Z_BITS>>,
    k_sext: Constant<Bits<Z_BITS>>,
    k_zero: Constant<Bits<Z_BITS>>,
    k_one: Constant<Bits<Z_BITS>>,
    k_zero_lo: Constant<Bits<28>>,
    k_zero_hi: Constant<Bits<HI>>,
    k_one_27: Constant<Bits<LO>>,
    k_sh1: Constant<Bits<8>>,
    k_sh2: Constant<Bits<8>>,
    k_sh3: Constant<Bits<8>>,
    k_sh27: Constant<Bits<8>>,
    zce: Signal<Local, Bits<Z_BITS>>,
    sxe: Signal<Local, Bits<Z_BITS>>,
    sye: Signal<Local, Bits<Z_BITS>>,
    tx0: Signal<Local, Bits<Z_BITS>>,
    tx1: Signal<Local, Bits<Z_BITS>>,
    tx2: Signal<Local, Bits<Z_BITS>>,
    tx3: Signal<Local, Bits<Z_BITS>>,
    ty0: Signal<Local, Bits<Z_BITS>>,
    ty1: Signal<Local, Bits<Z_BITS>>,
    ty2: Signal<Local, Bits<Z_BITS>>,
    ty3: Signal<Local, Bits<Z_BITS>>,
    sa: Signal<Local, Bits<Z_BITS>>,
    ca: Signal<Local, Bits<Z_BITS>>,
    sb: Signal<Local, Bits<Z_BITS>>,
    cb: Signal<Local, Bits<Z_BITS>>,
    sc: Signal<Local, Bits<Z_BITS>>,
    cc: Signal<Local, Bits<Z_BITS>>,
    sf: Signal<Local, Bits<Z_BITS>>,
    cf: Signal<Local, Bits<Z_BITS>>,
    l_a: Signal<Local, Bits<LO>>,
    l_b: Signal<Local, Bits<LO>>,
    h_a: Signal<Local, Bits<HI>>,
    h_b: Signal<Local, Bits<HI>>,
    w_a: Signal<Local, Bits<LO>>,
    w_b: Signal<Local, Bits<LO>>,
    /// Every add and subtract of D4 and D5, at 28 bits (one local, so that the bits no
    /// add reads, only bit 0, make one lint note).
    w28: Signal<Local, Bits<28>>,
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
            e1_a: Default::default(),
            e1_b: Default::default(),
            e1_c: Default::default(),
            e1_d: Default::default(),
            e1_e: Default::default(),
            e1_f: Default::default(),
            e2_a: Default::default(),
            e2_b: Default::default(),
            e2_c: Default::default(),
            e2_d: Default::default(),
            e2_e: Default::default(),
            e2_f: Default::default(),
            e1_s: Default::default(),
            e1_k: Default::default(),
            e2_s: Default::default(),
            e2_k: Default::default(),
            e1_lo: Default::default(),
            e1_hs: Default::default(),
            e1_hk: Default::default(),
            e2_lo: Default::default(),
            e2_hs: Default::default(),
            e2_hk: Default::default(),
            z1_4: Default::default(),
            z2_4: Default::default(),
            bw_4: Default::default(),
            z1_5: Default::default(),
            z2_5: Default::default(),
            lt_5: Default::default(),
            z1_r: Default::default(),
            z2_r: Default::default(),
            zmin_r: Default::default(),
            zmax_r: Default::default(),
            k_sext: Constant::new(((1u64 << Z_BITS) - (1u64 << PB)).to_bits()),
            k_zero: Constant::new(0u64.to_bits()),
            k_one: Constant::new(1u64.to_bits()),
            k_zero_lo: Constant::new(0u64.to_bits()),
            k_zero_hi: Constant::new(0u64.to_bits()),
            k_one_27: Constant::new(1u64.to_bits()),
            k_sh1: Constant::new(1u64.to_bits()),
            k_sh2: Constant::new(2u64.to_bits()),
            k_sh3: Constant::new(3u64.to_bits()),
            k_sh27: Constant::new((LO as u64).to_bits()),
            zce: Default::default(),
            sxe: Default::default(),
            sye: Default::default(),
            tx0: Default::default(),
            tx1: Default::default(),
            tx2: Default::default(),
            tx3: Default::default(),
            ty0: Default::default(),
            ty1: Default::default(),
            ty2: Default::default(),
            ty3: Default::default(),
            sa: Default::default(),
            ca: Default::default(),
            sb: Default::default(),
            cb: Default::default(),
            sc: Default::default(),
            cc: Default::default(),
            sf: Default::default(),
            cf: Default::default(),
            l_a: Default::default(),
            l_b: Default::default(),
            h_a: Default::default(),
            h_b: Default::default(),
            w_a: Default::default(),
            w_b: Default::default(),
            w28: Default::default(),
        }
    }
}

impl Logic for DepthCalc {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, e1_a, e1_b, e1_c, e1_d, e1_e, e1_f, e2_a, e2_b, e2_c, e2_d, e2_e, e2_f,
            e1_s, e1_k, e2_s, e2_k, e1_lo, e1_hs, e1_hk, e2_lo, e2_hs, e2_hk, z1_4, z2_4, bw_4,
            z1_5, z2_5, lt_5, z1_r, z2_r, zmin_r, zmax_r
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
        // D1, end 1 (dx = word[3:0], dy = word[7:4]): terms, then 9 -> 6.
        self.tx0.next = self.k_zero.val();
        self.tx1.next = self.k_zero.val();
        self.tx2.next = self.k_zero.val();
        self.tx3.next = self.k_zero.val();
        self.ty0.next = self.k_zero.val();
        self.ty1.next = self.k_zero.val();
        self.ty2.next = self.k_zero.val();
        self.ty3.next = self.k_zero.val();
        if self.word.val().get_bit(0) {
            self.tx0.next = self.sxe.val();
        }
        if self.word.val().get_bit(1) {
            self.tx1.next = self.sxe.val() << self.k_sh1.val();
        }
        if self.word.val().get_bit(2) {
            self.tx2.next = self.sxe.val() << self.k_sh2.val();
        }
        if self.word.val().get_bit(3) {
            self.tx3.next = !(self.sxe.val() << self.k_sh3.val());
        }
        if self.word.val().get_bit(4) {
            self.ty0.next = self.sye.val();
        }
        if self.word.val().get_bit(5) {
            self.ty1.next = self.sye.val() << self.k_sh1.val();
        }
        if self.word.val().get_bit(6) {
            self.ty2.next = self.sye.val() << self.k_sh2.val();
        }
        if self.word.val().get_bit(7) {
            self.ty3.next = !(self.sye.val() << self.k_sh3.val());
        }
        self.sa.next = (self.zce.val() ^ self.tx0.val()) ^ self.tx1.val();
        self.ca.next = (((self.zce.val() & self.tx0.val()) | (self.zce.val() & self.tx1.val()))
            | (self.tx0.val() & self.tx1.val()))
            << self.k_sh1.val();
        self.sb.next = (self.tx2.val() ^ self.tx3.val()) ^ self.ty0.val();
        self.cb.next = (((self.tx2.val() & self.tx3.val()) | (self.tx2.val() & self.ty0.val()))
            | (self.tx3.val() & self.ty0.val()))
            << self.k_sh1.val();
        self.sc.next = (self.ty1.val() ^ self.ty2.val()) ^ self.ty3.val();
        self.cc.next = (((self.ty1.val() & self.ty2.val()) | (self.ty1.val() & self.ty3.val()))
            | (self.ty2.val() & self.ty3.val()))
            << self.k_sh1.val();
        // The + 1 of the two negated terms, in the free bit 0 of two carry vectors.
        if self.word.val().get_bit(3) {
            self.cb.next = self.cb.val() | self.k_one.val();
        }
        if self.word.val().get_bit(7) {
            self.cc.next = self.cc.val() | self.k_one.val();
        }
        self.e1_a.d.next = self.sa.val();
        self.e1_b.d.next = self.ca.val();
        self.e1_c.d.next = self.sb.val();
        self.e1_d.d.next = self.cb.val();
        self.e1_e.d.next = self.sc.val();
        self.e1_f.d.next = self.cc.val();
        // D1, end 2 (dx = word[11:8], dy = word[15:12]): the same.
        self.tx0.next = self.k_zero.val();
        self.tx1.next = self.k_zero.val();
        self.tx2.next = self.k_zero.val();
        self.tx3.next = self.k_zero.val();
        self.ty0.next = self.k_zero.val();
        self.ty1.next = self.k_zero.val();
        self.ty2.next = self.k_zero.val();
        self.ty3.next = self.k_zero.val();
        if self.word.val().get_bit(8) {
            self.tx0.next = self.sxe.val();
        }
        if self.word.val().get_bit(9) {
            self.tx1.next = self.sxe.val() << self.k_sh1.val();
        }
        if self.word.val().get_bit(10) {
            self.tx2.next = self.sxe.val() << self.k_sh2.val();
        }
        if self.word.val().get_bit(11) {
            self.tx3.next = !(self.sxe.val() << self.k_sh3.val());
        }
        if self.word.val().get_bit(12) {
            self.ty0.next = self.sye.val();
        }
        if self.word.val().get_bit(13) {
            self.ty1.next = self.sye.val() << self.k_sh1.val();
        }
        if self.word.val().get_bit(14) {
            self.ty2.next = self.sye.val() << self.k_sh2.val();
        }
        if self.word.val().get_bit(15) {
            self.ty3.next = !(self.sye.val() << self.k_sh3.val());
        }
        self.sa.next = (self.zce.val() ^ self.tx0.val()) ^ self.tx1.val();
        self.ca.next = (((self.zce.val() & self.tx0.val()) | (self.zce.val() & self.tx1.val()))
            | (self.tx0.val() & self.tx1.val()))
            << self.k_sh1.val();
        self.sb.next = (self.tx2.val() ^ self.tx3.val()) ^ self.ty0.val();
        self.cb.next = (((self.tx2.val() & self.tx3.val()) | (self.tx2.val() & self.ty0.val()))
            | (self.tx3.val() & self.ty0.val()))
            << self.k_sh1.val();
        self.sc.next = (self.ty1.val() ^ self.ty2.val()) ^ self.ty3.val();
        self.cc.next = (((self.ty1.val() & self.ty2.val()) | (self.ty1.val() & self.ty3.val()))
            | (self.ty2.val() & self.ty3.val()))
            << self.k_sh1.val();
        if self.word.val().get_bit(11) {
            self.cb.next = self.cb.val() | self.k_one.val();
        }
        if self.word.val().get_bit(15) {
            self.cc.next = self.cc.val() | self.k_one.val();
        }
        self.e2_a.d.next = self.sa.val();
        self.e2_b.d.next = self.ca.val();
        self.e2_c.d.next = self.sb.val();
        self.e2_d.d.next = self.cb.val();
        self.e2_e.d.next = self.sc.val();
        self.e2_f.d.next = self.cc.val();
        // D2: 6 -> 4 -> 3 -> 2 per end.
        self.sa.next = (self.e1_a.q.val() ^ self.e1_b.q.val()) ^ self.e1_c.q.val();
        self.ca.next = (((self.e1_a.q.val() & self.e1_b.q.val())
            | (self.e1_a.q.val() & self.e1_c.q.val()))
            | (self.e1_b.q.val() & self.e1_c.q.val()))
            << self.k_sh1.val();
        self.sb.next = (self.e1_d.q.val() ^ self.e1_e.q.val()) ^ self.e1_f.q.val();
        self.cb.next = (((self.e1_d.q.val() & self.e1_e.q.val())
            | (self.e1_d.q.val() & self.e1_f.q.val()))
            | (self.e1_e.q.val() & self.e1_f.q.val()))
            << self.k_sh1.val();
        self.sf.next = (self.sa.val() ^ self.ca.val()) ^ self.sb.val();
        self.cf.next = (((self.sa.val() & self.ca.val()) | (self.sa.val() & self.sb.val()))
            | (self.ca.val() & self.sb.val()))
            << self.k_sh1.val();
        self.e1_s.d.next = (self.sf.val() ^ self.cf.val()) ^ self.cb.val();
        self.e1_k.d.next = (((self.sf.val() & self.cf.val()) | (self.sf.val() & self.cb.val()))
            | (self.cf.val() & self.cb.val()))
            << self.k_sh1.val();
        self.sa.next = (self.e2_a.q.val() ^ self.e2_b.q.val()) ^ self.e2_c.q.val();
        self.ca.next = (((self.e2_a.q.val() & self.e2_b.q.val())
            | (self.e2_a.q.val() & self.e2_c.q.val()))
            | (self.e2_b.q.val() & self.e2_c.q.val()))
            << self.k_sh1.val();
        self.sb.next = (self.e2_d.q.val() ^ self.e2_e.q.val()) ^ self.e2_f.q.val();
        self.cb.next = (((self.e2_d.q.val() & self.e2_e.q.val())
            | (self.e2_d.q.val() & self.e2_f.q.val()))
            | (self.e2_e.q.val() & self.e2_f.q.val()))
            << self.k_sh1.val();
        self.sf.next = (self.sa.val() ^ self.ca.val()) ^ self.sb.val();
        self.cf.next = (((self.sa.val() & self.ca.val()) | (self.sa.val() & self.sb.val()))
            | (self.ca.val() & self.sb.val()))
            << self.k_sh1.val();
        self.e2_s.d.next = (self.sf.val() ^ self.cf.val()) ^ self.cb.val();
        self.e2_k.d.next = (((self.sf.val() & self.cf.val()) | (self.sf.val() & self.cb.val()))
            | (self.cf.val() & self.cb.val()))
            << self.k_sh1.val();
        // D3: low 27 bits with carry-out; the high halves wait a clock.
        self.l_a.next = self.e1_s.q.val().get_bits::<27>(0);
        self.l_b.next = self.e1_k.q.val().get_bits::<27>(0);
        self.e1_lo.d.next = bit_cast::<28, LO>(self.l_a.val()) + bit_cast::<28, LO>(self.l_b.val());
        self.e1_hs.d.next = self.e1_s.q.val().get_bits::<26>(27);
        self.e1_hk.d.next = self.e1_k.q.val().get_bits::<26>(27);
        self.l_a.next = self.e2_s.q.val().get_bits::<27>(0);
        self.l_b.next = self.e2_k.q.val().get_bits::<27>(0);
        self.e2_lo.d.next = bit_cast::<28, LO>(self.l_a.val()) + bit_cast::<28, LO>(self.l_b.val());
        self.e2_hs.d.next = self.e2_s.q.val().get_bits::<26>(27);
        self.e2_hk.d.next = self.e2_k.q.val().get_bits::<26>(27);
        // D4: high 26 bits with the carry-in, {a, 1} + {b, c}; and the low borrow of
        // z1 − z2.
        self.h_a.next = self.e1_hs.q.val();
        self.h_b.next = self.e1_hk.q.val();
        self.w_a.next =
            (bit_cast::<LO, HI>(self.h_a.val()) << self.k_sh1.val()) | self.k_one_27.val();
        self.w_b.next = bit_cast::<LO, HI>(self.h_b.val()) << self.k_sh1.val();
        if self.e1_lo.q.val().get_bit(27) {
            self.w_b.next = self.w_b.val() | self.k_one_27.val();
        }
        self.w28.next = bit_cast::<28, LO>(self.w_a.val()) + bit_cast::<28, LO>(self.w_b.val());
        self.h_a.next = self.w28.val().get_bits::<26>(1);
        self.l_a.next = self.e1_lo.q.val().get_bits::<27>(0);
        self.z1_4.d.next = (bit_cast::<Z_BITS, HI>(self.h_a.val()) << self.k_sh27.val())
            | bit_cast::<Z_BITS, LO>(self.l_a.val());
        self.h_a.next = self.e2_hs.q.val();
        self.h_b.next = self.e2_hk.q.val();
        self.w_a.next =
            (bit_cast::<LO, HI>(self.h_a.val()) << self.k_sh1.val()) | self.k_one_27.val();
        self.w_b.next = bit_cast::<LO, HI>(self.h_b.val()) << self.k_sh1.val();
        if self.e2_lo.q.val().get_bit(27) {
            self.w_b.next = self.w_b.val() | self.k_one_27.val();
        }
        self.w28.next = bit_cast::<28, LO>(self.w_a.val()) + bit_cast::<28, LO>(self.w_b.val());
        self.h_a.next = self.w28.val().get_bits::<26>(1);
        self.l_b.next = self.e2_lo.q.val().get_bits::<27>(0);
        self.z2_4.d.next = (bit_cast::<Z_BITS, HI>(self.h_a.val()) << self.k_sh27.val())
            | bit_cast::<Z_BITS, LO>(self.l_b.val());
        self.w28.next = bit_cast::<28, LO>(self.l_a.val()) - bit_cast::<28, LO>(self.l_b.val());
        self.bw_4.d.next = self.w28.val().get_bit(27);
        // D5: sign of z1 − z2 from the high 26 bits and the borrow, {a, 0} − {b, bw}.
        self.h_a.next = self.z1_4.q.val().get_bits::<26>(27);
        self.h_b.next = self.z2_4.q.val().get_bits::<26>(27);
        self.w_a.next = bit_cast::<LO, HI>(self.h_a.val()) << self.k_sh1.val();
        self.w_b.next = bit_cast::<LO, HI>(self.h_b.val()) << self.k_sh1.val();
        if self.bw_4.q.val() {
            self.w_b.next = self.w_b.val() | self.k_one_27.val();
        }
        self.w28.next = bit_cast::<28, LO>(self.w_a.val()) - bit_cast::<28, LO>(self.w_b.val());
        self.lt_5.d.next = self.w28.val().get_bit(26);
        self.z1_5.d.next = self.z1_4.q.val();
        self.z2_5.d.next = self.z2_4.q.val();
        // D6: min and max.
        self.z1_r.d.next = self.z1_5.q.val();
        self.z2_r.d.next = self.z2_5.q.val();
        self.zmin_r.d.next = self.z2_5.q.val();
        self.zmax_r.d.next = self.z1_5.q.val();
        if self.lt_5.q.val() {
            self.zmin_r.d.next = self.z1_5.q.val();
            self.zmax_r.d.next = self.z2_5.q.val();
        }
        if self.rst.val() {
            self.e1_a.d.next = self.k_zero.val();
            self.e1_b.d.next = self.k_zero.val();
            self.e1_c.d.next = self.k_zero.val();
            self.e1_d.d.next = self.k_zero.val();
            self.e1_e.d.next = self.k_zero.val();
            self.e1_f.d.next = self.k_zero.val();
            self.e2_a.d.next = self.k_zero.val();
            self.e2_b.d.next = self.k_zero.val();
            self.e2_c.d.next = self.k_zero.val();
            self.e2_d.d.next = self.k_zero.val();
            self.e2_e.d.next = self.k_zero.val();
            self.e2_f.d.next = self.k_zero.val();
            self.e1_s.d.next = self.k_zero.val();
            self.e1_k.d.next = self.k_zero.val();
            self.e2_s.d.next = self.k_zero.val();
            self.e2_k.d.next = self.k_zero.val();
            self.e1_lo.d.next = self.k_zero_lo.val();
            self.e1_hs.d.next = self.k_zero_hi.val();
            self.e1_hk.d.next = self.k_zero_hi.val();
            self.e2_lo.d.next = self.k_zero_lo.val();
            self.e2_hs.d.next = self.k_zero_hi.val();
            self.e2_hk.d.next = self.k_zero_hi.val();
            self.z1_4.d.next = self.k_zero.val();
            self.z2_4.d.next = self.k_zero.val();
            self.bw_4.d.next = false;
            self.z1_5.d.next = self.k_zero.val();
            self.z2_5.d.next = self.k_zero.val();
            self.lt_5.d.next = false;
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
    fn random_planes_and_offsets_match_plain_arithmetic() {
        // One new input per clock; each result checked DEPTH_LATENCY clocks later against
        // i64 arithmetic (extreme planes included: carries cross the 27-bit split).
        let mut u = DepthCalc::new();
        u.connect_all();
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut rnd = || crate::xorshift64(&mut x);
        let lim = (1i64 << 47) - 1;
        let pick = |r: u64| -> i64 {
            match r % 6 {
                0 => lim,
                1 => -lim - 1,
                2 => 0,
                3 => (r >> 8) as i64 % 4096 - 2048,
                _ => ((r >> 3) as i64) >> 16,
            }
        };
        let mut want = std::collections::VecDeque::new();
        for t in 0..4000 {
            let p = [pick(rnd()), pick(rnd()), pick(rnd())];
            let w = rnd() & 0xFFFF;
            let d = |v: u64| ((v as i64) << 60) >> 60;
            let z1 = p[0] + p[1] * d(w) + p[2] * d(w >> 4);
            let z2 = p[0] + p[1] * d(w >> 8) + p[2] * d(w >> 12);
            want.push_back([z1, z2, z1.min(z2), z1.max(z2)]);
            u.zc.next = plane_bits(p[0]);
            u.sx.next = plane_bits(p[1]);
            u.sy.next = plane_bits(p[2]);
            u.word.next = w.to_bits();
            cycle!(u);
            if t + 1 >= DEPTH_LATENCY {
                let got = [&u.z1, &u.z2, &u.zmin, &u.zmax].map(|s| depth_of(s.val()));
                assert_eq!(
                    got,
                    want.pop_front().unwrap(),
                    "input {}",
                    t + 1 - DEPTH_LATENCY
                );
            }
        }
    }

    #[test]
    fn verilog_passes_yosys() {
        crate::mask_search::yosys_check("pixelproc_rtl_depth_calc", DepthCalc::new());
    }
}
