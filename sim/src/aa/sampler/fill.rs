//! The writes of one triangle's samples on one lattice row: each sample's depth, stepped
//! from the plane's value at the range's start, tested against the stored one in scene
//! order, and where it passes the triangle's index and its colours written (the closed
//! form of the module header of [`super`], in 64-bit sums where every value fits).

use crate::raster::depth;

/// A triangle's samples on one lattice row, [`fill_samples`] over the slices `out`
/// (depths, colours, triangle indices), `z` and `colours` the planes' values at the first
/// sample and their steps: in `i64` where the values at both ends (so every value
/// between) and the steps fit 62 bits, else in `i128`. Returns whether a sample was
/// written.
#[inline(always)]
pub(super) fn fill_range(
    z: (i128, i128),
    colours: impl Fn() -> [(i128, i128); 3],
    out: (&mut [i64], &mut [[u32; 3]], &mut [i32]),
    tri: (i32, bool),
) -> bool {
    let span = out.0.len().saturating_sub(1) as i128;
    let fits = |(v, d): (i128, i128)| {
        const LIM: i128 = 1 << 62;
        v.abs() < LIM && d.abs() < LIM && (v + span * d).abs() < LIM
    };
    if fits(z) {
        fill_samples::<i64>(z, colours, &fits, out, tri)
    } else {
        fill_samples::<i128>(z, colours, &fits, out, tri)
    }
}

/// A triangle's samples on one lattice row: depth `(Z + k·dZ) >> 20` tested against `zr`
/// in scene order (`decal`: `≤`), and where it passes the triangle's index `idx` and its
/// colours `clamp((C + k·dC) >> 32)` written, `k` the sample's offset in the slices (the
/// planes' values `Z`, `C` at `k = 0`). Depth sums run in `T`; the colours, set up by
/// `colours` at the first write, in `i64` where `fits` says all their values fit, else in
/// `i128`. Returns whether a sample was written.
#[inline(always)]
fn fill_samples<T>(
    (z, dz): (i128, i128),
    colours: impl Fn() -> [(i128, i128); 3],
    fits: &impl Fn((i128, i128)) -> bool,
    (zr, cr, tr): (&mut [i64], &mut [[u32; 3]], &mut [i32]),
    (idx, decal): (i32, bool),
) -> bool
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Shr<u32, Output = T> + Into<i128>,
    T: TryFrom<i128>,
{
    let narrow = |v: i128| T::try_from(v).ok().expect("checked by fits");
    let (mut zacc, dz) = (narrow(z), narrow(dz));
    // Up to the first sample that passes, depths only.
    let mut k0 = zr.len();
    for (k, zb) in zr.iter_mut().enumerate() {
        let zv = zacc.shr(20).into() as i64;
        zacc = zacc + dz;
        if depth::passes(zv, *zb, decal) {
            *zb = zv;
            k0 = k;
            break;
        }
    }
    if k0 == zr.len() {
        return false;
    }
    let cc = colours();
    let rest = Rest {
        k0,
        zacc,
        dz,
        decal,
        idx,
    };
    // The colour planes are linear in `k`: when their values at both ends of the slices
    // lie in range, so does every value between, and the clamp cannot act.
    let last = zr.len() as i128 - 1;
    let in_range = cc.iter().all(|&(c, d)| {
        let ends = [c >> 32, (c + last * d) >> 32];
        ends.iter().all(|e| (0..=COLOUR_MAX as i128).contains(e))
    });
    let out = (zr, cr, tr);
    match (cc.iter().all(|&p| fits(p)), in_range) {
        (true, true) => rest.fill::<i64, false>(narrow_colours(cc), out),
        (true, false) => rest.fill::<i64, true>(narrow_colours(cc), out),
        (false, true) => rest.fill::<i128, false>(cc, out),
        (false, false) => rest.fill::<i128, true>(cc, out),
    }
    true
}

/// The largest Q8.12 colour value.
const COLOUR_MAX: i64 = (255 << 12) + 4095;

/// Colour planes whose every value fits `i64` ([`fill_range`]'s test), narrowed.
fn narrow_colours(cc: [(i128, i128); 3]) -> [(i64, i64); 3] {
    cc.map(|(c, d)| (c as i64, d as i64))
}

/// The rest of a triangle's samples on one lattice row from the first that passed
/// (`k0`, already written but for its colours and index), `zacc` the depth sum of the
/// next.
struct Rest<T> {
    k0: usize,
    zacc: T,
    dz: T,
    decal: bool,
    idx: i32,
}

impl<T> Rest<T>
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Shr<u32, Output = T> + Into<i128>,
{
    /// Writes sample `k0`'s index and colours, then tests and writes the samples after
    /// it; colours `(C + k·dC) >> 32` in `U`, clamped when `CLAMP` (else every value is
    /// known to lie in range).
    #[inline(always)]
    fn fill<U, const CLAMP: bool>(
        self,
        cc: [(U, U); 3],
        (zr, cr, tr): (&mut [i64], &mut [[u32; 3]], &mut [i32]),
    ) where
        U: Copy
            + std::ops::Add<Output = U>
            + std::ops::Mul<Output = U>
            + std::ops::Shr<u32, Output = U>
            + Into<i128>
            + TryFrom<usize>,
    {
        let at = |k: usize| -> [u32; 3] {
            let k = U::try_from(k).ok().expect("a row's length fits");
            cc.map(|(c, d)| {
                let v: i128 = ((c + k * d) >> 32).into();
                if CLAMP {
                    v.clamp(0, COLOUR_MAX as i128) as u32
                } else {
                    v as u32
                }
            })
        };
        let Rest {
            k0,
            mut zacc,
            dz,
            decal,
            idx,
        } = self;
        tr[k0] = idx;
        cr[k0] = at(k0);
        let rest = zr[k0 + 1..]
            .iter_mut()
            .zip(&mut cr[k0 + 1..])
            .zip(&mut tr[k0 + 1..]);
        for (k, ((zb, c), ti)) in (k0 + 1..).zip(rest) {
            let zv = zacc.shr(20).into() as i64;
            zacc = zacc + dz;
            if depth::passes(zv, *zb, decal) {
                *zb = zv;
                *ti = idx;
                *c = at(k);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift64Star as Rng;

    /// The samples as the closed form states them, in `i128` throughout: sample `k` of the
    /// range has depth `(Z + k·dZ) >> 20` and colours `clamp((C + k·dC) >> 32)`.
    fn fill_literal(
        (z, dz): (i128, i128),
        cc: [(i128, i128); 3],
        zr: &mut [i64],
        cr: &mut [[u32; 3]],
        tr: &mut [i32],
        (idx, decal): (i32, bool),
    ) {
        for k in 0..zr.len() {
            let zv = ((z + k as i128 * dz) >> 20) as i64;
            if depth::passes(zv, zr[k], decal) {
                zr[k] = zv;
                tr[k] = idx;
                for ch in 0..3 {
                    let v = (cc[ch].0 + k as i128 * cc[ch].1) >> 32;
                    cr[k][ch] = v.clamp(0, (255 << 12) + 4095) as u32;
                }
            }
        }
    }

    /// `fill_range` (64-bit sums where they fit) writes what the closed form in 128 bits
    /// writes, over planes whose values at the range's ends lie below, near and beyond
    /// 2^62 (both sides of the narrowing test), decals and not, onto rows already drawn.
    #[test]
    fn narrowed_sums_are_the_closed_form() {
        let mut rng = Rng(0x5a3_91e5);
        let (mut narrow, mut wide, mut unclamped) = (0, 0, 0);
        for case in 0..20_000 {
            let len = 1 + (rng.next_u64() % 40) as usize;
            let value = |rng: &mut Rng| -> (i128, i128) {
                // Magnitudes from small to past 2^62, a step that may carry the far end
                // across the limit.
                let bits = [20u32, 50, 61, 62, 63, 70][(rng.next_u64() % 6) as usize];
                let v = (rng.next_u64() as i128) % (1i128 << bits.min(64));
                let v = v << bits.saturating_sub(64);
                let v = if rng.next_u64().is_multiple_of(2) {
                    v
                } else {
                    -v
                };
                let reach = (1i128 << 62) / len as i128;
                let d = (rng.next_u64() as i128 % (2 * reach + 1)) - reach;
                (v, if case % 7 == 0 { d * 3 } else { d })
            };
            // Colours that stay in 0..=255.4095 over the row (the clamp cannot act), in
            // a quarter of the cases.
            let colour = |rng: &mut Rng| -> (i128, i128) {
                if case % 4 == 1 {
                    let v = ((rng.next_u64() % (200 << 12)) as i128 + 4096) << 32;
                    (v, (rng.next_u64() % (1 << 33)) as i128 - (1 << 32))
                } else {
                    value(rng)
                }
            };
            let z = value(&mut rng);
            let cc = [colour(&mut rng), colour(&mut rng), colour(&mut rng)];
            let limit = |(v, d): (i128, i128)| {
                let e = v + (len as i128 - 1) * d;
                v.abs() < 1 << 62 && d.abs() < 1 << 62 && e.abs() < 1 << 62
            };
            if limit(z) && cc.iter().all(|&c| limit(c)) {
                narrow += 1;
            } else {
                wide += 1;
            }
            // Colour planes that never leave 0..=255.4095 over the row (no clamp).
            let last = len as i128 - 1;
            if cc.iter().all(|&(c, d)| {
                [c, c + last * d]
                    .iter()
                    .all(|e| (0..=(255 << 12) + 4095).contains(&(e >> 32)))
            }) {
                unclamped += 1;
            }
            let tri = (case, rng.next_u64().is_multiple_of(4));
            // A row already holding depths around the plane's, so that some samples pass.
            let zr0: Vec<i64> = (0..len)
                .map(|k| {
                    let at = ((z.0 + k as i128 * z.1) >> 20) as i64;
                    at.wrapping_add((rng.next_u64() % 3) as i64 - 1)
                })
                .collect();
            let (mut za, mut zb) = (zr0.clone(), zr0);
            let (mut ca, mut cb) = (vec![[7u32; 3]; len], vec![[7u32; 3]; len]);
            let (mut ta, mut tb) = (vec![-1; len], vec![-1; len]);
            fill_range(z, || cc, (&mut za, &mut ca, &mut ta), tri);
            fill_literal(z, cc, &mut zb, &mut cb, &mut tb, tri);
            assert_eq!(
                (za, ca, ta),
                (zb, cb, tb),
                "case {case}: z {z:?}, colours {cc:?}"
            );
        }
        assert!(
            narrow > 2000 && wide > 2000 && unclamped > 1000,
            "{narrow} narrow, {wide} wide, {unclamped} unclamped"
        );
    }
}
