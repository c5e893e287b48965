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
//! intersected, giving the crease position `t* ∈ [0, 1]` between the two centres
//! (`t* = (z₂ − z₁ − (z₁ − z₀))…`, see `docs/postfx.md`); the pixel the crease does not
//! pass through the centre of takes `|½ − t*|` of its neighbour's colour. Pixels blended
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
//! Not modelled: the seed's 5-line window for separating close parallel edges (runs are
//! found from the two rows on either side of the boundary only), and the in-drawing
//! maintenance of the second-difference buffer (here computed from the finished z).

use super::{baseline_visible, AaError, AaFrame, AaStats};
use crate::render::{render_frame, SpanSource};
use crate::setup::SnappedTri;

/// Parameters of post-process anti-aliasing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PostFxParams {
    /// Threshold on |z second difference| (24-bit depth units), `Zth`.
    pub zth: u32,
    /// A depth jump above this makes an edge class 2 (silhouette).
    pub zjump: u32,
    /// Also detect edges from reconstructed normals.
    pub normals: bool,
    /// Depth units per pixel used as the normal's z component.
    pub normal_scale: u32,
    /// cos θ threshold of the normal test, Q.16.
    pub cos_q16: u32,
    /// Blend class-1 (crease) edges in a first loop.
    pub creases: bool,
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
        }
    }
}

impl PostFxParams {
    /// A short label.
    pub fn label(&self) -> String {
        format!(
            "postfx zth={} zjump={}{}{}",
            self.zth,
            self.zjump,
            if self.normals { " normals" } else { "" },
            if self.creases { " creases" } else { "" }
        )
    }
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

/// Computes the edge bits of a depth buffer (see the module header).
pub fn detect_edges(z: &[u32], w: usize, h: usize, p: &PostFxParams) -> Edges {
    let at = |x: i64, y: i64| -> i64 {
        let x = x.clamp(0, w as i64 - 1) as usize;
        let y = y.clamp(0, h as i64 - 1) as usize;
        z[y * w + x] as i64
    };
    let mut ex = vec![0u8; w * h];
    let mut ey = vec![0u8; w * h];
    let class = |a: i64, b: i64| if (a - b).abs() > p.zjump as i64 { 2 } else { 1 };
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let c = at(x, y);
            for (dx, dy) in [(1i64, 0i64), (0, 1)] {
                let (zm, zp) = (at(x - dx, y - dy), at(x + dx, y + dy));
                let d2 = zp + zm - 2 * c;
                if d2.abs() > p.zth as i64 {
                    // Side with the larger first difference.
                    let (nx, ny) = if (zp - c).abs() >= (c - zm).abs() {
                        (x, y)
                    } else {
                        (x - dx, y - dy)
                    };
                    if nx >= 0 && ny >= 0 && nx + dx < w as i64 && ny + dy < h as i64 {
                        let k = ny as usize * w + nx as usize;
                        let cl = class(at(nx, ny), at(nx + dx, ny + dy));
                        let e = if dx == 1 { &mut ex[k] } else { &mut ey[k] };
                        *e = (*e).max(cl);
                    }
                }
            }
        }
    }
    if p.normals {
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
            // Scale down to stay in range: compare (dot·2^16)² < c²·na·nb.
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
    Edges { w, h, ex, ey }
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

/// One pass of loop 2 along rows (`transpose = false`: boundaries between rows y and
/// y+1, runs along x) or along columns. Reads `src`, or `dst` where `flag` is set;
/// writes `dst`, sets `flag`.
#[allow(clippy::too_many_arguments)]
fn run_pass(
    src: &[[u8; 3]],
    dst: &mut [[u8; 3]],
    flag: &mut [bool],
    skip: &[bool],
    e: &Edges,
    transpose: bool,
    reads: &mut u64,
) {
    let (w, h) = (e.w, e.h);
    // Along-run length u and across index v.
    let (nu, nv) = if transpose { (h, w) } else { (w, h) };
    let idx = |u: usize, v: usize| if transpose { u * w + v } else { v * w + u };
    // Edge across the boundary between v and v+1 at position u.
    let across = |u: usize, v: usize| {
        if transpose {
            e.ex[idx(u, v)]
        } else {
            e.ey[idx(u, v)]
        }
    };
    // Perpendicular edge between u and u+1 in line v.
    let perp = |u: usize, v: usize| {
        if transpose {
            e.ey[idx(u, v)] != 0
        } else {
            e.ex[idx(u, v)] != 0
        }
    };
    for v in 0..nv.saturating_sub(1) {
        // State machine: state 0 = outside a run, 1 = inside; count = run length.
        let mut state = 0;
        let mut count = 0usize;
        for u in 0..=nu {
            let on = u < nu && across(u, v) == 2;
            if on {
                if state == 0 {
                    state = 1;
                    count = 0;
                }
                count += 1;
                continue;
            }
            if state == 1 {
                state = 0;
                let (u0, len) = (u - count, count as i64);
                // End heights (in half pixels): step in line v (upper) → +1, line v+1 → −1.
                let end_h = |b: Option<usize>| match b {
                    None => 0,
                    Some(b) => {
                        if perp(b, v) {
                            1
                        } else if perp(b, v + 1) {
                            -1
                        } else {
                            0
                        }
                    }
                };
                let hl = end_h(u0.checked_sub(1));
                let hr = end_h((u < nu).then_some(u - 1).filter(|&b| b + 1 < nu));
                if hl == 0 && hr == 0 {
                    continue;
                }
                // Per-pixel (positive, negative) areas. Two steps on one side (U shape):
                // two half-lines meeting at 0 in the middle, integrated on half columns.
                let area = |k: i64| -> (i64, i64) {
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
                };
                {
                    for k in 0..len {
                        let (pos, neg) = area(k);
                        let uu = u0 + k as usize;
                        let (up, lo) = (idx(uu, v), idx(uu, v + 1));
                        if pos > 0 && !skip[up] {
                            *reads += 2;
                            let c = if flag[up] { dst[up] } else { src[up] };
                            let o = if flag[lo] { dst[lo] } else { src[lo] };
                            dst[up] = blend(c, o, pos);
                            flag[up] = true;
                        }
                        if neg > 0 && !skip[lo] {
                            *reads += 2;
                            let c = if flag[lo] { dst[lo] } else { src[lo] };
                            let o = if flag[up] { dst[up] } else { src[up] };
                            dst[lo] = blend(c, o, neg);
                            flag[lo] = true;
                        }
                    }
                }
            }
        }
    }
}

/// Loop 1: crease (class-1) edges. Returns the per-pixel "blended here" bits.
fn crease_pass(
    src: &[[u8; 3]],
    dst: &mut [[u8; 3]],
    z: &[u32],
    e: &Edges,
    reads: &mut u64,
) -> Vec<bool> {
    let (w, h) = (e.w, e.h);
    let mut done = vec![false; w * h];
    let at = |x: i64, y: i64| {
        z[(y.clamp(0, h as i64 - 1) as usize) * w + x.clamp(0, w as i64 - 1) as usize] as i64
    };
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let k = y as usize * w + x as usize;
            for (dx, dy, bit) in [(1i64, 0i64, e.ex[k]), (0, 1, e.ey[k])] {
                if bit != 1 {
                    continue;
                }
                // 1×4 depths across the crease: z0 z1 | z2 z3 (between z1 and z2).
                let z0 = at(x - dx, y - dy);
                let z1 = at(x, y);
                let z2 = at(x + dx, y + dy);
                let z3 = at(x + 2 * dx, y + 2 * dy);
                // Left plane z1 + s1·t, right plane z2 + s2·(t − 1); s1 = z1 − z0, s2 = z3 − z2.
                // Intersection: t* = (z2 − z1 − s2) / (s1 − s2), in Q.16.
                let (s1, s2) = (z1 - z0, z3 - z2);
                if s1 == s2 {
                    continue;
                }
                let num = (z2 - z1 - s2) as i128;
                let den = (s1 - s2) as i128;
                let t = ((num << 16) / den) as i64;
                if !(0..=1 << 16).contains(&t) {
                    continue;
                }
                let k2 = (y + dy) as usize * w + (x + dx) as usize;
                *reads += 2;
                let half = 1i64 << 15;
                if t < half {
                    dst[k] = blend(src[k], src[k2], half - t);
                    done[k] = true;
                } else if t > half {
                    dst[k2] = blend(src[k2], src[k], t - half);
                    done[k2] = true;
                }
            }
        }
    }
    done
}

/// Renders the baseline and post-processes it.
pub fn render(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    p: &PostFxParams,
) -> Result<AaFrame, AaError> {
    let src = SpanSource::new(tris, width, height)?;
    let frame = render_frame(&src, bg, width as usize, |_, _| {});
    let z = frame.depth();
    let (w, h) = (width as usize, height as usize);
    let img: Vec<[u8; 3]> = frame.rgb8().chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    let e = detect_edges(&z, w, h, p);
    let mut reads = 0u64;
    // Loop 1.
    let mut after1 = img.clone();
    let skip = if p.creases {
        crease_pass(&img, &mut after1, &z, &e, &mut reads)
    } else {
        vec![false; w * h]
    };
    // Loop 2: x pass then y pass, combined through the flag.
    let mut out = after1.clone();
    let mut flag = vec![false; w * h];
    run_pass(&after1, &mut out, &mut flag, &skip, &e, false, &mut reads);
    run_pass(&after1, &mut out, &mut flag, &skip, &e, true, &mut reads);
    let (visible, evals) = baseline_visible(tris, width, height)?;
    Ok(AaFrame {
        width,
        height,
        rgb: out.iter().flat_map(|c| *c).collect(),
        visible: Some(visible),
        stats: AaStats {
            depth_evals: evals,
            samples_written: (w * h) as u64,
            // z buffer read once per pixel per pass (edges), plus colour reads.
            sample_reads: 2 * (w * h) as u64 + reads,
            ..Default::default()
        },
    })
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
