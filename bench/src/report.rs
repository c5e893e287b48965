//! The sweep's text outputs: the per-setting CSV, the per-setting-and-scene CSV and the
//! Markdown report (the tables of `docs/accuracy.md`), and [`write_outputs`], which writes
//! them with the chart and the heat maps.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use pixelproc_sim::mask_search::DepthSelect;

use pixelproc_sim::hwcost::target::WidthFor;

use crate::chart::{chart, chart_hw, heat_montage, png_rgb};
use crate::hd::{FpsRow, HdResult, TARGET_FPS};
use crate::judge::pareto_frontier;
use crate::sweep::{Row, Sweep};
use crate::TradeoffError;

/// Files written by [`write_outputs`].
#[derive(Clone, Debug)]
pub struct Written {
    /// Per-setting CSV.
    pub csv: PathBuf,
    /// Per-setting-and-scene CSV.
    pub scenes_csv: PathBuf,
    /// Markdown report.
    pub markdown: PathBuf,
    /// Error-against-time chart.
    pub chart: PathBuf,
    /// Error against the modelled hardware's time (if the sweep has hardware figures).
    pub hw_chart: Option<PathBuf>,
    /// Heat-map montage (if a heat-map scene was kept).
    pub heatmap: Option<PathBuf>,
    /// The 1080p scene's CSV, with the 60 frames/s costs (if the sweep has it).
    pub hd_csv: Option<PathBuf>,
}

/// The CSV header of the per-setting file.
pub const CSV_HEADER: &str = "method,setting,ms_per_frame,wall_ms_per_frame,depth_evals_per_px,reads_per_px,rmse,max_err,wrong_visible,wrong_visible_clear,shade_levels_h,shade_levels_v,pareto,hw_cycles_per_frame,hw_ms_per_frame,hw_fps,hw_pareto";

/// Each row's (ms per frame, RMSE), the plane of the frontier and the chart.
pub(crate) fn points(sw: &Sweep) -> Vec<(f64, f64)> {
    sw.rows
        .iter()
        .map(|r| (r.ms_per_frame(), r.rmse()))
        .collect()
}

/// Each row's (hardware ms per frame at 1920×1080, RMSE): the plane of the hardware
/// frontier and chart; empty without hardware figures.
pub(crate) fn hw_points(sw: &Sweep) -> Vec<(f64, f64)> {
    match &sw.hardware {
        Some(hw) => (0..sw.rows.len())
            .map(|k| (hw.ms(k), sw.rows[k].rmse()))
            .collect(),
        None => Vec::new(),
    }
}

/// Row `k`'s hardware columns for the CSV: cycles, ms, fps, on the hardware frontier
/// (zeros without hardware figures).
fn hw_csv(sw: &Sweep, k: usize, front: &[usize]) -> String {
    match &sw.hardware {
        Some(hw) => format!(
            "{},{:.4},{:.2},{}",
            hw.rows[k].cycles(),
            hw.ms(k),
            hw.fps(k),
            front.contains(&k) as u8
        ),
        None => "0,0,0,0".into(),
    }
}

/// A setting's figures, in the column order of the CSV and the Markdown table: method,
/// setting, the four costs with `cost` decimals, RMSE with `rmse` decimals, max error with
/// `max` decimals, then the two wrong-visibility counts.
fn figures(r: &Row, cost: usize, rmse: usize, max: usize) -> [String; 10] {
    [
        r.setting.method.to_string(),
        r.setting.setting.to_string(),
        format!("{:.*}", cost, r.ms_per_frame()),
        format!("{:.*}", cost, r.wall_ms_per_frame()),
        format!("{:.*}", cost, r.evals_per_pixel()),
        format!("{:.*}", cost, r.reads_per_pixel()),
        format!("{:.*}", rmse, r.rmse()),
        format!("{:.*}", max, r.max_err()),
        r.wrong_visible().to_string(),
        r.wrong_visible_clear().to_string(),
    ]
}

/// The per-setting CSV text.
pub fn csv(sw: &Sweep) -> String {
    let front = pareto_frontier(&points(sw));
    let hw_front = pareto_frontier(&hw_points(sw));
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for (k, r) in sw.rows.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{},{},{},{}",
            figures(r, 4, 4, 2).join(","),
            r.shade_levels.0,
            r.shade_levels.1,
            front.contains(&k) as u8,
            hw_csv(sw, k, &hw_front)
        );
    }
    s
}

/// The per-setting-and-scene CSV text.
pub fn scenes_csv(sw: &Sweep) -> String {
    let mut s = String::from(
        "method,setting,scene,ms_per_frame,wall_ms_per_frame,depth_evals_per_px,reads_per_px,rmse,max_err,wrong_visible,wrong_visible_clear\n",
    );
    for r in &sw.rows {
        for sc in &r.scenes {
            let px = sc.pixels.max(1) as f64;
            let _ = writeln!(
                s,
                "{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.2},{},{}",
                r.setting.method,
                r.setting.setting,
                sc.scene,
                sc.seconds * 1e3,
                sc.wall_seconds * 1e3,
                sc.depth_evals as f64 / px,
                sc.sample_reads as f64 / px,
                sc.rmse(),
                sc.max_err,
                sc.wrong_visible,
                sc.wrong_visible_clear
            );
        }
    }
    s
}

/// The Markdown report. `command` is the command line that produced it.
pub fn markdown(sw: &Sweep, command: &str) -> String {
    let front = pareto_frontier(&points(sw));
    let mut s = String::new();
    md_intro(&mut s, sw, command);
    md_settings(&mut s, sw, &front);
    md_frontier(&mut s, sw, &front);
    md_hardware(&mut s, sw);
    md_per_scene(&mut s, sw);
    if !sw.variants.is_empty() {
        md_variants(&mut s, sw);
    }
    if let Some(hd) = &sw.hd {
        md_hd(&mut s, hd);
        md_fps(&mut s, hd);
        if !hd.sweep.variants.is_empty() {
            let _ = write!(s, "\n### A-buffer depth variants on the 1080p scene\n\n");
            let mut t = String::new();
            md_variants(&mut t, &hd.sweep);
            // Drop the set's section heading: this is a subsection.
            s.push_str(t.split_once("\n\n").map_or(&t[..], |(_, rest)| rest));
        }
    }
    s
}

/// The cell of the smallest width reaching the frame rate.
fn width_cell(r: &FpsRow) -> String {
    match r.width {
        WidthFor::Width { n, cycles } => format!("{n} ({cycles} cycles)"),
        WidthFor::NotReachable { floor_cycles } => format!(
            "not reachable: ≥ {floor_cycles} cycles at any N ({} samples at one per clock)",
            r.samples
        ),
    }
}

/// The 1080p scene's table: error, CPU time and hardware time per setting.
fn md_hd(s: &mut String, hd: &HdResult) {
    let sw = &hd.sweep;
    let Some(hw) = &sw.hardware else { return };
    let Some(sc) = sw.scenes.first() else { return };
    let c = &hw.config;
    let _ = writeln!(
        s,
        "\n## The 1080p scene\n\n`{}`, {}×{}, {} triangles: {}. Drawn at its own size, \
         not scaled. Every setting is judged against the exact reference of its filter, \
         as for the set; `ms/frame` is the thread CPU time of {} timed run(s); the \
         hardware columns are the cycle model on this scene as drawn, N = {}, {} MHz. \
         `frontier` / `hw front`: on the Pareto frontier of RMSE against CPU / hardware \
         time on this scene.\n",
        sc.name, sc.width, sc.height, sc.triangles, sc.about, sw.runs, c.array_width, c.clock_mhz
    );
    let front = pareto_frontier(&points(sw));
    let hw_front = pareto_frontier(&hw_points(sw));
    let _ = writeln!(
        s,
        "| method | setting | ms/frame | RMSE | max err | wrong vis. | clear | hw cycles/frame | hw ms | hw fps | frontier | hw front |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|"
    );
    for (k, r) in sw.rows.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {:.3} | {:.1} | {} | {} | {} | {:.2} | {:.1} | {} | {} |",
            r.setting.method,
            r.setting.setting,
            r.ms_per_frame(),
            r.rmse(),
            r.max_err(),
            r.wrong_visible(),
            r.wrong_visible_clear(),
            hw.rows[k].cycles(),
            hw.ms(k),
            hw.fps(k),
            if front.contains(&k) { "●" } else { "" },
            if hw_front.contains(&k) { "●" } else { "" },
        );
    }
}

/// What 60 frames per second on the 1080p scene costs each setting.
fn md_fps(s: &mut String, hd: &HdResult) {
    let sw = &hd.sweep;
    let Some(hw) = &sw.hardware else { return };
    let Some(sc) = sw.scenes.first() else { return };
    let c = &hw.config;
    let _ = writeln!(
        s,
        "\n## {}×{} at {} frames/s: array width and clock\n\nFrom the cycle model on \
         `{}` (`sim::hwcost::target`): the clock {} frames/s needs at N = {}; the clock it \
         needs at N = {} (the widest array that changes anything: one tile per row, no \
         width does better); and the smallest N that reaches it at {} MHz, found by \
         bisection on N, or why none does (the fewest cycles any width gives, and the \
         samples the busiest stage handles at one per clock).\n",
        sc.width, sc.height, TARGET_FPS, sc.name, TARGET_FPS, c.array_width, hd.widest, c.clock_mhz
    );
    let _ = writeln!(
        s,
        "| method | setting | cycles/frame (N = {n}) | MHz for {f} fps at N = {n} | MHz for {f} fps at N = {w} | smallest N at {mhz} MHz |\n|---|---|---:|---:|---:|---|",
        n = c.array_width,
        f = TARGET_FPS,
        w = hd.widest,
        mhz = c.clock_mhz
    );
    for (r, f) in sw.rows.iter().zip(&hd.fps) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} | {:.1} | {} |",
            r.setting.method,
            r.setting.setting,
            f.cycles,
            f.clock_mhz,
            f.floor_clock_mhz,
            width_cell(f)
        );
    }
}

/// The header of the 1080p scene's CSV.
pub const HD_CSV_HEADER: &str = "method,setting,ms_per_frame,rmse,max_err,wrong_visible,wrong_visible_clear,hw_cycles_per_frame,hw_ms_per_frame,hw_fps,hw_pareto,pareto,fps60_mhz_at_n,fps60_mhz_widest,fps60_min_width";

/// The 1080p scene's CSV text: one row per setting; `fps60_min_width` is 0 where no width
/// reaches 60 frames/s at the configured clock.
pub fn hd_csv(hd: &HdResult) -> String {
    let sw = &hd.sweep;
    let front = pareto_frontier(&points(sw));
    let hw_front = pareto_frontier(&hw_points(sw));
    let mut s = format!("{HD_CSV_HEADER}\n");
    for (k, (r, f)) in sw.rows.iter().zip(&hd.fps).enumerate() {
        let n = match f.width {
            WidthFor::Width { n, .. } => n,
            WidthFor::NotReachable { .. } => 0,
        };
        let _ = writeln!(
            s,
            "{},{},{:.4},{:.4},{:.2},{},{},{},{}",
            r.setting.method,
            r.setting.setting,
            r.ms_per_frame(),
            r.rmse(),
            r.max_err(),
            r.wrong_visible(),
            r.wrong_visible_clear(),
            hw_csv(sw, k, &hw_front),
            format_args!(
                "{},{:.3},{:.3},{}",
                front.contains(&k) as u8,
                f.clock_mhz,
                f.floor_clock_mhz,
                n
            )
        );
    }
    s
}

/// Title, how the figures were measured, and the scene table.
fn md_intro(s: &mut String, sw: &Sweep, command: &str) {
    let px: u64 = sw.rows.first().map_or(0, |r| r.sum(|s| s.pixels));
    let _ = writeln!(s, "# Anti-aliasing trade-off\n");
    let _ = writeln!(
        s,
        "Command: `{command}`. Machine: {} logical cores; every timed render ran alone on \
         one thread (a one-thread rayon pool); `ms/frame` is that thread's CPU time, the \
         median of {} runs per scene averaged over the {} scenes (`wall` is wall-clock \
         time of the same runs, which other load on the machine inflates). Errors are on the 0..255 scale against the exact \
         reference of each method's filter (the pixel box; the seed-002 Gaussian for \
         `gauss` multi-scanning), pooled over all {px} pixels of the set; they are \
         deterministic, times are not.\n",
        sw.cores,
        sw.runs,
        sw.scenes.len()
    );
    let _ = writeln!(
        s,
        "## Scenes\n\n| scene | size | triangles | what |\n|---|---|---|---|"
    );
    for sc in &sw.scenes {
        let _ = writeln!(
            s,
            "| {} | {}×{} | {} | {} |",
            sc.name, sc.width, sc.height, sc.triangles, sc.about
        );
    }
}

/// The table of every setting, its totals over the set and its place on the frontier.
fn md_settings(s: &mut String, sw: &Sweep, front: &[usize]) {
    let _ = writeln!(
        s,
        "\n## All settings\n\n`wrong vis.`: pixels whose visible surface (largest area) \
         differs from the reference's; `clear`: of those, pixels where the reference's \
         surface covers ≥ 3/4 of the pixel. `levels h/v`: distinct shades along a long \
         near-horizontal / near-vertical edge. `frontier`: on the Pareto frontier of \
         RMSE against time. `hw …`: the modelled hardware at 1920×1080 (see \
         \"Hardware time\" below): cycles, ms and frames per second per frame, the \
         ECP5 LUT4/FF of the blocks that have RTL (`~`: extrapolated), and `hw front`: \
         on the frontier of RMSE against hardware time.\n"
    );
    let hw_front = pareto_frontier(&hw_points(sw));
    let _ = writeln!(
        s,
        "| method | setting | ms/frame | wall | depth evals/px | reads/px | RMSE | max err | wrong vis. | clear | levels h/v | frontier | hw cycles/frame | hw ms | hw fps | LUT4/FF (RTL) | hw front |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---:|---|---|"
    );
    for (k, r) in sw.rows.iter().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {}/{} | {} | {} |",
            figures(r, 2, 3, 1).join(" | "),
            r.shade_levels.0,
            r.shade_levels.1,
            if front.contains(&k) { "●" } else { "" },
            hw_cells(sw, k, &hw_front)
        );
    }
}

/// Row `k`'s hardware cells for the Markdown table (dashes without hardware figures).
fn hw_cells(sw: &Sweep, k: usize, front: &[usize]) -> String {
    let Some(hw) = &sw.hardware else {
        return "— | — | — | — |".into();
    };
    let res = hw.rows[k].resources().map_or("—".to_string(), |r| {
        let t = if r.measured { "" } else { "~" };
        format!("{t}{} / {t}{}", r.lut4, r.ff)
    });
    format!(
        "{} | {:.2} | {:.1} | {} | {}",
        hw.rows[k].cycles(),
        hw.ms(k),
        hw.fps(k),
        res,
        if front.contains(&k) { "●" } else { "" }
    )
}

/// The hardware configuration, what the figures mean and the hardware frontier.
fn md_hardware(s: &mut String, sw: &Sweep) {
    let Some(hw) = &sw.hardware else {
        return;
    };
    let c = &hw.config;
    let _ = writeln!(
        s,
        "\n## Hardware time (model, 1920×1080)\n\n\
         Array width N = {}, clock {} MHz{}. Each scene is scaled to 1920×1080 and run \
         through the cycle model of its method (`sim::hwcost`); `hw cycles/frame` is the \
         mean over the scenes. The no-AA array's count is the streaming core's exact \
         cycle count; the other methods add stated assumptions (passes per pixel row, \
         one fragment per clock), documented per method in `sim::hwcost` and \
         `docs/accuracy.md`.\n",
        c.array_width,
        c.clock_mhz,
        if c.routed() {
            ""
        } else {
            " (an extrapolation: only the core at N = 8 was placed and routed)"
        }
    );
    let _ = writeln!(s, "Pareto frontier on hardware time (fastest first):\n");
    for &k in &pareto_frontier(&hw_points(sw)) {
        let r = &sw.rows[k];
        let _ = writeln!(
            s,
            "- {} {}: {} cycles, {:.2} ms/frame, {:.1} frames/s, {:.2} passes per row, RMSE {:.3}",
            r.setting.method,
            r.setting.setting,
            hw.rows[k].cycles(),
            hw.ms(k),
            hw.fps(k),
            hw.rows[k].passes_per_row(),
            r.rmse()
        );
    }
}

/// The frontier's settings, fastest first.
fn md_frontier(s: &mut String, sw: &Sweep, front: &[usize]) {
    let _ = writeln!(s, "\n## Pareto frontier (fastest first)\n");
    for &k in front {
        let r = &sw.rows[k];
        let _ = writeln!(
            s,
            "- {} {}: {:.2} ms/frame, RMSE {:.3}",
            r.setting.method,
            r.setting.setting,
            r.ms_per_frame(),
            r.rmse()
        );
    }
}

/// RMSE and wrong-visible-surface counts per setting and scene.
fn md_per_scene(s: &mut String, sw: &Sweep) {
    let _ = writeln!(s, "\n## RMSE per scene\n");
    let mut head = String::from("| method | setting |");
    let mut rule = String::from("|---|---|");
    for sc in &sw.scenes {
        let _ = write!(head, " {} |", sc.name);
        rule.push_str("---:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    for r in &sw.rows {
        let _ = write!(s, "| {} | {} |", r.setting.method, r.setting.setting);
        for sc in &r.scenes {
            let _ = write!(s, " {:.3} |", sc.rmse());
        }
        s.push('\n');
    }
    let _ = writeln!(
        s,
        "\n## Wrong visible surface per scene (all / clear majority)\n"
    );
    let _ = writeln!(s, "{head}\n{rule}");
    for r in &sw.rows {
        let _ = write!(s, "| {} | {} |", r.setting.method, r.setting.setting);
        for sc in &r.scenes {
            let _ = write!(s, " {}/{} |", sc.wrong_visible, sc.wrong_visible_clear);
        }
        s.push('\n');
    }
}

/// How often each A-buffer depth variant departs from the exhaustive search.
fn md_variants(s: &mut String, sw: &Sweep) {
    let _ = writeln!(
        s,
        "\n## A-buffer depth variants against the exhaustive search\n\n\
         Pixels with two or more fragments are where a fragment's depth is chosen. \
         `order≠`: pixels whose packing order differs from exhaustive; `visible≠`: whose \
         visible subpixels differ; `colour≠`: whose resolved colour differs.\n\n\
         | mask | multi-fragment pixels | variant | evals/sorted fragment | order≠ | visible≠ | colour≠ |\n|---|---:|---|---:|---:|---:|---:|"
    );
    for v in &sw.variants {
        for (k, d) in DepthSelect::ALL.iter().enumerate() {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.2} | {} | {} | {} |",
                v.size,
                v.multi_pixels,
                d.name(),
                v.evals[k] as f64 / v.sorted_fragments.max(1) as f64,
                v.order_diff[k],
                v.visible_diff[k],
                v.rgb_diff[k]
            );
        }
    }
}

/// Writes `tradeoff.csv`, `tradeoff_scenes.csv`, `tradeoff.md`, `tradeoff_1080p.csv`
/// (with the 1080p scene), `tradeoff.png`,
/// `tradeoff_hw.png` (with hardware figures) and `heatmap.png` into `dir` (created if needed), all or nothing: every file goes to a
/// temporary first and they are renamed together.
pub fn write_outputs(sw: &Sweep, dir: &Path, command: &str) -> Result<Written, TradeoffError> {
    let w = Written {
        csv: dir.join("tradeoff.csv"),
        scenes_csv: dir.join("tradeoff_scenes.csv"),
        markdown: dir.join("tradeoff.md"),
        chart: dir.join("tradeoff.png"),
        hw_chart: sw.hardware.as_ref().map(|_| dir.join("tradeoff_hw.png")),
        heatmap: sw.heat.as_ref().map(|_| dir.join("heatmap.png")),
        hd_csv: sw.hd.as_ref().map(|_| dir.join("tradeoff_1080p.csv")),
    };
    let out_err = |e: anyhow::Error| TradeoffError::Output(format!("{e:#}"));
    let mut files = pixelproc_output::OutputSet::new();
    files.add(&w.csv, csv(sw).as_bytes()).map_err(out_err)?;
    files
        .add(&w.scenes_csv, scenes_csv(sw).as_bytes())
        .map_err(out_err)?;
    files
        .add(&w.markdown, markdown(sw, command).as_bytes())
        .map_err(out_err)?;
    if let (Some(p), Some(hd)) = (&w.hd_csv, &sw.hd) {
        files.add(p, hd_csv(hd).as_bytes()).map_err(out_err)?;
    }
    let (cw, chh) = (1100, 760);
    files
        .add(&w.chart, &png_rgb(&chart(sw, cw, chh)?, cw, chh)?)
        .map_err(out_err)?;
    if let (Some(p), Some(buf)) = (&w.hw_chart, chart_hw(sw, cw, chh)?) {
        files.add(p, &png_rgb(&buf, cw, chh)?).map_err(out_err)?;
    }
    if let (Some(p), Some((buf, mw, mh))) = (&w.heatmap, heat_montage(sw)?) {
        files.add(p, &png_rgb(&buf, mw, mh)?).map_err(out_err)?;
    }
    files.commit().map_err(out_err)?;
    Ok(w)
}
