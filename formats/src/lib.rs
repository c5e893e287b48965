//! Bit formats shared by the golden model (`pixelproc-sim`) and the RTL (`pixelproc-rtl`).
//!
//! Everything downstream of the snapping step is integer fixed point in the formats
//! below; `docs/formats.md` draws the same layouts bit by bit. Names carry their unit:
//! `_q8` is a signed pixel coordinate with 8 fractional bits, `z24` a 24-bit depth,
//! `_q12` a value with 12 fractional bits.
//!
//! The span word is the one the pixel-processor array of seed 001 (Matsumoto,
//! section 3 "span data") consumes: `(attr, XL, XR, ZL, dZ, IL, dI)`, extended with an
//! object tag and a normal class.

#![deny(missing_docs)]

pub mod abuffer;
pub mod core_stream;
pub mod fields;
pub mod opcodes;
pub mod regs;

pub use fields::Field;
use thiserror::Error;

/// Fractional bits of a snapped vertex coordinate (1/256 pixel, D3D11-class).
pub const SUBPIXEL_BITS: u32 = 8;
/// One pixel in snapped units.
pub const SUBPIXEL_ONE: i32 = 1 << SUBPIXEL_BITS;
/// Largest screen width or height the formats support (`XL`, `XR` are [`X_BITS`] wide).
pub const MAX_SCREEN: u32 = 1 << X_BITS;
/// Largest column a span word (and so a CHECK range) can name.
pub const MAX_X: u16 = (MAX_SCREEN - 1) as u16;
/// Largest magnitude of a snapped vertex coordinate, in pixels (guard band).
/// Vertices beyond it are rejected at setup.
pub const MAX_COORD_PX: i32 = 16384;

/// Bits of the depth buffer value. 0 is nearest.
pub const Z_BITS: u32 = 24;
/// The clear ("far") value of the depth buffer; geometry never reaches it.
pub const Z_FAR: u32 = (1 << Z_BITS) - 1;
/// Smallest depth a snapped vertex may have.
pub const Z_GEOM_MIN: u32 = 16;
/// Largest depth a snapped vertex may have; the margin to [`Z_FAR`] absorbs the
/// sub-unit interpolation error of the span format so no pixel ever reaches `Z_FAR`.
pub const Z_GEOM_MAX: u32 = Z_FAR - 16;
/// Fractional bits of a depth value in a span word (`ZL`, `dZ`): depth units are
/// `2^-DEPTH_FRAC_BITS`.
pub const DEPTH_FRAC_BITS: u32 = 12;
/// One depth unit in span-word fixed point (`1 << DEPTH_FRAC_BITS`).
pub const DEPTH_ONE: i64 = 1 << DEPTH_FRAC_BITS;
/// Fractional bits of an intensity value in a span word (`IL`, `dI`): one step of the
/// 0..255 scale is `2^INTENSITY_FRAC_BITS`.
pub const INTENSITY_FRAC_BITS: u32 = 12;
/// One step of the 0..255 intensity scale in span-word fixed point.
pub const INTENSITY_ONE: u32 = 1 << INTENSITY_FRAC_BITS;
/// The rounding offset folded into every intensity (half a step), so that the array's
/// truncating `v >> INTENSITY_FRAC_BITS` rounds.
pub const INTENSITY_ROUND: u32 = INTENSITY_ONE / 2;
/// Fractional bits of `ZL` and `dZ` in a span word (the span-field spelling of
/// [`DEPTH_FRAC_BITS`]).
pub const Z_FRAC: u32 = DEPTH_FRAC_BITS;
/// Fractional bits of `IL` and `dI` in a span word (the span-field spelling of
/// [`INTENSITY_FRAC_BITS`]).
pub const I_FRAC: u32 = INTENSITY_FRAC_BITS;

/// Width of the span attribute code ([`Attr`]).
pub const ATTR_BITS: u32 = 2;
/// Width of `XL`/`XR` fields.
pub const X_BITS: u32 = 12;
/// Width of the `ZL` field: unsigned Q24.12.
pub const ZL_BITS: u32 = 36;
/// Width of the `dZ` field: two's complement Q26.12 (|dZ| ≤ 2^25 depth units per pixel).
pub const DZ_BITS: u32 = 38;
/// Width of one `IL` channel: unsigned Q8.12.
pub const IL_BITS: u32 = 20;
/// Width of one `dI` channel: two's complement Q9.12 (|dI| ≤ 255 per pixel).
pub const DI_BITS: u32 = 21;
/// Width of the object tag.
pub const TAG_BITS: u32 = 16;
/// Width of the normal-class field (seed 001 section 6, several lights).
pub const NCLASS_BITS: u32 = 8;
/// Width of the shade-channel field: 0 for a polygon's own span, `1..=MAX_SHADE_CHANNELS`
/// for the span carrying its intensity with one shadowing light removed.
pub const CHAN_BITS: u32 = 4;
/// Largest shade channel a span word can name (one per shadowing light: eight point lights
/// and one area light).
pub const MAX_SHADE_CHANNELS: u8 = 9;
/// Width of a packed span word (the remaining top bits are zero, reserved).
pub const SPAN_WORD_BITS: u32 = 256;

/// Span word field `attr` ([`Attr`] code), bits 1:0.
pub const SPAN_ATTR: Field = Field::first("attr", ATTR_BITS as usize);
/// Span word field `XL`.
pub const SPAN_XL: Field = SPAN_ATTR.then("XL", X_BITS as usize);
/// Span word field `XR`.
pub const SPAN_XR: Field = SPAN_XL.then("XR", X_BITS as usize);
/// Span word field `ZL`.
pub const SPAN_ZL: Field = SPAN_XR.then("ZL", ZL_BITS as usize);
/// Span word field `dZ`.
pub const SPAN_DZ: Field = SPAN_ZL.then("dZ", DZ_BITS as usize);
/// Span word field `IL_r`.
pub const SPAN_IL_R: Field = SPAN_DZ.then("IL_r", IL_BITS as usize);
/// Span word field `IL_g`.
pub const SPAN_IL_G: Field = SPAN_IL_R.then("IL_g", IL_BITS as usize);
/// Span word field `IL_b`.
pub const SPAN_IL_B: Field = SPAN_IL_G.then("IL_b", IL_BITS as usize);
/// Span word field `dI_r`.
pub const SPAN_DI_R: Field = SPAN_IL_B.then("dI_r", DI_BITS as usize);
/// Span word field `dI_g`.
pub const SPAN_DI_G: Field = SPAN_DI_R.then("dI_g", DI_BITS as usize);
/// Span word field `dI_b`.
pub const SPAN_DI_B: Field = SPAN_DI_G.then("dI_b", DI_BITS as usize);
/// Span word field `tag`.
pub const SPAN_TAG: Field = SPAN_DI_B.then("tag", TAG_BITS as usize);
/// Span word field `nclass`.
pub const SPAN_NCLASS: Field = SPAN_TAG.then("nclass", NCLASS_BITS as usize);
/// Span word field `decal`.
pub const SPAN_DECAL: Field = SPAN_NCLASS.then("decal", 1);
/// Span word field `chan` (shade channel).
pub const SPAN_CHAN: Field = SPAN_DECAL.then("chan", CHAN_BITS as usize);
/// The `IL` fields, R, G, B.
pub const SPAN_IL: [Field; 3] = [SPAN_IL_R, SPAN_IL_G, SPAN_IL_B];
/// The `dI` fields, R, G, B.
pub const SPAN_DI: [Field; 3] = [SPAN_DI_R, SPAN_DI_G, SPAN_DI_B];
/// The span word, LSB first: the one table `SpanWord::pack`/`unpack`, the RTL decode
/// and `docs/formats.md` follow. Bits above the last field are reserved (zero).
pub const SPAN_FIELDS: &[Field] = &[
    SPAN_ATTR,
    SPAN_XL,
    SPAN_XR,
    SPAN_ZL,
    SPAN_DZ,
    SPAN_IL_R,
    SPAN_IL_G,
    SPAN_IL_B,
    SPAN_DI_R,
    SPAN_DI_G,
    SPAN_DI_B,
    SPAN_TAG,
    SPAN_NCLASS,
    SPAN_DECAL,
    SPAN_CHAN,
];
const _: () = assert!(fields::table_end(SPAN_FIELDS) <= SPAN_WORD_BITS as usize);

/// Span attribute, seed 001 section 3.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum Attr {
    /// Ordinary polygon span: depth test and write.
    #[default]
    Op = 0,
    /// Shadow polygon span: toggles DSF where it lies in front of the visible surface.
    Sp = 1,
    /// Last shadow span of a volume: as SP, then FSF |= DSF.
    Ev = 2,
    /// Shadow span that also inverts DSF on every pixel (viewer inside the volume).
    If = 3,
}

impl Attr {
    /// The 2-bit code.
    pub fn code(self) -> u8 {
        self as u8
    }
    /// Decodes a 2-bit code.
    pub fn from_code(c: u8) -> Attr {
        match c & 3 {
            0 => Attr::Op,
            1 => Attr::Sp,
            2 => Attr::Ev,
            _ => Attr::If,
        }
    }
    /// True for SP, EV and IF (the spans of a shadow volume).
    pub fn is_shadow(self) -> bool {
        self != Attr::Op
    }
}

/// A field value that does not fit its bit width.
#[derive(Debug, Error, PartialEq, Eq)]
#[error("span word field {field} = {value} does not fit {bits} bits")]
pub struct FieldRangeError {
    /// Field name.
    pub field: &'static str,
    /// Offending value.
    pub value: i64,
    /// Width of the field.
    pub bits: u32,
}

/// One span word, unpacked. Field meanings follow seed 001 section 3.
///
/// Value at processor `p` (`XL <= p <= XR`):
/// `Z(p) = (ZL + (p − XL)·dZ) >> Z_FRAC`, `I_c(p) = clamp((IL_c + (p − XL)·dI_c) >> I_FRAC, 0, 255)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct SpanWord {
    /// Span attribute.
    pub attr: Attr,
    /// Leftmost pixel (inclusive), 0..4095.
    pub xl: u16,
    /// Rightmost pixel (inclusive), 0..4095. `xr < xl` is an empty span (allowed for EV).
    pub xr: u16,
    /// Depth at `xl`, unsigned Q24.12.
    pub zl: u64,
    /// Depth change per pixel, signed Q26.12.
    pub dz: i64,
    /// Intensity at `xl` per channel (R, G, B), unsigned Q8.12.
    pub il: [u32; 3],
    /// Intensity change per pixel per channel, signed Q9.12.
    pub di: [i32; 3],
    /// Object tag (which object the span belongs to; for shadow spans, the volume).
    pub tag: u16,
    /// Normal class for the several-lights table (seed 001 section 6); 0 when unused.
    pub nclass: u8,
    /// Decal (pattern) span: its depth plane is its host face's plane, and its depth
    /// test passes on equality (`Z <= ZB`) so it wins over the face it lies on
    /// (seed 002 section 3: a pattern lies in front of its face).
    pub decal: bool,
    /// Shade channel (exact shading in shadow): 0 for the polygon's own span; `c ≥ 1` for a
    /// span that follows its polygon's span with the same `XL`, `XR` and carries, in `IL`
    /// and `dI`, the polygon's intensity with shadowing light `c − 1` removed. It has no
    /// depth test: it writes shade register `c` where the polygon's span just won.
    pub chan: u8,
}

fn fits_unsigned(v: i64, bits: u32) -> bool {
    v >= 0 && (v as u64) < (1u64 << bits)
}
fn fits_signed(v: i64, bits: u32) -> bool {
    let lim = 1i64 << (bits - 1);
    v >= -lim && v < lim
}

impl SpanWord {
    /// Checks every field against its width.
    pub fn check(&self) -> Result<(), FieldRangeError> {
        let err = |field, value: i64, bits| Err(FieldRangeError { field, value, bits });
        if !fits_unsigned(self.xl as i64, X_BITS) {
            return err("XL", self.xl as i64, X_BITS);
        }
        if !fits_unsigned(self.xr as i64, X_BITS) {
            return err("XR", self.xr as i64, X_BITS);
        }
        if !fits_unsigned(self.zl as i64, ZL_BITS) {
            return err("ZL", self.zl as i64, ZL_BITS);
        }
        if !fits_signed(self.dz, DZ_BITS) {
            return err("dZ", self.dz, DZ_BITS);
        }
        if self.chan > MAX_SHADE_CHANNELS {
            return err("chan", self.chan as i64, CHAN_BITS);
        }
        for c in 0..3 {
            if !fits_unsigned(self.il[c] as i64, IL_BITS) {
                return err("IL", self.il[c] as i64, IL_BITS);
            }
            if !fits_signed(self.di[c] as i64, DI_BITS) {
                return err("dI", self.di[c] as i64, DI_BITS);
            }
        }
        Ok(())
    }

    /// Depth at pixel `p` in the exact closed form `(ZL + (p − XL)·dZ) >> Z_FRAC`.
    #[inline]
    pub fn z_at(&self, p: i64) -> u32 {
        ((self.zl as i64 + (p - self.xl as i64) * self.dz) >> Z_FRAC) as u32
    }

    /// Intensity of channel `c` at pixel `p`, `clamp((IL + (p − XL)·dI) >> I_FRAC, 0, 255)`.
    #[inline]
    pub fn i_at(&self, c: usize, p: i64) -> u8 {
        let v = (self.il[c] as i64 + (p - self.xl as i64) * self.di[c] as i64) >> I_FRAC;
        v.clamp(0, 255) as u8
    }

    /// True if pixel `p` is inside `[XL, XR]`.
    #[inline]
    pub fn covers(&self, p: i64) -> bool {
        p >= self.xl as i64 && p <= self.xr as i64
    }

    /// Packs the word into 256 bits, little-endian 64-bit limbs (limb 0 holds bit 0), in
    /// the layout of [`SPAN_FIELDS`]; the reserved top bits are 0.
    pub fn pack(&self) -> Result<[u64; 4], FieldRangeError> {
        self.check()?;
        let mut l = [0u64; 4];
        SPAN_ATTR.put(&mut l, self.attr.code() as u64);
        SPAN_XL.put(&mut l, self.xl as u64);
        SPAN_XR.put(&mut l, self.xr as u64);
        SPAN_ZL.put(&mut l, self.zl);
        SPAN_DZ.put(&mut l, self.dz as u64);
        for c in 0..3 {
            SPAN_IL[c].put(&mut l, self.il[c] as u64);
            SPAN_DI[c].put(&mut l, self.di[c] as i64 as u64);
        }
        SPAN_TAG.put(&mut l, self.tag as u64);
        SPAN_NCLASS.put(&mut l, self.nclass as u64);
        SPAN_DECAL.put(&mut l, self.decal as u64);
        SPAN_CHAN.put(&mut l, self.chan as u64);
        Ok(l)
    }

    /// Unpacks a word written by [`SpanWord::pack`].
    pub fn unpack(limbs: &[u64; 4]) -> SpanWord {
        let signed = |f: Field| sign_extend(f.get(limbs), f.width as u32);
        SpanWord {
            attr: Attr::from_code(SPAN_ATTR.get(limbs) as u8),
            xl: SPAN_XL.get(limbs) as u16,
            xr: SPAN_XR.get(limbs) as u16,
            zl: SPAN_ZL.get(limbs),
            dz: signed(SPAN_DZ),
            il: SPAN_IL.map(|f| f.get(limbs) as u32),
            di: SPAN_DI.map(|f| signed(f) as i32),
            tag: SPAN_TAG.get(limbs) as u16,
            nclass: SPAN_NCLASS.get(limbs) as u8,
            decal: SPAN_DECAL.get(limbs) == 1,
            chan: SPAN_CHAN.get(limbs) as u8,
        }
    }

    /// The packed word as 64 hexadecimal digits, most significant first (`$readmemh`).
    pub fn to_hex(&self) -> Result<String, FieldRangeError> {
        let l = self.pack()?;
        Ok(format!(
            "{:016x}{:016x}{:016x}{:016x}",
            l[3], l[2], l[1], l[0]
        ))
    }
}

/// Sign-extends the low `bits` bits of `v`.
pub fn sign_extend(v: u64, bits: u32) -> i64 {
    let shift = 64 - bits;
    ((v << shift) as i64) >> shift
}

/// Packs an RGB triple into the 24-bit intensity register layout `{R[23:16], G[15:8], B[7:0]}`.
pub fn pack_rgb(c: [u8; 3]) -> u32 {
    ((c[0] as u32) << 16) | ((c[1] as u32) << 8) | c[2] as u32
}
/// Inverse of [`pack_rgb`].
pub fn unpack_rgb(v: u32) -> [u8; 3] {
    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> SpanWord {
        SpanWord {
            chan: 0,
            attr: Attr::Ev,
            xl: 17,
            xr: MAX_X,
            zl: (1 << 36) - 1,
            dz: -(1 << 37),
            il: [0, (1 << 20) - 1, 12345],
            di: [-(1 << 20), (1 << 20) - 1, -7],
            tag: 0xBEEF,
            nclass: 0xA5,
            decal: true,
        }
    }

    #[test]
    fn pack_round_trips_extremes() {
        let w = sample();
        assert_eq!(SpanWord::unpack(&w.pack().unwrap()), w);
        let z = SpanWord::default();
        assert_eq!(z.pack().unwrap(), [0; 4]);
    }

    #[test]
    fn reserved_bits_stay_zero() {
        let l = sample().pack().unwrap();
        assert_eq!(l[3] >> (248 - 192), 0);
    }

    #[test]
    fn field_positions_match_docs() {
        // One bit set in each field lands where docs/formats.md says: (word, limb, bit).
        let d = SpanWord::default;
        let cases = [
            (SpanWord { xl: 1, ..d() }, 0, 2),
            (SpanWord { xr: 1, ..d() }, 0, 14),
            (SpanWord { zl: 1, ..d() }, 0, 26),
            (SpanWord { dz: 1, ..d() }, 0, 62),
            (SpanWord { tag: 1, ..d() }, 3, 223 - 192),
            (SpanWord { nclass: 1, ..d() }, 3, 239 - 192),
            (SpanWord { decal: true, ..d() }, 3, 247 - 192),
            (
                SpanWord {
                    il: [0, 0, 1],
                    ..d()
                },
                2,
                140 - 128,
            ),
        ];
        for (w, limb, bit) in cases {
            assert_eq!(w.pack().unwrap()[limb], 1 << bit, "{w:?}");
        }
    }

    #[test]
    fn span_table_matches_docs() {
        let doc = include_str!("../../docs/formats.md");
        assert_eq!(
            fields::parse_doc_table(doc, "## The span word"),
            fields::table_rows(SPAN_FIELDS)
        );
    }

    #[test]
    fn out_of_range_fields_are_rejected() {
        let w = SpanWord {
            xl: MAX_X + 1,
            ..Default::default()
        };
        assert_eq!(w.check().unwrap_err().field, "XL");
        let w = SpanWord {
            dz: 1 << 37,
            ..Default::default()
        };
        assert_eq!(w.check().unwrap_err().field, "dZ");
        let w = SpanWord {
            zl: 1 << 36,
            ..Default::default()
        };
        assert!(w.pack().is_err());
    }

    #[test]
    fn closed_form_matches_incremental_sum() {
        // The hardware adds dZ once per processor; in two's complement that sum equals
        // the closed form bit for bit (both are exact integer arithmetic).
        let w = SpanWord {
            xl: 3,
            xr: 4000,
            zl: 5 << Z_FRAC,
            dz: 4097,
            ..Default::default()
        };
        let mut acc = w.zl as i64;
        for p in 3..=4000 {
            assert_eq!((acc >> Z_FRAC) as u32, w.z_at(p));
            acc += w.dz;
        }
    }

    #[test]
    fn hex_is_64_digits() {
        assert_eq!(sample().to_hex().unwrap().len(), 64);
    }
}
