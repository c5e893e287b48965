//! Whole-frame rendering on the golden pixel-processor array (no anti-aliasing).
//!
//! Built on [`PixelArray::step`]: each scanline is split into tiles of the array's width;
//! every tile gets its part of the command stream ([`crate::stream`]): `ClearLine`, the OP
//! span words of the row (in scene order) that touch it, then the shadow commands, and is
//! read out. Rows are independent, so they run in
//! parallel (rayon) with bit-identical results.

use crate::pixel_array::{is_flag_command, Command, PixelArray, ProcState, RowFlags, MORE_SHADE};
use crate::raster::{SpanRaster, SpanSink};
use crate::setup::{SetupError, SnappedTri};
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
    render_frame_with(src, bg, array_width, extra, |_, _| {})
}

/// [`render_frame`], with `readout(row, more)` called on each row's final processor
/// states (and its shade registers 2.., empty if unused) as the row is read out, while it
/// is still in cache: where the core's shade unit corrects intensities
/// ([`crate::shadow::shade_row`]).
pub fn render_frame_with<G>(
    src: &SpanSource,
    bg: [u8; 3],
    array_width: usize,
    extra: &[Vec<Command>],
    readout: G,
) -> Frame
where
    G: Fn(&mut [ProcState], &[u32]) + Sync,
{
    assert!(
        extra.is_empty() || extra.len() == src.height as usize,
        "one command list per row"
    );
    let (w, h) = (src.width, src.height);
    let bg = pixelproc_formats::pack_rgb(bg);
    let tiles = (w as usize).div_ceil(array_width);
    let mut px = vec![ProcState::default(); (w * h) as usize];
    let more_stride = if src.max_chan >= 2 { MORE_SHADE } else { 0 };
    let mut more = vec![0u32; (w * h) as usize * more_stride];
    let mut more_rows = chunks_or_empty(&mut more, w as usize * more_stride, h as usize);
    px.par_chunks_mut(w as usize)
        .zip(more_rows.par_iter_mut())
        .enumerate()
        .for_each_init(
            || {
                (
                    PixelArray::new(array_width, 0),
                    vec![Vec::new(); tiles],
                    TileRouter::default(),
                    vec![Vec::new(); tiles],
                    RowFlags::default(),
                )
            },
            |(arr, per_tile, router, routed, flags), (j, (row, mrow))| {
                let cmds: &[Command] = extra.get(j).map_or(&[], |c| c);
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
                let spans = src.row_spans(j as u32);
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
                        mrow[b..b + n * more_stride]
                            .copy_from_slice(&arr.shade_regs()[..n * more_stride]);
                    }
                }
                if row_wide {
                    flags.run(row, cmds, array_width);
                }
                readout(row, mrow);
            },
        );
    drop(more_rows);
    Frame {
        width: w,
        height: h,
        px,
        more,
    }
}
