//! One colour channel of the array's entry pipeline (seed 001, Matsumoto, section 3:
//! the intensity at the tile's first column, `IL + max(0, base − XL)·dI`).
//!
//! Stages E2 to E4 of [`crate::pixel_array`] for one channel: E2 registers `IL` and
//! `dI` (0 unless the command is a SPAN), E3 forms the two 16 × 16 partial products of
//! the tile offset `m` and `dI` and `IL − s·m·2^21`, E4 adds them to two partial sums,
//! `IL + m·dI = (IL − s·m·2^21) + m·u21` (`u21` = `dI` as unsigned, `s` its sign). The
//! outputs are the sum of the E4 registers and the E4 copy of `dI`: the channel's part of
//! the token for processor 0. The array builds three of these and owns `m` (shared with the depth).

use crate::colour_lane::DI_W;
use crate::mul_reg::MulReg;
use crate::pixel_processor::IACC_W;
use pixelproc_formats::SPAN_IL_R;
use rust_hdl::prelude::*;

/// Width of one `IL` channel.
pub(crate) const IL_W: usize = SPAN_IL_R.width;
/// Operand width of the entry multipliers (RustHDL multiplies 16 × 16 bits only).
pub(crate) const MUL_W: usize = 16;
/// Width of one 16 × 16 partial product.
pub(crate) const PROD_W: usize = 2 * MUL_W;
/// Bits of `dI` above its low multiplier operand.
const DI_HI_W: usize = DI_W - MUL_W;
// A kernel can only take literal bit positions: the operand split at 16, the sign bit 20
// and the weight 2^21 below are these widths.
const _: () = assert!(MUL_W == 16 && DI_W == 21);

/// One channel's E2..E4 registers. Build with [`EntryChannel::new`].
#[derive(LogicBlock)]
pub struct EntryChannel {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// `IL` of the command in E1, Q8.12.
    pub il: Signal<In, Bits<IL_W>>,
    /// `dI` of the command in E1, Q9.12 two's complement.
    pub di: Signal<In, Bits<DI_W>>,
    /// The command in E1 is a SPAN (otherwise `dI` is taken as 0).
    pub span: Signal<In, Bit>,
    /// The tile offset `m` E2 loads (the multipliers register their own copies).
    pub m1: Signal<In, Bits<MUL_W>>,
    /// The tile offset `m` registered in E2.
    pub m2: Signal<In, Bits<MUL_W>>,
    /// `IL + m·dI`, Q22.12 two's complement: processor 0's accumulator.
    pub i: Signal<Out, Bits<IACC_W>>,
    /// `dI` in E4.
    pub o_di: Signal<Out, Bits<DI_W>>,
    e2_il: DFF<Bits<IL_W>>,
    e2_di: DFF<Bits<DI_W>>,
    /// `IL − s·m·2^21` (`s` the sign of dI): the signed product's correction taken here
    /// from E2's fabric registers, so that E4's adds take the DSP products with nothing
    /// in front of them.
    e3_ils: DFF<Bits<IACC_W>>,
    e3_di: DFF<Bits<DI_W>>,
    /// The partial products m·dI (low 16 bits of dI, the bits above): operands registered
    /// with E2, products with E3 (on an FPGA the DSP block's own registers).
    mp: [MulReg; 2],
    /// The value E2's `dI` register loads.
    l_di1: Signal<Local, Bits<DI_W>>,
    e4_di: DFF<Bits<DI_W>>,
    e4_a: DFF<Bits<IACC_W>>,
    e4_b: DFF<Bits<IACC_W>>,
    l_dihi: Signal<Local, Bits<MUL_W>>,
    k_zero: Constant<Bits<DI_W>>,
}

impl EntryChannel {
    /// A channel with its constants set and its registers at 0.
    pub fn new() -> Self {
        EntryChannel {
            clock: Default::default(),
            il: Default::default(),
            di: Default::default(),
            span: Default::default(),
            m1: Default::default(),
            m2: Default::default(),
            i: Default::default(),
            o_di: Default::default(),
            e2_il: Default::default(),
            e2_di: Default::default(),
            e3_ils: Default::default(),
            e3_di: Default::default(),
            mp: Default::default(),
            l_di1: Default::default(),
            e4_di: Default::default(),
            e4_a: Default::default(),
            e4_b: Default::default(),
            l_dihi: Default::default(),
            k_zero: Constant::new(0u64.to_bits()),
        }
    }
}

impl Default for EntryChannel {
    fn default() -> Self {
        Self::new()
    }
}

impl Logic for EntryChannel {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, e2_il, e2_di, e3_ils, e3_di, e4_di, e4_a, e4_b);
        // ---- E2: no increment unless SPAN.
        self.e2_il.d.next = self.il.val();
        self.l_di1.next = self.k_zero.val();
        if self.span.val() {
            self.l_di1.next = self.di.val();
        }
        self.e2_di.d.next = self.l_di1.val();
        // ---- E3: partial products m·dI, 16×16 unsigned, of the operands E2 loads.
        self.e3_ils.d.next = bit_cast::<IACC_W, IL_W>(self.e2_il.q.val());
        if self.e2_di.q.val().get_bit(20) {
            self.e3_ils.d.next = bit_cast::<IACC_W, IL_W>(self.e2_il.q.val())
                - (bit_cast::<IACC_W, MUL_W>(self.m2.val()) << 21);
        }
        self.e3_di.d.next = self.e2_di.q.val();
        self.l_dihi.next = bit_cast::<MUL_W, DI_HI_W>(self.l_di1.val().get_bits::<DI_HI_W>(16));
        for k in 0..2 {
            self.mp[k].clock.next = self.clock.val();
            self.mp[k].a.next = self.m1.val();
        }
        self.mp[0].b.next = self.l_di1.val().get_bits::<MUL_W>(0);
        self.mp[1].b.next = self.l_dihi.val();
        // ---- E4: m·dI = m·u21 − s·m·2^21, the second term in E3's `e3_ils`.
        self.e4_di.d.next = self.e3_di.q.val();
        self.e4_a.d.next = self.e3_ils.q.val() + bit_cast::<IACC_W, PROD_W>(self.mp[0].p.val());
        self.e4_b.d.next = bit_cast::<IACC_W, PROD_W>(self.mp[1].p.val()) << 16;
        self.i.next = self.e4_a.q.val() + self.e4_b.q.val();
        self.o_di.next = self.e4_di.q.val();
    }
}
