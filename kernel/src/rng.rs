//! The random number source: a 32-bit PCG stream whose start depends only on
//! (seed, pixel, sample index), so an image never depends on tile order or thread count.
//! Integer state only, 32-bit arithmetic only (cheap on a Cortex-M0).

use crate::math::Vec2;

/// PCG-RXS-M-XS 32 output permutation of one LCG step (O'Neill 2014; "pcg_hash").
#[inline]
fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A deterministic stream of uniform random numbers in [0, 1).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sampler {
    state: u32,
}

impl Sampler {
    /// The stream for one camera sample: `sample` of pixel `pixel` (row-major index) under `seed`.
    #[inline]
    pub fn new(seed: u32, pixel: u32, sample: u32) -> Self {
        let s = pcg_hash(seed ^ pcg_hash(pixel ^ pcg_hash(sample)));
        Self { state: s }
    }

    /// The next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.state = self.state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let s = self.state;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// A uniform number in [0, 1): 24 random bits, exactly representable in f32.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniform numbers in [0, 1)^2.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_deterministic_and_distinct() {
        let mut a = Sampler::new(7, 3, 1);
        let mut b = Sampler::new(7, 3, 1);
        let mut c = Sampler::new(7, 3, 2);
        let mut d = Sampler::new(8, 3, 1);
        let (xa, xb, xc, xd) = (a.next_u32(), b.next_u32(), c.next_u32(), d.next_u32());
        assert_eq!(xa, xb);
        assert_ne!(xa, xc);
        assert_ne!(xa, xd);
    }

    #[test]
    fn uniform_numbers_have_the_right_mean_and_range() {
        let mut s = Sampler::new(1, 2, 3);
        let n = 100_000;
        let mut sum = 0.0f32;
        for _ in 0..n {
            let x = s.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += x;
        }
        // Standard error of the mean of U(0,1) is sqrt(1/12/n); allow z < 4.
        let se = (1.0 / 12.0 / n as f32).sqrt();
        assert!((sum / n as f32 - 0.5).abs() < 4.0 * se);
    }
}
