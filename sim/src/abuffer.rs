//! The A-buffer: fragments per pixel, merge, packing and resolve, and a frame renderer.
//!
//! Implements seed 000 (JP2569952B2): the three A-buffer processes of its background
//! (mask generation in [`crate::mask`], **merge** of fraction masks with the same object tag
//! whose depths overlap, **packing** from a full free mask in depth order with contribution
//! = visible bits / (n·m)), with the fragment depth chosen per [`DepthSelect`] (claim 1 in
//! [`crate::mask_search`]) and the final weighting of subpixels (step 7).
//!
//! **Fragment** ([`Fragment`], built in `abuffer/fragment.rs`). Per pixel and triangle
//! with a non-empty fraction mask: the mask, the depth plane relative to the pixel centre
//! ([`FragPlane`](pixelproc_formats::abuffer::FragPlane), Q.12, each coefficient rounded
//! once, half up, from the exact `i128` plane through the snapped vertices as in
//! [`crate::setup`]), the colour at the pixel centre (Q8.12 per channel, rounded once and
//! clamped to 0..=255), the object tag, and the triangle's index (scene order).
//!
//! **Ordering depth.** Only pixels with two or more fragments need an order; the variant
//! runs there and nowhere else (a lone fragment's depth is never evaluated).
//!
//! **Merge.** Fragments with the same tag whose depth ranges overlap (closed intervals)
//! become one group, transitively. The range of a fragment is `[zmin, zmax]` of the variant
//! when the scene declares interpenetrating surfaces (the max search runs); otherwise it is
//! the plane's range over all subpixel centres of the pixel, `zc ± (|sx|·(n−1) + |sy|·(m−1))`,
//! which needs no depth evaluation and contains the depth of every covered subpixel. A
//! group's mask is the OR of its parts, its depth the min of theirs.
//!
//! **Patterns on their face.** Before merge, fragments with identical depth planes of
//! which at least one is a decal (a pattern lying on its host face) take one common
//! ordering depth, the nearest (farthest) pick of the class ([`coplanar_common_depth`]):
//! they are compared at a common point, not each at its own extreme subpixel, and the
//! tie order below puts the pattern in front of its face (seed 002, §3). The search unit
//! and its picks are unchanged; every other fragment keeps its own pick.
//!
//! **Packing.** Groups in order of `(zmin, zmax, decal first, first triangle index)`; the
//! free mask starts full; a group's visible bits are `mask & free`, then `free &= !mask`.
//! Inside a group the visible bits go to its parts in the same order, each bit once.
//!
//! **Resolve.** `rgb = round_half_up((Σ visible_bits·rgb_q12 + free_bits·(bg << 12)) /
//! (n·m·2^12))` per channel.

use crate::mask_search::DepthSelect;
use crate::setup::SetupError;
use pixelproc_formats::abuffer::MaskSize;
use pixelproc_formats::MAX_SCREEN;
use thiserror::Error;

mod fragment;
mod frame;
mod pixel;
mod scratch;
mod search_stream;
pub use fragment::{FragSetup, Fragment};
pub use frame::{multi_fragment_pixels, render_abuffer, render_abuffer_with, MultiFragmentPixel};
pub use pixel::{
    coplanar_common_depth, merge, pack, process_pixel, resolve, Group, Packed, PixelOut,
};
pub use search_stream::{search_stream, SearchRequest};

/// Why a frame cannot be rendered.
#[derive(Debug, Error, PartialEq)]
pub enum AbufferError {
    /// A triangle cannot be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The screen is larger than the formats allow.
    #[error("screen {0}x{1} exceeds {MAX_SCREEN}x{MAX_SCREEN}")]
    ScreenTooLarge(u32, u32),
}

/// Options of the A-buffer renderer (`--aa abuffer --mask .. --depth ..`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AbufferParams {
    /// Subpixel grid.
    pub size: MaskSize,
    /// Depth-selection variant.
    pub depth: DepthSelect,
    /// The scene declares interpenetrating surfaces: also search the max depth and merge on
    /// `[zmin, zmax]`.
    pub interpenetrating: bool,
    /// Also run every other variant on each multi-fragment pixel and count where it orders
    /// or resolves differently from `exhaustive` (slower; for reports).
    pub compare_variants: bool,
}

impl Default for AbufferParams {
    fn default() -> Self {
        AbufferParams {
            size: MaskSize::S4X4,
            depth: DepthSelect::Search,
            interpenetrating: false,
            compare_variants: false,
        }
    }
}

/// Frame statistics.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AbufferStats {
    /// Fragments generated (non-empty masks).
    pub fragments: u64,
    /// Pixels with two or more fragments (where depth selection runs).
    pub multi_pixels: u64,
    /// Fragments in those pixels (the ones that get an ordering depth).
    pub sorted_fragments: u64,
    /// Fragments absorbed by merging.
    pub merges: u64,
    /// Depth-calculator evaluations of the chosen variant.
    pub depth_evals: u64,
    /// Search-unit steps of the chosen variant.
    pub search_steps: u64,
    /// Pixels resolved on the fast path (one fragment, full mask).
    pub fast_pixels: u64,
    /// With `compare_variants`: per variant (order of [`DepthSelect::ALL`]) depth evaluations.
    pub variant_evals: [u64; 4],
    /// With `compare_variants`: pixels whose packing order differs from `exhaustive`.
    pub order_diff: [u64; 4],
    /// With `compare_variants`: pixels whose visible bits per fragment differ from
    /// `exhaustive`.
    pub visible_diff: [u64; 4],
    /// With `compare_variants`: pixels whose resolved colour differs from `exhaustive`.
    pub rgb_diff: [u64; 4],
}

impl AbufferStats {
    fn add(&mut self, o: &AbufferStats) {
        self.fragments += o.fragments;
        self.multi_pixels += o.multi_pixels;
        self.sorted_fragments += o.sorted_fragments;
        self.merges += o.merges;
        self.depth_evals += o.depth_evals;
        self.search_steps += o.search_steps;
        self.fast_pixels += o.fast_pixels;
        for k in 0..4 {
            self.variant_evals[k] += o.variant_evals[k];
            self.order_diff[k] += o.order_diff[k];
            self.visible_diff[k] += o.visible_diff[k];
            self.rgb_diff[k] += o.rgb_diff[k];
        }
    }
}

/// Which per-pixel outputs besides the image [`render_abuffer_with`] makes; the image and
/// the statistics are the same whichever are asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AbufferAovs {
    /// [`AbufferFrame::coverage`].
    pub coverage: bool,
    /// [`AbufferFrame::fragments`].
    pub fragments: bool,
    /// [`AbufferFrame::visible`].
    pub visible: bool,
}

impl AbufferAovs {
    /// Every output.
    pub const ALL: AbufferAovs = AbufferAovs {
        coverage: true,
        fragments: true,
        visible: true,
    };
    /// The image only.
    pub const NONE: AbufferAovs = AbufferAovs {
        coverage: false,
        fragments: false,
        visible: false,
    };
}

/// A rendered A-buffer frame. An output that was not asked for ([`AbufferAovs`]) is empty.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AbufferFrame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGB8, row-major.
    pub rgb: Vec<u8>,
    /// Coverage AOV: covered subpixels per pixel (0..=n·m), row-major.
    pub coverage: Vec<u16>,
    /// Fragment-count AOV: fragments per pixel before merging, row-major.
    pub fragments: Vec<u16>,
    /// Visible-surface AOV, row-major: the input index of the triangle with the most
    /// visible subpixels after packing (lowest index on a tie), or −1 when the free
    /// (background) subpixels are at least as many.
    pub visible: Vec<i32>,
    /// Statistics.
    pub stats: AbufferStats,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask_search::DepthSelector;
    use pixelproc_formats::abuffer::FragPlane;

    fn frag(mask: u64, zc: i64, rgb: u8, tag: u16, prim: u32) -> Fragment {
        Fragment {
            mask,
            plane: FragPlane { zc, sx: 0, sy: 0 },
            rgb_q12: [(rgb as u32) << 12; 3],
            tag,
            decal: false,
            prim,
        }
    }

    fn run(frags: &[Fragment], bg: u8) -> PixelOut {
        let size = MaskSize::S4X4;
        process_pixel(
            frags,
            &DepthSelector::new(size),
            DepthSelect::Exhaustive,
            false,
            [bg; 3],
            size,
        )
    }

    #[test]
    fn packing_front_fragment_hides_overlap() {
        // Front: left half (cols 0,1 = 0xCCCC, 8 bits), white. Back: top half (rows 0,1 =
        // 0x00FF, 8 bits), grey 100. Overlap = 4 bits (top-left quarter) goes to the front.
        // Visible: front 8, back 4, background 4 (black):
        // (8·255 + 4·100 + 4·0) / 16 = 152.5 → 153.
        let f = [
            frag(0x00FF, 20 << 12, 100, 1, 0),
            frag(0xCCCC, 10 << 12, 255, 2, 1),
        ];
        let o = run(&f, 0);
        assert_eq!(o.packed.order, vec![1, 0]);
        assert_eq!(o.packed.visible, vec![0x0033, 0xCCCC]);
        assert_eq!(o.packed.free, 0x3300);
        assert_eq!(o.rgb, [153; 3]);
        assert_eq!(o.covered.count_ones(), 12);
    }

    #[test]
    fn merge_needs_same_tag_and_overlapping_range() {
        // Two same-tag fragments at 10 and 30 with a different-tag one at 20 in between,
        // covering everything. Flat planes: ranges are points, no overlap, no merge: the
        // order is 10, 20, 30 and the one at 30 is hidden.
        let a = frag(0xCCCC, 10 << 12, 200, 7, 0);
        let b = frag(0x3333, 30 << 12, 200, 7, 1);
        let c = frag(0xFFFF, 20 << 12, 50, 8, 2);
        let o = run(&[a, b, c], 0);
        assert_eq!(o.merges, 0);
        assert_eq!(o.packed.visible, vec![0xCCCC, 0, 0x3333]);
        // Give a and b the slope sx = 4 per offset unit: their pixel ranges become
        // 10 ± 4·3 = [-2, 22] and 30 ± 12 = [18, 42], which overlap, so they merge.
        let mut a2 = a;
        let mut b2 = b;
        a2.plane.sx = 4 << 12;
        b2.plane.sx = 4 << 12;
        let o = run(&[a2, b2, c], 0);
        assert_eq!(o.merges, 1);
        // The merged group sorts by its nearest depth (a's subpixel at dx = -3: 10 - 12 =
        // -2), in front of c: both halves visible (the merge rule's documented effect).
        assert_eq!(o.packed.visible, vec![0xCCCC, 0x3333, 0]);
        assert_eq!(o.rgb, [200; 3]);
        // A different tag never merges.
        b2.tag = 9;
        assert_eq!(run(&[a2, b2, c], 0).merges, 0);
    }

    #[test]
    fn resolve_rounds_half_up_against_background() {
        // One bit of 255 on background 0: 255/16 = 15.94 → 16.
        let o = run(&[frag(1, 0, 255, 0, 0)], 0);
        assert_eq!(o.rgb, [16; 3]);
        // 8 bits of 1 on background 0: 0.5 → 1.
        let o = run(&[frag(0xFF, 0, 1, 0, 0)], 0);
        assert_eq!(o.rgb, [1; 3]);
    }
}
