//! A triangle's pixel columns on successive scanlines (the fill convention of
//! [`super`]: pixel centres inside the triangle, top-left rule on its edges), stepped with
//! additions only instead of a division per edge and row: the `XL` and `XR` of seed 001
//! section 3's span words.

use crate::raster::edge::EdgeFn;
use crate::raster::{FloorStep, FloorSteps};
use pixelproc_formats::SUBPIXEL_ONE;

#[cfg(doc)]
use super::{ShadowTri, TriSetup};

/// Which column bound an edge sets on a scanline (the three cases of
/// [`TriSetup::columns`]).
#[derive(Clone, Copy, Debug)]
enum EdgeBound {
    /// `A > 0`: the first column, `⌈−k / 256A⌉ = −⌊k / 256A⌋`.
    Left,
    /// `A < 0`: the last column, `⌈k / −256A⌉ − 1 = −⌊−k / −256A⌋ − 1`.
    Right,
    /// `A = 0`: the whole row is in or out by the fill rule on `k` (the edge's top-left
    /// flag).
    Flat(bool),
}

/// [`TriSetup::columns`] on successive rows with additions only
/// ([`TriSetup::column_rows`]): per edge, the floor quotient its bound is made of, stepped
/// by the edge function's row increment instead of divided afresh on every row. The same
/// columns, bit for bit. A triangle of non-zero area has a left edge and a right one (its
/// edges' `A`, `−Δy`, sum to zero), so only the third edge's kind varies.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColumnSteps {
    left: FloorSteps,
    right: FloorSteps,
    third: (EdgeBound, FloorSteps),
}

/// A triangle's [`ColumnSteps`] prepared once, to start at any row with one division per
/// edge ([`ShadowTri`]'s, started once per band).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColumnRows {
    left: EdgeRows,
    right: EdgeRows,
    third: (EdgeBound, EdgeRows),
}

/// One edge of [`ColumnRows`]: the edge function's row origin
/// `k(j) = s·(B·yc(j) + C + A·128)` (`s` the sign of its bound) and the floor step of its
/// row increment.
#[derive(Clone, Copy, Debug)]
struct EdgeRows {
    /// `s·B` and `s·(C + A·128)`.
    b: i64,
    c: i64,
    step: FloorStep,
}

impl EdgeRows {
    /// The bound edge `e` sets, and its rows.
    #[inline]
    fn of(e: &EdgeFn) -> (EdgeBound, EdgeRows) {
        let one = SUBPIXEL_ONE as i64;
        // E at column i of row j is 256·A·i + k(j), k(j + 1) = k(j) + 256·B.
        let (b, c) = (e.b, e.c + e.a * (one / 2));
        let (bound, s, d) = match e.a.cmp(&0) {
            std::cmp::Ordering::Greater => (EdgeBound::Left, 1, one * e.a),
            std::cmp::Ordering::Less => (EdgeBound::Right, -1, -one * e.a),
            std::cmp::Ordering::Equal => (EdgeBound::Flat(e.top_left), 1, 1),
        };
        let rows = EdgeRows {
            b: s * b,
            c: s * c,
            step: FloorStep::new(s * b * one, d),
        };
        (bound, rows)
    }

    /// The floor quotient's stepper from the row whose centre is at `yc` (Q.8).
    #[inline]
    fn start(&self, yc: i64) -> FloorSteps {
        FloorSteps::start(self.b * yc + self.c, &self.step)
    }
}

impl ColumnRows {
    /// Prepares the column steps of a triangle's wound `edges` (of non-zero area).
    #[inline]
    pub(super) fn of(edges: &[EdgeFn; 3]) -> ColumnRows {
        let a = edges.map(|e| e.a);
        let l = if a[0] > 0 {
            0
        } else if a[1] > 0 {
            1
        } else {
            2
        };
        let r = if a[0] < 0 {
            0
        } else if a[1] < 0 {
            1
        } else {
            2
        };
        assert!(
            a[l] > 0 && a[r] < 0,
            "a wound triangle has a left and a right edge"
        );
        ColumnRows {
            left: EdgeRows::of(&edges[l]).1,
            right: EdgeRows::of(&edges[r]).1,
            third: EdgeRows::of(&edges[3 - l - r]),
        }
    }

    /// The stepper from row `first` on.
    #[inline]
    pub(crate) fn at(&self, first: i64) -> ColumnSteps {
        let one = SUBPIXEL_ONE as i64;
        let yc = first * one + one / 2;
        ColumnSteps {
            left: self.left.start(yc),
            right: self.right.start(yc),
            third: (self.third.0, self.third.1.start(yc)),
        }
    }
}

impl ColumnSteps {
    /// The stepper of a triangle's columns (its wound `edges`) from row `first` on.
    #[inline]
    pub(super) fn new(edges: &[EdgeFn; 3], first: i64) -> ColumnSteps {
        ColumnRows::of(edges).at(first)
    }

    /// The current row's inclusive columns, clamped to `0..width`, or `None` (what
    /// [`TriSetup::columns`] gives on that row, if it lies in `row_min..=row_max`).
    #[inline]
    pub(crate) fn columns(&self, width: u32) -> Option<(i64, i64)> {
        let mut lo = (-self.left.value()).max(0);
        let mut hi = (-self.right.value() - 1).min(width as i64 - 1);
        let (bound, q) = &self.third;
        let q = q.value();
        match *bound {
            EdgeBound::Left => lo = lo.max(-q),
            EdgeBound::Right => hi = hi.min(-q - 1),
            EdgeBound::Flat(top_left) => {
                if !(q > 0 || (q == 0 && top_left)) {
                    return None;
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// Moves one row down.
    #[inline]
    pub(crate) fn advance(&mut self) {
        self.left.advance();
        self.right.advance();
        self.third.1.advance();
    }
}
