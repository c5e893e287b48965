//! Hidden fragments of the A-buffer's rows (seed 000, JP2569952B2, background processes
//! 2 and 3: fragments the packing of their pixel never reaches), counted instead of made.
//!
//! A fragment that cannot change its pixel's outcome need not be made; it is counted
//! instead ([`HiddenRow::per_pixel`], and its depth pick's evaluations and steps in
//! [`HiddenRow::counts`]). Without decals and interpenetration, a fragment with range
//! `[lo, hi]` (`zc ±` `FragSetup::half_range`, the merge range) is such a fragment when
//! - its mask is full: its depth pick's counts then depend on the triangle's slopes alone,
//!   not on the pixel;
//! - `lo` is beyond the nearest far end `front` of a full-mask fragment's range in the
//!   pixel: its ordering depth is at least `lo`, that full-mask fragment's group has one
//!   at most `front`, so packing takes that group first, which leaves no bit free, and
//!   the fragment's visible bits are none (the fragment whose range ends at `front` is
//!   never left out);
//! - no fragment with its tag in the pixel has a range that overlaps its own: it merges
//!   with nothing, so it is a group of its own that no other group depends on, and the
//!   merges are the same (one fragment and one group fewer). This is tested per row and
//!   triangle, conservatively ([`TagTest`]): every other triangle with the tag that
//!   touches the triangle's fully covered pixels must have depths there whose range stays
//!   clear of the triangle's ([`apart`]).
//!
//! The other fragments' groups, their order (keys compare first member indices, which
//! keep their order) and the resolve are then those of the full pixel. A row looks for
//! hidden fragments only where surfaces lie deep enough ([`HiddenRow::worth`]).

use super::{emit_triangle, FragSetup, Slots};
use crate::mask::RowMasks;
use crate::mask_search::{DepthSelect, DepthSelector};
use crate::raster::{PlaneStepper, RoundDivSteps};
use pixelproc_formats::abuffer::{saturate_plane, FragPlane, MaskSize, PLANE_MAX};

/// Fully covered pixels a row needs, in rows' widths, before it looks for hidden
/// fragments whatever its triangles: where surfaces lie fewer layers deep, the tests
/// cost more than the fragments they leave out.
const LAYERS_MIN: i64 = 5;

/// Fully covered pixels beyond one row's width a row needs per triangle with fully
/// covered pixels to look for hidden fragments on fewer layers: only those pixels can be
/// hidden, and each such triangle costs the row a set-up (its stepper, bounds and place
/// in the tag order) and a pass over its run, so a few large triangles a few layers deep
/// pay for the tests. (On the nine benchmark scenes: 15 leaves `large` and `closeup`
/// 10–13 % faster in paired runs and changes no other scene's instructions by more than
/// 0.2 %; 7 made `@boxes` 2 % slower, where rows of many small triangles then qualify.)
const EXTRA_PER_TRIANGLE: i64 = 15;

/// Leaving hidden fragments out of a row: the depth selection whose evaluations and steps
/// they count.
#[derive(Clone, Copy)]
pub(in crate::abuffer) struct Hidden<'a> {
    /// The depth selector of the frame.
    pub sel: &'a DepthSelector,
    /// The depth-selection variant.
    pub variant: DepthSelect,
}

/// One row being built: every triangle that touches it (setup index and masks, scene
/// order) and their setups.
pub(super) struct Row<'a> {
    pub setups: &'a [FragSetup],
    pub masks: &'a [(u32, RowMasks)],
    pub j: i64,
    pub size: MaskSize,
}

/// The hidden fragments a row leaves out, and the buffers of its tests (reused from row to
/// row).
#[derive(Default)]
pub(super) struct HiddenRow {
    /// Hidden fragments left out per pixel (`width` entries once prepared).
    per_pixel: Vec<u32>,
    /// The depth pick's evaluations and steps of the row's hidden fragments.
    counts: (u64, u64),
    /// Per pixel, the nearest far end of a full-mask fragment's depth range.
    front: Vec<i64>,
    /// Per block of [`HIDE_BLOCK`] pixels, the largest `front` in it.
    front_max: Vec<i64>,
    /// Each triangle's depth stepper from its first touched pixel, in `masks` order.
    zs: Vec<RoundDivSteps>,
    /// Each triangle's place in `by_tag`, in `masks` order.
    pos: Vec<u32>,
    /// (tag, touched range, index into `masks`), sorted: the tag test's order.
    by_tag: Vec<(u16, i64, i64, u32)>,
    /// Per `by_tag` entry, the farthest touched pixel of its tag's entries up to it.
    reach: Vec<i64>,
    /// Each triangle's fragment ranges `zc ± half` bounded over its whole touched run, in
    /// `masks` order: two triangles whose boxes are apart are apart on every pixel.
    spans: Vec<(i64, i64)>,
}

impl HiddenRow {
    /// Forgets the last row's hidden fragments.
    pub(super) fn clear(&mut self) {
        self.per_pixel.clear();
        self.counts = (0, 0);
    }

    /// Whether a row `w` pixels wide is worth the tests: its fully covered pixels add up to
    /// [`LAYERS_MIN`] widths or exceed its width by [`EXTRA_PER_TRIANGLE`] per triangle
    /// with any, and it has no decal.
    pub(super) fn worth(row: &Row, w: usize) -> bool {
        let (mut covered, mut triangles) = (0i64, 0i64);
        for (_, rm) in row.masks {
            if let Some((a, b)) = rm.cov.full {
                covered += b - a + 1;
                triangles += 1;
            }
        }
        let w = w as i64;
        (covered >= LAYERS_MIN * w || covered - w >= EXTRA_PER_TRIANGLE * triangles)
            && !row.masks.iter().any(|(k, _)| row.setups[*k as usize].decal)
    }

    /// The buffers of the tests of a row `w` pixels wide: every triangle's depth stepper,
    /// each pixel's `front`, and the tag test's order.
    pub(super) fn prepare(&mut self, row: &Row, w: usize) {
        let (setups, masks) = (row.setups, row.masks);
        self.per_pixel.resize(w, 0);
        self.front.clear();
        self.front.resize(w, i64::MAX);
        self.zs.clear();
        self.zs.extend(
            masks
                .iter()
                .map(|(k, rm)| setups[*k as usize].depth_steps(rm.cov.touched.0, row.j)),
        );
        for ((k, rm), z) in masks.iter().zip(&self.zs) {
            let Some(run) = rm.cov.full else { continue };
            let (t, a) = (&setups[*k as usize], rm.cov.touched.0);
            let half = t.half_range(row.size);
            match z.narrow((run.1 - a + 1) as u64) {
                Some(z) => front_run(&mut self.front, z, a, run, half),
                None => front_run(&mut self.front, *z, a, run, half),
            }
        }
        self.front_max.clear();
        self.front_max.extend(
            self.front
                .chunks(HIDE_BLOCK as usize)
                .map(|b| b.iter().copied().max().unwrap_or(i64::MAX)),
        );
        self.spans.clear();
        self.spans
            .extend(masks.iter().zip(&self.zs).map(|((k, rm), z)| {
                let (a, b) = rm.cov.touched;
                let half = setups[*k as usize].half_range(row.size);
                let (lo, hi) = z.bounds(0, (b - a) as u64);
                (saturate_plane(lo) - half, saturate_plane(hi) + half)
            }));
        self.by_tag.clear();
        self.by_tag
            .extend(masks.iter().enumerate().map(|(x, (k, rm))| {
                let (a, b) = rm.cov.touched;
                (setups[*k as usize].tag, a, b, x as u32)
            }));
        self.by_tag.sort_unstable();
        self.reach.clear();
        self.pos.clear();
        self.pos.resize(masks.len(), 0);
        let mut reach = (u16::MAX, i64::MIN);
        for (q, e) in self.by_tag.iter().enumerate() {
            let far = if e.0 == reach.0 {
                reach.1.max(e.2)
            } else {
                e.2
            };
            reach = (e.0, far);
            self.reach.push(far);
            self.pos[e.3 as usize] = q as u32;
        }
    }

    /// Writes the fragments of the row's triangle `x` (`masks` order) into `slots`, leaving
    /// its hidden ones out and counting them; the row is prepared.
    #[inline]
    pub(super) fn emit(&mut self, h: Hidden<'_>, x: usize, slots: &mut Slots<'_>, row: &Row) {
        let (k, rm) = &row.masks[x];
        let t = &row.setups[*k as usize];
        let full = row.size.full();
        if rm.cov.full.is_none() {
            emit_triangle(slots, t, rm, self.zs[x], row.j, full, &mut NoHiding);
            return;
        }
        let test = TagTest {
            by_tag: &self.by_tag,
            reach: &self.reach,
            zs: &self.zs,
            spans: &self.spans,
            row,
        };
        let mut behind = Behind {
            front: &self.front,
            front_max: &self.front_max,
            hidden: &mut self.per_pixel,
            half: t.half_range(row.size),
            count: 0,
            alone: None,
            test: || test.alone(self.pos[x] as usize),
        };
        emit_triangle(slots, t, rm, self.zs[x], row.j, full, &mut behind);
        if behind.count > 0 {
            // A full mask's pick counts depend on the slopes alone.
            let plane = FragPlane {
                zc: 0,
                sx: t.sx,
                sy: t.sy,
            };
            let p = h.sel.select_nearest(h.variant, full, &plane);
            self.counts.0 += behind.count * p.evals as u64;
            self.counts.1 += behind.count * p.steps as u64;
        }
    }

    /// Hidden fragments left out per pixel, or no entries if the row left none out.
    #[inline]
    pub(super) fn per_pixel(&self) -> &[u32] {
        &self.per_pixel
    }

    /// The depth pick's evaluations and steps of the row's hidden fragments.
    pub(super) fn counts(&self) -> (u64, u64) {
        self.counts
    }
}

/// Whether a triangle's fully covered fragment is hidden, and left out.
pub(super) trait Hiding {
    /// Whether [`Hiding::hides_block`] can ever say yes (a constant: without it the
    /// emitting loop looks at pixels one by one only).
    const BLOCKS: bool;
    /// Called for each fully covered pixel `i` with the fragment's `zc`.
    fn hides(&mut self, i: i64, zc: i64) -> bool;
    /// Called for the fully covered pixels `i .. i + HIDE_BLOCK` (`i` a multiple of
    /// [`HIDE_BLOCK`]) with a lower bound `zlo` of the fragment's `zc` on all of them:
    /// whether [`Hiding::hides`] would hide each of them, then counted as it counts them.
    /// `false` says nothing (the pixels are then asked one by one).
    fn hides_block(&mut self, i: i64, zlo: i64) -> bool;
}

/// Pixels per block of the row's `front` maxima ([`HiddenRow`]): a triangle's fully
/// covered fragments are first tested a block at a time against the block's farthest
/// `front`.
pub(super) const HIDE_BLOCK: i64 = 32;

/// Every fragment made.
pub(super) struct NoHiding;

impl Hiding for NoHiding {
    const BLOCKS: bool = false;
    #[inline(always)]
    fn hides(&mut self, _: i64, _: i64) -> bool {
        false
    }
    #[inline(always)]
    fn hides_block(&mut self, _: i64, _: i64) -> bool {
        false
    }
}

/// A triangle's fully covered fragments whose range starts beyond the pixel's `front`
/// are left out and counted, if the triangle passes the tag test (`test`, run at the
/// first such fragment).
struct Behind<'a, F: FnMut() -> bool> {
    front: &'a [i64],
    /// The largest `front` of each block of [`HIDE_BLOCK`] pixels.
    front_max: &'a [i64],
    hidden: &'a mut [u32],
    /// The triangle's [`FragSetup::half_range`].
    half: i64,
    /// Fragments left out.
    count: u64,
    /// The tag test's outcome, once run.
    alone: Option<bool>,
    test: F,
}

impl<F: FnMut() -> bool> Behind<'_, F> {
    /// The tag test's outcome, run the first time it is asked for.
    #[inline(always)]
    fn alone(&mut self) -> bool {
        match self.alone {
            Some(a) => a,
            None => self.run_test(),
        }
    }

    /// Runs the tag test and remembers its outcome: kept out of the emitting loop, which
    /// only reads the memo.
    #[cold]
    #[inline(never)]
    fn run_test(&mut self) -> bool {
        let a = (self.test)();
        self.alone = Some(a);
        a
    }
}

impl<F: FnMut() -> bool> Hiding for Behind<'_, F> {
    const BLOCKS: bool = true;
    #[inline(always)]
    fn hides_block(&mut self, i: i64, zlo: i64) -> bool {
        // Every pixel's `zc − half ≥ zlo − half > front_max ≥ front`: each is hidden
        // exactly when the tag test passes, as `hides` finds pixel by pixel.
        if zlo - self.half <= self.front_max[(i / HIDE_BLOCK) as usize] {
            return false;
        }
        if !self.alone() {
            return false;
        }
        let i = i as usize;
        self.hidden[i..i + HIDE_BLOCK as usize]
            .iter_mut()
            .for_each(|h| *h += 1);
        self.count += HIDE_BLOCK as u64;
        true
    }
    #[inline(always)]
    fn hides(&mut self, i: i64, zc: i64) -> bool {
        let i = i as usize;
        if zc - self.half <= self.front[i] {
            return false;
        }
        if !self.alone() {
            return false;
        }
        self.hidden[i] += 1;
        self.count += 1;
        true
    }
}

/// Most other triangles of its tag the tag test compares with one triangle pixel by pixel
/// ([`apart_closely`]); with more it fails (keeps the fragments), which bounds its cost.
/// Triangles whose ranges are apart by their bounds ([`HiddenRow`]'s `spans` over their
/// whole runs, then [`apart_bounded`] on the common pixels) are not counted: in a mesh of
/// many layers, each apart from the next, only the few that come near the triangle's
/// depth are.
const TAG_TEST_MAX: usize = 6;

/// The tag test on one row: the row's triangles in (tag, first touched
/// pixel) order (`by_tag`, with each entry's `reach`: the farthest touched pixel of its
/// tag's entries up to it) and their depth steppers (`zs`, `masks` order).
struct TagTest<'a> {
    by_tag: &'a [(u16, i64, i64, u32)],
    reach: &'a [i64],
    zs: &'a [RoundDivSteps],
    /// [`HiddenRow`]'s `spans`.
    spans: &'a [(i64, i64)],
    row: &'a Row<'a>,
}

impl TagTest<'_> {
    /// Whether the triangle at `by_tag[pos]` (with fully covered pixels `fa..=fb`) has
    /// depth ranges apart from those of every other triangle of its tag on the pixels both
    /// touch there: the later entries of the tag that start by `fb`, and the earlier ones
    /// while their tag's reach gets to `fa`.
    fn alone(&self, pos: usize) -> bool {
        let (by, masks, setups) = (self.by_tag, self.row.masks, self.row.setups);
        let e = by[pos];
        let x = e.3 as usize;
        let Some((fa, fb)) = masks[x].1.cov.full else {
            return false;
        };
        let later = by[pos + 1..].iter().take_while(|u| u.0 == e.0 && u.1 <= fb);
        let earlier = (0..pos)
            .rev()
            .take_while(|&q| by[q].0 == e.0 && self.reach[q] >= fa)
            .map(|q| &by[q]);
        let t = &setups[masks[x].0 as usize];
        let ts = self.spans[x];
        let mut met = 0;
        later.chain(earlier).filter(|u| u.2 >= fa).all(|u| {
            let y = u.3 as usize;
            let us = self.spans[y];
            if ts.1 < us.0 || us.1 < ts.0 {
                // Apart over the whole runs, so on the common pixels.
                return true;
            }
            let o = &setups[masks[y].0 as usize];
            let run = (fa.max(u.1), fb.min(u.2));
            let size = self.row.size;
            if apart_bounded((t, self.zs[x], e.1), (o, self.zs[y], u.1), run, size) {
                return true;
            }
            met += 1;
            met <= TAG_TEST_MAX && apart_closely(t, o, run, self.row.j, size)
        })
    }
}

/// Whether the depth ranges of the fragments of triangles `t` and `o` (each with its
/// depth stepper `z` from its first touched pixel `a`) stay apart on pixels `p..=q` of
/// row `j`: [`apart_bounded`], else [`apart_closely`].
#[cfg(test)]
fn apart(
    t: (&FragSetup, RoundDivSteps, i64),
    o: (&FragSetup, RoundDivSteps, i64),
    run: (i64, i64),
    j: i64,
    size: MaskSize,
) -> bool {
    apart_bounded(t, o, run, size) || apart_closely(t.0, o.0, run, j, size)
}

/// [`apart`] from each stepper's bounds over the whole run
/// ([`RoundDivSteps::bounds`]): `true` when those bounds are apart, `false` when they do
/// not tell.
fn apart_bounded(
    (t, tz, ta): (&FragSetup, RoundDivSteps, i64),
    (o, oz, oa): (&FragSetup, RoundDivSteps, i64),
    (p, q): (i64, i64),
    size: MaskSize,
) -> bool {
    let (th, oh) = (t.half_range(size), o.half_range(size));
    let band = |z: RoundDivSteps, a: i64, half: i64| {
        let (lo, hi) = z.bounds((p - a) as u64, (q - a) as u64);
        (saturate_plane(lo) - half, saturate_plane(hi) + half)
    };
    let (tb, ob) = (band(tz, ta, th), band(oz, oa, oh));
    tb.1 < ob.0 || ob.1 < tb.0
}

/// [`apart`] from the depths at the run's ends ([`apart_by_ends`]) where they settle it,
/// else pixel by pixel: exact.
fn apart_closely(t: &FragSetup, o: &FragSetup, (p, q): (i64, i64), j: i64, size: MaskSize) -> bool {
    let (th, oh) = (t.half_range(size), o.half_range(size));
    let steps = (q - p + 1) as u64;
    let (tz, oz) = (t.depth_steps(p, j), o.depth_steps(p, j));
    if steps >= ENDS_MIN {
        let (tq, oq) = (t.depth_steps(q, j), o.depth_steps(q, j));
        if apart_by_ends([tz.value(), tq.value()], [oz.value(), oq.value()], th + oh) {
            return true;
        }
    }
    match (tz.narrow(steps), oz.narrow(steps)) {
        (Some(tz), Some(oz)) => apart_each(tz, th, oz, oh, steps),
        _ => apart_each(tz, th, oz, oh, steps),
    }
}

/// Pixels a run of [`apart`] needs before its ends are looked at: on a shorter run the
/// pixel-by-pixel test costs less than the two more divisions that give the far end.
const ENDS_MIN: u64 = 64;

/// [`apart`] from the depths at the two ends of a run alone, where they settle it: `true`
/// when the two fragments' ranges (`zc ± half`, `margin` the sum of the halves) are apart
/// on every pixel of the run, `false` when the ends do not tell.
///
/// `t` and `o` are the rounded depths (`round_div` of the planes, before
/// `saturate_plane`) at the first and the last pixel. Rounding half up puts each in
/// `(v − ½, v + ½]` of its exact plane value `v`, so `d = t − o` lies strictly within 1
/// of `D = T − O`, which is linear along the row and so between the ends at least its
/// smaller end value. Hence at every pixel `d > D − 1 ≥ min(D_first, D_last) − 1 >
/// min(d_first, d_last) − 2`, that is `d ≥ min(d_first, d_last) − 1` (integers), and the
/// ranges are apart there (`d > margin`) when that bound exceeds `margin`; the same holds
/// on the other side with the maxima. The rounded values are monotone along the row, so when the four ends lie
/// inside `saturate_plane`'s range every pixel's does, and the saturation changes
/// nothing.
fn apart_by_ends(t: [i128; 2], o: [i128; 2], margin: i64) -> bool {
    let lim = PLANE_MAX as i128;
    if t.iter().chain(&o).any(|v| v.abs() > lim) {
        return false;
    }
    let d = [t[0] - o[0], t[1] - o[1]];
    let m = margin as i128;
    d[0].min(d[1]) - 1 > m || d[0].max(d[1]) + 1 < -m
}

/// [`apart`] pixel by pixel: the ranges `zc ± half` of two steppers over `steps` pixels
/// never overlap.
fn apart_each<A: PlaneStepper, B: PlaneStepper>(
    mut tz: A,
    th: i64,
    mut oz: B,
    oh: i64,
    steps: u64,
) -> bool {
    for _ in 0..steps {
        let (t, o) = (saturate_plane(tz.value()), saturate_plane(oz.value()));
        if t - th <= o + oh && o - oh <= t + th {
            return false;
        }
        tz.advance();
        oz.advance();
    }
    true
}

/// Each pixel's `front` lowered to the far end of the range of a triangle's fully
/// covered fragments (`run`), the depth stepped from its first touched pixel `a`.
fn front_run<Z: PlaneStepper>(front: &mut [i64], mut z: Z, a: i64, run: (i64, i64), half: i64) {
    for _ in a..run.0 {
        z.advance();
    }
    for f in &mut front[run.0 as usize..=run.1 as usize] {
        *f = (*f).min(saturate_plane(z.value()) + half);
        z.advance();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::SnappedTri;
    use pixelproc_formats::{Z_GEOM_MAX, Z_GEOM_MIN};

    /// The reference of [`apart`]: each pixel's two ranges `zc ± half` computed from the
    /// planes directly ([`FragSetup::plane_at`]) and compared, pixel by pixel.
    fn apart_direct(
        t: &FragSetup,
        o: &FragSetup,
        (p, q): (i64, i64),
        j: i64,
        size: MaskSize,
    ) -> bool {
        let (th, oh) = (t.half_range(size), o.half_range(size));
        (p..=q).all(|i| {
            let (a, b) = (t.plane_at(i, j).zc, o.plane_at(i, j).zc);
            a - th > b + oh || b - oh > a + th
        })
    }

    /// `apart` (bounds over the run, then the ends of a long run, then pixel by pixel)
    /// agrees with the pixel-by-pixel reference on pairs of wide triangles: planes nearly
    /// parallel, crossing, steep enough to saturate off the triangle, runs from one
    /// pixel to hundreds; and the ends settle many long runs that the bounds do not.
    #[test]
    fn apart_agrees_with_the_pixel_by_pixel_test() {
        let mut rng = crate::rng::Lcg64(0x0a9a_47e5);
        let size = MaskSize::S4X4;
        let (lo, hi) = (Z_GEOM_MIN as f64, Z_GEOM_MAX as f64);
        let (mut apart_n, mut overlap_n, mut by_ends) = (0, 0, 0);
        for case in 0..3000 {
            let base = rng.range(lo, hi);
            // Depth differences across the triangle from none to the whole range; every
            // fourth case steep (far beyond the range once extrapolated off the triangle).
            let spread = match case % 4 {
                0 => 0.0,
                1 => rng.range(0.0, 2000.0),
                2 => rng.range(0.0, 200_000.0),
                _ => rng.range(0.0, hi - lo),
            };
            let tri = |rng: &mut crate::rng::Lcg64, z0: f64| {
                let v = [
                    [rng.range(-50.0, 20.0), rng.range(-30.0, 10.0)],
                    [rng.range(600.0, 900.0), rng.range(-30.0, 40.0)],
                    [rng.range(100.0, 500.0), rng.range(30.0, 90.0)],
                ]
                .map(|p| p.map(|c| (c * 256.0) as i32));
                let z = [0; 3].map(|_| (z0 + rng.range(-spread, spread)).clamp(lo, hi) as u32);
                SnappedTri {
                    v,
                    z,
                    ..Default::default()
                }
            };
            let a = tri(&mut rng, base);
            // The other triangle's depth: on the same plane, near it, or well apart.
            let gap = [0.0, 3.0, 300.0, 30_000.0][case % 4 / 2 + (case / 4) % 3 % 2 * 2];
            let z0 = base + rng.range(-gap, gap);
            let b = tri(&mut rng, z0);
            let (Some(t), Some(o)) = (
                FragSetup::new(&a, 0, size).unwrap(),
                FragSetup::new(&b, 1, size).unwrap(),
            ) else {
                continue;
            };
            let j = (rng.step() % 40) as i64;
            let p = (rng.step() % 500) as i64;
            let q = p + [0, 5, 63, 64, 300][case % 5] + (rng.step() % 50) as i64;
            let (ta, oa) = (p - (rng.step() % 4) as i64, p - (rng.step() % 4) as i64);
            let got = apart(
                (&t, t.depth_steps(ta, j), ta),
                (&o, o.depth_steps(oa, j), oa),
                (p, q),
                j,
                size,
            );
            let want = apart_direct(&t, &o, (p, q), j, size);
            assert_eq!(got, want, "case {case}: run {p}..={q} of row {j}");
            if want {
                apart_n += 1;
            } else {
                overlap_n += 1;
            }
            let ends = |s: &FragSetup| [s.depth_steps(p, j).value(), s.depth_steps(q, j).value()];
            let margin = t.half_range(size) + o.half_range(size);
            if q - p + 1 >= ENDS_MIN as i64 && apart_by_ends(ends(&t), ends(&o), margin) {
                by_ends += 1;
            }
        }
        assert!(
            apart_n > 500 && overlap_n > 500 && by_ends > 300,
            "{apart_n} apart, {overlap_n} overlapping, {by_ends} settled by the ends"
        );
    }

    /// The ends' rule alone, on rounded linear functions with small denominators (where
    /// rounding moves values most), margins within a few units of their difference and
    /// values at the edge of `saturate_plane`'s range: whenever it says apart, every pixel
    /// of the run is apart after rounding and saturation.
    #[test]
    fn the_ends_rule_never_misses_an_overlap() {
        let mut rng = crate::rng::Lcg64(0x0e4d_5a9a);
        let lim = PLANE_MAX as i128;
        let (mut said, mut near) = (0, 0);
        for case in 0..200_000 {
            let base = [0, lim - 40, -lim + 40][case % 3];
            let line = |rng: &mut crate::rng::Lcg64| {
                let c = 1 + (rng.step() % 7) as i128;
                let b = (rng.step() % 9) as i128 - 4;
                let a = (base + (rng.step() % 41) as i128 - 20) * c + (rng.step() % 7) as i128;
                move |x: i128| crate::raster::round_div(a + b * x, c)
            };
            let (t, o) = (line(&mut rng), line(&mut rng));
            let n = 64 + (rng.step() % 30) as i128;
            let d0 = t(0) - o(0);
            let margin = (d0.abs() - 3 + (rng.step() % 7) as i128).max(0) as i64;
            if !apart_by_ends([t(0), t(n - 1)], [o(0), o(n - 1)], margin) {
                continue;
            }
            said += 1;
            let m = margin as i128;
            let mut closest = i128::MAX;
            for x in 0..n {
                let (a, b) = (saturate_plane(t(x)) as i128, saturate_plane(o(x)) as i128);
                assert!(a - b > m || b - a > m, "case {case}: pixel {x} overlaps");
                closest = closest.min((a - b).abs() - m);
            }
            near += (closest == 1) as u32;
        }
        assert!(
            said > 5000 && near > 150,
            "{said} said apart, {near} one unit from the margin"
        );
    }
}
