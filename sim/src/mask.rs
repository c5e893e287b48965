//! Fraction-mask generation: one bit per subpixel centre, from a snapped triangle's edges.
//!
//! Implements the "mask generation" process of seed 000 (JP2569952B2, background, process
//! 1): each pixel is an area of n×m subpixels; every polygon edge gives an *edge mask* (the
//! subpixel centres on its inner side) and the Boolean AND of the three edge masks is the
//! polygon's **fraction mask** in that pixel. No subpixel depth is computed (claim 1,
//! step 1). Bit order and sizes are those of [`pixelproc_formats::abuffer`].
//!
//! **Integer evaluation.** With edges wound so that `E(x, y) = A·x + B·y + C` (Q.8 units,
//! as in [`crate::setup`]) is positive inside, the centre of subpixel (c, r) of pixel
//! (i, j) is `x = i + (2c+1)/(2n)`, `y = j + (2r+1)/(2m)`, which is not a Q.8 integer for
//! every size. The edge function is therefore scaled by `4nm`:
//!
//! ```text
//! E' = 256·2m·A·X + 256·2n·B·Y + 4nm·C,   X = 2n·i + 2c + 1,   Y = 2m·j + 2r + 1
//! ```
//!
//! which is `4nm·E` exactly at every subpixel centre, an integer for every size, and at most
//! about 2^55 in magnitude for the coordinate range of the formats (`i64`).
//!
//! **Fill rule.** The top-left rule of [`crate::setup`] applied at subpixel centres: a centre
//! with `E' = 0` belongs to the triangle only if the edge is a left edge (`A > 0`) or a top
//! edge (`A = 0, B > 0`). Two triangles sharing an edge therefore cover every subpixel centre
//! on their union exactly once.

use crate::raster::edge::{check_coords, rewind, winding, EdgeFn};
use crate::raster::floor_div;
use crate::raster::rows::touched_rows;
use crate::setup::{SetupError, SnappedTri};
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_formats::SUBPIXEL_ONE;

/// One scaled edge function `E' = ax·X + by·Y + c0` (see the module header): `4nm` times
/// the edge function `edge`, whose fill rule it keeps.
#[derive(Clone, Copy, Debug)]
struct ScaledEdge {
    ax: i64,
    by: i64,
    c0: i64,
    edge: EdgeFn,
    /// The bound of a sloped edge (`ax ≠ 0`) on one subpixel row is `±⌊M / D⌋` with
    /// `D = 2|ax|` and `M` growing by `±2·by` per subpixel row: that step as
    /// `(⌊s / D⌋, s mod D)`, prepared once so that the next rows take additions only.
    step: (i64, i64),
}

impl ScaledEdge {
    #[inline]
    fn inside(&self, e: i64) -> bool {
        self.edge.inside(e)
    }
}

/// The three edges of a triangle, ready to produce fraction masks of one size.
#[derive(Clone, Debug)]
pub struct MaskEdges {
    size: MaskSize,
    edges: [ScaledEdge; 3],
    /// First pixel row that may hold covered subpixel centres (unclamped).
    pub row_min: i64,
    /// Last pixel row that may hold covered subpixel centres (unclamped).
    pub row_max: i64,
}

/// The pixels of one row a triangle touches: every pixel with a covered subpixel centre
/// lies in `touched`; every pixel in `full` (if any) has all its subpixel centres covered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowCoverage {
    /// Inclusive range of pixel columns that may have covered subpixels.
    pub touched: (i64, i64),
    /// Inclusive range of pixel columns that are fully covered, or `None`.
    pub full: Option<(i64, i64)>,
}

/// One pixel row of a triangle: its [`RowCoverage`] and, per subpixel row, the inclusive
/// range of global subpixel columns `g = n·i + c` whose centres are covered. A triangle is
/// convex, so on one subpixel row the centres inside all three edges form one interval:
/// the one [`MaskEdges::row_coverage`] computes from the edges with the same fill rule as
/// [`MaskEdges::edge_mask`]. A pixel's fraction mask is therefore that interval cut to the
/// pixel's columns, row by row ([`RowMasks::mask`]).
#[derive(Clone, Copy, Debug)]
pub struct RowMasks {
    size: MaskSize,
    /// Covered columns per subpixel row (`lo > hi`: none).
    rows: [(i64, i64); 8],
    /// The pixels touched and fully covered.
    pub cov: RowCoverage,
}

impl RowMasks {
    /// The fraction mask of pixel `i` of the row: equal to [`MaskEdges::fraction_mask`].
    #[inline]
    pub fn mask(&self, i: i64) -> u64 {
        let (n, m) = (self.size.n() as i64, self.size.m() as i64);
        let (c0, c1) = (n * i, n * i + n - 1);
        let mut mask = 0u64;
        for (r, &(lo, hi)) in self.rows.iter().enumerate().take(m as usize) {
            let (a, b) = (lo.max(c0) - c0, hi.min(c1) - c0);
            if a <= b {
                // Columns a..=b are bits n·r + (n − 1 − c): a contiguous run.
                let run = (1u64 << (b - a + 1)) - 1;
                mask |= run << (n * r as i64 + n - 1 - b);
            }
        }
        mask
    }
}

impl MaskEdges {
    /// Edge functions of a snapped triangle for masks of `size`. `Ok(None)` for a zero-area
    /// triangle, which covers nothing.
    pub fn new(t: &SnappedTri, size: MaskSize) -> Result<Option<MaskEdges>, SetupError> {
        check_coords(&t.v)?;
        let Some(order) = winding(t.v) else {
            return Ok(None);
        };
        let v = rewind(order, t.v);
        let (n, m) = (size.n() as i64, size.m() as i64);
        let one = SUBPIXEL_ONE as i64;
        let scaled = |e: EdgeFn| {
            let (ax, by) = (one * 2 * m * e.a, one * 2 * n * e.b);
            // See `subrow_intervals`: left edges step `M` by 2·by, right edges by −2·by.
            let step = match ax.signum() {
                1 => (floor_div(2 * by, 2 * ax), (2 * by).rem_euclid(2 * ax)),
                -1 => (floor_div(-2 * by, -2 * ax), (-2 * by).rem_euclid(-2 * ax)),
                _ => (0, 0),
            };
            ScaledEdge {
                ax,
                by,
                c0: 4 * n * m * e.c,
                edge: e,
                step,
            }
        };
        let ymin = v.iter().map(|p| p[1]).min().unwrap_or(0) as i64;
        let ymax = v.iter().map(|p| p[1]).max().unwrap_or(0) as i64;
        let (row_min, row_max) = touched_rows(ymin, ymax);
        Ok(Some(MaskEdges {
            size,
            edges: EdgeFn::of_triangle(v).map(scaled),
            row_min,
            row_max,
        }))
    }

    /// The mask size.
    pub fn size(&self) -> MaskSize {
        self.size
    }

    /// Edge mask of edge `k` (0..3) in pixel (i, j): the subpixel centres on its inner side.
    pub fn edge_mask(&self, k: usize, i: i64, j: i64) -> u64 {
        let e = &self.edges[k];
        let (n, m) = (self.size.n() as i64, self.size.m() as i64);
        let mut mask = 0u64;
        for r in 0..m {
            let y = 2 * m * j + 2 * r + 1;
            let mut val = e.ax * (2 * n * i + 1) + e.by * y + e.c0;
            for c in 0..n {
                if e.inside(val) {
                    mask |= 1u64 << self.size.bit_index(c as u32, r as u32);
                }
                val += 2 * e.ax;
            }
        }
        mask
    }

    /// The fraction mask of pixel (i, j): the AND of the three edge masks.
    pub fn fraction_mask(&self, i: i64, j: i64) -> u64 {
        self.edge_mask(0, i, j) & self.edge_mask(1, i, j) & self.edge_mask(2, i, j)
    }

    /// Inclusive range of global subpixel columns `g = n·i + c` covered on global subpixel
    /// row `y_sub = m·j + r`, or `None`: the direct form of [`MaskEdges::subrow_intervals`]
    /// (which the tests hold against it).
    #[cfg(test)]
    fn subrow_interval(&self, y_sub: i64) -> Option<(i64, i64)> {
        use crate::raster::ceil_div;
        let y = 2 * y_sub + 1;
        let (mut lo, mut hi) = (i64::MIN / 4, i64::MAX / 4);
        for e in &self.edges {
            // E' at column g is ax·(2g + 1) + k.
            let k = e.by * y + e.c0;
            match e.ax.cmp(&0) {
                std::cmp::Ordering::Greater => {
                    // Left edge (inclusive): 2g·ax ≥ −k − ax.
                    lo = lo.max(ceil_div(-k - e.ax, 2 * e.ax));
                }
                std::cmp::Ordering::Less => {
                    // Right edge (exclusive): 2g·(−ax) < k + ax.
                    hi = hi.min(ceil_div(k + e.ax, -2 * e.ax) - 1);
                }
                std::cmp::Ordering::Equal => {
                    if !e.inside(k) {
                        return None;
                    }
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// [`MaskEdges::subrow_interval`] of the `m` subpixel rows of each pixel row `j_first`,
    /// `j_first + 1`, … (`rows` of them), handed to `f(j, intervals)` in order (`lo > hi`
    /// for none; entries past `m` are empty): per sloped edge one division on the first
    /// subpixel row, then exact floor steps from one subpixel row to the next, also across
    /// pixel rows.
    ///
    /// A left edge (`ax > 0`) bounds `lo = ceil((−k − ax) / 2ax) = −⌊(k + ax) / 2ax⌋`, a
    /// right edge `hi = ceil((k + ax) / −2ax) − 1 = −⌊(−k − ax) / −2ax⌋ − 1`, and `k` grows
    /// by `2·by` per subpixel row.
    fn subrow_intervals(
        &self,
        j_first: i64,
        rows: usize,
        mut f: impl FnMut(i64, &[(i64, i64); 8]),
    ) {
        let m = self.size.m() as usize;
        let y0 = 2 * (m as i64 * j_first) + 1;
        // Per edge, `⌊num / d⌋` as quotient and remainder, one subpixel row before the
        // first (every row then takes the same step); `num` is `k + ax` for a left edge,
        // `−k − ax` for a right one, and `k` for a horizontal one (`d = 1`, steps `2·by`),
        // which is inside where `k > thr`.
        let mut q = [0i64; 3];
        let mut rem = [0i64; 3];
        let mut d = [1i64; 3];
        let mut step = [(0i64, 0i64); 3];
        let (mut left, mut right, mut flat) = ([false; 3], [false; 3], [false; 3]);
        let mut thr = [0i64; 3];
        for (x, e) in self.edges.iter().enumerate() {
            let k0 = e.by * y0 + e.c0;
            let num = match e.ax.signum() {
                1 => {
                    left[x] = true;
                    d[x] = 2 * e.ax;
                    step[x] = e.step;
                    k0 + e.ax
                }
                -1 => {
                    right[x] = true;
                    d[x] = -2 * e.ax;
                    step[x] = e.step;
                    -(k0 + e.ax)
                }
                _ => {
                    flat[x] = true;
                    thr[x] = if e.edge.inside(0) { -1 } else { 0 };
                    step[x] = (2 * e.by, 0);
                    k0
                }
            };
            q[x] = floor_div(num, d[x]) - step[x].0;
            rem[x] = num.rem_euclid(d[x]) - step[x].1;
            if rem[x] < 0 {
                rem[x] += d[x];
                q[x] -= 1;
            }
        }
        for row in 0..rows {
            let mut out = [(1, 0); 8];
            for o in out.iter_mut().take(m) {
                let (mut lo, mut hi, mut outside) = (i64::MIN / 4, i64::MAX / 4, false);
                for x in 0..3 {
                    q[x] += step[x].0;
                    rem[x] += step[x].1;
                    let wrap = rem[x] >= d[x];
                    // As likely as not on an edge's subpixel rows: no branch.
                    rem[x] -= std::hint::select_unpredictable(wrap, d[x], 0);
                    q[x] += wrap as i64;
                    lo = lo.max(if left[x] { -q[x] } else { i64::MIN / 4 });
                    hi = hi.min(if right[x] { -q[x] - 1 } else { i64::MAX / 4 });
                    outside |= flat[x] & (q[x] <= thr[x]);
                }
                if !outside && lo <= hi {
                    *o = (lo, hi);
                }
            }
            f(j_first + row as i64, &out);
        }
    }

    /// [`MaskEdges::row_coverage`] with the covered subpixel columns of each subpixel row,
    /// from which [`RowMasks::mask`] gives every pixel's fraction mask without evaluating
    /// the edges per pixel.
    pub fn row_masks(&self, j: i64, width: u32) -> Option<RowMasks> {
        let mut out = None;
        self.band_row_masks(j, j, width, |_, rm| out = Some(rm));
        out
    }

    /// [`MaskEdges::row_masks`] of every row `j0..=j1` the triangle covers, handed to
    /// `f(j, masks)` in row order: the same masks, with one division per sloped edge for
    /// all the rows instead of one per row.
    pub fn band_row_masks(&self, j0: i64, j1: i64, width: u32, mut f: impl FnMut(i64, RowMasks)) {
        let (lo, hi) = (j0.max(self.row_min), j1.min(self.row_max));
        if lo > hi {
            return;
        }
        self.subrow_intervals(lo, (hi - lo + 1) as usize, |j, rows| {
            if let Some(cov) = self.coverage_of(rows, width) {
                f(
                    j,
                    RowMasks {
                        size: self.size,
                        rows: *rows,
                        cov,
                    },
                );
            }
        });
    }

    /// Which pixels of row `j` within `0..width` the triangle touches and fully covers, or
    /// `None` if it covers no subpixel centre of the row.
    pub fn row_coverage(&self, j: i64, width: u32) -> Option<RowCoverage> {
        self.row_masks(j, width).map(|r| r.cov)
    }

    /// The coverage of a pixel row from its subpixel rows' covered columns (`lo > hi`:
    /// none).
    fn coverage_of(&self, rows: &[(i64, i64); 8], width: u32) -> Option<RowCoverage> {
        let (n, m) = (self.size.n() as i64, self.size.m() as usize);
        let gmax = n * width as i64 - 1;
        // Extremes of the clamped row bounds first: the pixel bounds below are monotone
        // in them, so one division each gives the min / max over the rows.
        let (mut lo_min, mut hi_max) = (i64::MAX, i64::MIN);
        let (mut lo_max, mut hi_min) = (i64::MIN, i64::MAX);
        let mut all_rows = true;
        for &(lo, hi) in rows.iter().take(m) {
            let (lo, hi) = (lo.max(0), hi.min(gmax));
            if lo > hi {
                all_rows = false;
                continue;
            }
            lo_min = lo_min.min(lo);
            hi_max = hi_max.max(hi);
            lo_max = lo_max.max(lo);
            hi_min = hi_min.min(hi);
        }
        if lo_min > hi_max {
            return None;
        }
        // The clamped bounds are ≥ 0 (and `hi_min + 1` too): floor division is `/`, and
        // for the usual power-of-two `n` a shift.
        let div = |x: i64| {
            if n.count_ones() == 1 {
                x >> n.trailing_zeros()
            } else {
                x / n
            }
        };
        let (tlo, thi) = (div(lo_min), div(hi_max));
        let (flo, fhi) = (div(lo_max + n - 1), div(hi_min + 1) - 1);
        let full = (all_rows && flo <= fhi).then_some((flo, fhi));
        Some(RowCoverage {
            touched: (tlo, thi),
            full,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(v: [[i32; 2]; 3]) -> SnappedTri {
        SnappedTri {
            v,
            ..Default::default()
        }
    }

    #[test]
    fn half_pixel_split_gives_the_left_columns() {
        // A big triangle whose right edge is the vertical line x = 10.5 px: in pixel 10 the
        // subpixel centres at +0.125 and +0.375 (columns 2, 3) lie right of it.
        let t = tri([[0, 0], [2688, 0], [2688, 25600]]); // (0,0), (10.5,0), (10.5,100)
        let e = MaskEdges::new(&t, MaskSize::S4X4).unwrap().unwrap();
        // Row 50 is far below the diagonal's reach at x = 10: only the x-limit matters.
        // Columns 0 and 1 of every row: bits 3, 2, 7, 6, 11, 10, 15, 14 = 0xCCCC.
        assert_eq!(e.fraction_mask(10, 50), 0xCCCC);
    }

    #[test]
    fn right_edge_through_centres_excludes_them() {
        // Vertical right edge exactly through the centres of column 2 (x = 10 + 5/8 px =
        // 2720/256): the right edge excludes them, columns 0 and 1 remain.
        let t = tri([[0, 0], [2720, 0], [2720, 25600]]);
        let e = MaskEdges::new(&t, MaskSize::S4X4).unwrap().unwrap();
        assert_eq!(e.fraction_mask(10, 50), 0xCCCC);
        // The complementary triangle on the right takes them.
        let u = tri([[2720, 0], [5120, 0], [2720, 25600]]);
        let f = MaskEdges::new(&u, MaskSize::S4X4).unwrap().unwrap();
        assert_eq!(f.fraction_mask(10, 1), 0x3333);
    }

    #[test]
    fn row_masks_equal_the_and_of_the_edge_masks() {
        // Every pixel of every row of random triangles (small and large, edges through
        // subpixel centres on a coarse grid, every winding) for several sizes: the mask cut
        // from the subpixel-row intervals is the per-pixel AND of the three edge masks.
        let mut rng = crate::rng::Lcg64(0x5eed_0f3a_5c00);
        let (w, h) = (12u32, 10u32);
        let sizes = [(4, 4), (8, 8), (2, 2), (3, 5), (8, 1), (1, 8), (5, 7)];
        let mut compared = 0u64;
        for k in 0..600 {
            let (n, m) = sizes[k % sizes.len()];
            let size = MaskSize::new(n, m).unwrap();
            // Coordinates on a 1/16 px grid (many on subpixel centres and boundaries) or
            // any Q.8 value, reaching past the screen.
            let grid = if k % 2 == 0 { 16 } else { 1 };
            let mut coord = |lim: u32| {
                let span = (lim as u64 + 4) * 256 / grid as u64;
                (((rng.step() >> 33) % span) as i64 * grid - 512) as i32
            };
            let t = tri([
                [coord(w), coord(h)],
                [coord(w), coord(h)],
                [coord(w), coord(h)],
            ]);
            let Some(e) = MaskEdges::new(&t, size).unwrap() else {
                continue;
            };
            // The intervals stepped from one division are the direct ones on every
            // subpixel row, also off screen and across pixel rows.
            let mut rows_seen = 0;
            e.subrow_intervals(-2, h as usize + 4, |j, stepped| {
                assert_eq!(j, rows_seen - 2);
                rows_seen += 1;
                for (r, &got) in stepped.iter().enumerate().take(m as usize) {
                    let direct = e.subrow_interval(m as i64 * j + r as i64);
                    assert_eq!((got.0 <= got.1).then_some(got), direct, "{k} row {j}.{r}");
                }
            });
            assert_eq!(rows_seen, h as i64 + 4);
            // A band's masks are the rows' own, for bands starting anywhere.
            let j0 = (k as i64 % 5) - 2;
            let mut band = Vec::new();
            e.band_row_masks(j0, j0 + 6, w, |j, rm| band.push((j, rm.rows, rm.cov)));
            let own: Vec<_> = (j0..=j0 + 6)
                .filter_map(|j| e.row_masks(j, w).map(|rm| (j, rm.rows, rm.cov)))
                .collect();
            assert_eq!(band, own, "{k}");
            for j in -2..h as i64 + 2 {
                if !(0..h as i64).contains(&j) {
                    continue;
                }
                let rm = e.row_masks(j, w);
                for i in 0..w as i64 {
                    let want = e.fraction_mask(i, j);
                    let got = rm.map_or(0, |r| r.mask(i));
                    assert_eq!(got, want, "triangle {k} {:?} {n}x{m} pixel ({i}, {j})", t.v);
                    if let Some(r) = rm {
                        let (a, b) = r.cov.touched;
                        assert!(
                            want == 0 || (a <= i && i <= b),
                            "touched range misses a mask"
                        );
                        if let Some((fa, fb)) = r.cov.full {
                            if fa <= i && i <= fb {
                                assert_eq!(want, size.full());
                            }
                        }
                    }
                    compared += (want != 0) as u64;
                }
            }
        }
        assert!(compared > 5_000, "only {compared} non-empty masks compared");
    }
}
