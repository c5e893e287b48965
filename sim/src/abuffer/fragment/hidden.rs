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
//! hidden fragments only where surfaces lie [`LAYERS_MIN`] deep.

use super::{emit_triangle, FragSetup, Slots};
use crate::mask::RowMasks;
use crate::mask_search::{DepthSelect, DepthSelector};
use crate::raster::{PlaneStepper, RoundDivSteps};
use pixelproc_formats::abuffer::{saturate_plane, FragPlane, MaskSize};

/// Fully covered pixels a row needs, in rows' widths, before it looks for hidden
/// fragments: where surfaces lie fewer layers deep, the tests cost more than the
/// fragments they leave out.
const LAYERS_MIN: i64 = 5;

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
    /// Each triangle's depth stepper from its first touched pixel, in `masks` order.
    zs: Vec<RoundDivSteps>,
    /// Each triangle's place in `by_tag`, in `masks` order.
    pos: Vec<u32>,
    /// (tag, touched range, index into `masks`), sorted: the tag test's order.
    by_tag: Vec<(u16, i64, i64, u32)>,
    /// Per `by_tag` entry, the farthest touched pixel of its tag's entries up to it.
    reach: Vec<i64>,
}

impl HiddenRow {
    /// Forgets the last row's hidden fragments.
    pub(super) fn clear(&mut self) {
        self.per_pixel.clear();
        self.counts = (0, 0);
    }

    /// Whether a row `w` pixels wide is worth the tests: its fully covered pixels add up to
    /// [`LAYERS_MIN`] widths, and it has no decal.
    pub(super) fn worth(row: &Row, w: usize) -> bool {
        let covered: i64 = row
            .masks
            .iter()
            .filter_map(|(_, rm)| rm.cov.full.map(|(a, b)| b - a + 1))
            .sum();
        covered >= LAYERS_MIN * w as i64
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
            row,
        };
        let mut behind = Behind {
            front: &self.front,
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
    /// Called for each fully covered pixel `i` with the fragment's `zc`.
    fn hides(&mut self, i: i64, zc: i64) -> bool;
}

/// Every fragment made.
pub(super) struct NoHiding;

impl Hiding for NoHiding {
    #[inline(always)]
    fn hides(&mut self, _: i64, _: i64) -> bool {
        false
    }
}

/// A triangle's fully covered fragments whose range starts beyond the pixel's `front`
/// are left out and counted, if the triangle passes the tag test (`test`, run at the
/// first such fragment).
struct Behind<'a, F: FnMut() -> bool> {
    front: &'a [i64],
    hidden: &'a mut [u32],
    /// The triangle's [`FragSetup::half_range`].
    half: i64,
    /// Fragments left out.
    count: u64,
    /// The tag test's outcome, once run.
    alone: Option<bool>,
    test: F,
}

impl<F: FnMut() -> bool> Hiding for Behind<'_, F> {
    #[inline(always)]
    fn hides(&mut self, i: i64, zc: i64) -> bool {
        let i = i as usize;
        if zc - self.half <= self.front[i] {
            return false;
        }
        if !*self.alone.get_or_insert_with(&mut self.test) {
            return false;
        }
        self.hidden[i] += 1;
        self.count += 1;
        true
    }
}

/// Most other triangles of its tag the tag test looks at for one triangle; with more it
/// fails (keeps the fragments), which bounds its cost where a tag is a mesh of many
/// overlapping parts.
const TAG_TEST_MAX: usize = 6;

/// The tag test on one row: the row's triangles in (tag, first touched
/// pixel) order (`by_tag`, with each entry's `reach`: the farthest touched pixel of its
/// tag's entries up to it) and their depth steppers (`zs`, `masks` order).
struct TagTest<'a> {
    by_tag: &'a [(u16, i64, i64, u32)],
    reach: &'a [i64],
    zs: &'a [RoundDivSteps],
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
        let mut met = 0;
        later.chain(earlier).filter(|u| u.2 >= fa).all(|u| {
            met += 1;
            if met > TAG_TEST_MAX {
                return false;
            }
            let y = u.3 as usize;
            apart(
                (t, self.zs[x], e.1),
                (&setups[masks[y].0 as usize], self.zs[y], u.1),
                (fa.max(u.1), fb.min(u.2)),
                self.row.j,
                self.row.size,
            )
        })
    }
}

/// Whether the depth ranges of the fragments of triangles `t` and `o` (each with its
/// depth stepper `z` from its first touched pixel `a`) stay apart on pixels `p..=q` of
/// row `j`. First bounded over the whole run ([`RoundDivSteps::bounds`]); if those bounds
/// meet, pixel by pixel.
fn apart(
    (t, tz, ta): (&FragSetup, RoundDivSteps, i64),
    (o, oz, oa): (&FragSetup, RoundDivSteps, i64),
    (p, q): (i64, i64),
    j: i64,
    size: MaskSize,
) -> bool {
    let (th, oh) = (t.half_range(size), o.half_range(size));
    let band = |z: RoundDivSteps, a: i64, half: i64| {
        let (lo, hi) = z.bounds((p - a) as u64, (q - a) as u64);
        (saturate_plane(lo) - half, saturate_plane(hi) + half)
    };
    let (tb, ob) = (band(tz, ta, th), band(oz, oa, oh));
    if tb.1 < ob.0 || ob.1 < tb.0 {
        return true;
    }
    let steps = (q - p + 1) as u64;
    let (tz, oz) = (t.depth_steps(p, j), o.depth_steps(p, j));
    match (tz.narrow(steps), oz.narrow(steps)) {
        (Some(tz), Some(oz)) => apart_each(tz, th, oz, oh, steps),
        _ => apart_each(tz, th, oz, oh, steps),
    }
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
