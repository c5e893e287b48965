//! One pixel of the A-buffer (seed 000, JP2569952B2, background processes 2 and 3 and
//! step 7 of claim 1): ordering depths for pixels with two or more fragments, **merge** of
//! same-tag fragments with overlapping depth ranges, **packing** from a full free mask in
//! depth order, and the **resolve** weighting visible subpixels. The rules are stated in
//! the header of [`crate::abuffer`].

use super::Fragment;
use crate::mask_search::{DepthPick, DepthSelect, DepthSelector};
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_formats::I_FRAC;

/// The seed-002 order of a pattern on its face (Nishita & Nakamae, §3: "pattern in front
/// of face"), applied before merge and packing: fragments whose depth planes are
/// identical, at least one of them a decal, are one surface, so they are compared at a
/// common point instead of at their own extreme subpixels. Every member of such a class
/// takes the class's nearest `zmin` (and farthest `zmax`), a depth of the shared plane
/// over the union of their masks; the packing keys then tie on depth and the tie order
/// decides (decal first, later decal over earlier). Other fragments keep their picks.
pub fn coplanar_common_depth(frags: &[Fragment], picks: &mut [DepthPick]) {
    if !frags.iter().any(|f| f.decal) {
        return;
    }
    let n = frags.len();
    for k in 0..n {
        let same = |q: &usize| frags[*q].plane == frags[k].plane;
        let mut class = (0..n).filter(same);
        if !class.clone().any(|q| frags[q].decal) || class.clone().count() < 2 {
            continue;
        }
        let zmin = class.clone().map(|q| picks[q].zmin).min();
        let zmax = class.by_ref().filter_map(|q| picks[q].zmax).max();
        if let Some(z) = zmin {
            picks[k].zmin = z;
        }
        if picks[k].zmax.is_some() {
            picks[k].zmax = zmax;
        }
    }
}

/// A merged group of fragments (indices into the pixel's fragment list).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// Member fragments, ascending index.
    pub parts: Vec<usize>,
    /// OR of the members' masks.
    pub mask: u64,
    /// Merge range (see the module header), Q.12.
    pub range: (i64, i64),
    /// Nearest ordering depth of the members.
    pub zmin: i64,
    /// Farthest ordering depth of the members (interpenetrating scenes), else `zmin`.
    pub zmax: i64,
}

/// The merge range of a fragment.
fn merge_range(f: &Fragment, p: &DepthPick, size: MaskSize, interpenetrating: bool) -> (i64, i64) {
    if interpenetrating {
        (p.zmin, p.zmax.unwrap_or(p.zmin))
    } else {
        let s = f.plane.sx.abs() * (size.n() as i64 - 1) + f.plane.sy.abs() * (size.m() as i64 - 1);
        (f.plane.zc - s, f.plane.zc + s)
    }
}

/// Merges fragments with the same tag whose ranges overlap, transitively. Groups come out
/// in order of their first member.
pub fn merge(
    frags: &[Fragment],
    picks: &[DepthPick],
    size: MaskSize,
    interpenetrating: bool,
) -> Vec<Group> {
    let mut groups: Vec<Group> = frags
        .iter()
        .zip(picks)
        .enumerate()
        .map(|(k, (f, p))| Group {
            parts: vec![k],
            mask: f.mask,
            range: merge_range(f, p, size, interpenetrating),
            zmin: p.zmin,
            zmax: p.zmax.unwrap_or(p.zmin),
        })
        .collect();
    'again: loop {
        for a in 0..groups.len() {
            for b in a + 1..groups.len() {
                let (ga, gb) = (&groups[a], &groups[b]);
                if frags[ga.parts[0]].tag == frags[gb.parts[0]].tag
                    && ga.range.0 <= gb.range.1
                    && gb.range.0 <= ga.range.1
                {
                    let gb = groups.remove(b);
                    let ga = &mut groups[a];
                    ga.parts.extend(gb.parts);
                    ga.parts.sort_unstable();
                    ga.mask |= gb.mask;
                    ga.range = (ga.range.0.min(gb.range.0), ga.range.1.max(gb.range.1));
                    ga.zmin = ga.zmin.min(gb.zmin);
                    ga.zmax = ga.zmax.max(gb.zmax);
                    continue 'again;
                }
            }
        }
        return groups;
    }
}

/// Result of packing one pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Packed {
    /// Fragment indices in packing order (groups in depth order, members in depth order).
    pub order: Vec<usize>,
    /// Visible bits per fragment (index as in the input).
    pub visible: Vec<u64>,
    /// Bits left free (background).
    pub free: u64,
}

/// Packs merged groups: free mask starts full and is ANDed away in depth order.
pub fn pack(frags: &[Fragment], picks: &[DepthPick], groups: &[Group], size: MaskSize) -> Packed {
    // Ties follow the pixel-processor array's depth test as a sort key (the order of
    // `raster::depth::tie_front`): decals first, among ordinary fragments the earlier
    // primitive wins (`Z < ZB`), among decals the later one (`Z ≤ ZB`).
    let tie = |k: usize| {
        let prim = frags[k].prim as i64;
        if frags[k].decal {
            -prim
        } else {
            prim
        }
    };
    let part_key = |k: usize| {
        let p = &picks[k];
        (p.zmin, p.zmax.unwrap_or(p.zmin), !frags[k].decal, tie(k))
    };
    let mut gorder: Vec<usize> = (0..groups.len()).collect();
    gorder.sort_by_key(|&g| {
        let gr = &groups[g];
        let decal = gr.parts.iter().any(|&k| frags[k].decal);
        let first = gr.parts.iter().map(|&k| tie(k)).min().unwrap_or(0);
        (gr.zmin, gr.zmax, !decal, first)
    });
    let mut free = size.full();
    let mut visible = vec![0u64; frags.len()];
    let mut order = Vec::with_capacity(frags.len());
    for g in gorder {
        let gr = &groups[g];
        let mut vis = gr.mask & free;
        free &= !gr.mask;
        let mut parts = gr.parts.clone();
        parts.sort_by_key(|&k| part_key(k));
        for k in parts {
            visible[k] = frags[k].mask & vis;
            vis &= !frags[k].mask;
            order.push(k);
        }
    }
    Packed {
        order,
        visible,
        free,
    }
}

/// Resolve: weights every fragment's colour by its visible bits and the background by the
/// free bits, rounding half up to 8 bits.
pub fn resolve(frags: &[Fragment], packed: &Packed, bg: [u8; 3], size: MaskSize) -> [u8; 3] {
    resolve_bits(frags, &packed.visible, packed.free, bg, size)
}

/// [`resolve`] on the visible bits per fragment and the free bits.
#[inline]
pub(crate) fn resolve_bits(
    frags: &[Fragment],
    visible: &[u64],
    free: u64,
    bg: [u8; 3],
    size: MaskSize,
) -> [u8; 3] {
    let denom = (size.bits() as u64) << I_FRAC;
    let free = free.count_ones() as u64;
    let mut sum = bg.map(|b| free * ((b as u64) << I_FRAC));
    for (f, &v) in frags.iter().zip(visible) {
        if v != 0 {
            let bits = v.count_ones() as u64;
            for (s, &c) in sum.iter_mut().zip(&f.rgb_q12) {
                *s += bits * c as u64;
            }
        }
    }
    // A grid of 2^k subpixels (4×4, 8×8, ...) divides by a power of two: a shift.
    if denom.is_power_of_two() {
        let shift = (2 * denom).trailing_zeros();
        sum.map(|s| ((2 * s + denom) >> shift).min(255) as u8)
    } else {
        sum.map(|s| ((2 * s + denom) / (2 * denom)).min(255) as u8)
    }
}

/// The visible-surface AOV of a pixel: the triangle with the most visible subpixels
/// (lowest index on a tie), or −1 when the free subpixels are at least as many.
pub(crate) fn dominant_bits(frags: &[Fragment], visible: &[u64], free: u64) -> i32 {
    let mut best = (-1i32, free.count_ones());
    for (f, v) in frags.iter().zip(visible) {
        let n = v.count_ones();
        if n > best.1 || (n == best.1 && best.0 >= 0 && (f.prim as i32) < best.0) {
            best = (f.prim as i32, n);
        }
    }
    best.0
}

/// Everything the renderer learns about one pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PixelOut {
    /// Resolved colour.
    pub rgb: [u8; 3],
    /// Union of the fragments' masks.
    pub covered: u64,
    /// Depth-calculator evaluations.
    pub evals: u32,
    /// Search-unit steps.
    pub steps: u32,
    /// Fragments absorbed by merging (`fragments − groups`).
    pub merges: u32,
    /// The packing result.
    pub packed: Packed,
}

/// Runs depth selection (if two or more fragments), merge, packing and resolve on one
/// pixel's fragments (scene order).
pub fn process_pixel(
    frags: &[Fragment],
    sel: &DepthSelector,
    variant: DepthSelect,
    interpenetrating: bool,
    bg: [u8; 3],
    size: MaskSize,
) -> PixelOut {
    let covered = frags.iter().fold(0, |a, f| a | f.mask);
    let (picks, evals, steps) = if frags.len() >= 2 {
        let picks: Vec<DepthPick> = frags
            .iter()
            .map(|f| sel.select(variant, f.mask, &f.plane, interpenetrating))
            .collect();
        let e = picks.iter().map(|p| p.evals).sum();
        let s = picks.iter().map(|p| p.steps).sum();
        let mut picks = picks;
        coplanar_common_depth(frags, &mut picks);
        (picks, e, s)
    } else {
        let p = frags.iter().map(|f| DepthPick {
            zmin: f.plane.zc,
            zmax: None,
            evals: 0,
            steps: 0,
        });
        (p.collect(), 0, 0)
    };
    let groups = merge(frags, &picks, size, interpenetrating);
    let packed = pack(frags, &picks, &groups, size);
    PixelOut {
        rgb: resolve(frags, &packed, bg, size),
        covered,
        evals,
        steps,
        merges: (frags.len() - groups.len()) as u32,
        packed,
    }
}

/// What the renderer keeps of one pixel processed by [`PixelScratch::process`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PixelSummary {
    /// Resolved colour.
    pub rgb: [u8; 3],
    /// Union of the fragments' masks.
    pub covered: u64,
    /// Depth-calculator evaluations.
    pub evals: u32,
    /// Search-unit steps.
    pub steps: u32,
    /// Fragments absorbed by merging.
    pub merges: u32,
    /// Bits left free (background).
    pub free: u64,
}

/// The packing key of a group: (zmin, zmax, not decal, first tie, first member). Unique
/// per group (the first member is).
type GroupKey = (i64, i64, bool, i64, usize);

/// One merged group as [`PixelScratch`] builds it (the fields of [`Group`] without the
/// member list, plus the packing key's parts).
#[derive(Clone, Copy, Debug)]
struct GroupAcc {
    mask: u64,
    zmin: i64,
    zmax: i64,
    decal: bool,
    first_tie: i64,
    first: usize,
    /// Number of members.
    parts: usize,
    /// Already packed.
    taken: bool,
}

impl GroupAcc {
    #[inline]
    fn key(&self) -> GroupKey {
        (
            self.zmin,
            self.zmax,
            !self.decal,
            self.first_tie,
            self.first,
        )
    }
}

/// A group's visible bits `vis` shared out among its members in packing order: each
/// takes the bits of its mask still left, until none is.
#[inline]
fn share_visible(
    visible: &mut [u64],
    frags: &[Fragment],
    order: impl Iterator<Item = usize>,
    mut vis: u64,
) {
    for q in order {
        if vis == 0 {
            break;
        }
        visible[q] = frags[q].mask & vis;
        vis &= !frags[q].mask;
    }
}

/// Most fragments a pixel may have for [`PixelScratch::process_plain`].
const PLAIN_MAX: usize = 16;

/// A merged group of [`PixelScratch::process_plain`].
#[derive(Clone, Copy, Debug, Default)]
struct PlainGroup {
    mask: u64,
    zmin: i64,
    zmax: i64,
    /// Smallest member primitive (the first tie, no member being a decal).
    prim: u32,
    /// First member.
    first: u32,
    /// Number of members.
    parts: u32,
}

impl PlainGroup {
    /// The packing key of [`GroupAcc::key`] without decals.
    #[inline]
    fn key(&self) -> (i64, i64, u32, u32) {
        (self.zmin, self.zmax, self.prim, self.first)
    }
}

/// The sweep key of the merge: tag, then range start (sign bit flipped so that the
/// unsigned order is the signed one), then fragment index, packed into one integer.
#[inline]
fn sweep_key(tag: u16, start: i64, k: usize) -> u128 {
    ((tag as u128) << 112) | (((start as u64 ^ (1 << 63)) as u128) << 48) | k as u128
}

/// Reusable buffers for [`process_pixel`]'s work without allocating per pixel: the same
/// depth picks, merge (the connected components of "same tag, overlapping range", which
/// is what [`merge`]'s repeated pairwise merging produces, in order of first member), the
/// same visible bits, and the same resolve.
///
/// Packing takes the groups in [`pack`]'s order, each the minimum of the packing keys
/// not yet taken, and stops when no free bit is left: every later group's visible bits
/// are `mask & 0`. In a pixel whose front surface covers it fully one group is taken
/// and nothing is sorted.
#[derive(Default)]
pub(crate) struct PixelScratch {
    picks: Vec<DepthPick>,
    ranges: Vec<(i64, i64)>,
    /// Sweep order of the merge ([`sweep_key`]).
    by_range: Vec<u128>,
    /// First member of each fragment's component.
    comp: Vec<usize>,
    groups: Vec<GroupAcc>,
    /// Group index per component (at its first member).
    grank: Vec<usize>,
    /// Members of the group being packed: (zmin, zmax, not decal, tie, fragment).
    parts: Vec<(i64, i64, bool, i64, usize)>,
    visible: Vec<u64>,
    /// The fixed-size buffers of [`PixelScratch::process_plain`].
    plain: PlainScratch,
}

/// Buffers of [`PixelScratch::process_plain`], indexed by fragment (or group): only the
/// first `n` entries of a pixel are read, each written first, so nothing is cleared
/// between pixels.
#[derive(Default)]
struct PlainScratch {
    zmin: [i64; PLAIN_MAX],
    hi: [i64; PLAIN_MAX],
    keys: [u128; PLAIN_MAX],
    groups: [PlainGroup; PLAIN_MAX],
    group_of: [u8; PLAIN_MAX],
}

impl PixelScratch {
    /// Visible bits per fragment of the last pixel processed.
    pub(crate) fn visible(&self) -> &[u64] {
        &self.visible
    }

    /// [`process_pixel`] on one pixel's fragments (scene order).
    pub(crate) fn process(
        &mut self,
        frags: &[Fragment],
        sel: &DepthSelector,
        variant: DepthSelect,
        interpenetrating: bool,
        bg: [u8; 3],
        size: MaskSize,
    ) -> PixelSummary {
        let n = frags.len();
        let covered = frags.iter().fold(0, |a, f| a | f.mask);
        self.visible.clear();
        if n <= 1 {
            // One fragment, one group: its bits are visible, the rest free (none: all
            // free).
            let mask = frags.first().map_or(0, |f| f.mask);
            let free = size.full() & !mask;
            self.visible
                .extend(frags.iter().map(|f| f.mask & size.full()));
            return PixelSummary {
                rgb: resolve_bits(frags, &self.visible, free, bg, size),
                covered,
                evals: 0,
                steps: 0,
                merges: 0,
                free,
            };
        }
        if !interpenetrating && n <= PLAIN_MAX && !frags.iter().any(|f| f.decal) {
            return self.process_plain(frags, sel, variant, bg, size, covered);
        }
        self.picks.clear();
        let (mut evals, mut steps) = (0, 0);
        for f in frags {
            let p = sel.select(variant, f.mask, &f.plane, interpenetrating);
            evals += p.evals;
            steps += p.steps;
            self.picks.push(p);
        }
        coplanar_common_depth(frags, &mut self.picks);
        let picks = &self.picks;
        // Merge: components of overlapping same-tag ranges, by a sweep in (tag, start)
        // order; a group's range is the union of its members' (they overlap), so two
        // groups overlap exactly when two of their members do.
        self.ranges.clear();
        self.ranges.extend(
            frags
                .iter()
                .zip(picks)
                .map(|(f, p)| merge_range(f, p, size, interpenetrating)),
        );
        self.comp.clear();
        self.comp.resize(n, 0);
        self.merge_sweep(frags);
        self.finish(frags, bg, size, covered, evals, steps)
    }

    /// [`PixelScratch::process`] on a pixel of 2..=[`PLAIN_MAX`] fragments without decals
    /// in a scene without interpenetrating surfaces, the common case, in fixed-size arrays:
    /// the same picks, merge, packing and resolve with what is constant there folded. No
    /// pick has a `zmax` (so a fragment's is its `zmin`, a group's the largest member
    /// `zmin`), no coplanar class exists, the merge range is the plane's, and every tie is
    /// the primitive number: groups pack by (zmin, zmax, smallest primitive, first member),
    /// members by (zmin, primitive, index).
    fn process_plain(
        &mut self,
        frags: &[Fragment],
        sel: &DepthSelector,
        variant: DepthSelect,
        bg: [u8; 3],
        size: MaskSize,
        covered: u64,
    ) -> PixelSummary {
        let n = frags.len();
        let PlainScratch {
            zmin,
            hi,
            keys,
            groups,
            group_of,
        } = &mut self.plain;
        let (mut evals, mut steps) = (0, 0);
        for (k, f) in frags.iter().enumerate() {
            let p = sel.select_nearest(variant, f.mask, &f.plane);
            evals += p.evals;
            steps += p.steps;
            zmin[k] = p.zmin;
            let (lo, h) = merge_range(f, &p, size, false);
            hi[k] = h;
            keys[k] = sweep_key(f.tag, lo, k);
        }
        let single = |q: usize| PlainGroup {
            mask: frags[q].mask,
            zmin: zmin[q],
            zmax: zmin[q],
            prim: frags[q].prim,
            first: q as u32,
            parts: 1,
        };
        let mut ng = 0;
        if (1..n).all(|a| (0..a).all(|b| frags[a].tag != frags[b].tag)) {
            // No two fragments share a tag: nothing merges, every fragment is a group
            // (the packing order does not depend on the order of the groups).
            for (q, g) in groups[..n].iter_mut().enumerate() {
                *g = single(q);
            }
            ng = n;
        } else {
            let keys = &mut keys[..n];
            keys.sort_unstable();
            // The merge sweep of `merge_sweep`, each component made a group as it closes.
            let member = |key: u128| (key & ((1 << 48) - 1)) as usize;
            let start = |key: u128| ((key >> 48) as u64 ^ (1 << 63)) as i64;
            let mut k = 0;
            while k < n {
                let head = member(keys[k]);
                let (tag, mut h) = (frags[head].tag, hi[head]);
                let mut e = k + 1;
                while e < n {
                    let q = member(keys[e]);
                    if frags[q].tag != tag || start(keys[e]) > h {
                        break;
                    }
                    h = h.max(hi[q]);
                    e += 1;
                }
                let mut g = single(head);
                g.parts = (e - k) as u32;
                for &key in &keys[k + 1..e] {
                    let q = member(key);
                    g.mask |= frags[q].mask;
                    g.zmin = g.zmin.min(zmin[q]);
                    g.zmax = g.zmax.max(zmin[q]);
                    g.prim = g.prim.min(frags[q].prim);
                    g.first = g.first.min(q as u32);
                }
                for &key in &keys[k..e] {
                    group_of[member(key)] = ng as u8;
                }
                groups[ng] = g;
                ng += 1;
                k = e;
            }
        }
        let groups = &groups[..ng];
        // Packing, until no bit is free.
        let mut free = size.full();
        self.visible.resize(n, 0);
        let mut taken = 0u32;
        while free != 0 {
            let mut best: Option<usize> = None;
            for (g, gr) in groups.iter().enumerate() {
                if taken & (1 << g) == 0 && best.is_none_or(|b| gr.key() < groups[b].key()) {
                    best = Some(g);
                }
            }
            let Some(g) = best else {
                break;
            };
            taken |= 1 << g;
            let gr = &groups[g];
            let vis = gr.mask & free;
            free &= !gr.mask;
            if gr.parts == 1 {
                let q = gr.first as usize;
                self.visible[q] = frags[q].mask & vis;
                continue;
            }
            let mut parts = [(0i64, 0u32, 0usize); PLAIN_MAX];
            let mut np = 0;
            for q in gr.first as usize..n {
                if group_of[q] as usize == g {
                    parts[np] = (zmin[q], frags[q].prim, q);
                    np += 1;
                }
            }
            let parts = &mut parts[..np];
            parts.sort_unstable();
            share_visible(&mut self.visible, frags, parts.iter().map(|p| p.2), vis);
        }
        PixelSummary {
            rgb: resolve_bits(frags, &self.visible, free, bg, size),
            covered,
            evals,
            steps,
            merges: (n - ng) as u32,
            free,
        }
    }

    /// The merge sweep in (tag, start) order: sets `comp` (first member of each
    /// fragment's component) from `ranges`.
    fn merge_sweep(&mut self, frags: &[Fragment]) {
        let n = frags.len();
        let ranges = &self.ranges;
        self.by_range.clear();
        self.by_range
            .extend((0..n).map(|k| sweep_key(frags[k].tag, ranges[k].0, k)));
        self.by_range.sort_unstable();
        let member = |key: u128| (key & ((1 << 48) - 1)) as usize;
        let mut k = 0;
        while k < n {
            // A component: a run of the sweep whose ranges chain.
            let head = member(self.by_range[k]);
            let (tag, mut hi) = (frags[head].tag, ranges[head].1);
            let mut first = head;
            let mut e = k + 1;
            while e < n {
                let q = member(self.by_range[e]);
                if frags[q].tag != tag || ranges[q].0 > hi {
                    break;
                }
                hi = hi.max(ranges[q].1);
                first = first.min(q);
                e += 1;
            }
            for &key in &self.by_range[k..e] {
                self.comp[member(key)] = first;
            }
            k = e;
        }
    }

    /// Groups, packing and resolve of [`PixelScratch::process`] once `picks` and `comp`
    /// are set.
    fn finish(
        &mut self,
        frags: &[Fragment],
        bg: [u8; 3],
        size: MaskSize,
        covered: u64,
        evals: u32,
        steps: u32,
    ) -> PixelSummary {
        let n = frags.len();
        let picks = &self.picks;
        // Groups in order of first member.
        let tie = |k: usize| {
            let prim = frags[k].prim as i64;
            if frags[k].decal {
                -prim
            } else {
                prim
            }
        };
        self.groups.clear();
        self.grank.clear();
        self.grank.resize(n, usize::MAX);
        for k in 0..n {
            let p = &picks[k];
            let (zmin, zmax) = (p.zmin, p.zmax.unwrap_or(p.zmin));
            let c = self.comp[k];
            if c == k {
                self.grank[k] = self.groups.len();
                self.groups.push(GroupAcc {
                    mask: frags[k].mask,
                    zmin,
                    zmax,
                    decal: frags[k].decal,
                    first_tie: tie(k),
                    first: k,
                    parts: 1,
                    taken: false,
                });
            } else {
                let g = &mut self.groups[self.grank[c]];
                g.mask |= frags[k].mask;
                g.zmin = g.zmin.min(zmin);
                g.zmax = g.zmax.max(zmax);
                g.decal |= frags[k].decal;
                g.first_tie = g.first_tie.min(tie(k));
                g.parts += 1;
            }
        }
        // Packing: groups by (zmin, zmax, decal first, first tie, first member), members
        // by (zmin, zmax, decal first, tie, index), until no bit is free.
        let mut free = size.full();
        self.visible.resize(n, 0);
        while free != 0 {
            let mut best: Option<(usize, GroupKey)> = None;
            for (g, gr) in self.groups.iter().enumerate() {
                if !gr.taken && best.is_none_or(|(_, b)| gr.key() < b) {
                    best = Some((g, gr.key()));
                }
            }
            let Some((g, _)) = best else {
                break;
            };
            let gr = &mut self.groups[g];
            gr.taken = true;
            let vis = gr.mask & free;
            free &= !gr.mask;
            if gr.parts == 1 {
                self.visible[gr.first] = frags[gr.first].mask & vis;
                continue;
            }
            let head = gr.first;
            self.parts.clear();
            self.parts
                .extend((head..n).filter(|&q| self.comp[q] == head).map(|q| {
                    let p = &picks[q];
                    (p.zmin, p.zmax.unwrap_or(p.zmin), !frags[q].decal, tie(q), q)
                }));
            self.parts.sort_unstable();
            share_visible(
                &mut self.visible,
                frags,
                self.parts.iter().map(|p| p.4),
                vis,
            );
        }
        PixelSummary {
            rgb: resolve_bits(frags, &self.visible, free, bg, size),
            covered,
            evals,
            steps,
            merges: (n - self.groups.len()) as u32,
            free,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift64Star as Rng;
    use pixelproc_formats::abuffer::FragPlane;

    /// A random pixel: up to 12 fragments with masks that are full, empty-ish or random,
    /// a handful of depths close together (ties and overlapping ranges), few tags (so
    /// merges happen), some decals sharing a plane with a face.
    fn random_pixel(rng: &mut Rng, size: MaskSize) -> Vec<Fragment> {
        let n = 1 + (rng.next_u64() % 12) as usize;
        let mut out: Vec<Fragment> = Vec::new();
        for k in 0..n {
            let mask = match rng.next_u64() % 4 {
                0 | 1 => size.full(),
                2 => rng.next_u64() & size.full() | 1,
                _ => 1u64 << (rng.next_u64() % size.bits() as u64),
            };
            let small = |rng: &mut Rng, m: u64| (rng.next_u64() % m) as i64 - (m / 2) as i64;
            let mut plane = FragPlane {
                zc: 1000 + small(rng, 8) * 300,
                sx: small(rng, 5) * 40,
                sy: small(rng, 5) * 40,
            };
            let decal = rng.next_u64().is_multiple_of(5);
            if decal && !out.is_empty() {
                plane = out[(rng.next_u64() % out.len() as u64) as usize].plane;
            }
            out.push(Fragment {
                mask,
                plane,
                rgb_q12: [0; 3].map(|_| (rng.next_u64() % (256 << 12)) as u32),
                tag: (rng.next_u64() % 3) as u16,
                decal,
                prim: k as u32 * 3 + (rng.next_u64() % 3) as u32,
            });
        }
        out
    }

    /// The resolve's shift on power-of-two grids is the rounded division, on random
    /// pixels of every grid kind (the division itself on the others).
    #[test]
    fn resolve_shift_is_the_division() {
        let mut rng = Rng(0x0005_1f7d);
        for (n, m) in [(4, 4), (8, 8), (2, 2), (3, 5), (8, 1)] {
            let size = MaskSize::new(n, m).unwrap();
            for _ in 0..3000 {
                let frags = random_pixel(&mut rng, size);
                let visible: Vec<u64> = frags
                    .iter()
                    .map(|f| f.mask & rng.next_u64() & size.full())
                    .collect();
                let free = rng.next_u64() & size.full();
                let bg = [0; 3].map(|_| rng.next_u64() as u8);
                let denom = (size.bits() as u64) << I_FRAC;
                let mut sum = bg.map(|b| free.count_ones() as u64 * ((b as u64) << I_FRAC));
                for (f, v) in frags.iter().zip(&visible) {
                    for (s, &c) in sum.iter_mut().zip(&f.rgb_q12) {
                        *s += v.count_ones() as u64 * c as u64;
                    }
                }
                let want = sum.map(|s| ((2 * s + denom) / (2 * denom)).min(255) as u8);
                assert_eq!(resolve_bits(&frags, &visible, free, bg, size), want);
            }
        }
    }

    /// The scratch path gives what the literal merge and pack of [`process_pixel`] give,
    /// on every variant, with and without interpenetration, with and without decals (the
    /// pixels without decals in scenes without interpenetration take
    /// [`PixelScratch::process_plain`]).
    #[test]
    fn scratch_equals_process_pixel() {
        let mut rng = Rng(0x005e_edab);
        let mut scratch = PixelScratch::default();
        let mut plain = 0;
        for size in [MaskSize::S4X4, MaskSize::S8X8] {
            let sel = DepthSelector::new(size);
            for case in 0..8000 {
                let mut frags = random_pixel(&mut rng, size);
                if case % 2 == 1 {
                    frags.iter_mut().for_each(|f| f.decal = false);
                }
                plain +=
                    (case % 3 != 0 && frags.len() >= 2 && !frags.iter().any(|f| f.decal)) as usize;
                let variant = DepthSelect::ALL[case % 4];
                let inter = case % 3 == 0;
                let bg = [17, 200, 99];
                let want = process_pixel(&frags, &sel, variant, inter, bg, size);
                let got = scratch.process(&frags, &sel, variant, inter, bg, size);
                let ctx = format!("{frags:?} {variant:?} {inter}");
                assert_eq!(got.rgb, want.rgb, "{ctx}");
                assert_eq!(got.covered, want.covered, "{ctx}");
                assert_eq!(got.evals, want.evals, "{ctx}");
                assert_eq!(got.steps, want.steps, "{ctx}");
                assert_eq!(got.merges, want.merges, "{ctx}");
                assert_eq!(got.free, want.packed.free, "{ctx}");
                assert_eq!(scratch.visible(), &want.packed.visible[..], "{ctx}");
            }
        }
        assert!(plain > 4000, "{plain} pixels on the plain path");
    }
}
