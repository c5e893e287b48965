//! Runs a plan: the stages [`crate::plan::plan`] lists, in order, each timed.

use crate::frontend::{self, FrontError, Projected};
use crate::pixel_array::Command;
use crate::plan::{plan, AaMethod, Aov, Effects, Stage};
use crate::render::{render_frame, Frame, SpanSource};
use crate::scene::LoadedScene;
use crate::setup::SetupError;
use crate::shadow::{self, FactorTable, ShadowError, ShadowLight, ShadowStats};
use crate::{aa, abuffer};
use std::time::{Duration, Instant};
use thiserror::Error;

/// Render errors.
#[derive(Debug, Error)]
pub enum RenderError {
    /// Front-end failure.
    #[error(transparent)]
    Front(#[from] FrontError),
    /// Setup failure.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// Shadow failure.
    #[error(transparent)]
    Shadow(#[from] ShadowError),
    /// Anti-aliasing failure.
    #[error(transparent)]
    Aa(#[from] aa::AaError),
    /// A-buffer failure.
    #[error(transparent)]
    Abuffer(#[from] abuffer::AbufferError),
}

/// An 8-bit image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Channels per pixel (1 or 3).
    pub channels: u8,
    /// Row-major samples.
    pub data: Vec<u8>,
}

/// What a render produced.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// The image.
    pub image: Image,
    /// Debug images.
    pub aovs: Vec<(Aov, Image)>,
    /// Each stage that ran and its wall time.
    pub timings: Vec<(Stage, Duration)>,
    /// Snapped triangles fed to setup.
    pub triangles: usize,
    /// Span words generated (OP spans over all rows).
    pub span_words: u64,
    /// Shadow statistics (zero without shadows).
    pub shadow: ShadowStats,
    /// The array's final per-pixel state (depth, flags, light mask, counter), when the
    /// plan ran the array.
    pub frame: Option<Frame>,
    /// Counters of the anti-aliasing method, when one ran.
    pub aa: Option<AaReport>,
}

/// Counters of the anti-aliasing stage.
#[derive(Clone, Debug)]
pub enum AaReport {
    /// The A-buffer's own statistics.
    Abuffer(abuffer::AbufferStats),
    /// Another method's counters.
    Other(aa::AaStats),
}

/// Renders a loaded scene with the given effects.
pub fn render(ls: &LoadedScene, fx: &Effects) -> Result<RenderOutput, RenderError> {
    let (w, h) = (ls.scene.width, ls.scene.height);
    let bg = ls
        .scene
        .background
        .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    let mut timings = Vec::new();
    let mut projected: Option<Projected> = None;
    let mut src: Option<SpanSource> = None;
    let mut frame: Option<Frame> = None;
    let mut aovs = Vec::new();
    let lights: Vec<ShadowLight> = shadow::shadow_lights(ls, &fx.shadow_lights)?;
    let mut shadow_rows: Vec<Vec<Command>> = vec![Vec::new(); h as usize];
    let mut shadow_stats = ShadowStats::default();
    let mut table: Option<FactorTable> = None;
    let mut aa_rgb: Option<Vec<u8>> = None;
    let mut coverage: Option<Vec<u8>> = None;
    let mut aa_stats = None;
    for stage in plan(fx) {
        let t0 = Instant::now();
        match &stage {
            Stage::FrontEnd => projected = Some(frontend::project(ls)?),
            Stage::SpanSetup => {
                let p = projected.as_ref().expect("front end runs first");
                src = Some(SpanSource::new(&p.tris, w, h)?);
            }
            Stage::ShadowVolumes { light } => {
                let pj = frontend::Projector::new(ls);
                let l: Vec<ShadowLight> = lights
                    .iter()
                    .filter(|x| x.index == *light)
                    .cloned()
                    .collect();
                let sc = shadow::shadow_commands(ls, &pj, &l, fx.shadow_form)?;
                for (dst, src) in shadow_rows.iter_mut().zip(sc.rows) {
                    dst.extend(src);
                }
                shadow_stats.volumes += sc.stats.volumes;
                shadow_stats.span_words += sc.stats.span_words;
                shadow_stats.eye_inside += sc.stats.eye_inside;
            }
            Stage::PixelArray => {
                let s = src.as_ref().expect("setup runs first");
                let rows = &shadow_rows;
                frame = Some(render_frame(s, bg, fx.array_width, |j, cmds| {
                    cmds.extend_from_slice(&rows[j as usize])
                }));
            }
            Stage::ShadowShade => {
                let t = FactorTable::new(ls, &lights);
                shadow::shade(&mut frame.as_mut().expect("array runs first").px, &t);
                table = Some(t);
            }
            Stage::Antialias(_) => {
                let tris = &projected.as_ref().expect("front end runs first").tris;
                if let AaMethod::Abuffer(p) = &fx.aa {
                    let a = abuffer::render_abuffer(tris, w, h, bg, p)?;
                    let full = p.size.bits();
                    coverage = Some(
                        a.coverage
                            .iter()
                            .map(|&c| (c as u32 * 255 / full) as u8)
                            .collect(),
                    );
                    aa_rgb = Some(a.rgb);
                    aa_stats = Some(AaReport::Abuffer(a.stats));
                } else {
                    let f = aa::render_aa(tris, w, h, bg, &fx.aa)?;
                    aa_rgb = Some(f.rgb);
                    aa_stats = Some(AaReport::Other(f.stats));
                }
            }
            Stage::ShadowApply => {
                let t = table.as_ref().expect("shadow shading runs first");
                let f = frame.as_ref().expect("array runs first");
                let img = aa_rgb.as_mut().expect("anti-aliasing runs first");
                shadow::apply_to_rgb8(img, &f.px, t);
            }
            Stage::Aov(a) => {
                let img = match (a, &coverage) {
                    (Aov::Coverage, Some(c)) => Image {
                        width: w,
                        height: h,
                        channels: 1,
                        data: c.clone(),
                    },
                    _ => aov_image(
                        *a,
                        frame
                            .as_ref()
                            .expect("the plan runs the array for this AOV"),
                        table.as_ref(),
                    ),
                };
                aovs.push((*a, img));
            }
        }
        timings.push((stage, t0.elapsed()));
    }
    let span_words = src.as_ref().map(|s| s.span_count() as u64).unwrap_or(0);
    let data = match aa_rgb {
        Some(rgb) => rgb,
        None => frame
            .as_ref()
            .expect("the plan renders a frame or an AA image")
            .rgb8(),
    };
    Ok(RenderOutput {
        image: Image {
            width: w,
            height: h,
            channels: 3,
            data,
        },
        aovs,
        timings,
        triangles: projected.map(|p| p.tris.len()).unwrap_or(0),
        span_words,
        shadow: shadow_stats,
        frame,
        aa: aa_stats,
    })
}

/// A debug image from the array's state.
fn aov_image(a: Aov, f: &Frame, table: Option<&FactorTable>) -> Image {
    let data: Vec<u8> = match a {
        // Depth: near = bright, background = black; scaled to the frame's range.
        Aov::Depth => {
            let zs =
                f.px.iter()
                    .map(|s| s.zb)
                    .filter(|&z| z != pixelproc_formats::Z_FAR);
            let (lo, hi) = zs.fold((u32::MAX, 0), |(l, h), z| (l.min(z), h.max(z)));
            f.px.iter()
                .map(|s| {
                    if s.zb == pixelproc_formats::Z_FAR || hi <= lo {
                        if s.zb == pixelproc_formats::Z_FAR {
                            0
                        } else {
                            255
                        }
                    } else {
                        (255 - ((s.zb - lo) as u64 * 223 / (hi - lo) as u64) as u32) as u8
                    }
                })
                .collect()
        }
        // Shadowed fraction of the lights (penumbra for an area light); 0 without shadows.
        Aov::Shadow => {
            f.px.iter()
                .map(|s| table.map(|t| t.shadow_level(s)).unwrap_or(0))
                .collect()
        }
        Aov::Coverage => {
            f.px.iter()
                .map(|s| {
                    if s.zb == pixelproc_formats::Z_FAR {
                        0
                    } else {
                        255
                    }
                })
                .collect()
        }
    };
    Image {
        width: f.width,
        height: f.height,
        channels: 1,
        data,
    }
}
