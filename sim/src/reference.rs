//! Exact box-filtered reference images for screen-space triangle scenes (f64).
//!
//! This module judges the anti-aliasing methods of [`crate::aa`] and deliberately shares
//! no code with them nor with [`crate::setup`]: it reads the snapped triangles' raw
//! fields (Q.8 vertices, 24-bit depths, Q8.12 colours, decal host planes) and does its own
//! floating-point geometry.
//!
//! For every pixel square `[i, i+1) × [j, j+1)`:
//! 1. each triangle is clipped to the square (Sutherland–Hodgman, convex);
//! 2. the visible part of triangle `P` is its clipped polygon minus, for every other
//!    clipped triangle `Q`, the part of `Q` where `Q` is in front of `P`. Depth is planar,
//!    so `z_Q − z_P` is affine and "`Q` in front" is a half-plane: the occluder is the
//!    convex polygon `Q ∩ {z_Q < z_P}`. Triangles that interpenetrate are thereby split
//!    exactly along their line of intersection. Coplanar pairs follow the renderer's
//!    depth-test order: a decal (pattern, `host: Some`) beats a non-decal on its plane, a
//!    later decal beats an earlier one, an earlier non-decal beats a later one;
//! 3. a vertex intensity `v` (Q8.12 with the +2048 rounding offset of span setup) stands
//!    for `v/4096 − ½` on the 0..255 scale; the pixel value is `Σ area(piece)·I(centroid(piece)) + (1 − Σ area)·bg`: Gouraud
//!    intensity is affine, so the value at the centroid times the area is its exact
//!    integral over the piece (the box filter of the exact image).
//!
//! The only approximations are f64 rounding and the coplanarity tolerance
//! ([`COPLANAR_EPS`] depth units). See `docs/reference.md`.

use rayon::prelude::*;

use crate::setup::SnappedTri;

mod filtered;
pub use filtered::{filtered_reference_image, FilteredRef, RefFilter};

/// Two planes whose depth difference is below this (in 24-bit depth units) at every
/// vertex of the region they share are treated as coplanar.
pub const COPLANAR_EPS: f64 = 1e-6;

/// A convex polygon, counter-clockwise or clockwise, in pixel units.
type Poly = Vec<[f64; 2]>;

/// An affine function `a·x + b·y + c` of pixel coordinates.
#[derive(Clone, Copy, Debug)]
struct Affine {
    a: f64,
    b: f64,
    c: f64,
}

impl Affine {
    /// The affine function through three (x, y, value) points, or `None` if collinear.
    fn through(p: [[f64; 2]; 3], v: [f64; 3]) -> Option<Affine> {
        let (dx1, dy1) = (p[1][0] - p[0][0], p[1][1] - p[0][1]);
        let (dx2, dy2) = (p[2][0] - p[0][0], p[2][1] - p[0][1]);
        let det = dx1 * dy2 - dx2 * dy1;
        if det == 0.0 {
            return None;
        }
        let (dv1, dv2) = (v[1] - v[0], v[2] - v[0]);
        let a = (dv1 * dy2 - dv2 * dy1) / det;
        let b = (dx1 * dv2 - dx2 * dv1) / det;
        Some(Affine {
            a,
            b,
            c: v[0] - a * p[0][0] - b * p[0][1],
        })
    }
    fn at(&self, p: [f64; 2]) -> f64 {
        self.a * p[0] + self.b * p[1] + self.c
    }
}

/// One triangle in float form.
#[derive(Clone, Debug)]
struct RefTri {
    p: [[f64; 2]; 3],
    z: Affine,
    col: [Affine; 3],
    decal: bool,
    bbox: [f64; 4],
}

fn to_ref(t: &SnappedTri) -> Option<RefTri> {
    let px = |v: [i32; 2]| [v[0] as f64 / 256.0, v[1] as f64 / 256.0];
    let p = t.v.map(px);
    let z = match &t.host {
        Some(h) => Affine::through(h.v.map(px), h.z.map(|z| z as f64))?,
        None => Affine::through(p, t.z.map(|z| z as f64))?,
    };
    // Q8.12 with the +2048 rounding offset folded in (docs/formats.md): v/4096 − ½.
    let col = [0, 1, 2].map(|k| Affine::through(p, t.c.map(|c| c[k] as f64 / 4096.0 - 0.5)));
    let col = [col[0]?, col[1]?, col[2]?];
    let xs = p.map(|q| q[0]);
    let ys = p.map(|q| q[1]);
    let bbox = [
        xs.iter().cloned().fold(f64::INFINITY, f64::min),
        ys.iter().cloned().fold(f64::INFINITY, f64::min),
        xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
    ];
    Some(RefTri {
        p,
        z,
        col,
        decal: t.host.is_some(),
        bbox,
    })
}

/// Signed area (positive counter-clockwise in a y-up frame; sign unused except for
/// orientation of triangles).
fn signed_area(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    let mut s = 0.0;
    for k in 0..n {
        let (a, b) = (p[k], p[(k + 1) % n]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    0.5 * s
}

/// Area and area-weighted centroid.
fn area_centroid(p: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let n = p.len();
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    // Fan from p[0]: exact for convex polygons, well conditioned for small ones.
    for k in 1..n.saturating_sub(1) {
        let (o, b, c) = (p[0], p[k], p[k + 1]);
        let t = (b[0] - o[0]) * (c[1] - o[1]) - (c[0] - o[0]) * (b[1] - o[1]);
        a2 += t;
        cx += t * (o[0] + b[0] + c[0]) / 3.0;
        cy += t * (o[1] + b[1] + c[1]) / 3.0;
    }
    if a2 == 0.0 {
        return (0.0, p.first().copied().unwrap_or([0.0, 0.0]));
    }
    ((0.5 * a2).abs(), [cx / a2, cy / a2])
}

/// Keeps the part of `poly` where `f ≥ 0` (`keep_pos`) or `f ≤ 0` (otherwise).
fn clip(poly: &[[f64; 2]], f: &dyn Fn([f64; 2]) -> f64, keep_pos: bool) -> Poly {
    let s = if keep_pos { 1.0 } else { -1.0 };
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        let (fa, fb) = (s * f(a), s * f(b));
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa > 0.0 && fb < 0.0) || (fa < 0.0 && fb > 0.0) {
            let t = fa / (fa - fb);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    if out.len() < 3 {
        out.clear();
    }
    out
}

/// Half-planes (as affine functions, inside where ≥ 0) bounding a convex polygon.
fn edge_functions(p: &[[f64; 2]]) -> Vec<Affine> {
    let orient = if signed_area(p) >= 0.0 { 1.0 } else { -1.0 };
    let n = p.len();
    (0..n)
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % n]);
            // Left of a→b for positive orientation.
            let ea = -(b[1] - a[1]) * orient;
            let eb = (b[0] - a[0]) * orient;
            Affine {
                a: ea,
                b: eb,
                c: -(ea * a[0] + eb * a[1]),
            }
        })
        .collect()
}

/// `pieces \ occluder` for convex pieces and a convex occluder.
fn subtract(pieces: Vec<Poly>, occ: &[[f64; 2]]) -> Vec<Poly> {
    // A repeated vertex gives a zero-length edge whose "half-plane" is the whole plane:
    // both sides of it would keep the whole piece and count it twice. Skip such edges.
    let edges: Vec<Affine> = edge_functions(occ)
        .into_iter()
        .filter(|e| e.a != 0.0 || e.b != 0.0)
        .collect();
    let mut out = Vec::new();
    for piece in pieces {
        let mut rest = piece;
        for e in &edges {
            let f = |q: [f64; 2]| e.at(q);
            let outside = clip(&rest, &f, false);
            if !outside.is_empty() && area_centroid(&outside).0 > 0.0 {
                out.push(outside);
            }
            rest = clip(&rest, &f, true);
            if rest.is_empty() {
                break;
            }
        }
    }
    out
}

/// An exact reference image.
#[derive(Clone, Debug)]
pub struct RefImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGB in 0..=255 (f64, unrounded).
    pub rgb: Vec<[f64; 3]>,
    /// Row-major covered (non-background) area per pixel, 0..=1.
    pub covered: Vec<f64>,
    /// Row-major dominant visible surface: the input index of the triangle with the
    /// largest visible area in the pixel, or −1 when the background's area is largest.
    pub dominant: Vec<i32>,
    /// Row-major visible area of the dominant surface (background included), 0..=1.
    pub dominant_area: Vec<f64>,
    /// Total visible area of each input triangle over the whole image, in pixels².
    pub visible_area: Vec<f64>,
    /// Row-major: more than one triangle has a visible piece of positive area here.
    pub mixed: Vec<bool>,
}

impl RefImage {
    /// The reference rounded to RGB8 (half away from zero), row-major.
    pub fn rgb8(&self) -> Vec<u8> {
        self.rgb
            .iter()
            .flat_map(|c| c.map(|v| v.round().clamp(0.0, 255.0) as u8))
            .collect()
    }

    /// Root-mean-square error of an RGB8 image against this reference, over all channels.
    pub fn rmse(&self, rgb8: &[u8]) -> f64 {
        self.rmse_masked(rgb8, |_| true)
    }

    /// RMSE over the pixels for which `keep(pixel_index)` holds (0 if none).
    pub fn rmse_masked(&self, rgb8: &[u8], keep: impl Fn(usize) -> bool) -> f64 {
        assert_eq!(rgb8.len(), self.rgb.len() * 3, "image size mismatch");
        let (mut s, mut n) = (0.0, 0usize);
        for (k, c) in self.rgb.iter().enumerate() {
            if !keep(k) {
                continue;
            }
            for ch in 0..3 {
                let d = rgb8[3 * k + ch] as f64 - c[ch];
                s += d * d;
            }
            n += 3;
        }
        if n == 0 {
            0.0
        } else {
            (s / n as f64).sqrt()
        }
    }

    /// Pixels that are "edge pixels": neither fully covered nor fully background, or
    /// covered by more than one visible surface (`0 < covered < 1` or a dominant
    /// surface below full area).
    pub fn edge_mask(&self) -> Vec<bool> {
        self.covered
            .iter()
            .zip(&self.mixed)
            .map(|(&c, &p)| (c > 1e-9 && c < 1.0 - 1e-9) || p)
            .collect()
    }
}

/// Whether `q` is drawn in front of `p` where their planes coincide.
fn coplanar_wins(q: usize, qt: &RefTri, p: usize, pt: &RefTri) -> bool {
    match (qt.decal, pt.decal) {
        (true, false) => true,
        (false, true) => false,
        (true, true) => q > p,
        (false, false) => q < p,
    }
}

/// Triangles whose bounding box touches each row `j` of `rlo..rhi` (at index `j − rlo`).
fn bin_rows(rt: &[Option<RefTri>], rlo: i64, rhi: i64) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = vec![Vec::new(); (rhi - rlo).max(0) as usize];
    for (k, t) in rt.iter().enumerate() {
        let Some(t) = t else { continue };
        let lo = (t.bbox[1].floor() as i64).max(rlo);
        let hi = (t.bbox[3].ceil() as i64 - 1).min(rhi - 1);
        for j in lo..=hi {
            rows[(j - rlo) as usize].push(k);
        }
    }
    rows
}

/// Each triangle of `row` clipped to the pixel square at `(x0, y0)`, where it has area.
fn candidates(rt: &[Option<RefTri>], row: &[usize], x0: f64, y0: f64) -> Vec<(usize, Poly)> {
    let square: Poly = vec![
        [x0, y0],
        [x0 + 1.0, y0],
        [x0 + 1.0, y0 + 1.0],
        [x0, y0 + 1.0],
    ];
    let mut cands: Vec<(usize, Poly)> = Vec::new();
    for &k in row {
        let Some(t) = rt[k].as_ref() else { continue };
        if t.bbox[0] >= x0 + 1.0 || t.bbox[2] <= x0 {
            continue;
        }
        let mut poly = square.clone();
        for e in edge_functions(&t.p) {
            poly = clip(&poly, &|q| e.at(q), true);
            if poly.is_empty() {
                break;
            }
        }
        if !poly.is_empty() && area_centroid(&poly).0 > 0.0 {
            cands.push((k, poly));
        }
    }
    cands
}

/// The pieces of candidate `pi` that no other candidate hides (exact depth planes;
/// coplanar pairs by [`coplanar_wins`]).
fn visible_pieces(rt: &[Option<RefTri>], cands: &[(usize, Poly)], pi: usize) -> Vec<Poly> {
    let (p, ppoly) = &cands[pi];
    let Some(pt) = rt[*p].as_ref() else {
        return Vec::new();
    };
    let mut pieces = vec![ppoly.clone()];
    for (qi, (q, qpoly)) in cands.iter().enumerate() {
        if qi == pi || pieces.is_empty() {
            continue;
        }
        let Some(qt) = rt[*q].as_ref() else { continue };
        let d = Affine {
            a: qt.z.a - pt.z.a,
            b: qt.z.b - pt.z.b,
            c: qt.z.c - pt.z.c,
        };
        let coplanar = qpoly.iter().all(|&v| d.at(v).abs() < COPLANAR_EPS);
        let occ = if coplanar {
            if coplanar_wins(*q, qt, *p, pt) {
                qpoly.clone()
            } else {
                continue;
            }
        } else {
            clip(qpoly, &|v| d.at(v), false)
        };
        if occ.is_empty() {
            continue;
        }
        pieces = subtract(pieces, &occ);
    }
    pieces
}

/// The visible pieces of one pixel square: per candidate triangle (in candidate order),
/// its input index and the convex pieces of it that nothing hides.
type SquarePieces = Vec<(usize, Vec<Poly>)>;

/// The visible-area decomposition of the pixel square at `(x0, y0)`: the one computation
/// every filter of the reference integrates over.
fn square_pieces(rt: &[Option<RefTri>], row: &[usize], x0: f64, y0: f64) -> SquarePieces {
    let cands = candidates(rt, row, x0, y0);
    (0..cands.len())
        .map(|pi| (cands[pi].0, visible_pieces(rt, &cands, pi)))
        .collect()
}

/// One reference pixel.
struct RefPixel {
    rgb: [f64; 3],
    covered: f64,
    dominant: i32,
    dominant_area: f64,
    mixed: bool,
}

/// Integrates one pixel: visible area × colour at the piece's centroid (colours are affine),
/// plus the background over the uncovered rest. Adds each triangle's visible area to `vis`.
fn pixel(rt: &[Option<RefTri>], sq: &SquarePieces, bgf: [f64; 3], vis: &mut [f64]) -> RefPixel {
    let mut acc = [0.0; 3];
    let mut covered = 0.0;
    let mut best = (-1i32, 0.0f64);
    let mut surfaces = 0;
    for (p, pieces) in sq {
        let Some(pt) = rt[*p].as_ref() else { continue };
        let mut area = 0.0;
        for piece in pieces {
            let (a, c) = area_centroid(piece);
            area += a;
            for (ch, v) in acc.iter_mut().enumerate() {
                *v += a * pt.col[ch].at(c);
            }
        }
        covered += area;
        vis[*p] += area;
        if area > 1e-9 {
            surfaces += 1;
        }
        if area > best.1 {
            best = (*p as i32, area);
        }
    }
    let covered = covered.clamp(0.0, 1.0);
    for (v, b) in acc.iter_mut().zip(bgf) {
        *v += (1.0 - covered) * b;
    }
    if 1.0 - covered >= best.1 {
        best = (-1, 1.0 - covered);
    }
    RefPixel {
        rgb: acc,
        covered,
        dominant: best.0,
        dominant_area: best.1,
        mixed: surfaces > 1,
    }
}

/// Renders the exact box-filtered reference of `tris` on a `width × height` screen with
/// background `bg`. Degenerate triangles (zero area, or a degenerate host plane) are
/// skipped, as in the renderer.
pub fn reference_image(tris: &[SnappedTri], width: u32, height: u32, bg: [u8; 3]) -> RefImage {
    let rt: Vec<Option<RefTri>> = tris.iter().map(to_ref).collect();
    let rows = bin_rows(&rt, 0, height as i64);
    let bgf = bg.map(|v| v as f64);
    let per_row: Vec<(Vec<RefPixel>, Vec<f64>)> = (0..height)
        .into_par_iter()
        .map(|j| {
            let mut vis = vec![0.0; tris.len()];
            let px = (0..width)
                .map(|i| {
                    let sq = square_pieces(&rt, &rows[j as usize], i as f64, j as f64);
                    pixel(&rt, &sq, bgf, &mut vis)
                })
                .collect();
            (px, vis)
        })
        .collect();
    assemble(width, height, tris.len(), per_row)
}

/// The image of per-row pixels and per-row visible areas (summed in row order).
fn assemble(
    width: u32,
    height: u32,
    ntris: usize,
    per_row: Vec<(Vec<RefPixel>, Vec<f64>)>,
) -> RefImage {
    let mut img = RefImage {
        width,
        height,
        rgb: Vec::new(),
        covered: Vec::new(),
        dominant: Vec::new(),
        dominant_area: Vec::new(),
        visible_area: vec![0.0; ntris],
        mixed: Vec::new(),
    };
    for (px, vis) in per_row {
        for p in px {
            img.rgb.push(p.rgb);
            img.covered.push(p.covered);
            img.dominant.push(p.dominant);
            img.dominant_area.push(p.dominant_area);
            img.mixed.push(p.mixed);
        }
        for (a, b) in img.visible_area.iter_mut().zip(vis) {
            *a += b;
        }
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subtract_square_from_square_leaves_l_shape_area() {
        let a: Poly = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        let b: Poly = vec![[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]];
        let rest = subtract(vec![a], &b);
        let area: f64 = rest.iter().map(|p| area_centroid(p).0).sum();
        assert!((area - 3.0).abs() < 1e-12);
    }

    #[test]
    fn subtract_ignores_a_repeated_occluder_vertex() {
        let a: Poly = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        let b: Poly = vec![[1.0, 1.0], [3.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]];
        let rest = subtract(vec![a], &b);
        let area: f64 = rest.iter().map(|p| area_centroid(p).0).sum();
        assert!((area - 3.0).abs() < 1e-12, "{area}");
    }

    #[test]
    fn centroid_of_unit_square() {
        let (a, c) = area_centroid(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert!((a - 1.0).abs() < 1e-15);
        assert!((c[0] - 0.5).abs() < 1e-15 && (c[1] - 0.5).abs() < 1e-15);
    }
}
