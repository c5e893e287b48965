//! Where counting starts: the near plane against each volume (inside, outside, cut), the
//! near cap of a cut volume, and a volume's span words per row.

use super::*;
use crate::raster::PlaneStepper;
use crate::setup::ShadowTri;

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
pub(super) fn clip_planes(mut poly: Vec<DVec3>, planes: &[DVec4]) -> Vec<DVec3> {
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
/// plane created between two such. Into `out` (`tmp` is a second buffer; both are reused).
pub(super) fn clip_tagged(
    poly: &[DVec4],
    out: &mut Vec<(DVec4, bool)>,
    tmp: &mut Vec<(DVec4, bool)>,
) {
    let planes: [fn(&DVec4) -> f64; 6] = [
        |p| p.z,
        |p| p.w - p.z,
        |p| GUARD * p.w - p.x,
        |p| GUARD * p.w + p.x,
        |p| GUARD * p.w - p.y,
        |p| GUARD * p.w + p.y,
    ];
    out.clear();
    out.extend(poly.iter().map(|&p| (p, p.z == 0.0)));
    for (k, d) in planes.iter().enumerate() {
        if out.is_empty() {
            break;
        }
        let poly = &*out;
        tmp.clear();
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (da, db) = (d(&a.0), d(&b.0));
            if da >= 0.0 {
                tmp.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                tmp.push((a.0 + (b.0 - a.0) * t, k == 0 || (a.1 && b.1)));
            }
        }
        std::mem::swap(out, tmp);
    }
}

/// Snapped screen position of a clip-space point, and its 24-bit depth.
pub(super) fn snap_clip(pj: &Projector, p: DVec4) -> Result<([i32; 2], u32), SetupError> {
    let (x, y, z) = pj.to_screen(p);
    Ok((
        [crate::setup::snap_coord(x)?, crate::setup::snap_coord(y)?],
        crate::frontend::depth24(z),
    ))
}

/// A snapped polygon as a fan of triangles from its first vertex, in fan order.
pub(super) fn fan(sv: &[([i32; 2], u32)]) -> impl Iterator<Item = SnappedTri> + '_ {
    (1..sv.len().saturating_sub(1)).map(|i| SnappedTri {
        v: [sv[0].0, sv[i].0, sv[i + 1].0],
        z: [sv[0].1, sv[i].1, sv[i + 1].1],
        ..Default::default()
    })
}

/// Sets up a snapped polygon as a fan from its first vertex ([`fan`]), pushing the
/// non-degenerate triangles in fan order.
pub(super) fn fan_tris(sv: &[([i32; 2], u32)], out: &mut Vec<ShadowTri>) -> Result<(), SetupError> {
    for t in fan(sv) {
        if let Some(s) = ShadowTri::new(&t)? {
            out.push(s);
        }
    }
    Ok(())
}

/// The near plane's rectangle inside the guard band, as world points.
pub(super) fn near_rect(pj: &Projector) -> Vec<DVec3> {
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
pub(super) fn box_planes(lo: DVec3, hi: DVec3) -> Vec<DVec4> {
    (0..3)
        .flat_map(|a| {
            let e = [DVec3::X, DVec3::Y, DVec3::Z][a];
            [e.extend(-lo[a]), (-e).extend(hi[a])]
        })
        .collect()
}

/// Classifies the near plane against a volume.
pub(super) fn near_plane(pj: &Projector, v: &Volume) -> NearPlane {
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
pub(super) fn near_cap(
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

/// A volume's shadow polygons, set up: the fans of its clipped polygons in polygon order,
/// then its near cap's fan. Each triangle sends at most one SP word per row, and a row's
/// words come in this order.
#[derive(Clone, Debug, Default)]
pub(super) struct VolumeTris {
    tris: Vec<ShadowTri>,
}

/// Where [`VolumeTris::band_words`] puts a band's words.
pub(super) trait WordSink {
    /// Row `j`'s next word.
    fn word(&mut self, j: i64, w: SpanWord);

    /// Whether a triangle whose words lie on columns `lo..=hi` with a depth (`Z >>
    /// Z_FRAC`) of at least `depth` on every pixel ([`ShadowTri::depth_floor`]) is behind
    /// everything on the band's rows, so that its words need only be counted
    /// ([`WordSink::behind`]).
    fn is_behind(&mut self, _lo: usize, _hi: usize, _depth: i64) -> bool {
        false
    }

    /// Row `j`'s next word, which lies behind everything ([`WordSink::is_behind`]).
    fn behind(&mut self, j: i64);
}

/// A closure takes every word.
impl<F: FnMut(i64, SpanWord)> WordSink for F {
    #[inline]
    fn word(&mut self, j: i64, w: SpanWord) {
        self(j, w)
    }

    fn behind(&mut self, _j: i64) {
        unreachable!("a closure takes every word")
    }
}

impl VolumeTris {
    /// Gives the SP words of rows `j0..=j1` to `sink`, triangle after triangle, each
    /// triangle's rows top to bottom: on every row, the words come in triangle order.
    /// Each triangle's columns and depth plane are stepped exactly
    /// ([`ShadowTri::column_rows`], [`ShadowTri::depth_rows`]) from the first of those rows
    /// it covers, so its set-up is read once per band rather than once per row. A
    /// triangle the sink finds behind everything has its columns stepped only, for the
    /// rows it has a word on.
    pub(super) fn band_words(&self, j0: i64, j1: i64, width: u32, sink: &mut impl WordSink) {
        /// One triangle's rows `first..=last`, `z` standing at `first`.
        #[inline(always)]
        fn rows(
            t: &ShadowTri,
            (first, last): (i64, i64),
            width: u32,
            mut z: impl PlaneStepper,
            sink: &mut impl WordSink,
        ) {
            let mut cols = t.column_rows(first);
            for j in first..=last {
                if let Some(w) = t.shadow_span(width, &cols, &z) {
                    sink.word(j, w);
                }
                cols.advance();
                z.advance();
            }
        }
        for t in &self.tris {
            let (first, last) = (t.row_min.max(j0), t.row_max.min(j1));
            if first > last {
                continue;
            }
            let Some((lo, hi, depth)) = t.depth_floor(width) else {
                continue;
            };
            if sink.is_behind(lo, hi, depth) {
                let mut cols = t.column_rows(first);
                for j in first..=last {
                    if cols.columns(width).is_some() {
                        sink.behind(j);
                    }
                    cols.advance();
                }
                continue;
            }
            // The depth stepper in 64 bits when its values stay there (nearly always).
            let z = t.depth_rows(first);
            match z.narrow((last - first) as u64) {
                Some(z) => rows(t, (first, last), width, z, sink),
                None => rows(t, (first, last), width, z, sink),
            }
        }
    }

    /// The rows any of the triangles may cover, clamped to `0..height`, if any.
    pub(super) fn rows(&self, height: u32) -> Option<(u32, u32)> {
        let lo = self.tris.iter().map(|t| t.row_min).min()?.max(0);
        let hi = self
            .tris
            .iter()
            .map(|t| t.row_max)
            .max()?
            .min(height as i64 - 1);
        (lo <= hi).then_some((lo as u32, hi as u32))
    }

    /// Adds 1 to `steps[first]` and subtracts 1 from `steps[last + 1]` for each triangle's
    /// rows `first..=last` on the screen (`steps` has one entry per row and one more): the
    /// running sum of `steps` then counts, per row, the triangles that may send a word on
    /// it.
    pub(super) fn count_rows(&self, steps: &mut [i64]) {
        let rows = steps.len() as i64 - 1;
        for t in &self.tris {
            let (a, b) = (t.row_min.max(0), t.row_max.min(rows - 1));
            if a <= b {
                steps[a as usize] += 1;
                steps[b as usize + 1] -= 1;
            }
        }
    }
}

/// Projects a volume's polygons (clip to the ray box, then the view frustum; snap) and
/// sets up the triangles of their fans, in polygon order, then those of its near cap
/// when the near plane cuts it; and tells where the near plane lies.
pub(super) fn volume_tris(
    pj: &Projector,
    v: &Volume,
    bbox: (DVec3, DVec3),
    buf: &mut ClipBuffers,
) -> Result<(VolumeTris, NearPlane), SetupError> {
    let mut tris = Vec::new();
    let mut near_edges = Vec::new();
    let ClipBuffers {
        world,
        world_tmp,
        clip,
        tagged,
        tagged_tmp,
        snapped,
    } = buf;
    for poly in &v.polys {
        clip_to_box(poly, bbox.0, bbox.1, world, world_tmp);
        if world.len() < 3 {
            continue;
        }
        clip.clear();
        clip.extend(world.iter().map(|p| pj.view_proj * *p));
        clip_tagged(clip, tagged, tagged_tmp);
        let clipped = &*tagged;
        if clipped.len() < 3 || clipped.iter().any(|c| c.0.w <= 0.0) {
            continue;
        }
        snapped.clear();
        for c in clipped {
            snapped.push(snap_clip(pj, c.0)?);
        }
        let sv = &*snapped;
        if !clipped.iter().all(|c| c.1) {
            for i in 0..clipped.len() {
                let k = (i + 1) % clipped.len();
                if clipped[i].1 && clipped[k].1 && sv[i].0 != sv[k].0 {
                    near_edges.push([sv[i].0, sv[k].0]);
                }
            }
        }
        fan_tris(sv, &mut tris)?;
    }
    let near = near_plane(pj, v);
    if near == NearPlane::Cut {
        let cap = near_cap(pj, v, bbox, &near_edges)?;
        let zn = crate::frontend::depth24(0.0);
        let sv: Vec<([i32; 2], u32)> = cap.into_iter().map(|p| (p, zn)).collect();
        fan_tris(&sv, &mut tris)?;
    }
    Ok((VolumeTris { tris }, near))
}

/// The buffers [`volume_tris`] clips and snaps a volume's polygons in, reused from
/// polygon to polygon and from volume to volume.
#[derive(Default)]
pub(super) struct ClipBuffers {
    world: Vec<DVec4>,
    world_tmp: Vec<DVec4>,
    clip: Vec<DVec4>,
    tagged: Vec<(DVec4, bool)>,
    tagged_tmp: Vec<(DVec4, bool)>,
    snapped: Vec<([i32; 2], u32)>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift64Star;
    use crate::setup::TriSetup;

    /// A band's words give, on every row, each volume's SP words in triangle order, each
    /// equal to the triangle's span computed directly on that row (`TriSetup::span`,
    /// exact division, no stepping) with attr SP and zero intensities; on random fans,
    /// with bands starting inside, above and below the triangles, off-screen parts
    /// included.
    #[test]
    fn band_rows_give_each_rows_direct_spans_in_order() {
        let mut rng = XorShift64Star(0x0bad_5eed_f00d);
        let (w, h) = (96u32, 80i64);
        let mut coord = |lo: f64, hi: f64| lo + (hi - lo) * rng.unit();
        let mut words = 0;
        for case in 0..60 {
            let mut vols = Vec::new();
            for _ in 0..1 + case % 4 {
                let n = 3 + case % 5;
                let sv: Vec<([i32; 2], u32)> = (0..n)
                    .map(|_| {
                        let (x, y) = (coord(-20.0, 116.0), coord(-20.0, 100.0));
                        let z = coord(1000.0, 900_000.0) as u32;
                        (
                            [
                                crate::setup::snap_coord(x).unwrap(),
                                crate::setup::snap_coord(y).unwrap(),
                            ],
                            z,
                        )
                    })
                    .collect();
                let mut tris = Vec::new();
                fan_tris(&sv, &mut tris).unwrap();
                // The same triangles set up in full, for their spans by division.
                let full: Vec<TriSetup> = fan(&sv)
                    .filter_map(|t| TriSetup::new(&t).unwrap())
                    .collect();
                assert_eq!(full.len(), tris.len());
                vols.push((VolumeTris { tris }, full));
            }
            for band in [1i64, 5, 16] {
                let mut j0 = 0;
                while j0 < h {
                    let j1 = (j0 + band - 1).min(h - 1);
                    for (i, (v, full)) in vols.iter().enumerate() {
                        let mut rows = vec![Vec::new(); (j1 - j0 + 1) as usize];
                        v.band_words(j0, j1, w, &mut |j, s| rows[(j - j0) as usize].push(s));
                        for (j, got) in (j0..).zip(rows) {
                            let want: Vec<SpanWord> = full
                                .iter()
                                .filter_map(|t| t.span(j, w))
                                .map(crate::setup::shadow_word)
                                .collect();
                            assert_eq!(got, want, "case {case} band {band} row {j} volume {i}");
                            words += got.len();
                        }
                    }
                    j0 = j1 + 1;
                }
            }
        }
        assert!(words > 10_000, "the fans covered {words} spans");
    }
}
