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
use crate::pixel_array::{BandFlags, Command, ProcState};
use crate::scene::LoadedScene;
use crate::setup::{SetupError, SnappedTri};
use glam::{DVec3, DVec4};
use pixelproc_formats::core_stream::shade_rgb;
use pixelproc_formats::{Attr, SpanWord, Z_FAR};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use thiserror::Error;

mod near;
mod occluder;
mod shading;
mod volume;

pub use near::NearPlane;
use near::*;
use occluder::*;
pub use occluder::{occluders, Occluder};
pub use shading::{apply_to_rgb8, shade_row, FactorTable, Shading};
use volume::*;
pub use volume::{ray_box, volumes, Volume};

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
    /// Under anti-aliasing: array frames rendered at the method's sample lattices for
    /// its shadows (0 when the method takes the array's one sample per pixel).
    pub sample_passes: usize,
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
    shadow_commands_of(&occluders(ls), ls, pj, lights, form)
}

/// [`shadow_commands`] with the scene's occluders already found ([`occluders`]: they do
/// not depend on the light or the camera, so one list serves every light and every
/// sample lattice of a frame).
pub fn shadow_commands_of(
    occ: &[Occluder],
    ls: &LoadedScene,
    pj: &Projector,
    lights: &[ShadowLight],
    form: ShadowForm,
) -> Result<ShadowCommands, ShadowError> {
    let setup = ShadowRows::new(occ, ls, pj, lights, form)?;
    Ok(setup.commands())
}

/// Rows per band: a band's rows are made by one walk over the volumes that reach it.
const BAND: usize = 16;

/// One light sample's volumes, set up.
struct SampleVolumes {
    /// Per volume: its triangles and where the near plane lies.
    per_vol: Vec<(VolumeTris, NearPlane)>,
    /// The rows a volume may emit on: those its triangles may cover, or every row when
    /// the near plane is inside it (its IF span comes even without spans).
    reach: Vec<Option<(u32, u32)>>,
    /// The control that ends the sample's commands on every row.
    end: Command,
    /// Per row: an upper bound on the sample's commands
    /// ([`ShadowRows::sample_rows_at_once`]).
    row_bound: Vec<u64>,
}

/// The most commands (by [`SampleVolumes::row_bound`]) made at once for one light sample
/// when they are stored ([`ShadowRows::commands`]): 2^20 commands of 56 bytes, 59 MB per
/// band being made.
const BAND_BUDGET: u64 = 1 << 20;

/// Some lights' shadow volumes, set up (clipped, snapped, their triangles set up). The
/// renderer applies them to a band of rows' flags as it draws the band, a light sample at
/// a time ([`ShadowRows::sample_flags`]), with the result of the commands of
/// [`shadow_commands_of`], which are made only when asked for ([`ShadowRows::commands`],
/// a band of rows and a light sample at a time). Per light sample and row: `ClearFlags`,
/// the volumes' spans in volume order (first IF when the near plane is inside the volume,
/// last EV or a `Check`), then `LatchShadow` (point light) or `AccumulateShadow`
/// (area-light sample).
pub struct ShadowRows {
    samples: Vec<SampleVolumes>,
    form: ShadowForm,
    width: u32,
    height: u32,
    /// Statistics of the set-up (`span_words` is counted in `words` as rows are made).
    stats: ShadowStats,
    /// Shadow span words made so far.
    words: AtomicU64,
    /// The most commands made at once for one light sample ([`BAND_BUDGET`]).
    budget: u64,
}

impl ShadowRows {
    /// Sets up the volumes of `lights`' samples cast by `occ`, seen through `pj`.
    pub fn new(
        occ: &[Occluder],
        ls: &LoadedScene,
        pj: &Projector,
        lights: &[ShadowLight],
        form: ShadowForm,
    ) -> Result<ShadowRows, ShadowError> {
        let (width, height) = pj.raster_size();
        let bbox = ray_box(ls, pj.eye);
        let mut stats = ShadowStats::default();
        let mut samples = Vec::new();
        for l in lights {
            for &s in &l.samples {
                let vols = volumes(occ, s, pj.eye);
                stats.volumes += vols.len();
                stats.eye_inside += vols.iter().filter(|v| v.eye_inside).count();
                let per_vol: Vec<(VolumeTris, NearPlane)> = vols
                    .par_iter()
                    .map_init(near::ClipBuffers::default, |buf, v| {
                        volume_tris(pj, v, bbox, buf)
                    })
                    .collect::<Result<_, _>>()?;
                stats.near_caps += per_vol
                    .iter()
                    .filter(|(_, near)| *near == NearPlane::Cut)
                    .count();
                let reach: Vec<Option<(u32, u32)>> = per_vol
                    .iter()
                    .map(|(tris, near)| match near {
                        NearPlane::Inside => Some((0, u32::MAX)),
                        _ => tris.rows(height),
                    })
                    .collect();
                let end = match l.bit {
                    Some(bit) => Command::LatchShadow { bit },
                    None => Command::AccumulateShadow,
                };
                // On each row: `ClearFlags` and the end control, at most one word per
                // triangle whose rows include it, and one more per volume that reaches it
                // (a `Check`, or an EV added), two with the near plane inside (an IF too).
                let mut steps = vec![0i64; height as usize + 1];
                steps[0] += 2;
                for ((tris, near), reach) in per_vol.iter().zip(&reach) {
                    tris.count_rows(&mut steps);
                    if let Some((a, z)) = *reach {
                        let extra = 1 + (*near == NearPlane::Inside) as i64;
                        steps[a as usize] += extra;
                        steps[z.min(height - 1) as usize + 1] -= extra;
                    }
                }
                let row_bound = steps[..height as usize]
                    .iter()
                    .scan(0i64, |sum, d| {
                        *sum += d;
                        Some(*sum as u64)
                    })
                    .collect();
                samples.push(SampleVolumes {
                    per_vol,
                    reach,
                    end,
                    row_bound,
                });
            }
        }
        Ok(ShadowRows {
            samples,
            form,
            width,
            height,
            stats,
            words: AtomicU64::new(0),
            budget: BAND_BUDGET,
        })
    }

    /// Puts `more`'s commands after this set-up's on every row (one more light).
    pub fn append(&mut self, more: ShadowRows) {
        assert_eq!(
            (self.width, self.height, self.form),
            (more.width, more.height, more.form),
            "shadow set-ups of different frames"
        );
        self.stats.volumes += more.stats.volumes;
        self.stats.eye_inside += more.stats.eye_inside;
        self.stats.near_caps += more.stats.near_caps;
        *self.words.get_mut() += more.words.into_inner();
        self.samples.extend(more.samples);
    }

    /// Rows of the frame.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Statistics, with the shadow span words made so far.
    pub fn stats(&self) -> ShadowStats {
        ShadowStats {
            span_words: self.words.load(Ordering::Relaxed),
            ..self.stats.clone()
        }
    }

    /// Light samples (one per point light, one per sample of an area light), in the
    /// order their commands come on every row.
    pub fn samples(&self) -> usize {
        self.samples.len()
    }

    /// How many rows from `j0` on (at least 1, at most `max`) to make light sample `k`'s
    /// commands for at once ([`ShadowRows::sample_rows`]): as many as keep them within
    /// about 59 MB, by an upper bound counted at set-up (on each row: two controls, at
    /// most one word per triangle whose rows include the row, and one more per volume
    /// that reaches it, two with the near plane inside). The benchmark's one-light 1080p
    /// scenes take whole bands of 16 rows on all but a few of their busiest rows.
    fn sample_rows_at_once(&self, k: usize, j0: u32, max: usize) -> usize {
        let mut sum = 0;
        let fit = self.samples[k].row_bound[j0 as usize..]
            .iter()
            .take(max)
            .take_while(|&&b| {
                sum += b;
                sum <= self.budget
            })
            .count();
        fit.clamp(1, max.max(1))
    }

    /// Sets the most commands made at once for one light sample (the tests' way to make
    /// a band's rows a few at a time).
    #[cfg(test)]
    pub(crate) fn set_budget(&mut self, budget: u64) {
        self.budget = budget;
    }

    /// Light sample `k`'s commands on rows `j0 .. j0 + made.len()`, made at once into
    /// `made` (one list per row, cleared first; their allocations are reused):
    /// `ClearFlags`, the words of each volume that reaches the rows
    /// (`VolumeTris::band_words`), each row's ended (`end_volume_row`), in volume
    /// order as a pass over all volumes row by row would append them (a volume with no
    /// span on a row, and the near plane outside it, adds nothing to it), then the
    /// sample's end control. A row's commands are its samples' in sample order; samples
    /// are independent (each starts by clearing the flags, and every volume ends with an
    /// EV or a `Check`), so they can be applied one after the other. Walking a volume's
    /// triangles once for all the rows, each through its rows, reads each triangle's
    /// set-up once instead of once per row.
    fn sample_rows(&self, k: usize, j0: u32, made: &mut [Vec<Command>]) {
        let j1 = j0 + made.len() as u32 - 1;
        assert!(
            !made.is_empty() && j1 < self.height,
            "rows {j0}..={j1} of {}",
            self.height
        );
        let s = &self.samples[k];
        let (form, width) = (self.form, self.width);
        // Per row: where the current volume's commands start, and its words' columns.
        let mut open = vec![(0usize, u16::MAX, 0u16); made.len()];
        let mut words = 0;
        for out in made.iter_mut() {
            out.clear();
            out.push(Command::ClearFlags);
        }
        for ((tris, near), reach) in s.per_vol.iter().zip(&s.reach) {
            if !reach.is_some_and(|(a, z)| a <= j1 && z >= j0) {
                continue;
            }
            for (o, out) in open.iter_mut().zip(made.iter()) {
                *o = (out.len(), u16::MAX, 0);
            }
            // The volume's SP words go straight into the rows' commands; their column
            // range is kept for a `Check`.
            tris.band_words(j0 as i64, j1 as i64, width, &mut |j, w: SpanWord| {
                let r = (j - j0 as i64) as usize;
                let o = &mut open[r];
                (o.1, o.2) = (o.1.min(w.xl), o.2.max(w.xr));
                made[r].push(Command::Span(w));
            });
            let inside = *near == NearPlane::Inside;
            for (out, &(start, lo, hi)) in made.iter_mut().zip(&open) {
                if out.len() == start && !inside {
                    continue;
                }
                end_volume_row(out, start, (lo, hi), inside, form, width);
                words += (out.len() - start) as u64;
            }
        }
        made.iter_mut().for_each(|out| out.push(s.end));
        self.words.fetch_add(words, Ordering::Relaxed);
    }

    /// Light sample `k`'s commands on the rows of `band` (whole rows from row `j0`),
    /// applied as [`crate::pixel_array::RowFlags::run`] applies those
    /// [`ShadowRows::commands`] stores (`ClearFlags`, each volume's words and end, the
    /// sample's end control), without making them: each volume's SP words toggle `flags`
    /// as they are stepped, then each row the volume reaches is ended ([`BandFlags`] says
    /// why that is the same). `flags` holds the band's ZB ([`BandFlags::load`]); the flags
    /// are left in it, for [`BandFlags::store`] after the last sample. Counts the same
    /// shadow span words.
    /// A triangle that lies behind ZB on all the band's rows and columns it may reach is
    /// not stepped for its words, only counted ([`BandFlags::count_behind`]).
    pub fn sample_flags(&self, k: usize, j0: u32, band: &mut [ProcState], flags: &mut BandFlags) {
        self.sample_flags_with(k, j0, band, flags, true);
    }

    /// [`ShadowRows::sample_flags`], with triangles behind ZB only counted if `cull`;
    /// tells how many triangles (once per band) were.
    fn sample_flags_with(
        &self,
        k: usize,
        j0: u32,
        band: &mut [ProcState],
        flags: &mut BandFlags,
        cull: bool,
    ) -> u64 {
        let n = flags.rows();
        let j1 = j0 + n as u32 - 1;
        assert!(
            n > 0 && band.len() == n * self.width as usize && j1 < self.height,
            "rows {j0}..={j1} of {}",
            self.height
        );
        let s = &self.samples[k];
        let mut words = 0;
        let mut behind = 0;
        flags.clear();
        for ((tris, near), reach) in s.per_vol.iter().zip(&s.reach) {
            if !reach.is_some_and(|(a, z)| a <= j1 && z >= j0) {
                continue;
            }
            tris.band_words(
                j0 as i64,
                j1 as i64,
                self.width,
                &mut FlagSink {
                    flags: &mut *flags,
                    j0: j0 as i64,
                    cull,
                    behind: &mut behind,
                },
            );
            let inside = *near == NearPlane::Inside;
            for r in 0..n {
                let made = flags.end_volume(r, inside);
                words += ended_len(made, inside, self.form);
            }
        }
        flags.latch(&s.end, band);
        self.words.fetch_add(words, Ordering::Relaxed);
        behind
    }

    /// Every row's commands, stored.
    pub fn commands(&self) -> ShadowCommands {
        let mut rows: Vec<Vec<Command>> = vec![Vec::new(); self.height as usize];
        rows.par_chunks_mut(BAND).enumerate().for_each(|(b, band)| {
            let j0 = (b * BAND) as u32;
            let mut made = Vec::new();
            for k in 0..self.samples.len() {
                let mut r = 0;
                while r < band.len() {
                    let m = self.sample_rows_at_once(k, j0 + r as u32, band.len() - r);
                    made.resize_with(m.max(made.len()), Vec::new);
                    self.sample_rows(k, j0 + r as u32, &mut made[..m]);
                    for (row, more) in band[r..r + m].iter_mut().zip(&made) {
                        row.extend_from_slice(more);
                    }
                    r += m;
                }
            }
        });
        ShadowCommands {
            rows,
            stats: self.stats(),
        }
    }
}

/// [`ShadowRows::sample_flags`]'s words, applied to a band's flags as they are made;
/// a triangle behind the band's greatest ZB on its columns is only counted.
struct FlagSink<'a> {
    flags: &'a mut BandFlags,
    /// The band's first row.
    j0: i64,
    /// Whether a triangle behind ZB is only counted.
    cull: bool,
    /// The triangles found behind ZB.
    behind: &'a mut u64,
}

impl WordSink for FlagSink<'_> {
    #[inline]
    fn word(&mut self, j: i64, w: SpanWord) {
        self.flags.toggle((j - self.j0) as usize, &w)
    }

    #[inline]
    fn is_behind(&mut self, lo: usize, hi: usize, depth: i64) -> bool {
        let behind = self.cull && self.flags.behind(lo, hi, depth);
        *self.behind += behind as u64;
        behind
    }

    #[inline]
    fn behind(&mut self, j: i64) {
        self.flags.count_behind((j - self.j0) as usize)
    }
}

/// How many commands [`end_volume_row`] leaves for a volume's row of `made` SP words
/// (none when there are none and the near plane is outside): the words, an empty IF when
/// there are none and the near plane is inside, and an empty EV unless the last word (not
/// made IF) can become EV, or the `Check`.
fn ended_len(made: u32, inside: bool, form: ShadowForm) -> u64 {
    if made == 0 && !inside {
        return 0;
    }
    let empty_if = (inside && made == 0) as u64;
    let end = match form {
        // The last word stays SP (and becomes EV) unless it is the only one and IF.
        ShadowForm::Ev => !(made > 1 || (made == 1 && !inside)) as u64,
        ShadowForm::Check => 1,
    };
    made as u64 + empty_if + end
}

/// Ends one volume's commands for one row, whose SP words are `out[start..]` (columns
/// `lo..=hi` between them, `lo > hi` if none): the first word made IF (or an empty IF
/// added) when the near point lies inside the volume, then the last word made EV (or an
/// empty EV added), or a `Check` of the words' range (of the line with IF).
fn end_volume_row(
    out: &mut Vec<Command>,
    start: usize,
    (lo, hi): (u16, u16),
    eye_inside: bool,
    form: ShadowForm,
    width: u32,
) {
    let empty = SpanWord {
        xl: 1,
        xr: 0,
        ..Default::default()
    };
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

/// Adds two shadowing lights beside the scene's first, a point light and an area light
/// of three samples (the tests' scenes with several light samples).
#[cfg(test)]
pub(crate) fn add_test_lights(ls: &mut LoadedScene) {
    let p0 = ls.scene.lights[0].position;
    for (dx, radius) in [(-3.0, 0.0), (2.0, 0.8)] {
        ls.scene.lights.push(crate::scene::Light {
            position: [p0[0] + dx, p0[1], p0[2] + 1.0],
            intensity: 0.5,
            shadows: true,
            radius,
            samples: Some(3),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Triangles found behind ZB and only counted leave every processor (flags,
    /// counter, light mask) and the count of shadow span words as stepping their words
    /// leaves them: the box city and the default scene, each with two more lights (one
    /// an area light), both forms, bands of 16 and of 5 rows, over the ZB its polygons
    /// leave; and in the city some triangles are found behind.
    #[test]
    fn triangles_behind_zb_counted_leave_what_their_words_leave() {
        use crate::frontend::Projector;
        use crate::render::render_frame;
        use crate::scene::load_builtin;
        use crate::stream::SceneStream;
        let cases = [
            ("boxes", ShadowForm::Ev),
            ("boxes", ShadowForm::Check),
            ("default", ShadowForm::Ev),
        ];
        for (scene, form) in cases {
            let mut ls = load_builtin(scene).unwrap();
            let (w, h) = (192, 108);
            (ls.scene.width, ls.scene.height) = (w as u32, h as u32);
            add_test_lights(&mut ls);
            let which: Vec<usize> = (0..ls.scene.lights.len()).collect();
            let s = SceneStream::of_scene(&ls, &which, form, Shading::Exact).unwrap();
            let frame = render_frame(&s.spans, s.bg, 16, &[]);
            let (pj, occ) = (Projector::new(&ls), occluders(&ls));
            let lights = shadow_lights(&ls, &which).unwrap();
            let rows = ShadowRows::new(&occ, &ls, &pj, &lights, form).unwrap();
            let (mut behind, mut words) = (0, 0);
            for band in [16, 5] {
                for j0 in (0..h).step_by(band) {
                    let n = band.min(h - j0);
                    let mut culled = frame.px[j0 * w..(j0 + n) * w].to_vec();
                    let mut stepped = culled.clone();
                    let (mut fc, mut fs) = (BandFlags::default(), BandFlags::default());
                    fc.load(&culled, w);
                    fs.load(&stepped, w);
                    let before = rows.stats().span_words;
                    for k in 0..rows.samples() {
                        behind += rows.sample_flags_with(k, j0 as u32, &mut culled, &mut fc, true);
                    }
                    let mid = rows.stats().span_words;
                    for k in 0..rows.samples() {
                        rows.sample_flags_with(k, j0 as u32, &mut stepped, &mut fs, false);
                    }
                    let after = rows.stats().span_words;
                    fc.store(&mut culled);
                    fs.store(&mut stepped);
                    assert!(
                        culled == stepped,
                        "{scene} {form:?}: band of {band} from {j0}"
                    );
                    assert_eq!(
                        mid - before,
                        after - mid,
                        "{scene} {form:?}: rows {j0}..+{n}"
                    );
                    words += mid - before;
                }
            }
            assert!(
                scene != "boxes" || behind > 100,
                "{scene} {form:?}: {behind} triangles behind, {words} words"
            );
            assert!(frame.px.iter().all(|p| !p.dsf && !p.fsf));
        }
    }

    /// [`ended_len`] is the length of what [`end_volume_row`] leaves of a volume's row
    /// (nothing for a row without words outside the volume, which
    /// [`ShadowRows::sample_rows`] skips): zero to five words, the near plane inside the
    /// volume or not, both forms.
    #[test]
    fn ended_len_counts_the_ended_rows_commands() {
        for form in [ShadowForm::Ev, ShadowForm::Check] {
            for inside in [false, true] {
                for made in 0..6u16 {
                    let mut out = vec![Command::ClearFlags];
                    out.extend((0..made).map(|k| {
                        Command::Span(SpanWord {
                            attr: Attr::Sp,
                            xl: 3 * k,
                            xr: 3 * k + 2,
                            ..Default::default()
                        })
                    }));
                    let want = if made == 0 && !inside {
                        0
                    } else {
                        let cols = if made == 0 { (1, 0) } else { (0, 3 * made - 1) };
                        end_volume_row(&mut out, 1, cols, inside, form, 64);
                        out.len() - 1
                    };
                    let got = ended_len(made as u32, inside, form);
                    assert_eq!(got, want as u64, "{form:?}, inside {inside}, {made} words");
                }
            }
        }
    }
}
