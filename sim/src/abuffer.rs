//! The A-buffer: fragments per pixel, merge, packing and resolve, and a frame renderer.
//!
//! Implements seed 000 (JP2569952B2): the three A-buffer processes of its background
//! (mask generation in [`crate::mask`], **merge** of fraction masks with the same object tag
//! whose depths overlap, **packing** from a full free mask in depth order with contribution
//! = visible bits / (n·m)), with the fragment depth chosen per [`DepthSelect`] (claim 1 in
//! [`crate::mask_search`]) and the final weighting of subpixels (step 7).
//!
//! **Fragment.** Per pixel and triangle with a non-empty fraction mask: the mask, the
//! depth plane relative to the pixel centre ([`FragPlane`], Q.12, each coefficient rounded
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

use crate::mask::{MaskEdges, RowMasks};
use crate::mask_search::{DepthSelect, DepthSelector};
use crate::raster::edge::check_depths;
use crate::raster::rows::Bands;
use crate::raster::{round_div, PlaneStepper, RoundDivStep, RoundDivSteps};
use crate::setup::{ExactPlane, SetupError, SnappedTri};
use pixelproc_formats::abuffer::{saturate_plane, FragPlane, MaskSize, PLANE_FRAC};
use pixelproc_formats::{I_FRAC, MAX_SCREEN, SUBPIXEL_ONE};
use rayon::prelude::*;
use thiserror::Error;

mod pixel;
mod search_stream;
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

/// One fragment: a triangle's share of one pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fragment {
    /// Fraction mask (bit order of [`pixelproc_formats::abuffer`]).
    pub mask: u64,
    /// Depth plane relative to the pixel centre.
    pub plane: FragPlane,
    /// Colour at the pixel centre, Q8.12 per channel.
    pub rgb_q12: [u32; 3],
    /// Object tag.
    pub tag: u16,
    /// Decal: wins depth ties against non-decals.
    pub decal: bool,
    /// Triangle index in scene order (final tie-break).
    pub prim: u32,
}

impl ExactPlane {
    /// `round(v · 2^frac)` at the centre of pixel (i, j).
    fn at_centre(&self, i: i64, j: i64, frac: u32) -> i128 {
        let one = SUBPIXEL_ONE as i128;
        let (x, y) = (i as i128 * one + one / 2, j as i128 * one + one / 2);
        let num =
            (self.v0 * self.area2 + self.nx * (x - self.x0) + self.ny * (y - self.y0)) << frac;
        round_div(num, self.area2)
    }
}

/// Per-triangle fragment setup: edges for the masks, planes for depth and colour.
#[derive(Clone, Debug)]
pub struct FragSetup {
    /// The triangle's edges.
    pub edges: MaskEdges,
    z: ExactPlane,
    sx: i64,
    sy: i64,
    c: [ExactPlane; 3],
    /// Steps per pixel along a row of the depth plane (Q.12) and the colour planes: the
    /// same on every row, prepared once.
    steps: [RoundDivStep; 4],
    /// A flat triangle's colour (every colour plane constant: its value is the plane's
    /// `v0` exactly, `round(v0·area2 / area2)`), else `None`.
    flat: Option<[i128; 3]>,
    tag: u16,
    decal: bool,
    prim: u32,
}

impl FragSetup {
    /// Sets up triangle number `prim`. `Ok(None)` for a zero-area triangle.
    pub fn new(t: &SnappedTri, prim: u32, size: MaskSize) -> Result<Option<FragSetup>, SetupError> {
        // Depths (with the host's) are checked, coordinates only the triangle's own: the
        // host plane's coordinates are not range-checked here, unlike span setup.
        check_depths(t)?;
        let Some(edges) = MaskEdges::new(t, size)? else {
            return Ok(None);
        };
        let zp = match &t.host {
            Some(h) => ExactPlane::new(h.v, h.z.map(|x| x as i64)),
            None => ExactPlane::new(t.v, t.z.map(|x| x as i64)),
        };
        let Some(z) = zp else { return Ok(None) };
        let cp = |k: usize| ExactPlane::new(t.v, [0, 1, 2].map(|q| t.c[q][k] as i64));
        let (Some(c0), Some(c1), Some(c2)) = (cp(0), cp(1), cp(2)) else {
            return Ok(None);
        };
        let one = SUBPIXEL_ONE as i128;
        // Slope per offset unit (1/(2n) px): ∂z/∂x_q8 · 256 / (2n), in Q.12.
        let sx = saturate_plane(round_div(
            (z.nx * one) << PLANE_FRAC,
            z.area2 * 2 * size.n() as i128,
        ));
        let sy = saturate_plane(round_div(
            (z.ny * one) << PLANE_FRAC,
            z.area2 * 2 * size.m() as i128,
        ));
        let step = |p: &ExactPlane, frac: u32| RoundDivStep::new((p.nx * one) << frac, p.area2);
        let steps = [
            step(&z, PLANE_FRAC),
            step(&c0, 0),
            step(&c1, 0),
            step(&c2, 0),
        ];
        let c = [c0, c1, c2];
        let flat = c
            .iter()
            .all(|p| p.nx == 0 && p.ny == 0)
            .then(|| c.map(|p| p.v0));
        Ok(Some(FragSetup {
            edges,
            z,
            sx,
            sy,
            steps,
            flat,
            c,
            tag: t.tag,
            decal: t.host.is_some(),
            prim,
        }))
    }

    /// The depth plane at pixel (i, j).
    pub fn plane_at(&self, i: i64, j: i64) -> FragPlane {
        FragPlane {
            zc: saturate_plane(self.z.at_centre(i, j, PLANE_FRAC)),
            sx: self.sx,
            sy: self.sy,
        }
    }

    /// Steppers of the depth and colour planes along row `j` from pixel `i0`: the values
    /// [`FragSetup::fragment`] computes, pixel after pixel, with additions only.
    fn row_steps(&self, i0: i64, j: i64) -> [RoundDivSteps; 4] {
        let one = SUBPIXEL_ONE as i128;
        let (x, y) = (i0 as i128 * one + one / 2, j as i128 * one + one / 2);
        let at = |p: &ExactPlane, frac: u32, s: &RoundDivStep| {
            let num = (p.v0 * p.area2 + p.nx * (x - p.x0) + p.ny * (y - p.y0)) << frac;
            RoundDivSteps::start(num, s)
        };
        [
            at(&self.z, PLANE_FRAC, &self.steps[0]),
            at(&self.c[0], 0, &self.steps[1]),
            at(&self.c[1], 0, &self.steps[2]),
            at(&self.c[2], 0, &self.steps[3]),
        ]
    }

    /// The fragment whose depth and colour planes the steppers are at (see
    /// [`FragSetup::row_steps`]).
    #[inline]
    fn fragment_from<Z: PlaneStepper, C: PlaneStepper>(
        &self,
        z: &Z,
        c: &[C; 3],
        mask: u64,
    ) -> Fragment {
        let max = 255i128 << I_FRAC;
        Fragment {
            mask,
            plane: FragPlane {
                zc: saturate_plane(z.value()),
                sx: self.sx,
                sy: self.sy,
            },
            rgb_q12: c.map(|s| s.value().clamp(0, max) as u32),
            tag: self.tag,
            decal: self.decal,
            prim: self.prim,
        }
    }

    /// The fragment of pixel (i, j) with a given mask.
    pub fn fragment(&self, i: i64, j: i64, mask: u64) -> Fragment {
        let max = 255i128 << I_FRAC;
        Fragment {
            mask,
            plane: self.plane_at(i, j),
            rgb_q12: self.c.map(|p| p.at_centre(i, j, 0).clamp(0, max) as u32),
            tag: self.tag,
            decal: self.decal,
            prim: self.prim,
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

/// A rendered A-buffer frame.
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

/// Rows per bin band.
const BAND: i64 = 8;

/// Sets up every triangle for fragments (degenerate ones dropped) and bins them into bands
/// of [`BAND`] rows.
fn frag_setups(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    size: MaskSize,
) -> Result<(Vec<FragSetup>, Bands), AbufferError> {
    if width > MAX_SCREEN || height > MAX_SCREEN {
        return Err(AbufferError::ScreenTooLarge(width, height));
    }
    // Degenerate triangles dropped in the parallel pass itself (no serial copy of the
    // setups afterwards); the order is the input's.
    let setups: Vec<FragSetup> = tris
        .par_iter()
        .enumerate()
        .filter_map(|(k, t)| FragSetup::new(t, k as u32, size).transpose())
        .collect::<Result<_, _>>()?;
    let bands = Bands::new(
        BAND,
        height,
        setups.iter().map(|s| (s.edges.row_min, s.edges.row_max)),
    );
    Ok((setups, bands))
}

/// The fragments of one row grouped by pixel: `frags[start[i]..end[i]]` are pixel `i`'s,
/// in scene order. Buffers are reused from row to row.
///
/// Each pixel gets a run of slots as long as the number of triangles whose touched range
/// ([`crate::mask::RowCoverage`]) contains it (a difference array over the ranges, summed),
/// and every fragment is written straight into its pixel's run; a touched pixel whose
/// mask is empty leaves its slot unused.
#[derive(Default)]
struct RowFrags {
    /// The row's masks of the triangles that touch it: (setup index, masks), scene order.
    masks: Vec<(u32, RowMasks)>,
    /// Difference array of the touched ranges (`width + 1` entries).
    diff: Vec<i32>,
    /// Fragment slots, pixel after pixel.
    frags: Vec<Fragment>,
    /// First slot of each pixel; `width + 1` entries.
    start: Vec<u32>,
    /// One past the last fragment written for each pixel.
    end: Vec<u32>,
}

impl RowFrags {
    /// Generates the non-empty fraction masks of row `j` of the triangles
    /// `setups[members[..]]` (scene order) with their fragments, grouped by pixel.
    fn build(&mut self, j: i64, width: u32, setups: &[FragSetup], members: &[u32], size: MaskSize) {
        let w = width as usize;
        self.masks.clear();
        self.diff.clear();
        self.diff.resize(w + 1, 0);
        for &k in members {
            if let Some(rm) = setups[k as usize].edges.row_masks(j, width) {
                let (a, b) = rm.cov.touched;
                self.diff[a as usize] += 1;
                self.diff[b as usize + 1] -= 1;
                self.masks.push((k, rm));
            }
        }
        self.start.clear();
        self.start.push(0);
        let mut live = 0i32;
        for i in 0..w {
            live += self.diff[i];
            self.start.push(self.start[i] + live as u32);
        }
        self.end.clear();
        self.end.extend_from_slice(&self.start[..w]);
        let slots = self.start[w] as usize;
        if self.frags.len() < slots {
            self.frags.resize(slots, EMPTY_FRAGMENT);
        }
        let full = size.full();
        let (frags, end) = (&mut self.frags, &mut self.end);
        for (k, rm) in &self.masks {
            let t = &setups[*k as usize];
            let (a, b) = rm.cov.touched;
            let st = t.row_steps(a, j);
            let steps = (b - a + 1) as u64;
            let [z, c0, c1, c2] = st;
            match (z.narrow(steps), t.flat) {
                (Some(z), Some(rgb)) => emit(frags, end, t, rm, (z, rgb.map(Constant)), full),
                (None, Some(rgb)) => emit(frags, end, t, rm, (z, rgb.map(Constant)), full),
                (z64, None) => match (z64, [c0, c1, c2].map(|c| c.narrow(steps))) {
                    (Some(z), [Some(r), Some(g), Some(bl)]) => {
                        emit(frags, end, t, rm, (z, [r, g, bl]), full)
                    }
                    _ => emit(frags, end, t, rm, (z, [c0, c1, c2]), full),
                },
            }
        }
    }

    /// The fragments of pixel `i`.
    #[inline]
    fn pixel(&self, i: usize) -> &[Fragment] {
        &self.frags[self.start[i] as usize..self.end[i] as usize]
    }
}

/// Writes the fragments of one triangle's row into their pixels' slots (`end[i]` is pixel
/// `i`'s next free slot), the depth and colour planes stepped from the first touched
/// pixel.
#[inline]
fn emit<Z: PlaneStepper, C: PlaneStepper>(
    frags: &mut [Fragment],
    end: &mut [u32],
    t: &FragSetup,
    rm: &RowMasks,
    (mut z, mut c): (Z, [C; 3]),
    full: u64,
) {
    let rc = rm.cov;
    for i in rc.touched.0..=rc.touched.1 {
        let mask = match rc.full {
            Some((a, b)) if a <= i && i <= b => full,
            _ => rm.mask(i),
        };
        if mask != 0 {
            let at = &mut end[i as usize];
            frags[*at as usize] = t.fragment_from(&z, &c, mask);
            *at += 1;
        }
        z.advance();
        for s in c.iter_mut() {
            s.advance();
        }
    }
}

/// The value of a constant plane (a flat triangle's colour): the same at every pixel.
#[derive(Clone, Copy, Debug)]
struct Constant(i128);

impl PlaneStepper for Constant {
    #[inline]
    fn value(&self) -> i128 {
        self.0
    }
    #[inline]
    fn advance(&mut self) {}
}

/// A filler for fragment slots not yet written.
const EMPTY_FRAGMENT: Fragment = Fragment {
    mask: 0,
    plane: FragPlane {
        zc: 0,
        sx: 0,
        sy: 0,
    },
    rgb_q12: [0; 3],
    tag: 0,
    decal: false,
    prim: 0,
};

/// A pixel with two or more fragments (where the depth selection runs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MultiFragmentPixel {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// Its fragments in scene order, as the renderer builds them.
    pub fragments: Vec<Fragment>,
}

/// The multi-fragment pixels of a frame: every pixel with two or more fragments, row by
/// row, left to right, with the same fragments (masks, planes, colours) as
/// [`render_abuffer`] gives [`process_pixel`].
pub fn multi_fragment_pixels(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    size: MaskSize,
) -> Result<Vec<MultiFragmentPixel>, AbufferError> {
    let (setups, bands) = frag_setups(tris, width, height, size)?;
    let per_row: Vec<Vec<MultiFragmentPixel>> = (0..height as i64)
        .into_par_iter()
        .map(|j| {
            let band = bands.members(bands.of_row(j));
            let mut rf = RowFrags::default();
            rf.build(j, width, &setups, band, size);
            (0..width as usize)
                .filter(|&i| rf.pixel(i).len() >= 2)
                .map(|i| MultiFragmentPixel {
                    x: i as u32,
                    y: j as u32,
                    fragments: rf.pixel(i).to_vec(),
                })
                .collect()
        })
        .collect();
    Ok(per_row.into_iter().flatten().collect())
}

/// Renders triangles (scene order) with the A-buffer. Rows run in parallel with identical
/// results.
pub fn render_abuffer(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    params: &AbufferParams,
) -> Result<AbufferFrame, AbufferError> {
    let size = params.size;
    let (setups, bands) = frag_setups(tris, width, height, size)?;
    let sel = DepthSelector::new(size);
    let (w, h) = (width as usize, height as usize);
    let mut rgb = vec![0u8; w * h * 3];
    let mut coverage = vec![0u16; w * h];
    let mut fragments = vec![0u16; w * h];
    let mut visible = vec![-1i32; w * h];
    let stats = rgb
        .par_chunks_mut(w * 3)
        .zip(coverage.par_chunks_mut(w))
        .zip(fragments.par_chunks_mut(w))
        .zip(visible.par_chunks_mut(w))
        .enumerate()
        .map_init(
            RowScratch::default,
            |scratch, (j, (((rgb_row, cov_row), frag_row), vis_row))| {
                let band = bands.members(bands.of_row(j as i64));
                render_row(
                    j as i64,
                    width,
                    (&setups, band),
                    &sel,
                    params,
                    bg,
                    rgb_row,
                    cov_row,
                    frag_row,
                    vis_row,
                    scratch,
                )
            },
        )
        .reduce(AbufferStats::default, |mut a, b| {
            a.add(&b);
            a
        });
    Ok(AbufferFrame {
        width,
        height,
        rgb,
        coverage,
        fragments,
        visible,
        stats,
    })
}

/// Runs every depth-selection variant on one multi-fragment pixel and counts, per variant,
/// its evaluations and where its order, visible bits or colour differ from `exhaustive`.
fn compare_variants(
    frags: &[Fragment],
    sel: &DepthSelector,
    interpenetrating: bool,
    bg: [u8; 3],
    size: MaskSize,
    st: &mut AbufferStats,
) {
    let outs: Vec<PixelOut> = DepthSelect::ALL
        .iter()
        .map(|&v| process_pixel(frags, sel, v, interpenetrating, bg, size))
        .collect();
    let ex = &outs[3];
    for (v, o) in outs.iter().enumerate() {
        st.variant_evals[v] += o.evals as u64;
        st.order_diff[v] += (o.packed.order != ex.packed.order) as u64;
        st.visible_diff[v] += (o.packed.visible != ex.packed.visible) as u64;
        st.rgb_diff[v] += (o.rgb != ex.rgb) as u64;
    }
}

/// Renders one row; returns its statistics.
#[allow(clippy::too_many_arguments)]
fn render_row(
    j: i64,
    width: u32,
    (setups, members): (&[FragSetup], &[u32]),
    sel: &DepthSelector,
    params: &AbufferParams,
    bg: [u8; 3],
    rgb_row: &mut [u8],
    cov_row: &mut [u16],
    frag_row: &mut [u16],
    vis_row: &mut [i32],
    scratch: &mut RowScratch,
) -> AbufferStats {
    let size = params.size;
    let full = size.full();
    let mut st = AbufferStats::default();
    let RowScratch { rows, pixel } = scratch;
    rows.build(j, width, setups, members, size);
    for px in rgb_row.chunks_mut(3) {
        px.copy_from_slice(&bg);
    }
    for iu in 0..width as usize {
        let frags = rows.pixel(iu);
        if frags.is_empty() {
            continue;
        }
        st.fragments += frags.len() as u64;
        frag_row[iu] = frags.len() as u16;
        if frags.len() == 1 && frags[0].mask == full {
            // Fast path: one triangle covers the whole pixel.
            let f = &frags[0];
            rgb_row[3 * iu..3 * iu + 3].copy_from_slice(&pixel::resolve_bits(
                frags,
                &[full],
                0,
                bg,
                size,
            ));
            cov_row[iu] = size.bits() as u16;
            vis_row[iu] = f.prim as i32;
            st.fast_pixels += 1;
            continue;
        }
        let out = pixel.process(frags, sel, params.depth, params.interpenetrating, bg, size);
        rgb_row[3 * iu..3 * iu + 3].copy_from_slice(&out.rgb);
        cov_row[iu] = out.covered.count_ones() as u16;
        vis_row[iu] = pixel::dominant_bits(frags, pixel.visible(), out.free);
        st.merges += out.merges as u64;
        st.depth_evals += out.evals as u64;
        st.search_steps += out.steps as u64;
        if frags.len() >= 2 {
            st.multi_pixels += 1;
            st.sorted_fragments += frags.len() as u64;
            if params.compare_variants {
                compare_variants(frags, sel, params.interpenetrating, bg, size, &mut st);
            }
        }
    }
    st
}

/// Buffers one rendering thread reuses from row to row.
#[derive(Default)]
struct RowScratch {
    rows: RowFrags,
    pixel: pixel::PixelScratch,
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// Every fragment a row builds (stepped planes, 64-bit or not, flat colours) is the
    /// one computed directly at its pixel by exact division, with the edges' mask.
    #[test]
    fn row_fragments_equal_the_direct_ones() {
        let mut rng = crate::rng::Lcg64(0x00f1_a7c0);
        let (w, h) = (40u32, 24u32);
        let mut tris = Vec::new();
        for k in 0..60 {
            let mut p = || {
                [
                    (rng.range(-4.0, w as f64 + 4.0) * 256.0) as i32,
                    (rng.range(-4.0, h as f64 + 4.0) * 256.0) as i32,
                ]
            };
            let v = [p(), p(), p()];
            let z = [0; 3].map(|_| (rng.unit() * 16_000_000.0) as u32 + 16);
            let rgb =
                |rng: &mut crate::rng::Lcg64| [0; 3].map(|_| (rng.unit() * 255.0 * 4096.0) as u32);
            // Every other triangle flat (one colour at all three vertices).
            let c = if k % 2 == 0 {
                let one = rgb(&mut rng);
                [one; 3]
            } else {
                [rgb(&mut rng), rgb(&mut rng), rgb(&mut rng)]
            };
            tris.push(SnappedTri {
                v,
                z,
                c,
                tag: k as u16,
                ..Default::default()
            });
        }
        let size = MaskSize::S4X4;
        let set = frag_setups(&tris, w, h, size).unwrap();
        let flat = set.0.iter().filter(|t| t.flat.is_some()).count();
        assert!(flat > 20 && flat < set.0.len(), "{flat} flat");
        let mut rf = RowFrags::default();
        let mut compared = 0;
        for j in 0..h as i64 {
            rf.build(j, w, &set.0, set.1.members(set.1.of_row(j)), size);
            for i in 0..w as usize {
                let got = rf.pixel(i);
                let want: Vec<Fragment> = set
                    .0
                    .iter()
                    .filter_map(|t| {
                        let mask = t.edges.fraction_mask(i as i64, j);
                        (mask != 0).then(|| t.fragment(i as i64, j, mask))
                    })
                    .collect();
                assert_eq!(got, &want[..], "pixel ({i}, {j})");
                compared += want.len();
            }
        }
        assert!(compared > 2000, "{compared}");
    }

    #[test]
    fn multi_fragment_pixels_are_the_renderers() {
        // Two overlapping triangles and a third crossing both: the pixels listed are the
        // ones the renderer counts as multi-fragment, with as many fragments.
        let t = |v: [[i32; 2]; 3], z: u32, tag: u16| SnappedTri {
            v,
            z: [z; 3],
            c: [[128 << 12; 3]; 3],
            tag,
            ..Default::default()
        };
        let tris = [
            t([[100, 50], [3000, 400], [600, 2900]], 1000, 1),
            t([[2900, 100], [3100, 2800], [200, 1500]], 2000, 2),
            t([[0, 1300], [3200, 1200], [1600, 1400]], 500, 3),
        ];
        let p = AbufferParams::default();
        let f = render_abuffer(&tris, 14, 12, [0; 3], &p).unwrap();
        let m = multi_fragment_pixels(&tris, 14, 12, p.size).unwrap();
        assert_eq!(m.len() as u64, f.stats.multi_pixels);
        assert!(m.len() > 10);
        for px in &m {
            let at = (px.y * 14 + px.x) as usize;
            assert_eq!(px.fragments.len(), f.fragments[at] as usize);
            assert!(px.fragments.windows(2).all(|w| w[0].prim < w[1].prim));
        }
    }
}
