//! A shadow polygon's triangles and their SP span words (seed 001 section 4: a shadow span
//! tests depth only, so it carries no intensities).

use super::columns::{ColumnRows, ColumnSteps};
use super::plane::ExactPlane;
use super::{depth_fields, rows_of, SetupError, SnappedTri, TriSetup};
use crate::raster::edge::{rewind, winding, EdgeFn};
use crate::raster::{PlaneStepper, RoundDivStep, RoundDivSteps};
use pixelproc_formats::{Attr, SpanWord, SUBPIXEL_BITS, SUBPIXEL_ONE, Z_FRAC};

/// A shadow polygon's triangle, set up for its SP span words (seed 001 §4: a shadow span
/// tests depth only): the edges, the depth plane and the rows of [`TriSetup`], without
/// its three colour planes and slopes (a shadow word's intensities are zero), and with its
/// column and depth row steps prepared, since a volume's triangle is started again on
/// every band of rows it crosses. Its words are
/// [`TriSetup::span`]'s of the same triangle with attr SP and zero intensities and slopes.
#[derive(Clone, Debug)]
pub(crate) struct ShadowTri {
    cols: ColumnRows,
    z: ExactPlane,
    /// The depth plane's row step ([`ExactPlane::row_step`]).
    z_step: RoundDivStep,
    /// First and last scanline whose centre may be covered (unclamped).
    pub(crate) row_min: i64,
    pub(crate) row_max: i64,
    /// dZ, Q26.12 per pixel.
    dz: i64,
    /// `2^Z_FRAC` times the least vertex depth.
    z_min: i64,
    /// The columns whose centres lie within the vertices' `x` (Q.8), unclamped: from
    /// `⌈(x_min − 128) / 256⌉` to `⌊(x_max − 128) / 256⌋`.
    col_box: (i64, i64),
    tag: u16,
    nclass: u8,
    chan: u8,
}

impl ShadowTri {
    /// Prepares a triangle without a decal host ([`TriSetup::new`]'s checks and its
    /// `None` for a degenerate triangle).
    pub(crate) fn new(t: &SnappedTri) -> Result<Option<ShadowTri>, SetupError> {
        debug_assert!(t.host.is_none(), "a shadow polygon has no decal host");
        TriSetup::check(t)?;
        let Some(order) = winding(t.v) else {
            return Ok(None);
        };
        let (v, z) = (rewind(order, t.v), rewind(order, t.z));
        let Some(zp) = ExactPlane::new(v, z.map(|x| x as i64)) else {
            return Ok(None);
        };
        let (row_min, row_max) = rows_of(&v);
        Ok(Some(ShadowTri {
            cols: ColumnRows::of(&EdgeFn::of_triangle(v)),
            dz: zp.ddx_per_px(Z_FRAC),
            z_step: zp.row_step(Z_FRAC),
            z: zp,
            row_min,
            row_max,
            z_min: (z.into_iter().min().unwrap_or(0) as i64) << Z_FRAC,
            col_box: centre_columns(&v),
            tag: t.tag,
            nclass: t.nclass,
            chan: t.chan,
        }))
    }

    /// The columns `lo..=hi` (within `0..width`) that hold every pixel of the triangle's
    /// words, and a lower bound of the depth `Z >> Z_FRAC` the array compares with ZB on
    /// each of those pixels; `None` if the triangle sends no word on any row.
    ///
    /// The bound: a covered pixel centre lies in the closed triangle, so the exact plane
    /// `Q` there (Q.12) is at least `2^12` times the least vertex depth. A word's pixel `p`
    /// gets `Z = max(0, Z0 + XL·dZ) + (p − XL)·dZ ≥ Z0 + p·dZ` (its one-pixel `dZ = 0`
    /// included), where `Z0` and `dZ` are `Q` at column 0's centre and its slope per
    /// pixel, each rounded to within ½: so `Z ≥ Q(p) − ½ − p/2 > 2^12·z_min − hi − 2`.
    #[inline]
    pub(crate) fn depth_floor(&self, width: u32) -> Option<(usize, usize, i64)> {
        let lo = self.col_box.0.max(0);
        let hi = self.col_box.1.min(width as i64 - 1);
        if lo > hi {
            return None;
        }
        Some((lo as usize, hi as usize, (self.z_min - hi - 2) >> Z_FRAC))
    }

    /// The column stepper from row `first` on ([`TriSetup::column_rows`]), from the
    /// steps prepared with the triangle.
    #[inline]
    pub(crate) fn column_rows(&self, first: i64) -> ColumnSteps {
        self.cols.at(first)
    }

    /// The depth plane's row stepper from row `first` on ([`ExactPlane::rows`]), from
    /// the row step prepared with the triangle.
    #[inline]
    pub(crate) fn depth_rows(&self, first: i64) -> RoundDivSteps {
        self.z
            .rows_by((SUBPIXEL_ONE / 2) as i64, first, Z_FRAC, &self.z_step)
    }

    /// The SP word of the row the steppers `cols` and `z` stand at, or `None` if the row
    /// covers no pixel centre: `ZL = Z0 + XL·dZ` (clamped at 0 as [`TriSetup`]'s words
    /// are), dZ zero for a one-pixel span, zero intensities and slopes.
    #[inline]
    pub(crate) fn shadow_span(
        &self,
        width: u32,
        cols: &ColumnSteps,
        z: &impl PlaneStepper,
    ) -> Option<SpanWord> {
        let (xl, xr) = cols.columns(width)?;
        let (zl, dz) = depth_fields(z.value() as i64, xl, xr, self.dz);
        Some(SpanWord {
            attr: Attr::Sp,
            xl: xl as u16,
            xr: xr as u16,
            zl,
            dz,
            il: [0; 3],
            di: [0; 3],
            tag: self.tag,
            nclass: self.nclass,
            decal: false,
            chan: self.chan,
        })
    }
}

/// The columns whose centres `(c + ½)·256` lie within the `x` of the vertices `v` (Q.8),
/// unclamped: every column a triangle through them can cover.
fn centre_columns(v: &[[i32; 2]; 3]) -> (i64, i64) {
    let x = v.map(|p| p[0] as i64 - (SUBPIXEL_ONE / 2) as i64);
    let (lo, hi) = (x.into_iter().min(), x.into_iter().max());
    let one = SUBPIXEL_ONE as i64;
    // ⌈lo / 256⌉ and ⌊hi / 256⌋.
    (
        (lo.unwrap_or(0) + one - 1) >> SUBPIXEL_BITS,
        hi.unwrap_or(0) >> SUBPIXEL_BITS,
    )
}

/// A span word as a shadow polygon sends it: attr SP, zero intensities and slopes (the
/// array's shadow spans test depth only). [`ShadowTri::shadow_span`] makes them directly;
/// the tests compare.
#[cfg(test)]
pub(crate) fn shadow_word(w: SpanWord) -> SpanWord {
    SpanWord {
        attr: Attr::Sp,
        il: [0; 3],
        di: [0; 3],
        ..w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::{random_vertices, snap_coord};
    use pixelproc_formats::{Z_GEOM_MAX, Z_GEOM_MIN};

    /// [`ShadowTri::depth_floor`] bounds every pixel of every word the triangle sends:
    /// the word's columns lie in its range, and the depth the array compares with ZB,
    /// `(ZL + (p − XL)·dZ) >> Z_FRAC`, is at least its floor, which is at most two below
    /// the least vertex depth (one on lines up to 4094 pixels). The words are
    /// [`TriSetup::span`]'s, by division on each row: random triangles on the pixel
    /// lattice, near the screen and anywhere in the coordinate range, with depths near
    /// each other or across the whole range, on lines of 1 to 4096 pixels.
    #[test]
    fn depth_floor_bounds_every_pixel_of_every_word() {
        let mut rng = crate::rng::XorShift64Star(0x0dee_9f10);
        let (mut pixels, mut none, mut tight) = (0u64, 0, 0);
        for case in 0..4000 {
            let v = random_vertices(&mut rng, case % 3, 300.0);
            let span = (Z_GEOM_MAX - Z_GEOM_MIN) as f64;
            let z0 = Z_GEOM_MIN + (rng.unit() * span) as u32;
            let z: [u32; 3] = std::array::from_fn(|_| match case % 4 {
                // Steep: the vertices anywhere in the range.
                0 => Z_GEOM_MIN + (rng.unit() * span) as u32,
                // Nearly flat, or flat.
                1 => z0,
                _ => (z0 + (rng.unit() * 40.0) as u32).min(Z_GEOM_MAX),
            });
            let t = SnappedTri {
                v: v.map(|p| p.map(|x| snap_coord(x).unwrap())),
                z,
                ..Default::default()
            };
            let (Some(s), Some(full)) = (ShadowTri::new(&t).unwrap(), TriSetup::new(&t).unwrap())
            else {
                continue;
            };
            let width = [1u32, 16, 40, 300, 1920, 4096][case % 6];
            let floor = s.depth_floor(width);
            let zmin = *z.iter().min().unwrap() as i64;
            if let Some((_, hi, d)) = floor {
                let most = if hi + 2 <= 1 << Z_FRAC { 1 } else { 2 };
                assert!(
                    d >= zmin - most,
                    "case {case}: floor {d}, least vertex {zmin}"
                );
            }
            let mut least = i64::MAX;
            let rows = full.row_min.max(-2)..=full.row_max.min(400);
            for w in rows.filter_map(|j| full.span(j, width)) {
                let Some((lo, hi, d)) = floor else {
                    panic!("case {case}: a word {w:?} where the floor says none");
                };
                assert!(
                    lo <= w.xl as usize && w.xr as usize <= hi,
                    "case {case}: {w:?} outside {lo}..={hi}"
                );
                for p in w.xl as i64..=w.xr as i64 {
                    let zp = (w.zl as i64 + (p - w.xl as i64) * w.dz) >> Z_FRAC;
                    assert!(
                        zp >= d,
                        "case {case}: pixel {p} at {zp}, floor {d} ({v:?}, {z:?})"
                    );
                    least = least.min(zp);
                    pixels += 1;
                }
            }
            none += floor.is_none() as u32;
            tight += floor.is_some_and(|(_, _, d)| least <= d + 1) as u32;
        }
        assert!(pixels > 1_000_000, "{pixels} pixels");
        assert!(
            none > 100 && tight > 100,
            "{none} without a column, {tight} tight"
        );
    }
}
