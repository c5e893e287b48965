//! Fragments of the A-buffer (seed 000, JP2569952B2, background process 1: mask
//! generation, and the fragment each mask is stored with): per pixel and triangle the
//! fraction mask from [`crate::mask`], the depth plane relative to the pixel centre
//! ([`FragPlane`]) and the colour at the pixel centre, built row by row for the frame
//! renderer in [`super`]. The rules are stated in the header of [`super`].

use super::AbufferError;
use crate::mask::{MaskEdges, RowMasks};
use crate::raster::edge::check_depths;
use crate::raster::rows::Bands;
use crate::raster::{round_div, PlaneStepper, RoundDivStep, RoundDivSteps, RoundDivSteps64};
use crate::setup::{ExactPlane, SetupError, SnappedTri};
use pixelproc_formats::abuffer::{saturate_plane, FragPlane, MaskSize, PLANE_FRAC};
use pixelproc_formats::{I_FRAC, MAX_SCREEN, SUBPIXEL_ONE};
use rayon::prelude::*;

mod hidden;
pub(super) use hidden::Hidden;
use hidden::{HiddenRow, Hiding, NoHiding, Row, HIDE_BLOCK};

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
///
/// In the order each row reads them (`repr(C)`): the edges, which every row tests for
/// every triangle of its band, first; then what every fragment copies; then the depth
/// plane and the steps; the colour planes, which only shaded triangles read, last.
#[derive(Clone, Debug)]
#[repr(C)]
pub struct FragSetup {
    /// The triangle's edges.
    pub edges: MaskEdges,
    tag: u16,
    decal: bool,
    prim: u32,
    sx: i64,
    sy: i64,
    /// A flat triangle's colour (every colour plane constant: its value is the plane's
    /// `v0` exactly, `round(v0·area2 / area2)`), else `None`.
    flat: Option<[i128; 3]>,
    z: ExactPlane,
    /// Steps per pixel along a row of the depth plane (Q.12) and the colour planes: the
    /// same on every row, prepared once.
    steps: [RoundDivStep; 4],
    c: [ExactPlane; 3],
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

    /// Half the width of a fragment's depth range over its pixel's subpixel centres,
    /// `|sx|·(n − 1) + |sy|·(m − 1)`: the range is `zc ±` this (the merge range without
    /// interpenetration, [`super::pixel::merge_range`]).
    #[inline]
    fn half_range(&self, size: MaskSize) -> i64 {
        self.sx.abs() * (size.n() as i64 - 1) + self.sy.abs() * (size.m() as i64 - 1)
    }

    /// The depth plane at pixel (i, j).
    pub fn plane_at(&self, i: i64, j: i64) -> FragPlane {
        FragPlane {
            zc: saturate_plane(self.z.at_centre(i, j, PLANE_FRAC)),
            sx: self.sx,
            sy: self.sy,
        }
    }

    /// The stepper of plane `p` (step `s`, `frac` fractional bits) along row `j` from
    /// pixel `i0`: the values [`FragSetup::fragment`] computes, pixel after pixel, with
    /// additions only.
    #[inline(always)]
    fn row_step(p: &ExactPlane, frac: u32, s: &RoundDivStep, i0: i64, j: i64) -> RoundDivSteps {
        let one = SUBPIXEL_ONE as i128;
        let (x, y) = (i0 as i128 * one + one / 2, j as i128 * one + one / 2);
        let num = (p.v0 * p.area2 + p.nx * (x - p.x0) + p.ny * (y - p.y0)) << frac;
        RoundDivSteps::start(num, s)
    }

    /// The depth plane's stepper along row `j` from pixel `i0` ([`FragSetup::row_step`]).
    #[inline(always)]
    fn depth_steps(&self, i0: i64, j: i64) -> RoundDivSteps {
        Self::row_step(&self.z, PLANE_FRAC, &self.steps[0], i0, j)
    }

    /// The colour planes' steppers along row `j` from pixel `i0` ([`FragSetup::row_step`]);
    /// a flat triangle never needs them.
    #[inline(always)]
    fn colour_steps(&self, i0: i64, j: i64) -> [RoundDivSteps; 3] {
        [0, 1, 2].map(|k| Self::row_step(&self.c[k], 0, &self.steps[k + 1], i0, j))
    }

    /// The fragment whose depth plane the stepper is at (see [`FragSetup::depth_steps`]),
    /// with colour `rgb_q12` ([`RowColour`]).
    #[inline]
    fn fragment_from<Z: PlaneStepper>(&self, z: &Z, rgb_q12: [u32; 3], mask: u64) -> Fragment {
        Fragment {
            mask,
            plane: FragPlane {
                zc: saturate_plane(z.value()),
                sx: self.sx,
                sy: self.sy,
            },
            rgb_q12,
            tag: self.tag,
            decal: self.decal,
            prim: self.prim,
        }
    }

    /// The fragment of pixel (i, j) with a given mask.
    pub fn fragment(&self, i: i64, j: i64, mask: u64) -> Fragment {
        Fragment {
            mask,
            plane: self.plane_at(i, j),
            rgb_q12: self.c.map(|p| clamp_q12(p.at_centre(i, j, 0))),
            tag: self.tag,
            decal: self.decal,
            prim: self.prim,
        }
    }
}

/// Rows per bin band.
const BAND: i64 = 8;

/// Sets up every triangle for fragments (degenerate ones dropped) and bins them into bands
/// of [`BAND`] rows.
pub(super) fn frag_setups(
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
/// mask is empty leaves its slot unused. With [`Hidden`], fragments that cannot change
/// their pixel are counted instead of made ([`hidden`]).
#[derive(Default)]
pub(super) struct RowFrags {
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
    /// The hidden fragments left out of the row, and the tests' buffers.
    hidden: HiddenRow,
}

impl RowFrags {
    /// Generates the non-empty fraction masks of row `j` of the triangles
    /// `setups[members[..]]` (scene order) with their fragments, grouped by pixel.
    pub(super) fn build(
        &mut self,
        j: i64,
        width: u32,
        setups: &[FragSetup],
        members: &[u32],
        size: MaskSize,
    ) {
        let mut masks = std::mem::take(&mut self.masks);
        masks.clear();
        for &k in members {
            if let Some(rm) = setups[k as usize].edges.row_masks(j, width) {
                masks.push((k, rm));
            }
        }
        self.build_from(j, width, setups, &masks, size, None);
        self.masks = masks;
    }

    /// The fragments of row `j` from its masks `masks` (setup index and masks of every
    /// triangle that touches the row, scene order), grouped by pixel; with `hidden`, the
    /// hidden fragments are left out and counted (see [`RowFrags`]) where the row has no
    /// decal.
    pub(super) fn build_from(
        &mut self,
        j: i64,
        width: u32,
        setups: &[FragSetup],
        masks: &[(u32, RowMasks)],
        size: MaskSize,
        hidden: Option<Hidden<'_>>,
    ) {
        let w = width as usize;
        self.diff.clear();
        self.diff.resize(w + 1, 0);
        for (_, rm) in masks {
            let (a, b) = rm.cov.touched;
            self.diff[a as usize] += 1;
            self.diff[b as usize + 1] -= 1;
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
        self.hidden.clear();
        let row = Row {
            setups,
            masks,
            j,
            size,
        };
        let hidden = hidden.filter(|_| HiddenRow::worth(&row, w));
        if hidden.is_some() {
            self.hidden.prepare(&row, w);
        }
        for (x, (k, rm)) in masks.iter().enumerate() {
            let mut slots = Slots {
                frags: &mut self.frags,
                end: &mut self.end,
            };
            match hidden {
                Some(h) => self.hidden.emit(h, x, &mut slots, &row),
                None => {
                    let t = &setups[*k as usize];
                    let z = t.depth_steps(rm.cov.touched.0, j);
                    emit_triangle(&mut slots, t, rm, z, j, full, &mut NoHiding);
                }
            }
        }
    }

    /// Hidden fragments left out of pixel `i` (none without [`Hidden`]).
    #[cfg(test)]
    pub(super) fn hidden_at(&self, i: usize) -> u32 {
        self.hidden.per_pixel().get(i).copied().unwrap_or(0)
    }

    /// Hidden fragments left out per pixel, or no entries if the row left none out.
    #[inline]
    pub(super) fn hidden_row(&self) -> &[u32] {
        self.hidden.per_pixel()
    }

    /// The depth pick's evaluations and steps of the row's hidden fragments.
    pub(super) fn hidden_counts(&self) -> (u64, u64) {
        self.hidden.counts()
    }

    /// The fragments of pixel `i`.
    #[inline]
    pub(super) fn pixel(&self, i: usize) -> &[Fragment] {
        &self.frags[self.start[i] as usize..self.end[i] as usize]
    }
}

/// The masks of the rows of one band: per row, the setup index and [`RowMasks`] of every
/// triangle that touches it, in scene order. Each triangle's edges are set up once for the
/// band ([`MaskEdges::band_row_masks`]) instead of once per row. Buffers are reused from
/// band to band.
#[derive(Default)]
pub(super) struct BandMasks {
    /// First row of the band.
    j0: i64,
    rows: Vec<Vec<(u32, RowMasks)>>,
}

impl BandMasks {
    /// The masks of rows `j0..=j1` of the triangles `setups[members[..]]` (scene order).
    pub(super) fn fill(
        &mut self,
        (j0, j1): (i64, i64),
        width: u32,
        setups: &[FragSetup],
        members: &[u32],
    ) {
        let n = (j1 - j0 + 1).max(0) as usize;
        if self.rows.len() < n {
            self.rows.resize_with(n, Vec::new);
        }
        self.rows.iter_mut().for_each(Vec::clear);
        self.j0 = j0;
        let rows = &mut self.rows;
        for &k in members {
            setups[k as usize]
                .edges
                .band_row_masks(j0, j1, width, |j, rm| rows[(j - j0) as usize].push((k, rm)));
        }
    }

    /// The masks of row `j` of the band.
    pub(super) fn row(&self, j: i64) -> &[(u32, RowMasks)] {
        &self.rows[(j - self.j0) as usize]
    }
}

/// A row's fragment slots, pixel after pixel, and each pixel's next free slot.
struct Slots<'a> {
    frags: &'a mut [Fragment],
    end: &'a mut [u32],
}

/// Writes the fragments of triangle `t`'s row `j` into their pixels' slots, the depth
/// stepped by `z` from the first touched pixel, the colour by the cheapest stepper that
/// gives the same values.
#[inline(always)]
fn emit_triangle<H: Hiding>(
    slots: &mut Slots<'_>,
    t: &FragSetup,
    rm: &RowMasks,
    z: RoundDivSteps,
    j: i64,
    full: u64,
    hiding: &mut H,
) {
    let (a, b) = rm.cov.touched;
    let steps = (b - a + 1) as u64;
    match (z.narrow(steps), t.flat) {
        (Some(z), Some(rgb)) => emit(slots, t, rm, (z, Flat::of(rgb)), full, hiding),
        (None, Some(rgb)) => emit(slots, t, rm, (z, Flat::of(rgb)), full, hiding),
        (z64, None) => {
            let [c0, c1, c2] = t.colour_steps(a, j);
            match (z64, [c0, c1, c2].map(|c| c.narrow(steps))) {
                (Some(z), [Some(r), Some(g), Some(bl)]) => {
                    let c = [r, g, bl];
                    if c.iter().all(|s| s.stays_within(steps, 0, COLOUR_Q12_MAX)) {
                        emit(slots, t, rm, (z, InRange(c)), full, hiding)
                    } else {
                        emit(slots, t, rm, (z, c), full, hiding)
                    }
                }
                _ => emit(slots, t, rm, (z, [c0, c1, c2]), full, hiding),
            }
        }
    }
}

/// Writes the fragments of one triangle's row into their pixels' slots (`end[i]` is pixel
/// `i`'s next free slot), the depth and colour planes stepped from the first touched
/// pixel; a fully covered fragment `hiding` hides is not written.
#[inline]
fn emit<Z: PlaneStepper, C: RowColour, H: Hiding>(
    slots: &mut Slots<'_>,
    t: &FragSetup,
    rm: &RowMasks,
    (mut z, mut c): (Z, C),
    full: u64,
    hiding: &mut H,
) {
    let Slots { frags, end } = slots;
    let rc = rm.cov;
    const BLOCK_U: u64 = HIDE_BLOCK as u64;
    // The steppers' jumps over a block, prepared at the first hidden block.
    let mut jumps: Option<(Z::Jump, C::Jump)> = None;
    let mut i = rc.touched.0;
    while i <= rc.touched.1 {
        let mask = match rc.full {
            Some((a, b)) if a <= i && i <= b => {
                // A whole block of fully covered pixels at once where `hiding` hides it.
                if H::BLOCKS && i % HIDE_BLOCK == 0 && i + HIDE_BLOCK - 1 <= b {
                    let zlo = saturate_plane(z.lower(BLOCK_U - 1));
                    if hiding.hides_block(i, zlo) {
                        let (jz, jc) =
                            jumps.get_or_insert_with(|| (z.jump_by(BLOCK_U), c.jump_by(BLOCK_U)));
                        z.jump(jz);
                        c.jump(jc);
                        i += HIDE_BLOCK;
                        continue;
                    }
                }
                if hiding.hides(i, saturate_plane(z.value())) {
                    z.advance();
                    c.advance();
                    i += 1;
                    continue;
                }
                full
            }
            _ => rm.mask(i),
        };
        if mask != 0 {
            let at = &mut end[i as usize];
            frags[*at as usize] = t.fragment_from(&z, c.rgb_q12(), mask);
            *at += 1;
        }
        z.advance();
        c.advance();
        i += 1;
    }
}

/// The largest colour value, 255 in Q8.12.
const COLOUR_Q12_MAX: i64 = 255 << I_FRAC;

/// A colour plane's value clamped to `0..=COLOUR_Q12_MAX`, a fragment's channel.
#[inline]
fn clamp_q12(v: i128) -> u32 {
    v.clamp(0, COLOUR_Q12_MAX as i128) as u32
}

/// A fragment's colour along a row of pixels: Q8.12 per channel, each colour plane's value
/// clamped to `0..=COLOUR_Q12_MAX`.
trait RowColour {
    /// The colour at the current pixel.
    fn rgb_q12(&self) -> [u32; 3];
    /// Moves one pixel on.
    fn advance(&mut self);
    /// `k` pixels prepared as one move ([`PlaneStepper::Jump`]).
    type Jump: Copy;
    /// Prepares [`RowColour::jump`] by `k` pixels.
    fn jump_by(&self, k: u64) -> Self::Jump;
    /// Moves on by the pixels `j` was prepared for.
    fn jump(&mut self, j: &Self::Jump);
}

/// A flat triangle's colour (every colour plane constant), clamped once: the same at
/// every pixel.
#[derive(Clone, Copy, Debug)]
struct Flat([u32; 3]);

impl Flat {
    /// The colour of the constant planes `rgb`.
    #[inline]
    fn of(rgb: [i128; 3]) -> Flat {
        Flat(rgb.map(clamp_q12))
    }
}

impl RowColour for Flat {
    #[inline]
    fn rgb_q12(&self) -> [u32; 3] {
        self.0
    }
    #[inline]
    fn advance(&mut self) {}
    type Jump = ();
    fn jump_by(&self, _: u64) {}
    #[inline]
    fn jump(&mut self, _: &()) {}
}

/// The three colour planes stepped, each value clamped.
impl<S: PlaneStepper> RowColour for [S; 3] {
    #[inline]
    fn rgb_q12(&self) -> [u32; 3] {
        self.map(|s| clamp_q12(s.value()))
    }
    #[inline]
    fn advance(&mut self) {
        self.iter_mut().for_each(|s| s.advance());
    }
    type Jump = [S::Jump; 3];
    fn jump_by(&self, k: u64) -> Self::Jump {
        self.map(|s| s.jump_by(k))
    }
    #[inline]
    fn jump(&mut self, j: &Self::Jump) {
        self.iter_mut().zip(j).for_each(|(s, j)| s.jump(j));
    }
}

/// The three colour planes stepped in 64 bits over a run that
/// [`RoundDivSteps64::stays_within`] `0..=COLOUR_Q12_MAX` at every pixel: the clamp is the
/// identity there and is left out.
#[derive(Clone, Copy, Debug)]
struct InRange([RoundDivSteps64; 3]);

impl RowColour for InRange {
    #[inline]
    fn rgb_q12(&self) -> [u32; 3] {
        self.0.map(|s| s.value() as u32)
    }
    #[inline]
    fn advance(&mut self) {
        self.0.iter_mut().for_each(|s| s.advance());
    }
    type Jump = [<RoundDivSteps64 as PlaneStepper>::Jump; 3];
    fn jump_by(&self, k: u64) -> Self::Jump {
        self.0.map(|s| s.jump_by(k))
    }
    #[inline]
    fn jump(&mut self, j: &Self::Jump) {
        self.0.iter_mut().zip(j).for_each(|(s, j)| s.jump(j));
    }
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

#[cfg(test)]
mod tests {
    use super::*;

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
            // Channels at either end of the range as often as inside it: fragments of
            // pixels whose centre lies outside the triangle extrapolate past the ends, where
            // the clamp acts.
            let rgb = |rng: &mut crate::rng::Lcg64| {
                [0; 3].map(|_| match rng.step() % 3 {
                    0 => 0,
                    1 => 255 << I_FRAC,
                    _ => (rng.unit() * 255.0 * 4096.0) as u32,
                })
            };
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
        let (mut compared, mut clamped) = (0, 0);
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
                clamped += set
                    .0
                    .iter()
                    .filter(|t| t.edges.fraction_mask(i as i64, j) != 0)
                    .filter(|t| {
                        t.c.iter().any(|p| {
                            let v = p.at_centre(i as i64, j, 0);
                            !(0..=255 << I_FRAC).contains(&v)
                        })
                    })
                    .count();
            }
        }
        assert!(
            compared > 2000 && clamped > 100,
            "{compared} fragments, {clamped} clamped"
        );
    }
}
