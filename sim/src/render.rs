//! Whole-frame rendering on the golden pixel-processor array (no anti-aliasing).
//!
//! Built on [`PixelArray::step`]: each scanline is split into tiles of the array's width;
//! every tile gets its part of the command stream ([`crate::stream`]): `ClearLine`, the OP
//! span words of the row (in scene order) that touch it, then the shadow commands, and is
//! read out. Rows are independent, so they run in
//! parallel (rayon) with bit-identical results.

use crate::pixel_array::{
    is_flag_command, BandFlags, Command, PixelArray, ProcState, RowFlags, MORE_SHADE,
};
use crate::raster::{SpanRaster, SpanSink};
use crate::setup::{SetupError, SnappedTri};
use crate::shadow::ShadowRows;
use crate::stream::{feed_routed, feed_routed_pairs, TileRouter};
use pixelproc_formats::{SpanWord, MAX_SCREEN};
use rayon::prelude::*;

/// A rendered frame: per-pixel processor state after the last command of its row.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major per-pixel state (depth, intensity, shadow flags, counter).
    pub px: Vec<ProcState>,
    /// Shade registers 2.. per pixel ([`MORE_SHADE`] each, row-major), when the frame's
    /// spans used more than one shade channel; else empty.
    pub more: Vec<u32>,
}

impl Frame {
    /// RGB8 bytes, row-major.
    pub fn rgb8(&self) -> Vec<u8> {
        self.px
            .iter()
            .flat_map(|s| pixelproc_formats::unpack_rgb(s.rgb))
            .collect()
    }
    /// Depth buffer, row-major.
    pub fn depth(&self) -> Vec<u32> {
        self.px.iter().map(|s| s.zb).collect()
    }
}

/// The span words of a frame, per scanline, in scene (draw) order: the array feed, a
/// [`SpanSink`] of the raster core.
pub struct SpanSource {
    width: u32,
    height: u32,
    rows: Vec<Vec<SpanWord>>,
    triangles: usize,
    max_chan: u8,
}

/// Collects one band's span words per row (the array feed's [`SpanSink`]).
struct RowFeed {
    lo: i64,
    rows: Vec<Vec<SpanWord>>,
}

impl SpanSink for RowFeed {
    fn span(&mut self, _prim: u32, row: u32, w: &SpanWord) {
        self.rows[(row as i64 - self.lo) as usize].push(*w);
    }
}

impl SpanSource {
    /// Sets up every triangle (degenerate ones are dropped) and scan-converts each row
    /// band of the raster core ([`SpanRaster`]) in parallel, triangles in scene order
    /// within each row: the same words and order as a sequential run.
    pub fn new(tris: &[SnappedTri], width: u32, height: u32) -> Result<SpanSource, SetupError> {
        assert!(width <= MAX_SCREEN && height <= MAX_SCREEN);
        let raster = SpanRaster::new(tris, width, height)?;
        let bands: Vec<Vec<Vec<SpanWord>>> = (0..raster.band_count())
            .into_par_iter()
            .map(|b| {
                let (lo, _) = raster.band_rows(b);
                let mut feed = RowFeed {
                    lo,
                    rows: raster
                        .band_row_bounds(b)
                        .into_iter()
                        .map(Vec::with_capacity)
                        .collect(),
                };
                raster.scan_band(b, &mut feed);
                feed.rows
            })
            .collect();
        let rows = bands.into_iter().flatten().collect();
        Ok(SpanSource {
            width,
            height,
            rows,
            triangles: raster.triangles(),
            max_chan: tris.iter().map(|t| t.chan).max().unwrap_or(0),
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

    /// The OP span words of row `j`, in scene order.
    pub fn row_spans(&self, j: u32) -> &[SpanWord] {
        &self.rows[j as usize]
    }

    /// Number of span words over all rows.
    pub fn span_count(&self) -> usize {
        self.rows.iter().map(Vec::len).sum()
    }

    /// Pixels of all span words (`Σ xr − xl + 1`): the depth tests the array makes.
    pub fn span_pixels(&self) -> u64 {
        self.rows
            .par_iter()
            .map(|r| {
                r.iter()
                    .map(|w| (w.xr as i64 - w.xl as i64 + 1) as u64)
                    .sum::<u64>()
            })
            .sum()
    }

    /// Number of non-degenerate triangles set up.
    pub fn visible_triangles(&self) -> usize {
        self.triangles
    }

    /// The largest shade channel of the input triangles (0 without exact shading).
    pub fn max_chan(&self) -> u8 {
        self.max_chan
    }
}

/// `buf` in chunks of `chunk` items to hand out beside `count` rows or bands in parallel;
/// `count` empty slices when `buf` is empty (a per-pixel buffer that is not wanted).
pub(crate) fn chunks_or_empty<T>(buf: &mut [T], chunk: usize, count: usize) -> Vec<&mut [T]> {
    if buf.is_empty() {
        (0..count).map(|_| &mut [][..]).collect()
    } else {
        buf.chunks_mut(chunk).collect()
    }
}

/// Renders every row on an array of `array_width` processors; a wider line is processed
/// in tiles. Each tile is fed the per-tile form of the command stream
/// ([`crate::stream::feed_tile`], its choice made for all tiles at once by a
/// [`TileRouter`]):
/// `ClearLine`, the row's OP span words that touch it (an OP span outside a tile is a
/// no-op there, so the span feeder skips it), then the row's commands `extra[row]`
/// (shadow spans and controls, which all tiles see: IF acts on every processor; `extra`
/// is empty when there are none). When a row's `extra` holds shadow commands only
/// ([`is_flag_command`], as the shadow stage makes them), they are applied to the whole
/// row once its tiles hold their polygon spans ([`RowFlags`]): the same state, one pass
/// per span instead of one per tile.
pub fn render_frame(
    src: &SpanSource,
    bg: [u8; 3],
    array_width: usize,
    extra: &[Vec<Command>],
) -> Frame {
    render_frame_with(src, bg, array_width, RowExtra::Stored(extra), |_, _| {})
}

/// Where each row's commands after its polygon spans come from.
#[derive(Clone, Copy)]
pub enum RowExtra<'a> {
    /// One stored list per row (or none at all: an empty slice).
    Stored(&'a [Vec<Command>]),
    /// The shadow volumes set up beforehand, applied to a band of rows' flags a light
    /// sample at a time as the rows are drawn ([`ShadowRows::sample_flags`]), with the
    /// result of their commands, which are never made.
    Shadows(&'a ShadowRows),
}

/// Rows drawn by one task: a band's polygon spans, then each light sample's shadow
/// volumes applied to the band's flags in one walk ([`ShadowRows::sample_flags`]).
const BAND: usize = 16;

/// [`render_frame`], with `readout(row, more)` called on each row's final processor
/// states (and its shade registers 2.., empty if unused) as the row is read out, while it
/// is still in cache (its band's rows are 600 KB at 1080p): where the core's shade unit
/// corrects intensities ([`crate::shadow::shade_row`]). Rows are drawn in bands of 16,
/// in parallel: a band's polygon spans first, then each light sample's shadow volumes
/// in turn, applied to the band's flags.
pub fn render_frame_with<G>(
    src: &SpanSource,
    bg: [u8; 3],
    array_width: usize,
    extra: RowExtra,
    readout: G,
) -> Frame
where
    G: Fn(&mut [ProcState], &[u32]) + Sync,
{
    match extra {
        RowExtra::Stored(rows) => assert!(
            rows.is_empty() || rows.len() == src.height as usize,
            "one command list per row"
        ),
        RowExtra::Shadows(s) => assert_eq!(s.height(), src.height, "one shadow row per row"),
    }
    let (w, h) = (src.width, src.height);
    let bg = pixelproc_formats::pack_rgb(bg);
    let tiles = (w as usize).div_ceil(array_width);
    // Zeroed memory (the default state): at 1080p the allocator maps fresh pages, which the
    // bands below fault in in parallel as they write their rows, instead of one thread
    // writing the whole frame first (41 MB at 1080p: 15–20 ms on one core).
    let mut px: Vec<ProcState> = bytemuck::zeroed_vec((w * h) as usize);
    let more_stride = if src.max_chan >= 2 { MORE_SHADE } else { 0 };
    let mut more = vec![0u32; (w * h) as usize * more_stride];
    let bands = (h as usize).div_ceil(BAND);
    let mut more_bands = chunks_or_empty(&mut more, w as usize * more_stride * BAND, bands);
    px.par_chunks_mut(w as usize * BAND)
        .zip(more_bands.par_iter_mut())
        .enumerate()
        .for_each_init(
            || RowScratch::new(array_width, tiles),
            |scratch, (b, (band, mband))| {
                let j0 = (b * BAND) as u32;
                let n = band.len() / w as usize;
                let ws = w as usize * more_stride;
                let mrow = |mband: &mut [u32], r: usize| -> std::ops::Range<usize> {
                    if mband.is_empty() {
                        0..0
                    } else {
                        r * ws..(r + 1) * ws
                    }
                };
                let row = |r: usize| r * w as usize..(r + 1) * w as usize;
                // Each row's polygon spans (and stored commands) through the tiles.
                let shadows = match extra {
                    RowExtra::Shadows(s) => Some(s),
                    RowExtra::Stored(_) => None,
                };
                for r in 0..n {
                    let j = j0 + r as u32;
                    let cmds: &[Command] = match extra {
                        RowExtra::Stored(rows) => rows.get(j as usize).map_or(&[], |c| c),
                        RowExtra::Shadows(_) => &[],
                    };
                    let m = mrow(mband, r);
                    scratch.draw(src, bg, j, cmds, &mut band[row(r)], &mut mband[m.clone()]);
                    if shadows.is_none() {
                        readout(&mut band[row(r)], &mut mband[m]);
                    }
                }
                // Then the shadows, light sample by light sample, each applied to the
                // band's flags as the routed tiles would apply its commands.
                if let Some(s) = shadows {
                    if s.samples() > 0 {
                        let flags = &mut scratch.band_flags;
                        flags.load(band, w as usize);
                        for k in 0..s.samples() {
                            s.sample_flags(k, j0, band, flags);
                        }
                        flags.store(band);
                    }
                    for r in 0..n {
                        let m = mrow(mband, r);
                        readout(&mut band[row(r)], &mut mband[m]);
                    }
                }
            },
        );
    drop(more_bands);
    Frame {
        width: w,
        height: h,
        px,
        more,
    }
}

/// One task's array and buffers for drawing rows.
struct RowScratch {
    arr: PixelArray,
    /// Per tile: the indices of the row's OP spans that touch it.
    per_tile: Vec<Vec<u32>>,
    router: TileRouter,
    /// Per tile: which of the row's commands it is fed ([`TileRouter::route`]).
    routed: Vec<Vec<u32>>,
    flags: RowFlags,
    /// The band's shadow flags, for the volumes of each light sample.
    band_flags: BandFlags,
}

impl RowScratch {
    fn new(array_width: usize, tiles: usize) -> RowScratch {
        RowScratch {
            arr: PixelArray::new(array_width, 0),
            per_tile: vec![Vec::new(); tiles],
            router: TileRouter::default(),
            routed: vec![Vec::new(); tiles],
            flags: RowFlags::default(),
            band_flags: BandFlags::default(),
        }
    }

    /// Draws row `j` of `src` into `row` (and its shade registers 2.. into `mrow`, empty
    /// if unused): its tiles fed `ClearLine`, their OP spans and the routed `cmds`.
    fn draw(
        &mut self,
        src: &SpanSource,
        bg: u32,
        j: u32,
        cmds: &[Command],
        row: &mut [ProcState],
        mrow: &mut [u32],
    ) {
        let RowScratch {
            arr,
            per_tile,
            router,
            routed,
            flags,
            ..
        } = self;
        let array_width = arr.width();
        let (w, tiles) = (src.width, per_tile.len());
        let more_stride = if src.max_chan >= 2 { MORE_SHADE } else { 0 };
        // Shadow commands alone (as the shadow stage makes them) are applied to the
        // whole row once its tiles hold their polygons, with the result of routing
        // them to the tiles; anything else goes through the tiles.
        let row_wide = !cmds.is_empty() && cmds.iter().all(is_flag_command);
        router.route(
            if row_wide { &[] } else { cmds },
            array_width as u32,
            routed,
        );
        for t in per_tile.iter_mut() {
            t.clear();
        }
        let spans = src.row_spans(j);
        for (k, s) in spans.iter().enumerate() {
            let (a, b) = (s.xl as usize / array_width, s.xr as usize / array_width);
            for t in per_tile.iter_mut().take(b.min(tiles - 1) + 1).skip(a) {
                t.push(k as u32);
            }
        }
        for (t, list) in per_tile.iter().enumerate() {
            let base = (t * array_width) as u32;
            arr.set_base(base);
            let ops = list.iter().map(|&k| &spans[k as usize]);
            if src.max_chan >= 1 {
                feed_routed_pairs(arr, bg, ops, cmds, &routed[t]);
            } else {
                feed_routed(arr, bg, ops, cmds, &routed[t]);
            }
            let n = (w - base).min(array_width as u32) as usize;
            row[base as usize..base as usize + n].copy_from_slice(&arr.state()[..n]);
            if more_stride > 0 && !arr.shade_regs().is_empty() {
                let b = base as usize * more_stride;
                mrow[b..b + n * more_stride].copy_from_slice(&arr.shade_regs()[..n * more_stride]);
            }
        }
        if row_wide {
            flags.run(row, cmds, array_width);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontend::Projector;
    use crate::scene::load_builtin;
    use crate::setup::TriSetup;
    use crate::shadow::{occluders, shadow_lights, Shading, ShadowForm};
    use crate::stream::SceneStream;

    /// Each row of a [`SpanSource`] holds, in input order, exactly the words each
    /// triangle makes on it by division ([`TriSetup::span`]), though the rows are
    /// scanned band by band in parallel and copies together: random triangles with
    /// shade-channel copies, decals and a degenerate one
    /// ([`crate::raster::copies_scene`]), heights that are and are not a multiple of the
    /// band. The word and pixel counts agree.
    #[test]
    fn span_source_rows_hold_each_triangles_words_in_order() {
        let mut rng = crate::rng::Lcg64(0x5107_f00d);
        for (w, h, n) in [(96u32, 80u32, 400), (130, 37, 250), (17, 5, 60)] {
            let tris = crate::raster::copies_scene(&mut rng, w, h, n);
            let src = SpanSource::new(&tris, w, h).unwrap();
            let setups: Vec<Option<TriSetup>> =
                tris.iter().map(|t| TriSetup::new(t).unwrap()).collect();
            let (mut words, mut pixels) = (0, 0);
            for j in 0..h {
                let want: Vec<SpanWord> = setups
                    .iter()
                    .flatten()
                    .filter_map(|t| t.span(j as i64, w))
                    .collect();
                assert_eq!(src.row_spans(j), &want[..], "{w}x{h} row {j}");
                words += want.len();
                pixels += want.iter().map(|s| (s.xr - s.xl + 1) as u64).sum::<u64>();
            }
            assert!(words > 40, "{w}x{h}: {words} words");
            assert_eq!(src.span_count(), words);
            assert_eq!(src.span_pixels(), pixels);
        }
    }

    /// Drawing with each band's shadow volumes applied to its flags as its rows are drawn
    /// gives the same frame (every register, the shade registers 2.. included) and the
    /// same count of shadow span words as drawing the commands stored per row, one light's
    /// after the other's, as the RTL benches' stimulus stores them (which the volumes make
    /// a band, a row or a few rows at a time): two point lights and an area
    /// light with exact shading (three shade channels), both shadow forms, heights that
    /// are and are not a multiple of the band, arrays narrower and wider than the screen;
    /// and each row is what one array as wide as the screen makes of the stream's row.
    #[test]
    fn shadow_rows_made_per_band_draw_the_stored_commands_frame() {
        let mut drawn = 0;
        for (h, form, n) in [
            (37u32, ShadowForm::Ev, 16usize),
            (48, ShadowForm::Check, 7),
            (9, ShadowForm::Ev, 128),
        ] {
            let mut ls = load_builtin("default").unwrap();
            ls.scene.width = 96;
            ls.scene.height = h;
            crate::shadow::add_test_lights(&mut ls);
            let which: Vec<usize> = (0..ls.scene.lights.len()).collect();
            let s = SceneStream::of_scene(&ls, &which, form, Shading::Exact).unwrap();
            assert!(
                s.spans.max_chan() >= 2,
                "exact shading uses shade registers 2.."
            );
            let (pj, occ) = (Projector::new(&ls), occluders(&ls));
            let lights = shadow_lights(&ls, &which).unwrap();
            let make = |budget: u64| {
                let mut made: Option<ShadowRows> = None;
                for l in &lights {
                    let more =
                        ShadowRows::new(&occ, &ls, &pj, std::slice::from_ref(l), form).unwrap();
                    match &mut made {
                        Some(m) => m.append(more),
                        None => made = Some(more),
                    }
                }
                let mut made = made.unwrap();
                made.set_budget(budget);
                made
            };
            let bg = s.bg;
            let want = render_frame(&s.spans, bg, n, &s.shadow);
            // Each light sample's commands made for a whole band at once, one row at a
            // time (the least budget) and a few rows at a time, are the stored ones.
            for budget in [1, 3000, u64::MAX] {
                let rows = make(budget).commands().rows;
                assert!(rows == s.shadow, "height {h}, {form:?}, budget {budget}");
            }
            // Drawn with each light sample's volumes applied to a band's flags.
            let made = make(u64::MAX);
            let got = render_frame_with(&s.spans, bg, n, RowExtra::Shadows(&made), |_, _| {});
            assert_eq!(got.px, want.px, "height {h}, {form:?}, array {n}");
            assert_eq!(got.more, want.more, "height {h}, {form:?}, array {n}");
            assert!(!got.more.is_empty());
            // And each row as one array as wide as the screen runs it, straight from the
            // stream's commands (no tiles, no bands).
            let w = s.width() as usize;
            let mut arr = PixelArray::new(w, 0);
            for j in 0..h as usize {
                arr.run_line(s.bg_packed(), &s.row(j as u32));
                assert_eq!(arr.state(), &got.px[j * w..(j + 1) * w], "row {j}");
                let m = &got.more[j * w * MORE_SHADE..(j + 1) * w * MORE_SHADE];
                match arr.shade_regs() {
                    [] => assert!(m.iter().all(|&v| v == 0), "row {j}: no shade register 2.."),
                    regs => assert_eq!(regs, m, "row {j}'s shade registers 2.."),
                }
            }
            let stats = made.stats();
            assert_eq!(stats.span_words, s.shadow_stats.span_words);
            assert_eq!(stats.volumes, s.shadow_stats.volumes);
            assert!(want.px.iter().any(|p| p.mask != 0) && want.px.iter().any(|p| p.count != 0));
            drawn += stats.span_words;
        }
        assert!(drawn > 1000, "{drawn} shadow span words drawn");
    }
}
