//! Depth bounds of a lattice row, a block of samples at a time: a software shortcut of
//! the golden model (no stage of the modelled hardware keeps them), which leaves out the
//! samples of a triangle that cannot pass the depth test without testing them one by one.
//! The samples it leaves out would have changed nothing; the raster still counts each
//! covered sample as a depth evaluation ([`super::LatticeRaster::row`]).

/// Samples per block of [`DepthBounds`].
pub(super) const DEPTH_BLOCK: usize = 32;

thread_local! {
    /// Each thread's [`DepthBounds`] (the rows it rasterizes reuse it).
    pub(super) static DEPTH_BOUNDS: std::cell::RefCell<DepthBounds> = Default::default();
}

/// Per block of [`DEPTH_BLOCK`] samples of one lattice row, an upper bound of the depths
/// stored there: exact once recomputed, and kept until a triangle writes into the block,
/// after which it is recomputed when next asked for. A triangle whose smallest depth on
/// the row is not in front of a block's bound (`≥`, or `>` for a decal, the depth test's
/// opposite) passes at no sample of that block.
#[derive(Default)]
pub(super) struct DepthBounds {
    pub(super) max: Vec<i64>,
    stale: Vec<bool>,
}

impl DepthBounds {
    /// A row of `n` samples, all empty (`i64::MAX`).
    pub(super) fn reset(&mut self, n: usize) {
        let nb = n.div_ceil(DEPTH_BLOCK);
        self.max.clear();
        self.max.resize(nb, i64::MAX);
        self.stale.clear();
        self.stale.resize(nb, false);
    }

    /// Samples `lo ..= hi` were written.
    pub(super) fn touch(&mut self, lo: usize, hi: usize) {
        self.stale[lo / DEPTH_BLOCK..=hi / DEPTH_BLOCK].fill(true);
    }

    /// Whether no sample of block `k` of `zr` passes the depth test of a triangle whose
    /// depths on the row are all at least `zmin`.
    fn hides(&mut self, zr: &[i64], k: usize, zmin: i128, decal: bool) -> bool {
        if self.stale[k] {
            let s = k * DEPTH_BLOCK;
            let e = (s + DEPTH_BLOCK).min(zr.len());
            self.max[k] = zr[s..e].iter().copied().max().unwrap_or(i64::MAX);
            self.stale[k] = false;
        }
        let bound = self.max[k] as i128;
        if decal {
            zmin > bound
        } else {
            zmin >= bound
        }
    }

    /// `lo ..= hi` without the blocks at either end where no sample can pass, `ends`
    /// the triangle's depths at `lo` and `hi` (the per-sample depths are `(Z + a·dZ) >>
    /// 20`, linear before the shift, so every depth between lies between them).
    pub(super) fn trim(
        &mut self,
        zr: &[i64],
        (mut lo, mut hi): (i64, i64),
        ends: (i128, i128),
        decal: bool,
    ) -> (i64, i64) {
        // Depths beyond 64 bits wrap where the row stores them: no bound is claimed.
        let fits = |v: i128| i64::try_from(v).is_ok();
        if !fits(ends.0) || !fits(ends.1) {
            return (lo, hi);
        }
        let zmin = ends.0.min(ends.1);
        let block = DEPTH_BLOCK as i64;
        while lo <= hi && self.hides(zr, (lo / block) as usize, zmin, decal) {
            lo = (lo / block + 1) * block;
        }
        while lo <= hi && self.hides(zr, (hi / block) as usize, zmin, decal) {
            hi = (hi / block) * block - 1;
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::depth;
    use crate::rng::XorShift64Star as Rng;

    /// The depth bounds trim exactly the blocks at a range's ends where no sample passes
    /// the depth test for the triangle's nearest depth (the best any of its samples can
    /// do): random rows with repeated depths, ranges, nearest depths at, just below and
    /// just above a block's largest depth, decals and not, bounds stale and fresh.
    #[test]
    fn depth_bounds_trim_the_blocks_no_sample_can_pass() {
        let mut rng = Rng(0xb0_0d5);
        let (mut trimmed, mut kept) = (0, 0);
        for case in 0..4000 {
            let n = 1 + (rng.next_u64() % 150) as usize;
            let zr: Vec<i64> = (0..n)
                .map(|_| match rng.next_u64() % 60 {
                    0 => i64::MAX,
                    _ => 100 + (rng.next_u64() % 4) as i64,
                })
                .collect();
            let mut hz = DepthBounds::default();
            hz.reset(n);
            if case % 2 == 0 {
                hz.touch(0, n - 1);
            } else {
                // Fresh bounds, as the recomputation gives them.
                for (k, m) in hz.max.iter_mut().enumerate() {
                    *m = *zr[k * DEPTH_BLOCK..((k + 1) * DEPTH_BLOCK).min(n)]
                        .iter()
                        .max()
                        .unwrap();
                }
            }
            let a = (rng.next_u64() % n as u64) as i64;
            let b = (rng.next_u64() % n as u64) as i64;
            let (lo, hi) = (a.min(b), a.max(b));
            let zmin = 99 + (rng.next_u64() % 7) as i128;
            let decal = rng.next_u64().is_multiple_of(3);
            let ends = if rng.next_u64().is_multiple_of(2) {
                (zmin, zmin + 5)
            } else {
                (zmin + 5, zmin)
            };
            let got = hz.trim(&zr, (lo, hi), ends, decal);
            // A block is left out when none of its samples would take the nearest depth.
            let hopeless = |k: i64| {
                let s = (k as usize) * DEPTH_BLOCK;
                !zr[s..(s + DEPTH_BLOCK).min(n)]
                    .iter()
                    .any(|&zb| depth::passes(zmin, zb as i128, decal))
            };
            let blk = DEPTH_BLOCK as i64;
            let (mut wlo, mut whi) = (lo, hi);
            while wlo <= whi && hopeless(wlo / blk) {
                wlo = (wlo / blk + 1) * blk;
            }
            while wlo <= whi && hopeless(whi / blk) {
                whi = whi / blk * blk - 1;
            }
            let want = if wlo > whi { None } else { Some((wlo, whi)) };
            let got_some = (got.0 <= got.1).then_some(got);
            assert_eq!(
                got_some, want,
                "case {case}: {zr:?} {lo}..={hi} zmin {zmin} decal {decal}"
            );
            if got != (lo, hi) {
                trimmed += 1;
            } else {
                kept += 1;
            }
        }
        assert!(
            trimmed > 500 && kept > 500,
            "{trimmed} trimmed, {kept} kept"
        );
    }
}
