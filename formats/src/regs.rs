//! The registers of one pixel processor (seed 001, Matsumoto: section 3 "scanline
//! Z-buffer" for `ZB` and the intensity, section 4 for the shadow flags DSF and FSF,
//! section 6 for the counter, the light mask and the normal class), and the packed
//! readout word the array's readout port carries.
//!
//! One record, [`ProcState`], serves the golden model (`pixelproc_sim::pixel_array`
//! re-exports it) and the RTL probes (`pixelproc_rtl::pixel_processor::ProcRegs` is the
//! same type), so the two are compared field for field without conversion.
//!
//! The readout word ([`READOUT_FIELDS`], [`READOUT_BITS`] = 99 bits, LSB first) is what
//! each RTL processor drives onto the array's OR-combined readout bus, what the array
//! slices into its `rd_*` ports, and what the external testbench's `expect.hex` holds
//! (`docs/formats.md` prints the table).

use crate::fields::{table_end, Field};
use crate::{NCLASS_BITS, Z_BITS};

/// The registers of one pixel processor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ProcState {
    /// Depth buffer value `ZB` (24 bits).
    pub zb: u32,
    /// Intensity, RGB888 packed.
    pub rgb: u32,
    /// Shadow decision flag.
    pub dsf: bool,
    /// Final shadow flag.
    pub fsf: bool,
    /// Number of point lights that shadow this pixel (area lights, section 6).
    pub count: u8,
    /// Which point lights shadow this pixel, one bit per light (section 6).
    pub mask: u8,
    /// Normal class of the visible surface (from the span word's `nclass`, section 6).
    pub nclass: u8,
    /// Shade register 1, RGB888: the visible surface's intensity with shadowing light 0
    /// removed (written by span words with `chan = 1`; exact shading in shadow).
    pub sh: u32,
    /// The last polygon span (`chan = 0`) covering this processor passed its depth test:
    /// the shade-channel spans that follow it may write.
    pub won: bool,
}

// SAFETY: every field is an integer or a `bool`, for which all-zero bits are a valid value
// (0, `false`); the all-zero `ProcState` is `ProcState::default()` (tested below). A field
// added later must keep both true (no reference, no enum without a zero variant). It lets a
// frame of processor states be allocated as zeroed memory (`bytemuck::zeroed_vec`).
unsafe impl bytemuck::Zeroable for ProcState {}

/// Width of the intensity register (RGB888).
pub const RGB_BITS: usize = 24;
/// Width of the shadow counter.
pub const COUNT_BITS: usize = 8;
/// Width of the light mask (one bit per point light).
pub const MASK_BITS: usize = 8;

/// Readout field `COUNT`.
pub const RD_COUNT: Field = Field::first("COUNT", COUNT_BITS);
/// Readout field `FSF`.
pub const RD_FSF: Field = RD_COUNT.then("FSF", 1);
/// Readout field `DSF`.
pub const RD_DSF: Field = RD_FSF.then("DSF", 1);
/// Readout field `RGB`.
pub const RD_RGB: Field = RD_DSF.then("RGB", RGB_BITS);
/// Readout field `ZB`.
pub const RD_ZB: Field = RD_RGB.then("ZB", Z_BITS as usize);
/// Readout field `MASK`.
pub const RD_MASK: Field = RD_ZB.then("MASK", MASK_BITS);
/// Readout field `NCLASS`.
pub const RD_NCLASS: Field = RD_MASK.then("NCLASS", NCLASS_BITS as usize);
/// Readout field `SH` (shade register 1).
pub const RD_SH: Field = RD_NCLASS.then("SH", RGB_BITS);
/// Readout field `WON`.
pub const RD_WON: Field = RD_SH.then("WON", 1);
/// The readout word, LSB first.
pub const READOUT_FIELDS: &[Field] = &[
    RD_COUNT, RD_FSF, RD_DSF, RD_RGB, RD_ZB, RD_MASK, RD_NCLASS, RD_SH, RD_WON,
];
/// Width of the readout word.
pub const READOUT_BITS: usize = table_end(READOUT_FIELDS);

/// A state whose fields all differ (`ZB` 0xABCDEF, RGB 0x123456, DSF set, COUNT 200, MASK
/// 0x81, NCLASS 7), for round-trip checks of the readout layout.
pub const SAMPLE_STATE: ProcState = ProcState {
    zb: 0xABCDEF,
    rgb: 0x123456,
    dsf: true,
    fsf: false,
    count: 200,
    mask: 0x81,
    nclass: 7,
    sh: 0x9A8B7C,
    won: true,
};

impl ProcState {
    /// The readout word of these registers (fields wider than their slot are truncated).
    pub fn pack_readout(&self) -> u128 {
        let values = [
            self.count as u64,
            self.fsf as u64,
            self.dsf as u64,
            self.rgb as u64,
            self.zb as u64,
            self.mask as u64,
            self.nclass as u64,
            self.sh as u64,
            self.won as u64,
        ];
        let mut w = 0u128;
        for (f, v) in READOUT_FIELDS.iter().zip(values) {
            f.put_u128(&mut w, v);
        }
        w
    }

    /// Inverse of [`ProcState::pack_readout`].
    pub fn unpack_readout(w: u128) -> ProcState {
        ProcState {
            zb: RD_ZB.get_u128(w) as u32,
            rgb: RD_RGB.get_u128(w) as u32,
            dsf: RD_DSF.get_u128(w) == 1,
            fsf: RD_FSF.get_u128(w) == 1,
            count: RD_COUNT.get_u128(w) as u8,
            mask: RD_MASK.get_u128(w) as u8,
            nclass: RD_NCLASS.get_u128(w) as u8,
            sh: RD_SH.get_u128(w) as u32,
            won: RD_WON.get_u128(w) == 1,
        }
    }

    /// The same registers with the shade channel (SH, WON) cleared: what the core's debug
    /// `tuser` carries (SH reaches the output only through the shaded colour).
    pub fn without_shade_channel(mut self) -> ProcState {
        self.sh = 0;
        self.won = false;
        self
    }

    /// The same registers with the shadow registers (DSF, FSF, COUNT, MASK, SH, WON)
    /// cleared: what a processor built without the shadow logic reads.
    pub fn without_shadow_regs(mut self) -> ProcState {
        self.dsf = false;
        self.fsf = false;
        self.count = 0;
        self.mask = 0;
        self.sh = 0;
        self.won = false;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fields::{parse_doc_table, table_rows};

    /// A zeroed state (what a frame allocated as zeroed memory starts from) is the
    /// default state, field by field.
    #[test]
    fn zeroed_state_is_the_default() {
        let z: ProcState = bytemuck::Zeroable::zeroed();
        assert_eq!(z, ProcState::default());
        let v: Vec<ProcState> = bytemuck::zeroed_vec(3);
        assert_eq!(v, vec![ProcState::default(); 3]);
    }

    #[test]
    fn readout_is_99_bits_and_round_trips() {
        assert_eq!(READOUT_BITS, 99);
        let s = SAMPLE_STATE;
        assert_eq!(ProcState::unpack_readout(s.pack_readout()), s);
        // The layout `{WON, SH, NCLASS, MASK, ZB, RGB, DSF, FSF, COUNT}`.
        let old = (1u128 << 98)
            | (0x9A8B7Cu128 << 74)
            | (7u128 << 66)
            | (0x81u128 << 58)
            | (0xABCDEFu128 << 34)
            | (0x123456u128 << 10)
            | (1u128 << 9)
            | 200;
        assert_eq!(s.pack_readout(), old);
    }

    #[test]
    fn readout_table_matches_docs() {
        let doc = include_str!("../../docs/formats.md");
        assert_eq!(
            parse_doc_table(doc, "## The readout word"),
            table_rows(READOUT_FIELDS)
        );
    }
}
