//! The fragment stream an A-buffer render feeds the search unit (seed 000, claim 2): every
//! search request in render order, with the golden result of each.

use super::{multi_fragment_pixels, AbufferError};
use crate::mask_search::{depth_calc, SearchResult, SearchTables, SearchUnit};
use crate::setup::SnappedTri;
use pixelproc_formats::abuffer::{Corner, FragPlane, MaskSize, SearchFamily};

/// One request to the search unit and its golden result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SearchRequest {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The fragment's triangle (scene order).
    pub prim: u32,
    /// The max search of an interpenetrating scene (from the opposite corner); false for
    /// the min search.
    pub max: bool,
    /// Fraction mask.
    pub mask: u64,
    /// Start corner.
    pub corner: Corner,
    /// Depth plane relative to the pixel centre.
    pub plane: FragPlane,
    /// Golden search: steps, first non-zero AND result and its ROM word.
    pub result: SearchResult,
    /// Depth at end 1 of the ROM word (`zc` without a hit).
    pub z1: i64,
    /// Depth at end 2 (`z1` without a pair).
    pub z2: i64,
}

impl SearchRequest {
    /// Golden search of `mask` from `corner` with the depth calculator on its ROM word.
    pub fn new(
        tables: &SearchTables,
        (x, y, prim, max): (u32, u32, u32, bool),
        mask: u64,
        corner: Corner,
        plane: FragPlane,
    ) -> SearchRequest {
        let result = SearchUnit::new(tables).run(mask, corner);
        let (z1, z2) = match result.hit {
            Some((_, w)) => {
                let (z1, z2, _) = depth_calc(&plane, w);
                (z1, z2.unwrap_or(z1))
            }
            None => (plane.zc, plane.zc),
        };
        SearchRequest {
            x,
            y,
            prim,
            max,
            mask,
            corner,
            plane,
            result,
            z1,
            z2,
        }
    }

    /// The smaller depth.
    pub fn zmin(&self) -> i64 {
        self.z1.min(self.z2)
    }

    /// The larger depth.
    pub fn zmax(&self) -> i64 {
        self.z1.max(self.z2)
    }

    /// The depth the renderer takes from this search: `zmin` for a min search, `zmax` for a
    /// max search (the golden `DepthSelector` with `DepthSelect::Search`).
    pub fn depth(&self) -> i64 {
        if self.max {
            self.zmax()
        } else {
            self.zmin()
        }
    }
}

/// Every search the A-buffer render of `tris` (`width`×`height`, `size` masks, the seed's
/// diagonal search, `DepthSelect::Search`) runs, in render order: pixels with two or more
/// fragments row by row, left to right; their fragments in scene order; per fragment the
/// min search from `Corner::of_min(sx, sy)` and, if `interpenetrating`, then the max
/// search from the opposite corner. Same fragments as [`super::render_abuffer`] builds
/// ([`multi_fragment_pixels`]); the render itself is not changed.
pub fn search_stream(
    tris: &[SnappedTri],
    width: u32,
    height: u32,
    size: MaskSize,
    interpenetrating: bool,
) -> Result<Vec<SearchRequest>, AbufferError> {
    let tables = SearchTables::new(size, SearchFamily::DIAGONAL);
    let pixels = multi_fragment_pixels(tris, width, height, size)?;
    let mut out = Vec::new();
    for p in &pixels {
        for f in &p.fragments {
            let c = Corner::of_min(f.plane.sx, f.plane.sy);
            out.push(SearchRequest::new(
                &tables,
                (p.x, p.y, f.prim, false),
                f.mask,
                c,
                f.plane,
            ));
            if interpenetrating {
                out.push(SearchRequest::new(
                    &tables,
                    (p.x, p.y, f.prim, true),
                    f.mask,
                    c.opposite(),
                    f.plane,
                ));
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abuffer::{render_abuffer, AbufferParams};
    use crate::mask_search::{DepthSelect, DepthSelector};

    /// The stream is the render's: its steps and depth evaluations are the renderer's
    /// statistics, and every request's depth is the renderer's pick for that fragment.
    #[test]
    fn the_stream_is_what_the_renderer_searches() {
        let ls = crate::scene::load_builtin("default").unwrap();
        let proj = crate::frontend::project(&ls).unwrap();
        let (w, h) = (ls.scene.width, ls.scene.height);
        for (size, inter) in [(MaskSize::S4X4, false), (MaskSize::S8X8, true)] {
            let params = AbufferParams {
                size,
                depth: DepthSelect::Search,
                interpenetrating: inter,
                compare_variants: false,
            };
            let frame = render_abuffer(&proj.tris, w, h, [0; 3], &params).unwrap();
            let s = search_stream(&proj.tris, w, h, size, inter).unwrap();
            let steps: u64 = s.iter().map(|r| r.result.steps as u64).sum();
            let evals: u64 = s
                .iter()
                .filter_map(|r| r.result.hit)
                .map(|(_, w)| 1 + w.pair as u64)
                .sum();
            assert_eq!(steps, frame.stats.search_steps);
            assert_eq!(evals, frame.stats.depth_evals);
            let per_frag = 1 + inter as u64;
            assert_eq!(s.len() as u64, frame.stats.sorted_fragments * per_frag);
            let sel = DepthSelector::new(size);
            for r in s.iter().step_by(7) {
                let p = sel.select(DepthSelect::Search, r.mask, &r.plane, inter);
                let want = if r.max { p.zmax.unwrap() } else { p.zmin };
                assert_eq!(r.depth(), want, "{r:?}");
            }
        }
    }
}
