//! The hidden-surface walk of one sub-scanline (seed 002, §3, stack memory NEXT): sorted
//! crossings, the current polygon and the stack, and the visible pieces it emits (see the
//! module header of [`super`]).

use super::spans::{MsTri, RowPlane};
use super::ZF;
use crate::raster::depth;

/// Where x starts in a crossing's sort key: below it the kind, the decal bit and the
/// polygon's candidate index in its band.
const KEY_X: u32 = 34;
/// The candidate bits of a crossing's sort key.
const CAND_MASK: u64 = (1 << (KEY_X - 2)) - 1;
/// A crossing's sort key without its x.
const LOW_MASK: u64 = (1 << KEY_X) - 1;
/// [`WalkScratch::slots`] of a candidate the line does not hit.
pub(super) const NO_SLOT: u32 = u32::MAX;

/// One visible piece `[x0, x1)` of triangle `tri` (−1 background) on a sub-scanline,
/// with its row planes for colour.
#[derive(Clone, Copy, Debug)]
pub(super) struct Piece {
    pub(super) x0: i64,
    pub(super) x1: i64,
    pub(super) tri: i32,
    pub(super) slot: usize,
}

/// A triangle hit by the sub-scanline: its depth plane on the line and its interval, and
/// its index and decal flag (copies of the triangle's, which the walk reads at every
/// crossing).
pub(super) struct Active<'a> {
    pub(super) t: &'a MsTri,
    pub(super) idx: i32,
    /// Its index among the band's candidates.
    pub(super) cand: u32,
    pub(super) decal: bool,
    pub(super) z: RowPlane,
    pub(super) xl: i64,
    pub(super) xr: i64,
}

/// `a` in front of `b` at equal depth (the renderer's depth-test order).
pub(super) fn tie_front(a: &Active, b: &Active) -> bool {
    depth::tie_front((a.decal, a.idx as i64), (b.decal, b.idx as i64))
}

/// The walk of one sub-scanline over `[xa, xb)`: visible pieces in order, and the number
/// of depth evaluations.
pub(super) fn walk(
    act: &[Active],
    xa: i64,
    xb: i64,
    inter: bool,
    out: &mut Vec<Piece>,
    ws: &mut WalkScratch,
) -> u64 {
    // The sort key's fields (see below) must fit: x relative to `xa` in 30 bits (the
    // screen is at most 2^12 pixels of 2^16), the candidate index in 32.
    assert!(
        xb - xa < 1 << (64 - KEY_X) && (ws.slot_of.len() as u64) <= CAND_MASK,
        "walk of {} candidates over {} units exceeds the crossing key",
        ws.slot_of.len(),
        xb - xa
    );
    debug_assert!(act.windows(2).all(|w| w[0].idx < w[1].idx));
    out.clear();
    let WalkScratch {
        ev,
        fresh,
        carried,
        kept,
        slot_of,
        next,
        zcache,
        zrange,
    } = ws;
    next.clear();
    zcache.clear();
    zcache.resize(act.len(), [(i64::MIN, 0); 2]);
    zrange.clear();
    zrange.resize(act.len(), (i64::MIN, i64::MAX));
    let inside = |a: &Active| a.xr > xa && a.xl < xb;
    // Key, most significant first: x, right (0) before left (1); rights: decal first;
    // lefts: face first; then the triangle, which is the candidate's order (the active
    // list and the candidates are both in input order), so the candidate index stands for
    // both (keys distinct).
    let key = |x: i64, kind: u64, d: u64, ci: u32| {
        ((x - xa) as u64) << KEY_X | kind << (KEY_X - 1) | d << (KEY_X - 2) | ci as u64
    };
    // The last line's crossings, in their order, at this line's x: polygons move little
    // from one sub-scanline to the next, so they are nearly sorted.
    kept.clear();
    kept.resize(act.len(), false);
    carried.clear();
    for &k in ev.iter() {
        let s = slot_of[(k & CAND_MASK) as usize];
        let Some(a) = act.get(s as usize).filter(|a| inside(a)) else {
            continue; // not hit on this line (`NO_SLOT`), or outside the walk
        };
        kept[s as usize] = true;
        let x = if k >> (KEY_X - 1) & 1 == 1 {
            a.xl.max(xa)
        } else {
            a.xr.min(xb)
        };
        carried.push(((x - xa) as u64) << KEY_X | (k & LOW_MASK));
    }
    let budget = 4 * carried.len() + 64;
    if !insertion_sort_bounded(carried, budget) {
        carried.sort_unstable();
    }
    // Polygons new on this line, sorted and merged in; and the depth ranges.
    fresh.clear();
    for (s, a) in act.iter().enumerate() {
        if !inside(a) {
            continue;
        }
        if !kept[s] {
            let d = a.decal as u64;
            fresh.push(key(a.xl.max(xa), 1, d, a.cand));
            fresh.push(key(a.xr.min(xb), 0, 1 - d, a.cand));
        }
        if inter {
            // The depth range over the polygon's part of the line: the rounded plane is
            // monotone in x, so its ends bound it. The ends also seed the cache (the
            // walk asks for the left end first). Only with the intersection check, whose
            // per-interval passes over NEXT it mostly serves: without it the range
            // stays unbounded and `nearest` compares every polygon as the seed does.
            let (x0, x1) = (a.xl.max(xa), a.xr.min(xb));
            let (z0, z1) = (a.z.at(x0, ZF), a.z.at(x1, ZF));
            zrange[s] = (z0.min(z1), z0.max(z1));
            zcache[s] = [(x1, z1), (x0, z0)];
        }
    }
    fresh.sort_unstable();
    merge_sorted(carried, fresh, ev);
    let mut wk = Walker {
        act,
        evals: 0,
        zcache,
        zrange,
    };
    let mut cur: Option<usize> = None;
    let mut x = xa;
    // The least depth any polygon of NEXT reaches on the line (`i64::MAX` when NEXT is
    // empty), kept as NEXT changes: when the current polygon's greatest depth is not
    // beyond it, no polygon of NEXT passes in front, and `first_pass` need not look.
    let mut nmin = i64::MAX;
    let qmin =
        |next: &[usize], zr: &[(i64, i64)]| next.iter().map(|&q| zr[q].0).min().unwrap_or(i64::MAX);
    for &key in ev.iter() {
        let (ex, kind, s) = (
            (key >> KEY_X) as i64 + xa,
            (key >> (KEY_X - 1)) as u8 & 1,
            slot_of[(key & CAND_MASK) as usize] as usize,
        );
        // Between crossings: a polygon of NEXT may pass in front of the current one.
        if inter {
            while let Some(c) = cur {
                if ex <= x || next.is_empty() {
                    break;
                }
                if nmin >= wk.zrange[c].1 {
                    // Every polygon of NEXT fails `first_pass`'s first test: its four
                    // evaluations each are counted, as there.
                    wk.evals += 4 * next.len() as u64;
                    break;
                }
                match wk.first_pass(c, next, x, ex) {
                    Some(xs) if xs < ex => {
                        emit(out, act, x, xs, cur);
                        x = xs;
                        // The front-most of NEXT and the old current becomes current
                        // (a decal on the passing polygon's plane comes with it).
                        next.push(c);
                        cur = wk.nearest(next, xs).map(|b| next.swap_remove(b));
                        nmin = qmin(next, wk.zrange);
                    }
                    _ => break,
                }
            }
        }
        emit(out, act, x, ex, cur);
        x = ex;
        if kind == 1 {
            match cur {
                None => cur = Some(s),
                Some(c) => {
                    let back = if wk.front(s, c, ex) {
                        cur = Some(s);
                        c
                    } else {
                        s
                    };
                    next.push(back);
                    nmin = nmin.min(wk.zrange[back].0);
                }
            }
        } else if cur == Some(s) {
            // The nearest polygon in NEXT becomes current.
            cur = wk.nearest(next, ex).map(|b| next.swap_remove(b));
            if cur.is_some_and(|c| wk.zrange[c].0 == nmin) {
                nmin = qmin(next, wk.zrange);
            }
        } else if let Some(p) = next.iter().position(|&q| q == s) {
            next.swap_remove(p);
            if wk.zrange[s].0 == nmin {
                nmin = qmin(next, wk.zrange);
            }
        }
    }
    emit(out, act, x, xb, cur);
    wk.evals
}

/// Appends the visible piece `[x0, x1)` of `cur` (background if `None`), if non-empty.
pub(super) fn emit(out: &mut Vec<Piece>, act: &[Active], x0: i64, x1: i64, cur: Option<usize>) {
    if x1 > x0 {
        out.push(Piece {
            x0,
            x1,
            tri: cur.map_or(-1, |s| act[s].idx),
            slot: cur.unwrap_or(usize::MAX),
        });
    }
}

/// Sorts `v` by insertion while at most `budget` elements move; `false` (and `v` a
/// permutation of itself, partly sorted) once more would.
fn insertion_sort_bounded(v: &mut [u64], budget: usize) -> bool {
    let mut moved = 0;
    for i in 1..v.len() {
        let x = v[i];
        let mut j = i;
        while j > 0 && v[j - 1] > x {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
        moved += i - j;
        if moved > budget {
            return false;
        }
    }
    true
}

/// The sorted `a` and `b` merged into `out`.
fn merge_sorted(a: &[u64], b: &[u64], out: &mut Vec<u64>) {
    out.clear();
    out.reserve(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] <= b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
}

/// Buffers of [`walk`], reused from sub-scanline to sub-scanline, and the crossings'
/// order carried from one sub-scanline of a band to the next.
#[derive(Default)]
pub(super) struct WalkScratch {
    /// Crossings, as sort keys (see [`walk`]), sorted: the last line's until the next
    /// walk re-sorts them.
    pub(super) ev: Vec<u64>,
    /// Scratch of the re-sort: the keys of the polygons a line adds to the last line's,
    /// and the last line's keys carried to the new x.
    fresh: Vec<u64>,
    carried: Vec<u64>,
    /// Per active polygon: were its crossings among the last line's.
    kept: Vec<bool>,
    /// Per candidate of the band: its slot in the current line's active list, or
    /// [`NO_SLOT`].
    slot_of: Vec<u32>,
    /// The stack NEXT.
    pub(super) next: Vec<usize>,
    /// Per active polygon, its last two depths `(x, z)` (older first).
    pub(super) zcache: Vec<[(i64, i64); 2]>,
    /// Per active polygon, the least and greatest depth on its part of the line.
    pub(super) zrange: Vec<(i64, i64)>,
}

impl WalkScratch {
    /// Starts a band: no crossings carried over.
    pub(super) fn new_band(&mut self) {
        self.ev.clear();
    }

    /// The slots of the band's `n` candidates on the line, for the hit tests to fill.
    pub(super) fn slots(&mut self, n: usize) -> &mut [u32] {
        self.slot_of.resize(n, NO_SLOT);
        &mut self.slot_of[..n]
    }
}

/// Whether a depth in `rp` is less than one in `rq`, when the two ranges (`(least,
/// greatest)`) settle it for every such pair: they are apart, so the depths differ and
/// their order is the ranges'. `None` when they meet (equal depths, and with them the
/// slope and tie rules of [`Walker::front`], are possible).
fn ahead_by_ranges(rp: (i64, i64), rq: (i64, i64)) -> Option<bool> {
    if rp.1 < rq.0 {
        Some(true)
    } else if rq.1 < rp.0 {
        Some(false)
    } else {
        None
    }
}

/// Depth comparisons of one sub-scanline walk, counting plane evaluations.
pub(super) struct Walker<'a, 'b, 'c> {
    pub(super) act: &'a [Active<'b>],
    pub(super) evals: u64,
    /// Per active polygon, its last two depths: the walk asks for the same polygon at
    /// the same crossing again and again (the count of evaluations is unchanged; only
    /// the arithmetic is not repeated).
    pub(super) zcache: &'c mut [[(i64, i64); 2]],
    /// Per active polygon, bounds of its depths on the line (see [`WalkScratch`]).
    pub(super) zrange: &'c [(i64, i64)],
}

impl Walker<'_, '_, '_> {
    /// Depth of active polygon `s` at `x` (one evaluation).
    #[inline]
    pub(super) fn zat(&mut self, s: usize, x: i64) -> i64 {
        self.evals += 1;
        self.z(s, x)
    }

    /// [`Walker::zat`] without counting: for bounds that decide comparisons whose
    /// evaluations are counted where they are made (or counted without being made).
    #[inline]
    fn z(&mut self, s: usize, x: i64) -> i64 {
        let c = &mut self.zcache[s];
        if c[1].0 == x {
            return c[1].1;
        }
        if c[0].0 == x {
            c.swap(0, 1);
            return c[1].1;
        }
        let z = self.act[s].z.at(x, ZF);
        c[0] = c[1];
        c[1] = (x, z);
        z
    }

    /// Is `p` in front of `q` at x (depth, then slope to the right, then tie order)? `x`
    /// lies on both polygons' parts of the line.
    pub(super) fn front(&mut self, p: usize, q: usize, x: i64) -> bool {
        // Depth ranges apart on the line settle it without the two evaluations, which are
        // counted: each depth at x lies in its polygon's range (the rounded plane is
        // monotone along the line, the range its two ends).
        if let Some(ahead) = ahead_by_ranges(self.zrange[p], self.zrange[q]) {
            self.evals += 2;
            return ahead;
        }
        let (zp, zq) = (self.zat(p, x), self.zat(q, x));
        if zp != zq {
            return zp < zq;
        }
        let act = self.act;
        let (sp, sq) = (act[p].z.s * act[q].z.d, act[q].z.s * act[p].z.d);
        if sp != sq {
            return sp < sq;
        }
        tie_front(&act[p], &act[q])
    }

    /// The first x in `(x, ex]` where a polygon of `next` is in front of the current one
    /// `c` (the earliest over `next`, the first listed on a tie), if any passes it.
    pub(super) fn first_pass(&mut self, c: usize, next: &[usize], x: i64, ex: i64) -> Option<i64> {
        let mut best: Option<i64> = None;
        // `c`'s depth at `ex`, evaluated only when the bounds alone do not settle it
        // (`c_end` is at most `c`'s greatest depth on the line).
        let mut c_end: Option<i64> = None;
        let c_max = self.zrange[c].1;
        for &q in next {
            let q_min = self.zrange[q].0;
            if q_min >= c_max || q_min >= *c_end.get_or_insert_with(|| self.z(c, ex)) {
                // q is nowhere on the line nearer than c is at `ex`, so not there: it does
                // not pass. The four evaluations below are counted, not computed.
                self.evals += 4;
                continue;
            }
            let (za, zb) = (
                self.zat(q, x) - self.zat(c, x),
                self.zat(q, ex) - self.zat(c, ex),
            );
            if za >= 0 && zb < 0 {
                // First x in (x, ex] where q is in front: d(x*) < 0.
                let xs = x + ((ex - x) as i128 * za as i128 / (za - zb) as i128) as i64 + 1;
                let xs = xs.min(ex);
                if best.is_none_or(|b| xs < b) {
                    best = Some(xs);
                }
            }
        }
        best
    }

    /// Position in `next` of its front-most polygon at `x` (the first listed on a tie).
    pub(super) fn nearest(&mut self, next: &[usize], x: i64) -> Option<usize> {
        let mut best: Option<usize> = None;
        for (ni, &q) in next.iter().enumerate() {
            best = match best {
                None => Some(ni),
                Some(b)
                    if self.zrange[q].0 > self.zrange[next[b]].1
                        || self.zrange[q].0 > self.z(next[b], x) =>
                {
                    // q is behind the best at x wherever it is on the line (behind the
                    // best's farthest depth, or behind its depth at x): `front` would
                    // find it farther. Its two evaluations are counted.
                    self.evals += 2;
                    Some(b)
                }
                Some(b) => {
                    if self.front(q, next[b], x) {
                        Some(ni)
                    } else {
                        Some(b)
                    }
                }
            };
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ahead_by_ranges` against every pair of depths in small ranges: where it answers,
    /// every pair differs and orders as it says; it answers for every pair of ranges
    /// that are apart.
    #[test]
    fn ranges_apart_order_every_pair_of_depths() {
        let ranges: Vec<(i64, i64)> = (-3..=3)
            .flat_map(|lo| (lo..=3).map(move |hi| (lo, hi)))
            .collect();
        let mut answered = 0;
        for &rp in &ranges {
            for &rq in &ranges {
                let pairs = || (rp.0..=rp.1).flat_map(|zp| (rq.0..=rq.1).map(move |zq| (zp, zq)));
                match ahead_by_ranges(rp, rq) {
                    Some(ahead) => {
                        answered += 1;
                        assert!(pairs().all(|(zp, zq)| zp != zq && (zp < zq) == ahead));
                    }
                    None => assert!(pairs().any(|(zp, zq)| zp == zq), "{rp:?} {rq:?}"),
                }
            }
        }
        assert!(answered > 100, "{answered}");
    }

    /// The re-sort of carried crossings: the bounded insertion sort sorts whenever it
    /// reports success, gives up on a reversed list, and the merge of two sorted lists is
    /// their sorted union (duplicates kept).
    #[test]
    fn carried_order_sorts_and_merges() {
        let mut rng = crate::rng::Lcg64(0x0c2_055e5);
        for case in 0..2000 {
            let n = (rng.step() % 300) as usize;
            // Nearly sorted: a sorted list with a few neighbours swapped and a few moved
            // far; every fifth case fully shuffled-looking.
            let mut v: Vec<u64> = (0..n as u64).map(|i| i * 3 + rng.step() % 3).collect();
            let swaps = if case % 5 == 0 { 10 * n } else { n / 20 + 1 };
            for _ in 0..swaps.min(n * n) {
                if n < 2 {
                    break;
                }
                let i = (rng.step() % (n as u64 - 1)) as usize;
                let j = if case % 5 == 0 {
                    (rng.step() % n as u64) as usize
                } else {
                    i + 1
                };
                v.swap(i, j);
            }
            let mut want = v.clone();
            want.sort_unstable();
            let mut got = v.clone();
            if insertion_sort_bounded(&mut got, 4 * n + 64) {
                assert_eq!(got, want, "case {case}");
            } else {
                got.sort_unstable();
                assert_eq!(got, want, "case {case}");
            }
            let m = (rng.step() % 40) as usize;
            let mut b: Vec<u64> = (0..m).map(|_| rng.step() % (3 * n as u64 + 5)).collect();
            b.sort_unstable();
            let mut out = vec![7; 3];
            merge_sorted(&want, &b, &mut out);
            let mut all = [want.clone(), b].concat();
            all.sort_unstable();
            assert_eq!(out, all, "case {case}");
        }
        let mut rev: Vec<u64> = (0..500).rev().collect();
        assert!(!insertion_sort_bounded(&mut rev, 4 * 500 + 64));
        let mut sorted: Vec<u64> = (0..500).collect();
        assert!(insertion_sort_bounded(&mut sorted, 0));
    }
}
