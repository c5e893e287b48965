//! Exact spans of multi-scanning (seed 002, §2): each triangle's edges and planes set up
//! once, its x-interval on a sub-scanline rounded once to Q.16, and its depth and colour
//! planes restricted to a sub-scanline (see the module header of [`super`]).

use super::{COLOUR_MAX, ONE16};
use crate::raster::divisor::FloorDivisor;
use crate::raster::{round_div, RoundDivStep};
use crate::setup::ExactPlane as Plane;
use crate::setup::SnappedTri;

/// A plane restricted to one sub-scanline: `value(x16) = (k + s·x16) / d`.
#[derive(Clone, Copy, Debug)]
pub(super) struct RowPlane {
    pub(super) k: i128,
    pub(super) s: i128,
    pub(super) d: i128,
    /// `d` and `2d` prepared for division by multiplication, when `0 < d < 2^62`.
    pub(super) div: Option<(FloorDivisor, FloorDivisor)>,
}

/// [`RowPlane::div`] for denominator `d`.
fn divisors(d: i128) -> Option<(FloorDivisor, FloorDivisor)> {
    Some((FloorDivisor::new(d)?, FloorDivisor::new(2 * d)?))
}

impl RowPlane {
    /// The plane `(k + s·x16) / d` (its divisors prepared: once per plane, not per row).
    pub(super) fn new(k: i128, s: i128, d: i128) -> RowPlane {
        RowPlane {
            k,
            s,
            d,
            div: divisors(d),
        }
    }

    /// `round_div((k + s·x16) · 2^frac, d)`.
    #[inline]
    pub(super) fn at(&self, x16: i64, frac: u32) -> i64 {
        let n = self.k + self.s * x16 as i128;
        // The same quotient from two 64-bit divisions where they fit: with `n = q·d + r`,
        // `0 ≤ r < d`: `⌊(2n·2^f + d) / 2d⌋ = q·2^f + ⌊(2r·2^f + d) / 2d⌋` (`q·d·2^(f+1)`
        // is a multiple of `2d`). `n` in `i64` and `0 < d < 2^(61 − f)` keep every
        // intermediate inside `i64`, and so does the result while `|q| < 2^(61 − f)`.
        // Both divisions by multiplication ([`FloorDivisor`], prepared with the plane).
        // Otherwise the 128-bit division.
        if let (true, Some((dv, dv2)), Ok(n)) = (
            frac <= 24 && self.d < 1i128 << (61 - frac),
            &self.div,
            i64::try_from(n),
        ) {
            let d = self.d as i64;
            let q = dv.floor(n);
            if q.unsigned_abs() < 1 << (61 - frac) {
                let r = n - q * d;
                return (q << frac) + dv2.floor((r << (frac + 1)) + d);
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
    div: Option<(FloorDivisor, FloorDivisor)>,
}

impl RowPlanes {
    pub(super) fn new(p: &Plane, yden: i64) -> RowPlanes {
        let at0 = p.subscanline_row(0, yden);
        RowPlanes {
            k0: at0.k,
            ky: p.ny * 256 * 256,
            s: at0.s,
            d: at0.d,
            div: at0.div,
        }
    }

    #[inline]
    pub(super) fn row(&self, ynum: i64) -> RowPlane {
        RowPlane {
            k: self.k0 + self.ky * ynum as i128,
            s: self.s,
            d: self.d,
            div: self.div,
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
        RowPlane::new(k, self.nx * yd, d)
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

/// A triangle set up for multi-scanning. The fields a band's [`Cand`] copies (its y
/// extent and edges, its index and decal flag) come first and in this order (`repr(C)`),
/// so that making the candidate reads the start of the struct; the planes, read for the
/// triangles that are hit, follow.
#[derive(Clone, Debug)]
#[repr(C)]
pub(super) struct MsTri {
    /// `ymin`, `ymax` times `yden`.
    pub(super) ylo: i64,
    pub(super) yhi: i64,
    /// The non-horizontal edges, `ne` of them.
    pub(super) ne: usize,
    pub(super) idx: i32,
    pub(super) decal: bool,
    pub(super) edges: [MsEdge; 3],
    /// Flat colour (every colour plane constant: each [`RowPlane::at`] is exactly the
    /// plane's `v0`), clamped as the walk's colours are; `None` for a shaded triangle.
    pub(super) flat: Option<[i64; 3]>,
    pub(super) ymin: i64,
    pub(super) ymax: i64,
    /// Depth (the host face's plane for a decal) and colour planes on the sub-scanlines
    /// of the frame's denominator.
    pub(super) rows: [RowPlanes; 4],
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

/// Does a triangle of y extent `(ylo, yhi)` (Q.8 · `yden`) reach the sub-scanline at
/// `y = 256·ynum` (Q.8 · `yden`)? From below: `ylo ≤ y < yhi`; from above (`y → y⁻`):
/// `ylo < y ≤ yhi`.
#[inline(always)]
fn reaches((ylo, yhi): (i64, i64), y: i64, from_above: bool) -> bool {
    if from_above {
        ylo < y && y <= yhi
    } else {
        ylo <= y && y < yhi
    }
}

impl MsTri {
    /// The Q.16 x-interval `[xl, xr)` on the sub-scanline `y = ynum/yden` (`yden` of
    /// [`prepare`]), if non-empty. `from_above` takes the limit `y → y⁻` (the
    /// cross-section just above the line: `ymin < y ≤ ymax`) instead of `y → y⁺`
    /// (`ymin ≤ y < ymax`).
    #[inline]
    pub(super) fn interval(&self, ynum: i64, from_above: bool) -> Option<(i64, i64)> {
        let y = 256 * ynum; // Q.8 · yden
        if !reaches((self.ylo, self.yhi), y, from_above) {
            return None;
        }
        // The least and greatest x at which the edges that reach the line (inclusive y
        // extent) cross it.
        let (mut lo, mut hi) = (i64::MAX, i64::MIN);
        for e in self.edges[..self.ne]
            .iter()
            .filter(|e| e.ya <= y && y <= e.yb)
        {
            let x = round_div(e.a + e.b * ynum as i128, e.d) as i64;
            lo = lo.min(x);
            hi = hi.max(x);
        }
        (lo < hi).then_some((lo, hi))
    }

    /// Does the sub-scanline `y = ynum/yden` see a different interval from above than
    /// from below (a horizontal edge of the triangle lies on it)? (The renderer asks
    /// [`Cand::sides_differ`]; this is its reference.)
    #[cfg(test)]
    pub(super) fn sides_differ(&self, ynum: i64) -> bool {
        let y = 256 * ynum;
        (self.ylo == y || self.yhi == y)
            && (self.interval(ynum, true).is_some() || self.interval(ynum, false).is_some())
    }
}

/// A non-horizontal edge in 64-bit form, normalised to a positive denominator: on
/// `y = ynum/yden` it is at `x16 = ⌊(2(a + b·ynum) + d) / 2d⌋`, the value
/// [`MsTri::interval`] rounds from [`MsEdge`].
#[derive(Clone, Copy, Debug, Default)]
struct Edge64 {
    a: i64,
    b: i64,
    d: i64,
}

impl Edge64 {
    #[inline(always)]
    fn x_at(&self, ynum: i64) -> i64 {
        (2 * (self.a + self.b * ynum) + self.d).div_euclid(2 * self.d)
    }
}

/// A band's candidate triangle as the hit test of every sub-scanline reads it, packed
/// (104 bytes) and stored contiguously for the band; what a hit needs besides is in
/// [`CandHit`], read only for the triangles a sub-scanline hits.
///
/// The edges are the triangle's two *chains*: the long edge, which spans the whole y
/// extent, and the short edge on the line (`upper` above `split`, `lower` from `split`
/// on). Every line the triangle spans meets the long edge and one short edge, and where
/// it meets both short edges (`y = split`, the middle vertex) they meet it at the vertex,
/// exactly: so the interval is the long edge's x and the chosen short edge's x, one
/// compare instead of a test per edge. With a horizontal edge (left out of the edges)
/// the two others both span the extent, and `upper = lower`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cand {
    ylo: i64,
    yhi: i64,
    split: i64,
    long: Edge64,
    upper: Edge64,
    lower: Edge64,
    /// An edge does not fit 64 bits: the triangle's own [`MsTri::interval`] is used.
    wide: bool,
}

/// The rest of a band's candidate, read for the triangles a line hits.
pub(super) struct CandHit<'a> {
    pub(super) t: &'a MsTri,
    /// Copies of the triangle's input index and decal flag.
    pub(super) idx: i32,
    pub(super) decal: bool,
    /// The depth plane's rows (a copy of `t.rows[0]`).
    pub(super) z: RowPlanes,
}

impl<'a> CandHit<'a> {
    pub(super) fn new(t: &'a MsTri) -> CandHit<'a> {
        CandHit {
            t,
            idx: t.idx,
            decal: t.decal,
            z: t.rows[0],
        }
    }
}

impl Cand {
    pub(super) fn new(t: &MsTri) -> Cand {
        // Every intermediate of the 64-bit rounding must stay inside `i64` for the
        // sub-scanlines the edge spans (`|ynum| ≤ max(|ya|, |yb|) / 256`).
        const LIM: i128 = 1 << 60;
        let narrow = |e: &MsEdge| -> Option<Edge64> {
            let (a, b, d) = if e.d < 0 {
                (-e.a, -e.b, -e.d)
            } else {
                (e.a, e.b, e.d)
            };
            let yn = (e.ya.unsigned_abs().max(e.yb.unsigned_abs()) / 256 + 1) as i128;
            let reach = a.abs().checked_add(b.abs().checked_mul(yn)?)?;
            (reach < LIM && d < LIM).then_some(Edge64 {
                a: a as i64,
                b: b as i64,
                d: d as i64,
            })
        };
        let edges = &t.edges[..t.ne];
        let wide = Cand {
            ylo: t.ylo,
            yhi: t.yhi,
            split: 0,
            long: Edge64::default(),
            upper: Edge64::default(),
            lower: Edge64::default(),
            wide: true,
        };
        // The long edge spans the extent; the upper one starts at the top, the lower one
        // ends at the bottom (with a horizontal edge: both of the others span it).
        let long = edges.iter().position(|e| e.ya == t.ylo && e.yb == t.yhi);
        let (Some(l), 2 | 3) = (long, t.ne) else {
            return wide;
        };
        let others = || (0..t.ne).filter(move |&k| k != l).map(|k| &edges[k]);
        let upper = others().find(|e| e.ya == t.ylo);
        let lower = others().find(|e| e.yb == t.yhi);
        let (Some(u), Some(w)) = (upper, lower) else {
            return wide;
        };
        // Where the lower edge takes over: the middle vertex (with a horizontal edge, the
        // top, so the lower edge, the same as the upper one, is taken everywhere).
        let split = w.ya;
        match (narrow(&edges[l]), narrow(u), narrow(w)) {
            (Some(long), Some(upper), Some(lower)) => Cand {
                ylo: t.ylo,
                yhi: t.yhi,
                split,
                long,
                upper,
                lower,
                wide: false,
            },
            _ => wide,
        }
    }

    /// [`MsTri::interval`] of the triangle `t` (the one this candidate was made from).
    #[inline]
    pub(super) fn interval(&self, t: &MsTri, ynum: i64, from_above: bool) -> Option<(i64, i64)> {
        if self.wide {
            return t.interval(ynum, from_above);
        }
        let y = 256 * ynum; // Q.8 · yden
        if !reaches((self.ylo, self.yhi), y, from_above) {
            return None;
        }
        let short = if y < self.split {
            &self.upper
        } else {
            &self.lower
        };
        let (xa, xb) = (self.long.x_at(ynum), short.x_at(ynum));
        let (lo, hi) = (xa.min(xb), xa.max(xb));
        (lo < hi).then_some((lo, hi))
    }

    /// [`MsTri::sides_differ`] of the triangle `t`.
    #[inline]
    pub(super) fn sides_differ(&self, t: &MsTri, ynum: i64) -> bool {
        let y = 256 * ynum;
        (self.ylo == y || self.yhi == y)
            && (self.interval(t, ynum, true).is_some() || self.interval(t, ynum, false).is_some())
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
            let p = RowPlane::new(
                draw(kb),
                draw(kb.min(40)),
                match draw(db) {
                    0 => 1,
                    d => d,
                },
            );
            let x = (draw(28) as i64).clamp(-(1 << 27), 1 << 28);
            for frac in [0, 12, 20] {
                let want = round_div((p.k + p.s * x as i128) << frac, p.d) as i64;
                assert_eq!(p.at(x, frac), want, "{p:?} at {x}, frac {frac}");
            }
        }
    }

    /// A candidate's 64-bit hit test gives the triangle's intervals on every sub-scanline
    /// it spans, from above and from below, for on-screen triangles and for triangles far
    /// outside the screen (whose edges take the 128-bit path).
    #[test]
    fn candidate_intervals_equal_the_triangles() {
        let (w, h) = (300u32, 200u32);
        let mut tris = crate::rng::random_tris(0x0ca0_d1da, 300, w, h);
        let far = crate::rng::random_tris(0x0fa2_0ff5, 100, w, h);
        let far_at = |t: &SnappedTri, s: i32| {
            let mut t = *t;
            for p in &mut t.v {
                p[0] = p[0].saturating_mul(s);
                p[1] = p[1].saturating_mul(s / 2);
            }
            t
        };
        tris.extend(far.iter().map(|t| far_at(t, 1 << 14)));
        tris.extend(far.iter().map(|t| far_at(t, 1 << 6)));
        // Edges 128 px tall from a pixel row: on the sub-scanlines of 8 and 32 per pixel
        // some meet them exactly half-way between two Q.16 positions, where the rounding
        // direction decides.
        let mut rng = crate::rng::Lcg64(0x71e5_0f0a);
        tris.extend((0..100).map(|_| {
            let mut r = |m: u64| (rng.step() % m) as i32;
            let (px, py) = (r(150 * 256), 256 * r(60));
            let mut t = far[0];
            t.v = [
                [px, py],
                [px + 1 + 2 * r(2000), py + 32768],
                [px - 1 - r(9000), py + r(32768)],
            ];
            t
        }));
        let (mut hits, mut wide, mut ties) = (0, 0, 0);
        for yden in [2i64, 8, 32] {
            for (k, t) in tris.iter().enumerate() {
                let Some(mt) = prepare(k, t, yden) else {
                    continue;
                };
                let c = Cand::new(&mt);
                wide += c.wide as usize;
                let (lo, hi) = (mt.ylo / 256 - 1, mt.yhi / 256 + 1);
                let step = ((hi - lo) / 4000).max(1) as usize;
                for ynum in (lo..=hi).step_by(step).chain([mt.ylo / 256, mt.yhi / 256]) {
                    ties += mt.edges[..mt.ne]
                        .iter()
                        .filter(|e| {
                            let y = 256 * ynum;
                            let n = 2 * (e.a + e.b * ynum as i128) + e.d;
                            e.ya <= y && y <= e.yb && n % (2 * e.d) == 0
                        })
                        .count();
                    for above in [false, true] {
                        let want = mt.interval(ynum, above);
                        hits += want.is_some() as usize;
                        let got = c.interval(&mt, ynum, above);
                        assert_eq!(got, want, "triangle {k}, {ynum}/{yden}");
                    }
                    assert_eq!(c.sides_differ(&mt, ynum), mt.sides_differ(ynum));
                }
            }
        }
        assert!(
            hits > 10_000 && wide > 50 && ties > 500,
            "{hits} hits, {wide} wide candidates, {ties} ties"
        );
    }
}
