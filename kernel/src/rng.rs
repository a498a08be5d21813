//! The sample streams. A camera sample's random numbers depend only on (seed, pixel, sample
//! index), so an image never depends on tile order or thread count. Integer state only, 32-bit
//! arithmetic only (cheap on a Cortex-M0, the same bits everywhere), no tables.
//!
//! Two streams ([`SamplerKind`]):
//! - **independent**: a 32-bit PCG stream per camera sample;
//! - **sobol**: padded, Owen-scrambled Sobol (Burley 2020, "Practical Hash-based Owen
//!   Scrambling", JCGT 9(4); pbrt-v4's `PaddedSobolSampler`). Request d of camera sample i of a
//!   pixel takes Sobol dimensions 0 and 1 of a shuffled index (i Owen-scrambled with a hash of
//!   (seed, pixel, d)), and Owen-scrambles each coordinate with its own seed. The first 2^m
//!   samples of a pixel are a (0, m, 2)-net in every 2-D request, and every point is uniformly
//!   distributed, so estimates stay unbiased. Prefer power-of-two sample counts.

use crate::math::Vec2;

/// PCG-RXS-M-XS 32 output permutation of one LCG step (O'Neill 2014; "pcg_hash").
#[inline]
fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A cheap 32-bit mixer (xor-shift-multiply; Wellons' "lowbias32" first round), for seeds
/// derived from a hash.
#[inline]
fn mix(x: u32) -> u32 {
    let x = (x ^ (x >> 16)).wrapping_mul(0x7feb_352d);
    x ^ (x >> 15)
}

/// Odd multipliers that turn a request's hash into the scramble seeds of its two coordinates
/// (bijections of the hash, distinct from it and from each other).
const SEED_0: u32 = 0x2c1b_3c6d;
const SEED_1: u32 = 0x297a_2d39;

/// Owen scramble in the bit-reversed domain: bit k of the result is bit k of `v` flipped by a
/// function of `seed` and the bits below k only (every step is an addition or `v ^= v * even`,
/// each of which has that property, and is a bijection). On the reversed digits of a number in
/// [0, 1) this permutes every elementary interval's children, as Owen's nested scrambling does.
/// The first rounds of the Laine-Karras hash (Burley 2020), kept short for the Cortex-M: the seed
/// enters by addition, so every point is uniformly distributed whatever the mixing after it.
#[inline]
fn owen_reversed(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v
}

/// Sobol dimension 1 of `index`, bit-reversed (digit k of the point in bit k). Its generator
/// matrix is Pascal's triangle mod 2: digit k is the xor of the index bits j with k a subset of j
/// (Lucas), a superset-sum transform over the 5 bits of the position, one masked xor-shift each.
#[inline]
fn sobol1_reversed(index: u32) -> u32 {
    let mut w = index;
    w ^= (w >> 1) & 0x5555_5555;
    w ^= (w >> 2) & 0x3333_3333;
    w ^= (w >> 4) & 0x0f0f_0f0f;
    w ^= (w >> 8) & 0x00ff_00ff;
    w ^= w >> 16;
    w
}

/// 32 bits as a number in [0, 1): the top 24, exactly representable in f32.
#[inline]
fn to_unit(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The closed set of sample streams.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SamplerKind {
    /// Independent uniform numbers (PCG).
    Independent,
    /// Padded Owen-scrambled Sobol: every 2-D request is a scrambled (0, 2)-sequence.
    #[default]
    Sobol,
}

impl SamplerKind {
    /// Every sample stream, the default first.
    pub const ALL: [SamplerKind; 2] = [SamplerKind::Sobol, SamplerKind::Independent];

    /// The stream's name (command line, scene files, charts).
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Sobol => "sobol",
        }
    }

    /// The stream called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// The random numbers of one camera sample, request by request: `next_f32` for one number,
/// `next_2d` for a pair that should be stratified together.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sampler {
    kind: SamplerKind,
    /// PCG state (independent) or the pixel's hash (sobol).
    state: u32,
    /// Sample index within the pixel (sobol).
    index: u32,
    /// The same, bit-reversed (sobol).
    index_reversed: u32,
    /// The next request's dimension (sobol).
    dim: u32,
}

impl Sampler {
    /// An independent (PCG) stream for `sample` of pixel `pixel` (row-major index) under `seed`;
    /// also a plain random number generator for tests and tools.
    #[inline]
    pub fn new(seed: u32, pixel: u32, sample: u32) -> Self {
        Self::with_kind(SamplerKind::Independent, seed, pixel, sample)
    }

    /// The stream of kind `kind` for `sample` of pixel `pixel` under `seed`.
    #[inline]
    pub fn with_kind(kind: SamplerKind, seed: u32, pixel: u32, sample: u32) -> Self {
        match kind {
            SamplerKind::Independent => {
                let state = pcg_hash(seed ^ pcg_hash(pixel ^ pcg_hash(sample)));
                Self { kind, state, index: sample, index_reversed: 0, dim: 0 }
            }
            SamplerKind::Sobol => {
                let state = pcg_hash(seed ^ pcg_hash(pixel));
                Self { kind, state, index: sample, index_reversed: sample.reverse_bits(), dim: 0 }
            }
        }
    }

    /// The kind of stream.
    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    #[inline]
    fn pcg_next(&mut self) -> u32 {
        self.state = self.state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let s = self.state;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// The next Sobol request: its hash and its sample index. The first request (the pixel
    /// position) takes the index itself; every later one a shuffled index, an Owen scramble of the
    /// index's reversed digits (a nested uniform shuffle: the first 2^m samples get one aligned
    /// block of 2^m indices), so the pairing of points across requests is random.
    #[inline]
    fn sobol_request(&mut self) -> (u32, u32) {
        // A Weyl sequence of request seeds, mixed.
        self.state = self.state.wrapping_add(0x9e37_79b9);
        let hash = mix(self.state);
        let first = self.dim == 0;
        self.dim = self.dim.wrapping_add(1);
        let index = if first { self.index } else { owen_reversed(self.index_reversed, hash).reverse_bits() };
        (hash, index)
    }

    /// The next 32 random bits (for sobol: the next 1-D request's digits).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        match self.kind {
            SamplerKind::Independent => self.pcg_next(),
            SamplerKind::Sobol => {
                let (hash, index) = self.sobol_request();
                // Sobol dimension 0 is the bit-reversed index: in the reversed domain, the index.
                owen_reversed(index, hash.wrapping_mul(SEED_0)).reverse_bits()
            }
        }
    }

    /// A uniform number in [0, 1): 24 bits, exactly representable in f32.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        to_unit(self.next_u32())
    }

    /// Two uniform numbers in [0, 1)^2, stratified together by the sobol stream.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let (x, y) = self.next_2d_reusable();
        Vec2::new(to_unit(x), y)
    }

    /// A 2-D request like [`Sampler::next_2d`] whose first coordinate comes as its 32 bits (its
    /// top 24 are the `x` that `next_2d` would give): for a number that makes a discrete choice
    /// and is then reused, rescaled within the chosen option's share, as the first coordinate
    /// of a stratified pair (see [`LightSampler::select`](crate::light_sampler::LightSampler)).
    #[inline]
    pub fn next_2d_reusable(&mut self) -> (u32, f32) {
        match self.kind {
            SamplerKind::Independent => {
                let x = self.pcg_next();
                (x, to_unit(self.pcg_next()))
            }
            SamplerKind::Sobol => {
                let (hash, index) = self.sobol_request();
                let (s0, s1) = (hash.wrapping_mul(SEED_0), hash.wrapping_mul(SEED_1));
                let x = owen_reversed(index, s0).reverse_bits();
                let y = owen_reversed(sobol1_reversed(index), s1).reverse_bits();
                (x, to_unit(y))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_deterministic_and_distinct() {
        for kind in SamplerKind::ALL {
            let mut a = Sampler::with_kind(kind, 7, 3, 1);
            let mut b = Sampler::with_kind(kind, 7, 3, 1);
            let mut c = Sampler::with_kind(kind, 7, 3, 2);
            let mut d = Sampler::with_kind(kind, 8, 3, 1);
            let mut e = Sampler::with_kind(kind, 7, 4, 1);
            let (xa, xb, xc, xd, xe) = (a.next_u32(), b.next_u32(), c.next_u32(), d.next_u32(), e.next_u32());
            assert_eq!(xa, xb);
            assert_ne!(xa, xc);
            assert_ne!(xa, xd);
            assert_ne!(xa, xe);
            // Successive requests differ.
            assert_ne!(a.next_u32(), xa);
        }
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

    /// Sobol dimension 1 from its direction numbers v_0 = 2^31, v_(j+1) = v_j ^ (v_j >> 1).
    fn sobol1_reference(index: u32) -> u32 {
        let (mut v, mut out) = (1u32 << 31, 0u32);
        for j in 0..32 {
            if index >> j & 1 == 1 {
                out ^= v;
            }
            v ^= v >> 1;
        }
        out
    }

    #[test]
    fn sobol_dimension_1_matches_its_direction_numbers() {
        let mut rng = Sampler::new(5, 6, 7);
        for i in (0..4096).chain((0..4096).map(|_| rng.next_u32())) {
            assert_eq!(sobol1_reversed(i).reverse_bits(), sobol1_reference(i), "index {i}");
        }
    }

    #[test]
    fn owen_scramble_is_a_nested_permutation() {
        // Bit k of the output depends on bits <= k of the input only: flipping bit k of the input
        // leaves bits < k alone, and the map is a bijection on every low-bit prefix.
        for seed in [0u32, 1, 0xdead_beef, 0x1234_5678] {
            let mut seen = [false; 256];
            for v in 0..256u32 {
                let o = owen_reversed(v, seed);
                for k in 0..8 {
                    let low = (1u32 << k) - 1;
                    assert_eq!(owen_reversed(v ^ (1 << k), seed) & low, o & low);
                }
                seen[(o & 0xff) as usize] = true;
            }
            assert!(seen.iter().all(|&s| s));
        }
    }

    #[test]
    fn every_2d_request_of_a_power_of_two_prefix_is_a_0m2_net() {
        // 2^m points: each of the m + 1 shapes of elementary interval of area 2^-m holds one.
        for m in [0u32, 1, 4, 6, 8] {
            let n = 1u32 << m;
            for pixel in [0u32, 17, 90_001] {
                let mut pts = [[Vec2::ZERO; 256]; 3];
                for i in 0..n {
                    let mut s = Sampler::with_kind(SamplerKind::Sobol, 42, pixel, i);
                    for p in pts.iter_mut() {
                        p[i as usize] = s.next_2d();
                    }
                }
                for (d, p) in pts.iter().enumerate() {
                    for a in 0..=m {
                        let (nx, ny) = (1u32 << a, 1u32 << (m - a));
                        let mut count = [0u16; 256];
                        for q in &p[..n as usize] {
                            let cell = (q.x * nx as f32) as u32 * ny + (q.y * ny as f32) as u32;
                            count[cell as usize] += 1;
                        }
                        assert!(
                            count[..n as usize].iter().all(|&c| c == 1),
                            "m {m} pixel {pixel} dim {d} a {a}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn names_round_trip() {
        for k in SamplerKind::ALL {
            assert_eq!(SamplerKind::from_name(k.name()), Some(k));
        }
        assert_eq!(SamplerKind::from_name("halton"), None);
        assert_eq!(SamplerKind::ALL[0], SamplerKind::default());
    }
}
