//! `k × k` ordered supersampling with a box resolve (comparison method).
//!
//! Samples at `((i + (2a+1)/(2k)), (j + (2b+1)/(2k)))`, `a, b < k`, on one lattice of
//! `(W·k) × (H·k)` points ([`super::sampler`]: exact coverage with the top-left rule,
//! scene-order z-buffer). The resolve sums the `k²` Q8.12 intensities of a pixel and
//! truncates once: `C = ⌊Σ I / (k²·2^12)⌋` (the +2048 rounding offset is already in every
//! Q8.12 intensity, `docs/formats.md`, so this is a rounding of the true mean). The visible triangle of a pixel is
//! the one owning most of its samples (lowest index on a tie, background −1 first).

use super::sampler::{prepare_all, Lattice, LatticeRaster};
use super::{AaError, AaFrame, AaStats};
use crate::setup::SnappedTri;
use rayon::prelude::*;

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

/// The frame's sample lattice: sample row `b` of pixel row `j = b / k` at
/// `y = (2b + 1)/(2k)`, sample `a` at `x = (2a + 1)/(2k)`.
fn lattice(width: u32, height: u32, k: u32) -> Lattice {
    Lattice {
        nx: width * k,
        ny: height * k,
        sx: 2,
        sy: 2,
        ox: 1,
        oy: 1,
        den: 2 * k as i64,
    }
}

/// [`render`]; with `visible` false the visible-triangle AOV is not computed
/// ([`AaFrame::visible`] is `None`), the image and counters are the same.
///
/// Pixel rows run in parallel, each rasterizing its `k` sample rows into a buffer of its
/// thread ([`LatticeRaster::row`]: every sample is independent, so this is the whole
/// lattice's result) and resolving them at once: memory is `k² · W` samples per thread,
/// not the frame's lattice.
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
    let want_visible = visible;
    let (w, h) = (width as usize, height as usize);
    let st = prepare_all(tris);
    let lr = LatticeRaster::new(&st, &lattice(width, height, k), bg);
    let nx = w * k as usize;
    let band = nx * k as usize;
    let mut rgb = vec![0u8; w * h * 3];
    let mut visible = if want_visible {
        vec![-1i32; w * h]
    } else {
        Vec::new()
    };
    let mut vis_rows = crate::render::chunks_or_empty(&mut visible, w, h);
    let evals: u64 = rgb
        .par_chunks_mut(3 * w)
        .zip(vis_rows.par_iter_mut())
        .enumerate()
        .map_init(
            || Rows {
                z: vec![0; band],
                rgb: vec![[0; 3]; band],
                tri: vec![0; band],
                counts: Vec::new(),
                acc: Vec::new(),
            },
            |buf, (j, (rgb_row, vis_row))| {
                let mut evals = 0;
                for b in 0..k as usize {
                    let r = b * nx..(b + 1) * nx;
                    evals += lr.row(
                        j as u32 * k + b as u32,
                        &mut buf.z[r.clone()],
                        &mut buf.rgb[r.clone()],
                        &mut buf.tri[r],
                    );
                }
                buf.resolve(k as usize, rgb_row, want_visible.then_some(&mut **vis_row));
                evals
            },
        )
        .sum();
    drop(vis_rows);
    let samples = (w * h) as u64 * (k * k) as u64;
    Ok(AaFrame {
        width,
        height,
        rgb,
        visible: want_visible.then_some(visible),
        stats: AaStats {
            depth_evals: evals,
            samples_written: samples,
            sample_reads: samples,
            pixels: (w * h) as u64,
            ..Default::default()
        },
    })
}

/// The `k` sample rows of one pixel row (a thread's buffer) and the resolve's scratch.
struct Rows {
    z: Vec<i64>,
    rgb: Vec<[u32; 3]>,
    tri: Vec<i32>,
    counts: Vec<(i32, u32)>,
    /// Per pixel of the row, the sums of its samples' Q8.12 colours.
    acc: Vec<[u64; 3]>,
}

impl Rows {
    /// Box resolve of the pixel row: every pixel's `k²` samples summed and truncated
    /// once; the visible triangle is the one owning most samples (lowest index on a tie).
    fn resolve(&mut self, k: usize, rgb: &mut [u8], visible: Option<&mut [i32]>) {
        let w = rgb.len() / 3;
        let nx = w * k;
        let n = (k * k) as u64;
        // Sample row by sample row, each pixel's `k` samples added to its sums.
        let acc = &mut self.acc;
        acc.clear();
        acc.resize(w, [0; 3]);
        for row in self.rgb[..k * nx].chunks_exact(nx) {
            for (a, px) in acc.iter_mut().zip(row.chunks_exact(k)) {
                for c in px {
                    for ch in 0..3 {
                        a[ch] += c[ch] as u64;
                    }
                }
            }
        }
        fn put(acc: &[[u64; 3]], rgb: &mut [u8], norm: impl Fn(u64) -> u64) {
            for (out, a) in rgb.chunks_exact_mut(3).zip(acc) {
                for ch in 0..3 {
                    out[ch] = norm(a[ch]).min(255) as u8;
                }
            }
        }
        // `⌊Σ / (k²·2^12)⌋`: a shift when k² is a power of two (`⌊⌊Σ / 2^12⌋ / k²⌋`
        // is the same quotient), else a division; chosen once per row.
        if n.is_power_of_two() {
            let sh = 12 + n.trailing_zeros();
            put(acc, rgb, |a| a >> sh);
        } else {
            let d = n * 4096;
            put(acc, rgb, |a| a / d);
        }
        let Some(visible) = visible else {
            return;
        };
        let counts = &mut self.counts;
        for (i, v) in visible.iter_mut().enumerate() {
            counts.clear();
            for b in 0..k {
                let s0 = b * nx + i * k;
                for &t in &self.tri[s0..s0 + k] {
                    match counts.iter_mut().find(|c| c.0 == t) {
                        Some(c) => c.1 += 1,
                        None => counts.push((t, 1)),
                    }
                }
            }
            counts.sort_by_key(|c| (std::cmp::Reverse(c.1), c.0));
            *v = counts[0].0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::sampler::rasterize;

    /// Streaming pixel rows through per-thread buffers gives what the whole lattice
    /// rasterized at once and box-resolved gives (written out here), for several `k`.
    #[test]
    fn row_streaming_equals_the_whole_lattice() {
        let ls = crate::scene::load_builtin("default").unwrap();
        let p = crate::frontend::project(&ls).unwrap();
        let (w, h) = (ls.scene.width, ls.scene.height);
        let bg = [10, 20, 30];
        for k in [1, 2, 3] {
            let got = render(&p.tris, w, h, bg, k).unwrap();
            let buf = rasterize(&p.tris, &[lattice(w, h, k)], bg).pop().unwrap();
            let (w, k) = (w as usize, k as usize);
            for j in 0..h as usize {
                for i in 0..w {
                    let mut acc = [0u64; 3];
                    let mut owners = std::collections::BTreeMap::new();
                    for b in 0..k {
                        for a in 0..k {
                            let s = buf.idx((i * k + a) as u32, (j * k + b) as u32);
                            for (sum, &v) in acc.iter_mut().zip(&buf.rgb[s]) {
                                *sum += v as u64;
                            }
                            *owners.entry(buf.tri[s]).or_insert(0) += 1;
                        }
                    }
                    let want: Vec<u8> = acc
                        .iter()
                        .map(|&a| (a / (k * k * 4096) as u64).min(255) as u8)
                        .collect();
                    let px = j * w + i;
                    assert_eq!(got.rgb[3 * px..3 * px + 3], want[..], "k {k} ({i}, {j})");
                    let most = owners.values().max().unwrap();
                    let vis = owners.iter().find(|e| e.1 == most).unwrap().0;
                    assert_eq!(got.visible.as_ref().unwrap()[px], *vis);
                }
            }
            assert_eq!(got.stats.depth_evals, buf.depth_evals);
            assert_eq!(got.stats.samples_written, buf.z.len() as u64);
        }
    }
}
