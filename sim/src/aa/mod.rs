//! Anti-aliasing methods behind one interface: [`render_aa`].
//!
//! | method | seed | module |
//! |---|---|---|
//! | none (the pixel-processor array, one sample at each pixel centre) | 001 | [`crate::render`] |
//! | multi-scanning, box or axisymmetric filter | 002 (Nishita & Nakamae) §2.2, §3 | [`multiscan`] |
//! | corner-shared sampling, D3D 4×, ordered 2×2 | 003 (JP4801088B2) | [`corner`] |
//! | post-process from z and normals | 004 (CN1674049) | [`postfx`] |
//! | A-buffer with the depth search unit | 000 (JP2569952B2) | [`crate::abuffer`] |
//! | k×k supersampling, box resolve | (comparison) | [`ssaa`] |
//!
//! Every method takes the same input (snapped screen-space triangles in scene order, a
//! screen size and a background colour) and returns an [`AaFrame`]: RGB8, the per-pixel
//! visible triangle (the one with the largest weight in the pixel, where the method knows
//! it) and cost counters. All methods are integer arithmetic on documented formats; the
//! exact reference they are judged against is [`crate::reference`].

pub mod corner;
pub mod multiscan;
pub mod postfx;
pub mod sampler;
pub mod shadow_samples;
pub mod ssaa;

use std::time::Instant;

use thiserror::Error;

use crate::raster::{SpanRaster, VisibleProbe};
use crate::render::{render_frame, SpanSource};
use crate::setup::{SetupError, SnappedTri, TriSetup};

pub use corner::{CornerParams, CornerWeights, Pattern};
pub use multiscan::{Filter, MultiscanParams};
pub use postfx::PostFxParams;

/// Errors of the anti-aliasing renderers (bad parameters or bad input geometry).
#[derive(Debug, Error, PartialEq)]
pub enum AaError {
    /// A triangle could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A method parameter outside its supported range.
    #[error("invalid parameter: {0}")]
    Param(String),
    /// Screen size zero or above the format limit.
    #[error("screen size {0}×{1} is not supported (1..=4096)")]
    Screen(u32, u32),
}

impl From<crate::abuffer::AbufferError> for AaError {
    fn from(e: crate::abuffer::AbufferError) -> AaError {
        match e {
            crate::abuffer::AbufferError::Setup(s) => AaError::Setup(s),
            crate::abuffer::AbufferError::ScreenTooLarge(w, h) => AaError::Screen(w, h),
        }
    }
}

/// Which method, with its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum AaMethod {
    /// No anti-aliasing: the pixel-processor array baseline.
    None,
    /// Multi-scanning (seed 002).
    Multiscan(MultiscanParams),
    /// Corner-shared sampling and the comparison patterns (seed 003).
    Corner(CornerParams),
    /// Post-process anti-aliasing on the baseline's depth and colour (seed 004).
    PostFx(PostFxParams),
    /// The A-buffer with the depth search unit (seed 000), [`crate::abuffer`].
    Abuffer(crate::abuffer::AbufferParams),
    /// `k × k` ordered supersampling with a box resolve.
    Ssaa {
        /// Samples per pixel along each axis, 1..=64.
        k: u32,
    },
}

impl AaMethod {
    /// A short label for reports, e.g. `multiscan n=3 box`.
    pub fn label(&self) -> String {
        match self {
            AaMethod::None => "none".into(),
            AaMethod::Multiscan(p) => {
                format!("multiscan n={} {:?}", p.subscanlines, p.filter).to_lowercase()
            }
            AaMethod::Corner(p) => p.label(),
            AaMethod::PostFx(p) => p.label(),
            AaMethod::Ssaa { k } => format!("ssaa {k}x{k}"),
            AaMethod::Abuffer(p) => format!("abuffer {} {}", p.size, p.depth.name()),
        }
    }
}

/// Cost counters of one rendering.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AaStats {
    /// Plane depth evaluations (per sample or per crossing, as the method does them).
    pub depth_evals: u64,
    /// Samples (or sub-scanline pieces) shaded and stored.
    pub samples_written: u64,
    /// Sample-memory (or pixel-memory) reads made by the resolve.
    pub sample_reads: u64,
    /// Pixels resolved (width × height), set by each method where it makes its counters
    /// (the pipeline reaches the post-process of a shadowed baseline without
    /// [`render_aa`]).
    pub pixels: u64,
    /// Wall-clock time of [`render_aa`], seconds.
    pub seconds: f64,
}

impl AaStats {
    /// Resolve reads per pixel.
    pub fn reads_per_pixel(&self) -> f64 {
        self.sample_reads as f64 / self.pixels.max(1) as f64
    }
    /// Depth evaluations per pixel.
    pub fn depth_evals_per_pixel(&self) -> f64 {
        self.depth_evals as f64 / self.pixels.max(1) as f64
    }
}

/// The result of [`render_aa`].
#[derive(Clone, Debug)]
pub struct AaFrame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGB8, row-major.
    pub rgb: Vec<u8>,
    /// Row-major visible triangle per pixel (input index; −1 background): the surface with
    /// the largest weight in the pixel. Post-processing reports the baseline's (it only
    /// blends colours). `None` when the caller asked for no visible-triangle AOV
    /// ([`render_aa_with`]).
    pub visible: Option<Vec<i32>>,
    /// Cost counters.
    pub stats: AaStats,
}

/// Checks the screen size.
pub(crate) fn check_screen(width: u32, height: u32) -> Result<(), AaError> {
    if width == 0 || height == 0 || width > 4096 || height > 4096 {
        return Err(AaError::Screen(width, height));
    }
    Ok(())
}

/// Checks every triangle for setup errors (range of coordinates and depths).
pub(crate) fn check_tris(tris: &[SnappedTri]) -> Result<(), AaError> {
    for t in tris {
        TriSetup::new(t)?;
    }
    Ok(())
}

/// Renders `tris` with `method`. The one entry point for the CLI and the trade-off sweep.
pub fn render_aa(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    method: &AaMethod,
) -> Result<AaFrame, AaError> {
    render_aa_with(tris, width, height, bg, method, true)
}

/// [`render_aa`], with `visible` false when the caller does not need the visible-triangle
/// AOV: a method may then skip work that only that AOV needs (the post-process skips a
/// second scan of every span word, multi-scanning the weights per triangle of each
/// pixel, the A-buffer its visible-surface choice per pixel) and leave
/// [`AaFrame::visible`] `None`. The image and the counters are the same either way.
pub fn render_aa_with(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    method: &AaMethod,
    visible: bool,
) -> Result<AaFrame, AaError> {
    check_screen(width, height)?;
    check_tris(tris)?;
    let t0 = Instant::now();
    let mut f = match method {
        AaMethod::None => render_none(tris, width, height, bg)?,
        AaMethod::Multiscan(p) => multiscan::render_with(tris, width, height, bg, p, visible)?,
        AaMethod::Corner(p) => corner::render_with(tris, width, height, bg, p, visible)?,
        AaMethod::PostFx(p) => {
            postfx::render_with(tris, width, height, bg, p, None, visible).map(|(f, _)| f)?
        }
        AaMethod::Ssaa { k } => ssaa::render_with(tris, width, height, bg, *k, visible)?,
        AaMethod::Abuffer(p) => {
            let aovs = crate::abuffer::AbufferAovs {
                visible,
                ..crate::abuffer::AbufferAovs::NONE
            };
            let a = crate::abuffer::render_abuffer_with(tris, width, height, bg, p, aovs)?;
            AaFrame {
                width,
                height,
                rgb: a.rgb,
                visible: visible.then_some(a.visible),
                stats: AaStats {
                    depth_evals: a.stats.depth_evals,
                    samples_written: a.stats.fragments,
                    // The resolve reads each stored fragment once.
                    sample_reads: a.stats.fragments,
                    pixels: width as u64 * height as u64,
                    ..Default::default()
                },
            }
        }
    };
    f.stats.seconds = t0.elapsed().as_secs_f64();
    Ok(f)
}

/// The baseline: the golden pixel-processor array, one sample per pixel centre. The
/// visible triangle per pixel is found by replaying the array's depth test on the same
/// span words with the triangle index attached.
fn render_none(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
) -> Result<AaFrame, AaError> {
    let src = SpanSource::new(tris, width, height)?;
    let frame = render_frame(&src, bg, width as usize, &[]);
    let (visible, evals) = baseline_visible(tris, width, height)?;
    Ok(AaFrame {
        width,
        height,
        rgb: frame.rgb8(),
        visible: Some(visible),
        stats: AaStats {
            depth_evals: evals,
            samples_written: width as u64 * height as u64,
            sample_reads: width as u64 * height as u64,
            pixels: width as u64 * height as u64,
            ..Default::default()
        },
    })
}

/// Per-pixel visible triangle of the baseline (same span words and depth test as the
/// array, through the raster core's visibility probe), and the number of depth tests made.
pub(crate) fn baseline_visible(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
) -> Result<(Vec<i32>, u64), AaError> {
    let mut probe = VisibleProbe::new(width, height);
    SpanRaster::new(tris, width, height)?.scan(&mut probe);
    Ok((probe.visible, probe.depth_tests))
}

/// Number of distinct grey levels a method gives the pixels along a long, nearly
/// horizontal (`vertical = false`) or nearly vertical white edge on black: the edge
/// `y = 8.5 − x/64` (transposed for vertical) across a 64×16 (16×64) screen, rows
/// (columns) 6..10 counted, so 0 and 255 are among the levels.
pub fn edge_shade_levels(method: &AaMethod, vertical: bool) -> Result<usize, AaError> {
    let q = |x: f64| (x * 256.0).round() as i32;
    let white = [(255u32 << 12) + 2048; 3];
    let (mut a, mut b, mut c) = ([-4.0, 8.5625], [68.0, 7.4375], [-4.0, 40.0]);
    let (w, h) = if vertical { (16, 64) } else { (64, 16) };
    if vertical {
        for p in [&mut a, &mut b, &mut c] {
            p.swap(0, 1);
        }
    }
    let t = SnappedTri {
        v: [a, b, c].map(|p| [q(p[0]), q(p[1])]),
        z: [1000; 3],
        c: [white; 3],
        ..Default::default()
    };
    let f = render_aa(&[t], w, h, [0, 0, 0], method)?;
    let mut levels = std::collections::BTreeSet::new();
    for k in 0..64u32 {
        for d in 6..10u32 {
            let (x, y) = if vertical { (d, k) } else { (k, d) };
            levels.insert(f.rgb[3 * (y * w + x) as usize]);
        }
    }
    Ok(levels.len())
}
