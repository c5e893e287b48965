//! Runs a plan: the parts [`Plan`] lists, in order, each stage timed. Each part hands
//! its output to the next as a value (the array's frame and shadow table, the
//! anti-aliased image), so a stage cannot run before what it reads. The one stage that
//! reads only the scene, the shadow casters, runs alongside the front end and span
//! setup.

use crate::frontend::{self, FrontError, Projected};
use crate::plan::{AaMethod, Aov, ArrayPlan, Effects, Plan, Stage};
use crate::render::{render_frame_with, Frame, RowExtra, SpanSource};
use crate::scene::LoadedScene;
use crate::setup::SetupError;
use crate::shadow::{self, FactorTable, ShadowError, ShadowLight, ShadowRows, ShadowStats};
use crate::stream::StreamError;
use crate::{aa, abuffer};
use rayon::prelude::*;
use std::time::{Duration, Instant};
use thiserror::Error;

mod shadow_samples;

/// Render errors.
#[derive(Debug, Error)]
pub enum RenderError {
    /// Front end, span setup or shadow volumes (the stages of the command stream).
    #[error(transparent)]
    Stream(#[from] StreamError),
    /// Anti-aliasing failure.
    #[error(transparent)]
    Aa(#[from] aa::AaError),
    /// A-buffer failure.
    #[error(transparent)]
    Abuffer(#[from] abuffer::AbufferError),
}

/// The stream stages' own errors convert through [`StreamError`], so `?` works on each.
macro_rules! via_stream {
    ($($t:ty),*) => {$(
        impl From<$t> for RenderError {
            fn from(e: $t) -> Self {
                RenderError::Stream(e.into())
            }
        }
    )*};
}
via_stream!(FrontError, SetupError, ShadowError);

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

/// Wall time of each stage that ran, in order.
type Timings = Vec<(Stage, Duration)>;

/// Runs one stage and records its wall time.
fn timed<T>(timings: &mut Timings, stage: Stage, run: impl FnOnce() -> T) -> T {
    let t0 = Instant::now();
    let out = run();
    timings.push((stage, t0.elapsed()));
    out
}

/// What the pixel-processor array's stages hand on.
struct ArrayOut {
    /// Span words generated (OP spans over all rows).
    span_words: u64,
    /// The array's final per-pixel state.
    frame: Frame,
    /// The shadow factor table, when shadows were shaded.
    table: Option<FactorTable>,
    /// Shadow statistics.
    shadow: ShadowStats,
}

/// What the anti-aliasing stage hands on.
struct AaOut {
    /// The image, RGB8.
    rgb: Vec<u8>,
    /// The A-buffer's coverage per pixel, scaled to 0..=255.
    coverage: Option<Vec<u8>>,
    /// The method's counters.
    report: AaReport,
}

/// Renders a loaded scene with the given effects, following [`Plan::new`].
pub fn render(ls: &LoadedScene, fx: &Effects) -> Result<RenderOutput, RenderError> {
    let (w, h) = (ls.scene.width, ls.scene.height);
    let bg = ls
        .scene
        .background
        .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    let lights: Vec<ShadowLight> = shadow::shadow_lights(ls, &fx.shadow_lights)?;
    let shape = Plan::new(fx);
    let mut timings = Timings::new();
    let shadows = shape.array().is_some_and(|a| !a.shadow_lights.is_empty());
    // The front end and span setup, with the shadow casters found alongside: they depend
    // on neither the camera nor a light, and their meshes' welding and convexity tests
    // fill the cores where the two stages run on one (their serial parts). Timed as the
    // wall time they add after span setup is done. Without shadows the two stages run
    // alone, on the calling thread.
    let front = |timings: &mut Timings| -> Result<_, RenderError> {
        let projected = timed(timings, Stage::FrontEnd, || {
            frontend::project_shaded(ls, fx.shade_channels())
        })?;
        let src = match shape.array() {
            Some(_) => Some(timed(timings, Stage::SpanSetup, || {
                SpanSource::new(&projected.array_tris(), w, h)
            })?),
            None => None,
        };
        Ok((projected, src))
    };
    let (projected, src, occ) = if shadows {
        let t0 = Instant::now();
        let (first, occ) = rayon::join(
            || front(&mut timings).map(|f| (f, t0.elapsed())),
            || shadow::occluders(ls),
        );
        let ((projected, src), ahead) = first?;
        timings.push((Stage::ShadowCasters, t0.elapsed().saturating_sub(ahead)));
        (projected, src, occ)
    } else {
        let (projected, src) = front(&mut timings)?;
        (projected, src, Vec::new())
    };
    let ctx_of = |a| ArrayCtx {
        ls,
        fx,
        a,
        lights: &lights,
        occ: &occ,
        bg,
    };
    let run = |a, timings: &mut Timings| match &src {
        Some(src) => run_array(&ctx_of(a), src, timings),
        None => unreachable!("span setup runs for every plan with an array"),
    };
    // Under anti-aliasing: the shadowed fraction per pixel from the method's own samples,
    // and how many sample lattices the array rendered for it.
    let mut fraction: Option<Vec<u8>> = None;
    let mut shadow_passes = 0;
    let (data, array, aa) = match &shape {
        Plan::Array(a) => {
            let arr = run(a, &mut timings)?;
            (arr.frame.rgb8(), Some(arr), None)
        }
        Plan::Antialias { method, array, .. } => {
            let arr = match array {
                Some(a) => Some(run(a, &mut timings)?),
                None => None,
            };
            let stage = Stage::Antialias(*method);
            let shadowed = arr
                .as_ref()
                .and_then(|a| a.table.as_ref().map(|t| (&a.frame, t)));
            if let (AaMethod::PostFx(p), Some((frame, t))) = (&fx.aa, shadowed) {
                // Post-processing starts from the shaded baseline and treats shadow
                // boundaries as edges (`aa::postfx::render_with`).
                let (mut out, f) = timed(&mut timings, stage, || {
                    postfx_shadowed(&projected, w, h, bg, p, frame, t)
                })?;
                fraction = f;
                (std::mem::take(&mut out.rgb), arr, Some(out))
            } else {
                let coverage = matches!(shape, Plan::Antialias { coverage: true, .. });
                let mut out = timed(&mut timings, stage, || {
                    run_aa(&projected, w, h, bg, &fx.aa, coverage)
                })?;
                if let (
                    Some(ArrayOut {
                        frame,
                        table: Some(t),
                        ..
                    }),
                    Some(a),
                ) = (&arr, array)
                {
                    let sampled = timed(&mut timings, Stage::ShadowApply, || {
                        let inp = shadow_samples::PassInput {
                            ctx: ctx_of(a),
                            table: t,
                        };
                        shadow_samples::sample_shadows(&inp, &fx.aa, &mut out.rgb)
                    })?;
                    match sampled {
                        Some(s) => {
                            shadow_passes = s.passes;
                            fraction = Some(s.fraction);
                        }
                        // A method without a sample lattice of its own would take the
                        // array's centre samples (every lattice-less method is handled
                        // above; kept so a new method cannot silently lose its shadows).
                        None => shadow::apply_to_rgb8(&mut out.rgb, frame, t),
                    }
                }
                (std::mem::take(&mut out.rgb), arr, Some(out))
            }
        }
    };
    let mut aovs = Vec::new();
    if let (Some(arr), Some(a)) = (&array, shape.array()) {
        for &aov in &a.aovs {
            let img = timed(&mut timings, Stage::Aov(aov), || match (&fraction, aov) {
                (Some(f), Aov::Shadow) => Image {
                    width: w,
                    height: h,
                    channels: 1,
                    data: f.clone(),
                },
                _ => aov_image(aov, &arr.frame, arr.table.as_ref()),
            });
            aovs.push((aov, img));
        }
    }
    if let (
        Plan::Antialias { coverage: true, .. },
        Some(AaOut {
            coverage: Some(c), ..
        }),
    ) = (&shape, &aa)
    {
        let img = timed(&mut timings, Stage::Aov(Aov::Coverage), || Image {
            width: w,
            height: h,
            channels: 1,
            data: c.clone(),
        });
        aovs.push((Aov::Coverage, img));
    }
    let (span_words, shadow, frame) = match array {
        Some(a) => (
            a.span_words,
            ShadowStats {
                sample_passes: shadow_passes,
                ..a.shadow
            },
            Some(a.frame),
        ),
        None => (0, ShadowStats::default(), None),
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
        triangles: projected.tris.len(),
        span_words,
        shadow,
        frame,
        aa: aa.map(|a| a.report),
    })
}

/// The array's stages after span setup (`src`): each light's shadow volumes, the array,
/// shadow shading.
fn run_array(
    ctx: &ArrayCtx,
    src: &SpanSource,
    timings: &mut Timings,
) -> Result<ArrayOut, RenderError> {
    let ArrayCtx { ls, fx, a, .. } = *ctx;
    // Shadows need a camera: planning allows them only for 3-D scenes.
    let pj = (!a.shadow_lights.is_empty()).then(|| frontend::Projector::new(ls));
    // With shadows, each row is shaded as it is read out of the array (the core's shade
    // unit), in the array's stage.
    let table =
        (!a.shadow_lights.is_empty()).then(|| FactorTable::for_mode(ls, ctx.lights, fx.shading));
    let (frame, stats) = ctx.draw(src, pj.as_ref(), table.as_ref(), timings)?;
    Ok(ArrayOut {
        span_words: src.span_count() as u64,
        frame,
        table,
        shadow: stats,
    })
}

/// What the array draws a frame with: the scene, its effects and array plan, the
/// shadowing lights and the background.
#[derive(Clone, Copy)]
pub(super) struct ArrayCtx<'a> {
    /// The scene.
    pub ls: &'a LoadedScene,
    /// Its effects.
    pub fx: &'a Effects,
    /// The array's part of the plan.
    pub a: &'a ArrayPlan,
    /// The shadowing lights.
    pub lights: &'a [ShadowLight],
    /// The scene's shadow casters ([`shadow::occluders`]; empty without shadows).
    pub occ: &'a [shadow::Occluder],
    /// Background colour.
    pub bg: [u8; 3],
}

impl ArrayCtx<'_> {
    /// The array drawing a frame: each shadowing light's volumes through `pj` set up
    /// (timed as their own stages), then the span words of `src` with those volumes'
    /// shadow commands behind each row's spans, applied as the rows are drawn. Each row is
    /// shaded by `table` at readout, if given.
    fn draw(
        &self,
        src: &SpanSource,
        pj: Option<&frontend::Projector>,
        table: Option<&FactorTable>,
        timings: &mut Timings,
    ) -> Result<(Frame, ShadowStats), RenderError> {
        let mut shadows: Option<ShadowRows> = None;
        if let Some(pj) = pj {
            for &light in &self.a.shadow_lights {
                let more = timed(timings, Stage::ShadowVolumes { light }, || {
                    self.shadow_volumes(pj, light)
                })?;
                match &mut shadows {
                    Some(s) => s.append(more),
                    None => shadows = Some(more),
                }
            }
        }
        let extra = match &shadows {
            Some(s) => RowExtra::Shadows(s),
            None => RowExtra::Stored(&[]),
        };
        let frame = timed(timings, Stage::PixelArray, || {
            render_frame_with(src, self.bg, self.fx.array_width, extra, |row, more| {
                if let Some(t) = table {
                    shadow::shade_row(row, more, t)
                }
            })
        });
        let stats = shadows.map_or_else(ShadowStats::default, |s| s.stats());
        Ok((frame, stats))
    }

    /// One light's shadow volumes, set up.
    fn shadow_volumes(
        &self,
        pj: &frontend::Projector,
        light: usize,
    ) -> Result<ShadowRows, RenderError> {
        let l: Vec<ShadowLight> = self
            .lights
            .iter()
            .filter(|x| x.index == light)
            .cloned()
            .collect();
        Ok(ShadowRows::new(
            self.occ,
            self.ls,
            pj,
            &l,
            self.fx.shadow_form,
        )?)
    }
}

/// Post-processing of the array's shadowed baseline: the image and the shadowed fraction.
fn postfx_shadowed(
    projected: &Projected,
    w: u32,
    h: u32,
    bg: [u8; 3],
    p: &aa::PostFxParams,
    frame: &Frame,
    t: &FactorTable,
) -> Result<(AaOut, Option<Vec<u8>>), RenderError> {
    let rgb = frame.rgb8();
    let level: Vec<u8> = frame.px.iter().map(|s| t.shadow_level(s)).collect();
    let base = aa::postfx::ShadowedBaseline {
        rgb: &rgb,
        level: &level,
    };
    let (f, fraction) = aa::postfx::render_with(&projected.tris, w, h, bg, p, Some(base), false)?;
    Ok((
        AaOut {
            rgb: f.rgb,
            coverage: None,
            report: AaReport::Other(f.stats),
        },
        fraction,
    ))
}

/// The anti-aliasing stage; the A-buffer's coverage image only when `coverage` (the plan
/// asks for it). No other per-pixel output of a method is made.
fn run_aa(
    projected: &Projected,
    w: u32,
    h: u32,
    bg: [u8; 3],
    method: &AaMethod,
    coverage: bool,
) -> Result<AaOut, RenderError> {
    let tris = &projected.tris;
    Ok(if let AaMethod::Abuffer(p) = method {
        let aovs = abuffer::AbufferAovs {
            coverage,
            ..abuffer::AbufferAovs::NONE
        };
        let a = abuffer::render_abuffer_with(tris, w, h, bg, p, aovs)?;
        let full = p.size.bits();
        AaOut {
            coverage: coverage.then(|| {
                a.coverage
                    .par_iter()
                    .map(|&c| (c as u32 * 255 / full) as u8)
                    .collect()
            }),
            rgb: a.rgb,
            report: AaReport::Abuffer(a.stats),
        }
    } else {
        let f = aa::render_aa_with(tris, w, h, bg, method, false)?;
        AaOut {
            rgb: f.rgb,
            coverage: None,
            report: AaReport::Other(f.stats),
        }
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
