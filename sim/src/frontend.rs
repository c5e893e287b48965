//! Front end (floating point): camera, lighting, clipping, projection, and the one
//! snapping step into fixed point.
//!
//! Everything here is `f64` (glam); its output is [`SnappedTri`]s, after which the model is
//! integer only. 3-D scenes: world → clip space by `perspective_rh` (depth 0..1) and
//! `look_at_rh`, Sutherland–Hodgman clipping in homogeneous space against the near and
//! far planes and a guard band of ±[`GUARD`]·w in x and y (so every snapped coordinate
//! fits the Q.8 range), perspective divide, viewport (`x_s = (x/w + 1)/2·W`,
//! `y_s = (1 − y/w)/2·H`, y down), depth `z24 = Z_GEOM_MIN + round(z/w·(Z_GEOM_MAX −
//! Z_GEOM_MIN))`. Screen-space z, being planar per triangle and mapped affinely, stays
//! planar; so does perspective `z/w` over a planar face.

use crate::scene::{LoadedScene, SceneError};
use crate::setup::{snap_coord, snap_intensity, HostPlane, SetupError, SnappedTri};
use glam::{DMat4, DVec3, DVec4};
use pixelproc_formats::{Z_GEOM_MAX, Z_GEOM_MIN};
use rayon::prelude::*;
use smallvec::SmallVec;
use thiserror::Error;

/// Guard band in units of w: clip-space |x|, |y| ≤ GUARD·w.
pub const GUARD: f64 = 2.0;

/// Front-end errors.
#[derive(Debug, Error)]
pub enum FrontError {
    /// Invalid scene content.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A triangle does not fit the fixed-point formats.
    #[error("triangle {index}")]
    Setup {
        /// Index of the scene triangle.
        index: usize,
        /// Cause.
        source: SetupError,
    },
}

/// Where a snapped triangle came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Screen-space triangle `k` of the scene.
    Screen(usize),
    /// Face `face` of mesh `mesh`.
    Mesh {
        /// Mesh index.
        mesh: usize,
        /// Triangle index within the mesh.
        face: usize,
    },
    /// Pattern `k`.
    Pattern(usize),
}

/// The front end's output: snapped triangles in draw order, with their origin.
#[derive(Clone, Debug, Default)]
pub struct Projected {
    /// Snapped triangles, in scene order.
    pub tris: Vec<SnappedTri>,
    /// Origin of each triangle.
    pub origin: Vec<Origin>,
    /// Exact shading: for each triangle `i`, its copies `shade[i·K + c]` (`K` =
    /// [`Projected::channels`]) with the intensities the lighting model gives without
    /// shadowing light `c` (`chan = c + 1`). Empty without exact shading.
    pub shade: Vec<SnappedTri>,
    /// Number of shade channels `K` (the shadowing lights' count in exact shading, else 0).
    pub channels: usize,
    /// Triangles dropped because they were entirely clipped away.
    pub clipped_away: usize,
}

/// Camera transform and viewport: world points to screen pixels and 24-bit depth.
#[derive(Clone, Copy, Debug)]
pub struct Projector {
    /// World → clip matrix.
    pub view_proj: DMat4,
    /// Eye position, world space.
    pub eye: DVec3,
    /// Screen width.
    pub width: f64,
    /// Screen height.
    pub height: f64,
    /// The sample grid the raster's pixel centres stand for (the screen's own pixel
    /// centres unless [`Projector::for_grid`] moved them).
    pub grid: SampleGrid,
}

/// Where the raster's pixel centres sample the screen: raster pixel `(a, b)`'s centre is
/// the screen point `(x0 + a·step_x, y0 + b·step_y)` (pixels), and the raster is
/// `cols × rows`. An anti-aliasing method's sample lattice (e.g. one of `k × k`
/// sub-pixel offsets) becomes an ordinary raster this way: the array renders it as a
/// frame, shadows included. Applied before snapping, like the viewport.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleGrid {
    /// Screen x of raster column 0's centre, pixels.
    pub x0: f64,
    /// Screen y of raster row 0's centre, pixels.
    pub y0: f64,
    /// Screen pixels between raster columns.
    pub step_x: f64,
    /// Screen pixels between raster rows.
    pub step_y: f64,
    /// Raster columns.
    pub cols: u32,
    /// Raster rows.
    pub rows: u32,
}

impl SampleGrid {
    /// The screen's own pixel centres: `(i + ½, j + ½)`, `width × height`.
    pub fn pixels(width: u32, height: u32) -> SampleGrid {
        SampleGrid {
            x0: 0.5,
            y0: 0.5,
            step_x: 1.0,
            step_y: 1.0,
            cols: width,
            rows: height,
        }
    }

    /// Whether this is the screen's own pixel grid.
    fn is_identity(&self) -> bool {
        self.x0 == 0.5 && self.y0 == 0.5 && self.step_x == 1.0 && self.step_y == 1.0
    }
}

/// A clip-space vertex with attributes carried through clipping.
#[derive(Clone, Copy, Debug)]
pub struct ClipVert {
    /// Clip-space position.
    pub p: DVec4,
    /// Attributes (intensity RGB, 0..1).
    pub a: DVec3,
}

/// The clip planes of [`Projector::clip_polygon`] (near, far, the guard band), as
/// functions `d(p)` of a clip-space point, `d(p) ≥ 0` inside.
const CLIP_PLANES: [fn(&DVec4) -> f64; 6] = [
    |p| p.z,
    |p| p.w - p.z,
    |p| GUARD * p.w - p.x,
    |p| GUARD * p.w + p.x,
    |p| GUARD * p.w - p.y,
    |p| GUARD * p.w + p.y,
];

/// Whether [`Projector::clip_polygon`] keeps a polygon with every vertex at `p` as it is:
/// each vertex inside every plane, by the same test (false for a NaN).
fn unclipped<'a>(p: impl IntoIterator<Item = &'a DVec4>) -> bool {
    p.into_iter()
        .all(|p| CLIP_PLANES.iter().all(|d| d(p) >= 0.0))
}

impl Projector {
    /// Builds the projector of a 3-D scene.
    pub fn new(ls: &LoadedScene) -> Projector {
        let s = &ls.scene;
        let cam = s.camera.as_ref().expect("3-D scene");
        let eye = DVec3::from(cam.eye);
        let near = cam.near.unwrap_or(0.1);
        let far = cam.far.unwrap_or_else(|| {
            let mut d: f64 = 1.0;
            for m in &ls.meshes {
                for p in &m.positions {
                    d = d.max((DVec3::from(*p) - eye).length());
                }
            }
            (d * 1.05 + 1.0).max(near * 2.0)
        });
        let aspect = s.width as f64 / s.height as f64;
        let proj = DMat4::perspective_rh(cam.fov_y_deg.to_radians(), aspect, near, far);
        let view = DMat4::look_at_rh(eye, DVec3::from(cam.target), DVec3::from(cam.up));
        Projector {
            view_proj: proj * view,
            eye,
            width: s.width as f64,
            height: s.height as f64,
            grid: SampleGrid::pixels(s.width, s.height),
        }
    }

    /// The same camera rendering the sample grid `g` instead of the pixel centres.
    pub fn for_grid(&self, g: SampleGrid) -> Projector {
        Projector { grid: g, ..*self }
    }

    /// Raster size, `(cols, rows)`.
    pub fn raster_size(&self) -> (u32, u32) {
        (self.grid.cols, self.grid.rows)
    }

    /// World point to clip space.
    pub fn clip(&self, p: DVec3) -> DVec4 {
        self.view_proj * p.extend(1.0)
    }

    /// Clips a convex polygon against near, far and the guard band.
    pub fn clip_polygon(&self, poly: Vec<ClipVert>) -> Vec<ClipVert> {
        if unclipped(poly.iter().map(|v| &v.p)) {
            // Each pass below would keep the polygon as it is, vertex for vertex.
            return poly;
        }
        let mut poly = poly;
        for d in CLIP_PLANES {
            if poly.is_empty() {
                break;
            }
            let mut out = Vec::with_capacity(poly.len() + 2);
            for i in 0..poly.len() {
                let a = poly[i];
                let b = poly[(i + 1) % poly.len()];
                let (da, db) = (d(&a.p), d(&b.p));
                if da >= 0.0 {
                    out.push(a);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    let t = da / (da - db);
                    out.push(ClipVert {
                        p: a.p + (b.p - a.p) * t,
                        a: a.a + (b.a - a.a) * t,
                    });
                }
            }
            poly = out;
        }
        poly
    }

    /// Raster position (pixels, y down; the screen's pixels unless a [`SampleGrid`] is set)
    /// and depth in 0..1 of a clipped vertex.
    pub fn to_screen(&self, p: DVec4) -> (f64, f64, f64) {
        let (x, y, z) = (p.x / p.w, p.y / p.w, p.z / p.w);
        let (sx, sy) = ((x + 1.0) * 0.5 * self.width, (1.0 - y) * 0.5 * self.height);
        let g = &self.grid;
        if g.is_identity() {
            return (sx, sy, z.clamp(0.0, 1.0));
        }
        (
            (sx - g.x0) / g.step_x + 0.5,
            (sy - g.y0) / g.step_y + 0.5,
            z.clamp(0.0, 1.0),
        )
    }
}

/// Maps a depth in 0..1 to the 24-bit geometry range.
pub fn depth24(z01: f64) -> u32 {
    Z_GEOM_MIN + (z01.clamp(0.0, 1.0) * (Z_GEOM_MAX - Z_GEOM_MIN) as f64).round() as u32
}

/// Screen-space and snapped vertex of a triangle corner.
fn snap_vertex(x: f64, y: f64) -> Result<[i32; 2], SetupError> {
    Ok([snap_coord(x)?, snap_coord(y)?])
}

/// Lambert shading of a surface point (linear RGB, unclamped above by the sum of lights,
/// then clamped to 1): `colour · (ambient + Σ intensity_l · max(0, n·l̂))`.
pub fn lambert(ls: &LoadedScene, p: DVec3, n: DVec3, colour: [f64; 3]) -> DVec3 {
    lambert_without(ls, p, n, colour, None)
}

/// [`lambert`] with light `skip`'s term left out (the intensity in that light's shadow).
pub fn lambert_without(
    ls: &LoadedScene,
    p: DVec3,
    n: DVec3,
    colour: [f64; 3],
    skip: Option<usize>,
) -> DVec3 {
    let mut k = ls.scene.ambient;
    for (i, l) in ls.scene.lights.iter().enumerate() {
        if Some(i) == skip {
            continue;
        }
        let d = (DVec3::from(l.position) - p).normalize_or_zero();
        k += l.intensity * n.dot(d).max(0.0);
    }
    (DVec3::from(colour) * k).min(DVec3::ONE)
}

/// Runs the front end on a loaded scene.
pub fn project(ls: &LoadedScene) -> Result<Projected, FrontError> {
    project_shaded(ls, &[])
}

fn project_3d(ls: &LoadedScene, channels: &[usize]) -> Result<Projected, FrontError> {
    project_3d_with(ls, &Projector::new(ls), channels)
}

/// Runs the front end with exact-shading channels: for each triangle, one copy per light
/// in `channels` (scene light indices, in channel order) lit without that light.
pub fn project_shaded(ls: &LoadedScene, channels: &[usize]) -> Result<Projected, FrontError> {
    if ls.is_3d() {
        project_3d(ls, channels)
    } else {
        project_screen(ls)
    }
}

impl Projected {
    /// The triangles the pixel-processor array draws: each triangle followed by its
    /// shade-channel copies (the same as [`Projected::tris`] without exact shading).
    pub fn array_tris(&self) -> std::borrow::Cow<'_, [SnappedTri]> {
        if self.channels == 0 {
            return std::borrow::Cow::Borrowed(&self.tris);
        }
        let k = self.channels;
        let mut out = Vec::with_capacity(self.tris.len() * (k + 1));
        for (i, t) in self.tris.iter().enumerate() {
            out.push(*t);
            out.extend_from_slice(&self.shade[i * k..(i + 1) * k]);
        }
        std::borrow::Cow::Owned(out)
    }
}

fn project_screen(ls: &LoadedScene) -> Result<Projected, FrontError> {
    let s = &ls.scene;
    let (zmin, zmax) = match s.depth_range {
        Some([a, b]) => (a, b),
        None => {
            let zs = s.triangles.iter().flat_map(|t| t.v.iter().map(|p| p[2]));
            let lo = zs.clone().fold(f64::INFINITY, f64::min);
            let hi = zs.fold(f64::NEG_INFINITY, f64::max);
            if lo.is_finite() && hi > lo {
                (lo, hi)
            } else {
                (lo - 1.0, lo + 1.0)
            }
        }
    };
    let z24 = |k: usize, z: f64| -> Result<u32, FrontError> {
        if z < zmin || z > zmax {
            return Err(FrontError::Scene(SceneError::Invalid(format!(
                "triangle {k}: z = {z} is outside depth_range [{zmin}, {zmax}]"
            ))));
        }
        Ok(depth24((z - zmin) / (zmax - zmin)))
    };
    let mut out = Projected::default();
    let mut snapped_pos = Vec::with_capacity(s.triangles.len());
    for (k, t) in s.triangles.iter().enumerate() {
        let mut v = [[0i32; 2]; 3];
        let mut z = [0u32; 3];
        for i in 0..3 {
            v[i] = snap_vertex(t.v[i][0], t.v[i][1]).map_err(|e| FrontError::Setup {
                index: k,
                source: e,
            })?;
            z[i] = z24(k, t.v[i][2])?;
        }
        snapped_pos.push((v, z));
    }
    for (k, t) in s.triangles.iter().enumerate() {
        let (v, z) = snapped_pos[k];
        let cols = t.colors.unwrap_or([t.color; 3]);
        let c = cols.map(|c| c.map(snap_intensity));
        let host = t.pattern_on.map(|h| HostPlane {
            v: snapped_pos[h].0,
            z: snapped_pos[h].1,
        });
        let tag = t.tag.unwrap_or(((k + 1) % 65536) as u16);
        out.tris.push(SnappedTri {
            chan: 0,
            v,
            z,
            c,
            tag,
            host,
            nclass: 0,
        });
        out.origin.push(Origin::Screen(k));
    }
    Ok(out)
}

/// A triangle in world space with per-vertex shading, before projection.
struct WorldTri {
    p: [DVec3; 3],
    a: [DVec3; 3],
}

/// A world triangle's snapped pieces: one where it is not clipped, without allocating.
type Pieces = SmallVec<[SnappedTri; 1]>;

/// Clips, projects and snaps a world triangle into zero or more snapped triangles
/// (a fan of the clipped polygon), and says whether it was [`unclipped`] (then its one
/// piece is its three corners, in order).
fn emit(
    pj: &Projector,
    wt: &WorldTri,
    tag: u16,
    host: Option<HostPlane>,
    nclass: u8,
) -> Result<(Pieces, bool), SetupError> {
    let corners = [0, 1, 2].map(|i| ClipVert {
        p: pj.clip(wt.p[i]),
        a: wt.a[i],
    });
    let snap = |cv: &ClipVert| -> Result<_, SetupError> {
        let (x, y, z) = pj.to_screen(cv.p);
        let c = [cv.a.x, cv.a.y, cv.a.z].map(snap_intensity);
        Ok((snap_vertex(x, y)?, depth24(z), c))
    };
    let piece = |a: ([i32; 2], u32, [u32; 3]),
                 b: ([i32; 2], u32, [u32; 3]),
                 c: ([i32; 2], u32, [u32; 3])| {
        SnappedTri {
            chan: 0,
            v: [a.0, b.0, c.0],
            z: [a.1, b.1, c.1],
            c: [a.2, b.2, c.2],
            tag,
            host,
            nclass,
        }
    };
    if unclipped(corners.iter().map(|c| &c.p)) {
        // What `clip_polygon` returns for it: the triangle as it is.
        let [a, b, c] = [snap(&corners[0])?, snap(&corners[1])?, snap(&corners[2])?];
        return Ok((smallvec::smallvec![piece(a, b, c)], true));
    }
    let poly = pj.clip_polygon(corners.to_vec());
    let mut out = Pieces::new();
    if poly.len() < 3 {
        return Ok((out, false));
    }
    let sv = poly.iter().map(snap).collect::<Result<Vec<_>, _>>()?;
    for i in 1..sv.len() - 1 {
        out.push(piece(sv[0], sv[i], sv[i + 1]));
    }
    Ok((out, false))
}

/// [`project_shaded`] of a 3-D scene through the projector `pj` (e.g. one rendering an
/// anti-aliasing method's sample grid, [`Projector::for_grid`]).
pub fn project_3d_with(
    ls: &LoadedScene,
    pj: &Projector,
    channels: &[usize],
) -> Result<Projected, FrontError> {
    let mut out = Projected {
        channels: channels.len(),
        ..Default::default()
    };
    let first_piece = project_meshes(ls, pj, channels, &mut out)?;
    for k in 0..ls.scene.patterns.len() {
        project_pattern(ls, pj, k, &first_piece, channels, &mut out)?;
    }
    Ok(out)
}

/// What a world triangle's snapped pieces carry besides geometry and intensity.
struct Face {
    tag: u16,
    host: Option<HostPlane>,
    nclass: u8,
    origin: Origin,
}

/// A world triangle's snapped pieces, and per piece its shade-channel copies.
struct ShadedFace {
    /// The pieces, in fan order.
    tris: Pieces,
    /// Piece `i`'s copies are `copies[i·K .. (i + 1)·K]` (`K` shade channels, `chan` set).
    copies: Pieces,
}

/// World triangle `p` lit by `shade(vertex, None)` and, per shade channel, its copy lit by
/// `shade(vertex, Some(light))` (without that light), clipped and snapped.
fn shade_face(
    pj: &Projector,
    p: [DVec3; 3],
    shade: impl Fn(usize, Option<usize>) -> DVec3,
    channels: &[usize],
    f: &Face,
) -> Result<ShadedFace, SetupError> {
    let lit = |skip: Option<usize>| WorldTri {
        p,
        a: [0, 1, 2].map(|k| shade(k, skip)),
    };
    let (tris, whole) = emit(pj, &lit(None), f.tag, f.host, f.nclass)?;
    if !channels.is_empty() && whole {
        // Not clipped: `emit` snaps the three vertices as they are, in order, into one
        // triangle, so a copy's geometry is the polygon's and only its intensities
        // (snapped the same way) differ.
        let copies = (1..)
            .zip(channels)
            .map(|(c, &l)| SnappedTri {
                c: [0, 1, 2].map(|k| {
                    let a = shade(k, Some(l));
                    [a.x, a.y, a.z].map(snap_intensity)
                }),
                chan: c,
                ..tris[0]
            })
            .collect();
        return Ok(ShadedFace { tris, copies });
    }
    shade_face_clipped(pj, p, &shade, channels, f, tris)
}

/// [`shade_face`] by clipping and snapping each copy on its own: `tris` are the pieces of
/// `p` lit by `shade(vertex, None)`.
fn shade_face_clipped(
    pj: &Projector,
    p: [DVec3; 3],
    shade: &impl Fn(usize, Option<usize>) -> DVec3,
    channels: &[usize],
    f: &Face,
    tris: Pieces,
) -> Result<ShadedFace, SetupError> {
    let lit = |skip: Option<usize>| WorldTri {
        p,
        a: [0, 1, 2].map(|k| shade(k, skip)),
    };
    let mut per_chan = Vec::with_capacity(channels.len());
    for &l in channels {
        let (ct, _) = emit(pj, &lit(Some(l)), f.tag, f.host, f.nclass)?;
        debug_assert_eq!(ct.len(), tris.len());
        per_chan.push(ct);
    }
    let mut copies = Pieces::with_capacity(tris.len() * channels.len());
    for (i, st) in tris.iter().enumerate() {
        for (c, ct) in per_chan.iter().enumerate() {
            let mut t = ct[i];
            // The same clipped and snapped geometry as the polygon (the clip depends on
            // positions only); only the intensities differ.
            debug_assert_eq!((t.v, t.z), (st.v, st.z));
            t.chan = c as u8 + 1;
            copies.push(t);
        }
    }
    Ok(ShadedFace { tris, copies })
}

/// Appends a face's pieces (from [`shade_face`], or its error: the error's index is that of
/// the face's first piece in `out`) to `out`; returns its first piece's plane.
fn append_face(
    out: &mut Projected,
    face: Result<ShadedFace, SetupError>,
    origin: Origin,
) -> Result<Option<HostPlane>, FrontError> {
    let face = face.map_err(|e| FrontError::Setup {
        index: out.tris.len(),
        source: e,
    })?;
    out.origin
        .extend(std::iter::repeat_n(origin, face.tris.len()));
    out.tris.extend_from_slice(&face.tris);
    out.shade.extend_from_slice(&face.copies);
    Ok(face.tris.first().map(|t| HostPlane { v: t.v, z: t.z }))
}

/// The first snapped piece of each face of each mesh (a pattern on the face takes its
/// depth plane), `None` where the face was clipped away.
type FacePlanes = Vec<Vec<Option<HostPlane>>>;

/// Lights, clips and snaps every mesh face into `out`. Faces are independent, so they are
/// done in parallel, then appended in mesh and face order: the same output, and the same
/// error (the first failing face's, with its index), as one face after another.
fn project_meshes(
    ls: &LoadedScene,
    pj: &Projector,
    channels: &[usize],
    out: &mut Projected,
) -> Result<FacePlanes, FrontError> {
    let meshes = ls.meshes.len().min(ls.scene.meshes.len());
    let faces: Vec<(usize, usize)> = (0..meshes)
        .flat_map(|mi| (0..ls.meshes[mi].triangles.len()).map(move |fi| (mi, fi)))
        .collect();
    let done: Vec<(Result<ShadedFace, SetupError>, Origin)> = faces
        .par_iter()
        .map(|&(mi, fi)| {
            let (m, mr) = (&ls.meshes[mi], &ls.scene.meshes[mi]);
            let t = m.triangles[fi];
            let p = t.map(|i| DVec3::from(m.positions[i as usize]));
            let fnorm = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let n = |k: usize| match &m.normals {
                Some(ns) => DVec3::from(ns[t[k] as usize]).normalize_or_zero(),
                None => fnorm,
            };
            let shade = |k: usize, skip| lambert_without(ls, p[k], n(k), mr.color, skip);
            let face = Face {
                tag: mr.tag.unwrap_or((mi + 1) as u16),
                host: None,
                nclass: normal_class(fnorm),
                origin: Origin::Mesh { mesh: mi, face: fi },
            };
            (shade_face(pj, p, shade, channels, &face), face.origin)
        })
        .collect();
    let mut first_piece: FacePlanes = ls.meshes[..meshes]
        .iter()
        .map(|m| Vec::with_capacity(m.triangles.len()))
        .collect();
    for (&(mi, _), (face, origin)) in faces.iter().zip(done) {
        let first = append_face(out, face, origin)?;
        if first.is_none() {
            out.clipped_away += 1;
        }
        first_piece[mi].push(first);
    }
    Ok(first_piece)
}

/// Pattern `k`, cut along its mesh's coplanar faces; each piece takes the depth plane of
/// the face it lies on, so it ties exactly with that face's spans.
fn project_pattern(
    ls: &LoadedScene,
    pj: &Projector,
    k: usize,
    first_piece: &FacePlanes,
    channels: &[usize],
    out: &mut Projected,
) -> Result<(), FrontError> {
    let pat = &ls.scene.patterns[k];
    let m = &ls.meshes[pat.on_mesh];
    let poly: Vec<DVec3> = pat.polygon.iter().map(|p| DVec3::from(*p)).collect();
    let mut placed = false;
    for (fi, t) in m.triangles.iter().enumerate() {
        let p = t.map(|i| DVec3::from(m.positions[i as usize]));
        let Some((piece, n)) = pattern_on_face(&poly, &p) else {
            continue;
        };
        placed = true;
        let Some(hp) = first_piece[pat.on_mesh][fi] else {
            continue;
        };
        for i in 1..piece.len() - 1 {
            let tri = [piece[0], piece[i], piece[i + 1]];
            let shade = |i: usize, skip| lambert_without(ls, tri[i], n, pat.color, skip);
            let face = Face {
                tag: 0x8000 | k as u16,
                host: Some(hp),
                nclass: normal_class(n),
                origin: Origin::Pattern(k),
            };
            append_face(
                out,
                shade_face(pj, tri, shade, channels, &face),
                face.origin,
            )?;
        }
    }
    if !placed {
        return Err(FrontError::Scene(SceneError::Invalid(format!(
            "pattern {k}: it lies on no face of mesh {} (it must be coplanar with a face)",
            pat.on_mesh
        ))));
    }
    Ok(())
}

/// The part of a coplanar polygon inside face `p`, with the face's unit normal; `None`
/// when the polygon is not in the face's plane or misses it.
fn pattern_on_face(poly: &[DVec3], p: &[DVec3; 3]) -> Option<(Vec<DVec3>, DVec3)> {
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let len = n.length();
    if len == 0.0 {
        return None;
    }
    let n = n / len;
    let scale = (p[1] - p[0]).length().max((p[2] - p[0]).length()).max(1.0);
    if !poly
        .iter()
        .all(|q| (*q - p[0]).dot(n).abs() <= 1e-6 * scale)
    {
        return None;
    }
    let mut piece = poly.to_vec();
    for i in 0..3 {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        let inward = n.cross(b - a);
        piece = clip_halfspace(&piece, |q| (q - a).dot(inward));
    }
    (piece.len() >= 3).then_some((piece, n))
}

/// Clips a planar polygon to the half-space `d(q) ≥ 0`.
fn clip_halfspace(poly: &[DVec3], d: impl Fn(DVec3) -> f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (da, db) = (d(a), d(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}

/// Side of the octahedral grid of normal classes: 16 × 16 = 256 classes (an 8-bit `nclass`).
pub const NCLASS_GRID: u32 = 16;

/// Quantizes a unit normal to one of 256 classes (octahedral map, 16 × 16 cells): the
/// "coarsely quantized normal class" of seed 001 §6.
pub fn normal_class(n: DVec3) -> u8 {
    let n = n.normalize_or_zero();
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if l1 == 0.0 {
        return 0;
    }
    let (mut u, mut v) = (n.x / l1, n.z / l1);
    if n.y < 0.0 {
        let (ou, ov) = (u, v);
        u = (1.0 - ov.abs()) * ou.signum();
        v = (1.0 - ou.abs()) * ov.signum();
    }
    let g = NCLASS_GRID as f64;
    let cell = |t: f64| (((t + 1.0) * 0.5 * g).floor() as i64).clamp(0, g as i64 - 1) as u32;
    (cell(v) * NCLASS_GRID + cell(u)) as u8
}

/// The unit normal at the centre of class `c` (inverse of [`normal_class`]).
pub fn class_normal(c: u8) -> DVec3 {
    let g = NCLASS_GRID as f64;
    let (cu, cv) = (
        (c as u32 % NCLASS_GRID) as f64,
        (c as u32 / NCLASS_GRID) as f64,
    );
    let (u, v) = ((cu + 0.5) / g * 2.0 - 1.0, (cv + 0.5) / g * 2.0 - 1.0);
    let y = 1.0 - u.abs() - v.abs();
    let (x, z) = if y < 0.0 {
        ((1.0 - v.abs()) * u.signum(), (1.0 - u.abs()) * v.signum())
    } else {
        (u, v)
    };
    DVec3::new(x, y, z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unclipped shortcut of [`shade_face`] gives the copies that clipping and
    /// snapping each one gives, for triangles inside the view, cut by the near plane or
    /// the guard band, and behind the eye.
    #[test]
    fn unclipped_copies_equal_clipped_ones() {
        let ls = crate::scene::load_builtin("default").unwrap();
        let pj = Projector::new(&ls);
        let mut rng = crate::rng::Lcg64(0x00c0_b1e5);
        let (mut fast, mut cut) = (0, 0);
        for i in 0..3_000 {
            let mut r = |s: f64| ((rng.step() >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * s;
            let scale = [2.0, 20.0, 200.0][i % 3];
            let c = DVec3::new(r(scale), r(scale), r(scale));
            let p = [0; 3].map(|_| c + DVec3::new(r(scale), r(scale), r(scale)));
            let seed = rng.step();
            let shade = |k: usize, skip: Option<usize>| {
                let h = seed ^ (k as u64 * 0x9e37) ^ skip.map_or(7, |l| l as u64 * 131);
                DVec3::new(
                    (h % 1000) as f64 / 999.0,
                    (h / 1000 % 1000) as f64 / 999.0,
                    (h / 1_000_000 % 1000) as f64 / 999.0,
                )
            };
            let f = Face {
                tag: i as u16,
                host: None,
                nclass: 3,
                origin: Origin::Pattern(0),
            };
            let channels = [[0].as_slice(), &[1, 0], &[2, 0, 1]][i % 3];
            let Ok(got) = shade_face(&pj, p, shade, channels, &f) else {
                continue;
            };
            let lit = WorldTri {
                p,
                a: [0, 1, 2].map(|k| shade(k, None)),
            };
            let (tris, _) = emit(&pj, &lit, f.tag, f.host, f.nclass).unwrap();
            let want = shade_face_clipped(&pj, p, &shade, channels, &f, tris).unwrap();
            assert_eq!(got.tris, want.tris, "case {i}");
            assert_eq!(got.copies, want.copies, "case {i}");
            if unclipped(&p.map(|x| pj.clip(x))) {
                fast += 1;
            } else if !want.tris.is_empty() {
                cut += 1;
            }
        }
        assert!(fast > 300 && cut > 300, "{fast} unclipped, {cut} clipped");
    }
}
