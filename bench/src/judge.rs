//! Judging an image against the exact reference of its own filter from
//! [`pixelproc_sim::reference`] (see `docs/accuracy.md`), and the Pareto frontier of error
//! against time.

use pixelproc_sim::aa::multiscan::GAUSS_SIGMA;
use pixelproc_sim::aa::{AaMethod, Filter};
use pixelproc_sim::reference::{RefFilter, RefImage};

/// The filter a method resolves with, hence the reference it is judged against: the
/// seed-002 Gaussian or cone for multi-scanning with those filters, the pixel box for
/// every other method.
pub fn reference_filter(aa: &AaMethod) -> RefFilter {
    match aa {
        AaMethod::Multiscan(p) => match p.filter {
            Filter::Box => RefFilter::Box,
            Filter::Gauss => RefFilter::Gauss { sigma: GAUSS_SIGMA },
            Filter::Cone => RefFilter::Cone,
        },
        _ => RefFilter::Box,
    }
}

/// How far one rendered image is from the reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Judgement {
    /// Sum of squared channel errors on the 0..255 scale.
    pub sq_err: f64,
    /// Largest channel error.
    pub max_err: f64,
    /// Pixels whose visible surface differs from the reference's dominant surface (zero
    /// when the method reports no visibility).
    pub wrong_visible: u64,
    /// Of those, pixels where the reference's dominant surface covers at least 3/4 of the
    /// pixel (a clear majority: not a near-tie at an edge).
    pub wrong_visible_clear: u64,
}

/// Judges the RGB8 image `rgb` (and the per-pixel visible surface, if the method reports
/// one) against the reference `r`.
pub fn judge(r: &RefImage, rgb: &[u8], visible: Option<&Vec<i32>>) -> Judgement {
    let mut sq = 0.0;
    let mut mx: f64 = 0.0;
    for (k, c) in r.rgb.iter().enumerate() {
        for ch in 0..3 {
            let d = rgb[3 * k + ch] as f64 - c[ch];
            sq += d * d;
            mx = mx.max(d.abs());
        }
    }
    let (mut wrong, mut clear) = (0, 0);
    if let Some(v) = visible {
        for (k, (&a, &b)) in v.iter().zip(&r.dominant).enumerate() {
            if a != b {
                wrong += 1;
                if r.dominant_area[k] >= 0.75 {
                    clear += 1;
                }
            }
        }
    }
    Judgement {
        sq_err: sq,
        max_err: mx,
        wrong_visible: wrong,
        wrong_visible_clear: clear,
    }
}

/// Indices of the points on the Pareto frontier of `(time, error)` (both minimised): no
/// other point is at most as slow and at most as wrong and better in one of the two.
/// Sorted by time.
pub fn pareto_frontier(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let (ti, ei) = points[i];
            !points
                .iter()
                .enumerate()
                .any(|(j, &(tj, ej))| j != i && tj <= ti && ej <= ei && (tj < ti || ej < ei))
        })
        .collect();
    idx.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    idx
}
