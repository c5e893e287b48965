//! The A-buffer's frame renderer (seed 000, JP2569952B2, background processes 1 to 3 and
//! step 7 of claim 1, frame by frame): bands of rows in parallel, each row's fragments
//! made once ([`RowFrags`], hidden ones left out), each pixel merged, packed and resolved
//! ([`PixelScratch`](super::scratch::PixelScratch)), its outputs and statistics summed.

use super::fragment::{frag_setups, BandMasks, Hidden, RowFrags};
use super::{
    pixel, process_pixel, scratch, AbufferAovs, AbufferError, AbufferFrame, AbufferParams,
    AbufferStats, FragSetup, Fragment, PixelOut,
};
use crate::mask::RowMasks;
use crate::mask_search::{DepthSelect, DepthSelector};
use crate::setup::SnappedTri;
use pixelproc_formats::abuffer::MaskSize;
use rayon::prelude::*;
use std::cell::RefCell;
use thread_local::ThreadLocal;

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

/// Renders triangles (scene order) with the A-buffer, every output. Bands of rows run in parallel
/// with identical results.
pub fn render_abuffer(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    params: &AbufferParams,
) -> Result<AbufferFrame, AbufferError> {
    render_abuffer_with(tris, width, height, bg, params, AbufferAovs::ALL)
}

/// The rows of a `w`-wide buffer, or `h` empty rows when the buffer is not made.
fn rows_of<T>(v: &mut [T], w: usize, h: usize) -> Vec<&mut [T]> {
    if v.is_empty() {
        (0..h).map(|_| <&mut [T]>::default()).collect()
    } else {
        v.chunks_mut(w).collect()
    }
}

/// Row `r` of a band of `w`-wide rows, or an empty row when the buffer is not made.
fn band_row<T>(band: &mut [T], w: usize, r: usize) -> &mut [T] {
    if band.is_empty() {
        band
    } else {
        &mut band[w * r..w * (r + 1)]
    }
}

/// [`render_abuffer`] making only the per-pixel outputs in `aovs` (the others are empty).
pub fn render_abuffer_with(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    params: &AbufferParams,
    aovs: AbufferAovs,
) -> Result<AbufferFrame, AbufferError> {
    render_frame(tris, width, height, bg, params, aovs, true)
}

/// [`render_abuffer_with`]; `leave_out_hidden` lets rows leave hidden fragments out
/// ([`RowFrags`]), which changes no output. They are all made when the frame compares
/// variants or has interpenetrating surfaces.
fn render_frame(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    bg: [u8; 3],
    params: &AbufferParams,
    aovs: AbufferAovs,
    leave_out_hidden: bool,
) -> Result<AbufferFrame, AbufferError> {
    let size = params.size;
    let (setups, bands) = frag_setups(tris, width, height, size)?;
    let sel = DepthSelector::new(size);
    let hidden = (leave_out_hidden && !params.interpenetrating && !params.compare_variants)
        .then_some(Hidden {
            sel: &sel,
            variant: params.depth,
        });
    let (w, h) = (width as usize, height as usize);
    let len = |want: bool| if want { w * h } else { 0 };
    let mut rgb = vec![0u8; w * h * 3];
    let mut coverage = vec![0u16; len(aovs.coverage)];
    let mut fragments = vec![0u16; len(aovs.fragments)];
    let mut visible = vec![-1i32; len(aovs.visible)];
    // One scratch per worker thread for the whole frame (rayon's `map_init` would make a
    // new one for every piece of work it splits off, growing its buffers again each time).
    let scratch: ThreadLocal<RefCell<RowScratch>> = ThreadLocal::new();
    // Bands of rows in parallel: each band's masks are made once for its rows.
    let bh = bands.band() as usize;
    let nb = bands.len();
    let frame = Frame {
        width,
        setups: &setups,
        sel: &sel,
        hidden,
        params,
        bg,
    };
    let stats = rgb
        .par_chunks_mut((w * 3 * bh).max(1))
        .zip(rows_of(&mut coverage, w * bh, nb))
        .zip(rows_of(&mut fragments, w * bh, nb))
        .zip(rows_of(&mut visible, w * bh, nb))
        .enumerate()
        .map(|(b, (((rgb_band, cov_band), frag_band), vis_band))| {
            let sc = &mut *scratch.get_or_default().borrow_mut();
            let (j0, j1) = bands.rows(b);
            sc.band.fill((j0, j1), width, &setups, bands.members(b));
            let mut st = AbufferStats::default();
            for j in j0..=j1 {
                let r = (j - j0) as usize;
                let out = RowOut {
                    rgb: &mut rgb_band[w * 3 * r..w * 3 * (r + 1)],
                    coverage: band_row(cov_band, w, r),
                    fragments: band_row(frag_band, w, r),
                    visible: band_row(vis_band, w, r),
                };
                st.add(&frame.render_row(j, sc.band.row(j), out, &mut sc.rows, &mut sc.pixel));
            }
            st
        })
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

/// What every row of a frame reads: its width, the triangles' setups, the depth
/// selection, whether rows leave hidden fragments out, the parameters and the background.
struct Frame<'a> {
    width: u32,
    setups: &'a [FragSetup],
    sel: &'a DepthSelector,
    hidden: Option<Hidden<'a>>,
    params: &'a AbufferParams,
    bg: [u8; 3],
}

/// One row of the frame's outputs; a per-pixel output not asked for is empty.
struct RowOut<'a> {
    rgb: &'a mut [u8],
    coverage: &'a mut [u16],
    fragments: &'a mut [u16],
    visible: &'a mut [i32],
}

impl Frame<'_> {
    /// Renders row `j` from its masks (setup index and masks of every triangle that
    /// touches it, scene order) into `out`; returns its statistics.
    fn render_row(
        &self,
        j: i64,
        masks: &[(u32, RowMasks)],
        out: RowOut<'_>,
        rows: &mut RowFrags,
        pixel: &mut scratch::PixelScratch,
    ) -> AbufferStats {
        let Frame {
            width,
            setups,
            sel,
            hidden,
            params,
            bg,
        } = *self;
        let RowOut {
            rgb: rgb_row,
            coverage: cov_row,
            fragments: frag_row,
            visible: vis_row,
        } = out;
        let size = params.size;
        let full = size.full();
        let mut st = AbufferStats::default();
        rows.build_from(j, width, setups, masks, size, hidden);
        (st.depth_evals, st.search_steps) = rows.hidden_counts();
        for px in rgb_row.chunks_exact_mut(3) {
            let [r, g, b] = bg;
            px[0] = r;
            px[1] = g;
            px[2] = b;
        }
        let hidden_row = rows.hidden_row();
        for iu in 0..width as usize {
            let frags = rows.pixel(iu);
            // The pixel's fragments: those made and the hidden ones left out.
            let n = frags.len() + hidden_row.get(iu).map_or(0, |&h| h as usize);
            if n == 0 {
                continue;
            }
            st.fragments += n as u64;
            if let Some(f) = frag_row.get_mut(iu) {
                *f = n as u16;
            }
            if n == 1 && frags[0].mask == full {
                // Fast path: one triangle covers the whole pixel.
                let f = &frags[0];
                rgb_row[3 * iu..3 * iu + 3].copy_from_slice(&pixel::resolve_bits(
                    frags,
                    &[full],
                    0,
                    bg,
                    size,
                ));
                if let Some(c) = cov_row.get_mut(iu) {
                    *c = size.bits() as u16;
                }
                if let Some(v) = vis_row.get_mut(iu) {
                    *v = f.prim as i32;
                }
                st.fast_pixels += 1;
                continue;
            }
            let out = if frags.len() == n {
                pixel.process(frags, sel, params.depth, params.interpenetrating, bg, size)
            } else {
                pixel.process_without_hidden(frags, sel, params.depth, bg, size)
            };
            rgb_row[3 * iu..3 * iu + 3].copy_from_slice(&out.rgb);
            if let Some(c) = cov_row.get_mut(iu) {
                *c = out.covered.count_ones() as u16;
            }
            if let Some(v) = vis_row.get_mut(iu) {
                *v = pixel::dominant_bits(frags, pixel.visible(), out.free);
            }
            st.merges += out.merges as u64;
            st.depth_evals += out.evals as u64;
            st.search_steps += out.steps as u64;
            if n >= 2 {
                st.multi_pixels += 1;
                st.sorted_fragments += n as u64;
                if params.compare_variants {
                    compare_variants(frags, sel, params.interpenetrating, bg, size, &mut st);
                }
            }
        }
        st
    }
}

/// Buffers one rendering thread reuses from row to row.
#[derive(Default)]
struct RowScratch {
    band: BandMasks,
    rows: RowFrags,
    pixel: scratch::PixelScratch,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each per-pixel output asked for alone is the one of the full render, an output
    /// not asked for is empty, and the image and statistics never change.
    #[test]
    fn outputs_asked_for_are_the_full_renders() {
        let (w, h) = (41u32, 23u32);
        let tris = crate::rng::random_tris(0x0ab0_0f00, 90, w, h);
        let p = AbufferParams::default();
        let all = render_abuffer(&tris, w, h, [3, 4, 5], &p).unwrap();
        assert_eq!(all.coverage.len(), (w * h) as usize);
        assert!(all.stats.multi_pixels > 100, "{:?}", all.stats);
        let only = |aovs| render_abuffer_with(&tris, w, h, [3, 4, 5], &p, aovs).unwrap();
        let none = only(AbufferAovs::NONE);
        assert_eq!((&none.rgb, &none.stats), (&all.rgb, &all.stats));
        assert!(none.coverage.is_empty() && none.fragments.is_empty() && none.visible.is_empty());
        let cov = only(AbufferAovs {
            coverage: true,
            ..AbufferAovs::NONE
        });
        assert_eq!((&cov.rgb, &cov.coverage), (&all.rgb, &all.coverage));
        assert!(cov.fragments.is_empty() && cov.visible.is_empty());
        let frag = only(AbufferAovs {
            fragments: true,
            ..AbufferAovs::NONE
        });
        assert_eq!(frag.fragments, all.fragments);
        let vis = only(AbufferAovs {
            visible: true,
            ..AbufferAovs::NONE
        });
        assert_eq!((&vis.visible, &vis.stats), (&all.visible, &all.stats));
    }

    /// A scene of walls one behind another, as `closeup` and the city are: quads (two
    /// triangles on one plane, one tag) at random depths and slants (every fifth level, at
    /// one of three depths, so that depths tie), some of them the front and back of a thin
    /// slab (one tag, a gap that is sometimes under a pixel's depth range, so their ranges
    /// overlap), a few triangles of any shape, `tags` tags shared between walls, flat and
    /// shaded colours, and with `decals` a decal on some walls.
    fn layered_scene(rng: &mut crate::rng::Lcg64, decals: bool, tags: u64) -> Vec<SnappedTri> {
        use pixelproc_formats::{Z_GEOM_MAX, Z_GEOM_MIN};
        let mut tris = Vec::new();
        let span = (Z_GEOM_MAX - Z_GEOM_MIN) as f64;
        let colour = |rng: &mut crate::rng::Lcg64| {
            let c = [0; 3].map(|_| (rng.unit() * 255.0 * 4096.0) as u32);
            if rng.step().is_multiple_of(2) {
                [c; 3]
            } else {
                [c, [0; 3].map(|_| (rng.unit() * 255.0 * 4096.0) as u32), c]
            }
        };
        for w in 0..30 {
            let tag = (rng.step() % tags) as u16;
            let (x0, y0) = (
                (rng.unit() * 40.0 - 10.0) * 256.0,
                (rng.unit() * 30.0 - 8.0) * 256.0,
            );
            let (x1, y1) = (
                x0 + (16.0 + rng.unit() * 40.0) * 256.0,
                y0 + (6.0 + rng.unit() * 30.0) * 256.0,
            );
            let z0 = Z_GEOM_MIN as f64 + span * (0.05 + 0.8 * rng.unit());
            let (gx, gy) = (
                (rng.unit() - 0.5) * 2e-4 * span,
                (rng.unit() - 0.5) * 2e-4 * span,
            );
            // Every fifth wall level, at one of three depths: walls exactly as deep as
            // each other, and as another wall's nearest depth, tie.
            let (z0, gx, gy) = if w % 5 == 2 {
                let level = Z_GEOM_MIN as f64 + span * [0.3, 0.5, 0.7][(rng.step() % 3) as usize];
                (level, 0.0, 0.0)
            } else {
                (z0, gx, gy)
            };
            let slabs = if rng.step().is_multiple_of(3) { 2 } else { 1 };
            let gap = span * [0.0, 1e-6, 1e-5, 1e-4, 1e-3][(rng.step() % 5) as usize];
            for s in 0..slabs {
                let z = |x: f64, y: f64| {
                    (z0 + s as f64 * gap + gx * (x - x0) / 256.0 + gy * (y - y0) / 256.0)
                        .clamp(Z_GEOM_MIN as f64, Z_GEOM_MAX as f64) as u32
                };
                let v = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
                    .map(|[x, y]| ([x as i32, y as i32], z(x, y)));
                let c = colour(rng);
                for [a, b, d] in [[0, 1, 2], [0, 2, 3]] {
                    tris.push(SnappedTri {
                        v: [v[a].0, v[b].0, v[d].0],
                        z: [v[a].1, v[b].1, v[d].1],
                        c,
                        tag,
                        ..Default::default()
                    });
                }
                if decals && s == 0 && w % 4 == 1 {
                    // A decal on the wall's first triangle: a smaller triangle inside it.
                    let host = tris[tris.len() - 2];
                    let m = |p: usize, q: usize| {
                        [
                            (host.v[p][0] + host.v[q][0]) / 2,
                            (host.v[p][1] + host.v[q][1]) / 2,
                        ]
                    };
                    tris.push(SnappedTri {
                        v: [m(0, 1), m(1, 2), m(2, 0)],
                        z: [host.z[0]; 3],
                        c: colour(rng),
                        tag,
                        host: Some(crate::setup::HostPlane {
                            v: host.v,
                            z: host.z,
                        }),
                        ..Default::default()
                    });
                }
            }
            if w % 3 == 0 {
                let p = |rng: &mut crate::rng::Lcg64| {
                    [
                        (rng.unit() * 52.0 - 6.0) * 256.0,
                        (rng.unit() * 40.0 - 4.0) * 256.0,
                    ]
                    .map(|c| c as i32)
                };
                let zt = |rng: &mut crate::rng::Lcg64| {
                    (Z_GEOM_MIN as f64 + span * (0.05 + 0.9 * rng.unit())) as u32
                };
                let (v, z) = ([p(rng), p(rng), p(rng)], [zt(rng), zt(rng), zt(rng)]);
                tris.push(SnappedTri {
                    v,
                    z,
                    c: colour(rng),
                    tag,
                    ..Default::default()
                });
            }
        }
        tris
    }

    /// Leaving hidden fragments out changes no output: on layered scenes (with and
    /// without decals, on both grids and every variant) the image, every AOV and every
    /// counter are those of the frame with every fragment made, and many fragments are
    /// left out.
    #[test]
    fn leaving_hidden_fragments_out_changes_no_output() {
        hidden_left_out_changes_nothing(0x1dde_7f00, (40, 30), 1, 12, 48, 6);
    }

    /// As [`leaving_hidden_fragments_out_changes_no_output`] with every wall of one tag (a
    /// mesh of many layers, as one model loaded from one file is): each triangle has many
    /// other triangles of its tag on its pixels, most of them apart from it in depth, a
    /// few (the slabs' other face) not.
    #[test]
    fn leaving_hidden_fragments_of_one_tag_out_changes_no_output() {
        hidden_left_out_changes_nothing(0x1dde_7f00, (40, 30), 1, 1, 48, 10);
    }

    /// As [`leaving_hidden_fragments_out_changes_no_output`] on rows several blocks of
    /// hidden fragments wide (the layered scene stretched six times along x), where whole
    /// blocks are left out at once.
    #[test]
    fn leaving_hidden_blocks_out_changes_no_output() {
        hidden_left_out_changes_nothing(0xb10c_4ed0, (240, 30), 6, 12, 24, 5);
    }

    /// Two walls of a few large triangles each, one behind the other, across a frame 400
    /// pixels wide: rows two layers deep, far fewer than five rows' widths of fully
    /// covered pixels, whose few triangles still pay for the hidden-fragment tests
    /// (`HiddenRow::worth`). The back wall's fully covered fragments are left out, and
    /// nothing changes.
    #[test]
    fn a_few_large_triangles_two_layers_deep_leave_hidden_fragments_out() {
        let (w, h) = (400u32, 24u32);
        let wall = |x0: i32, x1: i32, z: u32, tag: u16| {
            let v = [[x0, -256], [x1, -256], [x1, 30 * 256], [x0, 30 * 256]];
            [[0, 1, 2], [0, 2, 3]].map(|[a, b, c]| SnappedTri {
                v: [v[a], v[b], v[c]],
                z: [z; 3],
                c: [[(40 + 100 * tag as u32) << 12; 3]; 3],
                tag,
                ..Default::default()
            })
        };
        let mut tris = Vec::new();
        tris.extend(wall(-256, 401 * 256, 6_000_000, 1));
        tris.extend(wall(20 * 256, 380 * 256, 2_000_000, 2));
        for p in [
            AbufferParams::default(),
            AbufferParams {
                size: MaskSize::S8X8,
                ..AbufferParams::default()
            },
        ] {
            let (made, left_out) = hidden_left_out(&tris, (w, h), &p);
            // The back wall behind the front one: 360 of its 400 pixels per row, so
            // nearly half of all fragments.
            assert!(left_out * 5 > made * 2, "{left_out} of {made} left out");
        }
    }

    /// Renders `cases` layered scenes of `tags` tags (x stretched by `sx`) on a `w`×`h`
    /// frame with and without leaving hidden fragments out, and asserts that every output
    /// is the same and that more than one fragment in `one_in` was left out.
    fn hidden_left_out_changes_nothing(
        seed: u64,
        (w, h): (u32, u32),
        sx: i32,
        tags: u64,
        cases: usize,
        one_in: u64,
    ) {
        let mut rng = crate::rng::Lcg64(seed);
        let (mut made, mut left_out) = (0u64, 0u64);
        for case in 0..cases {
            let mut tris = layered_scene(&mut rng, case % 4 == 3, tags);
            for t in &mut tris {
                t.v.iter_mut().for_each(|p| p[0] *= sx);
                if let Some(hp) = &mut t.host {
                    hp.v.iter_mut().for_each(|p| p[0] *= sx);
                }
            }
            let p = AbufferParams {
                size: [MaskSize::S4X4, MaskSize::S8X8][case % 2],
                depth: DepthSelect::ALL[(case / 2) % 4],
                ..AbufferParams::default()
            };
            let (m, l) = hidden_left_out(&tris, (w, h), &p);
            made += m;
            left_out += l;
        }
        assert!(
            left_out * one_in > made,
            "{left_out} of {made} fragments left out"
        );
    }

    /// Renders `tris` on a `w`×`h` frame with and without leaving hidden fragments out,
    /// asserts that every output is the same, and returns the fragments of the frame and
    /// how many of them the rows left out.
    fn hidden_left_out(tris: &[SnappedTri], (w, h): (u32, u32), p: &AbufferParams) -> (u64, u64) {
        let all = render_frame(tris, w, h, [9, 99, 199], p, AbufferAovs::ALL, false);
        let got = render_frame(tris, w, h, [9, 99, 199], p, AbufferAovs::ALL, true);
        let (all, got) = (all.unwrap(), got.unwrap());
        assert_eq!(got.rgb, all.rgb);
        assert_eq!(got.coverage, all.coverage);
        assert_eq!(got.fragments, all.fragments);
        assert_eq!(got.visible, all.visible);
        assert_eq!(got.stats, all.stats);
        // How many the rows left out.
        let sel = DepthSelector::new(p.size);
        let hidden = Hidden {
            sel: &sel,
            variant: p.depth,
        };
        let (setups, bands) = frag_setups(tris, w, h, p.size).unwrap();
        let mut rf = RowFrags::default();
        let mut band = BandMasks::default();
        let mut left_out = 0;
        for b in 0..bands.len() {
            let (j0, j1) = bands.rows(b);
            band.fill((j0, j1), w, &setups, bands.members(b));
            for j in j0..=j1 {
                rf.build_from(j, w, &setups, band.row(j), p.size, Some(hidden));
                left_out += (0..w as usize).map(|i| rf.hidden_at(i) as u64).sum::<u64>();
            }
        }
        (all.stats.fragments, left_out)
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
