//! Shadows under anti-aliasing: the array's shadow passes at the method's own samples
//! ([`crate::aa::shadow_samples`]).
//!
//! Each of the method's sample lattices is rendered by the array as a frame of its own
//! (front end through the lattice's [`SampleGrid`], span setup, the shadow volumes' spans,
//! the per-pixel program, shading). Per sample that gives the lit intensity `u` and the
//! shaded one `v` (exact or table shading, [`FactorTable::shade_pixel`]) and the shadowed
//! fraction of the lights. A pixel then takes the method's own colour `C` minus the
//! weighted mean darkening, per channel,
//! `C' = max(0, C − ⌊(Σ_t w_t·(u_t − v_t) + W/2) / W⌋)`,
//! and its shadow AOV is `⌊(Σ_t w_t·level_t + W/2) / W⌋` (the shadowed fraction in the
//! method's weights, 0..=255). All integer; a pixel no sample of which is in shadow keeps
//! exactly the method's colour.

use super::{ArrayCtx, RenderError};
use crate::aa::shadow_samples::{grid_of, ShadowTaps};
use crate::frontend::{self, Projector, SampleGrid};
use crate::plan::AaMethod;
use crate::render::SpanSource;
use crate::shadow::FactorTable;
use pixelproc_formats::{unpack_rgb, Z_FAR};
use rayon::prelude::*;

/// What the sample passes produce.
pub(super) struct SampledShadow {
    /// The shadowed fraction per pixel, 0..=255 (the shadow AOV under anti-aliasing).
    pub fraction: Vec<u8>,
    /// Sample lattices rendered (one array frame each).
    pub passes: usize,
}

/// What every sample pass renders with: the array's inputs and the frame's shading table.
pub(super) struct PassInput<'a> {
    /// The scene, effects, plan, lights and background.
    pub ctx: ArrayCtx<'a>,
    /// The shading table of the frame.
    pub table: &'a FactorTable,
}

/// One rendered lattice: per sample, the darkening `u − v` per channel and the shadow
/// level.
fn lattice_pass(inp: &PassInput, pj: &Projector) -> Result<Vec<[u8; 4]>, RenderError> {
    let (ls, fx, table) = (inp.ctx.ls, inp.ctx.fx, inp.table);
    let (w, h) = pj.raster_size();
    let projected = frontend::project_3d_with(ls, pj, fx.shade_channels())?;
    let src = SpanSource::new(&projected.array_tris(), w, h)?;
    // The pass's own stage times are not reported: the sample stage is timed as a whole.
    let (frame, _) = inp.ctx.draw(&src, Some(pj), None, &mut Vec::new())?;
    let stride = if frame.more.is_empty() {
        0
    } else {
        crate::pixel_array::MORE_SHADE
    };
    Ok(frame
        .px
        .par_iter()
        .enumerate()
        .map(|(k, s)| {
            if s.zb == Z_FAR {
                return [0; 4];
            }
            let more = &frame.more[k * stride..(k + 1) * stride];
            let (u, v) = (
                unpack_rgb(s.rgb),
                unpack_rgb(table.shade_pixel(s.rgb, s, more)),
            );
            [
                u[0].saturating_sub(v[0]),
                u[1].saturating_sub(v[1]),
                u[2].saturating_sub(v[2]),
                table.shadow_level(s),
            ]
        })
        .collect())
}

/// Renders `method`'s shadow samples and darkens its image `rgb` (RGB8, `width × height`)
/// by them; `None` if the method samples shadows once per pixel (see
/// [`ShadowTaps::for_method`]).
pub(super) fn sample_shadows(
    inp: &PassInput,
    method: &AaMethod,
    rgb: &mut [u8],
) -> Result<Option<SampledShadow>, RenderError> {
    let ls = inp.ctx.ls;
    let (w, h) = (ls.scene.width, ls.scene.height);
    let Some(taps) = ShadowTaps::for_method(method, w, h) else {
        return Ok(None);
    };
    let base = Projector::new(ls);
    // Per pixel: summed weighted darkening (RGB) and level.
    let mut acc = vec![[0u64; 4]; (w * h) as usize];
    for (li, lat) in taps.lattices.iter().enumerate() {
        let grid: SampleGrid = grid_of(lat);
        let samples = lattice_pass(inp, &base.for_grid(grid))?;
        for b in 0..lat.ny {
            for x in 0..lat.nx {
                let s = samples[(b * lat.nx + x) as usize];
                if s == [0; 4] {
                    continue;
                }
                taps.scatter(li, x, b, |i, j, wt| {
                    let p = &mut acc[(j * w + i) as usize];
                    for c in 0..4 {
                        p[c] += wt as u64 * s[c] as u64;
                    }
                });
            }
        }
    }
    let total = taps.total as u64;
    let round = |v: u64| ((v + total / 2) / total) as u8;
    let fraction: Vec<u8> = acc.iter().map(|p| round(p[3])).collect();
    rgb.par_chunks_mut(3)
        .zip(acc.par_iter())
        .for_each(|(c, p)| {
            for k in 0..3 {
                c[k] = c[k].saturating_sub(round(p[k]));
            }
        });
    Ok(Some(SampledShadow {
        fraction,
        passes: taps.lattices.len(),
    }))
}
