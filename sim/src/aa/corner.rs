//! Corner-shared sampling (seed 003, JP4801088B2, Ström & Akenine-Möller) and two
//! comparison patterns (the D3D standard 4× pattern, an ordered 2×2 grid).
//!
//! **Corner pattern (seed 003, "sample regions at the pixel corners", Fig. 3a).** A pixel
//! is 3×3 subpixels; a 2×2-subpixel sample region is centred on each pixel corner and
//! holds one sample, at a subpixel centre, `±1/6` pixel from the corner. The sample of
//! corner `(I, J)` is shared by the four pixels meeting there, so one sample is rendered
//! per pixel on average. The offset alternates with the corner's parity (the mirrored,
//! period-2 structure of the seed):
//!
//! | `(I mod 2, J mod 2)` | offset from the corner (pixels) |
//! |---|---|
//! | (0, 0) | (−1/6, −1/6) |
//! | (1, 0) | (+1/6, +1/6) |
//! | (0, 1) | (+1/6, −1/6) |
//! | (1, 1) | (−1/6, +1/6) |
//!
//! For pixel (0, 0) this puts its samples at (−2/3, −2/3), (+2/3, −1/3), (−1/3, +1/3),
//! (+1/3, +2/3) from its centre: the seed's example (1-based subpixels (3,3), (7,4),
//! (4,6), (6,7) of the 9×9 grid): four distinct x, four distinct y, no two on one 45°
//! line, so a near-horizontal or near-vertical edge passes through all five levels
//! 0, ¼, ½, ¾, 1. Exactly one of the four lies inside the pixel square.
//!
//! **Weights.** Integers normalised by their sum ([`CornerWeights`]): ¼ each by default,
//! or e.g. 0.4 for the sample inside the pixel and 0.2 for the others, and, with the
//! optional centre sample (two samples per pixel), a higher weight for it. The resolve
//! truncates once: `C = ⌊Σ w·I / (W·2^12)⌋`, `W = Σ w`, `I` in Q8.12 with the +2048
//! rounding offset folded in (`docs/formats.md`), so truncation rounds the true value.
//!
//! **Resolve with a row buffer (seed 003, memory paragraph).** Pixels are resolved row by
//! row, left to right; an on-chip row buffer holds the previous row's bottom corner
//! samples and a register holds the previous pixel's right-hand bottom sample, so each
//! pixel reads one new corner sample from sample memory (plus one per row start, one row
//! of corners at the top, and the centre sample if enabled). [`AaStats::sample_reads`]
//! counts those reads. Border pixels use the corner samples outside the screen edge,
//! which the lattice includes (`(W+1) × (H+1)` corners).
//!
//! Coverage, depth and intensity per sample come from [`super::sampler`].

use super::sampler::{prepare_all, LatticeRaster};
use super::{AaError, AaFrame, AaStats};
use crate::setup::SnappedTri;
use rayon::prelude::*;

mod pattern;
use pattern::RowSamples;
pub use pattern::{
    lattices, pattern_metrics, pixel_offsets, pixel_samples, CornerParams, CornerWeights, Pattern,
    PatternMetrics,
};

/// Pixel rows per band of [`render_with`] (each band rasterizes the lattice rows it
/// reads into its thread's buffers).
const BAND_ROWS: u32 = 16;

/// Per lattice (`n` of them), the range `(lo, hi)` of lattice rows the pixels of rows
/// `j0 .. j1` read (`lo > hi`: none).
fn read_rows(p: &CornerParams, n: usize, j0: u32, j1: u32) -> Vec<(u32, u32)> {
    let mut r = vec![(u32::MAX, 0); n];
    for j in j0..j1 {
        let rows = RowSamples::new(p, j);
        for tpl in &rows.tpl {
            for &(l, _, b, _) in tpl.as_slice() {
                r[l] = (r[l].0.min(b), r[l].1.max(b));
            }
        }
    }
    r
}

/// A band's rows `lo ..= hi` of one lattice (a thread's buffer).
#[derive(Clone, Default)]
struct SampleRows {
    lo: u32,
    nx: usize,
    rgb: Vec<[u32; 3]>,
    tri: Vec<i32>,
    z: Vec<i64>,
}

impl SampleRows {
    /// Rasterizes rows `lo ..= hi` of `lr`'s lattice; returns the depth evaluations of
    /// the rows after `seen` (those an earlier band has not counted).
    fn fill(&mut self, lr: &LatticeRaster, lo: u32, hi: u32, seen: Option<u32>) -> u64 {
        self.lo = lo;
        self.nx = lr.lattice().nx as usize;
        let n = if lo > hi {
            0
        } else {
            (hi - lo + 1) as usize * self.nx
        };
        self.z.resize(n, 0);
        self.rgb.resize(n, [0; 3]);
        self.tri.resize(n, 0);
        let mut evals = 0;
        for (k, b) in (lo..=hi).enumerate() {
            let r = k * self.nx..(k + 1) * self.nx;
            let e = lr.row(
                b,
                &mut self.z[r.clone()],
                &mut self.rgb[r.clone()],
                &mut self.tri[r],
            );
            if seen.is_none_or(|s| b > s) {
                evals += e;
            }
        }
        evals
    }

    /// The owner of sample `(a, b)`.
    #[inline]
    fn owner(&self, a: u32, b: u32) -> i32 {
        self.tri[(b - self.lo) as usize * self.nx + a as usize]
    }

    /// The colours of lattice row `b`.
    #[inline]
    fn rgb_row(&self, b: u32) -> &[[u32; 3]] {
        let s = (b - self.lo) as usize * self.nx;
        &self.rgb[s..s + self.nx]
    }
}

fn check(p: &CornerParams) -> Result<u64, AaError> {
    let w = p.weights;
    let total = w.inside as u64 + 3 * w.outside as u64 + if p.centre { w.centre as u64 } else { 0 };
    if total == 0 || total > 1 << 16 {
        return Err(AaError::Param(format!(
            "corner weights {w:?} must sum to 1..=65536"
        )));
    }
    Ok(total)
}

/// The resolved colours of pixel row `rows` into `out` (RGB8, three bytes per pixel),
/// `⌊Σ wt·C / (total·2^12)⌋` per channel over each pixel's samples (colours truncate; at
/// most 255). Each pixel's samples are those [`RowSamples::of`] gives it, read from the
/// template's lattice rows at the template column plus the shift per two pixels, without
/// a lookup per sample.
fn resolve_row(rows: &RowSamples, bufs: &[SampleRows], total: u64, out: &mut [u8]) {
    match rows.tpl[0].n {
        4 => resolve_row_n::<4>(rows, bufs, total, out),
        5 => resolve_row_n::<5>(rows, bufs, total, out),
        n => unreachable!("{n} samples per pixel"),
    }
}

/// A sample slot of a row's pixels of one column parity: its lattice row's colours, the
/// column of the template pixel, the shift per two pixels, the weight.
type Slot<'b> = (&'b [[u32; 3]], usize, usize, u64);

/// [`resolve_row`] for pixels of `N` samples each.
fn resolve_row_n<const N: usize>(
    rows: &RowSamples,
    bufs: &[SampleRows],
    total: u64,
    out: &mut [u8],
) {
    let slots: [[Slot; N]; 2] = std::array::from_fn(|q| {
        std::array::from_fn(|n| {
            let (l, a0, b, wt) = rows.tpl[q].s[n];
            let step = rows.adv[q][n];
            (bufs[l].rgb_row(b), a0 as usize, step as usize, wt as u64)
        })
    });
    if total.is_power_of_two() {
        let sh = 12 + total.trailing_zeros();
        resolve_pixels(&slots, out, |a| a >> sh);
    } else {
        let d = total * 4096;
        resolve_pixels(&slots, out, |a| a / d);
    }
}

/// [`resolve_row_n`]'s loop, `norm` the division by the weights' sum.
#[inline(always)]
fn resolve_pixels<const N: usize>(
    slots: &[[Slot; N]; 2],
    out: &mut [u8],
    norm: impl Fn(u64) -> u64,
) {
    for (i, o) in out.chunks_exact_mut(3).enumerate() {
        let k = i >> 1;
        let mut acc = [0u64; 3];
        for &(src, a0, step, wt) in &slots[i & 1] {
            let c = src[a0 + k * step];
            for ch in 0..3 {
                acc[ch] += wt * c[ch] as u64;
            }
        }
        for ch in 0..3 {
            o[ch] = norm(acc[ch]).min(255) as u8;
        }
    }
}

/// The visible triangle of one pixel from the owners of its samples `(owner, weight)`:
/// the one with the largest summed weight, the lowest index on a tie. `wsum` is scratch
/// space.
fn owner_of(vals: &[(i32, u32)], wsum: &mut Vec<(i32, u64)>) -> i32 {
    wsum.clear();
    for &(t, wt) in vals {
        match wsum.iter_mut().find(|e| e.0 == t) {
            Some(e) => e.1 += wt as u64,
            None => wsum.push((t, wt as u64)),
        }
    }
    wsum.sort_by_key(|e| (std::cmp::Reverse(e.1), e.0));
    wsum[0].0
}

/// Renders with the pattern of `p`.
pub fn render(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &CornerParams,
) -> Result<AaFrame, AaError> {
    render_with(tris, width, height, bg, p, true)
}

/// [`render`]; with `visible` false the visible-triangle AOV is not computed
/// ([`AaFrame::visible`] is `None`), the image and counters are the same.
pub fn render_with(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &CornerParams,
    visible: bool,
) -> Result<AaFrame, AaError> {
    let want_visible = visible;
    let total = check(p)?;
    let lats = lattices(p, width, height);
    let st = prepare_all(tris);
    let lrs: Vec<LatticeRaster> = lats
        .iter()
        .map(|l| LatticeRaster::new(&st, l, bg))
        .collect();
    let (w, h) = (width as usize, height as usize);
    let band = BAND_ROWS as usize;
    let mut rgb = vec![0u8; w * h * 3];
    // The visible-triangle AOV only when wanted (else one empty slice per band).
    let mut visible = if want_visible {
        vec![-1i32; w * h]
    } else {
        Vec::new()
    };
    let mut vis_bands = crate::render::chunks_or_empty(&mut visible, w * band, h.div_ceil(band));
    let corner = p.pattern == Pattern::Corner;
    // The hardware reads each corner sample once: the samples of a pixel row's top edge
    // come from a row buffer (the first row's are read before it), sample 2 of every
    // pixel but the first is the previous pixel's sample 3. Bands of rows run in parallel
    // reading the samples directly (the same values) and count the reads that order makes.
    let first_row_reads = if corner { width as u64 + 1 } else { 0 };
    let (reads, evals) = rgb
        .par_chunks_mut(3 * w * band)
        .zip(vis_bands.par_iter_mut())
        .enumerate()
        .map_init(
            || (vec![SampleRows::default(); lrs.len()], Vec::new()),
            |(bufs, wsum), (k, (rgb_band, vis_band))| {
                let j0 = (k * band) as u32;
                let j1 = (j0 + BAND_ROWS).min(height);
                // Each lattice row is counted by the first band that reads it.
                let prev = (k > 0).then(|| read_rows(p, lrs.len(), j0 - BAND_ROWS, j0));
                let mut evals = 0u64;
                for (l, (&(lo, hi), buf)) in read_rows(p, lrs.len(), j0, j1)
                    .iter()
                    .zip(bufs.iter_mut())
                    .enumerate()
                {
                    let seen = prev.as_ref().map(|r| r[l].1);
                    evals += buf.fill(&lrs[l], lo, hi, seen);
                }
                let mut reads = 0u64;
                let mut vals = [(-1i32, 0u32); 5];
                for j in j0..j1 {
                    let rows = RowSamples::new(p, j);
                    let r = (j - j0) as usize;
                    resolve_row(
                        &rows,
                        bufs,
                        total,
                        &mut rgb_band[3 * r * w..3 * (r + 1) * w],
                    );
                    // Each pixel reads its samples; for the corner pattern samples 0 and 1
                    // come from the row buffer, sample 2 from the previous pixel's sample 3
                    // (but at the row's first pixel).
                    let n = rows.tpl[0].n as u64;
                    reads += if corner {
                        (n - 2) * width as u64 - (width as u64 - 1)
                    } else {
                        n * width as u64
                    };
                    if want_visible {
                        for i in 0..width {
                            let smp = rows.of(i);
                            let smp = smp.as_slice();
                            for (v, &(l, a, b, wt)) in vals.iter_mut().zip(smp) {
                                *v = (bufs[l].owner(a, b), wt);
                            }
                            vis_band[r * w + i as usize] = owner_of(&vals[..smp.len()], wsum);
                        }
                    }
                }
                (reads, evals)
            },
        )
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    let reads = reads + first_row_reads;
    drop(vis_bands);
    let samples: u64 = lats.iter().map(|l| l.nx as u64 * l.ny as u64).sum();
    Ok(AaFrame {
        width,
        height,
        rgb,
        visible: want_visible.then_some(visible),
        stats: AaStats {
            depth_evals: evals,
            samples_written: samples,
            sample_reads: reads,
            pixels: w as u64 * h as u64,
            ..Default::default()
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bands of rows rasterizing only the lattice rows they read give the image, the
    /// visible triangles and the counters of the whole lattices rasterized at once and
    /// resolved pixel by pixel (written out here), for every pattern, with and without
    /// the centre sample, on even and odd frame sizes.
    #[test]
    fn bands_equal_whole_lattices() {
        use crate::aa::sampler::rasterize;
        let mut ls = crate::scene::load_builtin("default").unwrap();
        for (w, h) in [(61, 37), (64, 48), (33, 1)] {
            ls.scene.width = w;
            ls.scene.height = h;
            let tris = crate::frontend::project(&ls).unwrap().tris;
            for pattern in [Pattern::Corner, Pattern::D3d4x, Pattern::Grid2x2] {
                for centre in [false, true] {
                    let p = CornerParams::new(pattern, centre);
                    let got = render(&tris, w, h, [9, 8, 7], &p).unwrap();
                    let total = check(&p).unwrap();
                    let bufs = rasterize(&tris, &lattices(&p, w, h), [9, 8, 7]);
                    let mut wsum = Vec::new();
                    let mut reads = 0;
                    for j in 0..h {
                        for i in 0..w {
                            let smp = pixel_samples(&p, i, j);
                            let mut acc = [0u64; 3];
                            let mut owners = Vec::new();
                            for &(l, a, b, wt) in &smp {
                                let s = bufs[l].idx(a, b);
                                for (a, &c) in acc.iter_mut().zip(&bufs[l].rgb[s]) {
                                    *a += wt as u64 * c as u64;
                                }
                                owners.push((bufs[l].tri[s], wt));
                            }
                            let c = acc.map(|a| (a / (total * 4096)).min(255) as u8);
                            let t = owner_of(&owners, &mut wsum);
                            let px = (j * w + i) as usize;
                            assert_eq!(got.rgb[3 * px..3 * px + 3], c, "{pattern:?} ({i}, {j})");
                            assert_eq!(got.visible.as_ref().unwrap()[px], t);
                            reads += smp.len() as u64;
                        }
                    }
                    // Every corner sample is read once (the row buffer and the register
                    // supply the other three of a pixel's corners); the other patterns and
                    // the centre sample read each of a pixel's samples.
                    let corners = (w as u64 + 1) * (h as u64 + 1);
                    let centres = if centre { (w * h) as u64 } else { 0 };
                    let want_reads = match pattern {
                        Pattern::Corner => corners + centres,
                        _ => reads,
                    };
                    assert_eq!(got.stats.sample_reads, want_reads, "{pattern:?} {w}x{h}");
                    let evals: u64 = bufs.iter().map(|b| b.depth_evals).sum();
                    let written: u64 = bufs.iter().map(|b| b.z.len() as u64).sum();
                    assert_eq!(got.stats.depth_evals, evals, "{pattern:?} {w}x{h}");
                    assert_eq!(got.stats.samples_written, written);
                    let hidden = render_with(&tris, w, h, [9, 8, 7], &p, false).unwrap();
                    assert_eq!(hidden.rgb, got.rgb);
                    assert_eq!(hidden.stats.depth_evals, evals);
                    assert_eq!(hidden.stats.sample_reads, got.stats.sample_reads);
                }
            }
        }
    }
}
