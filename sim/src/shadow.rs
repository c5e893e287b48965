//! Shadows by span parity (seed 001, Matsumoto, "hardware-oriented fast shadow
//! generation").
//!
//! - §2 (basic idea): after the ordinary spans of a scanline, the spans of shadow polygons
//!   (Crow 1977 shadow volumes) are expanded volume after volume, touching only flags.
//! - §3 (span data): shadow spans carry attr SP, EV (last span of a volume) or IF (also
//!   inverts DSF on every pixel: the viewer is inside the volume).
//! - §4 (per-pixel program): implemented in [`crate::pixel_array`].
//! - §5 (cautions): joints of one volume's polygons must not be counted twice. Here shadow
//!   polygons go through the same span setup as ordinary ones, whose top-left rule at pixel
//!   centres *is* a half-open convention: of two polygons sharing an edge exactly one takes a
//!   centre on it. The software form (a dummy check span per volume instead of EV) is
//!   [`ShadowForm::Check`].
//! - §6 (extensions): an area light is `k` point lights on a disc with a per-pixel counter
//!   (penumbra = count / k); several lights use a quantized normal class per pixel and a
//!   table indexed by (normal class, which lights shadow the pixel) giving the factor that
//!   multiplies the expanded intensity ([`FactorTable`]).
//!
//! **Volumes.** Each mesh that casts shadows is split into connected components. A closed
//! convex component gives one volume: its silhouette edges (one adjacent face toward the
//! light, one away) extruded to infinity (homogeneous w = 0), so no far cap is needed; the
//! near cap is the caster itself, which no view ray crosses in front of a visible point. A
//! component that is open or not convex (an L-shaped block) gives one volume per face
//! (light-facing faces of a closed component, all faces of an open one): the silhouette
//! extrusion of a non-convex solid can overlap itself (winding number 2), where parity would
//! be wrong, while a triangle's volume never does. FSF ORs the volumes.
//!
//! **Where counting starts: the near plane.** Span parity counts the shadow polygons a view
//! ray crosses between the near plane (nothing nearer is drawn) and the visible point, so
//! the flag a pixel needs at the start is whether its *near point* P (where its ray meets
//! the near plane) is inside the volume, not whether the eye is. Every volume is convex,
//! the intersection of half-spaces ([`Volume::planes`]): for one triangle, the planes
//! through the light and each edge and the triangle's plane; for a convex caster, the
//! planes through the light and each silhouette edge and the planes of its light-facing
//! faces (a point of the light's cone over the caster lies beyond the caster exactly when it
//! is behind every light-facing plane). The near plane's rectangle inside the guard band is
//! classified against them ([`NearPlane`]): wholly inside, the first span of every row is
//! IF (P inside for every pixel); wholly outside, nothing; cut, the *near cap* — the
//! cross-section near rectangle ∩ volume ∩ ray box, convex — is drawn as one more polygon
//! of the volume at the nearest depth, which toggles DSF on exactly the pixels whose P is
//! inside (it is in front of every visible surface).
//!
//! Why this is exact: for a pixel with visible point Q, `[Q inside] = [P inside] ⊕ (parity
//! of boundary crossings on PQ)`. The crossings with side polygons beyond the near plane are
//! the SP spans with `Z < ZB`; the other part of the boundary, the caster's light-facing
//! faces, is rendered geometry, so a view ray meets it only at or behind its visible point
//! and never counts it (a surface point takes the shadow of the space in front of it). The
//! cap must agree with the sides where they meet, on the line where the near plane cuts a
//! side: its edges there are the side polygon's near edge with *bit-identical* snapped end
//! points (the side polygons are clipped by [`Projector::clip_polygon`]'s planes with the
//! same arithmetic, tagging the vertices on the near plane; cap corners elsewhere come from
//! the float cross-section). With the top-left rule a pixel centre near that edge is then
//! taken by exactly one of the two polygons when they lie on opposite sides of it, by both
//! or neither when on the same side: its parity is that of its neighbours, no seam. The
//! cap's other edges lie on the guard band or the ray box (no visible pixel's P is there:
//! the segment from the eye to a visible point stays in the box) or on the caster's faces
//! cut by the near plane (an object edge in the image). Z-fail counting (crossings behind
//! Q) is not used: the per-pixel program only tests `Z < ZB`, and the far ends of the
//! extrusions are clipped by the far plane. [`Volume::eye_inside`] (the segment from the
//! eye to the light crosses the occluder) is kept for statistics only.

use crate::frontend::{class_normal, Projector, GUARD};
use crate::pixel_array::MORE_SHADE;
use crate::pixel_array::{Command, ProcState};
use crate::scene::LoadedScene;
use crate::setup::{SetupError, SnappedTri, TriSetup};
use glam::{DVec3, DVec4};
use pixelproc_formats::core_stream::shade_rgb;
use pixelproc_formats::{Attr, SpanWord, Z_FAR};
use rayon::prelude::*;
use std::collections::HashMap;
use thiserror::Error;

/// How a volume's end is marked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadowForm {
    /// Hardware form: the last span of a volume has attr EV (every processor checks DSF).
    #[default]
    Ev,
    /// Software form (§5): a dummy check span over the volume's span range instead of EV.
    Check,
}

/// Shadow errors.
#[derive(Debug, Error)]
pub enum ShadowError {
    /// A shadow polygon does not fit the fixed-point formats.
    #[error("shadow polygon: {0}")]
    Setup(#[from] SetupError),
    /// Unsupported light configuration.
    #[error("{0}")]
    Lights(String),
}

/// Largest number of shadowing point lights (bits of the per-pixel light mask).
pub const MAX_SHADOW_LIGHTS: usize = 8;

/// One light that casts shadows, with its point samples.
#[derive(Clone, Debug)]
pub struct ShadowLight {
    /// Index in the scene's lights.
    pub index: usize,
    /// Point lights sampling it (one for a point light).
    pub samples: Vec<DVec3>,
    /// Bit in the per-pixel light mask (point lights) or `None` (the area light's counter).
    pub bit: Option<u8>,
}

/// Area-light sample positions: `k` points on a disc of radius `r` centred at `c`, facing
/// `towards` (Vogel spiral, deterministic).
pub fn disc_samples(c: DVec3, r: f64, k: u32, towards: DVec3) -> Vec<DVec3> {
    let n = (towards - c).normalize_or(DVec3::NEG_Y);
    let a = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = n.cross(a).normalize();
    let v = n.cross(u);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..k)
        .map(|i| {
            let rad = r * ((i as f64 + 0.5) / k as f64).sqrt();
            let th = i as f64 * golden;
            c + u * (rad * th.cos()) + v * (rad * th.sin())
        })
        .collect()
}

/// The point samples of a scene light: its position for a point light; for an area light
/// (`radius > 0`) `samples` (default 8) points on a horizontal disc facing down (−y), so
/// they depend on the light alone.
pub fn light_samples(l: &crate::scene::Light) -> Vec<DVec3> {
    let p = DVec3::from(l.position);
    if l.radius > 0.0 {
        disc_samples(p, l.radius, l.samples.unwrap_or(8), p - DVec3::Y)
    } else {
        vec![p]
    }
}

/// Scene centre: the middle of all mesh vertices' bounding box.
pub fn scene_centre(ls: &LoadedScene) -> DVec3 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for m in &ls.meshes {
        for p in &m.positions {
            lo = lo.min(DVec3::from(*p));
            hi = hi.max(DVec3::from(*p));
        }
    }
    if lo.x.is_finite() {
        (lo + hi) * 0.5
    } else {
        DVec3::ZERO
    }
}

/// The shadowing lights of a scene for the given light indices: point lights get mask
/// bits; at most one area light (radius > 0) uses the per-pixel counter.
///
/// An area light's disc is horizontal, facing down (−y, like a ceiling panel): its samples
/// depend on the light alone, never on where the scene's geometry is.
pub fn shadow_lights(ls: &LoadedScene, which: &[usize]) -> Result<Vec<ShadowLight>, ShadowError> {
    let mut out = Vec::new();
    let (mut bits, mut areas) = (0u8, 0);
    for &i in which {
        let l = &ls.scene.lights[i];
        let p = DVec3::from(l.position);
        if l.radius > 0.0 {
            areas += 1;
            if areas > 1 {
                return Err(ShadowError::Lights(
                    "at most one area light may cast shadows (one per-pixel counter)".into(),
                ));
            }
            out.push(ShadowLight {
                index: i,
                samples: light_samples(l),
                bit: None,
            });
        } else {
            if bits as usize == MAX_SHADOW_LIGHTS {
                return Err(ShadowError::Lights(format!(
                    "at most {MAX_SHADOW_LIGHTS} point lights may cast shadows (the light mask is 8 bits)"
                )));
            }
            out.push(ShadowLight {
                index: i,
                samples: vec![p],
                bit: Some(bits),
            });
            bits += 1;
        }
    }
    Ok(out)
}

/// An occluder in world space: triangles and, per volume, the polygons to extrude.
#[derive(Clone, Debug)]
pub struct Occluder {
    /// Faces of the component (for the eye-inside test).
    pub faces: Vec<[DVec3; 3]>,
    /// Closed and convex: one silhouette volume; else one volume per face.
    pub convex_closed: bool,
    /// Closed (every edge shared by exactly two faces).
    pub closed: bool,
    /// Welded edges: vertex pairs and their adjacent faces.
    edges: Vec<([DVec3; 2], Vec<usize>)>,
}

/// Splits every shadow-casting mesh into connected components.
pub fn occluders(ls: &LoadedScene) -> Vec<Occluder> {
    let mut out = Vec::new();
    for (m, mr) in ls.meshes.iter().zip(&ls.scene.meshes) {
        if !mr.casts_shadows {
            continue;
        }
        let (pos, faces) = weld(m);
        let edge_faces = edge_faces(&faces);
        let comps = components(faces.len(), &edge_faces);
        // Each component's edges (those whose first face is in it), in one pass over the
        // edges rather than one per component.
        let mut comp_of = vec![0usize; faces.len()];
        for (c, fl) in comps.iter().enumerate() {
            for &f in fl {
                comp_of[f] = c;
            }
        }
        let mut comp_edges: Vec<Vec<&(usize, usize)>> = vec![Vec::new(); comps.len()];
        for (e, fs) in &edge_faces {
            comp_edges[comp_of[fs[0]]].push(e);
        }
        for (fl, keys) in comps.iter().zip(comp_edges) {
            out.push(occluder(&pos, &faces, &edge_faces, fl, keys));
        }
    }
    out
}

/// Welds a mesh's positions bit-exactly; drops faces that become degenerate.
fn weld(m: &crate::scene::LoadedMesh) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let mut ids: HashMap<[u64; 3], usize> = HashMap::new();
    let mut pos = Vec::new();
    let mut weld = |p: [f64; 3]| {
        *ids.entry(p.map(f64::to_bits)).or_insert_with(|| {
            pos.push(DVec3::from(p));
            pos.len() - 1
        })
    };
    let faces: Vec<[usize; 3]> = m
        .triangles
        .iter()
        .map(|t| t.map(|i| weld(m.positions[i as usize])))
        .filter(|f| f[0] != f[1] && f[1] != f[2] && f[0] != f[2])
        .collect();
    (pos, faces)
}

/// Faces adjacent to each undirected edge (vertex pair, smaller index first).
type EdgeFaces = HashMap<(usize, usize), Vec<usize>>;

fn edge_faces(faces: &[[usize; 3]]) -> EdgeFaces {
    let mut edge_faces: EdgeFaces = HashMap::new();
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            edge_faces.entry((a.min(b), a.max(b))).or_default().push(fi);
        }
    }
    edge_faces
}

/// Connected components of faces sharing an edge (union-find), ordered by their root.
fn components(n: usize, edge_faces: &EdgeFaces) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        let mut y = x;
        while p[y] != r {
            let n = p[y];
            p[y] = r;
            y = n;
        }
        r
    }
    for fs in edge_faces.values() {
        for w in fs.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            parent[a] = b;
        }
    }
    let mut comps: HashMap<usize, Vec<usize>> = HashMap::new();
    for fi in 0..n {
        let r = find(&mut parent, fi);
        comps.entry(r).or_default().push(fi);
    }
    let mut roots: Vec<usize> = comps.keys().copied().collect();
    roots.sort_unstable();
    roots
        .into_iter()
        .map(|r| comps.remove(&r).unwrap_or_default())
        .collect()
}

/// One component as an occluder: its faces, welded edges, closed and convex tests.
/// `keys` are the component's edges: those whose first face is in `fl`.
fn occluder(
    pos: &[DVec3],
    faces: &[[usize; 3]],
    edge_faces: &EdgeFaces,
    fl: &[usize],
    mut keys: Vec<&(usize, usize)>,
) -> Occluder {
    let local: HashMap<usize, usize> = fl.iter().enumerate().map(|(k, &f)| (f, k)).collect();
    let mut edges = Vec::new();
    let mut closed = true;
    keys.sort_unstable();
    for e in keys {
        let fs: Vec<usize> = edge_faces[e].iter().map(|f| local[f]).collect();
        closed &= fs.len() == 2;
        edges.push(([pos[e.0], pos[e.1]], fs));
    }
    let ftris: Vec<[DVec3; 3]> = fl.iter().map(|&f| faces[f].map(|i| pos[i])).collect();
    let convex = closed && is_convex(&ftris);
    Occluder {
        faces: ftris,
        convex_closed: convex,
        closed,
        edges,
    }
}

/// Every vertex lies on one side of every face's plane (within a relative 1e-9).
fn is_convex(ftris: &[[DVec3; 3]]) -> bool {
    let verts: Vec<DVec3> = ftris.iter().flatten().copied().collect();
    let scale = verts
        .iter()
        .fold(0.0f64, |s, v| s.max(v.abs().max_element()))
        .max(1.0);
    ftris.iter().all(|t| {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        let len = n.length();
        len > 0.0 && {
            let n = n / len;
            let side = |v: &DVec3| (*v - t[0]).dot(n);
            let eps = 1e-9 * scale;
            verts.iter().all(|v| side(v) <= eps) || verts.iter().all(|v| side(v) >= -eps)
        }
    })
}

fn facing(t: &[DVec3; 3], light: DVec3) -> f64 {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    n.dot(light - (t[0] + t[1] + t[2]) / 3.0)
}

/// Segment–triangle intersection (Möller–Trumbore), strictly inside `(0, 1)` of the segment.
fn segment_hits(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    let d = q - p;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let h = d.cross(e2);
    let a = e1.dot(h);
    if a.abs() < 1e-14 {
        return false;
    }
    let f = 1.0 / a;
    let s = p - t[0];
    let u = f * s.dot(h);
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = f * d.dot(qv);
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let tt = f * e2.dot(qv);
    tt > 1e-9 && tt < 1.0 - 1e-9
}

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
fn plane_towards(a: DVec3, b: DVec3, c: DVec3, inside: DVec3) -> Option<DVec4> {
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
fn convex_planes(o: &Occluder, light: DVec3, sil: &[[DVec3; 2]]) -> Vec<DVec4> {
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
fn triangle_planes(t: &[DVec3; 3], light: DVec3) -> Vec<DVec4> {
    let c = (t[0] + t[1] + t[2]) / 3.0;
    let mut planes: Vec<DVec4> = (0..3)
        .filter_map(|k| plane_towards(light, t[k], t[(k + 1) % 3], c))
        .collect();
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let n = if n.dot(light - t[0]) > 0.0 { -n } else { n };
    planes.push(n.extend(-n.dot(t[0])));
    planes
}

fn extrude(a: DVec3, b: DVec3, light: DVec3) -> Vec<DVec4> {
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

/// Clips a homogeneous world-space polygon to an axis-aligned box.
fn clip_to_box(poly: &[DVec4], lo: DVec3, hi: DVec3) -> Vec<DVec4> {
    let mut poly = poly.to_vec();
    for axis in 0..3 {
        for (bound, sign) in [(lo[axis], 1.0), (hi[axis], -1.0)] {
            if poly.is_empty() {
                return poly;
            }
            // Inside: sign·(x_axis − bound·w) ≥ 0.
            let d = |p: &DVec4| sign * (p[axis] - bound * p.w);
            let mut out = Vec::with_capacity(poly.len() + 1);
            for i in 0..poly.len() {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let (da, db) = (d(&a), d(&b));
                if da >= 0.0 {
                    out.push(a);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    let (p, q, dp, dq) = if da >= 0.0 {
                        (a, b, da, db)
                    } else {
                        (b, a, db, da)
                    };
                    out.push(p + (q - p) * (dp / (dp - dq)));
                }
            }
            poly = out;
        }
    }
    poly
}

/// Where the camera's near plane (its part inside the guard band) lies relative to a
/// volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NearPlane {
    /// Wholly outside the volume: counting starts at 0.
    Outside,
    /// Wholly inside: counting starts at 1 (the IF span).
    Inside,
    /// Cut by the volume's boundary: the near cap (the cross-section) is drawn at the
    /// nearest depth, so counting starts at 1 exactly on the pixels whose near point is
    /// inside.
    Cut,
}

/// Sutherland–Hodgman clipping of a polygon against half-spaces `h·(p, 1) ≥ 0`.
fn clip_planes(mut poly: Vec<DVec3>, planes: &[DVec4]) -> Vec<DVec3> {
    for h in planes {
        if poly.is_empty() {
            break;
        }
        let d = |p: &DVec3| h.truncate().dot(*p) + h.w;
        let mut out = Vec::with_capacity(poly.len() + 1);
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (da, db) = (d(&a), d(&b));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                out.push(a + (b - a) * (da / (da - db)));
            }
        }
        poly = out;
    }
    poly
}

/// The camera's clipping ([`Projector::clip_polygon`], the same planes in the same order
/// and the same arithmetic, so bit-identical vertices) that also tells which vertices lie
/// on the near plane: those the near plane created (or that lay on it), and those a later
/// plane created between two such.
fn clip_tagged(poly: Vec<DVec4>) -> Vec<(DVec4, bool)> {
    let planes: [fn(&DVec4) -> f64; 6] = [
        |p| p.z,
        |p| p.w - p.z,
        |p| GUARD * p.w - p.x,
        |p| GUARD * p.w + p.x,
        |p| GUARD * p.w - p.y,
        |p| GUARD * p.w + p.y,
    ];
    let mut poly: Vec<(DVec4, bool)> = poly.into_iter().map(|p| (p, p.z == 0.0)).collect();
    for (k, d) in planes.iter().enumerate() {
        if poly.is_empty() {
            break;
        }
        let mut out = Vec::with_capacity(poly.len() + 2);
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (da, db) = (d(&a.0), d(&b.0));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                out.push((a.0 + (b.0 - a.0) * t, k == 0 || (a.1 && b.1)));
            }
        }
        poly = out;
    }
    poly
}

/// Snapped screen position of a clip-space point, and its 24-bit depth.
fn snap_clip(pj: &Projector, p: DVec4) -> Result<([i32; 2], u32), SetupError> {
    let (x, y, z) = pj.to_screen(p);
    Ok((
        [crate::setup::snap_coord(x)?, crate::setup::snap_coord(y)?],
        crate::frontend::depth24(z),
    ))
}

/// Rasterizes a snapped polygon as a fan from its first vertex, pushing SP spans.
fn fan_spans(
    sv: &[([i32; 2], u32)],
    width: u32,
    height: u32,
    spans: &mut Vec<(u32, SpanWord)>,
) -> Result<(), SetupError> {
    for i in 1..sv.len().saturating_sub(1) {
        let t = SnappedTri {
            v: [sv[0].0, sv[i].0, sv[i + 1].0],
            z: [sv[0].1, sv[i].1, sv[i + 1].1],
            ..Default::default()
        };
        if let Some(s) = TriSetup::new(&t)? {
            s.for_each_span(width, height, |j, mut w| {
                w.attr = Attr::Sp;
                w.il = [0; 3];
                w.di = [0; 3];
                spans.push((j, w));
            });
        }
    }
    Ok(())
}

/// The near plane's rectangle inside the guard band, as world points.
fn near_rect(pj: &Projector) -> Vec<DVec3> {
    let inv = pj.view_proj.inverse();
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, y)| {
            let h = inv * DVec4::new(x * GUARD, y * GUARD, 0.0, 1.0);
            h.truncate() / h.w
        })
        .collect()
}

/// The box as six half-spaces `h·(p, 1) ≥ 0`.
fn box_planes(lo: DVec3, hi: DVec3) -> Vec<DVec4> {
    (0..3)
        .flat_map(|a| {
            let e = [DVec3::X, DVec3::Y, DVec3::Z][a];
            [e.extend(-lo[a]), (-e).extend(hi[a])]
        })
        .collect()
}

/// Classifies the near plane against a volume.
fn near_plane(pj: &Projector, v: &Volume) -> NearPlane {
    let rect = near_rect(pj);
    if v.planes.is_empty() {
        return NearPlane::Outside;
    }
    let inside = |p: &DVec3| v.planes.iter().all(|h| h.truncate().dot(*p) + h.w >= 0.0);
    if rect.iter().all(inside) {
        NearPlane::Inside
    } else if clip_planes(rect, &v.planes).len() < 3 {
        NearPlane::Outside
    } else {
        NearPlane::Cut
    }
}

/// The near cap of a volume the near plane cuts: the cross-section (near rectangle ∩
/// volume ∩ ray box, convex), as a snapped polygon whose edges along the volume's sides are
/// *bit-identical* to the near edges of the clipped side polygons (`near_edges`). Its
/// corners are the side polygons' near-edge end points plus the cross-section's other
/// corners (on the caster's faces, the guard band or the box) that are not within
/// `4/256` px of one of them, in angular order about the cross-section's centre.
fn near_cap(
    pj: &Projector,
    v: &Volume,
    bbox: (DVec3, DVec3),
    near_edges: &[[[i32; 2]; 2]],
) -> Result<Vec<[i32; 2]>, SetupError> {
    let mut planes = v.planes.clone();
    planes.extend(box_planes(bbox.0, bbox.1));
    let cs = clip_planes(near_rect(pj), &planes);
    if cs.len() < 3 {
        return Ok(Vec::new());
    }
    let one = pixelproc_formats::SUBPIXEL_ONE as f64;
    let screen: Vec<[f64; 2]> = cs
        .iter()
        .map(|p| {
            let (x, y, _) = pj.to_screen(pj.view_proj * p.extend(1.0));
            [x * one, y * one]
        })
        .collect();
    let mut pts: Vec<[i32; 2]> = near_edges.iter().flatten().copied().collect();
    pts.sort_unstable();
    pts.dedup();
    let exact = pts.len();
    for q in &screen {
        let near_one = pts[..exact].iter().any(|p| {
            let (dx, dy) = (p[0] as f64 - q[0], p[1] as f64 - q[1]);
            dx * dx + dy * dy <= 16.0
        });
        if !near_one {
            let (x, y) = (q[0] / one, q[1] / one);
            pts.push([crate::setup::snap_coord(x)?, crate::setup::snap_coord(y)?]);
        }
    }
    let n = screen.len() as f64;
    let c = screen
        .iter()
        .fold([0.0, 0.0], |s, q| [s[0] + q[0] / n, s[1] + q[1] / n]);
    let angle = |p: &[i32; 2]| (p[1] as f64 - c[1]).atan2(p[0] as f64 - c[0]);
    pts.sort_by(|a, b| angle(a).total_cmp(&angle(b)).then(a.cmp(b)));
    pts.dedup();
    Ok(pts)
}

/// Projects a volume's polygons (clip to the ray box, then the view frustum; snap) and
/// returns its span words per row, in polygon order, each with attr SP, then those of its
/// near cap when the near plane cuts it; and where the near plane lies.
fn volume_spans(
    pj: &Projector,
    v: &Volume,
    bbox: (DVec3, DVec3),
    width: u32,
    height: u32,
) -> Result<(Vec<(u32, SpanWord)>, NearPlane), SetupError> {
    let mut spans = Vec::new();
    let mut near_edges = Vec::new();
    for poly in &v.polys {
        let poly = clip_to_box(poly, bbox.0, bbox.1);
        if poly.len() < 3 {
            continue;
        }
        let cv: Vec<DVec4> = poly.iter().map(|p| pj.view_proj * *p).collect();
        let clipped = clip_tagged(cv);
        if clipped.len() < 3 || clipped.iter().any(|c| c.0.w <= 0.0) {
            continue;
        }
        let sv: Vec<([i32; 2], u32)> = clipped
            .iter()
            .map(|c| snap_clip(pj, c.0))
            .collect::<Result<_, _>>()?;
        if !clipped.iter().all(|c| c.1) {
            for i in 0..clipped.len() {
                let k = (i + 1) % clipped.len();
                if clipped[i].1 && clipped[k].1 && sv[i].0 != sv[k].0 {
                    near_edges.push([sv[i].0, sv[k].0]);
                }
            }
        }
        fan_spans(&sv, width, height, &mut spans)?;
    }
    let near = near_plane(pj, v);
    if near == NearPlane::Cut {
        let cap = near_cap(pj, v, bbox, &near_edges)?;
        let zn = crate::frontend::depth24(0.0);
        let sv: Vec<([i32; 2], u32)> = cap.into_iter().map(|p| (p, zn)).collect();
        fan_spans(&sv, width, height, &mut spans)?;
    }
    spans.sort_by_key(|(j, _)| *j);
    Ok((spans, near))
}

/// Statistics of the shadow stage.
#[derive(Clone, Debug, Default)]
pub struct ShadowStats {
    /// Shadow volumes over all light samples.
    pub volumes: usize,
    /// Shadow span words (SP/EV/IF, including empty IF/EV words).
    pub span_words: u64,
    /// Volumes containing the eye.
    pub eye_inside: usize,
    /// Volumes whose boundary cuts the near plane (drawn with a near cap).
    pub near_caps: usize,
}

/// Per-row shadow commands for the array, appended after the OP spans of each row.
pub struct ShadowCommands {
    /// Commands of row j.
    pub rows: Vec<Vec<Command>>,
    /// Statistics.
    pub stats: ShadowStats,
}

/// Builds the shadow commands of all shadowing lights: per light sample, `ClearFlags`, the
/// volumes' spans (first IF when the eye is inside, last EV or a `Check`), then
/// `LatchShadow` (point light) or `AccumulateShadow` (area-light sample).
pub fn shadow_commands(
    ls: &LoadedScene,
    pj: &Projector,
    lights: &[ShadowLight],
    form: ShadowForm,
) -> Result<ShadowCommands, ShadowError> {
    let (w, h) = (ls.scene.width, ls.scene.height);
    let occ = occluders(ls);
    let bbox = ray_box(ls, pj.eye);
    let mut rows: Vec<Vec<Command>> = vec![Vec::new(); h as usize];
    let mut stats = ShadowStats::default();
    for l in lights {
        for &s in &l.samples {
            for r in rows.iter_mut() {
                r.push(Command::ClearFlags);
            }
            let vols = volumes(&occ, s, pj.eye);
            stats.volumes += vols.len();
            stats.eye_inside += vols.iter().filter(|v| v.eye_inside).count();
            let per_vol: Vec<(Vec<(u32, SpanWord)>, NearPlane)> = vols
                .par_iter()
                .map(|v| volume_spans(pj, v, bbox, w, h))
                .collect::<Result<_, _>>()?;
            for (spans, near) in per_vol {
                let inside = near == NearPlane::Inside;
                stats.near_caps += (near == NearPlane::Cut) as usize;
                let mut k = 0;
                for j in 0..h {
                    let start = k;
                    while k < spans.len() && spans[k].0 == j {
                        k += 1;
                    }
                    let row = &spans[start..k];
                    if row.is_empty() && !inside {
                        continue;
                    }
                    let out = &mut rows[j as usize];
                    let before = out.len();
                    emit_volume_row(out, row.iter().map(|x| x.1), inside, form, w);
                    stats.span_words += (out.len() - before) as u64;
                }
            }
            let end = match l.bit {
                Some(bit) => Command::LatchShadow { bit },
                None => Command::AccumulateShadow,
            };
            for r in rows.iter_mut() {
                r.push(end);
            }
        }
    }
    Ok(ShadowCommands { rows, stats })
}

/// Appends one volume's commands for one row.
fn emit_volume_row(
    out: &mut Vec<Command>,
    spans: impl Iterator<Item = SpanWord>,
    eye_inside: bool,
    form: ShadowForm,
    width: u32,
) {
    let empty = SpanWord {
        xl: 1,
        xr: 0,
        ..Default::default()
    };
    let start = out.len();
    let (mut lo, mut hi) = (u16::MAX, 0u16);
    for s in spans {
        lo = lo.min(s.xl);
        hi = hi.max(s.xr);
        out.push(Command::Span(s));
    }
    if eye_inside {
        match out.get_mut(start) {
            Some(Command::Span(s)) => s.attr = Attr::If,
            _ => out.push(Command::Span(SpanWord {
                attr: Attr::If,
                ..empty
            })),
        }
    }
    match form {
        ShadowForm::Ev => {
            let n = out.len() - start;
            let last_is_plain =
                n > 0 && matches!(out.last(), Some(Command::Span(s)) if s.attr == Attr::Sp);
            if last_is_plain {
                if let Some(Command::Span(s)) = out.last_mut() {
                    s.attr = Attr::Ev;
                }
            } else {
                out.push(Command::Span(SpanWord {
                    attr: Attr::Ev,
                    ..empty
                }));
            }
        }
        ShadowForm::Check => {
            // With IF every pixel's DSF may change, so the whole line is checked.
            let (xl, xr) = if eye_inside || lo > hi {
                (0, width as u16 - 1)
            } else {
                (lo, hi)
            };
            out.push(Command::Check { xl, xr });
        }
    }
}

/// How a shadowed pixel is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Shading {
    /// Exact (the default): each polygon's spans carry, per shadowing light, its
    /// intensity without that light (span words with `chan ≥ 1`, shade registers per
    /// processor), and the readout removes the shadowed share of each light's difference.
    /// Depends on nothing but the pixel's own surface and lights.
    #[default]
    Exact,
    /// The seed's §6 table: the summed intensity times a factor indexed by (normal class,
    /// light mask, counter), computed with one direction per light from the scene centre.
    Table,
}

/// Attenuation table of seed 001 §6, indexed by (normal class, light mask, area count):
/// `F = (a + Σ_l w(c,l)·(1 − s_l)) / (a + Σ_l w(c,l))`, with `w(c,l) = I_l·max(0, n_c·d_l)`,
/// `d_l` the direction from the scene centre to light l (the distant-light assumption),
/// `s_l` = 1 if light l's mask bit is set (point light) or `count/k` (the area light), and
/// `a` the ambient level. Entries are Q0.8 (256 = 1), computed once per frame like a ROM.
///
/// In [`Shading::Exact`] the same table holds `F = 256` and, in its drop column, the
/// shadowed share `s_0` of the first shadowing light in Q0.8 (`G`); the readout then
/// computes `c − Σ_l ((max(0, c − sh_l)·G_l + 128) >> 8)` over the pixel's shade
/// registers `sh_l` (the intensity without light `l`), see
/// [`pixelproc_formats::core_stream::shade_rgb`].
#[derive(Clone, Debug)]
pub struct FactorTable {
    bits: u32,
    counts: u32,
    entries: Vec<u16>,
    drops: Vec<u16>,
    /// Per shade channel, the light's mask bit (`None`: the area light's counter).
    channels: Vec<Option<u8>>,
    /// Number of samples of the area light (0 if none).
    pub area_samples: u32,
    /// Number of point lights with mask bits.
    pub point_lights: u32,
    /// The shading mode the table implements.
    pub shading: Shading,
}

impl FactorTable {
    /// The table of `shading` for the scene's shadowing lights (in channel order).
    pub fn for_mode(ls: &LoadedScene, lights: &[ShadowLight], shading: Shading) -> FactorTable {
        match shading {
            Shading::Table => FactorTable::new(ls, lights),
            Shading::Exact => FactorTable::exact(lights),
        }
    }

    /// Shape of the table for `lights`: mask bits, counter values, area samples.
    fn shape(lights: &[ShadowLight]) -> (u32, u32, u32) {
        let bits = lights.iter().filter(|l| l.bit.is_some()).count() as u32;
        let area = lights.iter().find(|l| l.bit.is_none());
        let k = area.map(|l| l.samples.len() as u32).unwrap_or(0);
        (bits, k + 1, k)
    }

    /// The exact-shading table: `F = 256`, `G` = shadowed share of channel 1's light.
    pub fn exact(lights: &[ShadowLight]) -> FactorTable {
        let (bits, counts, k) = FactorTable::shape(lights);
        let n = 256 * (1usize << bits) * counts as usize;
        let channels: Vec<Option<u8>> = lights.iter().map(|l| l.bit).collect();
        let mut drops = vec![0u16; n];
        for (i, d) in drops.iter_mut().enumerate() {
            let cnt = (i % counts as usize) as u8;
            let mask = ((i / counts as usize) & ((1 << bits) - 1)) as u8;
            if let Some(&first) = channels.first() {
                *d = share(first, mask, cnt, k);
            }
        }
        FactorTable {
            bits,
            counts,
            entries: vec![256; n],
            drops,
            channels,
            area_samples: k,
            point_lights: bits,
            shading: Shading::Exact,
        }
    }

    /// Builds the seed's table (§6) for the scene's lights.
    pub fn new(ls: &LoadedScene, lights: &[ShadowLight]) -> FactorTable {
        let centre = scene_centre(ls);
        let (bits, counts, k) = FactorTable::shape(lights);
        let dir =
            |i: usize| (DVec3::from(ls.scene.lights[i].position) - centre).normalize_or(DVec3::Y);
        let mut entries = vec![0u16; 256 * (1usize << bits) * counts as usize];
        for c in 0..256usize {
            let n = class_normal(c as u8);
            let w = |i: usize| ls.scene.lights[i].intensity * n.dot(dir(i)).max(0.0);
            let total: f64 = ls.scene.ambient
                + ls.scene
                    .lights
                    .iter()
                    .enumerate()
                    .map(|(i, _)| w(i))
                    .sum::<f64>();
            for mask in 0..(1usize << bits) {
                for cnt in 0..counts {
                    let mut lit = total;
                    for l in lights {
                        let s = match l.bit {
                            Some(b) => ((mask >> b) & 1) as f64,
                            None => cnt as f64 / k as f64,
                        };
                        lit -= w(l.index) * s;
                    }
                    let f = if total > 0.0 {
                        (lit / total).clamp(0.0, 1.0)
                    } else {
                        1.0
                    };
                    entries[(c << bits | mask) * counts as usize + cnt as usize] =
                        (f * 256.0).round() as u16;
                }
            }
        }
        let n = entries.len();
        FactorTable {
            bits,
            counts,
            entries,
            drops: vec![0; n],
            channels: Vec::new(),
            area_samples: k,
            point_lights: bits,
            shading: Shading::Table,
        }
    }

    fn index(&self, s: &ProcState) -> usize {
        let mask = (s.mask as usize) & ((1 << self.bits) - 1);
        let cnt = (s.count as usize).min(self.counts as usize - 1);
        ((s.nclass as usize) << self.bits | mask) * self.counts as usize + cnt
    }

    /// The factor (Q0.8, 256 = 1) for a pixel's state.
    pub fn factor(&self, s: &ProcState) -> u16 {
        self.entries[self.index(s)]
    }

    /// The drop weight of shade register 1 (Q0.8) for a pixel's state (0 in table mode).
    pub fn drop_weight(&self, s: &ProcState) -> u16 {
        self.drops[self.index(s)]
    }

    /// Number of shade channels the exact mode uses (0 in table mode).
    pub fn channels(&self) -> usize {
        self.channels.len()
    }

    /// Light-mask bits the table is indexed by (one per shadowing point light).
    pub fn mask_bits(&self) -> u32 {
        self.bits
    }

    /// Counter values the table is indexed by (`area_samples + 1`).
    pub fn counts(&self) -> u32 {
        self.counts
    }

    /// Every entry as `(nclass, mask, count, factor, drop)`: what a hardware table holds.
    pub fn entries(&self) -> impl Iterator<Item = (u8, u8, u8, u16, u16)> + '_ {
        let (bits, counts) = (self.bits, self.counts as usize);
        self.entries
            .iter()
            .zip(&self.drops)
            .enumerate()
            .map(move |(i, (&f, &g))| {
                let cnt = i % counts;
                let rest = i / counts;
                let mask = rest & ((1 << bits) - 1);
                ((rest >> bits) as u8, mask as u8, cnt as u8, f, g)
            })
    }

    /// Shadowed fraction of the pixel's lights, 0..=255, for the shadow AOV.
    pub fn shadow_level(&self, s: &ProcState) -> u8 {
        let n = self.point_lights + (self.area_samples > 0) as u32;
        if n == 0 {
            return 0;
        }
        let pts = (s.mask as u32 & ((1 << self.bits) - 1)).count_ones() as f64;
        let area = if self.area_samples > 0 {
            s.count as f64 / self.area_samples as f64
        } else {
            0.0
        };
        (((pts + area) / n as f64) * 255.0).round() as u8
    }

    /// The shaded colour of one covered pixel of intensity `rgb` (RGB888) with state `s`
    /// and shade registers 2.. `more` (empty if unused).
    pub fn shade_pixel(&self, rgb: u32, s: &ProcState, more: &[u32]) -> u32 {
        if self.channels.len() <= 1 {
            return shade_rgb(rgb, s.sh, self.factor(s) as u32, self.drop_weight(s) as u32);
        }
        let c = pixelproc_formats::unpack_rgb(rgb);
        let mut out = c.map(|v| v as u32);
        for (l, &bit) in self.channels.iter().enumerate() {
            let g = share(bit, s.mask, s.count, self.area_samples) as u32;
            let sh = if l == 0 {
                s.sh
            } else {
                more.get(l - 1).copied().unwrap_or(0)
            };
            let sv = pixelproc_formats::unpack_rgb(sh);
            for k in 0..3 {
                let d = (c[k] as u32).saturating_sub(sv[k] as u32);
                out[k] = out[k].saturating_sub((d * g + 128) >> 8);
            }
        }
        pixelproc_formats::pack_rgb(out.map(|v| v as u8))
    }
}

/// The shadowed share of one light, Q0.8: 256 if a point light's mask bit is set,
/// `round(256·count/k)` for the area light (`bit = None`) of `k` samples.
fn share(bit: Option<u8>, mask: u8, count: u8, k: u32) -> u16 {
    match bit {
        Some(b) => ((mask >> b) & 1) as u16 * 256,
        None if k > 0 => ((256 * count.min(k as u8) as u32 + k / 2) / k) as u16,
        None => 0,
    }
}

/// "Correct the intensity and store it in the frame buffer" (§2): every covered pixel's
/// colour becomes [`FactorTable::shade_pixel`] of it (table mode: `(c·F + 128) >> 8`).
pub fn shade(frame: &mut crate::render::Frame, table: &FactorTable) {
    let stride = if frame.more.is_empty() { 0 } else { MORE_SHADE };
    let more = &frame.more;
    frame.px.par_iter_mut().enumerate().for_each(|(i, s)| {
        if s.zb == Z_FAR {
            return;
        }
        let m = &more[i * stride..(i + 1) * stride];
        s.rgb = table.shade_pixel(s.rgb, s, m);
    });
}

/// Applies each pixel centre's shadow shading to an anti-aliased RGB8 image (the shadow
/// flags and shade registers are those of the surface visible at the pixel centre; an
/// approximation at shadow and object edges, documented in `docs/shadows.md`).
pub fn apply_to_rgb8(rgb: &mut [u8], frame: &crate::render::Frame, table: &FactorTable) {
    let stride = if frame.more.is_empty() { 0 } else { MORE_SHADE };
    rgb.par_chunks_mut(3)
        .zip(frame.px.par_iter())
        .enumerate()
        .for_each(|(i, (c, s))| {
            if s.zb == Z_FAR {
                return;
            }
            let m = &frame.more[i * stride..(i + 1) * stride];
            let out = table.shade_pixel(pixelproc_formats::pack_rgb([c[0], c[1], c[2]]), s, m);
            c.copy_from_slice(&pixelproc_formats::unpack_rgb(out));
        });
}
