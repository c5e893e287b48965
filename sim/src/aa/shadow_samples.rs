//! Anti-aliased shadows: where each method samples the shadow flags, and with which weights.
//!
//! Seed 001's span parity (§4) decides shadow per *sample*: a processor toggles DSF when a
//! shadow span covers its sample point in front of its depth. The array samples pixel
//! centres; a method that anti-aliases takes more samples per pixel, and its hardware would
//! run the shadow spans once per sample set — on every sub-scanline for multi-scanning
//! (seed 002 §2.2: the shadow polygons are polygons like any other, drawn on every
//! sub-scanline), per subpixel for the A-buffer (seed 000: the fragment's subpixels), per
//! sample for corner sampling (seed 003) and supersampling. Each sample set is a regular
//! lattice ([`Lattice`]); the pipeline renders every lattice as a frame of the array
//! (shadow spans included, through a [`crate::frontend::SampleGrid`]), and a pixel's
//! shadow is the weighted sum over its [`Tap`]s.
//!
//! | method | lattices | taps per pixel, weights |
//! |---|---|---|
//! | multiscan `n` | `n × n`: sub-scanline `y = j + l/n`, `l < n` (the method's own, §2.2.1), and `n` x positions `i + (2m+1)/(2n)` per sub-scanline | `(n + 1)·n`: sub-scanlines `l = 0..=n` (`l = n` is the next row's `l = 0`), trapezoidal weights 1, 2, …, 2, 1 |
//! | A-buffer `n × m` mask | `n·m`, one per subpixel centre `((2a+1)/(2n), (2b+1)/(2m))` | `n·m`, weight 1 |
//! | corner, D3D 4×, grid 2×2 | the method's own lattices ([`super::corner::lattices`]) | the method's own samples and weights ([`super::corner::pixel_samples`]) |
//! | ssaa `k` | `k²`, one per sample offset `((2a+1)/(2k), (2b+1)/(2k))` | `k²`, weight 1 |
//!
//! Post-processing has no lattice: it works on the array's one sample per pixel and treats
//! a change of shadow state between neighbours as an edge ([`super::postfx`]).
//!
//! **Not exact:** multi-scanning computes object edges with exact x coverage per
//! sub-scanline, but the shadow state here is sampled at `n` points per sub-scanline (a
//! shadow boundary on a surface is where a shadow polygon's depth crosses the surface's,
//! not a span end, so its exact x would need a per-span depth intersection); the Gaussian
//! and cone filters' shadow weights are the box filter's over the pixel square.

use super::corner;
use super::sampler::Lattice;
use super::AaMethod;
use crate::frontend::SampleGrid;

/// One sample of a pixel: lattice `lattice`, sample `(a, b)` of it, integer weight.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tap {
    /// Index into [`ShadowTaps::lattices`].
    pub lattice: usize,
    /// Sample column in the lattice.
    pub a: u32,
    /// Sample row in the lattice.
    pub b: u32,
    /// Weight (the pixel's weights sum to [`ShadowTaps::total`]).
    pub weight: u32,
}

/// The shadow samples of one method on a `width × height` screen.
#[derive(Clone, Debug)]
pub struct ShadowTaps {
    /// The sample lattices, each rendered as one frame of the array.
    pub lattices: Vec<Lattice>,
    /// Sum of one pixel's tap weights.
    pub total: u32,
    rule: Rule,
    width: u32,
    height: u32,
}

#[derive(Clone, Debug)]
enum Rule {
    /// `nx × ny` lattices (row-major: offset `(a, b)` is lattice `b·nx + a`), one tap each.
    Grid { nx: u32, ny: u32 },
    /// Multi-scanning with `n` sub-scanlines.
    Multiscan { n: u32 },
    /// The corner module's own samples.
    Corner(corner::CornerParams),
}

/// `nx·ny` lattices of `width × height` at the sub-pixel offsets `(2a+1)/(2nx)`,
/// `(2b+1)/(2ny)`.
fn offset_grid(nx: u32, ny: u32, width: u32, height: u32) -> Vec<Lattice> {
    let mut v = Vec::new();
    for b in 0..ny as i64 {
        for a in 0..nx as i64 {
            // Common denominator 2·nx·ny keeps both axes exact.
            let den = 2 * nx as i64 * ny as i64;
            v.push(Lattice {
                nx: width,
                ny: height,
                sx: den,
                sy: den,
                ox: (2 * a + 1) * ny as i64,
                oy: (2 * b + 1) * nx as i64,
                den,
            });
        }
    }
    v
}

impl ShadowTaps {
    /// The samples of `method`, or `None` for the methods that sample shadows once per
    /// pixel (no anti-aliasing, post-processing).
    pub fn for_method(method: &AaMethod, width: u32, height: u32) -> Option<ShadowTaps> {
        let grid = |nx: u32, ny: u32| ShadowTaps {
            lattices: offset_grid(nx, ny, width, height),
            total: nx * ny,
            rule: Rule::Grid { nx, ny },
            width,
            height,
        };
        match method {
            AaMethod::None | AaMethod::PostFx(_) => None,
            AaMethod::Ssaa { k } => Some(grid(*k, *k)),
            AaMethod::Abuffer(p) => Some(grid(p.size.n(), p.size.m())),
            // Every pixel has one sample inside it and three outside (seed 003), so
            // pixel (0, 0)'s weights sum to every pixel's total.
            AaMethod::Corner(p) => Some(ShadowTaps {
                lattices: corner::lattices(p, width, height),
                total: corner::pixel_samples(p, 0, 0).iter().map(|s| s.3).sum(),
                rule: Rule::Corner(*p),
                width,
                height,
            }),
            AaMethod::Multiscan(p) => {
                let n = p.subscanlines.max(1);
                let den = 2 * n as i64;
                let mut lattices = Vec::new();
                for l in 0..n as i64 {
                    for m in 0..n as i64 {
                        lattices.push(Lattice {
                            nx: width,
                            // Sub-scanline 0 also serves as the bottom boundary (l = n)
                            // of the last row.
                            ny: if l == 0 { height + 1 } else { height },
                            sx: den,
                            sy: den,
                            ox: 2 * m + 1,
                            oy: 2 * l,
                            den,
                        });
                    }
                }
                Some(ShadowTaps {
                    lattices,
                    total: 2 * n * n,
                    rule: Rule::Multiscan { n },
                    width,
                    height,
                })
            }
        }
    }

    /// The taps of pixel `(i, j)`, into `out` (cleared first).
    pub fn pixel(&self, i: u32, j: u32, out: &mut Vec<Tap>) {
        out.clear();
        match &self.rule {
            Rule::Grid { nx, ny } => {
                for k in 0..(nx * ny) as usize {
                    out.push(Tap {
                        lattice: k,
                        a: i,
                        b: j,
                        weight: 1,
                    });
                }
            }
            Rule::Multiscan { n } => {
                let n = *n;
                for l in 0..=n {
                    let weight = if l == 0 || l == n { 1 } else { 2 };
                    let (row, b) = if l == n { (0, j + 1) } else { (l, j) };
                    for m in 0..n {
                        out.push(Tap {
                            lattice: (row * n + m) as usize,
                            a: i,
                            b,
                            weight,
                        });
                    }
                }
            }
            Rule::Corner(p) => {
                for (lattice, a, b, weight) in corner::pixel_samples(p, i, j) {
                    out.push(Tap {
                        lattice,
                        a,
                        b,
                        weight,
                    });
                }
            }
        }
    }
}

impl ShadowTaps {
    /// The pixels sample `(a, b)` of lattice `lattice` contributes to, with their weights:
    /// the inverse of [`ShadowTaps::pixel`], so one rendered lattice can be added into the
    /// pixels' sums and dropped.
    pub fn scatter(&self, lattice: usize, a: u32, b: u32, mut f: impl FnMut(u32, u32, u32)) {
        let (w, h) = (self.width, self.height);
        match &self.rule {
            Rule::Grid { .. } => f(a, b, 1),
            Rule::Multiscan { n } => {
                let row = lattice as u32 / n;
                if b < h {
                    f(a, b, if row == 0 { 1 } else { 2 });
                }
                if row == 0 && b >= 1 {
                    f(a, b - 1, 1);
                }
            }
            Rule::Corner(_) => {
                let mut taps = Vec::new();
                // A corner sample is shared by the (at most four) pixels around it; the
                // centre sample belongs to its pixel alone.
                let (x, y) = self.lattices[lattice].pos(a, b);
                let (ci, cj) = (x.round() as i64, y.round() as i64);
                for j in (cj - 1).max(0)..=cj.min(h as i64 - 1) {
                    for i in (ci - 1).max(0)..=ci.min(w as i64 - 1) {
                        self.pixel(i as u32, j as u32, &mut taps);
                        for t in &taps {
                            if (t.lattice, t.a, t.b) == (lattice, a, b) {
                                f(i as u32, j as u32, t.weight);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The raster grid that renders lattice `l` (its samples at the raster's pixel centres).
pub fn grid_of(l: &Lattice) -> SampleGrid {
    let d = l.den as f64;
    SampleGrid {
        x0: l.ox as f64 / d,
        y0: l.oy as f64 / d,
        step_x: l.sx as f64 / d,
        step_y: l.sy as f64 / d,
        cols: l.nx,
        rows: l.ny,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::{CornerParams, Filter, MultiscanParams, Pattern};

    /// Sample positions of pixel (i, j) with weights, from the taps.
    fn positions(t: &ShadowTaps, i: u32, j: u32) -> Vec<(f64, f64, u32)> {
        let mut taps = Vec::new();
        t.pixel(i, j, &mut taps);
        taps.iter()
            .map(|tp| {
                let (x, y) = t.lattices[tp.lattice].pos(tp.a, tp.b);
                (x, y, tp.weight)
            })
            .collect()
    }

    #[test]
    fn ssaa_taps_are_the_k_by_k_subpixel_centres() {
        let t = ShadowTaps::for_method(&AaMethod::Ssaa { k: 3 }, 5, 4).unwrap();
        let mut got = positions(&t, 2, 1);
        got.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let mut want = Vec::new();
        for a in 0..3 {
            for b in 0..3 {
                want.push((
                    2.0 + (2 * a + 1) as f64 / 6.0,
                    1.0 + (2 * b + 1) as f64 / 6.0,
                    1,
                ));
            }
        }
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(got.len(), 9);
        for (g, w) in got.iter().zip(&want) {
            assert!((g.0 - w.0).abs() < 1e-12 && (g.1 - w.1).abs() < 1e-12 && g.2 == w.2);
        }
        assert_eq!(t.total, 9);
    }

    #[test]
    fn multiscan_taps_are_the_sub_scanlines_with_trapezoid_weights() {
        let n = 4;
        let m = AaMethod::Multiscan(MultiscanParams::new(n, Filter::Box));
        let t = ShadowTaps::for_method(&m, 6, 3).unwrap();
        // The last row's bottom boundary exists.
        let got = positions(&t, 5, 2);
        assert_eq!(got.len(), ((n + 1) * n) as usize);
        let sum: u32 = got.iter().map(|g| g.2).sum();
        assert_eq!(sum, t.total);
        for &(x, y, w) in &got {
            let l = ((y - 2.0) * n as f64).round();
            assert!((y - 2.0 - l / n as f64).abs() < 1e-12, "y {y}");
            assert_eq!(w, if l == 0.0 || l == n as f64 { 1 } else { 2 });
            assert!(x > 5.0 && x < 6.0);
        }
        for tp in {
            let mut v = Vec::new();
            t.pixel(5, 2, &mut v);
            v
        } {
            let l = &t.lattices[tp.lattice];
            assert!(tp.a < l.nx && tp.b < l.ny);
        }
    }

    #[test]
    fn corner_taps_are_the_methods_own_samples() {
        let p = CornerParams::new(Pattern::Corner, false);
        let t = ShadowTaps::for_method(&AaMethod::Corner(p), 7, 5).unwrap();
        let want = corner::pixel_offsets(&p, 3, 2);
        let got = positions(&t, 3, 2);
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(&want) {
            assert!((g.0 - 3.5 - w.0).abs() < 1e-12 && (g.1 - 2.5 - w.1).abs() < 1e-12);
            assert_eq!(g.2 as f64, w.2);
        }
    }

    #[test]
    fn scatter_is_the_inverse_of_the_pixel_taps() {
        use crate::abuffer::AbufferParams;
        use pixelproc_formats::abuffer::MaskSize;
        let (w, h) = (7, 5);
        let methods = [
            AaMethod::Ssaa { k: 2 },
            AaMethod::Abuffer(AbufferParams {
                size: MaskSize::new(3, 2).unwrap(),
                ..Default::default()
            }),
            AaMethod::Multiscan(MultiscanParams::new(3, Filter::Box)),
            AaMethod::Corner(CornerParams::new(Pattern::Corner, true)),
            AaMethod::Corner(CornerParams::new(Pattern::D3d4x, false)),
        ];
        for m in methods {
            let t = ShadowTaps::for_method(&m, w, h).unwrap();
            let mut forward = Vec::new();
            let mut taps = Vec::new();
            for j in 0..h {
                for i in 0..w {
                    t.pixel(i, j, &mut taps);
                    let sum: u32 = taps.iter().map(|x| x.weight).sum();
                    assert_eq!(sum, t.total, "{m:?} ({i},{j})");
                    for x in &taps {
                        forward.push((x.lattice, x.a, x.b, i, j, x.weight));
                    }
                }
            }
            let mut back = Vec::new();
            for (li, l) in t.lattices.iter().enumerate() {
                for b in 0..l.ny {
                    for a in 0..l.nx {
                        t.scatter(li, a, b, |i, j, wt| back.push((li, a, b, i, j, wt)));
                    }
                }
            }
            forward.sort();
            back.sort();
            assert_eq!(forward, back, "{m:?}");
        }
    }

    #[test]
    fn a_lattice_grid_puts_its_samples_at_raster_centres() {
        let l = Lattice {
            nx: 9,
            ny: 4,
            sx: 12,
            sy: 12,
            ox: 5,
            oy: 7,
            den: 6,
        };
        let g = grid_of(&l);
        let (x, y) = l.pos(3, 2);
        assert!((g.x0 + 3.0 * g.step_x - x).abs() < 1e-12);
        assert!((g.y0 + 2.0 * g.step_y - y).abs() < 1e-12);
        assert_eq!((g.cols, g.rows), (9, 4));
    }
}
