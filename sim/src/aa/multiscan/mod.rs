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
use crate::setup::SnappedTri;

mod colour;
mod filter;
mod spans;
mod walk;
use colour::ColourRow;
use filter::{accumulate_box, accumulate_filtered, dominant, tables, PixMem, Tables};
use spans::{prepare, Cand, CandHit, MsTri};
use walk::{walk, Active, Piece, WalkScratch, NO_SLOT};

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
        (cand, hit): (&[Cand], &[CandHit<'a>]),
        ynum: i64,
        from_above: bool,
        act: &mut Vec<Active<'a>>,
        crow: &mut Vec<Option<Option<ColourRow>>>,
        ws: &mut WalkScratch,
    ) {
        act.clear();
        crow.clear();
        act.reserve(cand.len());
        let slot_of = ws.slots(cand.len());
        for (ci, ((c, h), so)) in cand.iter().zip(hit).zip(slot_of).enumerate() {
            *so = match c.interval(h.t, ynum, from_above) {
                Some((xl, xr)) => {
                    act.push(Active {
                        t: h.t,
                        idx: h.idx,
                        cand: ci as u32,
                        decal: h.decal,
                        z: h.z.row(ynum),
                        xl,
                        xr,
                    });
                    act.len() as u32 - 1
                }
                None => NO_SLOT,
            };
        }
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
            hit,
            crow,
        } = rs;
        acc.reset(nr * w, self.visible);
        // The crossings' order carried from line to line refers to this band's candidates.
        ws.new_band();
        let (mut evals, mut npieces) = (0u64, 0u64);
        // Triangles touching the rows' y range (a superset of those any sub-scanline of
        // the band hits; each sub-scanline tests them exactly).
        let (ylo, yhi) = (256 * (j0 - 1), 256 * (j1 + 2));
        cand.clear();
        hit.clear();
        for t in self
            .bands
            .members(b)
            .iter()
            .map(|&k| &self.mt[k as usize])
            .filter(|t| t.ymax >= ylo && t.ymin <= yhi)
        {
            cand.push(Cand::new(t));
            hit.push(CandHit::new(t));
        }
        let cand = (&cand[..], &hit[..]);
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
                        self.hits(cand, ynum, false, act, crow, ws);
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
                        self.hits(cand, ynum, false, act, crow, ws);
                        let e = walk(act, xa, xb, inter, pieces, ws);
                        evals += e;
                        npieces += pieces.len() as u64;
                        let r = row(ja);
                        accumulate_box(acc.row(r), pieces, act, crow, ynum, 1, self.bgc);
                        if above
                            && !cand
                                .0
                                .iter()
                                .zip(cand.1)
                                .any(|(c, h)| c.sides_differ(h.t, ynum))
                        {
                            // Both sides see the same spans: the same pieces.
                            let r = row(ja - 1);
                            accumulate_box(acc.row(r), pieces, act, crow, ynum, 1, self.bgc);
                            continue;
                        }
                    }
                    if above {
                        self.hits(cand, ynum, true, act, crow, ws);
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
                    self.hits(cand, ynum, false, act, crow, ws);
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
        // A shift where the divisor is a power of two (the box filter with n a power of
        // two), the same quotient.
        let shift = div.is_power_of_two().then(|| div.trailing_zeros());
        for (a, px) in acc.c.iter().zip(rgb.chunks_mut(3)) {
            for (o, &c) in px.iter_mut().zip(a) {
                let q = match shift {
                    Some(k) => c >> k,
                    None => c / div,
                };
                *o = q.min(255) as u8;
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
    /// The band's candidate triangles, packed for the hit tests, and what a hit reads.
    cand: Vec<Cand>,
    hit: Vec<CandHit<'a>>,
    /// Per triangle of `act`, its colour planes on the line in 64-bit form, once set up
    /// (`Some(None)`: they do not fit).
    crow: Vec<Option<Option<ColourRow>>>,
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
    stats.pixels = w as u64 * height as u64;
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
}
