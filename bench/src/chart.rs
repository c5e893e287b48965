//! The sweep's pictures: RMSE against time per frame (log–log) with the Pareto frontier,
//! for the model's CPU time and for the modelled hardware's time, and a montage of per-pixel error heat maps for one scene (see `docs/accuracy.md`).

use plotters::prelude::*;

use crate::judge::pareto_frontier;
use crate::report::{hw_points, points};
use crate::sweep::Sweep;
use crate::TradeoffError;

/// The colour of a method family on the chart.
fn family_colour(method: &str) -> plotters::style::RGBColor {
    use plotters::style::RGBColor;
    match method {
        "none" => RGBColor(0, 0, 0),
        "multiscan" => RGBColor(31, 119, 180),
        "abuffer" => RGBColor(214, 39, 40),
        "corner" => RGBColor(44, 160, 44),
        "d3d4x" => RGBColor(148, 103, 189),
        "grid2x2" => RGBColor(140, 86, 75),
        "postfx" => RGBColor(255, 127, 14),
        "ssaa" => RGBColor(23, 190, 207),
        _ => RGBColor(127, 127, 127),
    }
}

/// Registers the bundled DejaVu Sans as the plots' `sans-serif`.
fn register_font() -> Result<(), TradeoffError> {
    use plotters::style::FontStyle;
    plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| TradeoffError::Plot("font".into()))?;
    plotters::style::register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold())
        .map_err(|_| TradeoffError::Plot("font".into()))
}

/// Maps a drawing error to [`TradeoffError::Plot`], naming what was drawn.
fn plot_err<E: std::fmt::Debug>(what: &str) -> impl Fn(E) -> TradeoffError + '_ {
    move |e| TradeoffError::Plot(format!("{what}: {e:?}"))
}

/// Writes RGB8 pixels as a PNG.
pub(crate) fn png_rgb(buf: &[u8], w: u32, h: u32) -> Result<Vec<u8>, TradeoffError> {
    let mut out = Vec::new();
    let enc = image::codecs::png::PngEncoder::new(&mut out);
    image::ImageEncoder::write_image(enc, buf, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| TradeoffError::Plot(format!("PNG encoding: {e}")))?;
    Ok(out)
}

/// The chart's drawing context: log–log axes on an RGB8 buffer.
type LogChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// Draws RMSE against time (log–log), one colour per method family, the Pareto frontier
/// as a line with its points labelled. Returns the PNG's RGB8 pixels.
pub fn chart(sw: &Sweep, width: u32, height: u32) -> Result<Vec<u8>, TradeoffError> {
    chart_of(
        sw,
        &points(sw),
        "RMSE against the exact reference vs time per frame (one thread)",
        "ms per frame (thread CPU time, median, one thread; log scale)",
        width,
        height,
    )
}

/// The same chart against the modelled hardware's time per frame at 1920×1080
/// ([`crate::hardware`]), with its own Pareto frontier; `None` if the sweep has no
/// hardware figures.
pub fn chart_hw(sw: &Sweep, width: u32, height: u32) -> Result<Option<Vec<u8>>, TradeoffError> {
    let Some(hw) = &sw.hardware else {
        return Ok(None);
    };
    let c = &hw.config;
    let caption = format!(
        "RMSE vs hardware time per frame at 1920x1080 (N = {}, {} MHz, model)",
        c.array_width, c.clock_mhz
    );
    chart_of(
        sw,
        &hw_points(sw),
        &caption,
        "ms per frame on the modelled hardware (cycles / clock; log scale)",
        width,
        height,
    )
    .map(Some)
}

/// Draws RMSE (the second coordinate of `pts`) against the time in `pts`.
fn chart_of(
    sw: &Sweep,
    pts: &[(f64, f64)],
    caption: &str,
    x_desc: &str,
    width: u32,
    height: u32,
) -> Result<Vec<u8>, TradeoffError> {
    register_font()?;
    let pts = pts.to_vec();
    let front = pareto_frontier(&pts);
    let mut buf = vec![255u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err("chart"))?;
        let ((t0, t1), (e0, e1)) = axis_ranges(&pts);
        let mut ch = ChartBuilder::on(&root)
            .caption(caption, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (t0 / 1.3..t1 * 1.3).log_scale(),
                (e0 / 1.3..e1 * 1.3).log_scale(),
            )
            .map_err(plot_err("chart"))?;
        ch.configure_mesh()
            .x_desc(x_desc)
            .y_desc("RMSE, 0..255 scale (log scale)")
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(plot_err("mesh"))?;
        draw_families(&mut ch, sw, &pts)?;
        draw_frontier(&mut ch, sw, &pts, &front)?;
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(plot_err("legend"))?;
        root.present().map_err(plot_err("chart"))?;
    }
    Ok(buf)
}

/// The data's time and error ranges, kept away from zero for the log axes.
fn axis_ranges(pts: &[(f64, f64)]) -> ((f64, f64), (f64, f64)) {
    let fold = |f: fn(f64, f64) -> f64, init: f64, sel: fn(&(f64, f64)) -> f64| {
        pts.iter().map(sel).fold(init, f)
    };
    (
        (
            fold(f64::min, f64::INFINITY, |p| p.0).max(1e-6),
            fold(f64::max, 0.0, |p| p.0).max(1e-5),
        ),
        (
            fold(f64::min, f64::INFINITY, |p| p.1).max(1e-3),
            fold(f64::max, 0.0, |p| p.1).max(1e-2),
        ),
    )
}

/// One point series per method family (in sweep order), each with a legend entry.
fn draw_families(
    ch: &mut LogChart<'_, '_>,
    sw: &Sweep,
    pts: &[(f64, f64)],
) -> Result<(), TradeoffError> {
    let mut families: Vec<String> = Vec::new();
    for r in &sw.rows {
        if !families.contains(&r.setting.method) {
            families.push(r.setting.method.clone());
        }
    }
    for fam in &families {
        let c = family_colour(fam);
        let series: Vec<(f64, f64)> = sw
            .rows
            .iter()
            .zip(pts)
            .filter(|(r, _)| &r.setting.method == fam)
            .map(|(_, p)| *p)
            .collect();
        ch.draw_series(series.iter().map(|&p| Circle::new(p, 5, c.filled())))
            .map_err(plot_err("points"))?
            .label(fam.as_str())
            .legend(move |(x, y)| Circle::new((x + 8, y), 5, c.filled()));
    }
    Ok(())
}

/// The Pareto frontier: a line through its points, ringed and labelled.
fn draw_frontier(
    ch: &mut LogChart<'_, '_>,
    sw: &Sweep,
    pts: &[(f64, f64)],
    front: &[usize],
) -> Result<(), TradeoffError> {
    let line: Vec<(f64, f64)> = front.iter().map(|&k| pts[k]).collect();
    ch.draw_series(LineSeries::new(line.clone(), BLACK.stroke_width(2)))
        .map_err(plot_err("frontier"))?
        .label("Pareto frontier")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
    ch.draw_series(
        line.iter()
            .map(|&p| Circle::new(p, 8, BLACK.stroke_width(2))),
    )
    .map_err(plot_err("frontier"))?;
    for &k in front {
        let r = &sw.rows[k];
        let label = format!("{} {}", r.setting.method, r.setting.setting);
        ch.draw_series(std::iter::once(
            EmptyElement::at(pts[k])
                + Text::new(
                    label,
                    (10, -4),
                    ("sans-serif", 13).into_font().color(&BLACK),
                ),
        ))
        .map_err(plot_err("labels"))?;
    }
    Ok(())
}

/// Maps an absolute error on 0..255 to a colour: black (0) → red → yellow → white (≥ 64).
fn heat_colour(e: f64) -> [u8; 3] {
    let t = (e / 64.0).clamp(0.0, 1.0) * 3.0;
    let c = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [c(t), c(t - 1.0), c(t - 2.0)]
}

/// A montage of difference heat maps for the kept scene: per setting, the largest channel
/// error against the reference of its filter per pixel (black 0, red, yellow, white ≥ 64), the tiles
/// labelled. Returns (RGB8, width, height).
pub fn heat_montage(sw: &Sweep) -> Result<Option<(Vec<u8>, u32, u32)>, TradeoffError> {
    let Some(h) = &sw.heat else { return Ok(None) };
    register_font()?;
    let scale = if h.width <= 128 { 2 } else { 1 };
    let (tw, th) = (h.width * scale, h.height * scale);
    let label_h = 18;
    let cols = 8u32;
    let n = h.images.len() as u32;
    let rows = n.div_ceil(cols);
    let pad = 6;
    let (w, hh) = (
        cols * (tw + pad) + pad,
        rows * (th + label_h + pad) + pad + 24,
    );
    let mut buf = vec![255u8; (w * hh * 3) as usize];
    for (k, img) in h.images.iter().enumerate() {
        let rf = h.reference_of[k].map_or(&h.reference, |i| &h.filtered[i]);
        let (cx, cy) = (k as u32 % cols, k as u32 / cols);
        let (ox, oy) = (
            pad + cx * (tw + pad),
            24 + pad + cy * (th + label_h + pad) + label_h,
        );
        for y in 0..th {
            for x in 0..tw {
                let p = ((y / scale) * h.width + x / scale) as usize;
                let e = (0..3)
                    .map(|ch| (img[3 * p + ch] as f64 - rf[p][ch]).abs())
                    .fold(0.0, f64::max);
                let o = (((oy + y) * w + ox + x) * 3) as usize;
                buf[o..o + 3].copy_from_slice(&heat_colour(e));
            }
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, hh)).into_drawing_area();
        root.draw(&Text::new(
            format!(
                "|error| per pixel on scene '{}' (black 0, red 21, yellow 43, white ≥ 64 of 255)",
                h.scene
            ),
            (pad as i32, 4),
            ("sans-serif", 16).into_font().color(&BLACK),
        ))
        .map_err(plot_err("heat title"))?;
        for (k, row) in sw.rows.iter().enumerate() {
            let (cx, cy) = (k as u32 % cols, k as u32 / cols);
            let (ox, oy) = (pad + cx * (tw + pad), 24 + pad + cy * (th + label_h + pad));
            root.draw(&Text::new(
                format!("{} {}", row.setting.method, row.setting.setting),
                (ox as i32, oy as i32 + 2),
                ("sans-serif", 12).into_font().color(&BLACK),
            ))
            .map_err(plot_err("heat labels"))?;
        }
        root.present().map_err(plot_err("heat"))?;
    }
    Ok(Some((buf, w, hh)))
}
