//! Multi-scanning (seed 002, Nishita & Nakamae, IPSJ 1984): exact spans on sub-scanlines.
//!
//! **Sub-scanlines.** Sampling is continuous along x and discrete along y. A sub-scanline
//! lies at `y = ynum / yden` pixels (`yden = 2n`), exact rationals:
//! - box filter (§2.2.1): `y = j + l/n`, `l = 0..=n`, both pixel boundaries included;
//!   the boundary `l = n` of row `j` is `l = 0` of row `j + 1`;
//! - axisymmetric filters (§2.2.2): `y = j + ½ + l/n`, `l = 0..n`, the sub-scanlines of
//!   the square `R_{i,j}` between the centres of rows `j` and `j + 1`.
//!
//! **Exact spans.** On each sub-scanline every triangle's x-interval is computed from its
//! snapped (Q.8) edges exactly in `i128` and rounded once to **Q.16 pixels** (`x16`,
//! 65536 per pixel, half up). A sub-scanline hits a triangle when `ymin ≤ y < ymax`
//! (the cross-section just below the line). The one exception is the box filter's
//! bottom boundary `l = n` of a row, taken as the cross-section just *above* the line
//! (`ymin < y ≤ ymax`): each row integrates its own side of a horizontal edge lying
//! exactly on a pixel boundary, so an axis-aligned rectangle on pixel boundaries is
//! exact for every n (the seed shares the boundary sub-scanline without saying which
//! side it sees; this is the project's decision, and the shared line costs a second
//! span set only where a horizontal edge lies on it). Two
//! triangles sharing an edge compute the same rational for it, so their intervals meet
//! without gap or overlap.
//!
//! **Hidden surfaces (§3, stack memory NEXT).** Crossings are sorted by x; at equal x
//! the seed's order holds: right crossings before left ones; among right crossings
//! patterns (decals) first, among left crossings faces first (a face's pattern enters
//! after the face and leaves before it). Walking left to right with a current polygon
//! and the stack NEXT: (1) at the left crossing of P, if P is nearer than the current
//! polygon the current one is pushed into NEXT and P becomes current, else P is pushed;
//! (2) at the right crossing of the current polygon the nearest polygon in NEXT becomes
//! current; (3) at the right crossing of another polygon it is removed from NEXT. Depth is
//! evaluated at the crossing from the triangle's plane (decals use their host face's
//! plane), as a Q24.20 integer (exact rational, rounded half up); at equal depth the
//! renderer's order decides (decal over non-decal, later decal over earlier, earlier
//! non-decal over later). The seed assumes polygons that do not interpenetrate; with
//! [`MultiscanParams::intersections`] the walk also checks, between consecutive
//! crossings, whether a polygon of NEXT passes in front of the current one, and switches
//! at the interpolated x (integer division) where it does.
//!
//! **Colour (§3).** Each visible piece inside a pixel (box) or inside a square `R`
//! (axisymmetric) takes the Gouraud intensity at its midpoint (Q8.12, exact rational
//! rounded half up); background pieces take the background colour.
//!
//! **Box filter (§2.2.1, trapezoidal weights).** `C_i = Σ_l d_l Σ_f L_{f,l} I_f` with
//! `d_l = 1/(2n)` at `l = 0, n` and `1/n` otherwise. In integers: `L` in Q.16, `I` in
//! Q8.12, weights `2n·d_l ∈ {1, 2}`, accumulator `u64`; one truncation at the end:
//! `C = ⌊acc / (2n·2^16·2^12)⌋` (intensities carry the +2048 rounding offset of
//! `docs/formats.md`, the background is stored as `bg·4096 + 2048`, so this rounds).
//!
//! **Axisymmetric filters (§2.2.2, the 64-step F_l tables and W_{l,0..3}).** For filter
//! profile `f(r)` of radius 1 (Gaussian `exp(−r²/(2σ²))`, σ = 0.4, or cone `1 − r`),
//! `F_m[k] = ∫_0^{k/64} f(√(t² + (m/n)²)) dt`, `k = 0..=64`, `m = 0..=n`, scaled so that
//! the full weight of a pixel is close to 2^24 and rounded to integers (the table ROM,
//! generated once in f64). A visible piece `[x'_1, x'_2]` (offsets from the left centre of
//! its square, quantised to 1/64) on sub-scanline `l` adds
//! `W_{l,0} = F_l(x'_2) − F_l(x'_1)` to pixel (i, j), `W_{l,1} = F_l(1−x'_1) − F_l(1−x'_2)`
//! to (i+1, j), `W_{l,2} = F_{n−l}(1−x'_1) − F_{n−l}(1−x'_2)` to (i+1, j+1) and
//! `W_{l,3} = F_{n−l}(x'_2) − F_{n−l}(x'_1)` to (i, j+1), each times the intensity. The
//! final colour divides by the exact integer total weight `T` of a fully covered pixel:
//! `C = ⌊acc / (T·2^12)⌋`, so a uniform area stays exactly its colour.
//!
//! **Two rows of pixel memory.** Each sub-scanline adds to at most two pixel rows (box:
//! the boundary sub-scanline; axisymmetric: rows j and j + 1). The model computes bands
//! of 8 pixel rows in parallel (rayon); inside a band each sub-scanline is walked once,
//! top to bottom, and added to the rows it reaches, so only the sub-scanlines shared by
//! two bands are computed twice. The box filter's boundary sub-scanline is walked once
//! for both of its rows unless a horizontal edge lies on it (then each side has its own
//! span set). Pixel sums are integer sums and the visible triangle is the largest weight
//! (then the lowest index), so results do not depend on the order in which sub-scanlines
//! are added. The depth evaluation counter counts each sub-scanline once, as the hardware
//! does.

use rayon::prelude::*;

use super::{AaError, AaFrame, AaStats};
use crate::raster::rows::Bands;
use crate::raster::{floor_div_wide, PlaneStepper, RoundDivStep, RoundDivSteps, RoundDivSteps64};
use crate::setup::SnappedTri;

mod filter;
mod spans;
mod walk;
use filter::{dominant, tables, PixMem, PixRow, Tables};
use spans::{prepare, MsTri, RowPlane};
use walk::{walk, Active, Piece, WalkScratch};

/// Q.16 pixel unit.
const ONE16: i64 = 1 << 16;
/// The largest colour a piece takes (Q8.12 with the rounding offset).
const COLOUR_MAX: i64 = (255 << 12) + 4095;
/// Fractional bits of the depth values compared by the walk.
pub(super) const ZF: u32 = 20;

/// σ of the Gaussian filter, pixels (radius 1, §2.2.2 leaves σ to the implementation).
pub const GAUSS_SIGMA: f64 = 0.4;

/// Filter of the multi-scanning resolve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Box filter over the pixel square, trapezoidal weights (§2.2.1).
    Box,
    /// Gaussian, radius 1, σ = 0.4 (§2.2.2).
    Gauss,
    /// Cone `1 − r`, radius 1 (§2.2.2).
    Cone,
}

/// Parameters of multi-scanning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MultiscanParams {
    /// Sub-scanlines per pixel row, `n` in 1..=16.
    pub subscanlines: u32,
    /// Filter.
    pub filter: Filter,
    /// Handle interpenetrating triangles by switching where depths cross between
    /// crossings (an extension of the seed's walk).
    pub intersections: bool,
}

impl MultiscanParams {
    /// `n` sub-scanlines with `filter`, intersection handling on.
    pub fn new(subscanlines: u32, filter: Filter) -> MultiscanParams {
        MultiscanParams {
            subscanlines,
            filter,
            intersections: true,
        }
    }
}

/// Per-frame constants of a multi-scanning render.
struct MsFrame<'a> {
    mt: &'a [MsTri],
    p: &'a MultiscanParams,
    width: u32,
    height: u32,
    /// Background, Q8.12 with the rounding offset.
    bgc: [i64; 3],
    /// Filter tables (none for the box filter).
    tab: Option<Tables>,
    /// `mt` binned by the pixel rows whose sub-scanlines they can reach.
    bands: Bands,
    /// Find the visible triangle of every pixel (the AOV), else only the colours.
    visible: bool,
}

/// Output of one band of pixel rows besides its pixels: depth evaluations and pieces of
/// the sub-scanlines it owns.
type BandOut = (u64, u64);

impl<'a> MsFrame<'a> {
    /// The triangles hit by the sub-scanline `ynum` (seen from above or below), in input
    /// order, into `act`.
    fn hits(
        &self,
        cand: &[&'a MsTri],
        ynum: i64,
        from_above: bool,
        act: &mut Vec<Active<'a>>,
        crow: &mut Vec<Option<Option<ColourRow>>>,
    ) {
        act.clear();
        crow.clear();
        act.extend(cand.iter().filter_map(|&t| {
            let (xl, xr) = t.interval(ynum, from_above)?;
            Some(Active {
                t,
                z: t.rows[0].row(ynum),
                xl,
                xr,
            })
        }));
        crow.resize(act.len(), None);
    }

    /// Renders the pixel rows of band `b`: each sub-scanline reaching them is walked once
    /// and added to the (one or two) rows it reaches.
    /// Its RGB8 and visible triangles go to `rgb` and `vis` (the band's rows; `vis` is
    /// empty without the AOV).
    fn render_band(
        &self,
        b: usize,
        rs: &mut BandScratch<'a>,
        rgb: &mut [u8],
        vis: &mut [i32],
    ) -> BandOut {
        let (p, width, height) = (self.p, self.width, self.height);
        let (j0, j1) = self.bands.rows(b);
        let nr = (j1 - j0 + 1) as usize;
        let n64 = p.subscanlines as i64;
        let w = width as usize;
        let BandScratch {
            acc,
            pieces,
            walk: ws,
            act,
            cand,
            crow,
        } = rs;
        acc.reset(nr * w, self.visible);
        let (mut evals, mut npieces) = (0u64, 0u64);
        // Triangles touching the rows' y range (a superset of those any sub-scanline of
        // the band hits; each sub-scanline tests them exactly).
        let (ylo, yhi) = (256 * (j0 - 1), 256 * (j1 + 2));
        cand.clear();
        cand.extend(
            self.bands
                .members(b)
                .iter()
                .map(|&k| &self.mt[k as usize])
                .filter(|t| t.ymax >= ylo && t.ymin <= yhi),
        );
        let (xa, xb) = match p.filter {
            Filter::Box => (0, width as i64 * ONE16),
            _ => (-ONE16 / 2, width as i64 * ONE16 + ONE16 / 2),
        };
        let inter = p.intersections;
        // Row j's pixels in `acc`.
        let row = |j: i64| (j - j0) as usize * w..(j - j0 + 1) as usize * w;
        match &self.tab {
            None => {
                // Sub-scanline g at y = g/n lies in row ja = ⌊g/n⌋ at l = g − n·ja; l = 0 is
                // also the bottom boundary l = n of row ja − 1, seen from above.
                for g in j0 * n64..=(j1 + 1) * n64 {
                    let ynum = 2 * g;
                    let ja = g.div_euclid(n64);
                    let l = g - ja * n64;
                    if l != 0 {
                        self.hits(cand, ynum, false, act, crow);
                        let e = walk(act, xa, xb, inter, pieces, ws);
                        evals += e;
                        npieces += pieces.len() as u64;
                        let r = row(ja);
                        accumulate_box(acc.row(r), pieces, act, crow, ynum, 2, self.bgc);
                        continue;
                    }
                    // Row ja from below (owned), row ja − 1 from above (owned only by the
                    // last row).
                    let below = ja <= j1;
                    let above = ja > j0;
                    let above_owned = ja - 1 == height as i64 - 1;
                    if below {
                        self.hits(cand, ynum, false, act, crow);
                        let e = walk(act, xa, xb, inter, pieces, ws);
                        evals += e;
                        npieces += pieces.len() as u64;
                        let r = row(ja);
                        accumulate_box(acc.row(r), pieces, act, crow, ynum, 1, self.bgc);
                        if above && !cand.iter().any(|t| t.sides_differ(ynum)) {
                            // Both sides see the same spans: the same pieces.
                            let r = row(ja - 1);
                            accumulate_box(acc.row(r), pieces, act, crow, ynum, 1, self.bgc);
                            continue;
                        }
                    }
                    if above {
                        self.hits(cand, ynum, true, act, crow);
                        let e = walk(act, xa, xb, inter, pieces, ws);
                        if above_owned {
                            evals += e;
                            npieces += pieces.len() as u64;
                        }
                        let r = row(ja - 1);
                        accumulate_box(acc.row(r), pieces, act, crow, ynum, 1, self.bgc);
                    }
                }
            }
            Some(tab) => {
                // Sub-scanline g at y = ½ + g/n: m = g − n·ja ≥ 0 of row ja = ⌊g/n⌋ (owned)
                // and, for m > 0, m − n of row ja + 1.
                for g in j0 * n64 - (n64 - 1)..=j1 * n64 + (n64 - 1) {
                    let ynum = 2 * g + n64;
                    let ja = g.div_euclid(n64);
                    let m = g - ja * n64;
                    self.hits(cand, ynum, false, act, crow);
                    let e = walk(act, xa, xb, inter, pieces, ws);
                    // Row `j` with the table of distance `k`.
                    let mut add = |j: i64, k: i64| {
                        let fm = &tab.f[k as usize];
                        accumulate_filtered(
                            acc.row(row(j)),
                            pieces,
                            act,
                            crow,
                            (ynum, fm),
                            self.bgc,
                        );
                    };
                    if (j0..=j1).contains(&ja) {
                        evals += e;
                        npieces += pieces.len() as u64;
                        add(ja, m);
                    }
                    if m > 0 && (j0..=j1).contains(&(ja + 1)) {
                        add(ja + 1, n64 - m);
                    }
                }
            }
        }
        let div: u64 = match &self.tab {
            None => 2 * p.subscanlines as u64 * ONE16 as u64 * 4096,
            Some(t) => t.total as u64 * 4096,
        };
        for (a, px) in acc.c.iter().zip(rgb.chunks_mut(3)) {
            for (o, &c) in px.iter_mut().zip(a) {
                *o = (c / div).min(255) as u8;
            }
        }
        for (a, v) in acc.w.iter().zip(vis.iter_mut()) {
            *v = dominant(a);
        }
        (evals, npieces)
    }
}

/// Buffers one rendering thread reuses from band to band.
#[derive(Default)]
struct BandScratch<'a> {
    /// Pixel memory of the band's rows, row after row.
    acc: PixMem,
    pieces: Vec<Piece>,
    walk: WalkScratch,
    /// The triangles hit by the current sub-scanline.
    act: Vec<Active<'a>>,
    /// The band's candidate triangles.
    cand: Vec<&'a MsTri>,
    /// Per triangle of `act`, its colour planes on the line in 64-bit form, once set up
    /// (`Some(None)`: they do not fit).
    crow: Vec<Option<Option<ColourRow>>>,
}

/// Colours of one piece's parts, left to right: the background, or the polygon's colour
/// at the middle of the part, Q8.12. Parts one pixel wide in a row (the inside of a long
/// piece) have middles one pixel apart, whose colours are stepped with additions.
struct PieceColour<'a, 't> {
    src: ColourSource<'a, 't>,
    ynum: i64,
    /// Steppers at the middle `mid`, when set up.
    steps: Option<(ColourSteps, i64)>,
}

/// The three colour planes stepped one pixel at a time along a piece, in 64-bit
/// arithmetic where [`RoundDivSteps::narrow`] proves the steps fit.
enum ColourSteps {
    Wide([RoundDivSteps; 3]),
    Narrow([RoundDivSteps64; 3]),
}

impl ColourSteps {
    /// The current values; then moves one pixel on.
    #[inline]
    fn next(&mut self) -> [i128; 3] {
        fn take<S: PlaneStepper>(st: &mut [S; 3]) -> [i128; 3] {
            let v = st.map(|s| s.value());
            st.iter_mut().for_each(|s| s.advance());
            v
        }
        match self {
            ColourSteps::Wide(st) => take(st),
            ColourSteps::Narrow(st) => take(st),
        }
    }
}

/// A colour clamped to the range a piece takes (`0..=COLOUR_MAX` per channel).
#[inline]
fn clamp_colour(mut c: [i64; 3]) -> [i64; 3] {
    for v in &mut c {
        *v = (*v).clamp(0, COLOUR_MAX);
    }
    c
}

/// Where a piece's colours come from.
enum ColourSource<'a, 't> {
    /// The same colour for every part: the background, or a flat triangle's colour.
    Fixed([i64; 3]),
    /// A shaded triangle whose colour planes on the line fit the 64-bit form, with the
    /// triangle's steps by one pixel.
    Row(&'a ColourRow, &'t [RoundDivStep; 3]),
    /// A shaded triangle whose colour planes on the line do not fit 64 bits.
    Wide(&'a Active<'t>),
}

/// A shaded triangle's colour planes on one sub-scanline in 64-bit arithmetic, from one
/// reference point `x0`: `at(x) = q + ⌊(r + 2s·(x − x0)) / 2d⌋` per channel, which is
/// [`RowPlane::at`]`(x, 0) = ⌊(2(k + s·x) + d) / 2d⌋` split at `x0` (`q`, `r` the
/// quotient and remainder there). Set up only when every value stays below 2^62 for `x`
/// in the triangle's interval on the line.
#[derive(Clone, Copy, Debug)]
struct ColourRow {
    x0: i64,
    q: [i64; 3],
    r: [i64; 3],
    s2: [i64; 3],
    d2: [i64; 3],
}

impl ColourRow {
    /// The planes `c` for `x` in `[x0, x1]`, if they fit.
    fn new(c: &[RowPlane; 3], x0: i64, x1: i64) -> Option<ColourRow> {
        const LIM: i128 = 1 << 62;
        let span = (x1 - x0) as i128;
        let mut out = ColourRow {
            x0,
            q: [0; 3],
            r: [0; 3],
            s2: [0; 3],
            d2: [0; 3],
        };
        for (ch, p) in c.iter().enumerate() {
            let d2 = 2 * p.d;
            let s2 = 2 * p.s;
            if p.d <= 0 || d2 >= LIM || s2.checked_abs()?.checked_mul(span)? + d2 >= LIM {
                return None;
            }
            let n = (2 * (p.k.checked_add(p.s.checked_mul(x0 as i128)?)?)).checked_add(p.d)?;
            let q = floor_div_wide(n, d2);
            if q.abs() >= LIM {
                return None;
            }
            out.q[ch] = q as i64;
            out.r[ch] = (n - q * d2) as i64;
            out.s2[ch] = s2 as i64;
            out.d2[ch] = d2 as i64;
        }
        Some(out)
    }

    /// The three values at `x` (in the interval it was set up for).
    #[inline]
    fn at(&self, x: i64) -> [i64; 3] {
        let dx = x - self.x0;
        let mut v = [0; 3];
        for (ch, v) in v.iter_mut().enumerate() {
            *v = self.q[ch] + (self.r[ch] + self.s2[ch] * dx).div_euclid(self.d2[ch]);
        }
        v
    }

    /// Steppers of the values at `x`, `x + 2^16`, … (inside the interval it was set up
    /// for), from one division per channel: `steps` are the triangle's steps by one pixel
    /// ([`MsTri::cstep`](spans::MsTri), `2s·2^16` over `2d`, the same numerator and
    /// denominator as here). `None` where a step does not fit 64 bits. Every value stays
    /// inside the interval, where [`ColourRow::new`] keeps the numerators below 2^62.
    #[inline]
    fn run(&self, x: i64, steps: &[RoundDivStep; 3]) -> Option<[RoundDivSteps64; 3]> {
        let dx = x - self.x0;
        let at = |ch: usize| {
            let n = self.r[ch] + self.s2[ch] * dx;
            let q = n.div_euclid(self.d2[ch]);
            steps[ch].narrow_from(self.q[ch] + q, n - q * self.d2[ch])
        };
        Some([at(0)?, at(1)?, at(2)?])
    }
}

impl<'a, 't> PieceColour<'a, 't> {
    /// The colours of piece `pc` on the sub-scanline `ynum`.
    fn new(
        act: &'a [Active<'t>],
        crow: &'a mut [Option<Option<ColourRow>>],
        pc: &Piece,
        ynum: i64,
        bgc: [i64; 3],
    ) -> PieceColour<'a, 't> {
        let src = match (pc.tri >= 0).then(|| &act[pc.slot]) {
            None => ColourSource::Fixed(bgc),
            Some(a) => match a.t.flat {
                Some(c) => ColourSource::Fixed(c),
                None => match crow[pc.slot]
                    .get_or_insert_with(|| ColourRow::new(&Self::planes(a, ynum), a.xl, a.xr))
                {
                    Some(row) => ColourSource::Row(row, &a.t.cstep),
                    None => ColourSource::Wide(a),
                },
            },
        };
        PieceColour {
            src,
            ynum,
            steps: None,
        }
    }

    /// The colour planes of `a` on the sub-scanline `ynum`.
    #[inline]
    fn planes(a: &Active, ynum: i64) -> [RowPlane; 3] {
        let r = &a.t.rows;
        [r[1].row(ynum), r[2].row(ynum), r[3].row(ynum)]
    }

    /// The colours of `count` whole pixels from `x0` on (parts `[x0 + k·2^16,
    /// x0 + (k + 1)·2^16)`, `k = 0..count`), handed to `f(k, colour)`; `end` is the piece's
    /// end. The same values as [`PieceColour::at`] gives each part.
    #[inline]
    fn whole(&mut self, x0: i64, count: i64, end: i64, mut f: impl FnMut(i64, [i64; 3])) {
        match self.src {
            ColourSource::Fixed(c) => (0..count).for_each(|k| f(k, c)),
            ColourSource::Row(row, steps) => match row.run(x0 + ONE16 / 2, steps) {
                Some(mut st) => (0..count).for_each(|k| {
                    let mut c = [0; 3];
                    for (v, s) in c.iter_mut().zip(&mut st) {
                        *v = s.value() as i64;
                        s.advance();
                    }
                    f(k, clamp_colour(c))
                }),
                None => {
                    (0..count).for_each(|k| f(k, clamp_colour(row.at(x0 + k * ONE16 + ONE16 / 2))))
                }
            },
            ColourSource::Wide(_) => {
                for k in 0..count {
                    let p0 = x0 + k * ONE16;
                    f(k, self.at(p0, p0 + ONE16, end));
                }
            }
        }
    }

    /// The colour of the part `[x0, x1)`; `end` is the piece's end (how far steps go).
    #[inline]
    fn at(&mut self, x0: i64, x1: i64, end: i64) -> [i64; 3] {
        let mid = (x0 + x1).div_euclid(2);
        let a = match self.src {
            ColourSource::Fixed(c) => return c,
            ColourSource::Row(row, _) => return clamp_colour(row.at(mid)),
            ColourSource::Wide(a) => a,
        };
        let clamp = |v: i128| (v as i64).clamp(0, COLOUR_MAX);
        if let Some((st, m)) = &mut self.steps {
            if *m == mid {
                *m += ONE16;
                return st.next().map(clamp);
            }
        }
        if x1 - x0 == ONE16 && end - x1 >= 2 * ONE16 {
            // More whole parts follow: step from here, in 64 bits where the steps that
            // can follow (one per whole part up to `end`) stay inside them.
            let c = Self::planes(a, self.ynum);
            let st = [0, 1, 2].map(|k| {
                let p = &c[k];
                RoundDivSteps::start(p.k + p.s * mid as i128, &a.t.cstep[k])
            });
            let steps = ((end - mid) / ONE16 + 1) as u64;
            let mut st = match st.map(|s| s.narrow(steps)) {
                [Some(r), Some(g), Some(b)] => ColourSteps::Narrow([r, g, b]),
                _ => ColourSteps::Wide(st),
            };
            let v = st.next().map(clamp);
            self.steps = Some((st, mid + ONE16));
            return v;
        }
        Self::planes(a, self.ynum).map(|p| p.at(mid, 0).clamp(0, COLOUR_MAX))
    }
}

/// Box filter: adds each piece, split at pixel boundaries, with line weight `wl`, to the
/// pixel row `acc`.
fn accumulate_box(
    mut acc: PixRow,
    pieces: &[Piece],
    act: &[Active],
    crow: &mut [Option<Option<ColourRow>>],
    ynum: i64,
    wl: i64,
    bgc: [i64; 3],
) {
    for pc in pieces {
        let mut pcol = PieceColour::new(act, crow, pc, ynum, bgc);
        let (x0, x1, tri) = (pc.x0, pc.x1, pc.tri);
        // A part in the first pixel unless it is whole, the whole pixels, a part in the
        // last pixel.
        let i0 = x0.div_euclid(ONE16);
        let mut first = i0;
        if x0 != i0 * ONE16 || x1 < (i0 + 1) * ONE16 {
            let b0 = x1.min((i0 + 1) * ONE16);
            acc.add(i0 as usize, wl * (b0 - x0), pcol.at(x0, b0, x1), tri);
            if b0 == x1 {
                continue;
            }
            first = i0 + 1;
        }
        let i1 = x1.div_euclid(ONE16);
        pcol.whole(first * ONE16, i1 - first, x1, |k, col| {
            acc.add((first + k) as usize, wl * ONE16, col, tri)
        });
        let b1 = i1 * ONE16;
        if b1 < x1 {
            acc.add(i1 as usize, wl * (x1 - b1), pcol.at(b1, x1, x1), tri);
        }
    }
}

/// Axisymmetric filter: adds each piece, split at pixel centres (square R_i spans centres
/// i .. i+1), to the two pixels of its square with the table weights `fm`. `acc` is the
/// pixel row.
fn accumulate_filtered(
    mut acc: PixRow,
    pieces: &[Piece],
    act: &[Active],
    crow: &mut [Option<Option<ColourRow>>],
    (ynum, fm): (i64, &[i64; 65]),
    bgc: [i64; 3],
) {
    for pc in pieces {
        let mut pcol = PieceColour::new(act, crow, pc, ynum, bgc);
        let mut x0 = pc.x0;
        while x0 < pc.x1 {
            let i = (x0 - ONE16 / 2).div_euclid(ONE16);
            let cx = i * ONE16 + ONE16 / 2;
            let x1 = pc.x1.min(cx + ONE16);
            let col = pcol.at(x0, x1, pc.x1);
            let q = |x: i64| ((x - cx + 512) >> 10).clamp(0, 64) as usize;
            let (k1, k2) = (q(x0), q(x1));
            if i >= 0 {
                acc.add(i as usize, fm[k2] - fm[k1], col, pc.tri);
            }
            if i + 1 < acc.len() as i64 {
                acc.add((i + 1) as usize, fm[64 - k1] - fm[64 - k2], col, pc.tri);
            }
            x0 = x1;
        }
    }
}

/// Renders with multi-scanning.
pub fn render(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &MultiscanParams,
) -> Result<AaFrame, AaError> {
    render_with(tris, width, height, bg, p, true)
}

/// [`render`]; with `visible` false the per-pixel weights of each triangle are not kept
/// and [`AaFrame::visible`] is `None` (the image and the counters are the same).
pub fn render_with(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &MultiscanParams,
    visible: bool,
) -> Result<AaFrame, AaError> {
    let n = p.subscanlines;
    if !(1..=16).contains(&n) {
        return Err(AaError::Param(format!(
            "subscanlines = {n} must be in 1..=16"
        )));
    }
    let max = pixelproc_formats::MAX_SCREEN;
    if width > max || height > max {
        return Err(AaError::Param(format!(
            "screen {width}x{height} exceeds {max}x{max}"
        )));
    }
    let mt: Vec<MsTri> = tris
        .iter()
        .enumerate()
        .filter_map(|(k, t)| prepare(k, t, 2 * n as i64))
        .collect();
    // A triangle is a candidate of rows j with ymax ≥ 256(j − 1) and ymin ≤ 256(j + 2).
    let bands = Bands::new(
        8,
        height,
        mt.iter()
            .map(|t| (t.ymin.div_euclid(256) - 2, t.ymax.div_euclid(256) + 1)),
    );
    let f = MsFrame {
        bands,
        mt: &mt,
        p,
        width,
        height,
        bgc: bg.map(|v| ((v as i64) << 12) + 2048),
        tab: (p.filter != Filter::Box).then(|| tables(p.filter, n)),
        visible,
    };
    let w = width as usize;
    let mut rgb = vec![0u8; 3 * w * height as usize];
    let mut vis = vec![-1i32; if visible { w * height as usize } else { 0 }];
    // The bands are `f.bands.band()` rows each (the last one possibly fewer), written in
    // place.
    let band = f.bands.band() as usize;
    let rows: Vec<BandOut> = if rgb.is_empty() {
        Vec::new() // an empty screen: nothing to walk
    } else {
        let bands = rgb.par_chunks_mut(3 * w * band).enumerate();
        if visible {
            bands
                .zip(vis.par_chunks_mut(w * band))
                .map_init(BandScratch::default, |rs, ((b, r), v)| {
                    f.render_band(b, rs, r, v)
                })
                .collect()
        } else {
            bands
                .map_init(BandScratch::default, |rs, (b, r)| {
                    f.render_band(b, rs, r, &mut [])
                })
                .collect()
        }
    };
    let mut stats = AaStats::default();
    for (e, np) in rows {
        stats.depth_evals += e;
        stats.samples_written += np;
    }
    // Pixel memory: each pixel is read once for the final divide.
    stats.sample_reads = w as u64 * height as u64;
    Ok(AaFrame {
        width,
        height,
        rgb,
        visible: visible.then_some(vis),
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screens_beyond_the_formats_are_refused() {
        let p = MultiscanParams::new(4, Filter::Box);
        for (w, h) in [(4097, 10), (10, 4097)] {
            let e = render(&[], w, h, [0; 3], &p).unwrap_err();
            assert!(e.to_string().contains("exceeds 4096x4096"), "{e}");
        }
        assert!(render(&[], 4096, 2, [0; 3], &p).is_ok());
        // An empty screen renders nothing and counts nothing.
        for (w, h) in [(0, 5), (5, 0)] {
            let f = render(&[], w, h, [0; 3], &p).unwrap();
            assert!(f.rgb.is_empty() && f.stats.depth_evals == 0);
        }
    }

    /// Without the visible-triangle AOV the image and every counter are those of the
    /// full render, for the box and the axisymmetric filters.
    #[test]
    fn the_image_does_not_depend_on_the_visible_aov() {
        let (w, h) = (37u32, 29u32);
        let tris = crate::rng::random_tris(0x0a0f_f0a0, 80, w, h);
        for (n, filter) in [(4, Filter::Box), (3, Filter::Gauss), (2, Filter::Cone)] {
            let p = MultiscanParams::new(n, filter);
            let all = render(&tris, w, h, [9, 80, 200], &p).unwrap();
            let img = render_with(&tris, w, h, [9, 80, 200], &p, false).unwrap();
            assert_eq!(img.rgb, all.rgb, "{filter:?}");
            assert_eq!(img.stats, all.stats, "{filter:?}");
            assert!(img.visible.is_none());
            let vis = all.visible.unwrap();
            assert!(vis.iter().filter(|&&t| t >= 0).count() > 200, "{filter:?}");
        }
    }

    #[test]
    fn shared_edge_intervals_meet_exactly() {
        let q = |x: f64| (x * 256.0).round() as i32;
        let a = SnappedTri {
            v: [[q(0.3), q(0.1)], [q(9.7), q(3.3)], [q(2.2), q(7.9)]],
            z: [100, 200, 300],
            ..Default::default()
        };
        let b = SnappedTri {
            v: [[q(9.7), q(3.3)], [q(2.2), q(7.9)], [q(11.0), q(8.0)]],
            z: [100, 200, 300],
            ..Default::default()
        };
        let (ta, tb) = (prepare(0, &a, 12).unwrap(), prepare(1, &b, 12).unwrap());
        for g in 0..100 {
            let (ia, ib) = (ta.interval(g, false), tb.interval(g, false));
            if let (Some(ia), Some(ib)) = (ia, ib) {
                assert_eq!(ia.1, ib.0, "sub-scanline {g}");
            }
        }
    }

    /// The 64-bit colour row gives [`RowPlane::at`] everywhere on the interval it was set
    /// up for, and refuses planes that would not fit.
    #[test]
    fn colour_row_equals_the_wide_plane() {
        let mut rng = crate::rng::Lcg64(0x00c0_100e);
        let (mut built, mut refused) = (0, 0);
        for case in 0..3000 {
            let bits = [20u32, 40, 60, 70][case % 4];
            let mut draw = |b: u32| {
                let v = ((rng.step() as i128) << 64 | rng.step() as i128) % (1i128 << b);
                if rng.step() & 1 == 0 {
                    -v
                } else {
                    v
                }
            };
            let planes = [0; 3].map(|_| RowPlane {
                k: draw(bits + 10),
                s: draw(bits.min(44)),
                d: draw(bits).abs().max(1),
            });
            let x0 = (draw(26) as i64).abs() - (1 << 20);
            let x1 = x0 + 1 + (draw(22) as i64).abs();
            let Some(row) = ColourRow::new(&planes, x0, x1) else {
                refused += 1;
                continue;
            };
            built += 1;
            let mut xs = vec![x0, x1, (x0 + x1) / 2];
            xs.extend((0..8).map(|_| x0 + (draw(40) as i64).rem_euclid(x1 - x0 + 1)));
            for x in xs {
                assert_eq!(row.at(x), planes.map(|p| p.at(x, 0)), "{planes:?} at {x}");
            }
        }
        assert!(
            built > 1000 && refused > 300,
            "built {built}, refused {refused}"
        );
    }

    /// The whole pixels' steppers of a colour row give each pixel's colour as
    /// [`ColourRow::at`] (so [`RowPlane::at`]) does.
    #[test]
    fn colour_run_steps_equal_the_row() {
        let take = |st: &mut [RoundDivSteps64; 3]| {
            let mut c = [0; 3];
            for (v, s) in c.iter_mut().zip(st.iter_mut()) {
                *v = s.value() as i64;
                s.advance();
            }
            clamp_colour(c)
        };
        let (w, h) = (64u32, 40u32);
        let tris = crate::rng::random_tris(0x0c01_0e55, 60, w, h);
        let mut runs = 0;
        for (k, t) in tris.iter().enumerate() {
            let Some(mt) = prepare(k, t, 8) else { continue };
            for ynum in (mt.ylo / 256..=mt.yhi / 256).step_by(3) {
                let Some((xl, xr)) = mt.interval(ynum, false) else {
                    continue;
                };
                let planes = [1, 2, 3].map(|c| mt.rows[c].row(ynum));
                let Some(row) = ColourRow::new(&planes, xl, xr) else {
                    continue;
                };
                // Whole pixels inside the interval, from the first boundary on.
                let first = xl.div_euclid(ONE16) + 1;
                let Some(mut st) = row.run(first * ONE16 + ONE16 / 2, &mt.cstep) else {
                    continue;
                };
                let mut i = first;
                while (i + 1) * ONE16 <= xr {
                    let mid = i * ONE16 + ONE16 / 2;
                    let want = planes.map(|p| p.at(mid, 0).clamp(0, COLOUR_MAX));
                    assert_eq!(take(&mut st), want, "triangle {k}, line {ynum}, pixel {i}");
                    i += 1;
                    runs += 1;
                }
            }
        }
        assert!(runs > 2000, "{runs} steps");
        // Small denominators, where numerators meet a multiple of the denominator.
        let mut rng = crate::rng::Lcg64(0x5a11_d0e5);
        let mut exact = 0;
        for _ in 0..2000 {
            let mut small = |m: u64| (rng.step() % (2 * m + 1)) as i128 - m as i128;
            let planes = [0; 3].map(|_| RowPlane {
                k: small(1 << 40),
                s: small(1 << 10),
                d: small(40).abs().max(1),
            });
            let x0 = small(1 << 20) as i64;
            let x1 = x0 + 40 * ONE16;
            let Some(row) = ColourRow::new(&planes, x0, x1) else {
                continue;
            };
            let steps = planes.map(|p| RoundDivStep::new(p.s * ONE16 as i128, p.d));
            let mut st = row.run(x0 + ONE16 / 2, &steps).expect("small steps fit");
            for i in 0..39 {
                let mid = x0 + i * ONE16 + ONE16 / 2;
                let want = planes.map(|p| p.at(mid, 0).clamp(0, COLOUR_MAX));
                exact += planes
                    .iter()
                    .filter(|p| (2 * (p.k + p.s * mid as i128) + p.d) % (2 * p.d) == 0)
                    .count();
                assert_eq!(take(&mut st), want, "{planes:?} from {x0}, pixel {i}");
            }
        }
        assert!(exact > 1000, "{exact} exact quotients");
    }

    #[test]
    fn tables_are_monotone_and_total_near_2_24() {
        for f in [Filter::Gauss, Filter::Cone] {
            for n in [1, 3, 8] {
                let t = tables(f, n);
                for row in &t.f {
                    assert!(row.windows(2).all(|w| w[1] >= w[0]));
                }
                assert!((t.total - (1 << 24)).abs() < 64, "{f:?} {n}: {}", t.total);
            }
        }
    }
}
