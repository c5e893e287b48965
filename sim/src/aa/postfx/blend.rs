//! The blending loops of the post-process (seed 004, Fig. 7, 13, 16, 17, eqs. 17 and 18):
//! loop 1 on crease edges, loop 2's run state machine and trapezoid blending (see the
//! module header of [`super`]).

use super::{Edges, SecondDiffs};
use rayon::prelude::*;

/// One blend of loop 1: the pixel written and its new colour.
type CreaseWrite = (usize, [u8; 3]);

#[inline]
pub(super) fn blend(c: [u8; 3], o: [u8; 3], a_q16: i64) -> [u8; 3] {
    let a = a_q16.clamp(0, 1 << 16);
    [0, 1, 2].map(|k| ((c[k] as i64 * ((1 << 16) - a) + o[k] as i64 * a + (1 << 15)) >> 16) as u8)
}

/// Signed area (Q.16 of a pixel) under the line `h(t)`, `t ∈ [k, k+1]`, where `h` runs
/// linearly from `h0` at `t = 0` to `h1` at `t = len` (heights in halves: ±1 = ±½ pixel).
/// Returns `(positive part, negative part)` magnitudes.
pub(super) fn column_area(h0: i64, h1: i64, len: i64, k: i64) -> (i64, i64) {
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
pub(super) struct PassView<'a> {
    pub(super) e: &'a Edges,
    pub(super) transpose: bool,
    /// Along-run length.
    pub(super) nu: usize,
    /// Number of lines across.
    pub(super) nv: usize,
}

impl PassView<'_> {
    pub(super) fn new(e: &Edges, transpose: bool) -> PassView<'_> {
        let (nu, nv) = if transpose { (e.h, e.w) } else { (e.w, e.h) };
        PassView {
            e,
            transpose,
            nu,
            nv,
        }
    }

    /// Pixel index of `(u, v)`.
    pub(super) fn idx(&self, u: usize, v: usize) -> usize {
        if self.transpose {
            u * self.e.w + v
        } else {
            v * self.e.w + u
        }
    }

    /// Edge across the boundary between v and v+1 at position u.
    pub(super) fn across(&self, u: usize, v: usize) -> u8 {
        if self.transpose {
            self.e.ex[self.idx(u, v)]
        } else {
            self.e.ey[self.idx(u, v)]
        }
    }

    /// Perpendicular edge between u and u+1 in line v.
    pub(super) fn perp(&self, u: usize, v: usize) -> bool {
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
    pub(super) fn runs(&self, v: usize, window: bool) -> Vec<(usize, usize)> {
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
    pub(super) fn end_height(&self, v: usize, b: usize, c: usize, window: bool) -> i64 {
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
pub(super) fn run_area(hl: i64, hr: i64, len: i64, k: i64) -> (i64, i64) {
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

/// The colour buffer of the loop-2 passes, blended in place; never writes a pixel in
/// `skip` (blended by loop 1).
///
/// The seed keeps two buffers and a 1-bit flag per pixel: a pass reads the source image,
/// or the anti-aliased buffer where the flag says the pixel was blended, and writes the
/// anti-aliased buffer. That buffer starts as a copy of the source and a pixel differs
/// from it only once blended, when its flag is set; so the value the flag selects is
/// always the anti-aliased buffer's, and one buffer blended in place gives the same
/// image.
pub(super) struct PassBufs<'a> {
    pub(super) img: &'a mut [[u8; 3]],
    pub(super) skip: &'a [bool],
    pub(super) reads: &'a mut u64,
}

impl PassBufs<'_> {
    /// Blends pixel `a` toward pixel `o` by `area` (Q.16), if positive and not skipped.
    pub(super) fn blend_toward(&mut self, a: usize, o: usize, area: i64) {
        if area > 0 && !self.skip[a] {
            *self.reads += 2;
            self.img[a] = blend(self.img[a], self.img[o], area);
        }
    }
}

/// One pass of loop 2 along rows (`transpose = false`: boundaries between rows y and
/// y+1, runs along x) or along columns, blending [`PassBufs::img`] in place.
pub(super) fn run_pass(bufs: &mut PassBufs, e: &Edges, transpose: bool, window: bool) {
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
/// sz1)`. The numerator is the second difference at `sz2` (`d2`: the buffer kept during
/// drawing, or the final z-buffer's), the denominator the change of slope; `s` is the distance from the centre of
/// `sz3` back to the line where the two planes (through `sz1, sz2` and `sz3, sz4`) meet.
/// The pixel the crease does not reach the centre of takes `|s − ½|` of its neighbour.
#[allow(clippy::too_many_arguments)]
pub(super) fn crease_pass(
    img: &mut [[u8; 3]],
    z: &[u32],
    d2: SecondDiffs<'_>,
    e: &Edges,
    reads: &mut u64,
) -> Vec<bool> {
    let (w, h) = (e.w, e.h);
    let mut done = vec![false; w * h];
    let at = |x: i64, y: i64| {
        z[(y.clamp(0, h as i64 - 1) as usize) * w + x.clamp(0, w as i64 - 1) as usize] as i64
    };
    // Every blend reads the image as it was before the loop, so the blends of each row
    // are found in parallel and then written in the sequential order (a later write to
    // the same pixel wins).
    let src = &*img;
    let rows: Vec<Vec<Option<CreaseWrite>>> = (0..h as i64)
        .into_par_iter()
        .map(|y| {
            let mut writes = Vec::new();
            let row = y as usize * w..(y as usize + 1) * w;
            let (exr, eyr) = (&e.ex[row.clone()], &e.ey[row]);
            for (x, (&bx, &by)) in exr.iter().zip(eyr).enumerate() {
                if bx != 1 && by != 1 {
                    continue;
                }
                let x = x as i64;
                let k = y as usize * w + x as usize;
                for (dx, dy, bit) in [(1i64, 0i64, bx), (0, 1, by)] {
                    if bit != 1 {
                        continue;
                    }
                    let (xu, yu) = (x as usize, y as usize);
                    let d2 = if dx == 1 {
                        d2.dx(z, w, xu, yu)
                    } else {
                        d2.dy(z, w, h, xu, yu)
                    };
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
                        writes.push(Some((k, blend(src[k], src[k2], s - half))));
                    } else if s < half {
                        writes.push(Some((k2, blend(src[k2], src[k], half - s))));
                    } else {
                        writes.push(None);
                    }
                }
            }
            writes
        })
        .collect();
    for w in rows.into_iter().flatten() {
        *reads += 2;
        if let Some((k, c)) = w {
            img[k] = c;
            done[k] = true;
        }
    }
    done
}
