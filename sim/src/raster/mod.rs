//! The raster core: the one home of the rules every scan converter of the golden model
//! shares, and the one interface between scan conversion and what consumes it.
//!
//! Seed 001 (Matsumoto) section 3 defines the span data `(attr, XL, XR, ZL, dZ, IL, dI)`
//! and the scanline Z-buffer test; seed 000 (JP2569952B2, background, process 1) the edge
//! masks; seeds 002–004 reuse the same edges and depth test. The facts live here once:
//!
//! - [`edge`]: coverage validation of snapped coordinates and depths, winding, edge
//!   functions and the top-left fill rule;
//! - [`depth`]: the array's depth-test rule (`Z < ZB`, or `Z ≤ ZB` for a decal);
//! - [`rows`]: which rows a triangle can touch, and binning triangles into row bands;
//! - [`ceil_div`], [`floor_div`], [`round_div`]: exact integer division helpers, and
//!   `divisor`: floor division by a divisor prepared once, by multiplication;
//! - `steps`: the same quotients along arithmetic progressions with additions only
//!   (`RoundDivSteps` for planes along a row, `FloorSteps` for edge bounds down the rows);
//! - [`SpanSink`] and [`SpanRaster`]: span scan conversion (through
//!   [`crate::setup::TriSetup`]) separated from its consumers, in the way of a
//!   "blitter": the converter calls `sink.span(prim, row, word)`; the array feed
//!   ([`crate::render::SpanSource`]), the visibility probe ([`VisibleProbe`]) and the
//!   post-process draw buffers ([`crate::aa::postfx::draw_buffers`]) implement it.

pub mod depth;
pub(crate) mod divisor;
pub mod edge;
pub mod rows;
mod steps;

pub(crate) use steps::{
    FloorStep, FloorSteps, PlaneStepper, RoundDivStep, RoundDivSteps, RoundDivSteps64,
};

use crate::setup::{SetupError, SnappedTri, TriSetup};
use pixelproc_formats::{SpanWord, Z_FAR};
use rayon::prelude::*;
use rows::Bands;

/// `ceil(n / d)` for `d > 0`.
#[inline]
pub fn ceil_div(n: i64, d: i64) -> i64 {
    debug_assert!(d > 0);
    -((-n).div_euclid(d))
}

/// `floor(n / d)` for `d > 0`.
#[inline]
pub fn floor_div(n: i64, d: i64) -> i64 {
    debug_assert!(d > 0);
    n.div_euclid(d)
}

/// `round(n / d)` with ties toward +∞, exact.
#[inline]
pub fn round_div(n: i128, d: i128) -> i128 {
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    // The same quotient in 64-bit arithmetic when every intermediate fits (`|n|, d < 2^61`:
    // `2n + d` and `2d` stay inside `i64`), which is most calls and much cheaper.
    const LIM: i128 = 1 << 61;
    if -LIM < n && n < LIM && d < LIM {
        let (n, d) = (n as i64, d as i64);
        return (2 * n + d).div_euclid(2 * d) as i128;
    }
    (2 * n + d).div_euclid(2 * d)
}

/// `⌊n / d⌋` for `d > 0`, in 64-bit arithmetic when both fit.
#[inline]
pub(crate) fn floor_div_wide(n: i128, d: i128) -> i128 {
    if i64::try_from(n).is_ok() && i64::try_from(d).is_ok() {
        (n as i64).div_euclid(d as i64) as i128
    } else {
        n.div_euclid(d)
    }
}

/// The consumer of span scan conversion: one call per span word. For every pixel, the
/// calls whose span covers it arrive in scene order (the draw order the array's depth
/// test needs); calls of different rows may interleave.
pub trait SpanSink {
    /// Span word `w` of triangle `prim` (input index, scene order) on row `row`.
    fn span(&mut self, prim: u32, row: u32, w: &SpanWord);
}

/// Rows per band of the span scan converter.
pub const SPAN_BAND: i64 = 16;

/// Span scan conversion of a frame: every non-degenerate triangle set up once
/// ([`TriSetup`]), binned into bands of [`SPAN_BAND`] rows.
pub struct SpanRaster {
    width: u32,
    height: u32,
    /// The setup of each input triangle, by input index (`None`: degenerate).
    set: Vec<Option<TriSetup>>,
    /// Number of non-degenerate triangles.
    live: usize,
    /// Per input triangle, how many triangles right after it share its geometry
    /// ([`TriSetup::same_geometry`]: its shade-channel copies), scanned with it; 0 for those
    /// copies themselves, which [`SpanRaster::scan_band`] then skips.
    group: Vec<u8>,
    bands: Bands,
}

impl SpanRaster {
    /// Sets up every triangle (in parallel; degenerate ones are dropped) and bins them into
    /// row bands. Fails with the setup error of the first triangle (in input order) that
    /// has one.
    pub fn new(tris: &[SnappedTri], width: u32, height: u32) -> Result<SpanRaster, SetupError> {
        tris.iter().try_for_each(TriSetup::check)?;
        // An indexed collect writes each setup in place: no intermediate lists or
        // filtered copy of these large records. A triangle whose box holds no pixel
        // centre sends no word: it is not set up (most triangles of a mesh finer than
        // the pixels), and counted as set up if it is not degenerate.
        let set: Vec<Option<TriSetup>> = tris
            .par_iter()
            .map(|t| {
                if misses_centres(t) {
                    None
                } else {
                    TriSetup::of_checked(t)
                }
            })
            .collect();
        let live = tris.par_iter().filter(|t| TriSetup::is_live(t)).count();
        let mut group = vec![0u8; tris.len()];
        let mut lead = 0;
        for k in 1..tris.len() {
            // A shade-channel copy right after its polygon (or after another copy of it),
            // or any other triangle of the same geometry. Same geometry means both were set
            // up, or neither.
            if group[lead] < u8::MAX && TriSetup::same_geometry(&tris[lead], &tris[k]) {
                debug_assert_eq!(set[lead].is_some(), set[k].is_some());
                group[lead] += 1;
            } else {
                lead = k;
            }
        }
        let bands = Bands::new(
            SPAN_BAND,
            height,
            set.iter().map(|s| match s {
                Some(t) => (t.row_min, t.row_max),
                None => (0, -1),
            }),
        );
        Ok(SpanRaster {
            width,
            height,
            set,
            live,
            group,
            bands,
        })
    }

    /// Screen width.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Screen height.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of non-degenerate triangles.
    pub fn triangles(&self) -> usize {
        self.live
    }

    /// Number of row bands.
    pub fn band_count(&self) -> usize {
        self.bands.len()
    }

    /// The rows `lo..=hi` of band `b` (clamped to the screen).
    pub fn band_rows(&self, b: usize) -> (i64, i64) {
        self.bands.rows(b)
    }

    /// At most how many span words each row of band `b` receives (one per triangle whose
    /// row range holds the row), to size a sink's rows before [`SpanRaster::scan_band`].
    pub fn band_row_bounds(&self, b: usize) -> Vec<usize> {
        let (lo, hi) = self.bands.rows(b);
        let mut n = vec![0usize; (hi - lo + 1).max(0) as usize];
        for &k in self.bands.members(b) {
            if let Some(t) = &self.set[k as usize] {
                for c in
                    &mut n[(t.row_min.max(lo) - lo) as usize..=(t.row_max.min(hi) - lo) as usize]
                {
                    *c += 1;
                }
            }
        }
        n
    }

    /// Scan-converts band `b`: for each triangle binned there, in scene order, its span
    /// words of the band's rows, top to bottom.
    pub fn scan_band(&self, b: usize, sink: &mut impl SpanSink) {
        let (lo, hi) = self.bands.rows(b);
        let mut skip = 0;
        for &k in self.bands.members(b) {
            if skip > 0 {
                // A copy, scanned with its polygon (binned alike: the same rows).
                skip -= 1;
                continue;
            }
            let Some(t) = &self.set[k as usize] else {
                skip = self.group[k as usize];
                continue;
            };
            match self.group[k as usize] {
                0 => t.for_each_span_in(lo, hi, self.width, |j, w| sink.span(k, j, &w)),
                n => {
                    skip = n;
                    let copies = &self.set[k as usize + 1..=k as usize + n as usize];
                    t.for_each_span_shared(copies, lo, hi, self.width, |i, j, w| {
                        sink.span(k + i as u32, j, &w)
                    });
                }
            }
        }
    }

    /// Scan-converts the whole frame, band by band.
    pub fn scan(&self, sink: &mut impl SpanSink) {
        for b in 0..self.bands.len() {
            self.scan_band(b, sink);
        }
    }
}

/// Whether no pixel centre lies in the closed box of a triangle's vertices (Q.8): then
/// none lies in the triangle, and it sends no span word.
fn misses_centres(t: &SnappedTri) -> bool {
    let span = |k: usize| {
        let c = t.v.map(|p| p[k] as i64);
        let (lo, hi) = rows::centre_rows(
            c.into_iter().min().unwrap_or(0),
            c.into_iter().max().unwrap_or(0),
        );
        lo > hi
    };
    span(0) || span(1)
}

/// The visibility probe: replays the array's depth test ([`depth::passes`]) on the span
/// words with the triangle index attached, giving the visible triangle per pixel and the
/// number of depth tests made.
#[derive(Clone, Debug)]
pub struct VisibleProbe {
    w: usize,
    zb: Vec<u32>,
    /// Row-major visible triangle (input index, −1 background).
    pub visible: Vec<i32>,
    /// Depth tests made (pixels of all span words).
    pub depth_tests: u64,
}

impl VisibleProbe {
    /// An empty `width × height` probe.
    pub fn new(width: u32, height: u32) -> VisibleProbe {
        let n = width as usize * height as usize;
        VisibleProbe {
            w: width as usize,
            zb: vec![Z_FAR; n],
            visible: vec![-1; n],
            depth_tests: 0,
        }
    }
}

impl SpanSink for VisibleProbe {
    fn span(&mut self, prim: u32, row: u32, w: &SpanWord) {
        let base = row as usize * self.w;
        for p in w.xl as i64..=w.xr as i64 {
            self.depth_tests += 1;
            let z = w.z_at(p);
            let i = base + p as usize;
            if depth::passes(z, self.zb[i], w.decal) {
                self.zb[i] = z;
                self.visible[i] = prim as i32;
            }
        }
    }
}

/// A test scene of `n` random triangles over a `w × h` screen and a margin of 10 pixels
/// and more around it (every size, slivers, a decal every seventh), each followed by 0–3
/// shade-channel copies of its geometry (other intensities, channel, class and tag), and
/// a degenerate polygon with a copy at indices 5 and 6 (neither is scanned).
#[cfg(test)]
pub(crate) fn copies_scene(
    rng: &mut crate::rng::Lcg64,
    w: u32,
    h: u32,
    n: usize,
) -> Vec<SnappedTri> {
    let mut tris = Vec::new();
    for i in 0..n {
        let mut r = |m: u64| (rng.step() % m) as i32;
        let v = [0; 3].map(|_| {
            [
                r((w as u64 + 24) * 256) - 10 * 256,
                r((h as u64 + 20) * 256) - 10 * 256,
            ]
        });
        let z = [0; 3].map(|_| 1000 + r(1 << 20) as u32);
        let host = (i % 7 == 3).then_some(crate::setup::HostPlane {
            v: [[0, 0], [w as i32 * 256, 0], [0, h as i32 * 256]],
            z: [5000, 6000, 7000],
        });
        let col = |r: &mut dyn FnMut(u64) -> i32| [0; 3].map(|_| [0; 3].map(|_| r(1 << 20) as u32));
        let t = SnappedTri {
            v,
            z,
            c: col(&mut r),
            tag: i as u16,
            host,
            nclass: (i % 5) as u8,
            chan: 0,
        };
        tris.push(t);
        for c in 1..=(i % 4) {
            tris.push(SnappedTri {
                c: col(&mut r),
                chan: c as u8,
                tag: (i + c) as u16,
                nclass: (c * 3) as u8,
                ..t
            });
        }
    }
    let flat = SnappedTri {
        v: [[0, 0], [256, 256], [512, 512]],
        ..tris[0]
    };
    tris.insert(5, flat);
    tris.insert(6, SnappedTri { chan: 1, ..flat });
    tris
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Setup keeps input order: the triangles' setups (a degenerate one dropped, its index
    /// kept), the number of live ones, and, among several bad triangles, the first one's
    /// error, whichever the parallel pass meets first.
    #[test]
    fn setup_reports_the_first_bad_triangle_and_keeps_indices() {
        let tri = |x: i32, z: u32| SnappedTri {
            v: [[x, 0], [x + 2560, 0], [x, 2560]],
            z: [z; 3],
            ..Default::default()
        };
        let flat = SnappedTri {
            v: [[0, 0], [256, 256], [512, 512]],
            ..tri(0, 100)
        };
        let good = vec![tri(0, 100), flat, tri(512, 200), tri(1024, 300)];
        let r = SpanRaster::new(&good, 64, 16).unwrap();
        assert_eq!(r.triangles(), 3);
        let mut prims = Vec::new();
        struct Prims<'a>(&'a mut Vec<u32>);
        impl SpanSink for Prims<'_> {
            fn span(&mut self, prim: u32, _row: u32, _w: &SpanWord) {
                if self.0.last() != Some(&prim) {
                    self.0.push(prim);
                }
            }
        }
        r.scan_band(0, &mut Prims(&mut prims));
        assert_eq!(
            prims,
            vec![0, 2, 3],
            "input indices, the degenerate one skipped"
        );
        let lim = (pixelproc_formats::MAX_COORD_PX + 1) << 8;
        let mut bad = good.clone();
        bad[1] = tri(0, u32::MAX);
        bad[3] = tri(lim, 100);
        let first = TriSetup::new(&bad[1]).unwrap_err().to_string();
        for _ in 0..20 {
            let e = SpanRaster::new(&bad, 64, 16).err().expect("an error");
            assert_eq!(e.to_string(), first);
        }
    }

    /// Triangles of the same geometry in a row (shade-channel copies, a duplicated
    /// triangle) are scanned together; every row must still receive each triangle's own
    /// words ([`TriSetup::for_each_span_in`]), in input order, whatever the groups.
    #[test]
    fn shared_geometry_groups_give_each_triangles_own_words() {
        let mut rng = crate::rng::Lcg64(0x5eed_0c0b);
        let (w, h) = (96u32, 80u32);
        let tris = copies_scene(&mut rng, w, h, 300);
        let r = SpanRaster::new(&tris, w, h).unwrap();
        assert!(r.group.iter().any(|&g| g >= 2), "copies are grouped");
        let setups: Vec<_> = tris.iter().map(|t| TriSetup::new(t).unwrap()).collect();
        let expect = own_words(&setups, w, h);
        let got = scanned_words(&r, h);
        assert!(expect.iter().map(Vec::len).sum::<usize>() > 5_000);
        for (j, (g, e)) in got.iter().zip(&expect).enumerate() {
            assert_eq!(g, e, "row {j}");
        }
    }

    /// A mesh finer than the pixels: triangles of 0.05 to 3 px (many hold no pixel
    /// centre, some have vertices on a centre or its row or column, some are degenerate, some are decals
    /// on a host with or without area) send every word each one's own setup sends, in
    /// input order, and are counted as set up exactly when [`TriSetup::new`] sets them up,
    /// though most are never set up.
    #[test]
    fn triangles_without_a_pixel_centre_send_what_their_setups_send() {
        let mut rng = crate::rng::Lcg64(0x0ce7_7e55);
        let (w, h) = (40u32, 30u32);
        let mut tris = Vec::new();
        for k in 0..6000 {
            let size = [13, 64, 256, 768][k % 4];
            let (x, y) = (
                (rng.step() % (w as u64 * 256)) as i32,
                (rng.step() % (h as u64 * 256)) as i32,
            );
            let p = |rng: &mut crate::rng::Lcg64| {
                [
                    x + (rng.step() % size) as i32,
                    y + (rng.step() % size) as i32,
                ]
            };
            let mut v = [p(&mut rng), p(&mut rng), p(&mut rng)];
            if k % 7 == 0 {
                // A vertex on a pixel centre's column, another on a centre's row, and
                // every other time the first on a centre itself.
                v[0][0] = (v[0][0] & !255) | 128;
                v[1][1] = (v[1][1] & !255) | 128;
                if k % 14 == 0 {
                    v[0][1] = (v[0][1] & !255) | 128;
                }
            }
            if k % 11 == 0 {
                v[2] = v[1]; // degenerate
            }
            let z = [0; 3].map(|_| 16 + (rng.step() % 1_000_000) as u32);
            let host = (k % 5 == 0).then(|| crate::setup::HostPlane {
                // A host around the decal, or one without area.
                v: if k % 10 == 0 {
                    [v[0], v[0], v[1]]
                } else {
                    [[x - 512, y - 512], [x + 1536, y - 512], [x - 512, y + 1536]]
                },
                z,
            });
            tris.push(SnappedTri {
                v,
                z,
                c: [[(k as u32 % 200) << 12; 3]; 3],
                host,
                ..Default::default()
            });
        }
        let r = SpanRaster::new(&tris, w, h).unwrap();
        let setups: Vec<_> = tris.iter().map(|t| TriSetup::new(t).unwrap()).collect();
        assert_eq!(r.triangles(), setups.iter().filter(|s| s.is_some()).count());
        let unset = setups
            .iter()
            .zip(&r.set)
            .filter(|(a, b)| a.is_some() && b.is_none());
        assert!(unset.count() > 2000, "most triangles are not set up");
        for t in &tris {
            assert_eq!(TriSetup::is_live(t), TriSetup::of_checked(t).is_some());
        }
        let expect = own_words(&setups, w, h);
        let words = expect.iter().map(Vec::len).sum::<usize>();
        assert!(words > 600, "{words} words");
        assert_eq!(scanned_words(&r, h), expect);
    }

    /// Per row, the words of each triangle's own setup ([`TriSetup::for_each_span`]),
    /// with its input index, in input order.
    fn own_words(setups: &[Option<TriSetup>], w: u32, h: u32) -> Vec<Vec<(u32, SpanWord)>> {
        let mut rows = vec![Vec::new(); h as usize];
        for (k, s) in setups.iter().enumerate() {
            if let Some(s) = s {
                s.for_each_span(w, h, |j, sw| rows[j as usize].push((k as u32, sw)));
            }
        }
        rows
    }

    /// Per row, the words [`SpanRaster::scan`] sends, with their triangles' indices.
    fn scanned_words(r: &SpanRaster, h: u32) -> Vec<Vec<(u32, SpanWord)>> {
        struct Rows(Vec<Vec<(u32, SpanWord)>>);
        impl SpanSink for Rows {
            fn span(&mut self, prim: u32, row: u32, w: &SpanWord) {
                self.0[row as usize].push((prim, *w));
            }
        }
        let mut got = Rows(vec![Vec::new(); h as usize]);
        r.scan(&mut got);
        got.0
    }
}
