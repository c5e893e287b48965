//! The mask search unit with its offset ROM and depth calculator, and the depth-selection
//! variants built on it.
//!
//! Implements seed 000 (JP2569952B2), claim 1 / claim 2 and Fig. 6: the start-corner
//! selector (2) picks the corner where the plane is smallest from the signs of its slopes;
//! the search mask generator (3) supplies the band `p·c' + q·r' = k` (the seed's diagonal is
//! `p = q = 1`); the AND unit (4) and zero detector (5) test it against the fraction mask;
//! the mover (6) steps one line away from the corner while the AND result is zero; at the
//! first non-zero result the offset reader (7) addresses the offset ROM (8) with the AND
//! result (compacted to its most and least significant set bits, see
//! [`pixelproc_formats::abuffer`]) and gets the one or two *end* subpixels; the depth
//! calculator (10) evaluates the fragment plane `zc + sx·dx + sy·dy` there and keeps the min
//! (or, for interpenetrating fragments, also the max from the opposite corner).
//!
//! [`SearchUnit`] is the per-step golden model of the RTL block: `start(mask, corner)`, then
//! `step()` once per clock, each step reporting the search mask, the AND result, the zero
//! flag and the move. [`DepthSelect`] puts the variants behind one interface and counts
//! their depth evaluations; [`DepthSelector`] gets the unit's results without the per-step
//! outputs ([`SearchTables::first_hit`], and a cache for full masks).

use pixelproc_formats::abuffer::{
    offset_rom_table, search_mask_table, Corner, FragPlane, MaskSize, RomWord, SearchFamily,
    SubOffset,
};

/// Generated tables of one search-mask family for one mask size: the search masks of every
/// start corner and the offset ROM.
#[derive(Clone, Debug)]
pub struct SearchTables {
    size: MaskSize,
    family: SearchFamily,
    masks: [Vec<u64>; 4],
    rom: Vec<u8>,
}

impl SearchTables {
    /// Generates the tables (search masks per corner, offset ROM) for a size and family.
    pub fn new(size: MaskSize, family: SearchFamily) -> SearchTables {
        SearchTables {
            size,
            family,
            masks: Corner::ALL.map(|c| search_mask_table(size, family, c)),
            rom: offset_rom_table(size),
        }
    }
    /// The mask size.
    pub fn size(&self) -> MaskSize {
        self.size
    }
    /// The search family.
    pub fn family(&self) -> SearchFamily {
        self.family
    }
    /// Search mask of line `k` from `corner`.
    #[inline]
    pub fn search_mask(&self, corner: Corner, k: u32) -> u64 {
        self.masks[corner.code() as usize][k as usize]
    }
    /// Number of lines (the longest search).
    #[inline]
    pub fn lines(&self) -> u32 {
        self.masks[0].len() as u32
    }
    /// The result of a whole search, [`SearchUnit::run`], as one loop over the search
    /// lines: the first line whose AND result is non-zero is the hit, and the steps are its
    /// number plus one (every line, no hit, for an empty mask).
    #[inline]
    pub fn first_hit(&self, mask: u64, corner: Corner) -> SearchResult {
        let mask = mask & self.size.full();
        let lines = &self.masks[corner.code() as usize];
        for (k, &sm) in lines.iter().enumerate() {
            let and_result = mask & sm;
            if and_result != 0 {
                return SearchResult {
                    steps: k as u32 + 1,
                    hit: Some((and_result, self.offset_rom(and_result))),
                };
            }
        }
        SearchResult {
            steps: lines.len() as u32,
            hit: None,
        }
    }
    /// The raw offset ROM: entry `b` is the packed [`SubOffset`] of bit `b`.
    pub fn rom(&self) -> &[u8] {
        &self.rom
    }
    /// The offset ROM read as the RTL does it: priority-encode the most and least
    /// significant set bits of `and_result` and read the ROM at both. `and_result` must be
    /// non-zero (the unit only reads the ROM on a hit); zero reads entry 0 twice.
    #[inline]
    pub fn offset_rom(&self, and_result: u64) -> RomWord {
        let hi = 63u32.saturating_sub(and_result.leading_zeros());
        let lo = if and_result == 0 {
            0
        } else {
            and_result.trailing_zeros()
        };
        RomWord {
            end1: SubOffset::unpack(self.rom[hi as usize]),
            end2: SubOffset::unpack(self.rom[lo as usize]),
            pair: hi != lo,
        }
    }
}

/// What the search unit shows on one step (one clock).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct StepOutput {
    /// False if the unit was idle (no search running): every other field is zero.
    pub active: bool,
    /// Index `k` of the search line tested on this step.
    pub line: u32,
    /// The search mask of line `k`.
    pub search_mask: u64,
    /// `fraction mask & search mask`.
    pub and_result: u64,
    /// Zero detector: `and_result == 0`.
    pub zero: bool,
    /// The mover fired: the next step tests line `k + 1`.
    pub moved: bool,
    /// First hit: `and_result` addresses the offset ROM; the search is over.
    pub hit: bool,
    /// The search is over (hit, or every line tested zero: empty mask).
    pub done: bool,
}

/// The search unit: a small state machine over generated tables.
#[derive(Clone, Debug)]
pub struct SearchUnit<'t> {
    tables: &'t SearchTables,
    mask: u64,
    corner: Corner,
    line: u32,
    running: bool,
}

/// Result of a whole search (built on [`SearchUnit::step`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SearchResult {
    /// Steps taken (clocks), including the hit step.
    pub steps: u32,
    /// The first non-zero AND result and the ROM word it addresses, or `None` for an empty
    /// mask.
    pub hit: Option<(u64, RomWord)>,
}

impl<'t> SearchUnit<'t> {
    /// An idle unit over `tables`.
    pub fn new(tables: &'t SearchTables) -> SearchUnit<'t> {
        SearchUnit {
            tables,
            mask: 0,
            corner: Corner::TopLeft,
            line: 0,
            running: false,
        }
    }

    /// Loads a fraction mask and a start corner; the next step tests line 0.
    #[inline]
    pub fn start(&mut self, mask: u64, corner: Corner) {
        self.mask = mask & self.tables.size.full();
        self.corner = corner;
        self.line = 0;
        self.running = true;
    }

    /// One clock: AND the current search mask with the fraction mask, test for zero, and
    /// either stop (hit / exhausted) or move one line away from the corner.
    #[inline]
    pub fn step(&mut self) -> StepOutput {
        if !self.running {
            return StepOutput::default();
        }
        let search_mask = self.tables.search_mask(self.corner, self.line);
        let and_result = self.mask & search_mask;
        let zero = and_result == 0;
        let last = self.line + 1 >= self.tables.lines();
        let out = StepOutput {
            active: true,
            line: self.line,
            search_mask,
            and_result,
            zero,
            moved: zero && !last,
            hit: !zero,
            done: !zero || last,
        };
        if out.moved {
            self.line += 1;
        }
        if out.done {
            self.running = false;
        }
        out
    }

    /// Runs a whole search with [`SearchUnit::start`] and [`SearchUnit::step`].
    ///
    /// [`SearchTables::first_hit`] computes the same result without the per-step outputs.
    #[inline]
    pub fn run(&mut self, mask: u64, corner: Corner) -> SearchResult {
        self.start(mask, corner);
        let mut steps = 0;
        loop {
            let o = self.step();
            steps += 1;
            if o.hit {
                return SearchResult {
                    steps,
                    hit: Some((o.and_result, self.tables.offset_rom(o.and_result))),
                };
            }
            if o.done {
                return SearchResult { steps, hit: None };
            }
        }
    }
}

/// The depth calculator on a ROM word: depths at end 1 and (if `pair`) end 2, with the
/// number of evaluations (1 or 2).
#[inline]
pub fn depth_calc(plane: &FragPlane, w: RomWord) -> (i64, Option<i64>, u32) {
    let z1 = plane.depth_at(w.end1);
    if w.pair {
        (z1, Some(plane.depth_at(w.end2)), 2)
    } else {
        (z1, None, 1)
    }
}

/// How a fragment's ordering depth is chosen (the `--depth` option).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DepthSelect {
    /// One depth at the pixel centre (the cheap, wrong method the seed criticises).
    Center,
    /// The seed's method: diagonal search from the start corner, one or two depths.
    Search,
    /// Search with a family chosen per slope class (columns, 2:1, diagonal, 1:2, rows),
    /// the "table for a different inclination" the seed mentions.
    Slope,
    /// Depth at every covered subpixel: the exact extreme over subpixels.
    Exhaustive,
}

impl DepthSelect {
    /// All variants.
    pub const ALL: [DepthSelect; 4] = [
        DepthSelect::Center,
        DepthSelect::Search,
        DepthSelect::Slope,
        DepthSelect::Exhaustive,
    ];
    /// Name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DepthSelect::Center => "center",
            DepthSelect::Search => "search",
            DepthSelect::Slope => "slope",
            DepthSelect::Exhaustive => "exhaustive",
        }
    }
    /// Parses a command-line name.
    pub fn parse(s: &str) -> Option<DepthSelect> {
        DepthSelect::ALL.into_iter().find(|d| d.name() == s)
    }
}

/// The ordering depths of one fragment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthPick {
    /// Nearest depth (Q.12) as the variant sees it.
    pub zmin: i64,
    /// Farthest depth (Q.12), when asked for.
    pub zmax: Option<i64>,
    /// Depth-calculator evaluations spent.
    pub evals: u32,
    /// Search-unit steps spent (0 for `center` and `exhaustive`).
    pub steps: u32,
}

/// The slope classes of [`DepthSelect::Slope`], and the family each uses.
pub const SLOPE_FAMILIES: [SearchFamily; 5] = [
    SearchFamily { p: 1, q: 0 },
    SearchFamily { p: 2, q: 1 },
    SearchFamily { p: 1, q: 1 },
    SearchFamily { p: 1, q: 2 },
    SearchFamily { p: 0, q: 1 },
];

/// The index of the seed's diagonal family in [`SLOPE_FAMILIES`].
const DIAGONAL: usize = 2;

/// Slope class of a plane: index into [`SLOPE_FAMILIES`] whose line direction is closest to
/// the level lines of the plane. With `a = |sx|`, `b = |sy|` (one offset unit is half a
/// subpixel on both axes): `4b < a` columns, `4a < b` rows, `7b < 5a` 2:1, `7a < 5b` 1:2,
/// else diagonal. The thresholds 1/4 and 5/7 approximate the bisecting angles 13.3° and
/// 35.8° (tan = 0.236, 0.721).
pub fn slope_class(sx: i64, sy: i64) -> usize {
    let (a, b) = (sx.unsigned_abs() as u128, sy.unsigned_abs() as u128);
    if 4 * b < a {
        0
    } else if 4 * a < b {
        4
    } else if 7 * b < 5 * a {
        1
    } else if 7 * a < 5 * b {
        3
    } else {
        2
    }
}

/// Depth selection for one mask size: the generated tables of every family, shared
/// read-only across threads.
#[derive(Clone, Debug)]
pub struct DepthSelector {
    size: MaskSize,
    /// Tables per slope class (index 2 is the seed's diagonal family).
    tables: Vec<SearchTables>,
    /// Per table and start corner ([`Corner::code`]), the search of a full mask: the
    /// unit's result depends on the mask and the corner only, and full masks (a
    /// triangle covering the whole pixel) are the most common, so they are run once here.
    full: Vec<[SearchResult; 4]>,
    /// The same searches of a full mask as the ordering depth they give without a max:
    /// [`FullPick`] per table and start corner.
    full_pick: Vec<[FullPick; 4]>,
}

/// The nearest-depth pick of a full mask from one start corner of one table: the offsets
/// of the one or two end subpixels (the same twice for one) and the counts, so that the
/// pick is `zc + min(sx·dx + sy·dy)` over the two.
#[derive(Clone, Copy, Debug)]
struct FullPick {
    ends: [(i64, i64); 2],
    evals: u32,
    steps: u32,
}

impl FullPick {
    fn of(r: &SearchResult) -> FullPick {
        let (ends, evals) = match r.hit {
            Some((_, w)) => {
                let d = |o: SubOffset| (o.dx as i64, o.dy as i64);
                let e2 = if w.pair { w.end2 } else { w.end1 };
                ([d(w.end1), d(e2)], 1 + w.pair as u32)
            }
            None => ([(0, 0); 2], 0),
        };
        FullPick {
            ends,
            evals,
            steps: r.steps,
        }
    }
}

impl DepthSelector {
    /// Generates every table for `size`.
    pub fn new(size: MaskSize) -> DepthSelector {
        let tables: Vec<SearchTables> = SLOPE_FAMILIES
            .iter()
            .map(|&f| SearchTables::new(size, f))
            .collect();
        let full: Vec<[SearchResult; 4]> = tables
            .iter()
            .map(|t| Corner::ALL.map(|c| SearchUnit::new(t).run(size.full(), c)))
            .collect();
        let full_pick: Vec<[FullPick; 4]> = full
            .iter()
            .map(|rs: &[SearchResult; 4]| rs.map(|r| FullPick::of(&r)))
            .collect();
        DepthSelector {
            size,
            tables,
            full,
            full_pick,
        }
    }

    /// [`SearchUnit::run`] on table `ti`, from the cache for a full mask, else as
    /// [`SearchTables::first_hit`].
    #[inline]
    fn search(&self, ti: usize, mask: u64, corner: Corner) -> SearchResult {
        let full = self.size.full();
        if mask & full == full {
            self.full[ti][corner.code() as usize]
        } else {
            self.tables[ti].first_hit(mask, corner)
        }
    }

    /// The seed's diagonal tables.
    pub fn diagonal(&self) -> &SearchTables {
        &self.tables[DIAGONAL]
    }

    /// [`DepthSelector::select`] without the farthest depth, its most common case (the
    /// search of a full mask: a triangle covering the whole pixel) inlined where it is
    /// called, the same folded pick as there.
    #[inline(always)]
    pub fn select_nearest(&self, variant: DepthSelect, mask: u64, plane: &FragPlane) -> DepthPick {
        let full = self.size.full();
        if variant == DepthSelect::Search && mask & full == full {
            return self.full_pick(DIAGONAL, plane);
        }
        self.select(variant, mask, plane, false)
    }

    /// The nearest-depth pick of a full mask on table `ti` ([`FullPick`]: the search on
    /// the cached full-mask result, folded).
    #[inline(always)]
    fn full_pick(&self, ti: usize, plane: &FragPlane) -> DepthPick {
        let corner = Corner::of_min(plane.sx, plane.sy);
        let f = &self.full_pick[ti][corner.code() as usize];
        let z = |(dx, dy): (i64, i64)| plane.zc + plane.sx * dx + plane.sy * dy;
        DepthPick {
            zmin: z(f.ends[0]).min(z(f.ends[1])),
            zmax: None,
            evals: f.evals,
            steps: f.steps,
        }
    }

    /// Ordering depths of a fragment with fraction `mask` (non-zero) and `plane` under
    /// `variant`; `want_max` also finds the farthest depth (interpenetrating surfaces).
    #[inline]
    pub fn select(
        &self,
        variant: DepthSelect,
        mask: u64,
        plane: &FragPlane,
        want_max: bool,
    ) -> DepthPick {
        match variant {
            DepthSelect::Center => DepthPick {
                zmin: plane.zc,
                zmax: want_max.then_some(plane.zc),
                evals: 1,
                steps: 0,
            },
            DepthSelect::Exhaustive => {
                let (mut lo, mut hi, mut evals) = (i64::MAX, i64::MIN, 0);
                let mut bits = mask & self.size.full();
                while bits != 0 {
                    let b = bits.trailing_zeros();
                    bits &= bits - 1;
                    let (c, r) = self.size.col_row(b);
                    let z = plane.depth_at(self.size.offset(c, r));
                    lo = lo.min(z);
                    hi = hi.max(z);
                    evals += 1;
                }
                DepthPick {
                    zmin: lo,
                    zmax: want_max.then_some(hi),
                    evals,
                    steps: 0,
                }
            }
            DepthSelect::Search | DepthSelect::Slope => {
                let ti = if variant == DepthSelect::Search {
                    DIAGONAL
                } else {
                    slope_class(plane.sx, plane.sy)
                };
                let corner = Corner::of_min(plane.sx, plane.sy);
                let full = self.size.full();
                if !want_max && mask & full == full {
                    // The search below on the cached full-mask result, folded.
                    return self.full_pick(ti, plane);
                }
                let mut pick = DepthPick {
                    zmin: plane.zc,
                    zmax: None,
                    evals: 0,
                    steps: 0,
                };
                let r = self.search(ti, mask, corner);
                pick.steps += r.steps;
                if let Some((_, w)) = r.hit {
                    let (z1, z2, e) = depth_calc(plane, w);
                    pick.zmin = z2.map_or(z1, |z2| z1.min(z2));
                    pick.evals += e;
                }
                if want_max {
                    let r = self.search(ti, mask, corner.opposite());
                    pick.steps += r.steps;
                    let mut zmax = plane.zc;
                    if let Some((_, w)) = r.hit {
                        let (z1, z2, e) = depth_calc(plane, w);
                        zmax = z2.map_or(z1, |z2| z1.max(z2));
                        pick.evals += e;
                    }
                    pick.zmax = Some(zmax);
                }
                pick
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn px(size: MaskSize, o: SubOffset) -> (f64, f64) {
        o.to_px(size)
    }

    #[test]
    fn seed_vector_0100h() {
        let t = SearchTables::new(MaskSize::S4X4, SearchFamily::DIAGONAL);
        let w = t.offset_rom(0x0100);
        assert!(!w.pair);
        assert_eq!(px(t.size(), w.end1), (0.375, 0.125));
        assert_eq!(w.end1, w.end2);
    }

    #[test]
    fn seed_vector_0842h() {
        let t = SearchTables::new(MaskSize::S4X4, SearchFamily::DIAGONAL);
        let w = t.offset_rom(0x0842);
        assert!(w.pair);
        assert_eq!(px(t.size(), w.end1), (-0.375, 0.125));
        assert_eq!(px(t.size(), w.end2), (0.125, -0.375));
    }

    #[test]
    fn seed_vectors_arise_as_first_hits() {
        // 0842H is the first hit from the top-left corner of a mask whose nearest
        // anti-diagonal (c + r = 2) is fully covered and whose lines 0 and 1 are empty.
        let t = SearchTables::new(MaskSize::S4X4, SearchFamily::DIAGONAL);
        let mut u = SearchUnit::new(&t);
        u.start(0xFF73, Corner::TopLeft);
        let s0 = u.step();
        assert_eq!((s0.search_mask, s0.zero, s0.moved), (0x0008, true, true));
        let s1 = u.step();
        assert_eq!((s1.search_mask, s1.zero, s1.moved), (0x0084, true, true));
        let s2 = u.step();
        assert_eq!(s2.search_mask, 0x0842);
        assert_eq!(
            (s2.and_result, s2.zero, s2.hit, s2.done),
            (0x0842, false, true, true)
        );
        assert!(!u.step().active);
        // 0100H from the bottom-right: line 0 (bit 12) empty, line 1 = bits 8, 13.
        let r = u.run(0x0100 | 0x0011, Corner::BottomRight);
        assert_eq!(r.steps, 2);
        assert_eq!(r.hit.unwrap().0, 0x0100);
    }

    #[test]
    fn depth_calculator_is_plane_multiply_add() {
        let p = FragPlane {
            zc: 1000 << 12,
            sx: 3 << 12,
            sy: -5 << 12,
        };
        let w = SearchTables::new(MaskSize::S4X4, SearchFamily::DIAGONAL).offset_rom(0x0842);
        // (−3, +1) and (+1, −3) offset units: 1000 − 9 − 5 and 1000 + 3 + 15.
        assert_eq!(depth_calc(&p, w), (986 << 12, Some(1018 << 12), 2));
    }

    #[test]
    fn search_is_exact_for_diagonal_gradients() {
        // Equal slopes: the level lines are the anti-diagonals, so the first hit holds the
        // minimum; check against exhaustive on every 4×4 mask for one plane per corner.
        let sel = DepthSelector::new(MaskSize::S4X4);
        for (sx, sy) in [(7, 7), (-7, 7), (7, -7), (-7, -7)] {
            let p = FragPlane { zc: 0, sx, sy };
            for mask in 1..=0xFFFFu64 {
                let s = sel.select(DepthSelect::Search, mask, &p, true);
                let e = sel.select(DepthSelect::Exhaustive, mask, &p, true);
                assert_eq!((s.zmin, s.zmax), (e.zmin, e.zmax), "mask {mask:04x}");
                assert!(s.evals <= 4 && e.evals == mask.count_ones());
            }
        }
    }

    #[test]
    fn searches_bound_the_exact_extremes() {
        // A search depth is the depth of a covered subpixel, so it can never be nearer than
        // the exact minimum (nor farther than the exact maximum), and it costs at most two
        // evaluations per direction.
        let sel = DepthSelector::new(MaskSize::S4X4);
        let mut x = 0x1234_5678_9ABC_DEF1u64;
        for mask in (1..=0xFFFFu64).step_by(7) {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let p = FragPlane {
                zc: (x % 100_000) as i64,
                sx: (x >> 20) as i64 % 4000 - 2000,
                sy: (x >> 40) as i64 % 4000 - 2000,
            };
            let e = sel.select(DepthSelect::Exhaustive, mask, &p, true);
            for v in [DepthSelect::Search, DepthSelect::Slope] {
                let s = sel.select(v, mask, &p, true);
                assert!(s.zmin >= e.zmin && s.zmax.unwrap() <= e.zmax.unwrap());
                assert!((2..=4).contains(&s.evals), "{v:?} {mask:x}");
            }
        }
    }

    #[test]
    fn diagonal_search_misses_a_nearer_later_line() {
        // Mask: (col 2, row 0) = bit 1 and (col 0, row 3) = bit 15; plane rising in x only.
        // The diagonal search from the top-left hits line 2 (offset dx = +1), the exact
        // minimum is at dx = -3; the column family (slope class 0) finds it.
        let sel = DepthSelector::new(MaskSize::S4X4);
        let p = FragPlane {
            zc: 100,
            sx: 10,
            sy: 0,
        };
        let mask = (1 << 1) | (1 << 15);
        assert_eq!(sel.select(DepthSelect::Search, mask, &p, false).zmin, 110);
        assert_eq!(
            sel.select(DepthSelect::Exhaustive, mask, &p, false).zmin,
            70
        );
        assert_eq!(sel.select(DepthSelect::Slope, mask, &p, false).zmin, 70);
    }

    /// A full mask's pick from the folded cache is the general search's, on every
    /// family, corner and size, with random planes.
    #[test]
    fn full_mask_picks_are_the_searches() {
        let mut rng = crate::rng::XorShift64Star(0x00f0_11ca_c4e5);
        for (n, m) in [(4, 4), (8, 8), (3, 5), (2, 2), (8, 1), (1, 1)] {
            let size = MaskSize::new(n, m).unwrap();
            let sel = DepthSelector::new(size);
            for _ in 0..4000 {
                let x = rng.next_u64();
                let p = FragPlane {
                    zc: (x % 1_000_000) as i64 - 500_000,
                    sx: (x >> 20) as i64 % 4000 - 2000,
                    sy: (x >> 40) as i64 % 4000 - 2000,
                };
                for v in [DepthSelect::Search, DepthSelect::Slope] {
                    let got = sel.select(v, size.full(), &p, false);
                    let ti = if v == DepthSelect::Search {
                        DIAGONAL
                    } else {
                        slope_class(p.sx, p.sy)
                    };
                    let r = SearchUnit::new(&sel.tables[ti])
                        .run(size.full(), Corner::of_min(p.sx, p.sy));
                    let (z1, z2, e) = depth_calc(&p, r.hit.unwrap().1);
                    let want = DepthPick {
                        zmin: z2.map_or(z1, |z2| z1.min(z2)),
                        zmax: None,
                        evals: e,
                        steps: r.steps,
                    };
                    assert_eq!(got, want, "{size} {v:?} {p:?}");
                }
            }
        }
    }

    /// The one-loop search is the stepped unit's on every 4×4 mask (every family and
    /// corner) and on random masks of other sizes.
    #[test]
    fn first_hit_is_the_units_run() {
        let mut rng = crate::rng::XorShift64Star(0x0f17_57a1_c0de_5eed);
        for (n, m) in [(4, 4), (8, 8), (3, 5), (2, 2), (8, 1)] {
            let size = MaskSize::new(n, m).unwrap();
            for &family in &SLOPE_FAMILIES {
                let t = SearchTables::new(size, family);
                for corner in Corner::ALL {
                    let mut check = |mask: u64| {
                        let want = SearchUnit::new(&t).run(mask, corner);
                        assert_eq!(t.first_hit(mask, corner), want, "{size} {mask:x}");
                    };
                    if size.bits() <= 16 {
                        (0..=size.full()).for_each(&mut check);
                    } else {
                        for _ in 0..20_000 {
                            let x = rng.next_u64();
                            // Sparse masks too (long searches), and bits past the grid.
                            check(x & (x >> 17) & (x >> 31));
                            check(x);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn slope_classes() {
        assert_eq!(slope_class(100, 0), 0);
        assert_eq!(slope_class(0, 100), 4);
        assert_eq!(slope_class(100, 100), 2);
        assert_eq!(slope_class(-100, 50), 1);
        assert_eq!(slope_class(50, -100), 3);
    }
}
