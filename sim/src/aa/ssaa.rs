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

/// Renders with `k × k` supersampling, `1 ≤ k ≤ 64`.
#[allow(clippy::needless_range_loop)]
pub fn render(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    k: u32,
) -> Result<AaFrame, AaError> {
    if !(1..=64).contains(&k) {
        return Err(AaError::Param(format!("ssaa k = {k} must be in 1..=64")));
    }
    let lat = Lattice {
        nx: width * k,
        ny: height * k,
        sx: 2,
        sy: 2,
        ox: 1,
        oy: 1,
        den: 2 * k as i64,
    };
    let buf = rasterize(tris, &[lat], bg).pop().expect("one lattice");
    let (w, h, k) = (width as usize, height as usize, k as usize);
    let mut rgb = vec![0u8; w * h * 3];
    let mut visible = vec![-1i32; w * h];
    let n = (k * k) as u64;
    let mut counts: Vec<(i32, u32)> = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let mut acc = [0u64; 3];
            counts.clear();
            for b in 0..k {
                for a in 0..k {
                    let s = buf.idx((i * k + a) as u32, (j * k + b) as u32);
                    for ch in 0..3 {
                        acc[ch] += buf.rgb[s][ch] as u64;
                    }
                    let t = buf.tri[s];
                    match counts.iter_mut().find(|c| c.0 == t) {
                        Some(c) => c.1 += 1,
                        None => counts.push((t, 1)),
                    }
                }
            }
            for ch in 0..3 {
                rgb[3 * (j * w + i) + ch] = (acc[ch] / (n * 4096)).min(255) as u8;
            }
            counts.sort_by_key(|c| (std::cmp::Reverse(c.1), c.0));
            visible[j * w + i] = counts[0].0;
        }
    }
    Ok(AaFrame {
        width,
        height,
        rgb,
        visible: Some(visible),
        stats: AaStats {
            depth_evals: buf.depth_evals,
            samples_written: buf.z.len() as u64,
            sample_reads: buf.z.len() as u64,
            ..Default::default()
        },
    })
}
