//! A shadow polygon's triangles and their SP span words (seed 001 section 4: a shadow span
//! tests depth only, so it carries no intensities).

use super::columns::{ColumnRows, ColumnSteps};
use super::plane::ExactPlane;
use super::{depth_fields, rows_of, SetupError, SnappedTri, TriSetup};
use crate::raster::edge::{rewind, winding, EdgeFn};
use crate::raster::{PlaneStepper, RoundDivStep, RoundDivSteps};
use pixelproc_formats::{Attr, SpanWord, SUBPIXEL_ONE, Z_FRAC};

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
            tag: t.tag,
            nclass: t.nclass,
            chan: t.chan,
        }))
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
