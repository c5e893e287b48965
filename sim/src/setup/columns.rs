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
/// columns, bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColumnSteps {
    edges: [(EdgeBound, FloorSteps); 3],
}

/// A triangle's [`ColumnSteps`] prepared once, to start at any row with one division per
/// edge ([`ShadowTri`]'s, started once per band): per edge, its bound, the edge
/// function's row origin `k(j) = s·(B·yc(j) + C + A·128)` (`s` the bound's sign) and the
/// floor step of its row increment.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColumnRows {
    edges: [EdgeRows; 3],
}

/// One edge of [`ColumnRows`].
#[derive(Clone, Copy, Debug)]
struct EdgeRows {
    bound: EdgeBound,
    /// `s·B` and `s·(C + A·128)`.
    b: i64,
    c: i64,
    step: FloorStep,
}

impl ColumnRows {
    /// Prepares the column steps of a triangle's wound `edges`.
    #[inline]
    pub(super) fn of(edges: &[EdgeFn; 3]) -> ColumnRows {
        let one = SUBPIXEL_ONE as i64;
        let rows = edges.map(|e| {
            // E at column i of row j is 256·A·i + k(j), k(j + 1) = k(j) + 256·B.
            let (b, c) = (e.b, e.c + e.a * (one / 2));
            let (bound, s, d) = match e.a.cmp(&0) {
                std::cmp::Ordering::Greater => (EdgeBound::Left, 1, one * e.a),
                std::cmp::Ordering::Less => (EdgeBound::Right, -1, -one * e.a),
                std::cmp::Ordering::Equal => (EdgeBound::Flat(e.top_left), 1, 1),
            };
            EdgeRows {
                bound,
                b: s * b,
                c: s * c,
                step: FloorStep::new(s * b * one, d),
            }
        });
        // A left edge first and a right one second ([`ColumnSteps::columns`]): a
        // triangle of non-zero area has both, its edges' `A` (`−Δy`) summing to zero.
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
            edges: [rows[l], rows[r], rows[3 - l - r]],
        }
    }

    /// The stepper from row `first` on.
    #[inline]
    pub(crate) fn at(&self, first: i64) -> ColumnSteps {
        debug_assert!(matches!(
            (self.edges[0].bound, self.edges[1].bound),
            (EdgeBound::Left, EdgeBound::Right)
        ));
        let one = SUBPIXEL_ONE as i64;
        let yc = first * one + one / 2;
        ColumnSteps {
            edges: self
                .edges
                .map(|e| (e.bound, FloorSteps::start(e.b * yc + e.c, &e.step))),
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
        // The first edge is a left one and the second a right one ([`ColumnRows::of`]).
        let [(_, l), (_, r), (bound, q)] = &self.edges;
        let mut lo = (-l.value()).max(0);
        let mut hi = (-r.value() - 1).min(width as i64 - 1);
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
        for (_, q) in &mut self.edges {
            q.advance();
        }
    }
}
