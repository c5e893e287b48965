//! Triangle validation, winding, edge functions and the top-left fill rule.
//!
//! Seed 001 (Matsumoto) section 3 fills a span between the left and right edge of a
//! polygon on each scanline; seed 000 (JP2569952B2, background, process 1) ANDs one edge
//! mask per polygon edge. Both need the same edges of the snapped triangle:
//!
//! - **Validation.** Vertex depths within `Z_GEOM_MIN..=Z_GEOM_MAX`, coordinates within
//!   `±MAX_COORD_PX` px ([`check_depths`], [`check_coords`]).
//! - **Winding.** A zero doubled area covers nothing; a negative one is re-wound by
//!   swapping vertices 1 and 2 ([`winding`]), so every edge function is positive inside.
//! - **Edge functions.** `E(x, y) = A·x + B·y + C` in Q.8 units, exactly in `i64`, with
//!   `A = −(q_y − p_y)`, `B = q_x − p_x` for the edge from `p` to `q` ([`EdgeFn`]).
//! - **Top-left rule.** A sample with `E = 0` belongs to the triangle only if the edge is a
//!   *left* edge (`A > 0`) or a *top* edge (`A = 0, B > 0`; y grows downwards). An edge
//!   shared by two triangles has opposite `(A, B)` in each, so exactly one takes samples
//!   on it. The rule depends only on the sign of `E`, so it holds for any positive
//!   multiple of `E` (the scaled subpixel functions of [`crate::mask`], the lattice
//!   functions of [`crate::aa::sampler`]).

use crate::setup::{SetupError, SnappedTri};
use pixelproc_formats::{MAX_COORD_PX, SUBPIXEL_BITS, SUBPIXEL_ONE, Z_GEOM_MAX, Z_GEOM_MIN};

/// Checks that every vertex depth of `t` (and of its decal host, if any) lies in the
/// geometric range; the first failing depth is the error.
pub fn check_depths(t: &SnappedTri) -> Result<(), SetupError> {
    for &z in t.z.iter().chain(t.host.iter().flat_map(|h| h.z.iter())) {
        if !(Z_GEOM_MIN..=Z_GEOM_MAX).contains(&z) {
            return Err(SetupError::DepthOutOfRange(z as i64));
        }
    }
    Ok(())
}

/// Checks that every Q.8 coordinate of `points` lies within `±MAX_COORD_PX` px; the first
/// failing coordinate is the error.
pub fn check_coords<'a>(points: impl IntoIterator<Item = &'a [i32; 2]>) -> Result<(), SetupError> {
    let lim = (MAX_COORD_PX as i64) << SUBPIXEL_BITS;
    for p in points {
        for &k in p {
            if (k as i64).abs() > lim {
                return Err(SetupError::OutOfRange(k as f64 / SUBPIXEL_ONE as f64));
            }
        }
    }
    Ok(())
}

/// Doubled signed area of the triangle `v` (Q.8² units), positive when the vertices run
/// clockwise on screen (y down).
#[inline]
pub fn area2(v: [[i32; 2]; 3]) -> i64 {
    (v[1][0] as i64 - v[0][0] as i64) * (v[2][1] as i64 - v[0][1] as i64)
        - (v[2][0] as i64 - v[0][0] as i64) * (v[1][1] as i64 - v[0][1] as i64)
}

/// The vertex order that makes every edge function positive inside: `[0, 1, 2]`, or
/// `[0, 2, 1]` for a negative area; `None` for a zero-area (degenerate) triangle.
#[inline]
pub fn winding(v: [[i32; 2]; 3]) -> Option<[usize; 3]> {
    match area2(v).signum() {
        0 => None,
        1 => Some([0, 1, 2]),
        _ => Some([0, 2, 1]),
    }
}

/// Applies a vertex order from [`winding`] to per-vertex data.
#[inline]
pub fn rewind<T: Copy>(order: [usize; 3], x: [T; 3]) -> [T; 3] {
    order.map(|k| x[k])
}

/// One edge function `E(x, y) = A·x + B·y + C` in Q.8 units, positive inside, and whether
/// the edge takes the samples on it (top-left rule).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgeFn {
    /// `A = −(q_y − p_y)`.
    pub a: i64,
    /// `B = q_x − p_x`.
    pub b: i64,
    /// `C = −(A·p_x + B·p_y)`.
    pub c: i64,
    /// A left (`A > 0`) or top (`A = 0, B > 0`) edge.
    pub top_left: bool,
}

impl EdgeFn {
    /// The edge from `p` to `q` (Q.8).
    #[inline]
    pub fn new(p: [i32; 2], q: [i32; 2]) -> EdgeFn {
        let a = -((q[1] - p[1]) as i64);
        let b = (q[0] - p[0]) as i64;
        let c = -(a * p[0] as i64 + b * p[1] as i64);
        EdgeFn {
            a,
            b,
            c,
            top_left: a > 0 || (a == 0 && b > 0),
        }
    }

    /// The three edges of a triangle already wound by [`winding`]: `v0→v1`, `v1→v2`,
    /// `v2→v0`.
    #[inline]
    pub fn of_triangle(v: [[i32; 2]; 3]) -> [EdgeFn; 3] {
        [
            EdgeFn::new(v[0], v[1]),
            EdgeFn::new(v[1], v[2]),
            EdgeFn::new(v[2], v[0]),
        ]
    }

    /// The fill rule on a value `e` of this edge's function (or of any positive multiple
    /// of it): strictly inside, or on the edge of a top-left edge.
    #[inline]
    pub fn inside(&self, e: i64) -> bool {
        e > 0 || (e == 0 && self.top_left)
    }
}
