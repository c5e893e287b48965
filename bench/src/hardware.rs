//! The hardware side of the trade-off: every setting's cycles per frame on the modelled
//! hardware ([`pixelproc_sim::hwcost`]) at 1920×1080, for one configuration (array width
//! and clock, [`HwConfig`]).
//!
//! Each scene of the set is scaled to 1920×1080 (x by 1920/W, y by 1080/H,
//! [`pixelproc_sim::hwcost::rescale`]): the same triangles drawn at the display size. A
//! setting's cycles per frame are the mean over the scenes (each scene's count is exact
//! for the model, see the method modules for what is exact and what is stated).

use pixelproc_sim::aa::AaMethod;
use pixelproc_sim::abuffer::AbufferParams;
use pixelproc_sim::hwcost::{method_cost, rescale, Frame, HwConfig, HwCost, Resources};

use crate::scenes::TestScene;
use crate::settings::Setting;
use crate::TradeoffError;

/// The display size the hardware figures are given for.
pub const HW_WIDTH: u32 = 1920;
/// See [`HW_WIDTH`].
pub const HW_HEIGHT: u32 = 1080;

/// One setting's hardware figures.
#[derive(Clone, Debug, PartialEq)]
pub struct HwRow {
    /// Per scene (sweep order): the model's cost at 1920×1080.
    pub scenes: Vec<HwCost>,
}

impl HwRow {
    /// Mean cycles per frame over the scenes, rounded.
    pub fn cycles(&self) -> u64 {
        let n = self.scenes.len().max(1) as u64;
        (self.scenes.iter().map(|c| c.cycles).sum::<u64>() + n / 2) / n
    }
    /// LUT4/FF of the blocks with RTL (the same for every scene).
    pub fn resources(&self) -> Option<Resources> {
        self.scenes.first().and_then(|c| c.resources)
    }
    /// Passes of the array per pixel row.
    pub fn passes_per_row(&self) -> f64 {
        self.scenes
            .first()
            .map_or(0.0, |c| c.passes_per_row_milli as f64 / 1000.0)
    }
    /// Extra on-chip memory, bits (the largest over the scenes).
    pub fn extra_memory_bits(&self) -> u64 {
        self.scenes
            .iter()
            .map(|c| c.extra_memory_bits)
            .max()
            .unwrap_or(0)
    }
}

/// Every setting's hardware figures under one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct HwSweep {
    /// The configuration.
    pub config: HwConfig,
    /// One row per setting, in sweep order.
    pub rows: Vec<HwRow>,
}

impl HwSweep {
    /// Milliseconds per frame of row `k`.
    pub fn ms(&self, k: usize) -> f64 {
        self.config.ms(self.rows[k].cycles())
    }
    /// Frames per second of row `k`.
    pub fn fps(&self, k: usize) -> f64 {
        self.config.fps(self.rows[k].cycles())
    }
}

/// The method as costed on a scene: the A-buffer takes `interpenetrating` from the scene
/// (as the sweep renders it).
fn with_scene(aa: &AaMethod, sc: &TestScene) -> AaMethod {
    match aa {
        AaMethod::Abuffer(p) => AaMethod::Abuffer(AbufferParams {
            interpenetrating: sc.interpenetrating,
            compare_variants: false,
            ..*p
        }),
        m => m.clone(),
    }
}

/// Costs every setting on every scene, scaled to 1920×1080, under `config`.
pub fn hardware_sweep(
    scenes: &[TestScene],
    settings: &[Setting],
    config: &HwConfig,
) -> Result<HwSweep, TradeoffError> {
    let scaled: Vec<(Vec<_>, u32, u32)> = scenes
        .iter()
        .map(|s| {
            (
                rescale(&s.tris, s.width, s.height, HW_WIDTH, HW_HEIGHT),
                HW_WIDTH,
                HW_HEIGHT,
            )
        })
        .collect();
    sweep_frames(scenes, &scaled, settings, config)
}

/// Costs every setting on every scene at the scene's own size (no scaling: the 1080p
/// scene is costed as drawn), under `config`.
pub fn hardware_sweep_native(
    scenes: &[TestScene],
    settings: &[Setting],
    config: &HwConfig,
) -> Result<HwSweep, TradeoffError> {
    let frames: Vec<(Vec<_>, u32, u32)> = scenes
        .iter()
        .map(|s| (s.tris.clone(), s.width, s.height))
        .collect();
    sweep_frames(scenes, &frames, settings, config)
}

/// The method of setting `st` as costed on scene `sc` (see [`hardware_sweep`]).
pub(crate) fn costed_method(st: &Setting, sc: &TestScene) -> AaMethod {
    with_scene(&st.aa, sc)
}

/// Costs every setting on each scene's frame (triangles, width, height).
fn sweep_frames(
    scenes: &[TestScene],
    frames: &[(Vec<pixelproc_sim::setup::SnappedTri>, u32, u32)],
    settings: &[Setting],
    config: &HwConfig,
) -> Result<HwSweep, TradeoffError> {
    let mut rows = Vec::with_capacity(settings.len());
    for st in settings {
        let mut costs = Vec::with_capacity(scenes.len());
        for (sc, (tris, w, h)) in scenes.iter().zip(frames) {
            let frame = Frame {
                tris,
                width: *w,
                height: *h,
            };
            let c = method_cost(&with_scene(&st.aa, sc), &frame, config).map_err(|e| {
                TradeoffError::Option(format!(
                    "hardware model of {} {} on {}: {e}",
                    st.method, st.setting, sc.name
                ))
            })?;
            costs.push(c);
        }
        rows.push(HwRow { scenes: costs });
    }
    Ok(HwSweep {
        config: *config,
        rows,
    })
}
