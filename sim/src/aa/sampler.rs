//! Point-sampled z-buffer on regular sample lattices (shared by the corner-sampling and
//! supersampling methods).
//!
//! A [`Lattice`] is a regular grid of sample points in pixel units,
//! `x = (a·sx + ox) / den`, `y = (b·sy + oy) / den` for `a < nx`, `b < ny`, all integers,
//! so every sample position is an exact rational. Coverage uses the edge functions of the
//! snapped (Q.8) triangle multiplied by `den`, exactly in `i64`, with the same top-left
//! rule as span setup (a sample on an edge belongs to the triangle if the edge is a left
//! edge, or a top edge). Depth and intensity are planes through the snapped vertices; per
//! lattice row `b` the value at `a = 0` is the exact rational rounded to Q.32, and the
//! value at `a` is `(V(0, b) + a·step) >> 20` (depth, Q24.12) or `>> 32` (intensity, already
//! Q8.12), `step` the per-sample increment
//! rounded to Q.32 (a closed form anchored at `a = 0`, so two triangles on one plane, a
//! decal and its host, get identical depths at every sample). Triangles are drawn in
//! scene order with the array's depth test: `Z < ZB`, or `Z ≤ ZB` for a decal.
//!
//! Intensities follow the span-setup convention (`docs/formats.md`): a Q8.12 value
//! carries the +2048 rounding offset, so the background is stored as `bg·4096 + 2048`
//! and resolves truncate.

use crate::raster::edge::{rewind, winding, EdgeFn};
use crate::raster::rows::Bands;
use crate::raster::{ceil_div, round_div};
use crate::setup::{ExactPlane as Plane, SnappedTri};
use rayon::prelude::*;

mod depth_bounds;
mod fill;
use depth_bounds::{DepthBounds, DEPTH_BOUNDS};
use fill::fill_range;

/// A regular sample lattice (see the module header).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lattice {
    /// Samples per row.
    pub nx: u32,
    /// Rows.
    pub ny: u32,
    /// x step numerator.
    pub sx: i64,
    /// y step numerator.
    pub sy: i64,
    /// x offset numerator.
    pub ox: i64,
    /// y offset numerator.
    pub oy: i64,
    /// Common denominator (pixel units).
    pub den: i64,
}

impl Lattice {
    /// Position of sample `(a, b)` in pixels (for reports and tests).
    pub fn pos(&self, a: u32, b: u32) -> (f64, f64) {
        (
            (a as i64 * self.sx + self.ox) as f64 / self.den as f64,
            (b as i64 * self.sy + self.oy) as f64 / self.den as f64,
        )
    }
}

/// The contents of one lattice after rasterization.
#[derive(Clone, Debug)]
pub struct SampleBuf {
    /// The lattice.
    pub lat: Lattice,
    /// Depth per sample, Q24.12 (`i64::MAX` where nothing was drawn).
    pub z: Vec<i64>,
    /// Intensity per sample, Q8.12 per channel.
    pub rgb: Vec<[u32; 3]>,
    /// Input index of the triangle that owns the sample, −1 for background.
    pub tri: Vec<i32>,
    /// Depth evaluations made (covered samples tested).
    pub depth_evals: u64,
}

impl SampleBuf {
    /// Sample index of `(a, b)`.
    #[inline]
    pub fn idx(&self, a: u32, b: u32) -> usize {
        b as usize * self.lat.nx as usize + a as usize
    }
}

impl Plane {
    /// `V(0, b)` in Q.32 on lattice row `b`.
    fn lattice_value(&self, l: &Lattice, b: i64) -> i128 {
        let den = l.den as i128;
        let d = self.area2 * den;
        let yn = 256 * (b as i128 * l.sy as i128 + l.oy as i128) - self.y0 * den;
        let xn = 256 * l.ox as i128 - self.x0 * den;
        let num = self.v0 * d + self.nx * xn + self.ny * yn;
        round_div(num << 32, d)
    }

    /// The step per sample `a` in Q.32 (the same on every lattice row).
    fn lattice_step(&self, l: &Lattice) -> i128 {
        let step = self.nx * 256 * l.sx as i128;
        round_div(step << 32, self.area2 * l.den as i128)
    }
}

/// A triangle prepared for sampling.
#[derive(Clone, Debug)]
struct SampTri {
    idx: i32,
    /// Edge functions in Q.8, positive inside.
    edges: [EdgeFn; 3],
    z: Plane,
    c: [Plane; 3],
    decal: bool,
    /// Bounding box in Q.8.
    bb: [i64; 4],
}

fn prepare(k: usize, t: &SnappedTri) -> Option<SampTri> {
    let order = winding(t.v)?;
    let (v, c, z) = (rewind(order, t.v), rewind(order, t.c), rewind(order, t.z));
    let zp = match &t.host {
        Some(h) => Plane::new(h.v, h.z.map(|x| x as i64))?,
        None => Plane::new(v, z.map(|x| x as i64))?,
    };
    let cp = |k: usize| Plane::new(v, [c[0][k] as i64, c[1][k] as i64, c[2][k] as i64]);
    Some(SampTri {
        idx: k as i32,
        edges: EdgeFn::of_triangle(v),
        z: zp,
        c: [cp(0)?, cp(1)?, cp(2)?],
        decal: t.host.is_some(),
        bb: [
            v.iter().map(|p| p[0]).min().unwrap() as i64,
            v.iter().map(|p| p[1]).min().unwrap() as i64,
            v.iter().map(|p| p[0]).max().unwrap() as i64,
            v.iter().map(|p| p[1]).max().unwrap() as i64,
        ],
    })
}

/// Rasterizes `tris` (scene order, z-buffer) onto each lattice; background `bg`.
pub fn rasterize(tris: &[SnappedTri], lats: &[Lattice], bg: [u8; 3]) -> Vec<SampleBuf> {
    let st = prepare_all(tris);
    lats.iter()
        .map(|l| LatticeRaster::new(&st, l, bg).rasterize())
        .collect()
}

/// The triangles of `tris` prepared for sampling (degenerate ones dropped), in scene
/// order.
pub struct Prepared(Vec<SampTri>);

/// Prepares `tris` for [`LatticeRaster`].
pub fn prepare_all(tris: &[SnappedTri]) -> Prepared {
    Prepared(
        tris.iter()
            .enumerate()
            .filter_map(|(k, t)| prepare(k, t))
            .collect(),
    )
}

/// Lattice rows per bin band of [`LatticeRaster`].
const SAMPLE_BAND: i64 = 8;

/// The range of `a ≥ a0` (up to `a1`) where an edge with value `e0` at `a0` and step
/// `de` per sample is inside (the fill rule of [`EdgeFn::inside`]: `e > 0`, or `e ≥ 0`
/// on a top-left edge), as an inclusive `(lo, hi)`, possibly empty (`lo > hi`).
#[inline]
fn inside_range(ed: &EdgeFn, e0: i64, de: i64, a0: i64, a1: i64) -> (i64, i64) {
    // Integers: `inside(e)` is `e ≥ t`.
    let t = if ed.top_left { 0 } else { 1 };
    match de.cmp(&0) {
        std::cmp::Ordering::Greater => (a0 + ceil_div(t - e0, de).max(0), a1),
        std::cmp::Ordering::Less => (a0, a1.min(a0 + (e0 - t).div_euclid(-de))),
        std::cmp::Ordering::Equal => {
            if e0 >= t {
                (a0, a1)
            } else {
                (a0 + 1, a0)
            }
        }
    }
}

/// One lattice's rasterizer: the triangles binned by the lattice rows their bounding
/// boxes reach and their plane steps per sample, set up once; any lattice row can then be
/// rasterized on its own ([`LatticeRaster::row`]), with the same result as the whole
/// lattice at once, since every sample is independent.
pub struct LatticeRaster<'a> {
    st: &'a [SampTri],
    lat: Lattice,
    bgq: [u32; 3],
    bands: Bands,
    /// Per triangle, the steps per sample of its depth and colour planes on this
    /// lattice: the same on every row, so computed once.
    steps: Vec<[i128; 4]>,
}

impl<'a> LatticeRaster<'a> {
    /// Sets up lattice `l` for the prepared triangles `st`, background `bg`.
    pub fn new(st: &'a Prepared, l: &Lattice, bg: [u8; 3]) -> LatticeRaster<'a> {
        let st = &st.0[..];
        // Bin the triangles by the lattice rows their bounding boxes reach (scene order
        // kept within a band): each row visits only the triangles that can cover it.
        let bands = Bands::new(
            SAMPLE_BAND,
            l.ny,
            st.iter().map(|t| {
                // Rows b with bb[1]·den ≤ 256·(b·sy + oy) ≤ bb[3]·den.
                let lo = ceil_div(t.bb[1] * l.den - 256 * l.oy, 256 * l.sy);
                let hi = (t.bb[3] * l.den - 256 * l.oy).div_euclid(256 * l.sy);
                (lo, hi)
            }),
        );
        let steps = st
            .par_iter()
            .map(|t| {
                [
                    t.z.lattice_step(l),
                    t.c[0].lattice_step(l),
                    t.c[1].lattice_step(l),
                    t.c[2].lattice_step(l),
                ]
            })
            .collect();
        LatticeRaster {
            st,
            lat: *l,
            bgq: bg.map(|v| ((v as u32) << 12) + 2048),
            bands,
            steps,
        }
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lat
    }

    /// The whole lattice, rows in parallel.
    pub fn rasterize(&self) -> SampleBuf {
        let l = &self.lat;
        let n = l.nx as usize * l.ny as usize;
        let mut z = vec![0; n];
        let mut rgb = vec![[0; 3]; n];
        let mut tri = vec![0; n];
        let nx = l.nx as usize;
        let evals: u64 = z
            .par_chunks_mut(nx)
            .zip(rgb.par_chunks_mut(nx))
            .zip(tri.par_chunks_mut(nx))
            .enumerate()
            .map(|(b, ((zr, cr), tr))| self.row(b as u32, zr, cr, tr))
            .sum();
        SampleBuf {
            lat: *l,
            z,
            rgb,
            tri,
            depth_evals: evals,
        }
    }

    /// Rasterizes lattice row `b` into `zr`, `cr`, `tr` (each `nx` long), which it first
    /// sets to the background; returns the depth evaluations made.
    pub fn row(&self, b: u32, zr: &mut [i64], cr: &mut [[u32; 3]], tr: &mut [i32]) -> u64 {
        DEPTH_BOUNDS.with(|hz| self.row_with(b, zr, cr, tr, &mut hz.borrow_mut()))
    }

    /// [`LatticeRaster::row`] with the row's depth bounds `hz` (scratch).
    fn row_with(
        &self,
        b: u32,
        zr: &mut [i64],
        cr: &mut [[u32; 3]],
        tr: &mut [i32],
        hz: &mut DepthBounds,
    ) -> u64 {
        let l = &self.lat;
        zr.fill(i64::MAX);
        cr.fill(self.bgq);
        tr.fill(-1);
        hz.reset(zr.len());
        let b = b as i64;
        // Sample y in Q.8·den.
        let yq = 256 * (b * l.sy + l.oy);
        let mut evals = 0u64;
        for &ti in self.bands.members(self.bands.of_row(b)) {
            let t = &self.st[ti as usize];
            if yq < t.bb[1] * l.den || yq > t.bb[3] * l.den {
                continue;
            }
            // a range from the bounding box: 256·(a·sx + ox) ∈ [xmin·den, xmax·den].
            let a_lo = ceil_div(t.bb[0] * l.den - 256 * l.ox, 256 * l.sx).max(0);
            let a_hi = (t.bb[2] * l.den - 256 * l.ox)
                .div_euclid(256 * l.sx)
                .min(l.nx as i64 - 1);
            if a_lo > a_hi {
                continue;
            }
            // Narrowed to the samples inside all three edges (the only ones that do
            // anything).
            let (mut lo, mut hi) = (a_lo, a_hi);
            for ed in &t.edges {
                let e0 = ed.a * 256 * (a_lo * l.sx + l.ox) + ed.b * yq + ed.c * l.den;
                let (p, q) = inside_range(ed, e0, ed.a * 256 * l.sx, a_lo, a_hi);
                lo = lo.max(p);
                hi = hi.min(q);
            }
            if lo > hi {
                continue;
            }
            evals += (hi - lo + 1) as u64;
            let sp = &self.steps[ti as usize];
            let (z0, dz) = (t.z.lattice_value(l, b), sp[0]);
            // The samples at the range's ends that cannot pass the depth test are left
            // out a block at a time (every covered sample still counts as evaluated).
            let depth = |a: i64| (z0 + a as i128 * dz) >> 20;
            (lo, hi) = hz.trim(zr, (lo, hi), (depth(lo), depth(hi)), t.decal);
            if lo > hi {
                continue;
            }
            // Each plane's values at the ends of `lo..=hi`: linear in `a`, so every value
            // between lies between them, and where all fit 62 bits the same sums run in
            // `i64` (the colours only once a sample is written).
            let z = (z0 + lo as i128 * dz, dz);
            let colours = || {
                [0, 1, 2].map(|ch| {
                    let (c0, dc) = (t.c[ch].lattice_value(l, b), sp[1 + ch]);
                    (c0 + lo as i128 * dc, dc)
                })
            };
            let (lo, hi) = (lo as usize, hi as usize);
            let out = (&mut zr[lo..=hi], &mut cr[lo..=hi], &mut tr[lo..=hi]);
            if fill_range(z, colours, out, (t.idx, t.decal)) {
                hz.touch(lo, hi);
            }
        }
        evals
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::depth;
    use crate::rng::XorShift64Star as Rng;

    /// Every lattice row rasterized (ranges from the edges, the depth bounds that leave
    /// out hidden blocks, narrowed sums) holds what a z-buffer written sample by sample
    /// holds: for each sample, every prepared triangle in scene order, inside its three
    /// edges, depth `(V(0, b) + a·step) >> 20` tested against the stored one, colours
    /// clamped. Scenes of large quads drawn front to back and back to front (so that
    /// whole blocks are hidden), equal depths, decals on their hosts and small triangles,
    /// on the lattices of SSAA 2×2 and 3×3 and of the corner pattern.
    #[test]
    fn rows_equal_a_sample_by_sample_z_buffer() {
        use crate::setup::HostPlane;
        let mut rng = Rng(0x51_dec0);
        let (w, h) = (47u32, 23u32);
        let q = |x: f64| (x * 256.0) as i32;
        let mut hidden_rows = 0;
        for round in 0..12 {
            let mut tris = Vec::new();
            let colour =
                |rng: &mut Rng| [0; 3].map(|_| ((rng.next_u64() % 256) << 12) as u32 + 2048);
            // Walls across the screen at depths rising or falling with the scene order.
            for k in 0..6u32 {
                let z = if round % 2 == 0 {
                    1000 + 5000 * k
                } else {
                    40000 - 5000 * k
                };
                let (x0, x1) = (-2.0 + k as f64, w as f64 + 2.0 - k as f64);
                let (y0, y1) = (-1.0, h as f64 + 1.0);
                let c = [colour(&mut rng), colour(&mut rng), colour(&mut rng)];
                let tilt = (rng.next_u64() % 400) as u32;
                for v in [
                    [[x0, y0], [x1, y0], [x1, y1]],
                    [[x0, y0], [x1, y1], [x0, y1]],
                ] {
                    tris.push(SnappedTri {
                        v: v.map(|p| [q(p[0]), q(p[1])]),
                        z: [z, z + tilt, z],
                        c,
                        ..Default::default()
                    });
                }
            }
            // A decal on the nearest wall's plane, and a copy of a wall (equal depths).
            let host = tris[if round % 2 == 0 { 0 } else { 10 }];
            tris.push(SnappedTri {
                v: [[q(5.0), q(4.0)], [q(30.0), q(6.5)], [q(12.0), q(20.0)]],
                host: Some(HostPlane {
                    v: host.v,
                    z: host.z,
                }),
                c: [colour(&mut rng); 3],
                z: host.z,
                ..Default::default()
            });
            tris.push(tris[4]);
            // Small triangles in between.
            for _ in 0..30 {
                let (cx, cy) = (
                    (rng.next_u64() % w as u64) as f64,
                    (rng.next_u64() % h as u64) as f64,
                );
                let mut p = || {
                    [
                        cx + (rng.next_u64() % 1200) as f64 / 100.0 - 6.0,
                        cy + (rng.next_u64() % 1200) as f64 / 100.0 - 6.0,
                    ]
                };
                let v = [p(), p(), p()];
                let z = [0; 3].map(|_| 500 + (rng.next_u64() % 40000) as u32);
                tris.push(SnappedTri {
                    v: v.map(|p| [q(p[0]), q(p[1])]),
                    z,
                    c: [colour(&mut rng), colour(&mut rng), colour(&mut rng)],
                    ..Default::default()
                });
            }
            let ssaa = |k: u32| Lattice {
                nx: w * k,
                ny: h * k,
                sx: 2,
                sy: 2,
                ox: 1,
                oy: 1,
                den: 2 * k as i64,
            };
            let corner = Lattice {
                nx: w / 2 + 1,
                ny: h / 2 + 1,
                sx: 12,
                sy: 12,
                ox: 5,
                oy: 5,
                den: 6,
            };
            let bg = [1, 2, 3];
            let st = prepare_all(&tris);
            for lat in [ssaa(2), ssaa(3), corner] {
                let got = rasterize(&tris, &[lat], bg).pop().unwrap();
                let bgq = bg.map(|v| ((v as u32) << 12) + 2048);
                for b in 0..lat.ny as i64 {
                    let yq = 256 * (b * lat.sy + lat.oy);
                    for a in 0..lat.nx as i64 {
                        let xq = 256 * (a * lat.sx + lat.ox);
                        let (mut z, mut c, mut owner) = (i64::MAX, bgq, -1);
                        for t in &st.0 {
                            let e = |ed: &EdgeFn| ed.a * xq + ed.b * yq + ed.c * lat.den;
                            if !t.edges.iter().all(|ed| ed.inside(e(ed))) {
                                continue;
                            }
                            let at = |p: &Plane| {
                                p.lattice_value(&lat, b) + a as i128 * p.lattice_step(&lat)
                            };
                            let zv = (at(&t.z) >> 20) as i64;
                            if depth::passes(zv, z, t.decal) {
                                z = zv;
                                owner = t.idx;
                                c =
                                    t.c.each_ref()
                                        .map(|p| (at(p) >> 32).clamp(0, (255 << 12) + 4095) as u32);
                            }
                        }
                        let s = got.idx(a as u32, b as u32);
                        assert_eq!(
                            (got.z[s], got.rgb[s], got.tri[s]),
                            (z, c, owner),
                            "round {round}, lattice {lat:?}, sample ({a}, {b})"
                        );
                    }
                }
            }
            // Rows where the depth bounds left a wall out.
            let lr = LatticeRaster::new(&st, &ssaa(2), bg);
            let n = 2 * w as usize;
            let (mut z, mut c, mut t) = (vec![0; n], vec![[0; 3]; n], vec![0; n]);
            for b in 0..2 * h {
                let mut hz = DepthBounds::default();
                lr.row_with(b, &mut z, &mut c, &mut t, &mut hz);
                hidden_rows += hz.max.iter().any(|&m| m < i64::MAX) as usize;
            }
        }
        assert!(hidden_rows > 100, "{hidden_rows} rows with depth bounds");
    }
}
