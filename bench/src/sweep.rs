//! The sweep: every setting on every scene, judged against the exact reference and timed on
//! one thread, plus the A-buffer depth-variant comparison (see `docs/accuracy.md` and
//! `docs/abuffer.md`).
//!
//! Untimed work (reference images, the accuracy render, the A-buffer variant comparison)
//! uses the global rayon pool; its results do not depend on the thread count.

use pixelproc_formats::abuffer::MaskSize;
use pixelproc_sim::aa::{edge_shade_levels, render_aa, AaError, AaMethod};
use pixelproc_sim::abuffer::{render_abuffer, AbufferError, AbufferParams};
use pixelproc_sim::mask_search::DepthSelect;
use pixelproc_sim::reference::{filtered_reference_image, reference_image, RefFilter, RefImage};

use crate::judge::{judge, reference_filter};
use crate::scenes::TestScene;
use crate::settings::Setting;
use crate::timing::{one_thread_pool, time_setting};
use crate::TradeoffError;

/// Measurements of one setting on one scene.
#[derive(Clone, Debug)]
pub struct SceneResult {
    /// Scene name.
    pub scene: String,
    /// Median CPU time of one frame on one thread, seconds (the rendering thread's own
    /// CPU clock: insensitive to other processes on the machine; wall clock where the
    /// platform has no thread clock).
    pub seconds: f64,
    /// Median wall-clock time of the same runs, seconds.
    pub wall_seconds: f64,
    /// Depth evaluations.
    pub depth_evals: u64,
    /// Sample-memory reads of the resolve.
    pub sample_reads: u64,
    /// Pixels.
    pub pixels: u64,
    /// Sum of squared channel errors against the reference.
    pub sq_err: f64,
    /// Largest channel error.
    pub max_err: f64,
    /// Pixels whose visible surface differs from the reference's dominant surface.
    pub wrong_visible: u64,
    /// Of those, pixels where the reference's dominant surface covers at least 3/4 of the
    /// pixel (a clear majority: not a near-tie at an edge).
    pub wrong_visible_clear: u64,
}

impl SceneResult {
    /// RMSE over all channels of all pixels.
    pub fn rmse(&self) -> f64 {
        (self.sq_err / (3 * self.pixels).max(1) as f64).sqrt()
    }
}

/// One row of the result: a setting with its per-scene results and totals.
#[derive(Clone, Debug)]
pub struct Row {
    /// The setting.
    pub setting: Setting,
    /// Per scene, in scene order.
    pub scenes: Vec<SceneResult>,
    /// Shade levels on a near-horizontal and a near-vertical edge.
    pub shade_levels: (usize, usize),
}

impl Row {
    /// Sum of `f` over the row's scenes.
    pub(crate) fn sum<T: std::iter::Sum<T>>(&self, f: impl Fn(&SceneResult) -> T) -> T {
        self.scenes.iter().map(f).sum()
    }
    /// Mean over scenes of the per-scene median frame time (thread CPU time),
    /// milliseconds.
    pub fn ms_per_frame(&self) -> f64 {
        1e3 * self.sum(|s| s.seconds) / self.scenes.len().max(1) as f64
    }
    /// The same for wall-clock time.
    pub fn wall_ms_per_frame(&self) -> f64 {
        1e3 * self.sum(|s| s.wall_seconds) / self.scenes.len().max(1) as f64
    }
    /// Depth evaluations per pixel over the whole set.
    pub fn evals_per_pixel(&self) -> f64 {
        self.sum(|s| s.depth_evals) as f64 / self.sum(|s| s.pixels).max(1) as f64
    }
    /// Sample-memory reads per pixel over the whole set.
    pub fn reads_per_pixel(&self) -> f64 {
        self.sum(|s| s.sample_reads) as f64 / self.sum(|s| s.pixels).max(1) as f64
    }
    /// RMSE pooled over every channel of every pixel of the set.
    pub fn rmse(&self) -> f64 {
        (self.sum(|s| s.sq_err) / (3 * self.sum(|s| s.pixels)).max(1) as f64).sqrt()
    }
    /// Largest channel error over the set.
    pub fn max_err(&self) -> f64 {
        self.scenes.iter().map(|s| s.max_err).fold(0.0, f64::max)
    }
    /// Wrong-visible-surface pixels over the set.
    pub fn wrong_visible(&self) -> u64 {
        self.sum(|s| s.wrong_visible)
    }
    /// Wrong-visible-surface pixels where the reference has a clear majority surface.
    pub fn wrong_visible_clear(&self) -> u64 {
        self.sum(|s| s.wrong_visible_clear)
    }
}

/// How often each A-buffer depth variant orders a pixel's fragments differently from the
/// exhaustive search, per mask size (summed over the scene set).
#[derive(Clone, Debug)]
pub struct VariantRow {
    /// Mask size.
    pub size: MaskSize,
    /// Pixels with two or more fragments.
    pub multi_pixels: u64,
    /// Fragments in those pixels.
    pub sorted_fragments: u64,
    /// Per variant ([`DepthSelect::ALL`] order): depth evaluations.
    pub evals: [u64; 4],
    /// Per variant: pixels packed in a different order from exhaustive.
    pub order_diff: [u64; 4],
    /// Per variant: pixels whose visible subpixels differ from exhaustive.
    pub visible_diff: [u64; 4],
    /// Per variant: pixels whose colour differs from exhaustive.
    pub rgb_diff: [u64; 4],
}

/// Options of [`run_sweep`].
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Timed runs per setting and scene (median reported), after one untimed render.
    pub runs: usize,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// What the report says about one scene of the set.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneInfo {
    /// Scene name.
    pub name: String,
    /// What the scene exercises.
    pub about: String,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Triangles.
    pub triangles: usize,
}

impl SceneInfo {
    /// The summary of `s`.
    fn of(s: &TestScene) -> SceneInfo {
        SceneInfo {
            name: s.name.clone(),
            about: s.about.clone(),
            width: s.width,
            height: s.height,
            triangles: s.tris.len(),
        }
    }
}

/// The whole result.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The scenes, in sweep order.
    pub scenes: Vec<SceneInfo>,
    /// One row per setting, in sweep order.
    pub rows: Vec<Row>,
    /// A-buffer variant comparison.
    pub variants: Vec<VariantRow>,
    /// Timed runs per measurement.
    pub runs: usize,
    /// Logical cores of the machine.
    pub cores: usize,
    /// The scene of the heat maps, with the reference and each setting's image.
    pub heat: Option<HeatData>,
    /// Every setting's cycles on the modelled hardware at 1920×1080
    /// ([`crate::hardware`]); filled by [`crate::run_tradeoff_with`].
    pub hardware: Option<crate::hardware::HwSweep>,
    /// The 1080p scene, swept apart from the set, and what 60 frames per second costs on
    /// it ([`crate::hd`]); filled by [`crate::run_tradeoff_with`] for the built-in set.
    pub hd: Option<Box<crate::hd::HdResult>>,
}

/// Images of one scene for the heat maps.
#[derive(Clone, Debug)]
pub struct HeatData {
    /// Scene name.
    pub scene: String,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Reference, f64 RGB (box filter).
    pub reference: Vec<[f64; 3]>,
    /// References under the other filters some settings use, f64 RGB.
    pub filtered: Vec<Vec<[f64; 3]>>,
    /// Per setting (sweep order): the index into `filtered` of its reference, or `None`
    /// for the box reference.
    pub reference_of: Vec<Option<usize>>,
    /// Per setting (sweep order): RGB8.
    pub images: Vec<Vec<u8>>,
}

impl Row {
    /// An empty row for `s`, with the shade levels its method gives a long edge.
    fn new(s: &Setting) -> Row {
        let shade = (
            edge_shade_levels(&s.aa, false).unwrap_or(0),
            edge_shade_levels(&s.aa, true).unwrap_or(0),
        );
        Row {
            setting: s.clone(),
            scenes: Vec::new(),
            shade_levels: shade,
        }
    }
}

impl VariantRow {
    /// Zero counts for `size`.
    fn new(size: MaskSize) -> VariantRow {
        VariantRow {
            size,
            multi_pixels: 0,
            sorted_fragments: 0,
            evals: [0; 4],
            order_diff: [0; 4],
            visible_diff: [0; 4],
            rgb_diff: [0; 4],
        }
    }

    /// Renders `sc` with the exhaustive A-buffer comparing every depth variant and adds the
    /// counts.
    fn add_scene(&mut self, sc: &TestScene) -> Result<(), TradeoffError> {
        let p = AbufferParams {
            size: self.size,
            depth: DepthSelect::Exhaustive,
            interpenetrating: sc.interpenetrating,
            compare_variants: true,
        };
        let f = render_abuffer(&sc.tris, sc.width, sc.height, sc.bg, &p).map_err(|e| {
            TradeoffError::Render {
                method: format!("abuffer {} compare", self.size),
                scene: sc.name.clone(),
                source: match e {
                    AbufferError::Setup(s) => AaError::Setup(s),
                    AbufferError::ScreenTooLarge(w, h) => AaError::Screen(w, h),
                },
            }
        })?;
        let st = &f.stats;
        self.multi_pixels += st.multi_pixels;
        self.sorted_fragments += st.sorted_fragments;
        for k in 0..4 {
            self.evals[k] += st.variant_evals[k];
            self.order_diff[k] += st.order_diff[k];
            self.visible_diff[k] += st.visible_diff[k];
            self.rgb_diff[k] += st.rgb_diff[k];
        }
        Ok(())
    }
}

/// The method of a setting as run on a scene: the A-buffer takes `interpenetrating` from
/// the scene.
fn with_scene(aa: &AaMethod, sc: &TestScene) -> AaMethod {
    match aa {
        AaMethod::Abuffer(p) => AaMethod::Abuffer(AbufferParams {
            interpenetrating: sc.interpenetrating,
            ..*p
        }),
        m => m.clone(),
    }
}

/// Measures one setting on one scene: an untimed render judged against the reference `r`
/// of the setting's filter (any thread count gives the same image), then `runs` timed renders on the one-thread
/// pool. Returns the measurements and the untimed image (RGB8).
fn measure(
    one: &rayon::ThreadPool,
    sc: &TestScene,
    r: &RefImage,
    setting: &Setting,
    runs: usize,
) -> Result<(SceneResult, Vec<u8>), TradeoffError> {
    let aa = with_scene(&setting.aa, sc);
    let err = |source| TradeoffError::Render {
        method: format!("{} {}", setting.method, setting.setting),
        scene: sc.name.clone(),
        source,
    };
    let f = render_aa(&sc.tris, sc.width, sc.height, sc.bg, &aa).map_err(err)?;
    let j = judge(r, &f.rgb, f.visible.as_ref());
    let t = time_setting(one, sc, &aa, runs).map_err(err)?;
    let res = SceneResult {
        scene: sc.name.clone(),
        seconds: t.cpu,
        wall_seconds: t.wall,
        depth_evals: f.stats.depth_evals,
        sample_reads: f.stats.sample_reads,
        pixels: f.stats.pixels,
        sq_err: j.sq_err,
        max_err: j.max_err,
        wrong_visible: j.wrong_visible,
        wrong_visible_clear: j.wrong_visible_clear,
    };
    Ok((res, f.rgb))
}

/// The progress bar on stderr (hidden unless `show`).
fn progress_bar(show: bool, total: u64) -> Result<indicatif::ProgressBar, TradeoffError> {
    if !show {
        return Ok(indicatif::ProgressBar::hidden());
    }
    let b = indicatif::ProgressBar::new(total);
    b.set_style(
        indicatif::ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
            .map_err(|e| TradeoffError::Option(e.to_string()))?
            .progress_chars("=> "),
    );
    Ok(b)
}

/// The scene whose images are kept for the heat maps: `asked`, else `thin-horizontal` if
/// present, else the first scene.
fn heat_scene_name(scenes: &[TestScene], asked: Option<&str>) -> String {
    asked
        .map(str::to_string)
        .or_else(|| {
            scenes
                .iter()
                .find(|s| s.name == "thin-horizontal")
                .map(|s| s.name.clone())
        })
        .unwrap_or_else(|| scenes[0].name.clone())
}

/// Runs every setting on every scene. `heat_scene` names the scene whose images are kept
/// for the heat maps (default: `thin-horizontal` if present, else the first scene).
pub fn run_sweep(
    scenes: &[TestScene],
    settings: &[Setting],
    opts: &SweepOptions,
    heat_scene: Option<&str>,
) -> Result<Sweep, TradeoffError> {
    run_sweep_heat(scenes, settings, opts, heat_scene, true)
}

/// [`run_sweep`], keeping the heat-map images only if `heat` (a 1080p scene's images are
/// large and have no heat map).
pub(crate) fn run_sweep_heat(
    scenes: &[TestScene],
    settings: &[Setting],
    opts: &SweepOptions,
    heat_scene: Option<&str>,
    keep_heat: bool,
) -> Result<Sweep, TradeoffError> {
    crate::timing::check_runs(opts.runs).map_err(TradeoffError::Option)?;
    if scenes.is_empty() {
        return Err(TradeoffError::Option("no scenes".into()));
    }
    let one = one_thread_pool()?;
    let heat_name = heat_scene_name(scenes, heat_scene);
    let bar = progress_bar(opts.progress, (scenes.len() * (settings.len() + 1)) as u64)?;
    let mut rows: Vec<Row> = settings.iter().map(Row::new).collect();
    let mut variants: Vec<VariantRow> = [MaskSize::S4X4, MaskSize::S8X8]
        .into_iter()
        .map(VariantRow::new)
        .collect();
    let mut heat = None;
    for sc in scenes {
        bar.set_message(format!("{}: reference", sc.name));
        let r = reference_image(&sc.tris, sc.width, sc.height, sc.bg);
        // Each setting is judged against the reference of its own filter.
        let mut filtered: Vec<(RefFilter, RefImage)> = Vec::new();
        for row in &rows {
            let f = reference_filter(&row.setting.aa);
            if f != RefFilter::Box && !filtered.iter().any(|(g, _)| *g == f) {
                let img = filtered_reference_image(&sc.tris, sc.width, sc.height, sc.bg, f);
                filtered.push((f, img.image));
            }
        }
        for v in &mut variants {
            v.add_scene(sc)?;
        }
        bar.inc(1);
        let keep = keep_heat && sc.name == heat_name;
        let mut images = Vec::new();
        let mut reference_of = Vec::new();
        for row in rows.iter_mut() {
            bar.set_message(format!(
                "{}: {} {}",
                sc.name, row.setting.method, row.setting.setting
            ));
            let f = reference_filter(&row.setting.aa);
            let own = filtered.iter().position(|(g, _)| *g == f);
            let rf = own.map_or(&r, |i| &filtered[i].1);
            let (res, rgb) = measure(&one, sc, rf, &row.setting, opts.runs)?;
            row.scenes.push(res);
            if keep {
                images.push(rgb);
                reference_of.push(own);
            }
            bar.inc(1);
        }
        if keep {
            heat = Some(HeatData {
                scene: sc.name.clone(),
                width: sc.width,
                height: sc.height,
                reference: r.rgb,
                filtered: filtered.into_iter().map(|(_, img)| img.rgb).collect(),
                reference_of,
                images,
            });
        }
    }
    bar.finish_and_clear();
    Ok(Sweep {
        scenes: scenes.iter().map(SceneInfo::of).collect(),
        rows,
        variants,
        runs: opts.runs,
        cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        heat,
        hardware: None,
        hd: None,
    })
}
