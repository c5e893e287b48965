//! Whole-frame rendering on the golden pixel-processor array (no anti-aliasing).
//!
//! Built on [`PixelArray::step`]: each scanline is split into tiles of the array's width;
//! every tile gets `ClearLine`, the OP span words of the row (in scene order) that touch
//! it, then the shadow commands, and is read out. Rows are independent, so they run in
//! parallel (rayon) with bit-identical results.

use crate::pixel_array::{Command, PixelArray, ProcState};
use crate::setup::{SetupError, SnappedTri, TriSetup};
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

/// Triangles prepared for span setup, binned by scanline band.
pub struct SpanSource {
    width: u32,
    height: u32,
    tris: Vec<TriSetup>,
    /// For each band of [`BAND`] rows, the indices of triangles touching it, in order.
    bands: Vec<Vec<u32>>,
}

/// Rows per bin band.
pub const BAND: i64 = 8;

impl SpanSource {
    /// Sets up every triangle (degenerate ones are dropped) and bins them by band.
    pub fn new(tris: &[SnappedTri], width: u32, height: u32) -> Result<SpanSource, SetupError> {
        assert!(width <= MAX_SCREEN && height <= MAX_SCREEN);
        let set: Vec<Option<TriSetup>> = tris
            .par_iter()
            .map(TriSetup::new)
            .collect::<Result<_, _>>()?;
        let tris: Vec<TriSetup> = set.into_iter().flatten().collect();
        let nb = (height as i64 + BAND - 1) / BAND;
        let mut bands = vec![Vec::new(); nb as usize];
        for (k, t) in tris.iter().enumerate() {
            let lo = t.row_min.max(0) / BAND;
            let hi = t.row_max.min(height as i64 - 1);
            if hi < 0 || lo >= nb {
                continue;
            }
            for b in lo..=hi / BAND {
                bands[b as usize].push(k as u32);
            }
        }
        Ok(SpanSource {
            width,
            height,
            tris,
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

    /// The OP span words of row `j`, in scene order.
    pub fn row_spans(&self, j: u32) -> impl Iterator<Item = SpanWord> + '_ {
        let band = &self.bands[(j as i64 / BAND) as usize];
        band.iter()
            .filter_map(move |&k| self.tris[k as usize].span(j as i64, self.width))
    }

    /// Number of set-up (non-degenerate) triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }
}

/// Renders every row: OP spans, then `extra(j)` commands (e.g. shadow spans) per tile.
/// `array_width` is the number of processors; wider lines are processed in tiles.
pub fn render_frame<F>(src: &SpanSource, bg: [u8; 3], array_width: usize, extra: F) -> Frame
where
    F: Fn(u32, &mut Vec<Command>) + Sync,
{
    let (w, h) = (src.width, src.height);
    let bg = pixelproc_formats::pack_rgb(bg);
    let mut px = vec![ProcState::default(); (w * h) as usize];
    px.par_chunks_mut(w as usize).enumerate().for_each_init(
        || (PixelArray::new(array_width, 0), Vec::new()),
        |(arr, cmds), (j, row)| {
            cmds.clear();
            cmds.extend(src.row_spans(j as u32).map(Command::Span));
            extra(j as u32, cmds);
            let mut base = 0u32;
            while base < w {
                arr.set_base(base);
                arr.run_line(bg, cmds.iter());
                let n = (w - base).min(array_width as u32) as usize;
                row[base as usize..base as usize + n].copy_from_slice(&arr.state()[..n]);
                base += array_width as u32;
            }
        },
    );
    Frame {
        width: w,
        height: h,
        px,
    }
}
