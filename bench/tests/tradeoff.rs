//! The trade-off sweep: a quick run writes every file, the CSV parses, its frontier is the
//! non-dominated set (recomputed here by a different algorithm), and errors fall with the
//! parameter of multi-scanning and supersampling.

use std::collections::BTreeMap;
use std::path::PathBuf;

use pixelproc_bench::{
    load_scene_dir, pareto_frontier, run_tradeoff, TradeoffError, TradeoffOptions, CSV_HEADER,
    HD_CSV_HEADER,
};
use pixelproc_sim::aa::{render_aa, AaMethod};
use pixelproc_sim::abuffer::AbufferParams;
use pixelproc_sim::reference::reference_image;
use pixelproc_sim::setup::SnappedTri;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pixelproc-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Staircase frontier: sort by (time, error), keep a point when its error is below every
/// faster point's (equal points are kept together).
fn staircase(p: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..p.len()).collect();
    idx.sort_by(|&a, &b| p[a].0.total_cmp(&p[b].0).then(p[a].1.total_cmp(&p[b].1)));
    let mut best = f64::INFINITY;
    let mut last: Option<(f64, f64)> = None;
    let mut out = Vec::new();
    for k in idx {
        if p[k].1 < best || last == Some(p[k]) {
            out.push(k);
            best = best.min(p[k].1);
            last = Some(p[k]);
        }
    }
    out.sort();
    out
}

#[test]
fn quick_sweep_writes_consistent_outputs() {
    let dir = scratch("tradeoff-quick");
    let (sw, w) = run_tradeoff(&TradeoffOptions {
        scenes_dir: None,
        out_dir: dir.clone(),
        runs: 1,
        quick: true,
        progress: false,
        command: "pixelproc tradeoff --quick".into(),
    })
    .expect("sweep");
    for p in [&w.csv, &w.scenes_csv, &w.markdown, &w.chart]
        .into_iter()
        .chain(w.heatmap.as_ref())
    {
        let len = std::fs::metadata(p).expect("written").len();
        assert!(len > 100, "{} is only {len} bytes", p.display());
    }
    // The PNGs decode.
    let chart = image::open(&w.chart).expect("chart decodes");
    assert_eq!((chart.width(), chart.height()), (1100, 760));
    image::open(w.heatmap.as_ref().unwrap()).expect("heat map decodes");

    // Parse the CSV.
    let text = std::fs::read_to_string(&w.csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(CSV_HEADER));
    let cols: Vec<&str> = CSV_HEADER.split(',').collect();
    let mut rows: Vec<BTreeMap<&str, String>> = Vec::new();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f.len(), cols.len(), "{l}");
        for v in &f[2..] {
            let x: f64 = v.parse().unwrap_or_else(|_| panic!("{v} in {l}"));
            assert!(x.is_finite() && x >= 0.0, "{l}");
        }
        rows.push(
            cols.iter()
                .copied()
                .zip(f.iter().map(|s| s.to_string()))
                .collect(),
        );
    }
    assert_eq!(rows.len(), sw.rows.len());
    assert!(rows.len() >= 9);

    // Frontier: the library's, the CSV column and the staircase agree; frontier points are
    // not dominated and every other point is dominated by a frontier point.
    let pts: Vec<(f64, f64)> = sw
        .rows
        .iter()
        .map(|r| (r.ms_per_frame(), r.rmse()))
        .collect();
    let mut lib = pareto_frontier(&pts);
    lib.sort();
    assert_eq!(lib, staircase(&pts));
    let csv_front: Vec<usize> = (0..rows.len())
        .filter(|&k| rows[k]["pareto"] == "1")
        .collect();
    assert_eq!(csv_front, lib);
    let dominates =
        |a: (f64, f64), b: (f64, f64)| a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1);
    for k in 0..pts.len() {
        let dominated = pts.iter().any(|&q| dominates(q, pts[k]));
        assert_eq!(dominated, !lib.contains(&k), "point {k}");
        if dominated {
            assert!(lib.iter().any(|&f| dominates(pts[f], pts[k])));
        }
    }

    // Errors fall with the parameter.
    let rmse = |m: &str, s: &str| -> f64 {
        rows.iter()
            .find(|r| r["method"] == m && r["setting"] == s)
            .unwrap_or_else(|| panic!("{m} {s}"))["rmse"]
            .parse()
            .unwrap()
    };
    let ms = [1, 4, 12].map(|n| rmse("multiscan", &format!("n={n} box")));
    assert!(ms[0] > ms[1] && ms[1] > ms[2], "multiscan {ms:?}");
    let ss = [2, 8].map(|k| rmse("ssaa", &format!("k={k} ({k}x{k})")));
    assert!(ss[0] > ss[1], "ssaa {ss:?}");
    // And every anti-aliasing method beats none except the one-sample multiscan.
    let none = rmse("none", "1 sample");
    assert!(ms[1] < none && ss[0] < none);

    // The Markdown carries the table and the frontier.
    let md = std::fs::read_to_string(&w.markdown).unwrap();
    assert!(md.contains("| method | setting | ms/frame"));
    assert!(md.contains("## Pareto frontier"));
    // Set table, two per-scene tables, the city table and the 60 frames/s table.
    assert_eq!(md.matches("| multiscan | n=4 box |").count(), 5);
    assert!(md.contains("## The 1080p scene"));
    assert!(md.contains("at 60 frames/s: array width and clock"));

    // The city scene's CSV: one row per setting; its 60 fps clock is cycles · 60 / 10⁶.
    let hd = sw.hd.as_ref().expect("built-in set sweeps the city scene");
    assert_eq!(hd.sweep.scenes[0].name, "city-quick");
    let text = std::fs::read_to_string(w.hd_csv.as_ref().unwrap()).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HD_CSV_HEADER));
    let cols: Vec<&str> = HD_CSV_HEADER.split(',').collect();
    let col = |name: &str| cols.iter().position(|c| *c == name).unwrap();
    let mut n = 0;
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f.len(), cols.len(), "{l}");
        let cycles: f64 = f[col("hw_cycles_per_frame")].parse().unwrap();
        let mhz: f64 = f[col("fps60_mhz_at_n")].parse().unwrap();
        assert!((mhz - cycles * 60.0 / 1e6).abs() < 1e-3, "{l}");
        // 192×108 at one pixel per clock is 20,736 reads: 60 fps needs ≥ 1.24 MHz at any
        // width, and the default clock is far above that, so every setting is reachable
        // at some width.
        let widest: f64 = f[col("fps60_mhz_widest")].parse().unwrap();
        assert!(
            widest >= 192.0 * 108.0 * 60.0 / 1e6 && widest <= mhz + 1e-9,
            "{l}"
        );
        let nmin: u32 = f[col("fps60_min_width")].parse().unwrap();
        assert!((1..=192).contains(&nmin), "{l}");
        n += 1;
    }
    assert_eq!(n, sw.rows.len());
    let _ = std::fs::remove_dir_all(&dir);
}

fn q8(x: f64) -> i32 {
    (x * 256.0).round() as i32
}

fn tri(v: [[f64; 2]; 3], z: u32, grey: u32) -> SnappedTri {
    SnappedTri {
        v: v.map(|p| [q8(p[0]), q8(p[1])]),
        z: [z; 3],
        c: [[(grey << 12) + 2048; 3]; 3],
        ..Default::default()
    }
}

#[test]
fn abuffer_reports_the_visible_surface() {
    // A far triangle over the whole 4×2 screen, and a near one over x < 2.75: pixel 2 of
    // each row is 3/4 near, pixel 3 is all far.
    let tris = vec![
        tri([[-1.0, -1.0], [12.0, -1.0], [-1.0, 12.0]], 5000, 100),
        tri([[2.75, -10.0], [2.75, 10.0], [-20.0, 0.0]], 1000, 200),
    ];
    let f = render_aa(
        &tris,
        4,
        2,
        [0, 0, 0],
        &AaMethod::Abuffer(AbufferParams::default()),
    )
    .unwrap();
    let v = f.visible.expect("the A-buffer reports visibility");
    for row in v.chunks(4) {
        assert_eq!(row, [1, 1, 1, 0]);
    }
    // The reference's dominant area: 3/4 in pixel 2, 1 elsewhere.
    let r = reference_image(&tris, 4, 2, [0, 0, 0]);
    for j in 0..2 {
        for i in 0..4 {
            let want = if i == 2 { 0.75 } else { 1.0 };
            assert!((r.dominant_area[j * 4 + i] - want).abs() < 1e-9);
        }
    }
}

#[test]
fn scene_folder_loads_screen_space_files() {
    let dir = scratch("tradeoff-dir");
    std::fs::create_dir_all(&dir).unwrap();
    assert!(matches!(
        load_scene_dir(&dir),
        Err(TradeoffError::NoScenes(_))
    ));
    std::fs::write(
        dir.join("one.json"),
        r#"{"width": 16, "height": 8, "background": [0, 0, 1],
            "triangles": [{"v": [[1, 1, 0], [15, 2, 0], [3, 7, 1]], "color": [1, 0, 0]}]}"#,
    )
    .unwrap();
    let s = load_scene_dir(&dir).unwrap();
    assert_eq!(s.len(), 1);
    assert_eq!(
        (s[0].name.as_str(), s[0].width, s[0].height),
        ("one", 16, 8)
    );
    assert_eq!(s[0].tris.len(), 1);
    assert_eq!(s[0].bg, [0, 0, 255]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The hardware columns: a quick sweep with N = 8 at 100 MHz writes the hardware chart, its
/// CSV columns convert cycles to ms and frames/s at that clock, its hardware frontier is
/// the non-dominated set of (hardware ms, RMSE), and the no-AA row's cycles are the mean of
/// the core's cycle-level model (`core_model::CoreModel`, no stalls) over the scenes
/// scaled to 1920×1080.
#[test]
fn quick_sweep_reports_hardware_time() {
    use pixelproc_bench::{builtin_scenes, run_tradeoff_with, HwConfig};
    use pixelproc_sim::core_model::{run_frame, CoreModel, CoreStream, Stalls, DEFAULT_IN_ABITS};
    use pixelproc_sim::render::SpanSource;
    use pixelproc_sim::stream::SceneStream;

    let dir = scratch("tradeoff-hw");
    let hw = HwConfig::new(8, 100.0).unwrap();
    let (sw, w) = run_tradeoff_with(
        &TradeoffOptions {
            scenes_dir: None,
            out_dir: dir.clone(),
            runs: 1,
            quick: true,
            progress: false,
            command: "pixelproc tradeoff --quick --array-width 8 --clock-mhz 100".into(),
        },
        &hw,
    )
    .expect("sweep");
    let hw_chart = w.hw_chart.as_ref().expect("hardware chart");
    let img = image::open(hw_chart).expect("hardware chart decodes");
    assert_eq!((img.width(), img.height()), (1100, 760));

    let text = std::fs::read_to_string(&w.csv).unwrap();
    let cols: Vec<&str> = CSV_HEADER.split(',').collect();
    let col = |name: &str| cols.iter().position(|c| *c == name).unwrap();
    let rows: Vec<Vec<String>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let num = |r: &Vec<String>, c: &str| -> f64 { r[col(c)].parse().unwrap() };
    let mut pts = Vec::new();
    for r in &rows {
        let cycles = num(r, "hw_cycles_per_frame");
        assert!(cycles > 0.0);
        // 100 MHz: 100,000 cycles per millisecond.
        assert!(
            (num(r, "hw_ms_per_frame") - cycles / 1e5).abs() < 1e-3,
            "{r:?}"
        );
        assert!((num(r, "hw_fps") - 1e8 / cycles).abs() < 1e-2, "{r:?}");
        pts.push((num(r, "hw_ms_per_frame"), num(r, "rmse")));
    }
    let front: Vec<usize> = (0..rows.len())
        .filter(|&k| rows[k][col("hw_pareto")] == "1")
        .collect();
    assert_eq!(front, staircase(&pts));

    // The no-AA row against the core's cycle model on the scaled scenes.
    let mut total = 0u64;
    let scenes = builtin_scenes(true);
    for sc in &scenes {
        let tris = pixelproc_sim::hwcost::rescale(&sc.tris, sc.width, sc.height, 1920, 1080);
        let s = SceneStream {
            bg: sc.bg,
            spans: SpanSource::new(&tris, 1920, 1080).unwrap(),
            shadow: vec![Vec::new(); 1080],
            shadow_stats: Default::default(),
        };
        let cs = CoreStream::of_scene(&s, 8, None).unwrap();
        let mut m = CoreModel::new(8, false, false, DEFAULT_IN_ABITS).unwrap();
        let run = run_frame(
            &mut m,
            &cs.beats,
            cs.pixels(),
            &mut Stalls::new(1, 0, 0),
            1 << 34,
        )
        .unwrap();
        total += run.cycles.cycles;
    }
    let n = scenes.len() as u64;
    let none = rows.iter().find(|r| r[0] == "none").unwrap();
    assert_eq!(
        none[col("hw_cycles_per_frame")],
        ((total + n / 2) / n).to_string()
    );
    assert_eq!(sw.hardware.as_ref().unwrap().config, hw);

    let md = std::fs::read_to_string(&w.markdown).unwrap();
    assert!(md.contains("## Hardware time (model, 1920×1080)"));
    assert!(md.contains("| hw cycles/frame | hw ms | hw fps | LUT4/FF (RTL) | hw front |"));
    // N = 8 is the routed configuration: its LUT4/FF are the measured ones.
    assert!(md.contains("| 6226 / 4829 |"), "measured core resources");
    let _ = std::fs::remove_dir_all(&dir);
}
