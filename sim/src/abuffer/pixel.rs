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
pub(super) fn merge_range(
    f: &Fragment,
    p: &DepthPick,
    size: MaskSize,
    interpenetrating: bool,
) -> (i64, i64) {
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

#[cfg(test)]
pub(in crate::abuffer) mod tests {
    use super::*;
    use crate::rng::XorShift64Star as Rng;
    use pixelproc_formats::abuffer::FragPlane;

    /// A random pixel: up to 12 fragments with masks that are full, empty-ish or random,
    /// a handful of depths close together (ties and overlapping ranges), few tags (so
    /// merges happen), some decals sharing a plane with a face.
    pub(in crate::abuffer) fn random_pixel(rng: &mut Rng, size: MaskSize) -> Vec<Fragment> {
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
}
