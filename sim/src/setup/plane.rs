//! The exact plane through a triangle's three snapped vertices (seed 001 section 3: the
//! depth and intensity a span word carries): exact `i128` rationals, evaluated at a point
//! or stepped down the rows with additions only. Span setup, shadow triangles, fragments,
//! multi-scanning and the samplers all evaluate this one plane.

use crate::raster::{round_div, RoundDivStep, RoundDivSteps};
use pixelproc_formats::SUBPIXEL_ONE;

/// A plane `v(x, y) = v0 + (nx·(x − x0) + ny·(y − y0)) / area2` through three snapped
/// points, exact rationals (`area2 > 0`). The one exact plane of the golden model: span
/// setup, fragments, multi-scanning and the samplers all evaluate it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ExactPlane {
    pub(crate) v0: i128,
    pub(crate) x0: i128,
    pub(crate) y0: i128,
    pub(crate) nx: i128,
    pub(crate) ny: i128,
    pub(crate) area2: i128,
}

impl ExactPlane {
    /// Plane through three points; `None` if they are collinear.
    pub(crate) fn new(v: [[i32; 2]; 3], val: [i64; 3]) -> Option<ExactPlane> {
        let (x0, y0) = (v[0][0] as i128, v[0][1] as i128);
        let (dx1, dy1) = (v[1][0] as i128 - x0, v[1][1] as i128 - y0);
        let (dx2, dy2) = (v[2][0] as i128 - x0, v[2][1] as i128 - y0);
        let area2 = dx1 * dy2 - dx2 * dy1;
        if area2 == 0 {
            return None;
        }
        let dv1 = (val[1] - val[0]) as i128;
        let dv2 = (val[2] - val[0]) as i128;
        // Normalised to area2 > 0 (the value is unchanged: all terms flip with it).
        let s = area2.signum();
        Some(ExactPlane {
            v0: val[0] as i128,
            x0,
            y0,
            nx: s * (dv1 * dy2 - dv2 * dy1),
            ny: s * (dx1 * dv2 - dx2 * dv1),
            area2: s * area2,
        })
    }

    /// `round(v(x, y) · 2^frac)` at a Q.8 point, half up.
    pub(super) fn at(&self, x_q8: i64, y_q8: i64, frac: u32) -> i64 {
        let num = (self.v0 * self.area2
            + self.nx * (x_q8 as i128 - self.x0)
            + self.ny * (y_q8 as i128 - self.y0))
            << frac;
        round_div(num, self.area2) as i64
    }

    /// Exact incremental evaluator of `round(v(x_q8, y) · 2^frac)` down successive rows
    /// (y += 1 px): the quotient and remainder of `2·N + area2` by `2·area2` are stepped by
    /// the constant row increment (the raster core's [`RoundDivSteps`]), so every row's
    /// value equals [`ExactPlane::at`] bit for bit with additions only.
    #[inline]
    pub(super) fn rows(&self, x_q8: i64, first_row: i64, frac: u32) -> RoundDivSteps {
        self.rows_by(x_q8, first_row, frac, &self.row_step(frac))
    }

    /// The row step of [`ExactPlane::rows`] (one division), for [`ExactPlane::rows_by`].
    #[inline]
    pub(super) fn row_step(&self, frac: u32) -> RoundDivStep {
        RoundDivStep::new((self.ny * SUBPIXEL_ONE as i128) << frac, self.area2)
    }

    /// [`ExactPlane::rows`] with its row step `step` ([`ExactPlane::row_step`] of the same
    /// `frac`) prepared once.
    #[inline]
    pub(super) fn rows_by(
        &self,
        x_q8: i64,
        first_row: i64,
        frac: u32,
        step: &RoundDivStep,
    ) -> RoundDivSteps {
        let one = SUBPIXEL_ONE as i128;
        let yc = first_row as i128 * one + one / 2;
        let n =
            (self.v0 * self.area2 + self.nx * (x_q8 as i128 - self.x0) + self.ny * (yc - self.y0))
                << frac;
        RoundDivSteps::start(n, step)
    }

    /// `round(∂v/∂x · 2^frac)` per pixel, half up.
    #[inline]
    pub(super) fn ddx_per_px(&self, frac: u32) -> i64 {
        round_div((self.nx * SUBPIXEL_ONE as i128) << frac, self.area2) as i64
    }
}
