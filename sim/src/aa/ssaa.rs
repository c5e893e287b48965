//! `k × k` ordered supersampling with a box resolve (comparison method).
//!
//! Samples at `((i + (2a+1)/(2k)), (j + (2b+1)/(2k)))`, `a, b < k`, on one lattice of
//! `(W·k) × (H·k)` points ([`super::sampler`]: exact coverage with the top-left rule,
//! scene-order z-buffer). The resolve sums the `k²` Q8.12 intensities of a pixel and
//! truncates once: `C = ⌊Σ I / (k²·2^12)⌋` (the +2048 rounding offset is already in every
//! Q8.12 intensity, `docs/formats.md`, so this is a rounding of the true mean). The visible triangle of a pixel is
//! the one owning most of its samples (lowest index on a tie, background −1 first).

use super::sampler::{rasterize, Lattice};
use super::{AaError, AaFrame, AaStats};
use crate::setup::SnappedTri;
use rayon::prelude::*;

/// Bytes per lattice sample in [`super::sampler::SampleBuf`]: depth (8), Q8.12 RGB (12),
/// owner (4).
const SAMPLE_BYTES: u64 = 24;

/// Largest sample buffer one band may hold: the lattice is rasterized in bands of whole
/// pixel rows so that memory stays bounded whatever `k` and the resolution (every sample is
/// independent, so the result is the same as one whole-frame lattice).
const BAND_BYTES: u64 = 256 << 20;

/// Pixel rows per band for a `width`-wide frame at `k × k`.
fn band_rows(width: u32, k: u32) -> u32 {
    let row = width as u64 * (k as u64 * k as u64) * SAMPLE_BYTES;
    (BAND_BYTES / row.max(1)).clamp(1, u32::MAX as u64) as u32
}

/// Renders with `k × k` supersampling, `1 ≤ k ≤ 64`.
pub fn render(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    k: u32,
) -> Result<AaFrame, AaError> {
    render_with(tris, width, height, bg, k, true)
}

/// [`render`]; with `visible` false the visible-triangle AOV is not computed
/// ([`AaFrame::visible`] is `None`), the image and counters are the same.
pub fn render_with(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    k: u32,
    visible: bool,
) -> Result<AaFrame, AaError> {
    if !(1..=64).contains(&k) {
        return Err(AaError::Param(format!("ssaa k = {k} must be in 1..=64")));
    }
    render_in_bands(tris, width, height, bg, k, band_rows(width, k), visible)
}

/// [`render`] with an explicit band height in pixel rows.
fn render_in_bands(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    k: u32,
    rows: u32,
    want_visible: bool,
) -> Result<AaFrame, AaError> {
    let (w, h) = (width as usize, height as usize);
    let mut rgb = vec![0u8; w * h * 3];
    let mut visible = vec![-1i32; w * h];
    let mut stats = AaStats::default();
    for j0 in (0..height).step_by(rows as usize) {
        let j1 = (j0 + rows).min(height);
        // Sample row b of the band is frame sample row j0·k + b: y = (2(j0·k + b) + 1)/(2k).
        let lat = Lattice {
            nx: width * k,
            ny: (j1 - j0) * k,
            sx: 2,
            sy: 2,
            ox: 1,
            oy: 1 + 2 * (j0 as i64) * (k as i64),
            den: 2 * k as i64,
        };
        let buf = rasterize(tris, &[lat], bg).pop().expect("one lattice");
        let px = j0 as usize * w..j1 as usize * w;
        resolve(
            &buf,
            width,
            k,
            &mut rgb[px.start * 3..px.end * 3],
            want_visible.then(|| &mut visible[px]),
        );
        stats.depth_evals += buf.depth_evals;
        stats.samples_written += buf.z.len() as u64;
        stats.sample_reads += buf.z.len() as u64;
    }
    Ok(AaFrame {
        width,
        height,
        rgb,
        visible: want_visible.then_some(visible),
        stats,
    })
}

/// Box resolve of one band: every pixel's `k²` samples summed and truncated once; the
/// visible triangle is the one owning most samples (lowest index on a tie).
fn resolve(
    buf: &super::sampler::SampleBuf,
    width: u32,
    k: u32,
    rgb: &mut [u8],
    visible: Option<&mut [i32]>,
) {
    let (w, k) = (width as usize, k as usize);
    let n = (k * k) as u64;
    // The colour of pixel i of row j: the box sum of its k×k samples, truncated once.
    let colour = |i: usize, j: usize, out: &mut [u8]| {
        let mut acc = [0u64; 3];
        for b in 0..k {
            let s0 = buf.idx((i * k) as u32, (j * k + b) as u32);
            for c in &buf.rgb[s0..s0 + k] {
                for (a, &v) in acc.iter_mut().zip(c) {
                    *a += v as u64;
                }
            }
        }
        for (o, a) in out.iter_mut().zip(acc) {
            *o = super::div_q12(a, n).min(255) as u8;
        }
    };
    let Some(visible) = visible else {
        rgb.par_chunks_mut(3 * w)
            .enumerate()
            .for_each(|(j, rgb_row)| {
                for i in 0..w {
                    colour(i, j, &mut rgb_row[3 * i..3 * i + 3]);
                }
            });
        return;
    };
    rgb.par_chunks_mut(3 * w)
        .zip(visible.par_chunks_mut(w))
        .enumerate()
        .for_each_init(
            Vec::new,
            |counts: &mut Vec<(i32, u32)>, (j, (rgb_row, vis_row))| {
                for i in 0..w {
                    colour(i, j, &mut rgb_row[3 * i..3 * i + 3]);
                    counts.clear();
                    for b in 0..k {
                        let s0 = buf.idx((i * k) as u32, (j * k + b) as u32);
                        for &t in &buf.tri[s0..s0 + k] {
                            match counts.iter_mut().find(|c| c.0 == t) {
                                Some(c) => c.1 += 1,
                                None => counts.push((t, 1)),
                            }
                        }
                    }
                    counts.sort_by_key(|c| (std::cmp::Reverse(c.1), c.0));
                    vis_row[i] = counts[0].0;
                }
            },
        );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_bound_memory_and_change_nothing() {
        for (w, k) in [(1920, 2), (1920, 8), (4096, 64), (16, 1)] {
            let rows = band_rows(w, k) as u64;
            assert!(rows == 1 || rows * w as u64 * (k * k) as u64 * SAMPLE_BYTES <= BAND_BYTES);
        }
        let ls = crate::scene::load_builtin("default").unwrap();
        let p = crate::frontend::project(&ls).unwrap();
        let (w, h) = (ls.scene.width, ls.scene.height);
        let whole = render_in_bands(&p.tris, w, h, [10, 20, 30], 3, h, true).unwrap();
        for rows in [1, 7, 64] {
            let banded = render_in_bands(&p.tris, w, h, [10, 20, 30], 3, rows, true).unwrap();
            assert_eq!(banded.rgb, whole.rgb, "rows per band {rows}");
            assert_eq!(banded.visible, whole.visible);
            assert_eq!(banded.stats.depth_evals, whole.stats.depth_evals);
            assert_eq!(banded.stats.samples_written, whole.stats.samples_written);
        }
    }
}
