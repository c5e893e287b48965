//! The 1080p scene of the trade-off ([`crate::scenes::city_1080p`]), swept apart from the
//! 160×160 set, and what 60 frames per second at 1080p costs in array width and clock for
//! each setting.
//!
//! The scene is judged like the set (every setting against the exact reference of its
//! filter) but timed with [`HD_TIMED_RUNS`] run per setting: a frame takes 0.3–20 s of CPU
//! at this size. Its hardware cost is the cycle model on the scene as drawn, 1920×1080,
//! with no scaling ([`crate::hardware::hardware_sweep_native`]). The 60 frames/s table
//! turns each setting's model around ([`pixelproc_sim::hwcost::target`]): the clock it
//! needs at the configured array width, the clock it needs at the widest useful array,
//! and the smallest array width that reaches 60 frames/s at the configured clock.

use pixelproc_sim::hwcost::target::{clock_for_fps, min_width_for_fps, widest_useful, WidthFor};
use pixelproc_sim::hwcost::{Frame, HwConfig};

use crate::hardware::{costed_method, hardware_sweep_native};
use crate::scenes::{city_scene, TestScene};
use crate::settings::Setting;
use crate::sweep::{run_sweep_heat, Sweep, SweepOptions};
use crate::TradeoffError;

/// Timed runs per setting on the 1080p scene (the set uses `--runs`).
pub const HD_TIMED_RUNS: usize = 1;

/// The frame rate of the cost table.
pub const TARGET_FPS: f64 = 60.0;

/// What [`TARGET_FPS`] costs one setting on the 1080p scene.
#[derive(Clone, Debug, PartialEq)]
pub struct FpsRow {
    /// Cycles per frame at the configured array width.
    pub cycles: u64,
    /// Samples (pixels, sample points, fragments) the method processes per frame, at one
    /// per clock in its busiest stage: the readout for the array methods.
    pub samples: u64,
    /// The clock for [`TARGET_FPS`] at the configured width, MHz.
    pub clock_mhz: f64,
    /// Cycles per frame at the widest useful array ([`widest_useful`]).
    pub floor_cycles: u64,
    /// The clock for [`TARGET_FPS`] at the widest useful array, MHz: no width does it
    /// with less.
    pub floor_clock_mhz: f64,
    /// The smallest width reaching [`TARGET_FPS`] at the configured clock.
    pub width: WidthFor,
}

/// The 1080p part of the trade-off.
#[derive(Clone, Debug)]
pub struct HdResult {
    /// The scene swept alone (its `hardware` is the cost as drawn).
    pub sweep: Sweep,
    /// Per setting (sweep order): the cost of [`TARGET_FPS`].
    pub fps: Vec<FpsRow>,
    /// The widest useful array on this scene.
    pub widest: u32,
}

/// Sweeps the city scene (1920×1080; 192×108 for the quick set) with `settings`, costs it
/// under `hw` and tabulates what [`TARGET_FPS`] costs.
pub fn run_hd(
    quick: bool,
    settings: &[Setting],
    progress: bool,
    hw: &HwConfig,
) -> Result<HdResult, TradeoffError> {
    let scene = city_scene(quick);
    let scenes = std::slice::from_ref(&scene);
    let mut sweep = run_sweep_heat(
        scenes,
        settings,
        &SweepOptions {
            runs: HD_TIMED_RUNS,
            progress,
        },
        None,
        false,
    )?;
    let hws = hardware_sweep_native(scenes, settings, hw)?;
    let fps = fps_table(&scene, settings, &hws, hw)?;
    sweep.hardware = Some(hws);
    Ok(HdResult {
        sweep,
        fps,
        widest: widest_useful(&frame_of(&scene)),
    })
}

fn frame_of(sc: &TestScene) -> Frame<'_> {
    Frame {
        tris: &sc.tris,
        width: sc.width,
        height: sc.height,
    }
}

/// The cost of [`TARGET_FPS`] for every setting on `sc`, given its costs `hws` under `hw`.
fn fps_table(
    sc: &TestScene,
    settings: &[Setting],
    hws: &crate::hardware::HwSweep,
    hw: &HwConfig,
) -> Result<Vec<FpsRow>, TradeoffError> {
    let frame = frame_of(sc);
    settings
        .iter()
        .zip(&hws.rows)
        .map(|(st, row)| {
            let err = |e| {
                TradeoffError::Option(format!(
                    "60 frames/s model of {} {} on {}: {e}",
                    st.method, st.setting, sc.name
                ))
            };
            let m = costed_method(st, sc);
            let width = min_width_for_fps(&m, &frame, hw.clock_mhz, TARGET_FPS).map_err(err)?;
            let floor_cycles = match width {
                WidthFor::NotReachable { floor_cycles } => floor_cycles,
                WidthFor::Width { .. } => {
                    let wide =
                        HwConfig::new(widest_useful(&frame) as u64, hw.clock_mhz).map_err(err)?;
                    pixelproc_sim::hwcost::method_cost(&m, &frame, &wide)
                        .map_err(err)?
                        .cycles
                }
            };
            let cycles = row.cycles();
            Ok(FpsRow {
                cycles,
                samples: row.scenes.first().map_or(0, |c| c.samples),
                clock_mhz: clock_for_fps(cycles, TARGET_FPS),
                floor_cycles,
                floor_clock_mhz: clock_for_fps(floor_cycles, TARGET_FPS),
                width,
            })
        })
        .collect()
}
