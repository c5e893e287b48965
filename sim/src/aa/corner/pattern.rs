//! The sample patterns of corner sampling (see [`super`]): the seed's corner pattern
//! (seed 003, Fig. 3a) and the two comparison patterns, as sample lattices and per-pixel
//! samples with their weights, the per-row templates the resolve reads them with, and
//! the quality figures of a pattern from its positions and weights alone.

use super::super::sampler::Lattice;

/// Sample pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// Corner-shared sampling of seed 003.
    Corner,
    /// The D3D standard 4× pattern: (−2,−6), (6,−2), (−6,2), (2,6) sixteenths.
    D3d4x,
    /// Ordered 2×2 grid at (±¼, ±¼).
    Grid2x2,
}

/// Resolve weights (integers, normalised by their sum).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerWeights {
    /// Weight of the one corner sample that lies inside the pixel (corner pattern); for
    /// the per-pixel patterns, the weight of the first sample.
    pub inside: u32,
    /// Weight of each other pattern sample.
    pub outside: u32,
    /// Weight of the centre sample (used only with `centre = true`).
    pub centre: u32,
}

impl CornerWeights {
    /// ¼ each.
    pub const UNIFORM: CornerWeights = CornerWeights {
        inside: 1,
        outside: 1,
        centre: 0,
    };
    /// 0.4 for the inside sample, 0.2 for the others (seed 003).
    pub const INSIDE_04: CornerWeights = CornerWeights {
        inside: 2,
        outside: 1,
        centre: 0,
    };
    /// With the centre sample: 0.4 centre, 0.15 for each corner.
    pub const CENTRE_04: CornerWeights = CornerWeights {
        inside: 3,
        outside: 3,
        centre: 8,
    };
}

/// Parameters of [`Pattern`] sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerParams {
    /// The pattern.
    pub pattern: Pattern,
    /// Add one sample at each pixel centre (two samples per pixel for the corner pattern).
    pub centre: bool,
    /// Resolve weights.
    pub weights: CornerWeights,
}

impl CornerParams {
    /// Defaults: uniform weights; with the centre sample, [`CornerWeights::CENTRE_04`].
    pub fn new(pattern: Pattern, centre: bool) -> CornerParams {
        CornerParams {
            pattern,
            centre,
            weights: if centre {
                CornerWeights::CENTRE_04
            } else {
                CornerWeights::UNIFORM
            },
        }
    }

    /// A short label.
    pub fn label(&self) -> String {
        let p = match self.pattern {
            Pattern::Corner => "corner",
            Pattern::D3d4x => "d3d4x",
            Pattern::Grid2x2 => "grid2x2",
        };
        let w = self.weights;
        format!(
            "{p}{} w={}/{}/{}",
            if self.centre { "+centre" } else { "" },
            w.inside,
            w.outside,
            if self.centre { w.centre } else { 0 }
        )
    }
}

/// Offsets (sixths of a pixel) of the corner sample by corner parity `(I mod 2, J mod 2)`.
const CORNER_OFF6: [[(i64, i64); 2]; 2] = [[(-1, -1), (1, -1)], [(1, 1), (-1, 1)]];
// indexed [I mod 2][J mod 2]

/// Per-pixel offsets (sixteenths) of the D3D 4× pattern.
const D3D4X_OFF16: [(i64, i64); 4] = [(-2, -6), (6, -2), (-6, 2), (2, 6)];
/// Per-pixel offsets (sixteenths) of the ordered 2×2 grid.
const GRID_OFF16: [(i64, i64); 4] = [(-4, -4), (4, -4), (-4, 4), (4, 4)];

/// The lattices a pattern renders (plus the centre lattice last, when enabled).
pub fn lattices(p: &CornerParams, width: u32, height: u32) -> Vec<Lattice> {
    let mut v = Vec::new();
    match p.pattern {
        Pattern::Corner => {
            // Sub-lattice (pa, pb): corners I = 2a + pa, J = 2b + pb.
            for pb in 0..2u32 {
                for pa in 0..2u32 {
                    let (ox, oy) = CORNER_OFF6[pa as usize][pb as usize];
                    v.push(Lattice {
                        nx: (width - pa) / 2 + 1,
                        ny: (height - pb) / 2 + 1,
                        sx: 12,
                        sy: 12,
                        ox: 6 * pa as i64 + ox,
                        oy: 6 * pb as i64 + oy,
                        den: 6,
                    });
                }
            }
        }
        Pattern::D3d4x | Pattern::Grid2x2 => {
            let off = if p.pattern == Pattern::D3d4x {
                D3D4X_OFF16
            } else {
                GRID_OFF16
            };
            for (dx, dy) in off {
                v.push(Lattice {
                    nx: width,
                    ny: height,
                    sx: 16,
                    sy: 16,
                    ox: 8 + dx,
                    oy: 8 + dy,
                    den: 16,
                });
            }
        }
    }
    if p.centre {
        v.push(Lattice {
            nx: width,
            ny: height,
            sx: 2,
            sy: 2,
            ox: 1,
            oy: 1,
            den: 2,
        });
    }
    v
}

/// The samples of pixel `(i, j)`: `(lattice, a, b, weight)`, pattern samples first.
pub fn pixel_samples(p: &CornerParams, i: u32, j: u32) -> Vec<(usize, u32, u32, u32)> {
    let mut out = PixelSamples::default();
    pixel_samples_into(p, i, j, &mut out);
    out.as_slice().to_vec()
}

/// Up to five samples of one pixel, on the stack.
#[derive(Default)]
pub(super) struct PixelSamples {
    pub(super) s: [(usize, u32, u32, u32); 5],
    pub(super) n: usize,
}

impl PixelSamples {
    fn push(&mut self, v: (usize, u32, u32, u32)) {
        self.s[self.n] = v;
        self.n += 1;
    }
    pub(super) fn as_slice(&self) -> &[(usize, u32, u32, u32)] {
        &self.s[..self.n]
    }
}

/// [`pixel_samples`] into a buffer without allocating.
fn pixel_samples_into(p: &CornerParams, i: u32, j: u32, out: &mut PixelSamples) {
    out.n = 0;
    let lats_n = match p.pattern {
        Pattern::Corner => {
            for (ci, cj) in [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)] {
                let (pa, pb) = (ci % 2, cj % 2);
                let (ox, oy) = CORNER_OFF6[pa as usize][pb as usize];
                // Inside the pixel square [i, i+1) × [j, j+1), in sixths.
                let x6 = 6 * ci as i64 + ox;
                let y6 = 6 * cj as i64 + oy;
                let inside = (6 * i as i64..6 * (i as i64 + 1)).contains(&x6)
                    && (6 * j as i64..6 * (j as i64 + 1)).contains(&y6);
                let w = if inside {
                    p.weights.inside
                } else {
                    p.weights.outside
                };
                out.push(((2 * pb + pa) as usize, ci / 2, cj / 2, w));
            }
            4
        }
        Pattern::D3d4x | Pattern::Grid2x2 => {
            for l in 0..4 {
                let w = if l == 0 {
                    p.weights.inside
                } else {
                    p.weights.outside
                };
                out.push((l, i, j, w));
            }
            4
        }
    };
    if p.centre {
        out.push((lats_n, i, j, p.weights.centre));
    }
}

/// The samples of every pixel of one row from two templates: a pixel's samples depend on
/// the parity of its column only, up to a shift of their lattice column `a` by a fixed
/// amount per two pixels (one for the corner lattices, which hold every other corner;
/// two for lattices with a sample per pixel). [`pixel_samples_into`] of pixels 0 and 1
/// gives the templates, of pixels 2 and 3 the shifts; `of(i)` equals
/// `pixel_samples_into(p, i, j)` (tested).
pub(super) struct RowSamples {
    /// Per column parity: the samples of pixel 0 or 1.
    pub(super) tpl: [PixelSamples; 2],
    /// Per column parity and sample: the shift of `a` per two pixels.
    pub(super) adv: [[u32; 5]; 2],
}

impl RowSamples {
    pub(super) fn new(p: &CornerParams, j: u32) -> RowSamples {
        let mut tpl = [PixelSamples::default(), PixelSamples::default()];
        let mut adv = [[0u32; 5]; 2];
        for q in 0..2 {
            let mut next = PixelSamples::default();
            pixel_samples_into(p, q as u32, j, &mut tpl[q]);
            pixel_samples_into(p, q as u32 + 2, j, &mut next);
            for (n, (t, s)) in tpl[q].as_slice().iter().zip(next.as_slice()).enumerate() {
                adv[q][n] = s.1 - t.1;
            }
        }
        RowSamples { tpl, adv }
    }

    /// The samples of pixel `i` of the row.
    #[inline]
    pub(super) fn of(&self, i: u32) -> PixelSamples {
        let q = (i & 1) as usize;
        let k = i >> 1;
        let mut out = PixelSamples {
            n: self.tpl[q].n,
            ..Default::default()
        };
        for n in 0..out.n {
            let (l, a, b, w) = self.tpl[q].s[n];
            out.s[n] = (l, a + k * self.adv[q][n], b, w);
        }
        out
    }
}

/// Quality figures of a pattern, from its sample positions and weights alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatternMetrics {
    /// Distinct coverage levels a horizontal edge sweeping down through a pixel gives
    /// (minimum over the pixels of one pattern period).
    pub levels_horizontal: usize,
    /// The same for a vertical edge sweeping right.
    pub levels_vertical: usize,
    /// Root-mean-square edge-coverage error over edge orientations and offsets: for a
    /// straight edge at angle θ (uniform on [0, π), 180 steps) and signed distance d from
    /// the pixel centre (uniform on [−√2/2·1.5, +√2/2·1.5], 300 steps), the weighted
    /// fraction of samples on the covered side minus the exact covered fraction of the
    /// pixel square, squared and averaged (then over the pixels of one period).
    pub edge_error_rms: f64,
}

/// Sample offsets from the pixel centre and weights, for pixel `(i, j)`.
pub fn pixel_offsets(p: &CornerParams, i: u32, j: u32) -> Vec<(f64, f64, f64)> {
    let lats = lattices(p, 2, 2);
    pixel_samples(p, i, j)
        .into_iter()
        .map(|(l, a, b, w)| {
            let (x, y) = lats[l].pos(a, b);
            (x - i as f64 - 0.5, y - j as f64 - 0.5, w as f64)
        })
        .collect()
}

/// Levels and edge error of a pattern (see [`PatternMetrics`]); float, report-only.
pub fn pattern_metrics(p: &CornerParams) -> PatternMetrics {
    let mut lh = usize::MAX;
    let mut lv = usize::MAX;
    let mut err = 0.0;
    for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let s = pixel_offsets(p, i, j);
        let levels = |key: &dyn Fn(&(f64, f64, f64)) -> f64| {
            let mut v: Vec<&(f64, f64, f64)> = s.iter().collect();
            v.sort_by(|a, b| key(a).total_cmp(&key(b)));
            let mut sums = vec![0.0];
            let mut acc = 0.0;
            let mut k = 0;
            while k < v.len() {
                // Samples at the same coordinate are crossed together.
                let c = key(v[k]);
                while k < v.len() && key(v[k]) == c {
                    acc += v[k].2;
                    k += 1;
                }
                sums.push(acc);
            }
            sums.len()
        };
        lh = lh.min(levels(&|q| q.1));
        lv = lv.min(levels(&|q| q.0));
        let wt: f64 = s.iter().map(|q| q.2).sum();
        let (nt, nd) = (180, 300);
        let dmax = 1.5 * std::f64::consts::FRAC_1_SQRT_2;
        let mut e = 0.0;
        for ti in 0..nt {
            let th = std::f64::consts::PI * (ti as f64 + 0.5) / nt as f64;
            let (nx, ny) = (th.cos(), th.sin());
            for di in 0..nd {
                let d = -dmax + 2.0 * dmax * (di as f64 + 0.5) / nd as f64;
                // Covered side: n·p < d.
                let cov_s: f64 = s
                    .iter()
                    .filter(|q| nx * q.0 + ny * q.1 < d)
                    .map(|q| q.2)
                    .sum::<f64>()
                    / wt;
                let cov_a = square_fraction_below(nx, ny, d);
                e += (cov_s - cov_a).powi(2);
            }
        }
        err += e / (nt * nd) as f64;
    }
    PatternMetrics {
        levels_horizontal: lh,
        levels_vertical: lv,
        edge_error_rms: (err / 4.0).sqrt(),
    }
}

/// Area of `{q ∈ [−½, ½]² : n·q < d}` for a unit normal `n` (numerical: 400² midpoints
/// would be slow, so the closed form of a clipped square via polygon clipping).
fn square_fraction_below(nx: f64, ny: f64, d: f64) -> f64 {
    let sq = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
    let mut out: Vec<[f64; 2]> = Vec::new();
    for k in 0..4 {
        let (a, b) = (sq[k], sq[(k + 1) % 4]);
        let fa = d - (nx * a[0] + ny * a[1]);
        let fb = d - (nx * b[0] + ny * b[1]);
        if fa >= 0.0 {
            out.push(a);
        }
        if (fa > 0.0 && fb < 0.0) || (fa < 0.0 && fb > 0.0) {
            let t = fa / (fa - fb);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    let n = out.len();
    let mut s = 0.0;
    for k in 0..n {
        let (a, b) = (out[k], out[(k + 1) % n]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    (0.5 * s).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The per-row templates give every pixel the samples `pixel_samples` gives it, for
    /// every pattern with and without the centre sample (weights that tell the samples
    /// apart).
    #[test]
    fn row_templates_give_each_pixels_samples() {
        for pattern in [Pattern::Corner, Pattern::D3d4x, Pattern::Grid2x2] {
            for centre in [false, true] {
                let mut p = CornerParams::new(pattern, centre);
                p.weights = CornerWeights {
                    inside: 5,
                    outside: 3,
                    centre: 7,
                };
                for j in 0..7 {
                    let rows = RowSamples::new(&p, j);
                    for i in 0..41 {
                        assert_eq!(
                            rows.of(i).as_slice(),
                            pixel_samples(&p, i, j),
                            "{pattern:?} centre {centre} pixel ({i}, {j})"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn corner_pattern_matches_seed_example() {
        // Pixel (0, 0) offsets in thirds: (−2,−2), (+2,−1), (−1,+1), (+1,+2).
        let p = CornerParams::new(Pattern::Corner, false);
        let mut got: Vec<(i64, i64)> = pixel_offsets(&p, 0, 0)
            .iter()
            .map(|q| ((q.0 * 3.0).round() as i64, (q.1 * 3.0).round() as i64))
            .collect();
        got.sort();
        assert_eq!(got, vec![(-2, -2), (-1, 1), (1, 2), (2, -1)]);
    }

    #[test]
    fn every_corner_pixel_has_distinct_x_y_and_diagonals_and_one_inside() {
        let p = CornerParams::new(Pattern::Corner, false);
        for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1), (5, 8)] {
            let s = pixel_offsets(&p, i, j);
            let k = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
                let mut v: Vec<i64> = s.iter().map(|q| (f(q) * 6.0).round() as i64).collect();
                v.sort();
                v.dedup();
                v.len()
            };
            assert_eq!(k(&|q| q.0), 4);
            assert_eq!(k(&|q| q.1), 4);
            assert_eq!(k(&|q| q.0 - q.1), 4);
            assert_eq!(k(&|q| q.0 + q.1), 4);
            let inside = s
                .iter()
                .filter(|q| q.0.abs() < 0.5 && q.1.abs() < 0.5)
                .count();
            assert_eq!(inside, 1);
        }
    }
}
