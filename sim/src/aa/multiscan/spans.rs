//! Exact spans of multi-scanning (seed 002, §2): each triangle's edges and planes set up
//! once, its x-interval on a sub-scanline rounded once to Q.16, and its depth and colour
//! planes restricted to a sub-scanline (see the module header of [`super`]).

use super::{COLOUR_MAX, ONE16};
use crate::raster::{round_div, RoundDivStep};
use crate::setup::ExactPlane as Plane;
use crate::setup::SnappedTri;

/// A plane restricted to one sub-scanline: `value(x16) = (k + s·x16) / d`.
#[derive(Clone, Copy, Debug)]
pub(super) struct RowPlane {
    pub(super) k: i128,
    pub(super) s: i128,
    pub(super) d: i128,
}

impl RowPlane {
    /// `round_div((k + s·x16) · 2^frac, d)`.
    #[inline]
    pub(super) fn at(&self, x16: i64, frac: u32) -> i64 {
        let n = self.k + self.s * x16 as i128;
        // The same quotient from two 64-bit divisions where they fit: with `n = q·d + r`,
        // `0 ≤ r < d`: `⌊(2n·2^f + d) / 2d⌋ = q·2^f + ⌊(2r·2^f + d) / 2d⌋` (`q·d·2^(f+1)`
        // is a multiple of `2d`). `n` in `i64` and `0 < d < 2^(61 − f)` keep every
        // intermediate inside `i64`, and so does the result while `|q| < 2^(61 − f)`.
        // Otherwise the 128-bit division.
        if let (true, Ok(n)) = (
            frac <= 24 && 0 < self.d && self.d < 1i128 << (61 - frac),
            i64::try_from(n),
        ) {
            let d = self.d as i64;
            let q = n.div_euclid(d);
            if q.unsigned_abs() < 1 << (61 - frac) {
                let r = n - q * d;
                return (q << frac) + ((r << (frac + 1)) + d).div_euclid(2 * d);
            }
        }
        round_div(n << frac, self.d) as i64
    }
}

/// A plane's [`RowPlane`]s for every sub-scanline of one denominator: `k` is linear in
/// `ynum`, `k = k0 + ky·ynum`, so it is set up once per triangle instead of once per
/// sub-scanline (the same integers as [`Plane::subscanline_row`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct RowPlanes {
    pub(super) k0: i128,
    pub(super) ky: i128,
    pub(super) s: i128,
    pub(super) d: i128,
}

impl RowPlanes {
    pub(super) fn new(p: &Plane, yden: i64) -> RowPlanes {
        let at0 = p.subscanline_row(0, yden);
        RowPlanes {
            k0: at0.k,
            ky: p.ny * 256 * 256,
            s: at0.s,
            d: at0.d,
        }
    }

    #[inline]
    pub(super) fn row(&self, ynum: i64) -> RowPlane {
        RowPlane {
            k: self.k0 + self.ky * ynum as i128,
            s: self.s,
            d: self.d,
        }
    }
}

impl Plane {
    /// v = v0 + (nx·(x16/256 − x0) + ny·(256·ynum/yden − y0)) / area2, over the common
    /// denominator 256·yden·area2.
    pub(super) fn subscanline_row(&self, ynum: i64, yden: i64) -> RowPlane {
        let (yn, yd) = (ynum as i128, yden as i128);
        let d = 256 * yd * self.area2;
        let k =
            self.v0 * d - self.nx * 256 * self.x0 * yd + self.ny * (256 * yn - self.y0 * yd) * 256;
        RowPlane {
            k,
            s: self.nx * yd,
            d,
        }
    }
}

/// A non-horizontal edge on the sub-scanlines of the frame's denominator `yden`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct MsEdge {
    /// The edge's y extent `[ya, yb]`, Q.8 · `yden` (compared with `256·ynum`).
    pub(super) ya: i64,
    pub(super) yb: i64,
    /// On `y = ynum/yden` the edge is at `x16 = round(x(ynum))`, `x(ynum) = (a + b·ynum) / d`:
    /// `256·(px + (qx − px)(y − py)/(qy − py))` over the common denominator
    /// `(qy − py)·yden`, set up once per triangle.
    pub(super) a: i128,
    pub(super) b: i128,
    pub(super) d: i128,
}

#[derive(Clone, Debug)]
pub(super) struct MsTri {
    pub(super) idx: i32,
    pub(super) ymin: i64,
    pub(super) ymax: i64,
    /// `ymin`, `ymax` times `yden`.
    pub(super) ylo: i64,
    pub(super) yhi: i64,
    /// The non-horizontal edges, `ne` of them.
    pub(super) edges: [MsEdge; 3],
    pub(super) ne: usize,
    /// Depth (the host face's plane for a decal) and colour planes on the sub-scanlines
    /// of the frame's denominator.
    pub(super) rows: [RowPlanes; 4],
    pub(super) decal: bool,
    /// Flat colour (every colour plane constant: each [`RowPlane::at`] is exactly the
    /// plane's `v0`), clamped as the walk's colours are; `None` for a shaded triangle.
    pub(super) flat: Option<[i64; 3]>,
    /// Per colour plane, its step by one pixel (`s·2^16 / d`, the same on every
    /// sub-scanline), prepared once for stepping colours along a piece.
    pub(super) cstep: [RoundDivStep; 3],
}

pub(super) fn prepare(k: usize, t: &SnappedTri, yden: i64) -> Option<MsTri> {
    let v = t.v;
    let zp = match &t.host {
        Some(h) => Plane::new(h.v, h.z.map(|x| x as i64))?,
        None => Plane::new(v, t.z.map(|x| x as i64))?,
    };
    let cp = |ch: usize| Plane::new(v, [0, 1, 2].map(|q| t.c[q][ch] as i64));
    let c = [cp(0)?, cp(1)?, cp(2)?];
    let v = v.map(|p| [p[0] as i64, p[1] as i64]);
    let ymin = v.iter().map(|p| p[1]).min().unwrap();
    let ymax = v.iter().map(|p| p[1]).max().unwrap();
    let mut edges = [MsEdge::default(); 3];
    let mut ne = 0;
    let yd = yden as i128;
    for e in 0..3 {
        let (p, q) = (v[e], v[(e + 1) % 3]);
        if p[1] == q[1] {
            continue;
        }
        let (px, py, qx, qy) = (p[0] as i128, p[1] as i128, q[0] as i128, q[1] as i128);
        // 256·(px·(qy − py)·yd + (qx − px)·(256·ynum − py·yd)) / ((qy − py)·yd).
        edges[ne] = MsEdge {
            ya: p[1].min(q[1]) * yden,
            yb: p[1].max(q[1]) * yden,
            a: 256 * yd * (px * (qy - py) - (qx - px) * py),
            b: 256 * 256 * (qx - px),
            d: (qy - py) * yd,
        };
        ne += 1;
    }
    let rows = [
        RowPlanes::new(&zp, yden),
        RowPlanes::new(&c[0], yden),
        RowPlanes::new(&c[1], yden),
        RowPlanes::new(&c[2], yden),
    ];
    let flat = c
        .iter()
        .all(|p| p.nx == 0 && p.ny == 0)
        .then(|| c.map(|p| (p.v0 as i64).clamp(0, COLOUR_MAX)));
    let cstep = [1, 2, 3].map(|k| RoundDivStep::new(rows[k].s * ONE16 as i128, rows[k].d));
    Some(MsTri {
        idx: k as i32,
        ymin,
        ymax,
        ylo: ymin * yden,
        yhi: ymax * yden,
        edges,
        ne,
        rows,
        decal: t.host.is_some(),
        flat,
        cstep,
    })
}

impl MsTri {
    /// The Q.16 x-interval `[xl, xr)` on the sub-scanline `y = ynum/yden` (`yden` of
    /// [`prepare`]), if non-empty. `from_above` takes the limit `y → y⁻` (the
    /// cross-section just above the line: `ymin < y ≤ ymax`) instead of `y → y⁺`
    /// (`ymin ≤ y < ymax`).
    #[inline]
    pub(super) fn interval(&self, ynum: i64, from_above: bool) -> Option<(i64, i64)> {
        let y = 256 * ynum; // Q.8 · yden
        let hit = if from_above {
            self.ylo < y && y <= self.yhi
        } else {
            self.ylo <= y && y < self.yhi
        };
        if !hit {
            return None;
        }
        let (mut lo, mut hi) = (i64::MAX, i64::MIN);
        for e in &self.edges[..self.ne] {
            if y < e.ya || y > e.yb {
                continue;
            }
            let x = round_div(e.a + e.b * ynum as i128, e.d) as i64;
            lo = lo.min(x);
            hi = hi.max(x);
        }
        (lo < hi).then_some((lo, hi))
    }

    /// Does the sub-scanline `y = ynum/yden` see a different interval from above than
    /// from below (a horizontal edge of the triangle lies on it)?
    pub(super) fn sides_differ(&self, ynum: i64) -> bool {
        let y = 256 * ynum;
        (self.ylo == y || self.yhi == y)
            && (self.interval(ynum, true).is_some() || self.interval(ynum, false).is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 64-bit path of [`RowPlane::at`] gives the 128-bit rounded quotient, on planes
    /// inside and outside its bounds (small and huge denominators, negative numerators,
    /// every shift the renderer uses).
    #[test]
    fn row_plane_at_equals_the_wide_division() {
        let mut rng = crate::rng::Lcg64(0x5eed_0a7e);
        let mut draw = |bits: u32| -> i128 {
            let v = ((rng.step() as i128) << 64 | rng.step() as i128) & ((1i128 << bits) - 1);
            if rng.step() & 1 == 0 {
                -v
            } else {
                v
            }
        };
        for case in 0..200_000 {
            let kb = [30, 50, 61, 63, 70][case % 5];
            let db = [8, 30, 40, 41, 42, 50][(case / 5) % 6];
            let p = RowPlane {
                k: draw(kb),
                s: draw(kb.min(40)),
                d: match draw(db) {
                    0 => 1,
                    d => d,
                },
            };
            let x = (draw(28) as i64).clamp(-(1 << 27), 1 << 28);
            for frac in [0, 12, 20] {
                let want = round_div((p.k + p.s * x as i128) << frac, p.d) as i64;
                assert_eq!(p.at(x, frac), want, "{p:?} at {x}, frac {frac}");
            }
        }
    }
}
