//! Snapping and span setup: screen-space triangles to span words.
//!
//! Implements the span data of seed 001 (Matsumoto, section 3: `(attr, XL, XR, ZL, dZ,
//! IL, dI)`) for the scanline pixel-processor array. Everything here after
//! [`snap_coord`] is integer arithmetic on the formats of `pixelproc-formats`.
//!
//! **Fill convention.** A pixel (i, j) is covered when its centre
//! `(i + 1/2, j + 1/2)` lies inside the triangle, with the top-left rule on edges: with the
//! triangle wound so that every edge function `E(p) = A·x + B·y + C` is positive inside, a
//! centre with `E = 0` belongs to the triangle only if the edge is a *left* edge (`A > 0`)
//! or a *top* edge (`A = 0, B > 0`; y grows downwards). An edge shared by two triangles has
//! opposite `(A, B)` in each, so exactly one of them takes centres on it: no gap, no
//! double cover. Edge functions are evaluated exactly in `i64` on the snapped (Q.8)
//! coordinates.
//!
//! **Depth and intensity.** The plane through the three snapped vertices is
//! `z(x, y) = z0 + (Nx·(x − x0) + Ny·(y − y0)) / area2`. Per row, setup rounds (half up,
//! from exact `i128` rationals) the plane's value at the centre of column 0 to Q24.12,
//! `Z0`, and its slope to `dZ = round(Nx·256 / area2)` in Q26.12 per pixel, and sends
//! `ZL = Z0 + XL·dZ`. The value at pixel `p` is then `ZL + (p − XL)·dZ = Z0 + p·dZ`:
//! exact integers, so no drift along a span however long, and independent of where the
//! span starts (two spans of one plane agree at every pixel: a pattern ties exactly with
//! the face it lies on). Every row recomputes `Z0` from the plane, so no drift between
//! rows either. The distance to the true plane is at most `½ + 4095·½` units of 2^-12,
//! i.e. below half a depth unit; `Z_GEOM_MIN`/`Z_GEOM_MAX` leave a margin of 16 units so
//! an in-triangle value never leaves the 24-bit range or reaches `Z_FAR`.
//!
//! **Parts.** The exact plane ([`ExactPlane`], `plane.rs`), the column bounds per
//! scanline ([`ColumnSteps`], `columns.rs`) and the shadow polygons' triangles
//! ([`ShadowTri`], `shadow.rs`, seed 001 section 4); here, snapping and [`TriSetup`], a
//! polygon's span words.

mod columns;
mod plane;
mod shadow;

pub(crate) use columns::ColumnSteps;
pub(crate) use plane::ExactPlane;
#[cfg(test)]
pub(crate) use shadow::shadow_word;
pub(crate) use shadow::ShadowTri;

use crate::raster::edge::{check_coords, check_depths, rewind, winding, EdgeFn};
use crate::raster::{ceil_div, rows::centre_rows, RoundDivSteps};
use pixelproc_formats::{
    Attr, SpanWord, DI_BITS, DZ_BITS, IL_BITS, I_FRAC, MAX_COORD_PX, SUBPIXEL_ONE, Z_FRAC,
    Z_GEOM_MAX, Z_GEOM_MIN,
};
use thiserror::Error;

/// A number for a message: plain when moderate, in exponent form when huge or tiny (never
/// a 300-digit literal).
pub fn short_num(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Why a triangle cannot be set up.
#[derive(Debug, Error, PartialEq)]
pub enum SetupError {
    /// A coordinate is NaN or infinite.
    #[error("coordinate {0} is not a finite number")]
    NotFinite(f64),
    /// A coordinate lies outside the fixed-point range.
    #[error("coordinate {} px is outside the fixed-point range ±{MAX_COORD_PX} px", short_num(*.0))]
    OutOfRange(f64),
    /// A depth outside the geometric depth range.
    #[error("depth {0} is outside the 24-bit geometry range {Z_GEOM_MIN}..={Z_GEOM_MAX}")]
    DepthOutOfRange(i64),
    /// A span word field would not fit.
    #[error(transparent)]
    Field(#[from] pixelproc_formats::FieldRangeError),
}

/// Snaps a screen coordinate (pixels, f64) to Q.8 fixed point: `round(x · 256)`, ties away
/// from zero (`f64::round`). This is the one documented float-to-fixed step.
pub fn snap_coord(x: f64) -> Result<i32, SetupError> {
    if !x.is_finite() {
        return Err(SetupError::NotFinite(x));
    }
    if x.abs() > MAX_COORD_PX as f64 {
        return Err(SetupError::OutOfRange(x));
    }
    Ok((x * SUBPIXEL_ONE as f64).round() as i32)
}

/// Converts a linear colour channel in 0..1 to Q8.12 intensity with the rounding offset
/// folded in: `floor(c·255·4096) + 2048`. The array reads a channel as `v >> 12`
/// (truncation), which then yields exactly `round(c·255)` (ties up) for a flat colour:
/// `floor(floor(4096·x + 2048) / 4096) = floor(x + ½)`.
pub fn snap_intensity(c: f64) -> u32 {
    let c = if c.is_finite() {
        c.clamp(0.0, 1.0)
    } else {
        0.0
    };
    (c * 255.0 * (1u32 << I_FRAC) as f64).floor() as u32 + (1 << (I_FRAC - 1))
}

/// A triangle after snapping: the input of span setup (and of fragment setup).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct SnappedTri {
    /// Vertex positions, Q.8 pixels.
    pub v: [[i32; 2]; 3],
    /// Vertex depths, 24-bit (0 nearest), within `Z_GEOM_MIN..=Z_GEOM_MAX`.
    pub z: [u32; 3],
    /// Vertex intensities per channel, Q8.12.
    pub c: [[u32; 3]; 3],
    /// Object tag.
    pub tag: u16,
    /// For a decal (pattern), the host face whose depth plane it uses.
    pub host: Option<HostPlane>,
    /// Quantized normal class for the several-lights attenuation table (seed 001 §6).
    pub nclass: u8,
    /// Shade channel: 0 for a polygon; `c ≥ 1` for the copy of the polygon before it
    /// whose intensities are those without shadowing light `c − 1` (its span words carry
    /// `chan = c`; see [`pixelproc_formats::SpanWord::chan`]).
    pub chan: u8,
}

/// The snapped vertices and depths of a decal's host face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct HostPlane {
    /// Host vertex positions, Q.8.
    pub v: [[i32; 2]; 3],
    /// Host vertex depths.
    pub z: [u32; 3],
}

/// The first and last scanline whose centre a triangle with vertices `v` (Q.8) may cover
/// (unclamped).
fn rows_of(v: &[[i32; 2]; 3]) -> (i64, i64) {
    let ys = v.map(|p| p[1] as i64);
    centre_rows(
        ys.into_iter().min().unwrap_or(0),
        ys.into_iter().max().unwrap_or(0),
    )
}

/// A span's `ZL` and `dZ` from its row origin `Z0` (Q24.12, at the centre of column 0)
/// and the plane's slope: `ZL = Z0 + XL·dZ`, clamped at 0, and `dZ` zero for a one-pixel
/// span. Polygon and shadow words both take them from here, so they tie exactly.
#[inline]
fn depth_fields(z0: i64, xl: i64, xr: i64, dz: i64) -> (u64, i64) {
    ((z0 + xl * dz).max(0) as u64, if xl == xr { 0 } else { dz })
}

/// Everything per triangle that span setup needs, computed once.
#[derive(Clone, Debug)]
pub struct TriSetup {
    edges: [EdgeFn; 3],
    z: ExactPlane,
    c: [ExactPlane; 3],
    /// First scanline whose centre may be covered (unclamped).
    pub row_min: i64,
    /// Last scanline whose centre may be covered (unclamped).
    pub row_max: i64,
    /// Object tag.
    pub tag: u16,
    decal: bool,
    nclass: u8,
    chan: u8,
    /// Row-invariant slopes: dZ (Q26.12) and dI per channel (Q9.12) per pixel.
    dz: i64,
    di: [i64; 3],
}

impl TriSetup {
    /// Prepares a triangle. Returns `Ok(None)` for a zero-area (degenerate) triangle, which
    /// covers nothing.
    pub fn new(t: &SnappedTri) -> Result<Option<TriSetup>, SetupError> {
        TriSetup::check(t)?;
        Ok(TriSetup::of_checked(t))
    }

    /// The range checks [`TriSetup::new`] makes: depths and coordinates (the triangle's
    /// and its decal host's) within the formats.
    pub fn check(t: &SnappedTri) -> Result<(), SetupError> {
        check_depths(t)?;
        check_coords(t.v.iter().chain(t.host.iter().flat_map(|h| h.v.iter())))
    }

    /// Whether [`TriSetup::of_checked`] gives a setup, without making it: the triangle
    /// and the plane its depth comes from (its decal host's, if any) have area.
    pub fn is_live(t: &SnappedTri) -> bool {
        let area = |v: [[i32; 2]; 3]| {
            let d = |k: usize, c: usize| v[k][c] as i128 - v[0][c] as i128;
            d(1, 0) * d(2, 1) - d(2, 0) * d(1, 1) != 0
        };
        winding(t.v).is_some() && t.host.as_ref().map_or(area(t.v), |h| area(h.v))
    }

    /// [`TriSetup::new`] of a triangle that passed [`TriSetup::check`].
    pub fn of_checked(t: &SnappedTri) -> Option<TriSetup> {
        let order = winding(t.v)?;
        let (v, z, c) = (rewind(order, t.v), rewind(order, t.z), rewind(order, t.c));
        let edges = EdgeFn::of_triangle(v);
        let zp = match &t.host {
            Some(h) => ExactPlane::new(h.v, h.z.map(|x| x as i64)),
            None => ExactPlane::new(v, z.map(|x| x as i64)),
        };
        let zp = zp?;
        let cp = |k: usize| ExactPlane::new(v, [c[0][k] as i64, c[1][k] as i64, c[2][k] as i64]);
        let (c0, c1, c2) = (cp(0)?, cp(1)?, cp(2)?);
        let (row_min, row_max) = rows_of(&v);
        Some(TriSetup {
            edges,
            dz: zp.ddx_per_px(Z_FRAC),
            di: [c0.ddx_per_px(0), c1.ddx_per_px(0), c2.ddx_per_px(0)],
            z: zp,
            c: [c0, c1, c2],
            row_min,
            row_max,
            tag: t.tag,
            decal: t.host.is_some(),
            nclass: t.nclass,
            chan: t.chan,
        })
    }

    /// The inclusive range of pixel columns whose centres on row `j` the triangle covers,
    /// clamped to `0..width`, or `None`.
    pub fn columns(&self, j: i64, width: u32) -> Option<(i64, i64)> {
        if j < self.row_min || j > self.row_max {
            return None;
        }
        let one = SUBPIXEL_ONE as i64;
        let yc = j * one + one / 2;
        let (mut lo, mut hi) = (0i64, width as i64 - 1);
        for e in &self.edges {
            let k = e.b * yc + e.c + e.a * (one / 2); // E at column i is 256·A·i + k
            match e.a.cmp(&0) {
                std::cmp::Ordering::Greater => lo = lo.max(ceil_div(-k, one * e.a)),
                std::cmp::Ordering::Less => hi = hi.min(ceil_div(k, -one * e.a) - 1),
                std::cmp::Ordering::Equal => {
                    if !e.inside(k) {
                        return None;
                    }
                }
            }
            if lo > hi {
                return None;
            }
        }
        Some((lo, hi))
    }

    /// The stepper of [`TriSetup::columns`] from row `first` on: [`ColumnSteps::columns`]
    /// gives row `first`'s columns, and each [`ColumnSteps::advance`] moves one row down.
    /// (Rows outside `row_min..=row_max` are the caller's to skip, as `columns` does.)
    pub(crate) fn column_rows(&self, first: i64) -> ColumnSteps {
        ColumnSteps::new(&self.edges, first)
    }

    /// The OP span word of row `j`, or `None` if the row covers no pixel centre.
    pub fn span(&self, j: i64, width: u32) -> Option<SpanWord> {
        let (xl, xr) = self.columns(j, width)?;
        let yc = j * SUBPIXEL_ONE as i64 + (SUBPIXEL_ONE / 2) as i64;
        let x0 = (SUBPIXEL_ONE / 2) as i64;
        let c0 = [0, 1, 2].map(|k| self.c[k].at(x0, yc, 0));
        Some(self.word(xl, xr, self.z.at(x0, yc, Z_FRAC), c0))
    }

    /// Calls `f(row, word)` for every row `0..height` the triangle covers, top to bottom.
    /// Same words as [`TriSetup::span`], with the per-row plane origins stepped exactly
    /// (additions only) instead of divided afresh.
    pub fn for_each_span(&self, width: u32, height: u32, f: impl FnMut(u32, SpanWord)) {
        self.for_each_span_in(0, height as i64 - 1, width, f)
    }

    /// As [`TriSetup::for_each_span`], for the rows `lo..=hi` only.
    pub fn for_each_span_in(&self, lo: i64, hi: i64, width: u32, mut f: impl FnMut(u32, SpanWord)) {
        let first = self.row_min.max(lo).max(0);
        let last = self.row_max.min(hi);
        if first > last {
            return;
        }
        let x0 = (SUBPIXEL_ONE / 2) as i64;
        let mut zr = self.z.rows(x0, first, Z_FRAC);
        let mut cr = [0, 1, 2].map(|k| self.c[k].rows(x0, first, 0));
        let mut cols = self.column_rows(first);
        for j in first..=last {
            if let Some((xl, xr)) = cols.columns(width) {
                let w = self.word(xl, xr, zr.value() as i64, cr.map(|r| r.value() as i64));
                debug_assert_eq!(Some(w), self.span(j, width));
                f(j as u32, w);
            }
            cols.advance();
            zr.advance();
            for r in &mut cr {
                r.advance();
            }
        }
    }

    /// As [`TriSetup::for_each_span_in`] for this triangle and `copies`, triangles with
    /// the same snapped geometry (vertices, depths, decal host; only intensities, shade
    /// channel and tag may differ: the shade-channel copies of
    /// [`SnappedTri::chan`]). Their spans have the same columns and depth on every row, so
    /// the row's columns and depth are found once: `f(i, row, word)` gets, per row, this
    /// triangle's word (`i = 0`) and then each copy's (`i = 1 ..`), the same words as each
    /// triangle's own [`TriSetup::for_each_span_in`].
    pub fn for_each_span_shared(
        &self,
        copies: &[Option<TriSetup>],
        lo: i64,
        hi: i64,
        width: u32,
        mut f: impl FnMut(usize, u32, SpanWord),
    ) {
        let first = self.row_min.max(lo).max(0);
        let last = self.row_max.min(hi);
        if first > last {
            return;
        }
        debug_assert!(copies
            .iter()
            .all(|c| c.as_ref().is_some_and(|c| c.edges == self.edges
                && c.dz == self.dz
                && (c.row_min, c.row_max) == (self.row_min, self.row_max))));
        let all = || std::iter::once(self).chain(copies.iter().flatten());
        let x0 = (SUBPIXEL_ONE / 2) as i64;
        let mut zr = self.z.rows(x0, first, Z_FRAC);
        let mut cr: Vec<[RoundDivSteps; 3]> = all()
            .map(|t| [0, 1, 2].map(|k| t.c[k].rows(x0, first, 0)))
            .collect();
        let mut cols = self.column_rows(first);
        for j in first..=last {
            if let Some((xl, xr)) = cols.columns(width) {
                let z0 = zr.value() as i64;
                for (i, (t, r)) in all().zip(&cr).enumerate() {
                    let w = t.word(xl, xr, z0, r.map(|r| r.value() as i64));
                    debug_assert_eq!(Some(w), t.span(j, width));
                    f(i, j as u32, w);
                }
            }
            cols.advance();
            zr.advance();
            for r in cr.iter_mut().flatten() {
                r.advance();
            }
        }
    }

    /// Whether `a` and `b` have the same snapped vertices, depths and decal host: their
    /// span words then have the same rows, columns and depths (a shade-channel copy and
    /// its polygon; see [`TriSetup::for_each_span_shared`]).
    pub fn same_geometry(a: &SnappedTri, b: &SnappedTri) -> bool {
        (a.v, a.z, a.host) == (b.v, b.z, b.host)
    }

    /// Builds the word from the row origins `Z0` (Q24.12) and `C0` (Q8.12) at the centre of
    /// column 0: `ZL = Z0 + XL·dZ`, `IL = C0 + XL·dI`. Every span of one plane on one row
    /// thus gives the same value at the same pixel, whatever its XL (a pattern ties exactly
    /// with its face). A one-pixel span is sent with zero slopes (its value is unchanged).
    #[inline]
    fn word(&self, xl: i64, xr: i64, z0: i64, c0: [i64; 3]) -> SpanWord {
        let single = xl == xr;
        let (zl, dz) = depth_fields(z0, xl, xr, self.dz);
        let il = [0, 1, 2].map(|k| (c0[k] + xl * self.di[k]).clamp(0, (1 << IL_BITS) - 1) as u32);
        let di = if single {
            [0; 3]
        } else {
            self.di.map(|d| d as i32)
        };
        let w = SpanWord {
            attr: Attr::Op,
            xl: xl as u16,
            xr: xr as u16,
            zl,
            dz,
            il,
            di,
            tag: self.tag,
            nclass: self.nclass,
            decal: self.decal,
            chan: self.chan,
        };
        debug_assert!(w.check().is_ok(), "span word out of range: {w:?}");
        debug_assert!(
            w.dz.abs() < 1 << (DZ_BITS - 1) && di.iter().all(|d| d.abs() < 1 << (DI_BITS - 1))
        );
        debug_assert!(w.z_at(xr) < pixelproc_formats::Z_FAR);
        w
    }

    /// Depth of the triangle's plane at a pixel centre, Q24.12 (for debug images and tests).
    pub fn z_q12_at_centre(&self, i: i64, j: i64) -> i64 {
        let one = SUBPIXEL_ONE as i64;
        self.z.at(i * one + one / 2, j * one + one / 2, Z_FRAC)
    }
}

/// Three random vertices (pixels) of kind `kind`: 0 on the half-pixel lattice of a small
/// screen (flat edges, centres on edges), 1 anywhere around a screen `wide` pixels wide,
/// 2 anywhere in the coordinate range.
#[cfg(test)]
pub(crate) fn random_vertices(
    rng: &mut crate::rng::XorShift64Star,
    kind: usize,
    wide: f64,
) -> [[f64; 2]; 3] {
    let lim = pixelproc_formats::MAX_COORD_PX as f64;
    std::array::from_fn(|_| match kind {
        0 => [
            (rng.unit() * 80.0).round() / 2.0,
            (rng.unit() * 60.0).round() / 2.0,
        ],
        1 => [rng.unit() * wide - 10.0, rng.unit() * 50.0 - 10.0],
        _ => [
            (rng.unit() * 2.0 - 1.0) * lim,
            (rng.unit() * 2.0 - 1.0) * lim,
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(v: [[f64; 2]; 3]) -> SnappedTri {
        SnappedTri {
            v: v.map(|p| p.map(|x| snap_coord(x).unwrap())),
            z: [1000, 2000, 3000],
            c: [[255 << 12; 3]; 3],
            ..Default::default()
        }
    }

    #[test]
    fn snapping_rounds_half_away_and_rejects_bad_values() {
        assert_eq!(snap_coord(0.5 / 256.0).unwrap(), 1);
        assert_eq!(snap_coord(-0.5 / 256.0).unwrap(), -1);
        assert_eq!(snap_coord(1.0).unwrap(), 256);
        assert!(matches!(
            snap_coord(f64::NAN),
            Err(SetupError::NotFinite(_))
        ));
        assert!(matches!(snap_coord(1e9), Err(SetupError::OutOfRange(_))));
    }

    /// The stepped columns equal the divided ones on every row, from any first row: random
    /// triangles with vertices on the pixel lattice's centres and edges (flat edges, centres
    /// exactly on edges) and anywhere in the coordinate range, clamped to narrow and wide
    /// lines.
    #[test]
    fn stepped_columns_equal_divided_columns_on_every_row() {
        let mut rng = crate::rng::XorShift64Star(0x000c_01d5_7e95);
        let (mut rows, mut some) = (0, 0);
        for case in 0..3000 {
            let v = random_vertices(&mut rng, case % 3, 60.0);
            let Some(t) = TriSetup::new(&tri(v)).unwrap() else {
                continue;
            };
            let width = [1u32, 16, 40, 4096][case % 4];
            let first = t.row_min + (rng.unit() * 4.0) as i64 - 2;
            let last = t.row_max.min(first + 200);
            let mut cols = t.column_rows(first);
            for j in first..=last {
                if j >= t.row_min {
                    let got = cols.columns(width);
                    assert_eq!(got, t.columns(j, width), "case {case} row {j} {v:?}");
                    rows += 1;
                    some += got.is_some() as u32;
                }
                cols.advance();
            }
        }
        assert!(
            rows > 50_000 && some > 20_000,
            "{rows} rows, {some} covered"
        );
    }

    #[test]
    fn degenerate_triangle_covers_nothing() {
        let t = tri([[0.0, 0.0], [5.0, 5.0], [10.0, 10.0]]);
        assert!(TriSetup::new(&t).unwrap().is_none());
    }

    #[test]
    fn square_split_in_two_covers_each_centre_once() {
        let a = TriSetup::new(&tri([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]))
            .unwrap()
            .unwrap();
        let b = TriSetup::new(&tri([[4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]))
            .unwrap()
            .unwrap();
        for j in 0..4 {
            let mut n = [0; 4];
            for t in [&a, &b] {
                if let Some((l, r)) = t.columns(j, 16) {
                    for k in l..=r {
                        n[k as usize] += 1;
                    }
                }
            }
            assert_eq!(n, [1; 4], "row {j}");
        }
    }

    #[test]
    fn plane_values_are_exact_at_vertices_on_centres() {
        // Vertices on pixel centres: ZL at a vertex equals its depth exactly.
        let mut t = tri([[0.5, 0.5], [8.5, 0.5], [0.5, 8.5]]);
        t.z = [100, 900, 500];
        let s = TriSetup::new(&t).unwrap().unwrap();
        let w = s.span(0, 16).unwrap();
        // (8.5, 0.5) lies on the hypotenuse, a right edge: excluded by the top-left rule.
        assert_eq!((w.xl, w.xr), (0, 7));
        assert_eq!(w.z_at(0), 100);
        assert_eq!(w.z_at(7), 800);
        assert_eq!(w.dz, 100 << 12);
    }
}
