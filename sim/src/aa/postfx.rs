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
//! blend again"). Colours are RGB8; a blend is `(c·(2^16 − a) + c'·a + 2^15) >> 16`.
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

mod draw;
pub use draw::{draw_buffers, DrawBuffers, StoredNormal};

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

/// Second differences of a finished z-buffer (seed eq. 7, borders replicate):
/// `(d2x, d2y)`.
pub fn second_differences(z: &[u32], w: usize, h: usize) -> (Vec<i32>, Vec<i32>) {
    let at = |x: i64, y: i64| -> i32 {
        z[y.clamp(0, h as i64 - 1) as usize * w + x.clamp(0, w as i64 - 1) as usize] as i32
    };
    let mut dx = vec![0; w * h];
    let mut dy = vec![0; w * h];
    // Rows are independent: each writes only its own entries.
    dx.par_chunks_mut(w)
        .zip(dy.par_chunks_mut(w))
        .enumerate()
        .for_each(|(y, (dxr, dyr))| {
            let y = y as i64;
            for x in 0..w as i64 {
                let c = at(x, y);
                dxr[x as usize] = at(x + 1, y) + at(x - 1, y) - 2 * c;
                dyr[x as usize] = at(x, y + 1) + at(x, y - 1) - 2 * c;
            }
        });
    (dx, dy)
}

/// Edge bits between pixels and their class.
pub struct Edges {
    /// Width.
    pub w: usize,
    /// Height.
    pub h: usize,
    /// `ex[y·w + x]`: edge between (x, y) and (x+1, y); 0 none, 1 crease, 2 jump.
    pub ex: Vec<u8>,
    /// `ey[y·w + x]`: edge between (x, y) and (x, y+1).
    pub ey: Vec<u8>,
}

/// Computes the edge bits of a finished depth buffer: second differences from `z`,
/// reconstructed normals (see the module header). Equivalent to [`detect_edges_from`]
/// with the buffers of [`second_differences`] and no stored normals.
pub fn detect_edges(z: &[u32], w: usize, h: usize, p: &PostFxParams) -> Edges {
    let (dx, dy) = second_differences(z, w, h);
    detect_edges_from(z, &dx, &dy, None, w, h, p)
}

/// Computes the edge bits from a z-buffer, its second differences (from the final z or
/// maintained during drawing) and, if given and selected by
/// [`PostFxParams::normal_source`], a stored normal buffer (else normals are
/// reconstructed from `z`).
pub fn detect_edges_from(
    z: &[u32],
    d2x: &[i32],
    d2y: &[i32],
    stored: Option<&[StoredNormal]>,
    w: usize,
    h: usize,
    p: &PostFxParams,
) -> Edges {
    let at = |x: i64, y: i64| -> i64 {
        let x = x.clamp(0, w as i64 - 1) as usize;
        let y = y.clamp(0, h as i64 - 1) as usize;
        z[y * w + x] as i64
    };
    let mut ex = vec![0u8; w * h];
    let mut ey = vec![0u8; w * h];
    let class = |a: i64, b: i64| if (a - b).abs() > p.zjump as i64 { 2 } else { 1 };
    // A pixel whose |d2| exceeds Zth marks the boundary on the side with the larger first
    // difference: the one toward (x + dx, y + dy) when `forward`, else the one behind it.
    let over = |d2: i32| (d2 as i64).abs() > p.zth as i64;
    let forward = |x: i64, y: i64, dx: i64, dy: i64| {
        let c = at(x, y);
        (at(x + dx, y + dy) - c).abs() >= (c - at(x - dx, y - dy)).abs()
    };
    // Gathered per boundary, so rows are independent: the boundary between P and its
    // neighbour Q = P + (dx, dy) is an edge when P marks it forward or Q backward, of
    // the class of the pair (P, Q).
    ex.par_chunks_mut(w)
        .zip(ey.par_chunks_mut(w))
        .enumerate()
        .for_each(|(y, (exr, eyr))| {
            for x in 0..w {
                let k = y * w + x;
                let (xi, yi) = (x as i64, y as i64);
                if x + 1 < w
                    && ((over(d2x[k]) && forward(xi, yi, 1, 0))
                        || (over(d2x[k + 1]) && !forward(xi + 1, yi, 1, 0)))
                {
                    exr[x] = class(at(xi, yi), at(xi + 1, yi));
                }
                if y + 1 < h
                    && ((over(d2y[k]) && forward(xi, yi, 0, 1))
                        || (over(d2y[k + w]) && !forward(xi, yi + 1, 0, 1)))
                {
                    eyr[x] = class(at(xi, yi), at(xi, yi + 1));
                }
            }
        });
    if p.normals {
        match (p.normal_source, stored) {
            (NormalSource::Stored, Some(nb)) => {
                // Dot product of unit normals (Q2.30) against cos θ (Q.16 → Q.30).
                let cth = (p.cos_q16 as i64) << 14;
                let nv: Vec<[i64; 3]> = nb.iter().map(|n| n.unpack()).collect();
                let differs =
                    |a: [i64; 3], b: [i64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2] < cth;
                for y in 0..h {
                    for x in 0..w {
                        let k = y * w + x;
                        if x + 1 < w && differs(nv[k], nv[k + 1]) {
                            ex[k] = ex[k]
                                .max(class(at(x as i64, y as i64), at(x as i64 + 1, y as i64)));
                        }
                        if y + 1 < h && differs(nv[k], nv[k + w]) {
                            ey[k] = ey[k]
                                .max(class(at(x as i64, y as i64), at(x as i64, y as i64 + 1)));
                        }
                    }
                }
            }
            _ => reconstructed_normal_edges(&at, &mut ex, &mut ey, w, h, p, &class),
        }
    }
    Edges { w, h, ex, ey }
}

/// Normal edges from normals reconstructed from z (seed eq. 9).
fn reconstructed_normal_edges(
    at: &dyn Fn(i64, i64) -> i64,
    ex: &mut [u8],
    ey: &mut [u8],
    w: usize,
    h: usize,
    p: &PostFxParams,
    class: &dyn Fn(i64, i64) -> u8,
) {
    let s = p.normal_scale as i128;
    let n = |x: i64, y: i64| -> [i128; 3] {
        [
            (at(x + 1, y) - at(x, y)) as i128,
            (at(x, y + 1) - at(x, y)) as i128,
            -s,
        ]
    };
    let c = p.cos_q16 as i128;
    let differs = |a: [i128; 3], b: [i128; 3]| {
        let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let na = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
        let nb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
        // dot < cos·|a||b|  ⇔  dot < 0 or dot² < cos²·|a|²|b|² (cos ≥ 0).
        if dot < 0 {
            return true;
        }
        // Compare (dot·2^16)² < c²·na·nb.
        let l = (dot << 16).checked_mul(dot << 16);
        let r = (c * c).checked_mul(na).and_then(|v| v.checked_mul(nb));
        match (l, r) {
            (Some(l), Some(r)) => l < r,
            _ => {
                let (df, naf, nbf) = (dot as f64, na as f64, nb as f64);
                df * df * 65536.0 * 65536.0 < (c * c) as f64 * naf * nbf
            }
        }
    };
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let k = y as usize * w + x as usize;
            let a = n(x, y);
            if x + 1 < w as i64 && differs(a, n(x + 1, y)) {
                ex[k] = ex[k].max(class(at(x, y), at(x + 1, y)));
            }
            if y + 1 < h as i64 && differs(a, n(x, y + 1)) {
                ey[k] = ey[k].max(class(at(x, y), at(x, y + 1)));
            }
        }
    }
}

#[inline]
fn blend(c: [u8; 3], o: [u8; 3], a_q16: i64) -> [u8; 3] {
    let a = a_q16.clamp(0, 1 << 16);
    [0, 1, 2].map(|k| ((c[k] as i64 * ((1 << 16) - a) + o[k] as i64 * a + (1 << 15)) >> 16) as u8)
}

/// Signed area (Q.16 of a pixel) under the line `h(t)`, `t ∈ [k, k+1]`, where `h` runs
/// linearly from `h0` at `t = 0` to `h1` at `t = len` (heights in halves: ±1 = ±½ pixel).
/// Returns `(positive part, negative part)` magnitudes.
fn column_area(h0: i64, h1: i64, len: i64, k: i64) -> (i64, i64) {
    // Heights at the column ends, as rationals over 2·len (half-pixel units → pixels).
    let ha = h0 * (len - k) + h1 * k; // ·(1/(2·len)) pixels
    let hb = h0 * (len - k - 1) + h1 * (k + 1);
    let d = 2 * len;
    let one = 1i64 << 16;
    if ha >= 0 && hb >= 0 {
        ((ha + hb) * one / (2 * d), 0)
    } else if ha <= 0 && hb <= 0 {
        (0, -(ha + hb) * one / (2 * d))
    } else {
        // Sign change at fraction u = ha/(ha − hb) of the column.
        let (p, q) = if ha > 0 { (ha, -hb) } else { (-ha, hb) };
        let pos = p * p * one / (2 * d * (p + q));
        let neg = q * q * one / (2 * d * (p + q));
        if ha > 0 {
            (pos, neg)
        } else {
            (neg, pos)
        }
    }
}

/// The edge bits as one loop-2 pass sees them: along-run position `u`, across index `v`
/// (`transpose = false`: runs along x on the boundaries between rows v and v+1).
struct PassView<'a> {
    e: &'a Edges,
    transpose: bool,
    /// Along-run length.
    nu: usize,
    /// Number of lines across.
    nv: usize,
}

impl PassView<'_> {
    fn new(e: &Edges, transpose: bool) -> PassView<'_> {
        let (nu, nv) = if transpose { (e.h, e.w) } else { (e.w, e.h) };
        PassView {
            e,
            transpose,
            nu,
            nv,
        }
    }

    /// Pixel index of `(u, v)`.
    fn idx(&self, u: usize, v: usize) -> usize {
        if self.transpose {
            u * self.e.w + v
        } else {
            v * self.e.w + u
        }
    }

    /// Edge across the boundary between v and v+1 at position u.
    fn across(&self, u: usize, v: usize) -> u8 {
        if self.transpose {
            self.e.ex[self.idx(u, v)]
        } else {
            self.e.ey[self.idx(u, v)]
        }
    }

    /// Perpendicular edge between u and u+1 in line v.
    fn perp(&self, u: usize, v: usize) -> bool {
        if self.transpose {
            self.e.ey[self.idx(u, v)] != 0
        } else {
            self.e.ex[self.idx(u, v)] != 0
        }
    }

    /// The runs `(start, length)` on the boundary between v and v+1. State machine: state
    /// 0 = outside a run, 1 = inside; count = run length. A run ends where the edge stops
    /// or, with the 5-line window, where a perpendicular edge in line v or v+1 shows that
    /// the surface on one side changes inside the run (two edges meeting end to end on one
    /// boundary, the seed's Fig. 9): the run is split there and the two parts are blended
    /// separately.
    fn runs(&self, v: usize, window: bool) -> Vec<(usize, usize)> {
        let mut state = 0;
        let mut count = 0usize;
        let mut runs = Vec::new();
        for u in 0..=self.nu {
            let on = u < self.nu && self.across(u, v) == 2;
            let split =
                window && on && state == 1 && (self.perp(u - 1, v) || self.perp(u - 1, v + 1));
            if state == 1 && (!on || split) {
                state = 0;
                runs.push((u - count, count));
            }
            if on {
                if state == 0 {
                    state = 1;
                    count = 0;
                }
                count += 1;
            }
        }
        runs
    }

    /// End height (in half pixels) of a run on boundary v at the perpendicular edge between
    /// b and b+1: in line v (upper) → +1, in line v+1 (lower) → −1. With the 5-line window
    /// a step counts only if the run continues on the neighbouring boundary (v−1 for a step
    /// up, v+1 for a step down) at column c just beyond the end; an edge of a close
    /// parallel neighbour fails this test. If neither or both pass, the 3-line rule
    /// decides.
    fn end_height(&self, v: usize, b: usize, c: usize, window: bool) -> i64 {
        let (up3, dn3) = (self.perp(b, v), self.perp(b, v + 1));
        if window {
            let up = up3 && v >= 1 && self.across(c, v - 1) == 2;
            let dn = dn3 && v + 2 < self.nv && self.across(c, v + 1) == 2;
            match (up, dn) {
                (true, false) => return 1,
                (false, true) => return -1,
                _ => {}
            }
        }
        if up3 {
            1
        } else if dn3 {
            -1
        } else {
            0
        }
    }
}

/// Per-pixel (positive, negative) areas of column `k` of a run of length `len` with end
/// heights `hl`, `hr`. Two steps on one side (U shape): two half-lines meeting at 0 in the
/// middle, integrated on half columns.
fn run_area(hl: i64, hr: i64, len: i64, k: i64) -> (i64, i64) {
    if hl != 0 && hr != 0 && hl == hr {
        let mut acc = (0, 0);
        for c in [2 * k, 2 * k + 1] {
            let (p, n) = if c < len {
                column_area(hl, 0, len, c)
            } else {
                column_area(0, hr, len, c - len)
            };
            acc = (acc.0 + p, acc.1 + n);
        }
        (acc.0 / 2, acc.1 / 2)
    } else {
        column_area(hl, hr, len, k)
    }
}

/// The colour buffers of one loop-2 pass: reads `src`, or `dst` where `flag` is set;
/// writes `dst`, sets `flag`; never writes a pixel in `skip` (blended by loop 1).
struct PassBufs<'a> {
    src: &'a [[u8; 3]],
    dst: &'a mut [[u8; 3]],
    flag: &'a mut [bool],
    skip: &'a [bool],
    reads: &'a mut u64,
}

impl PassBufs<'_> {
    /// Blends pixel `a` toward pixel `o` by `area` (Q.16), if positive and not skipped.
    fn blend_toward(&mut self, a: usize, o: usize, area: i64) {
        if area > 0 && !self.skip[a] {
            *self.reads += 2;
            let c = if self.flag[a] {
                self.dst[a]
            } else {
                self.src[a]
            };
            let oc = if self.flag[o] {
                self.dst[o]
            } else {
                self.src[o]
            };
            self.dst[a] = blend(c, oc, area);
            self.flag[a] = true;
        }
    }
}

/// One pass of loop 2 along rows (`transpose = false`: boundaries between rows y and
/// y+1, runs along x) or along columns. Reads `src`, or `dst` where `flag` is set;
/// writes `dst`, sets `flag`.
fn run_pass(bufs: &mut PassBufs, e: &Edges, transpose: bool, window: bool) {
    let view = PassView::new(e, transpose);
    let (nu, nv) = (view.nu, view.nv);
    // The runs and their end heights depend on the edge bits only: found for every line
    // in parallel, then blended line after line in the sequential order (a blend reads
    // what an earlier line's blend wrote).
    let lines: Vec<Vec<(usize, usize, i64, i64)>> = (0..nv.saturating_sub(1))
        .into_par_iter()
        .map(|v| {
            view.runs(v, window)
                .into_iter()
                .filter_map(|(u0, count)| {
                    let u = u0 + count;
                    let hl = if u0 > 0 {
                        view.end_height(v, u0 - 1, u0 - 1, window)
                    } else {
                        0
                    };
                    let hr = if u < nu {
                        view.end_height(v, u - 1, u, window)
                    } else {
                        0
                    };
                    (hl != 0 || hr != 0).then_some((u0, count, hl, hr))
                })
                .collect()
        })
        .collect();
    for (v, runs) in lines.iter().enumerate() {
        for &(u0, count, hl, hr) in runs {
            let len = count as i64;
            for k in 0..len {
                let (pos, neg) = run_area(hl, hr, len, k);
                let uu = u0 + k as usize;
                let (up, lo) = (view.idx(uu, v), view.idx(uu, v + 1));
                bufs.blend_toward(up, lo, pos);
                bufs.blend_toward(lo, up, neg);
            }
        }
    }
}

/// Loop 1: crease (class-1) edges, seed eq. 18. Returns the per-pixel "blended here" bits.
///
/// For an edge between pixel `sz2` (the pixel of interest) and its neighbour `sz3` on the
/// 1×5 line `sz1 sz2 | sz3 sz4` of the cross: `s = (sz3 + sz1 − 2·sz2)/(sz4 − sz3 − sz2 +
/// sz1)`. The numerator is the second difference at `sz2` (read from the second-difference
/// buffer), the denominator the change of slope; `s` is the distance from the centre of
/// `sz3` back to the line where the two planes (through `sz1, sz2` and `sz3, sz4`) meet.
/// The pixel the crease does not reach the centre of takes `|s − ½|` of its neighbour.
#[allow(clippy::too_many_arguments)]
fn crease_pass(
    src: &[[u8; 3]],
    dst: &mut [[u8; 3]],
    z: &[u32],
    d2x: &[i32],
    d2y: &[i32],
    e: &Edges,
    reads: &mut u64,
) -> Vec<bool> {
    let (w, h) = (e.w, e.h);
    let mut done = vec![false; w * h];
    let at = |x: i64, y: i64| {
        z[(y.clamp(0, h as i64 - 1) as usize) * w + x.clamp(0, w as i64 - 1) as usize] as i64
    };
    // Every blend reads `src` only, so the blends of each row are found in parallel and
    // then written in the sequential order (a later write to the same pixel wins).
    let rows: Vec<Vec<(usize, [u8; 3])>> = (0..h as i64)
        .into_par_iter()
        .map(|y| {
            let mut writes = Vec::new();
            for x in 0..w as i64 {
                let k = y as usize * w + x as usize;
                for (dx, dy, bit, d2) in [(1i64, 0i64, e.ex[k], d2x[k]), (0, 1, e.ey[k], d2y[k])] {
                    if bit != 1 {
                        continue;
                    }
                    let sz1 = at(x - dx, y - dy);
                    let sz2 = at(x, y);
                    let sz3 = at(x + dx, y + dy);
                    let sz4 = at(x + 2 * dx, y + 2 * dy);
                    let num = d2 as i128; // = sz3 + sz1 − 2·sz2
                    let den = (sz4 - sz3 - sz2 + sz1) as i128;
                    if den == 0 {
                        continue;
                    }
                    let s = ((num << 16) / den) as i64;
                    if !(0..=1 << 16).contains(&s) {
                        continue;
                    }
                    let k2 = (y + dy) as usize * w + (x + dx) as usize;
                    let half = 1i64 << 15;
                    // Two reads per blend, counted below (one per entry of `writes`); a
                    // crease exactly at the centre (s = ½) reads too but writes nothing.
                    if s > half {
                        writes.push((k, blend(src[k], src[k2], s - half)));
                    } else if s < half {
                        writes.push((k2, blend(src[k2], src[k], half - s)));
                    } else {
                        writes.push((usize::MAX, [0; 3]));
                    }
                }
            }
            writes
        })
        .collect();
    for (k, c) in rows.into_iter().flatten() {
        *reads += 2;
        if k != usize::MAX {
            dst[k] = c;
            done[k] = true;
        }
    }
    done
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
    let frame = render_frame(&src, bg, width as usize, |_, _| {});
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
    let (d2x, d2y, stored, visible, evals, extra) = if need_draw {
        let b = draw_buffers(tris, width, height, p.normal_scale)?;
        let (d2x, d2y) = match p.d2_source {
            SecondDiffSource::DuringDraw => (b.d2x, b.d2y),
            SecondDiffSource::FinalZ => second_differences(&z, w, h),
        };
        (
            d2x,
            d2y,
            Some(b.normals),
            Some(b.visible),
            b.depth_tests,
            b.d2_updates,
        )
    } else {
        let (d2x, d2y) = second_differences(&z, w, h);
        let (visible, evals) = if visible {
            let (v, e) = super::baseline_visible(tris, width, height)?;
            (Some(v), e)
        } else {
            // The same count as the visibility probe's: one depth test per pixel of
            // every span word.
            (None, src.span_pixels())
        };
        (d2x, d2y, None, visible, evals, 0)
    };
    let mut e = detect_edges_from(&z, &d2x, &d2y, stored.as_deref(), w, h, p);
    if let Some(s) = &shadow {
        add_shadow_edges(&mut e, s.level);
    }
    // Loop 1, then loop 2 (x pass then y pass, combined through the flag).
    let post = |img: &[[u8; 3]], reads: &mut u64| {
        let mut after1 = img.to_vec();
        let skip = if p.creases {
            crease_pass(img, &mut after1, &z, &d2x, &d2y, &e, reads)
        } else {
            vec![false; w * h]
        };
        let mut out = after1.clone();
        let mut flag = vec![false; w * h];
        let mut bufs = PassBufs {
            src: &after1,
            dst: &mut out,
            flag: &mut flag,
            skip: &skip,
            reads,
        };
        run_pass(&mut bufs, &e, false, p.window);
        run_pass(&mut bufs, &e, true, p.window);
        out
    };
    let mut reads = extra;
    let out = post(&img, &mut reads);
    let fraction = shadow.map(|s| {
        let grey: Vec<[u8; 3]> = s.level.iter().map(|&l| [l; 3]).collect();
        post(&grey, &mut 0).iter().map(|c| c[0]).collect()
    });
    let frame = AaFrame {
        width,
        height,
        rgb: out.as_flattened().to_vec(),
        visible,
        stats: AaStats {
            depth_evals: evals,
            samples_written: (w * h) as u64,
            // z buffer read once per pixel per pass (edges), plus colour reads.
            sample_reads: 2 * (w * h) as u64 + reads,
            ..Default::default()
        },
    };
    Ok((frame, fraction))
}

#[cfg(test)]
mod tests {
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
