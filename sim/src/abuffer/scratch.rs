//! The A-buffer renderer's per-pixel work without allocating per pixel (seed 000,
//! JP2569952B2, background processes 2 and 3 and step 7 of claim 1): the same ordering
//! depths, merge, packing and resolve as the literal steps of [`super::pixel`]
//! ([`process_pixel`](super::process_pixel)), in buffers reused from pixel to pixel, with
//! a plain path for the common pixel (no decal, no interpenetration).

use super::pixel::{coplanar_common_depth, merge_range, resolve_bits};
use super::Fragment;
use crate::mask_search::{DepthPick, DepthSelect, DepthSelector};
use pixelproc_formats::abuffer::MaskSize;

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

/// One merged group as [`PixelScratch`] builds it (the fields of
/// [`Group`](super::Group) without the member list, plus the packing key's parts).
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

/// Reusable buffers for [`process_pixel`](super::process_pixel)'s work without allocating
/// per pixel: the same depth picks, merge (the connected components of "same tag,
/// overlapping range", which is what [`merge`](super::merge)'s repeated pairwise merging
/// produces, in order of first member), the same visible bits, and the same resolve.
///
/// Packing takes the groups in [`pack`](super::pack)'s order, each the minimum of the
/// packing keys not yet taken, and stops when no free bit is left: every later group's visible bits
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

    /// [`PixelScratch::process`] on the fragments a row made of a pixel whose hidden
    /// fragments it left out (see [`super::fragment::RowFrags`]; no decal, no
    /// interpenetration): the same outcome as on all of them, but for the depth picks of
    /// the hidden ones, which the row counts. A pixel of two or more fragments picks the
    /// depth of every fragment, so a lone fragment left (the full one in front) has its
    /// pick counted and takes every bit.
    #[inline]
    pub(crate) fn process_without_hidden(
        &mut self,
        frags: &[Fragment],
        sel: &DepthSelector,
        variant: DepthSelect,
        bg: [u8; 3],
        size: MaskSize,
    ) -> PixelSummary {
        let [f] = frags else {
            return self.process(frags, sel, variant, false, bg, size);
        };
        let full = size.full();
        let p = sel.select_nearest(variant, f.mask, &f.plane);
        self.visible.clear();
        self.visible.push(f.mask & full);
        let free = full & !f.mask;
        PixelSummary {
            rgb: resolve_bits(frags, &self.visible, free, bg, size),
            // The hidden fragments' masks are full.
            covered: full,
            evals: p.evals,
            steps: p.steps,
            merges: 0,
            free,
        }
    }

    /// [`process_pixel`](super::process_pixel) on one pixel's fragments (scene order).
    // Not inlined into the row loop, which calls it from two places (more instructions
    // there when it is, measured with callgrind).
    #[inline(never)]
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
    use super::super::pixel::tests::random_pixel;
    use super::super::process_pixel;
    use super::*;
    use crate::rng::XorShift64Star as Rng;

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
