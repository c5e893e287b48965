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

use thiserror::Error;

/// Fractional bits of a snapped vertex coordinate (1/256 pixel, D3D11-class).
pub const SUBPIXEL_BITS: u32 = 8;
/// One pixel in snapped units.
pub const SUBPIXEL_ONE: i32 = 1 << SUBPIXEL_BITS;
/// Largest screen width or height the formats support (`XL`, `XR` are 12 bits).
pub const MAX_SCREEN: u32 = 4096;
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
/// Fractional bits of `ZL` and `dZ` in a span word.
pub const Z_FRAC: u32 = 12;
/// Fractional bits of `IL` and `dI` in a span word.
pub const I_FRAC: u32 = 12;

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
/// Width of a packed span word (the remaining top bits are zero, reserved).
pub const SPAN_WORD_BITS: u32 = 256;

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

    /// Packs the word into 256 bits, little-endian 64-bit limbs (limb 0 holds bit 0).
    /// Layout (LSB first): attr[1:0], XL[13:2], XR[25:14], ZL[61:26], dZ[99:62],
    /// IL_r[119:100], IL_g[139:120], IL_b[159:140], dI_r[180:160], dI_g[201:181],
    /// dI_b[222:202], tag[238:223], nclass[246:239], decal[247], reserved[255:248] = 0.
    pub fn pack(&self) -> Result<[u64; 4], FieldRangeError> {
        self.check()?;
        let mut w = BitWriter::default();
        w.put(self.attr.code() as u64, 2);
        w.put(self.xl as u64, X_BITS);
        w.put(self.xr as u64, X_BITS);
        w.put(self.zl, ZL_BITS);
        w.put(self.dz as u64, DZ_BITS);
        for c in 0..3 {
            w.put(self.il[c] as u64, IL_BITS);
        }
        for c in 0..3 {
            w.put(self.di[c] as i64 as u64, DI_BITS);
        }
        w.put(self.tag as u64, TAG_BITS);
        w.put(self.nclass as u64, NCLASS_BITS);
        w.put(self.decal as u64, 1);
        Ok(w.limbs)
    }

    /// Unpacks a word written by [`SpanWord::pack`].
    pub fn unpack(limbs: &[u64; 4]) -> SpanWord {
        let mut r = BitReader { limbs, pos: 0 };
        let attr = Attr::from_code(r.get(2) as u8);
        let xl = r.get(X_BITS) as u16;
        let xr = r.get(X_BITS) as u16;
        let zl = r.get(ZL_BITS);
        let dz = sign_extend(r.get(DZ_BITS), DZ_BITS);
        let mut il = [0u32; 3];
        for v in il.iter_mut() {
            *v = r.get(IL_BITS) as u32;
        }
        let mut di = [0i32; 3];
        for v in di.iter_mut() {
            *v = sign_extend(r.get(DI_BITS), DI_BITS) as i32;
        }
        let tag = r.get(TAG_BITS) as u16;
        let nclass = r.get(NCLASS_BITS) as u8;
        let decal = r.get(1) == 1;
        SpanWord {
            attr,
            xl,
            xr,
            zl,
            dz,
            il,
            di,
            tag,
            nclass,
            decal,
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

#[derive(Default)]
struct BitWriter {
    limbs: [u64; 4],
    pos: u32,
}
impl BitWriter {
    fn put(&mut self, v: u64, bits: u32) {
        let v = if bits == 64 {
            v
        } else {
            v & ((1u64 << bits) - 1)
        };
        for b in 0..bits {
            if (v >> b) & 1 == 1 {
                let at = self.pos + b;
                self.limbs[(at / 64) as usize] |= 1u64 << (at % 64);
            }
        }
        self.pos += bits;
    }
}
struct BitReader<'a> {
    limbs: &'a [u64; 4],
    pos: u32,
}
impl BitReader<'_> {
    fn get(&mut self, bits: u32) -> u64 {
        let mut v = 0u64;
        for b in 0..bits {
            let at = self.pos + b;
            if (self.limbs[(at / 64) as usize] >> (at % 64)) & 1 == 1 {
                v |= 1u64 << b;
            }
        }
        self.pos += bits;
        v
    }
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
            attr: Attr::Ev,
            xl: 17,
            xr: 4095,
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
        // One bit set in each field lands where docs/formats.md says.
        let mut w = SpanWord {
            xl: 1,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[0], 1 << 2);
        w = SpanWord {
            xr: 1,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[0], 1 << 14);
        w = SpanWord {
            zl: 1,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[0], 1 << 26);
        w = SpanWord {
            dz: 1,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[0], 1 << 62);
        w = SpanWord {
            tag: 1,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[3], 1 << (223 - 192));
        w = SpanWord {
            nclass: 1,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[3], 1 << (239 - 192));
        w = SpanWord {
            decal: true,
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[3], 1 << (247 - 192));
        w = SpanWord {
            il: [0, 0, 1],
            ..Default::default()
        };
        assert_eq!(w.pack().unwrap()[2], 1 << (140 - 128));
    }

    #[test]
    fn out_of_range_fields_are_rejected() {
        let w = SpanWord {
            xl: 4096,
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
            zl: 5 << 12,
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
