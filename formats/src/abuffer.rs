//! A-buffer formats shared by the golden search unit (`pixelproc-sim::mask_search`) and its
//! RTL twin: mask layout and bit order, subpixel offsets, start corners, search-mask
//! tables, the offset ROM word, and the fragment depth-plane format.
//!
//! Implements the data of seed 000 (JP2569952B2): the fraction mask of an n×m subpixel
//! pixel area (background, "mask generation"), the search mask one subpixel-diagonal wide
//! parallel to the line joining the two corners adjacent to the start corner (claim 1,
//! Fig. 4), and the offset table addressed by the AND result (Tables 1 and 2). Every table
//! here is *generated* from the mask size; none is typed in.
//!
//! # Mask layout (bit order)
//!
//! A pixel area has `n` subpixel columns and `m` subpixel rows (`1 ≤ n, m ≤ 8`), so a
//! mask fits a `u64`. Row 0 is the top row, column 0 the left column, and
//!
//! ```text
//! bit index = n·row + (n − 1 − column)
//! ```
//!
//! so row 0 is the least significant group of `n` bits and, inside a row, column 0 is
//! the most significant bit of the group. For 4×4 (the seed's worked example):
//!
//! ```text
//!            col 0  col 1  col 2  col 3
//!   row 0      3      2      1      0      dy = −0.375
//!   row 1      7      6      5      4      dy = −0.125
//!   row 2     11     10      9      8      dy = +0.125
//!   row 3     15     14     13     12      dy = +0.375
//!           −0.375 −0.125 +0.125 +0.375  = dx
//! ```
//!
//! `0100H` is bit 8 = (col 3, row 2) → (+0.375, +0.125) and `0842H` is bits 11, 6, 1 = one
//! anti-diagonal, as the seed's Tables 1 and 2 state.
//!
//! # Subpixel offsets
//!
//! The centre of subpixel (c, r) is at `(c + ½)/n − ½` px right and `(r + ½)/m − ½` px below
//! the pixel centre. In units of `1/(2n)` px (x) and `1/(2m)` px (y) these are the small
//! integers `dx = 2c + 1 − n`, `dy = 2r + 1 − m`, in `−7..=7`. A [`SubOffset`] stores them;
//! on the wire each is a 4-bit two's-complement field (`[3:0]` dx, `[7:4]` dy).
//!
//! # Offset ROM (compacted)
//!
//! The seed addresses the offset table with the raw AND result (2^(n·m) words). Every AND
//! result that reaches the ROM is a non-empty subset of one search line, and the points of
//! one line have strictly increasing bit index as the row increases (for every search
//! family of [`SearchFamily`], including rows and columns). So the two *end* subpixels are
//! the subpixels of the highest and of the lowest set bit. The ROM is therefore compacted to
//! two priority encoders (most / least significant set bit, `⌈log2(n·m)⌉` bits each) and a
//! table of `n·m` 8-bit [`SubOffset`] words read at both addresses ([`offset_rom_table`]).
//! The ROM output word ([`RomWord`], 17 bits) is
//!
//! ```text
//!   [3:0] dx1  [7:4] dy1   end 1 = subpixel of the most significant set bit
//!  [11:8] dx2 [15:12] dy2  end 2 = subpixel of the least significant set bit
//!     [16] pair            1 when end 1 ≠ end 2 (two depth evaluations needed)
//! ```
//!
//! which for `0842H` gives end 1 = (−0.375, +0.125), end 2 = (+0.125, −0.375), the seed's
//! order.
//!
//! # Start corner and search lines
//!
//! [`Corner`] is 2 bits: bit 0 = right, bit 1 = bottom. Measured from the start corner,
//! `c' = c` or `n−1−c`, `r' = r` or `m−1−r`. The search line `k` of family `(p, q)` is the set
//! `{ (c, r) : p·c' + q·r' = k }`, `k = 0 ..= p(n−1) + q(m−1)`; the seed's diagonal band is
//! family `(1, 1)`. [`search_mask_table`] generates them.
//!
//! # Fragment depth plane
//!
//! A fragment carries the plane of its polygon relative to the pixel centre
//! ([`FragPlane`]): `zc` = depth at the pixel centre, `sx`, `sy` = depth change per offset
//! unit (1/(2n) px in x, 1/(2m) px in y), all signed fixed point with [`PLANE_FRAC`] = 12
//! fractional bits, saturated to [`PLANE_BITS`] = 48 bits two's complement. The depth
//! calculator evaluates `z = zc + sx·dx + sy·dy` (integer multiply-add, no rounding), in
//! the same Q.12 units, width 53 bits.

use thiserror::Error;

/// Largest number of subpixel columns or rows.
pub const MAX_MASK_SIDE: u8 = 8;
/// Fractional bits of the fragment depth plane (same as `Z_FRAC` of the span word).
pub const PLANE_FRAC: u32 = 12;
/// Width of each fragment plane field (`zc`, `sx`, `sy`), two's complement, saturated.
pub const PLANE_BITS: u32 = 48;
/// Largest magnitude of a plane field.
pub const PLANE_MAX: i64 = (1 << (PLANE_BITS - 1)) - 1;
/// Width of one offset field (dx or dy), two's complement.
pub const OFFSET_BITS: u32 = 4;
/// Width of a [`RomWord`].
pub const ROM_WORD_BITS: u32 = 17;

/// An unsupported mask size.
#[derive(Debug, Error, PartialEq, Eq)]
#[error("mask size {n}x{m} is not supported (each side 1..=8)")]
pub struct MaskSizeError {
    /// Columns requested.
    pub n: u32,
    /// Rows requested.
    pub m: u32,
}

/// Subpixel grid of a pixel: `n` columns × `m` rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaskSize {
    n: u8,
    m: u8,
}

impl MaskSize {
    /// 4×4, the seed's worked example.
    pub const S4X4: MaskSize = MaskSize { n: 4, m: 4 };
    /// 8×8.
    pub const S8X8: MaskSize = MaskSize { n: 8, m: 8 };

    /// A size with `n` columns and `m` rows, each in `1..=8`.
    pub fn new(n: u32, m: u32) -> Result<MaskSize, MaskSizeError> {
        let ok = |v: u32| (1..=MAX_MASK_SIDE as u32).contains(&v);
        if ok(n) && ok(m) {
            Ok(MaskSize {
                n: n as u8,
                m: m as u8,
            })
        } else {
            Err(MaskSizeError { n, m })
        }
    }

    /// Parses `"4x4"`, `"8x8"`, `"4x2"` (columns x rows).
    pub fn parse(s: &str) -> Result<MaskSize, MaskSizeError> {
        let mut it = s.trim().split(['x', 'X']);
        let n = it.next().and_then(|v| v.parse().ok()).unwrap_or(0);
        let m = it.next().and_then(|v| v.parse().ok()).unwrap_or(0);
        if it.next().is_some() {
            return Err(MaskSizeError { n: 0, m: 0 });
        }
        MaskSize::new(n, m)
    }

    /// Columns.
    #[inline]
    pub fn n(self) -> u32 {
        self.n as u32
    }
    /// Rows.
    #[inline]
    pub fn m(self) -> u32 {
        self.m as u32
    }
    /// Subpixels per pixel, `n·m`.
    #[inline]
    pub fn bits(self) -> u32 {
        self.n() * self.m()
    }
    /// The mask with every subpixel set.
    #[inline]
    pub fn full(self) -> u64 {
        if self.bits() == 64 {
            u64::MAX
        } else {
            (1u64 << self.bits()) - 1
        }
    }
    /// Bit index of subpixel (column `c`, row `r`): `n·r + (n − 1 − c)`.
    #[inline]
    pub fn bit_index(self, c: u32, r: u32) -> u32 {
        debug_assert!(c < self.n() && r < self.m());
        self.n() * r + (self.n() - 1 - c)
    }
    /// (column, row) of a bit index.
    #[inline]
    pub fn col_row(self, bit: u32) -> (u32, u32) {
        (self.n() - 1 - bit % self.n(), bit / self.n())
    }
    /// Offset of subpixel (c, r) from the pixel centre in units of 1/(2n), 1/(2m) px.
    #[inline]
    pub fn offset(self, c: u32, r: u32) -> SubOffset {
        SubOffset {
            dx: (2 * c as i32 + 1 - self.n() as i32) as i8,
            dy: (2 * r as i32 + 1 - self.m() as i32) as i8,
        }
    }
}

impl std::fmt::Display for MaskSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.n, self.m)
    }
}

/// Offset of a subpixel centre from the pixel centre: `dx` in units of 1/(2n) px, `dy` in
/// units of 1/(2m) px.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct SubOffset {
    /// Horizontal offset, `2c + 1 − n`.
    pub dx: i8,
    /// Vertical offset, `2r + 1 − m`.
    pub dy: i8,
}

impl SubOffset {
    /// The 8-bit ROM entry: `[3:0]` dx, `[7:4]` dy, each 4-bit two's complement.
    #[inline]
    pub fn pack(self) -> u8 {
        ((self.dx as u8) & 0xF) | (((self.dy as u8) & 0xF) << 4)
    }
    /// Inverse of [`SubOffset::pack`].
    #[inline]
    pub fn unpack(w: u8) -> SubOffset {
        let s = |v: u8| (((v & 0xF) << 4) as i8) >> 4;
        SubOffset {
            dx: s(w),
            dy: s(w >> 4),
        }
    }
    /// The offset in pixels (for reports and tests).
    pub fn to_px(self, size: MaskSize) -> (f64, f64) {
        (
            self.dx as f64 / (2 * size.n()) as f64,
            self.dy as f64 / (2 * size.m()) as f64,
        )
    }
}

/// Generated offset ROM: entry `b` is the packed [`SubOffset`] of the subpixel of bit `b`.
pub fn offset_rom_table(size: MaskSize) -> Vec<u8> {
    (0..size.bits())
        .map(|b| {
            let (c, r) = size.col_row(b);
            size.offset(c, r).pack()
        })
        .collect()
}

/// The offset ROM's output: the two end subpixels of a first hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct RomWord {
    /// End 1: subpixel of the most significant set bit of the AND result.
    pub end1: SubOffset,
    /// End 2: subpixel of the least significant set bit.
    pub end2: SubOffset,
    /// True when the ends differ (two depth evaluations).
    pub pair: bool,
}

impl RomWord {
    /// 17-bit word: `[7:0]` end 1, `[15:8]` end 2, `[16]` pair.
    pub fn pack(self) -> u32 {
        self.end1.pack() as u32 | (self.end2.pack() as u32) << 8 | (self.pair as u32) << 16
    }
    /// Inverse of [`RomWord::pack`].
    pub fn unpack(w: u32) -> RomWord {
        RomWord {
            end1: SubOffset::unpack(w as u8),
            end2: SubOffset::unpack((w >> 8) as u8),
            pair: (w >> 16) & 1 == 1,
        }
    }
}

/// Start corner of a search, 2-bit code: bit 0 = right, bit 1 = bottom.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum Corner {
    /// Top-left (code 0).
    #[default]
    TopLeft = 0,
    /// Top-right (code 1).
    TopRight = 1,
    /// Bottom-left (code 2).
    BottomLeft = 2,
    /// Bottom-right (code 3).
    BottomRight = 3,
}

impl Corner {
    /// All four, in code order.
    pub const ALL: [Corner; 4] = [
        Corner::TopLeft,
        Corner::TopRight,
        Corner::BottomLeft,
        Corner::BottomRight,
    ];
    /// The 2-bit code.
    #[inline]
    pub fn code(self) -> u8 {
        self as u8
    }
    /// Decodes a 2-bit code.
    #[inline]
    pub fn from_code(c: u8) -> Corner {
        Corner::ALL[(c & 3) as usize]
    }
    /// True for the right-hand corners.
    #[inline]
    pub fn right(self) -> bool {
        self.code() & 1 == 1
    }
    /// True for the bottom corners.
    #[inline]
    pub fn bottom(self) -> bool {
        self.code() & 2 == 2
    }
    /// The diagonally opposite corner (where a max search starts when the min search
    /// starts here).
    #[inline]
    pub fn opposite(self) -> Corner {
        Corner::from_code(self.code() ^ 3)
    }
    /// The corner where a plane with slopes `(sx, sy)` is smallest: left if `sx ≥ 0`, top if
    /// `sy ≥ 0` (a zero slope picks left / top).
    #[inline]
    pub fn of_min(sx: i64, sy: i64) -> Corner {
        Corner::from_code((sx < 0) as u8 | ((sy < 0) as u8) << 1)
    }
}

/// A family of search lines `p·c' + q·r' = k` (see the module header). The seed's diagonal
/// band is `(1, 1)`; `(1, 0)` searches column by column, `(0, 1)` row by row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SearchFamily {
    /// Weight of the column distance from the start corner.
    pub p: u8,
    /// Weight of the row distance from the start corner.
    pub q: u8,
}

impl SearchFamily {
    /// The seed's diagonal band.
    pub const DIAGONAL: SearchFamily = SearchFamily { p: 1, q: 1 };
    /// Number of search lines (steps of a full search) for a size.
    pub fn lines(self, size: MaskSize) -> u32 {
        self.p as u32 * (size.n() - 1) + self.q as u32 * (size.m() - 1) + 1
    }
}

/// Generated search masks of one family and corner, line `k` at index `k`.
///
/// Only families with `gcd(p, q) = 1` and `p, q ≤ 3` are meaningful (others leave empty
/// lines, which the search steps over harmlessly).
pub fn search_mask_table(size: MaskSize, fam: SearchFamily, corner: Corner) -> Vec<u64> {
    let mut t = vec![0u64; fam.lines(size) as usize];
    for r in 0..size.m() {
        for c in 0..size.n() {
            let cc = if corner.right() { size.n() - 1 - c } else { c };
            let rr = if corner.bottom() { size.m() - 1 - r } else { r };
            let k = fam.p as u32 * cc + fam.q as u32 * rr;
            t[k as usize] |= 1u64 << size.bit_index(c, r);
        }
    }
    t
}

/// A fragment's depth plane relative to its pixel centre (see the module header).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct FragPlane {
    /// Depth at the pixel centre, signed Q.12 (depth units, 0 nearest).
    pub zc: i64,
    /// Depth change per 1/(2n) px in x, signed Q.12.
    pub sx: i64,
    /// Depth change per 1/(2m) px in y, signed Q.12.
    pub sy: i64,
}

impl FragPlane {
    /// The depth calculator: `zc + sx·dx + sy·dy`, Q.12, exact.
    #[inline]
    pub fn depth_at(&self, o: SubOffset) -> i64 {
        self.zc + self.sx * o.dx as i64 + self.sy * o.dy as i64
    }
}

/// Saturates a value to the [`PLANE_BITS`] range.
#[inline]
pub fn saturate_plane(v: i128) -> i64 {
    v.clamp(-(PLANE_MAX as i128), PLANE_MAX as i128) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_bit_order() {
        let s = MaskSize::S4X4;
        // 0100H: bit 8 → (+0.375, +0.125).
        let (c, r) = s.col_row(8);
        assert_eq!(s.offset(c, r).to_px(s), (0.375, 0.125));
        // 0842H: bits 11, 6, 1 → one anti-diagonal.
        let pts: Vec<_> = [11, 6, 1].iter().map(|&b| s.col_row(b)).collect();
        assert_eq!(pts, vec![(0, 2), (1, 1), (2, 0)]);
    }

    #[test]
    fn offsets_pack_round_trip() {
        for dx in -7..=7i8 {
            for dy in -7..=7i8 {
                let o = SubOffset { dx, dy };
                assert_eq!(SubOffset::unpack(o.pack()), o);
            }
        }
        let w = RomWord {
            end1: SubOffset { dx: -3, dy: 1 },
            end2: SubOffset { dx: 1, dy: -3 },
            pair: true,
        };
        assert_eq!(w.pack() >> ROM_WORD_BITS, 0);
        assert_eq!(RomWord::unpack(w.pack()), w);
    }

    #[test]
    fn search_lines_partition_the_pixel() {
        for size in [MaskSize::S4X4, MaskSize::S8X8, MaskSize::new(4, 2).unwrap()] {
            for fam in [(1, 1), (1, 0), (0, 1), (2, 1), (1, 2)] {
                let fam = SearchFamily { p: fam.0, q: fam.1 };
                for corner in Corner::ALL {
                    let t = search_mask_table(size, fam, corner);
                    let mut acc = 0u64;
                    for &l in &t {
                        assert_eq!(acc & l, 0);
                        acc |= l;
                    }
                    assert_eq!(acc, size.full());
                    // The start corner's subpixel is on line 0 (alone if p, q > 0).
                    let c = if corner.right() { size.n() - 1 } else { 0 };
                    let r = if corner.bottom() { size.m() - 1 } else { 0 };
                    let b = 1 << size.bit_index(c, r);
                    if fam.p > 0 && fam.q > 0 {
                        assert_eq!(t[0], b);
                    } else {
                        assert_ne!(t[0] & b, 0);
                    }
                }
            }
        }
    }

    #[test]
    fn parse_sizes() {
        assert_eq!(MaskSize::parse("4x4").unwrap(), MaskSize::S4X4);
        assert_eq!(MaskSize::parse("8X8").unwrap(), MaskSize::S8X8);
        assert!(MaskSize::parse("9x9").is_err());
        assert!(MaskSize::parse("4").is_err());
        assert!(MaskSize::parse("4x4x4").is_err());
    }
}
