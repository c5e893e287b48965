//! Stimulus of the mask search checks (seed 000): every 4×4 mask, random masks, and the
//! fragments of a scene's multi-fragment pixels.

use super::SearchJob;
use crate::TbError;
use pixelproc_formats::abuffer::{Corner, FragPlane, MaskSize, PLANE_MAX};
use pixelproc_sim::abuffer::multi_fragment_pixels;
use pixelproc_sim::rng::XorShift64Star;

/// A plane field: the extremes, small values, zero and the full range.
fn plane_field(rng: &mut XorShift64Star) -> i64 {
    let r = rng.next_u64();
    match r % 8 {
        0 => PLANE_MAX,
        1 => -PLANE_MAX,
        2 => (r >> 8) as i64 % 4096 - 2048,
        3 => 0,
        _ => ((r >> 16) as i64 % PLANE_MAX) * if r & 0x100 != 0 { -1 } else { 1 },
    }
}

/// A random plane.
fn plane(rng: &mut XorShift64Star) -> FragPlane {
    FragPlane {
        zc: plane_field(rng),
        sx: plane_field(rng),
        sy: plane_field(rng),
    }
}

/// Every 4×4 mask × 4 corners, with a pseudo-random plane per job.
pub fn exhaustive_jobs() -> Vec<SearchJob> {
    let mut rng = XorShift64Star(0x9E37_79B9_7F4A_7C15);
    let mut v = Vec::with_capacity(4 << 16);
    for mask in 0..=0xFFFFu64 {
        for corner in Corner::ALL {
            v.push(SearchJob {
                mask,
                corner,
                plane: plane(&mut rng),
            });
        }
    }
    v
}

/// Random jobs for `size`: a third uniform masks, a third sparse (1–3 bits), a third
/// half-plane masks (edge pixels), random corners and planes.
pub fn random_jobs(size: MaskSize, count: usize, seed: u64) -> Vec<SearchJob> {
    let mut rng = XorShift64Star(seed | 1);
    let full = size.full();
    (0..count)
        .map(|k| {
            let r = rng.next_u64();
            let mask = match k % 3 {
                0 => r & full,
                1 => {
                    (0..1 + r % 3).fold(0u64, |a, _| a | 1 << (rng.next_u64() % size.bits() as u64))
                }
                _ => {
                    // Subpixels on one side of a random line through the pixel.
                    let (a, b, c) = (
                        (rng.next_u64() % 33) as i64 - 16,
                        (rng.next_u64() % 33) as i64 - 16,
                        (rng.next_u64() % 65) as i64 - 32,
                    );
                    let mut m = 0u64;
                    for b_ in 0..size.bits() {
                        let (col, row) = size.col_row(b_);
                        let o = size.offset(col, row);
                        if a * o.dx as i64 + b * o.dy as i64 + c > 0 {
                            m |= 1 << b_;
                        }
                    }
                    m
                }
            };
            SearchJob {
                mask,
                corner: Corner::from_code((r >> 60) as u8),
                plane: plane(&mut rng),
            }
        })
        .collect()
}

/// The fragments at the multi-fragment pixels of built-in scene `name` (golden front end,
/// golden fraction masks and planes, as the A-buffer renderer builds them): each gives a
/// min search from `Corner::of_min(sx, sy)` and a max search from the opposite corner.
pub fn scene_jobs(name: &str, size: MaskSize) -> Result<Vec<SearchJob>, TbError> {
    let ls = pixelproc_sim::scene::load_builtin(name).map_err(|e| TbError::Sim(e.to_string()))?;
    loaded_scene_jobs(&ls, size)
}

/// As [`scene_jobs`], for a scene already loaded (a file or a built-in).
pub fn loaded_scene_jobs(
    ls: &pixelproc_sim::scene::LoadedScene,
    size: MaskSize,
) -> Result<Vec<SearchJob>, TbError> {
    let err = |e: String| TbError::Sim(e);
    let proj = pixelproc_sim::frontend::project(ls).map_err(|e| err(e.to_string()))?;
    let (w, h) = (ls.scene.width, ls.scene.height);
    let pixels = multi_fragment_pixels(&proj.tris, w, h, size).map_err(|e| err(e.to_string()))?;
    let mut jobs = Vec::new();
    for f in pixels.iter().flat_map(|p| &p.fragments) {
        let c = Corner::of_min(f.plane.sx, f.plane.sy);
        for corner in [c, c.opposite()] {
            jobs.push(SearchJob {
                mask: f.mask,
                corner,
                plane: f.plane,
            });
        }
    }
    Ok(jobs)
}
