//! One pixel of the A-buffer (seed 000, JP2569952B2, background processes 2 and 3 and
//! step 7 of claim 1): ordering depths for pixels with two or more fragments, **merge** of
//! same-tag fragments with overlapping depth ranges, **packing** from a full free mask in
//! depth order, and the **resolve** weighting visible subpixels. The rules are stated in
//! the header of [`crate::abuffer`].

use super::Fragment;
use crate::mask_search::{DepthPick, DepthSelect, DepthSelector};
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_formats::I_FRAC;

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
    let denom = (size.bits() as u64) << I_FRAC;
    let free = packed.free.count_ones() as u64;
    let mut out = [0u8; 3];
    for (ch, o) in out.iter_mut().enumerate() {
        let mut sum = free * ((bg[ch] as u64) << I_FRAC);
        for (f, &v) in frags.iter().zip(&packed.visible) {
            sum += v.count_ones() as u64 * f.rgb_q12[ch] as u64;
        }
        *o = ((2 * sum + denom) / (2 * denom)).min(255) as u8;
    }
    out
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
