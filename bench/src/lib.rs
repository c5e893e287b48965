//! The accuracy/time trade-off sweep behind `pixelproc tradeoff` (see `docs/accuracy.md`).
//!
//! Every anti-aliasing method of [`pixelproc_sim::aa`] with every setting of the sweep
//! ([`sweep_settings`]) renders every scene of a set ([`builtin_scenes`], or a folder of
//! scene files, [`load_scene_dir`]). Each image is judged against the exact reference of
//! its own filter from [`pixelproc_sim::reference`] ([`reference_filter`], [`judge()`]):
//! box-filtered for most methods, the seed-002 Gaussian or cone for multi-scanning with
//! those filters: RMSE and maximum error on the 0..255 scale, and the pixels whose visible
//! surface (the triangle with the largest visible area) differs from the reference's. Cost is the median time of `runs` renders on
//! **one thread** ([`timing`]), the depth evaluations and sample-memory reads per pixel the
//! methods count themselves, and the shade levels a long near-horizontal / near-vertical
//! edge gets ([`pixelproc_sim::aa::edge_shade_levels`]).
//!
//! The built-in set adds a 1080p scene drawn at its true size, swept apart, with what 60
//! frames per second costs in array width and clock ([`hd`]).
//!
//! Outputs ([`write_outputs`]): a CSV per setting, a CSV per setting and scene, a
//! Markdown report ([`report`]), the 1080p scene's CSV, PNG charts of error against time with the Pareto frontier
//! marked (the model's CPU time, and the modelled hardware's time at 1920×1080,
//! [`hardware`]), and a montage of difference heat maps for one scene ([`mod@chart`]).
//!
//! This crate measures the golden model; the model itself (`pixelproc-sim`) does not
//! depend on it.

#![warn(missing_docs)]

pub mod chart;
pub mod hardware;
pub mod hd;
pub mod judge;
pub mod methods;
pub mod report;
pub mod scenes;
pub mod settings;
pub mod shadow_sweep;
pub mod sweep;
pub mod timing;

use std::path::{Path, PathBuf};

use pixelproc_sim::aa::AaError;
use thiserror::Error;

pub use chart::{chart, chart_hw, heat_montage};
pub use hardware::{hardware_sweep, HwRow, HwSweep};
pub use judge::{judge, pareto_frontier, reference_filter, Judgement};
pub use pixelproc_sim::hwcost::HwConfig;
pub use report::{
    csv, hd_csv, markdown, scenes_csv, write_outputs, Written, CSV_HEADER, HD_CSV_HEADER,
};
pub use scenes::{builtin_scenes, load_scene_dir, TestScene};
pub use settings::{sweep_settings, Setting};
pub use sweep::{
    run_sweep, HeatData, Row, SceneInfo, SceneResult, Sweep, SweepOptions, VariantRow,
};

/// Errors of the trade-off sweep.
#[derive(Debug, Error)]
pub enum TradeoffError {
    /// Reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The output files could not be written (nothing was replaced).
    #[error("{0}")]
    Output(String),
    /// A scene file could not be loaded.
    #[error(transparent)]
    Scene(#[from] pixelproc_sim::scene::SceneError),
    /// A scene could not be projected.
    #[error("{0}: {1}")]
    Front(String, pixelproc_sim::frontend::FrontError),
    /// A method failed on a scene.
    #[error("{method} on {scene}: {source}")]
    Render {
        /// Setting label.
        method: String,
        /// Scene name.
        scene: String,
        /// Cause.
        source: AaError,
    },
    /// The scene folder holds no scene.
    #[error("no scene files (*.json) in {0}")]
    NoScenes(String),
    /// A bad option.
    #[error("{0}")]
    Option(String),
    /// Drawing the chart or the heat maps failed.
    #[error("drawing {0}")]
    Plot(String),
}

/// Maps an I/O error on `path` to [`TradeoffError::Io`].
pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> TradeoffError + '_ {
    move |source| TradeoffError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Options of [`run_tradeoff`] (the `pixelproc tradeoff` command).
#[derive(Clone, Debug)]
pub struct TradeoffOptions {
    /// A folder of scene files instead of the built-in set.
    pub scenes_dir: Option<PathBuf>,
    /// Output folder.
    pub out_dir: PathBuf,
    /// Timed runs per setting and scene.
    pub runs: usize,
    /// The small subset (tests, CI).
    pub quick: bool,
    /// Progress bar on stderr.
    pub progress: bool,
    /// The command line, recorded in the report.
    pub command: String,
}

/// Runs the sweep and writes every output, with the hardware figures for the default
/// configuration ([`HwConfig::DEFAULT`]). Returns the result and the files written.
pub fn run_tradeoff(o: &TradeoffOptions) -> Result<(Sweep, Written), TradeoffError> {
    run_tradeoff_with(o, &HwConfig::DEFAULT)
}

/// [`run_tradeoff`] with the hardware figures for `hw` (array width and clock).
pub fn run_tradeoff_with(
    o: &TradeoffOptions,
    hw: &HwConfig,
) -> Result<(Sweep, Written), TradeoffError> {
    let scenes = match &o.scenes_dir {
        Some(d) => load_scene_dir(d)?,
        None => builtin_scenes(o.quick),
    };
    let settings = sweep_settings(o.quick);
    let mut sw = run_sweep(
        &scenes,
        &settings,
        &SweepOptions {
            runs: o.runs,
            progress: o.progress,
        },
        None,
    )?;
    sw.hardware = Some(hardware_sweep(&scenes, &settings, hw)?);
    if o.scenes_dir.is_none() {
        // The built-in set also sweeps the 1080p scene at its own size (`hd`).
        sw.hd = Some(Box::new(hd::run_hd(o.quick, &settings, o.progress, hw)?));
    }
    let w = write_outputs(&sw, &o.out_dir, &o.command)?;
    if o.scenes_dir.is_none() {
        // The built-in set also measures shadow boundaries on 3-D scenes with real shadow
        // volumes, against a ray cast (`shadows.md`, `shadows.csv`).
        let sc = shadow_sweep::shadow_scenes(o.quick);
        let rows = shadow_sweep::run_shadow_sweep(
            &sc,
            &shadow_sweep::shadow_settings(o.quick),
            o.runs,
            o.progress,
        )?;
        shadow_sweep::write_shadow_outputs(&rows, &sc, &o.out_dir)?;
    }
    Ok((sw, w))
}
