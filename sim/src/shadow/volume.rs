//! Shadow volumes as half-spaces: silhouette or per-face extrusions to infinity, their
//! bounding planes, and the ray box the extrusions are clipped to.

use super::*;

/// One shadow volume: polygons as world points (w = 1) and directions (w = 0), whether
/// the eye is inside it, and the volume as an intersection of half-spaces.
#[derive(Clone, Debug)]
pub struct Volume {
    /// Polygons, homogeneous world coordinates.
    pub polys: Vec<Vec<DVec4>>,
    /// The eye lies inside the volume (statistics: what IF means is decided at the near
    /// plane, see the module header).
    pub eye_inside: bool,
    /// The volume is convex: the points `p` with `h·(p, 1) ≥ 0` for every `h` here (planes
    /// through the light and each extruded edge, and the planes of the light-facing faces
    /// of the caster). Used to find where the near plane cuts it.
    pub planes: Vec<DVec4>,
}

/// The plane through `a`, `b`, `c` as `(n, −n·a)`, oriented so that `inside` is on its
/// positive side (or `None` when degenerate or `inside` lies on it).
pub(super) fn plane_towards(a: DVec3, b: DVec3, c: DVec3, inside: DVec3) -> Option<DVec4> {
    let n = (b - a).cross(c - a);
    let s = n.dot(inside - a);
    if s == 0.0 || !s.is_finite() {
        return None;
    }
    let n = if s > 0.0 { n } else { -n };
    Some(n.extend(-n.dot(a)))
}

/// Half-spaces of a convex caster's volume: light-side planes of its silhouette edges and
/// the planes of the faces that face the light (the light on the other side from the
/// caster's centre). A point is inside when the segment from the light to it meets the
/// caster.
pub(super) fn convex_planes(o: &Occluder, light: DVec3, sil: &[[DVec3; 2]]) -> Vec<DVec4> {
    let verts: Vec<DVec3> = o.faces.iter().flatten().copied().collect();
    let c = verts.iter().copied().sum::<DVec3>() / verts.len() as f64;
    let mut planes: Vec<DVec4> = sil
        .iter()
        .filter_map(|e| plane_towards(light, e[0], e[1], c))
        .collect();
    for t in &o.faces {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        let (sl, sc) = (n.dot(light - t[0]), n.dot(c - t[0]));
        if sl * sc < 0.0 {
            let n = if sc > 0.0 { n } else { -n };
            planes.push(n.extend(-n.dot(t[0])));
        }
    }
    planes
}

/// Half-spaces of one triangle's volume: the three planes through the light and an edge
/// (towards the triangle's centre) and the triangle's plane (away from the light).
pub(super) fn triangle_planes(t: &[DVec3; 3], light: DVec3) -> Vec<DVec4> {
    let c = (t[0] + t[1] + t[2]) / 3.0;
    let mut planes: Vec<DVec4> = (0..3)
        .filter_map(|k| plane_towards(light, t[k], t[(k + 1) % 3], c))
        .collect();
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let n = if n.dot(light - t[0]) > 0.0 { -n } else { n };
    planes.push(n.extend(-n.dot(t[0])));
    planes
}

pub(super) fn extrude(a: DVec3, b: DVec3, light: DVec3) -> Vec<DVec4> {
    vec![
        a.extend(1.0),
        b.extend(1.0),
        (b - light).extend(0.0),
        (a - light).extend(0.0),
    ]
}

/// The volumes of every occluder for one point light.
pub fn volumes(occ: &[Occluder], light: DVec3, eye: DVec3) -> Vec<Volume> {
    let mut out = Vec::new();
    for o in occ {
        if o.convex_closed {
            let front: Vec<bool> = o.faces.iter().map(|t| facing(t, light) > 0.0).collect();
            let sil: Vec<[DVec3; 2]> = o
                .edges
                .iter()
                .filter(|(_, fs)| front[fs[0]] != front[fs[1]])
                .map(|(e, _)| *e)
                .collect();
            if sil.is_empty() {
                continue;
            }
            let polys = sil.iter().map(|e| extrude(e[0], e[1], light)).collect();
            let eye_inside = o.faces.iter().any(|t| segment_hits(eye, light, t));
            out.push(Volume {
                polys,
                eye_inside,
                planes: convex_planes(o, light, &sil),
            });
        } else {
            for t in &o.faces {
                let f = facing(t, light);
                let n = (t[1] - t[0]).cross(t[2] - t[0]).length();
                if f.abs() <= 1e-12 * n * (light - t[0]).length() || (o.closed && f < 0.0) {
                    continue;
                }
                let polys = (0..3)
                    .map(|k| extrude(t[k], t[(k + 1) % 3], light))
                    .collect();
                out.push(Volume {
                    polys,
                    eye_inside: segment_hits(eye, light, t),
                    planes: triangle_planes(t, light),
                });
            }
        }
    }
    out
}

/// The box every view ray that matters lies in: the bounding box of all geometry and the
/// eye, slightly enlarged. A segment from the eye to a visible point stays inside it
/// (both ends do, and a box is convex), so the parts of shadow polygons outside it can
/// never be crossed in front of a visible point: clipping them away changes no parity,
/// and keeps infinite extrusions from spanning the screen to the horizon.
pub fn ray_box(ls: &LoadedScene, eye: DVec3) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (eye, eye);
    for m in &ls.meshes {
        for p in &m.positions {
            lo = lo.min(DVec3::from(*p));
            hi = hi.max(DVec3::from(*p));
        }
    }
    let pad = (hi - lo).length() * 1e-3 + 1e-6;
    (lo - DVec3::splat(pad), hi + DVec3::splat(pad))
}

/// Clips a homogeneous world-space polygon to an axis-aligned box, into `out` (`tmp` is a
/// second buffer; both are reused, so nothing is allocated once they have grown).
pub(super) fn clip_to_box(
    poly: &[DVec4],
    lo: DVec3,
    hi: DVec3,
    out: &mut Vec<DVec4>,
    tmp: &mut Vec<DVec4>,
) {
    out.clear();
    out.extend_from_slice(poly);
    for axis in 0..3 {
        for (bound, sign) in [(lo[axis], 1.0), (hi[axis], -1.0)] {
            if out.is_empty() {
                return;
            }
            // Inside: sign·(x_axis − bound·w) ≥ 0.
            let d = |p: &DVec4| sign * (p[axis] - bound * p.w);
            let poly = &*out;
            tmp.clear();
            for i in 0..poly.len() {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let (da, db) = (d(&a), d(&b));
                if da >= 0.0 {
                    tmp.push(a);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    let (p, q, dp, dq) = if da >= 0.0 {
                        (a, b, da, db)
                    } else {
                        (b, a, db, da)
                    };
                    tmp.push(p + (q - p) * (dp / (dp - dq)));
                }
            }
            std::mem::swap(out, tmp);
        }
    }
}
