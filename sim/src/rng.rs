//! Seeded deterministic random generators for tests, stimulus and generated scenes.
//!
//! Not part of the model: the golden pipeline never draws random numbers. They live here,
//! once, so that every test, testbench stimulus and generated benchmark scene draws from
//! the same two documented sequences (and a generated scene stays byte-identical across
//! releases, which a third-party generator's version bump would not guarantee).

/// xorshift64* (Vigna 2014): `x ^= x >> 12; x ^= x << 25; x ^= x >> 27; x · 0x2545F4914F6CDD1D`.
#[derive(Clone, Debug)]
pub struct XorShift64Star(pub u64);

impl XorShift64Star {
    /// The next 64-bit output.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A uniform value in `[0, 1)` from the top 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Knuth's MMIX 64-bit linear congruential generator; outputs the top 53 bits as `[0, 1)`.
#[derive(Clone, Debug)]
pub struct Lcg64(pub u64);

impl Lcg64 {
    /// Advance the state: `s · 6364136223846793005 + 1442695040888963407`.
    pub fn step(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0
    }

    /// A uniform value in `[0, 1)` from the top 53 bits of the new state.
    pub fn unit(&mut self) -> f64 {
        (self.step() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform value in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

/// `count` random snapped triangles over a `w × h` screen (vertices up to 3 px outside
/// it, depths in `1..=10^6`, tags `k % 7`), every other one flat-coloured: the shared
/// input of the unit tests that compare two ways of rendering the same frame.
#[cfg(test)]
pub(crate) fn random_tris(
    seed: u64,
    count: usize,
    w: u32,
    h: u32,
) -> Vec<crate::setup::SnappedTri> {
    let mut rng = Lcg64(seed);
    (0..count)
        .map(|k| {
            let mut p = || {
                [
                    (rng.range(-3.0, w as f64 + 3.0) * 256.0) as i32,
                    (rng.range(-3.0, h as f64 + 3.0) * 256.0) as i32,
                ]
            };
            let v = [p(), p(), p()];
            let z = [0; 3].map(|_| (rng.unit() * 1_000_000.0) as u32 + 1);
            let mut colour = || [0; 3].map(|_| (rng.unit() * 255.0 * 4096.0) as u32);
            let c = if k % 2 == 0 {
                [colour(); 3]
            } else {
                [colour(), colour(), colour()]
            };
            crate::setup::SnappedTri {
                v,
                z,
                c,
                tag: (k % 7) as u16,
                ..Default::default()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xorshift_first_output_follows_the_recurrence() {
        // Seed 1: 1 ^ (1 << 25) = 0x2000001, the shifts right leave it unchanged.
        let mut r = XorShift64Star(1);
        let x1: u64 = {
            let mut x: u64 = 1;
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            x
        };
        assert_eq!(x1, 0x0200_0001);
        assert_eq!(r.next_u64(), x1.wrapping_mul(0x2545_F491_4F6C_DD1D));
    }

    #[test]
    fn units_stay_in_range() {
        let mut a = XorShift64Star(7);
        let mut b = Lcg64(7);
        for _ in 0..10_000 {
            let (u, v) = (a.unit(), b.unit());
            assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
        }
    }
}
