//! Post-process anti-aliasing from the depth buffer (seed 004, Sony CN1674049).
//!
//! Input: the baseline's finished colour and 24-bit depth buffers (the pixel-processor
//! array, one sample per pixel). Nothing is drawn again.
//!
//! **Edge bits (seed 004, "edges from the z-buffer", "edges from normals").** Edges are
//! kept *between* pixels: `ex(x, y)` between (x, y) and (x+1, y), `ey(x, y)` between
//! (x, y) and (x, y+1) (the seed's per-pixel "edge" bit plus its "which side" bit).
//! - z second differences: `d2x(x) = z(x+1) + z(x−1) − 2z(x)` (borders replicate). If
//!   `|d2x(x)| > Zth` the pixel is on an edge, on the side with the larger first
//!   difference `|z(x±1) − z(x)|`. Likewise in y.
//! - normals (optional): reconstructed from z, `n = (z(x+1) − z(x), z(x, y+1) − z(x, y),
//!   −S)` with `S` depth units per pixel ([`PostFxParams::normal_scale`]); an edge lies
//!   between two neighbours when `n₁·n₂ < cos θ·|n₁||n₂|`, tested exactly in `i128` on
//!   squares with `cos θ` in Q.16.
//!
//! **Two edge classes, two loops (seed 004, Fig. 16/17).** An edge with a depth jump
//! `|z₂ − z₁| > Zjump` is class 2 (object against background or another object); any
//! other edge is class 1 (a crease between adjacent planes). Loop 1 blends class-1
//! edges: from the 1×4 depths across the crease the two planes are extended and
//! intersected (eq. 18, `s = (sz3 + sz1 − 2·sz2)/(sz4 − sz3 − sz2 + sz1)`, see
//! `crease_pass`); the pixel the crease does not reach the centre of takes `|s − ½|` of
//! its neighbour's colour. Pixels blended
//! here get the 1-bit flag and are skipped by loop 2.
//!
//! **Loop 2: the scanline state machine and trapezoid blending (seed 004, Fig. 7, 13,
//! eq. 17).** The x pass scans each boundary between rows y and y+1 left to right with
//! the variables `state`, `count`, `parity`: a run is a maximal sequence of class-2 `ey`
//! edges; at each end the perpendicular edge (an `ex` edge in the upper or lower row)
//! gives the end height `±½` (or 0 when there is none). The seed's modes follow: step at
//! the start only (mode 1), at the end only (mode 0), both (mode 2), none (no blend). The
//! ideal edge is the line from the start height to the end height (for two steps on the
//! same side, two half-lines meeting at 0 in the middle); the trapezoid it cuts in each
//! pixel column, `a = ∫ h(x) dx` over the pixel (eq. 17 in the linear case:
//! `0.25/Len·((k+1)² − k²)`), is the blend coefficient, computed exactly in integers and
//! rounded to Q.16: a positive area blends the upper pixel toward the lower one, a
//! negative area the lower toward the upper. The y pass does the same on columns.
//!
//! **x and y combined through the 1-bit flag (seed 004, "both directions").** The x pass
//! writes the blended image and sets a flag per pixel it changed; the y pass reads a
//! flagged pixel from the anti-aliased buffer and blends again ("priority to the first,
//! blend again"). Colours are RGB8; a blend is `(c·(2^16 − a) + c'·a + 2^15) >> 16`. The
//! model blends one buffer in place, which always holds the value the flag selects
//! (`PassBufs`).
//!
//! **5-line window (seed 004, Figs. 9–11).** With [`PostFxParams::window`] a run on the
//! boundary between lines v and v+1 reads the edge bits of lines v−1..v+2: runs split
//! where the surface on one side changes inside the run, and a step at a run end counts
//! only if the edge continues on the neighbouring boundary (see `run_pass`).
//!
//! **Buffers written during drawing (seed 004, eqs. 1–4, "normal vector buffer").**
//! [`draw_buffers`] replays the drawing in scene order and keeps the second-difference
//! buffer by read-modify-write and a [`StoredNormal`] per pixel. Loop 1 uses the seed's
//! eq. 18 for the crease position. Not modelled: the class-2 counting coefficient
//! (eq. 19), whose counted pixels are defined only in Fig. 17.

use super::{AaError, AaFrame, AaStats};
use crate::render::{render_frame, SpanSource};
use crate::setup::SnappedTri;
use rayon::prelude::*;

mod blend;
mod draw;
mod edges;
use blend::{crease_pass, run_pass, PassBufs};
pub use draw::{draw_buffers, DrawBuffers, StoredNormal};
pub use edges::{
    detect_edges, detect_edges_from, detect_edges_with, second_differences, Edges, SecondDiffs,
};

/// Where the normals of the normal edge test come from (seed 004, "edges from normals").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalSource {
    /// Reconstructed from the finished z-buffer, `n = (Δx z, Δy z, −S)` (seed eq. 9).
    #[default]
    Reconstructed,
    /// A per-pixel normal buffer written at each depth-test pass during drawing: the
    /// visible plane's unit normal as two Q1.15 components and the sign of the third
    /// ([`StoredNormal`]).
    Stored,
}

/// Where the z second differences come from (seed 004, eqs. 1–4 and 5–7).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SecondDiffSource {
    /// Computed by scanning the finished z-buffer.
    #[default]
    FinalZ,
    /// A second-difference buffer initialised to 0 and updated read-modify-write during
    /// drawing whenever a neighbour's z changes (eq. 4). Gives the same buffer, hence the
    /// same edge bits, as [`SecondDiffSource::FinalZ`].
    DuringDraw,
}

/// Parameters of post-process anti-aliasing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PostFxParams {
    /// Threshold on |z second difference| (24-bit depth units), `Zth`.
    pub zth: u32,
    /// A depth jump above this makes an edge class 2 (silhouette).
    pub zjump: u32,
    /// Also detect edges from normals.
    pub normals: bool,
    /// Depth units per pixel used as the normal's z component.
    pub normal_scale: u32,
    /// cos θ threshold of the normal test, Q.16.
    pub cos_q16: u32,
    /// Blend class-1 (crease) edges in a first loop.
    pub creases: bool,
    /// Use the 5-line window (2 lines above, 2 below) to tell which edge a perpendicular
    /// step at a run end belongs to. `false`: the two lines at the boundary only.
    pub window: bool,
    /// Stored or reconstructed normals (when [`PostFxParams::normals`] is set).
    pub normal_source: NormalSource,
    /// Second differences from the final z-buffer or maintained during drawing.
    pub d2_source: SecondDiffSource,
}

impl Default for PostFxParams {
    fn default() -> Self {
        PostFxParams {
            zth: 64,
            zjump: 4096,
            normals: false,
            normal_scale: 256,
            cos_q16: 58982, // 0.9
            creases: true,
            window: true,
            normal_source: NormalSource::Reconstructed,
            d2_source: SecondDiffSource::FinalZ,
        }
    }
}

impl PostFxParams {
    /// A short label.
    pub fn label(&self) -> String {
        format!(
            "postfx zth={} zjump={}{}{}{}{}",
            self.zth,
            self.zjump,
            match (self.normals, self.normal_source) {
                (false, _) => "",
                (true, NormalSource::Reconstructed) => " normals",
                (true, NormalSource::Stored) => " normals=stored",
            },
            if self.creases { " creases" } else { "" },
            if self.window { "" } else { " window=3" },
            if self.d2_source == SecondDiffSource::DuringDraw {
                " d2=draw"
            } else {
                ""
            }
        )
    }
}

/// The array's shadows, for post-processing a shadowed baseline.
pub struct ShadowedBaseline<'a> {
    /// The baseline's colours after shadow shading, RGB8 row-major (the image the
    /// post-process starts from instead of the unshaded one).
    pub rgb: &'a [u8],
    /// The shadow level per pixel, 0..=255 (0 on the background).
    pub level: &'a [u8],
}

/// Renders the baseline and post-processes it.
pub fn render(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &PostFxParams,
) -> Result<AaFrame, AaError> {
    render_with(tris, width, height, bg, p, None, true).map(|(f, _)| f)
}

/// Marks a class-2 edge between neighbours whose shadow levels differ, where no edge is
/// yet: a shadow boundary is an edge of the image like an object's (seed 004 finds edges
/// in the z-buffer; the shadow flags are one more per-pixel buffer of the same array).
fn add_shadow_edges(e: &mut Edges, level: &[u8]) {
    let (w, h) = (e.w, e.h);
    for y in 0..h {
        for x in 0..w {
            let k = y * w + x;
            if x + 1 < w && level[k] != level[k + 1] && e.ex[k] == 0 {
                e.ex[k] = 2;
            }
            if y + 1 < h && level[k] != level[k + w] && e.ey[k] == 0 {
                e.ey[k] = 2;
            }
        }
    }
}

/// [`render`] of a baseline with shadows: the post-process starts from the shaded colours,
/// treats a change of shadow level between neighbours as an edge, and blends the shadow
/// levels with the same coefficients as the colours (returned second: the shadowed
/// fraction in the method's own weights). Without `shadow`, exactly [`render`].
///
/// With `visible` false the frame's visible-triangle AOV is not computed
/// ([`AaFrame::visible`] is `None`; it needs a second scan of every span word); the image
/// and every counter are the same.
pub fn render_with(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &PostFxParams,
    shadow: Option<ShadowedBaseline>,
    visible: bool,
) -> Result<(AaFrame, Option<Vec<u8>>), AaError> {
    let src = SpanSource::new(tris, width, height)?;
    let frame = render_frame(&src, bg, width as usize, &[]);
    let (w, h) = (width as usize, height as usize);
    let z: Vec<u32> = frame.px.par_iter().map(|s| s.zb).collect();
    let img: Vec<[u8; 3]> = match &shadow {
        Some(s) => s.rgb.chunks(3).map(|c| [c[0], c[1], c[2]]).collect(),
        None => frame
            .px
            .par_iter()
            .map(|s| pixelproc_formats::unpack_rgb(s.rgb))
            .collect(),
    };
    // Second differences and normals: from the finished buffers, or the buffers kept
    // during drawing (which also give the visible triangle).
    let need_draw = p.d2_source == SecondDiffSource::DuringDraw
        || (p.normals && p.normal_source == NormalSource::Stored);
    // The second differences: the buffers kept during drawing, or the final z-buffer's,
    // computed where they are read (`SecondDiffs::FinalZ`).
    let (kept, stored, visible, evals, extra) = if need_draw {
        let b = draw_buffers(tris, width, height, p.normal_scale)?;
        let kept = match p.d2_source {
            SecondDiffSource::DuringDraw => Some((b.d2x, b.d2y)),
            SecondDiffSource::FinalZ => None,
        };
        (
            kept,
            Some(b.normals),
            Some(b.visible),
            b.depth_tests,
            b.d2_updates,
        )
    } else {
        let (visible, evals) = if visible {
            let (v, e) = super::baseline_visible(tris, width, height)?;
            (Some(v), e)
        } else {
            // The same count as the visibility probe's: one depth test per pixel of
            // every span word.
            (None, src.span_pixels())
        };
        (None, None, visible, evals, 0)
    };
    let d2 = match &kept {
        Some((d2x, d2y)) => SecondDiffs::Kept(d2x, d2y),
        None => SecondDiffs::FinalZ,
    };
    let mut e = detect_edges_with(&z, d2, stored.as_deref(), w, h, p);
    if let Some(s) = &shadow {
        add_shadow_edges(&mut e, s.level);
    }
    // Loop 1, then loop 2 (x pass then y pass, combined through the flag: one buffer
    // blended in place, `PassBufs`).
    let post = |mut img: Vec<[u8; 3]>, reads: &mut u64| {
        let skip = if p.creases {
            crease_pass(&mut img, &z, d2, &e, reads)
        } else {
            vec![false; w * h]
        };
        let mut bufs = PassBufs {
            img: &mut img,
            skip: &skip,
            reads,
        };
        run_pass(&mut bufs, &e, false, p.window);
        run_pass(&mut bufs, &e, true, p.window);
        img
    };
    let mut reads = extra;
    let out = post(img, &mut reads);
    let fraction = shadow.map(|s| {
        let grey: Vec<[u8; 3]> = s.level.iter().map(|&l| [l; 3]).collect();
        post(grey, &mut 0).iter().map(|c| c[0]).collect()
    });
    let frame = AaFrame {
        width,
        height,
        rgb: out.into_flattened(),
        visible,
        stats: AaStats {
            depth_evals: evals,
            samples_written: (w * h) as u64,
            // z buffer read once per pixel per pass (edges), plus colour reads.
            sample_reads: 2 * (w * h) as u64 + reads,
            pixels: (w * h) as u64,
            ..Default::default()
        },
    };
    Ok((frame, fraction))
}

#[cfg(test)]
mod tests {
    use super::blend::column_area;
    use super::*;

    #[test]
    fn column_areas_of_a_linear_ramp_follow_eq_17() {
        // h from 0 to ½ over Len = 5: area of column k = 0.25/Len·((k+1)² − k²).
        for k in 0..5 {
            let (pos, neg) = column_area(0, 1, 5, k);
            let want = 0.25 / 5.0 * (((k + 1) * (k + 1) - k * k) as f64);
            assert_eq!(neg, 0);
            assert!((pos as f64 / 65536.0 - want).abs() < 1e-4, "k={k}");
        }
    }

    /// The second differences computed where read equal the buffers of
    /// `second_differences` at every pixel, borders included, on random 24-bit depths of
    /// every shape down to one pixel; and the edges found with either are the same.
    #[test]
    fn second_differences_read_from_z_equal_the_buffers() {
        let mut rng = crate::rng::XorShift64Star(0x2d1f_f00d);
        for (w, h) in [(1, 1), (1, 7), (7, 1), (2, 2), (5, 4), (33, 17)] {
            for round in 0..20 {
                let z: Vec<u32> = (0..w * h)
                    .map(|_| match (rng.next_u64() % 4, round % 2) {
                        (0, _) => 0xFF_FFFF,
                        (1, 0) => 0,
                        _ => (rng.next_u64() % (1 << 24)) as u32,
                    })
                    .collect();
                let (dx, dy) = second_differences(&z, w, h);
                for y in 0..h {
                    for x in 0..w {
                        let k = y * w + x;
                        assert_eq!(
                            SecondDiffs::FinalZ.dx(&z, w, x, y),
                            dx[k],
                            "{w}x{h} ({x},{y})"
                        );
                        assert_eq!(
                            SecondDiffs::FinalZ.dy(&z, w, h, x, y),
                            dy[k],
                            "{w}x{h} ({x},{y})"
                        );
                    }
                }
                let p = PostFxParams {
                    zth: (rng.next_u64() % 5000) as u32,
                    ..PostFxParams::default()
                };
                let a = detect_edges(&z, w, h, &p);
                let b = detect_edges_from(&z, &dx, &dy, None, w, h, &p);
                assert_eq!((a.ex, a.ey), (b.ex, b.ey), "{w}x{h}");
            }
        }
    }

    /// The edge bits are the seed's rule (module header) applied boundary by boundary,
    /// written out here from the second-difference buffers: on random depths, planes
    /// with steps, every shape down to one pixel, thresholds from 0 up.
    #[test]
    fn edges_follow_the_rule_at_every_boundary() {
        let mut rng = crate::rng::XorShift64Star(0x000e_d9e5);
        let mut edges = 0;
        for (w, h) in [(1, 1), (1, 6), (6, 1), (2, 3), (9, 7), (40, 23)] {
            for round in 0..30 {
                let (gx, gy) = (rng.next_u64() % 3000, rng.next_u64() % 3000);
                let z: Vec<u32> = (0..w * h)
                    .map(|k| {
                        let (x, y) = ((k % w) as u64, (k / w) as u64);
                        let plane = 100_000 + gx * x + gy * y;
                        match (rng.next_u64() % 8, round % 3) {
                            (0, 0) => (rng.next_u64() % (1 << 24)) as u32,
                            (0 | 1, _) => (plane + rng.next_u64() % 20_000) as u32,
                            _ => plane as u32,
                        }
                    })
                    .collect();
                let p = PostFxParams {
                    zth: [0, 1, 64, 5000][round % 4],
                    zjump: [0, 4096, 30_000][round % 3],
                    ..PostFxParams::default()
                };
                let (dx, dy) = second_differences(&z, w, h);
                let at = |x: i64, y: i64| {
                    z[y.clamp(0, h as i64 - 1) as usize * w + x.clamp(0, w as i64 - 1) as usize]
                        as i64
                };
                let over = |d: i32| (d as i64).abs() > p.zth as i64;
                // P = (x, y) marks the boundary toward (x + sx, y + sy) when its first
                // difference that way is at least the one the other way.
                let toward = |x: i64, y: i64, sx: i64, sy: i64| {
                    (at(x + sx, y + sy) - at(x, y)).abs() >= (at(x, y) - at(x - sx, y - sy)).abs()
                };
                let class = |a: i64, b: i64| {
                    if (a - b).abs() > p.zjump as i64 {
                        2u8
                    } else {
                        1
                    }
                };
                let (mut wx, mut wy) = (vec![0u8; w * h], vec![0u8; w * h]);
                for y in 0..h as i64 {
                    for x in 0..w as i64 {
                        let k = (y * w as i64 + x) as usize;
                        if x + 1 < w as i64
                            && ((over(dx[k]) && toward(x, y, 1, 0))
                                || (over(dx[k + 1]) && !toward(x + 1, y, 1, 0)))
                        {
                            wx[k] = class(at(x, y), at(x + 1, y));
                        }
                        if y + 1 < h as i64
                            && ((over(dy[k]) && toward(x, y, 0, 1))
                                || (over(dy[k + w]) && !toward(x, y + 1, 0, 1)))
                        {
                            wy[k] = class(at(x, y), at(x, y + 1));
                        }
                    }
                }
                edges += wx.iter().chain(&wy).filter(|&&b| b != 0).count();
                let a = detect_edges(&z, w, h, &p);
                assert_eq!((&a.ex, &a.ey), (&wx, &wy), "{w}x{h} round {round}");
                let b = detect_edges_from(&z, &dx, &dy, None, w, h, &p);
                assert_eq!((&b.ex, &b.ey), (&wx, &wy), "{w}x{h} round {round}, kept");
            }
        }
        assert!(edges > 1000, "{edges} edge bits");
    }

    #[test]
    fn a_vertical_depth_step_gives_edges_on_one_column_boundary() {
        let (w, h) = (8, 4);
        let z: Vec<u32> = (0..w * h)
            .map(|k| if k % w < 3 { 1000 } else { 90000 })
            .collect();
        let e = detect_edges(&z, w, h, &PostFxParams::default());
        for y in 0..h {
            for x in 0..w {
                let want = if x == 2 { 2 } else { 0 };
                assert_eq!(e.ex[y * w + x], want, "({x},{y})");
                assert_eq!(e.ey[y * w + x], 0);
            }
        }
    }
}
