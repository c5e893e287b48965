//! Exact references for the axisymmetric filters of multi-scanning (seed 002, §2.2.2).
//!
//! A method that resolves with a Gaussian or a cone filter approximates
//! `C(c) = ∫∫ K(|p − c|) I(p) dp / ∫∫ K`, with `K(r) = f(r)` for `r < 1` and 0 beyond
//! (filter radius one pixel, volume normalised to 1; `c` the pixel centre). This module
//! integrates exactly that over the same visible-area decomposition as the box reference
//! (the parent module's visible pieces of every pixel square; the squares of the 3×3
//! neighbourhood hold the disc of radius 1, including the ring of squares just outside
//! the screen, where the scene continues as it is).
//!
//! **Per piece.** Intensity is affine, `I(p) = I(c) + g·(p − c)`, so a piece `P` adds
//! `I(c)·M0 + g·M1` with the moments `M0 = ∫∫_P K(r) dA` and `M1 = ∫∫_P K(r)(p − c) dA`.
//! In polar coordinates about `c` and by Green's theorem these are boundary integrals over
//! the piece's edges: `M0 = ∮ A0(ρ) dθ`, `M1 = ∮ A1(ρ) u(θ) dθ`, with `ρ = min(r, 1)`,
//! `u = (cos θ, sin θ)`, `A0(r) = ∫_0^r K(s) s ds` and `A1(r) = ∫_0^r K(s) s² ds` (closed
//! forms, or for the Gaussian's `A1` its everywhere-convergent power series). An edge is
//! split where it crosses the unit circle; outside it, `A0(1)·Δθ` and `A1(1)·∫u dθ` are
//! exact; inside it, the integrand in the edge parameter `t` is
//! `k·(A0/r², A1/r³ · (p − c))` with the constant `k = (p − c) × (q − p)`, which is
//! smooth (entire for the Gaussian). It is integrated by adaptive Gauss–Kronrod (7/15
//! points), bisecting until the Kronrod–Gauss difference is below [`QUAD_TOL`] per
//! interval. The image reports the sum of those estimates over each pixel (scaled to the
//! 0..255 scale) as [`FilteredRef::max_quad_err`]: a bound on the quadrature error far
//! below every error the trade-off measures.
//!
//! A pixel square that a single piece covers entirely uses the moments of a full square,
//! computed once per offset by the same integration.

use rayon::prelude::*;

use super::{
    assemble, bin_rows, pixel, signed_area, square_pieces, to_ref, Poly, RefImage, RefPixel,
    RefTri, SquarePieces,
};
use crate::setup::SnappedTri;

/// Absolute tolerance of one adaptive Gauss–Kronrod interval (moments of a kernel whose
/// integral is of order 1).
pub const QUAD_TOL: f64 = 1e-13;

/// Deepest bisection of an interval.
const MAX_DEPTH: u32 = 40;

/// The reconstruction filter a reference integrates, centred on each pixel centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefFilter {
    /// The pixel square, uniform ([`super::reference_image`]).
    Box,
    /// `exp(−r²/(2σ²))` for `r < 1` pixel, 0 beyond (the seed-002 Gaussian of radius 1).
    /// `sigma` must lie in `0.25..=4` (the power series of `A1` stays well conditioned).
    Gauss {
        /// Standard deviation, pixels.
        sigma: f64,
    },
    /// `1 − r` for `r < 1` pixel (the seed-002 cone).
    Cone,
}

impl RefFilter {
    /// `A0(r)/r²` for `0 ≤ r ≤ 1`.
    fn a0(&self, r: f64) -> f64 {
        match *self {
            RefFilter::Box => unreachable!("the box filter is not radial"),
            RefFilter::Cone => 0.5 - r / 3.0,
            RefFilter::Gauss { sigma } => {
                let x = r * r / (2.0 * sigma * sigma);
                if x == 0.0 {
                    0.5
                } else {
                    -(-x).exp_m1() / (2.0 * x)
                }
            }
        }
    }

    /// `A1(r)/r³` for `0 ≤ r ≤ 1`.
    fn a1(&self, r: f64) -> f64 {
        match *self {
            RefFilter::Box => unreachable!("the box filter is not radial"),
            RefFilter::Cone => 1.0 / 3.0 - r / 4.0,
            RefFilter::Gauss { sigma } => {
                // Σ (−x)^k / (k! (2k + 3)), x = r²/(2σ²) ≤ 8.
                let x = r * r / (2.0 * sigma * sigma);
                let (mut term, mut sum) = (1.0, 0.0);
                for k in 0..200 {
                    let add = term / (2 * k + 3) as f64;
                    sum += add;
                    if add.abs() < 1e-18 * sum.abs() {
                        break;
                    }
                    term *= -x / (k + 1) as f64;
                }
                sum
            }
        }
    }

    /// The kernel's integral over the plane: `2π·A0(1)` for the radial filters, 1 for
    /// the box.
    pub fn volume(&self) -> f64 {
        match self {
            RefFilter::Box => 1.0,
            _ => 2.0 * std::f64::consts::PI * self.a0(1.0),
        }
    }
}

/// A reference image under a filter, with the bound on its quadrature error.
#[derive(Clone, Debug)]
pub struct FilteredRef {
    /// The image: `rgb` under the filter; coverage, dominant surfaces, visible areas and
    /// the mixed bits are the box reference's (they describe the pixel square).
    pub image: RefImage,
    /// Largest per-pixel sum of the quadrature error estimates, 0..255 scale (0 for the
    /// box filter, which needs no quadrature).
    pub max_quad_err: f64,
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Gauss–Kronrod 15-point nodes (non-negative half) and weights, and the embedded
/// 7-point Gauss weights (of nodes 1, 3, 5, 7).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One Gauss–Kronrod step of a vector integrand over `[a, b]`: (Kronrod, |K − G|).
fn gk15(g: &dyn Fn(f64) -> [f64; 3], a: f64, b: f64) -> ([f64; 3], f64) {
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    let (mut k, mut gs) = ([0.0; 3], [0.0; 3]);
    for j in 0..8 {
        let xs: &[f64] = if j == 7 {
            &[m]
        } else {
            &[m - h * XGK[j], m + h * XGK[j]]
        };
        for &x in xs {
            let v = g(x);
            for c in 0..3 {
                k[c] += WGK[j] * v[c];
                if j % 2 == 1 {
                    gs[c] += WG[j / 2] * v[c];
                }
            }
        }
    }
    let k = k.map(|v| v * h);
    let err = (0..3).map(|c| (k[c] - gs[c] * h).abs()).fold(0.0, f64::max);
    (k, err)
}

/// Adaptive Gauss–Kronrod: bisects until each interval's estimate is below
/// [`QUAD_TOL`]. Adds the integral to `out` and the estimates to `err`.
fn adapt(
    g: &dyn Fn(f64) -> [f64; 3],
    a: f64,
    b: f64,
    depth: u32,
    out: &mut [f64; 3],
    err: &mut f64,
) {
    let (k, e) = gk15(g, a, b);
    if e <= QUAD_TOL || depth >= MAX_DEPTH {
        for c in 0..3 {
            out[c] += k[c];
        }
        *err += e;
        return;
    }
    let m = 0.5 * (a + b);
    adapt(g, a, m, depth + 1, out, err);
    adapt(g, m, b, depth + 1, out, err);
}

/// `(∮ A0 dθ, ∮ A1 u dθ)` along the edge `p → q` (relative to the filter's centre).
fn edge_moments(f: &RefFilter, p: [f64; 2], q: [f64; 2], err: &mut f64) -> [f64; 3] {
    let d = sub(q, p);
    let a = dot(d, d);
    if a == 0.0 {
        return [0.0; 3];
    }
    // Split where |p + t·d| = 1.
    let (b, c0) = (dot(p, d), dot(p, p) - 1.0);
    let mut ts = vec![0.0];
    let disc = b * b - a * c0;
    if disc > 0.0 {
        let s = disc.sqrt();
        for t in [(-b - s) / a, (-b + s) / a] {
            if t > 0.0 && t < 1.0 {
                ts.push(t);
            }
        }
    }
    ts.push(1.0);
    let at = |t: f64| [p[0] + t * d[0], p[1] + t * d[1]];
    let k = cross(p, d);
    let (a0_1, a1_1) = (f.a0(1.0), f.a1(1.0));
    let mut m = [0.0; 3];
    for w in ts.windows(2) {
        let (t1, t2) = (w[0], w[1]);
        if t2 <= t1 {
            continue;
        }
        let mid = at(0.5 * (t1 + t2));
        if dot(mid, mid) >= 1.0 {
            // Outside the support: A0(1)·Δθ and A1(1)·(Δ sin θ, −Δ cos θ).
            let (u, v) = (at(t1), at(t2));
            let dth = cross(u, v).atan2(dot(u, v));
            let (ru, rv) = (dot(u, u).sqrt(), dot(v, v).sqrt());
            m[0] += a0_1 * dth;
            m[1] += a1_1 * (v[1] / rv - u[1] / ru);
            m[2] -= a1_1 * (v[0] / rv - u[0] / ru);
        } else {
            let g = |t: f64| {
                let x = at(t);
                let r = dot(x, x).sqrt().min(1.0);
                let a1 = f.a1(r);
                [k * f.a0(r), k * a1 * x[0], k * a1 * x[1]]
            };
            adapt(&g, t1, t2, 0, &mut m, err);
        }
    }
    m
}

/// The moments `(M0, M1x, M1y)` of `K(|p − c|)` over the convex polygon `poly`.
fn piece_moments(f: &RefFilter, poly: &[[f64; 2]], c: [f64; 2], err: &mut f64) -> [f64; 3] {
    let s = if signed_area(poly) >= 0.0 { 1.0 } else { -1.0 };
    let n = poly.len();
    let mut m = [0.0; 3];
    for k in 0..n {
        let e = edge_moments(f, sub(poly[k], c), sub(poly[(k + 1) % n], c), err);
        for (a, b) in m.iter_mut().zip(e) {
            *a += s * b;
        }
    }
    m
}

/// Whether one piece covers the whole square (then the full-square moments apply).
fn full_square(sq: &SquarePieces) -> Option<usize> {
    match sq.as_slice() {
        [(p, pieces)] if pieces.len() == 1 => {
            let (a, _) = super::area_centroid(&pieces[0]);
            (a >= 1.0 - 1e-12).then_some(*p)
        }
        _ => None,
    }
}

/// One filtered pixel: the pieces of the 3×3 squares around it (`sqs[dy][dx]`, the pixel
/// itself at `[1][1]`), weighted by the filter centred at `c`.
fn filtered_pixel(
    f: &RefFilter,
    rt: &[Option<RefTri>],
    sqs: [[&SquarePieces; 3]; 3],
    c: [f64; 2],
    full: &[[[f64; 3]; 3]; 3],
    bgf: [f64; 3],
) -> ([f64; 3], f64) {
    let (mut acc, mut w0, mut err) = ([0.0; 3], 0.0, 0.0);
    for (dy, row) in sqs.iter().enumerate() {
        for (dx, sq) in row.iter().enumerate() {
            let mut add = |t: &RefTri, m: [f64; 3]| {
                w0 += m[0];
                for (ch, a) in acc.iter_mut().enumerate() {
                    let col = &t.col[ch];
                    *a += col.at(c) * m[0] + col.a * m[1] + col.b * m[2];
                }
            };
            if let Some(p) = full_square(sq) {
                if let Some(t) = rt[p].as_ref() {
                    add(t, full[dy][dx]);
                }
                continue;
            }
            for (p, pieces) in sq.iter() {
                let Some(t) = rt[*p].as_ref() else { continue };
                for piece in pieces {
                    add(t, piece_moments(f, piece, c, &mut err));
                }
            }
        }
    }
    let v = f.volume();
    let rgb = [0, 1, 2].map(|ch| (acc[ch] + (v - w0) * bgf[ch]) / v);
    // Each estimate bounds a moment; colours are at most ~255 and gradients small, so
    // scale by the largest colour magnitude over the volume.
    (rgb, err * 256.0 / v)
}

/// Renders the exact reference of `tris` under `filter` (see the module documentation).
/// For [`RefFilter::Box`] this is [`super::reference_image`].
pub fn filtered_reference_image(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    filter: RefFilter,
) -> FilteredRef {
    if filter == RefFilter::Box {
        return FilteredRef {
            image: super::reference_image(tris, width, height, bg),
            max_quad_err: 0.0,
        };
    }
    if let RefFilter::Gauss { sigma } = filter {
        assert!(
            (0.25..=4.0).contains(&sigma),
            "Gaussian sigma {sigma} outside 0.25..=4"
        );
    }
    let rt: Vec<Option<RefTri>> = tris.iter().map(to_ref).collect();
    let (w, h) = (width as i64, height as i64);
    // Squares -1..=w × -1..=h: the screen and the ring the filters reach.
    let rows = bin_rows(&rt, -1, h + 1);
    let grid: Vec<Vec<SquarePieces>> = (-1..=h)
        .into_par_iter()
        .map(|j| {
            (-1..=w)
                .map(|i| square_pieces(&rt, &rows[(j + 1) as usize], i as f64, j as f64))
                .collect()
        })
        .collect();
    let bgf = bg.map(|v| v as f64);
    // Box fields from the on-screen squares, exactly as the box reference computes them.
    let per_row: Vec<(Vec<RefPixel>, Vec<f64>)> = (0..h)
        .into_par_iter()
        .map(|j| {
            let mut vis = vec![0.0; tris.len()];
            let px = (0..w)
                .map(|i| {
                    pixel(
                        &rt,
                        &grid[(j + 1) as usize][(i + 1) as usize],
                        bgf,
                        &mut vis,
                    )
                })
                .collect();
            (px, vis)
        })
        .collect();
    let mut image = assemble(width, height, tris.len(), per_row);
    // Moments of a full square at each offset from the centre.
    let mut full = [[[0.0; 3]; 3]; 3];
    let mut unused = 0.0;
    for (dy, row) in full.iter_mut().enumerate() {
        for (dx, m) in row.iter_mut().enumerate() {
            let (x0, y0) = (dx as f64 - 1.5, dy as f64 - 1.5);
            let sq: Poly = vec![
                [x0, y0],
                [x0 + 1.0, y0],
                [x0 + 1.0, y0 + 1.0],
                [x0, y0 + 1.0],
            ];
            *m = piece_moments(&filter, &sq, [0.0, 0.0], &mut unused);
        }
    }
    let out: Vec<([f64; 3], f64)> = (0..h)
        .into_par_iter()
        .flat_map_iter(|j| {
            let (grid, rt, full) = (&grid, &rt, &full);
            (0..w).map(move |i| {
                let (gj, gi) = ((j + 1) as usize, (i + 1) as usize);
                let sqs = [0, 1, 2].map(|dy| [0, 1, 2].map(|dx| &grid[gj + dy - 1][gi + dx - 1]));
                let c = [i as f64 + 0.5, j as f64 + 0.5];
                filtered_pixel(&filter, rt, sqs, c, full, bgf)
            })
        })
        .collect();
    image.rgb = out.iter().map(|o| o.0).collect();
    let max_quad_err = out.iter().map(|o| o.1).fold(0.0, f64::max);
    FilteredRef {
        image,
        max_quad_err,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kronrod_rule_integrates_polynomials_to_degree_22() {
        for deg in 0..=22 {
            let g = |x: f64| [x.powi(deg), 0.0, 0.0];
            let (k, _) = gk15(&g, 0.0, 1.0);
            let exact = 1.0 / (deg + 1) as f64;
            assert!((k[0] - exact).abs() < 1e-14, "degree {deg}: {}", k[0]);
        }
        // The embedded Gauss rule is exact to degree 13: zero difference there.
        let (_, e) = gk15(&|x: f64| [x.powi(13), 0.0, 0.0], 0.0, 1.0);
        assert!(e < 1e-14, "{e}");
    }

    #[test]
    fn volume_of_the_cone_is_pi_over_3() {
        assert!((RefFilter::Cone.volume() - std::f64::consts::PI / 3.0).abs() < 1e-14);
        // Truncated Gaussian: 2πσ²(1 − exp(−1/(2σ²))).
        let s: f64 = 0.4;
        let v = 2.0 * std::f64::consts::PI * s * s * (1.0 - (-1.0 / (2.0 * s * s)).exp());
        assert!((RefFilter::Gauss { sigma: s }.volume() - v).abs() < 1e-14);
    }

    #[test]
    fn whole_disc_moments_are_the_volume_and_zero() {
        // A square far larger than the support: M0 = volume, M1 = 0.
        let big: Poly = vec![[-3.0, -2.0], [4.0, -2.0], [4.0, 5.0], [-3.0, 5.0]];
        for f in [RefFilter::Cone, RefFilter::Gauss { sigma: 0.4 }] {
            let mut e = 0.0;
            let m = piece_moments(&f, &big, [0.25, 0.5], &mut e);
            assert!((m[0] - f.volume()).abs() < 1e-12, "{f:?} {m:?}");
            assert!(m[1].abs() < 1e-12 && m[2].abs() < 1e-12, "{f:?} {m:?}");
        }
    }
}
