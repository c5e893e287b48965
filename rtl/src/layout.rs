//! The packed words of `pixelproc-formats` as named slices inside `#[hdl_gen]` kernels:
//! the span word of seed 001 section 3 (`attr, XL, XR, ZL, dZ, IL, dI`, plus tag, normal
//! class and decal; [`pixelproc_formats::SPAN_FIELDS`]) and the 99-bit readout word of a
//! processor ([`pixelproc_formats::regs::READOUT_FIELDS`]).
//!
//! A kernel cannot name a Rust constant as a bit offset: the code generator would emit
//! the constant's name into the Verilog. It does support RustHDL's struct-field
//! convention, which is used here: for a field `f`, `x.get_value_f()` reads and
//! `x.next.set_value_f(v)` writes the slice, and the generator asks the value for
//! `get_my_width_f()` and `get_my_offset_f()` and emits a part-select with those numbers
//! as literals. The traits below give `Bits<256>` and `Bits<74>` these methods, every
//! offset and width taken from the field tables in `pixelproc-formats`.

use crate::opcodes::OP_BITS;
use crate::pixel_processor::REL_W;
use pixelproc_formats::core_stream::{
    BEAT_DATA_BITS, KIND_BITS, OUT_COUNT, OUT_DSF, OUT_FSF, OUT_MASK, OUT_NCLASS, OUT_SOF,
    OUT_USER_BITS, OUT_ZB, SHADE_ADDR_BITS, SHADE_COUNT, SHADE_MASK, SHADE_NCLASS, TABLE_ADDR,
    TABLE_DROP, TABLE_FACTOR, TILE_BASE, TILE_BG, TILE_LAST, TILE_SOF,
};
use pixelproc_formats::fields::table_end;
use pixelproc_formats::regs::{
    RD_COUNT, RD_DSF, RD_FSF, RD_MASK, RD_NCLASS, RD_RGB, RD_SH, RD_WON, RD_ZB, READOUT_BITS,
};
use pixelproc_formats::Field;
use pixelproc_formats::{
    SPAN_ATTR, SPAN_CHAN, SPAN_DECAL, SPAN_DI_B, SPAN_DI_G, SPAN_DI_R, SPAN_DZ, SPAN_IL_B,
    SPAN_IL_G, SPAN_IL_R, SPAN_NCLASS, SPAN_WORD_BITS, SPAN_XL, SPAN_XR, SPAN_ZL,
};
use rust_hdl::prelude::*;

/// Width of the `cmd_word` port: one packed span word.
pub const SPAN_W: usize = SPAN_WORD_BITS as usize;
/// The three `IL` channels of the span word as one field (red in the low bits).
pub const SPAN_IL3: Field = SPAN_DZ.then("IL", 3 * SPAN_IL_R.width);
/// The three `dI` channels of the span word as one field (red in the low bits).
pub const SPAN_DI3: Field = SPAN_IL3.then("dI", 3 * SPAN_DI_R.width);
const _: () = assert!(SPAN_IL3.lsb == SPAN_IL_R.lsb && SPAN_DI3.lsb == SPAN_DI_R.lsb);

/// Token header field: opcode.
pub const HEAD_OP: Field = Field::first("op", OP_BITS);
/// Token header field: span attribute.
pub const HEAD_ATTR: Field = HEAD_OP.then("attr", SPAN_ATTR.width);
/// Token header field: decal flag.
pub const HEAD_DECAL: Field = HEAD_ATTR.then("decal", 1);
/// Token header field: normal class.
pub const HEAD_NCLASS: Field = HEAD_DECAL.then("nclass", SPAN_NCLASS.width);
/// Token header field: `XL − col − 1` (two's complement).
pub const HEAD_REL_L: Field = HEAD_NCLASS.then("rel_l", REL_W);
/// Token header field: `XR − col` (two's complement).
pub const HEAD_REL_R: Field = HEAD_REL_L.then("rel_r", REL_W);
/// Token header field: the span's shade channel.
pub const HEAD_CHAN: Field = HEAD_REL_R.then("chan", SPAN_CHAN.width);
/// Width of a token header: the part of the token that is not interpolated.
pub const HEAD_W: usize = table_end(&[
    HEAD_OP,
    HEAD_ATTR,
    HEAD_DECAL,
    HEAD_NCLASS,
    HEAD_REL_L,
    HEAD_REL_R,
    HEAD_CHAN,
]);

/// Width of the readout bus and of each processor's `rdo` output.
pub const READOUT_W: usize = READOUT_BITS;

/// Declares a trait of field accessors and implements it for one `Bits<N>`.
macro_rules! field_slices {
    (
        $(#[$doc:meta])* $tr:ident for $n:expr;
        bits { $($get:ident, $set:ident, $wid:ident, $off:ident: $f:path;)* }
        flags { $($bget:ident, $bset:ident, $bwid:ident, $boff:ident: $bf:path;)* }
    ) => {
        $(#[$doc])*
        pub trait $tr {
            $(
                #[doc = concat!("Reads field `", stringify!($f), "`.")]
                fn $get(&self) -> Bits<{ $f.width }>;
                #[doc = concat!("Writes field `", stringify!($f), "`.")]
                fn $set(&mut self, v: Bits<{ $f.width }>);
                #[doc = concat!("Width of `", stringify!($f), "` (read by the code generator).")]
                fn $wid(&self) -> usize;
                #[doc = concat!("LSB of `", stringify!($f), "` (read by the code generator).")]
                fn $off(&self) -> u32;
            )*
            $(
                #[doc = concat!("Reads the one-bit field `", stringify!($bf), "`.")]
                fn $bget(&self) -> Bit;
                #[doc = concat!("Writes the one-bit field `", stringify!($bf), "`.")]
                fn $bset(&mut self, v: Bit);
                #[doc = concat!("Width of `", stringify!($bf), "` (1).")]
                fn $bwid(&self) -> usize;
                #[doc = concat!("LSB of `", stringify!($bf), "` (read by the code generator).")]
                fn $boff(&self) -> u32;
            )*
        }
        impl $tr for Bits<{ $n }> {
            $(
                fn $get(&self) -> Bits<{ $f.width }> {
                    self.get_bits::<{ $f.width }>($f.lsb)
                }
                fn $set(&mut self, v: Bits<{ $f.width }>) {
                    self.set_bits::<{ $f.width }>($f.lsb, v)
                }
                fn $wid(&self) -> usize {
                    $f.width
                }
                fn $off(&self) -> u32 {
                    $f.lsb as u32
                }
            )*
            $(
                fn $bget(&self) -> Bit {
                    self.get_bit($bf.lsb)
                }
                fn $bset(&mut self, v: Bit) {
                    *self = self.replace_bit($bf.lsb, v)
                }
                fn $bwid(&self) -> usize {
                    1
                }
                fn $boff(&self) -> u32 {
                    $bf.lsb as u32
                }
            )*
        }
    };
}

field_slices! {
    /// The span word's fields as slices of the `cmd_word` value.
    SpanFields for SPAN_W;
    bits {
        get_value_attr, set_value_attr, get_my_width_attr, get_my_offset_attr: SPAN_ATTR;
        get_value_xl, set_value_xl, get_my_width_xl, get_my_offset_xl: SPAN_XL;
        get_value_xr, set_value_xr, get_my_width_xr, get_my_offset_xr: SPAN_XR;
        get_value_zl, set_value_zl, get_my_width_zl, get_my_offset_zl: SPAN_ZL;
        get_value_dz, set_value_dz, get_my_width_dz, get_my_offset_dz: SPAN_DZ;
        get_value_il_r, set_value_il_r, get_my_width_il_r, get_my_offset_il_r: SPAN_IL_R;
        get_value_il_g, set_value_il_g, get_my_width_il_g, get_my_offset_il_g: SPAN_IL_G;
        get_value_il_b, set_value_il_b, get_my_width_il_b, get_my_offset_il_b: SPAN_IL_B;
        get_value_di_r, set_value_di_r, get_my_width_di_r, get_my_offset_di_r: SPAN_DI_R;
        get_value_di_g, set_value_di_g, get_my_width_di_g, get_my_offset_di_g: SPAN_DI_G;
        get_value_di_b, set_value_di_b, get_my_width_di_b, get_my_offset_di_b: SPAN_DI_B;
        get_value_nclass, set_value_nclass, get_my_width_nclass, get_my_offset_nclass: SPAN_NCLASS;
        get_value_chan, set_value_chan, get_my_width_chan, get_my_offset_chan: SPAN_CHAN;
        get_value_il, set_value_il, get_my_width_il, get_my_offset_il: SPAN_IL3;
        get_value_di, set_value_di, get_my_width_di, get_my_offset_di: SPAN_DI3;
    }
    flags {
        get_value_decal, set_value_decal, get_my_width_decal, get_my_offset_decal: SPAN_DECAL;
    }
}

field_slices! {
    /// The token header's fields, as carried from the entry pipeline down the processor
    /// chain (one bus instead of six ports per processor).
    HeadFields for HEAD_W;
    bits {
        get_value_op, set_value_op, get_my_width_op, get_my_offset_op: HEAD_OP;
        get_value_attr, set_value_attr, get_my_width_attr, get_my_offset_attr: HEAD_ATTR;
        get_value_nclass, set_value_nclass, get_my_width_nclass, get_my_offset_nclass: HEAD_NCLASS;
        get_value_rel_l, set_value_rel_l, get_my_width_rel_l, get_my_offset_rel_l: HEAD_REL_L;
        get_value_rel_r, set_value_rel_r, get_my_width_rel_r, get_my_offset_rel_r: HEAD_REL_R;
        get_value_chan, set_value_chan, get_my_width_chan, get_my_offset_chan: HEAD_CHAN;
    }
    flags {
        get_value_decal, set_value_decal, get_my_width_decal, get_my_offset_decal: HEAD_DECAL;
    }
}

field_slices! {
    /// The readout word's fields as slices of a processor's `rdo` value.
    ReadoutFields for READOUT_W;
    bits {
        get_value_count, set_value_count, get_my_width_count, get_my_offset_count: RD_COUNT;
        get_value_rgb, set_value_rgb, get_my_width_rgb, get_my_offset_rgb: RD_RGB;
        get_value_zb, set_value_zb, get_my_width_zb, get_my_offset_zb: RD_ZB;
        get_value_mask, set_value_mask, get_my_width_mask, get_my_offset_mask: RD_MASK;
        get_value_nclass, set_value_nclass, get_my_width_nclass, get_my_offset_nclass: RD_NCLASS;
        get_value_sh, set_value_sh, get_my_width_sh, get_my_offset_sh: RD_SH;
    }
    flags {
        get_value_fsf, set_value_fsf, get_my_width_fsf, get_my_offset_fsf: RD_FSF;
        get_value_dsf, set_value_dsf, get_my_width_dsf, get_my_offset_dsf: RD_DSF;
        get_value_won, set_value_won, get_my_width_won, get_my_offset_won: RD_WON;
    }
}

/// Width of a command beat as the core's input FIFO stores it: a frame flag (1: the kind
/// is TILE or END, decoded as the beat enters the FIFO) in bit 0, where the FIFO's
/// look-ahead port `next_tag` reads it, then the beat kind (4), then `tdata` (256).
pub const BEAT_W: usize = 1 + KIND_BITS + BEAT_DATA_BITS;
/// Beat field: the frame flag (`kind` is TILE or END).
pub const BEAT_FRAME: Field = Field::first("frame", 1);
/// Beat field: the kind (`tuser`).
pub const BEAT_KIND: Field = BEAT_FRAME.then("kind", KIND_BITS);
/// Beat field: `tdata`.
pub const BEAT_DATA: Field = BEAT_KIND.then("tdata", BEAT_DATA_BITS);
const _: () = assert!(BEAT_DATA.end() == BEAT_W);
/// Pixel-stream beat field: RGB888 (`tdata`).
pub const PIX_RGB: Field = Field::first("rgb", 24);
/// Pixel-stream beat field: `tuser`.
pub const PIX_USER: Field = PIX_RGB.then("user", OUT_USER_BITS);
/// Pixel-stream beat field: `tlast`.
pub const PIX_LAST: Field = PIX_USER.then("last", 1);
/// Width of a pixel-stream beat as the output FIFO stores it.
pub const PIX_W: usize = PIX_LAST.end();

/// TABLE beat: the whole entry, `{DROP, FACTOR}` (what the shading table stores).
pub const TABLE_ENTRY: Field = TABLE_ADDR.then("entry", TABLE_FACTOR.width + TABLE_DROP.width);
const _: () =
    assert!(TABLE_DROP.lsb == TABLE_FACTOR.end() && TABLE_ENTRY.end() == TABLE_DROP.end());

field_slices! {
    /// A stored command beat: frame flag, kind and data.
    BeatFields for BEAT_W;
    bits {
        get_value_tdata, set_value_tdata, get_my_width_tdata, get_my_offset_tdata: BEAT_DATA;
        get_value_kind, set_value_kind, get_my_width_kind, get_my_offset_kind: BEAT_KIND;
    }
    flags {
        get_value_frame, set_value_frame, get_my_width_frame, get_my_offset_frame: BEAT_FRAME;
    }
}

field_slices! {
    /// The TILE, TABLE and LATCH_SHADOW beats' fields as slices of `tdata`.
    TileFields for SPAN_W;
    bits {
        get_value_bg, set_value_bg, get_my_width_bg, get_my_offset_bg: TILE_BG;
        get_value_base, set_value_base, get_my_width_base, get_my_offset_base: TILE_BASE;
        get_value_last, set_value_last, get_my_width_last, get_my_offset_last: TILE_LAST;
        get_value_taddr, set_value_taddr, get_my_width_taddr, get_my_offset_taddr: TABLE_ADDR;
        get_value_factor, set_value_factor, get_my_width_factor, get_my_offset_factor: TABLE_FACTOR;
        get_value_tentry, set_value_tentry, get_my_width_tentry, get_my_offset_tentry: TABLE_ENTRY;
    }
    flags {
        get_value_sof, set_value_sof, get_my_width_sof, get_my_offset_sof: TILE_SOF;
    }
}

field_slices! {
    /// A stored pixel beat: RGB, `tuser`, `tlast`.
    PixFields for PIX_W;
    bits {
        get_value_prgb, set_value_prgb, get_my_width_prgb, get_my_offset_prgb: PIX_RGB;
        get_value_puser, set_value_puser, get_my_width_puser, get_my_offset_puser: PIX_USER;
    }
    flags {
        get_value_plast, set_value_plast, get_my_width_plast, get_my_offset_plast: PIX_LAST;
    }
}

field_slices! {
    /// The pixel stream's `tuser` fields.
    UserFields for OUT_USER_BITS;
    bits {
        get_value_uzb, set_value_uzb, get_my_width_uzb, get_my_offset_uzb: OUT_ZB;
        get_value_ucount, set_value_ucount, get_my_width_ucount, get_my_offset_ucount: OUT_COUNT;
        get_value_umask, set_value_umask, get_my_width_umask, get_my_offset_umask: OUT_MASK;
        get_value_unclass, set_value_unclass, get_my_width_unclass, get_my_offset_unclass: OUT_NCLASS;
    }
    flags {
        get_value_usof, set_value_usof, get_my_width_usof, get_my_offset_usof: OUT_SOF;
        get_value_udsf, set_value_udsf, get_my_width_udsf, get_my_offset_udsf: OUT_DSF;
        get_value_ufsf, set_value_ufsf, get_my_width_ufsf, get_my_offset_ufsf: OUT_FSF;
    }
}

field_slices! {
    /// The shading-table address fields.
    ShadeAddrFields for SHADE_ADDR_BITS;
    bits {
        get_value_scount, set_value_scount, get_my_width_scount, get_my_offset_scount: SHADE_COUNT;
        get_value_smask, set_value_smask, get_my_width_smask, get_my_offset_smask: SHADE_MASK;
        get_value_snclass, set_value_snclass, get_my_width_snclass, get_my_offset_snclass: SHADE_NCLASS;
    }
    flags {}
}

field_slices! {
    /// The low bits of the readout word's counter and mask that address the shading
    /// table (one part-select each: chained selects are not Verilog-2005).
    ReadoutLowFields for READOUT_W;
    bits {
        get_value_count_lo, set_value_count_lo, get_my_width_count_lo, get_my_offset_count_lo: RD_COUNT_LO;
        get_value_mask_lo, set_value_mask_lo, get_my_width_mask_lo, get_my_offset_mask_lo: RD_MASK_LO;
    }
    flags {}
}

/// The counter's bits that address the shading table.
pub const RD_COUNT_LO: Field = Field {
    name: "COUNT",
    lsb: RD_COUNT.lsb,
    width: SHADE_COUNT.width,
};
/// The light mask's bits that address the shading table.
pub const RD_MASK_LO: Field = Field {
    name: "MASK",
    lsb: RD_MASK.lsb,
    width: SHADE_MASK.width,
};

#[cfg(test)]
mod tests {
    use super::*;
    use pixelproc_formats::regs::SAMPLE_STATE;
    use pixelproc_formats::{Attr, SpanWord};

    #[test]
    fn span_slices_read_what_pack_wrote() {
        let w = SpanWord {
            chan: 0,
            attr: Attr::Ev,
            xl: 17,
            xr: 4000,
            zl: 0x9_8765_4321,
            dz: -5,
            il: [1, 2, 3],
            di: [-1, 7, -9],
            tag: 0xBEEF,
            nclass: 0xA5,
            decal: true,
        };
        let l = w.pack().unwrap();
        let mut b: Bits<SPAN_W> = Bits::default();
        for (i, limb) in l.iter().enumerate() {
            b.set_bits::<64>(64 * i, limb.to_bits());
        }
        assert_eq!(b.get_value_attr().to_u64(), 2);
        assert_eq!(b.get_value_xl().to_u64(), 17);
        assert_eq!(b.get_value_xr().to_u64(), 4000);
        assert_eq!(b.get_value_zl().to_u64(), 0x9_8765_4321);
        assert_eq!(b.get_value_il_b().to_u64(), 3);
        assert_eq!(b.get_value_nclass().to_u64(), 0xA5);
        assert!(b.get_value_decal());
        assert_eq!((b.get_my_offset_decal(), b.get_my_width_zl()), (247, 36));
    }

    #[test]
    fn readout_slices_match_pack_readout() {
        let s = SAMPLE_STATE;
        let mut b: Bits<READOUT_W> = Bits::default();
        b.set_value_nclass(7u64.to_bits());
        b.set_value_mask(0x81u64.to_bits());
        b.set_value_zb(0xABCDEFu64.to_bits());
        b.set_value_rgb(0x123456u64.to_bits());
        b.set_value_dsf(true);
        b.set_value_fsf(false);
        b.set_value_count(200u64.to_bits());
        b.set_value_sh(0x9A8B7Cu64.to_bits());
        b.set_value_won(true);
        let w = s.pack_readout();
        let lo: u64 = b.get_bits::<64>(0).to_u64();
        let hi: u64 = b.get_bits::<{ READOUT_W - 64 }>(64).to_u64();
        assert_eq!(((hi as u128) << 64) | lo as u128, w);
        assert_eq!(b.get_value_zb().to_u64(), 0xABCDEF);
    }
}
