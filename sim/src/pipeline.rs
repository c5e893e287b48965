//! Runs a plan: the stages [`crate::plan::plan`] lists, in order, each timed.

use crate::frontend::{self, FrontError, Projected};
use crate::pixel_array::Command;
use crate::plan::{plan, Aov, Effects, Stage};
use crate::render::{render_frame, Frame, SpanSource};
use crate::scene::LoadedScene;
use crate::setup::SetupError;
use crate::shadow::{self, FactorTable, ShadowError, ShadowLight, ShadowStats};
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
    /// The array's final per-pixel state (depth, flags, light mask, counter).
    pub frame: Frame,
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
            Stage::Aov(a) => {
                let f = frame.as_ref().expect("array runs first");
                aovs.push((*a, aov_image(*a, f, table.as_ref())));
            }
        }
        timings.push((stage, t0.elapsed()));
    }
    let f = frame.expect("the plan always renders a frame");
    let span_words = src.as_ref().expect("setup ran").span_count() as u64;
    Ok(RenderOutput {
        image: Image {
            width: w,
            height: h,
            channels: 3,
            data: f.rgb8(),
        },
        aovs,
        timings,
        triangles: projected.map(|p| p.tris.len()).unwrap_or(0),
        span_words,
        shadow: shadow_stats,
        frame: f,
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
