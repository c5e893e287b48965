//! Edge detection of the post-process (seed 004, "edges from the z-buffer" and "edges
//! from normals"): second differences, edge bits between pixels and their class (see the
//! module header of [`super`]).

use super::{NormalSource, PostFxParams, StoredNormal};
use rayon::prelude::*;

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

/// The second differences the edge test and the crease pass read (seed eq. 7): the
/// buffers kept during drawing, or the final z-buffer's, computed where they are read
/// (the values of [`second_differences`], without its two frame-sized buffers).
#[derive(Clone, Copy, Debug)]
pub enum SecondDiffs<'a> {
    /// `(d2x, d2y)` buffers, row-major.
    Kept(&'a [i32], &'a [i32]),
    /// From the `w × h` z-buffer the reader passes, borders replicated.
    FinalZ,
}

impl SecondDiffs<'_> {
    /// `d2x` at pixel `(x, y)` of the `w`-wide z-buffer `z`.
    #[inline]
    pub fn dx(&self, z: &[u32], w: usize, x: usize, y: usize) -> i32 {
        match self {
            SecondDiffs::Kept(d, _) => d[y * w + x],
            SecondDiffs::FinalZ => {
                let r = &z[y * w..(y + 1) * w];
                r[(x + 1).min(w - 1)] as i32 + r[x.saturating_sub(1)] as i32 - 2 * r[x] as i32
            }
        }
    }

    /// `d2y` at pixel `(x, y)` of the `w × h` z-buffer `z`.
    #[inline]
    pub fn dy(&self, z: &[u32], w: usize, h: usize, x: usize, y: usize) -> i32 {
        match self {
            SecondDiffs::Kept(_, d) => d[y * w + x],
            SecondDiffs::FinalZ => {
                let at = |y: usize| z[y * w + x] as i32;
                at((y + 1).min(h - 1)) + at(y.saturating_sub(1)) - 2 * at(y)
            }
        }
    }
}

impl SecondDiffs<'_> {
    /// `d2x` of row `y` of the `w`-wide z-buffer `z` into `out` (`w` long): the values of
    /// [`SecondDiffs::dx`], a row at a time.
    pub fn dx_row(&self, z: &[u32], w: usize, y: usize, out: &mut [i32]) {
        match self {
            SecondDiffs::Kept(d, _) => out.copy_from_slice(&d[y * w..(y + 1) * w]),
            SecondDiffs::FinalZ => {
                let r = &z[y * w..(y + 1) * w];
                let at = |x: usize| {
                    r[(x + 1).min(w - 1)] as i32 + r[x.saturating_sub(1)] as i32 - 2 * r[x] as i32
                };
                // The borders replicate; between them, the three pixels around each.
                out[0] = at(0);
                out[w - 1] = at(w - 1);
                for (o, t) in out[1..].iter_mut().zip(r.windows(3)) {
                    *o = t[2] as i32 + t[0] as i32 - 2 * t[1] as i32;
                }
            }
        }
    }

    /// `d2y` of row `y` of the `w × h` z-buffer `z` into `out` (`w` long): the values of
    /// [`SecondDiffs::dy`], a row at a time.
    pub fn dy_row(&self, z: &[u32], w: usize, h: usize, y: usize, out: &mut [i32]) {
        match self {
            SecondDiffs::Kept(_, d) => out.copy_from_slice(&d[y * w..(y + 1) * w]),
            SecondDiffs::FinalZ => {
                let row = |y: usize| &z[y * w..(y + 1) * w];
                let (up, r, dn) = (row(y.saturating_sub(1)), row(y), row((y + 1).min(h - 1)));
                for (o, ((&a, &b), &c)) in out.iter_mut().zip(up.iter().zip(r).zip(dn)) {
                    *o = c as i32 + a as i32 - 2 * b as i32;
                }
            }
        }
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

/// Computes the edge bits of a finished depth buffer: second differences from `z`,
/// reconstructed normals (see the module header). Equivalent to [`detect_edges_from`]
/// with the buffers of [`second_differences`] and no stored normals.
pub fn detect_edges(z: &[u32], w: usize, h: usize, p: &PostFxParams) -> Edges {
    detect_edges_with(z, SecondDiffs::FinalZ, None, w, h, p)
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
    detect_edges_with(z, SecondDiffs::Kept(d2x, d2y), stored, w, h, p)
}

/// [`detect_edges_from`] with the second differences `d2` (kept buffers, or computed
/// from `z` where read).
pub fn detect_edges_with(
    z: &[u32],
    d2: SecondDiffs<'_>,
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
    // the class of the pair (P, Q). Each row first finds which of its pixels (and of the
    // next row's) exceed Zth, so that only boundaries next to such a pixel are looked at.
    ex.par_chunks_mut(w)
        .zip(ey.par_chunks_mut(w))
        .enumerate()
        .for_each_init(
            || [vec![0; w], vec![0; w], vec![0; w]],
            |[dx, dy, dy1], (y, (exr, eyr))| {
                d2.dx_row(z, w, y, dx);
                d2.dy_row(z, w, h, y, dy);
                if y + 1 < h {
                    d2.dy_row(z, w, h, y + 1, dy1);
                }
                let yi = y as i64;
                for x in 0..w {
                    if !(over(dx[x])
                        || over(dy[x])
                        || (x + 1 < w && over(dx[x + 1]))
                        || (y + 1 < h && over(dy1[x])))
                    {
                        continue;
                    }
                    let xi = x as i64;
                    if x + 1 < w
                        && ((over(dx[x]) && forward(xi, yi, 1, 0))
                            || (over(dx[x + 1]) && !forward(xi + 1, yi, 1, 0)))
                    {
                        exr[x] = class(at(xi, yi), at(xi + 1, yi));
                    }
                    if y + 1 < h
                        && ((over(dy[x]) && forward(xi, yi, 0, 1))
                            || (over(dy1[x]) && !forward(xi, yi + 1, 0, 1)))
                    {
                        eyr[x] = class(at(xi, yi), at(xi, yi + 1));
                    }
                }
            },
        );
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
pub(super) fn reconstructed_normal_edges(
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
