//! The sample streams. A camera sample's random numbers depend only on (seed, pixel, sample
//! index), so an image never depends on tile order or thread count. Integer state only, 32-bit
//! arithmetic only (cheap on a Cortex-M0, the same bits everywhere), no tables.
//!
//! Two streams ([`SamplerKind`]):
//! - **independent**: a 32-bit PCG stream per camera sample;
//! - **sobol**: Owen-scrambled Sobol (Burley 2020, "Practical Hash-based Owen Scrambling",
//!   JCGT 9(4)), each coordinate scrambled with its own seed, a hash of (seed, pixel, request).
//!   The first [`JOINT_REQUESTS`] requests of camera sample i of a pixel (the pixel position,
//!   then the first light sample and the first BSDF sample of the multi-sample estimator) take
//!   Sobol dimensions (2, 3), (0, 1) and (4, 5) of i itself ([`JOINT_PAIRS`]: the light sample
//!   gets the (0, 2)-sequence), so that they are stratified *jointly*: the pixel position with
//!   the point on the light and with the BSDF direction, as a 6-D Sobol net. (A shadow's or a
//!   highlight's edge is a discontinuity in the pixel position and the sample at once.) Every
//!   later request is padded (pbrt-v4's `PaddedSobolSampler`): Sobol dimensions 0 and 1 of a
//!   shuffled index (i Owen-scrambled with the request's hash). The first 2^m samples of a pixel
//!   are a (t, m, 2)-net in every 2-D request: t = 0 for the light sample and the padded
//!   requests, t <= 2 for the pixel position's dimensions (2, 3) up to 2^10 samples, and for
//!   (4, 5) up to 2^7 (3 at 2^8). Every point is uniformly distributed, so estimates stay
//!   unbiased. Prefer power-of-two sample counts.

use crate::num::{SOFT_FLOAT, Vec2};

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
/// (bijections of the hash, distinct from it and from each other; the second is then mixed,
/// [`y_seed`]).
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

/// Sobol dimensions 2 to 5 (Joe and Kuo 2008, `new-joe-kuo-6.21201`: primitive polynomials
/// x^2 + x + 1, x^3 + x + 1, x^3 + x^2 + 1, x^4 + x^3 + 1), bit-reversed: entry j of a row is
/// the generator matrix's column for index bit j with digit k in bit k. 512 bytes.
const SOBOL_2_TO_5_REVERSED: [[u32; 32]; 4] = [
    [
        0x00000001, 0x00000003, 0x00000006, 0x00000009, 0x00000017, 0x0000003a, 0x00000071, 0x000000a3,
        0x00000116, 0x00000339, 0x00000677, 0x000009aa, 0x00001601, 0x00003903, 0x00007706, 0x0000aa09,
        0x00010117, 0x0003033a, 0x00060671, 0x000909a3, 0x00171616, 0x003a3939, 0x00717777, 0x00a3aaaa,
        0x01170001, 0x033a0003, 0x06710006, 0x09a30009, 0x16160017, 0x3939003a, 0x77770071, 0xaaaa00a3,
    ],
    [
        0x00000001, 0x00000003, 0x00000004, 0x0000000a, 0x0000001f, 0x0000002e, 0x00000045, 0x000000c9,
        0x0000011b, 0x000002a4, 0x0000079a, 0x00000b67, 0x0000101e, 0x0000302d, 0x00004041, 0x0000a0c3,
        0x0001f104, 0x0002e28a, 0x000457df, 0x000c9bae, 0x0011a105, 0x002a7289, 0x0079e7db, 0x00b6dba4,
        0x0100011a, 0x030002a7, 0x0400079e, 0x0a000b6d, 0x1f001001, 0x2e003003, 0x45004004, 0xc900a00a,
    ],
    [
        0x00000001, 0x00000002, 0x00000004, 0x0000000d, 0x0000001f, 0x0000003b, 0x0000005e, 0x000000b9,
        0x0000015a, 0x000003f4, 0x00000685, 0x00000d0f, 0x0000115b, 0x000023f6, 0x00004681, 0x0000dd02,
        0x0001e144, 0x000393cd, 0x0005a6df, 0x000b4dbb, 0x0014401e, 0x003cd039, 0x006df05a, 0x00dbb0b4,
        0x0101e145, 0x020393cf, 0x0405a6db, 0x0d0b4db6, 0x1f144001, 0x3b3cd002, 0x5e6df004, 0xb9dbb00d,
    ],
    [
        0x00000001, 0x00000002, 0x00000006, 0x0000000c, 0x00000013, 0x00000024, 0x0000006a, 0x000000df,
        0x00000107, 0x0000020e, 0x00000615, 0x00000c28, 0x00001379, 0x000024fb, 0x00006b6d, 0x0000ddd1,
        0x00010012, 0x00020026, 0x0006006c, 0x000c00d3, 0x00130114, 0x0024022a, 0x006a067f, 0x00df0cf7,
        0x0107127e, 0x020e26f5, 0x06156d78, 0x0c28d1f9, 0x1378136b, 0x24f924dd, 0x6b6b6b01, 0xdddddd02,
    ],
];

/// How many requests of a camera sample are stratified jointly (Sobol dimensions 0 to 5 of the
/// sample index, two per request); later ones are padded.
pub const JOINT_REQUESTS: u32 = JOINT_PAIRS.len() as u32;

/// The Sobol pair (dimensions 2p, 2p + 1) of each joint request: the pixel position takes pair 1,
/// the first light sample pair 0 (dimensions 0 and 1, the one (0, 2)-sequence of the six: a
/// light sample's error depends on its 2-D stratification more than the pixel position's does),
/// the first BSDF sample pair 2.
pub const JOINT_PAIRS: [u32; 3] = [1, 0, 2];

/// Sobol dimensions (2d, 2d + 1) of `index` for a joint pair `d` in 1..=2 ([`JOINT_PAIRS`]),
/// bit-reversed: the xor of the generator columns of the index's set bits (one pass over them
/// for both coordinates). Pair 0 and padded requests use [`sobol1_reversed`] instead.
#[cfg(not(target_pointer_width = "64"))]
#[inline]
fn sobol_pair_reversed(d: u32, index: u32) -> (u32, u32) {
    let row = (2 * d.saturating_sub(1)) as usize & 3;
    let (cx, cy) = (&SOBOL_2_TO_5_REVERSED[row], &SOBOL_2_TO_5_REVERSED[row | 1]);
    let (mut x, mut y, mut i, mut j) = (0u32, 0u32, index, 0usize);
    while i != 0 {
        // All ones when bit j of the index is set, else zero.
        let mask = 0u32.wrapping_sub(i & 1);
        x ^= cx[j & 31] & mask;
        y ^= cy[j & 31] & mask;
        i >>= 1;
        j += 1;
    }
    (x, y)
}

/// Sobol dimensions (2d, 2d + 1) of `index` for a joint pair `d` in 1..=2, bit-reversed, on
/// 64-bit hosts: the same xor of generator columns as the 32-bit targets' bit-by-bit pass (whose
/// images the firmware tests compare with the host's), four index bits at a time from
/// [`SOBOL_PAIRS_BY_NIBBLE`], both coordinates in one 64-bit word (x low, y high).
#[cfg(target_pointer_width = "64")]
#[inline]
fn sobol_pair_reversed(d: u32, index: u32) -> (u32, u32) {
    let table = &SOBOL_PAIRS_BY_NIBBLE[d.saturating_sub(1) as usize & 1];
    let (mut xy, mut i, mut k) = (0u64, index, 0usize);
    while i != 0 {
        xy ^= table[k & 7][(i & 15) as usize];
        i >>= 4;
        k += 1;
    }
    (xy as u32, (xy >> 32) as u32)
}

/// For joint pairs 1 and 2 and each nibble position k of the index, the xor of the generator
/// columns of pair (2d, 2d + 1) over the set bits of every nibble value, x in the low word and
/// y in the high one ([`SOBOL_2_TO_5_REVERSED`], rows 2(d - 1) and 2(d - 1) + 1). 2 KiB.
#[cfg(target_pointer_width = "64")]
const SOBOL_PAIRS_BY_NIBBLE: [[[u64; 16]; 8]; 2] = {
    let mut t = [[[0u64; 16]; 8]; 2];
    let mut p = 0;
    while p < 2 {
        let mut k = 0;
        while k < 8 {
            let mut v = 0;
            while v < 16 {
                let mut b = 0;
                while b < 4 {
                    if v >> b & 1 == 1 {
                        let j = 4 * k + b;
                        let (cx, cy) = (SOBOL_2_TO_5_REVERSED[2 * p][j], SOBOL_2_TO_5_REVERSED[2 * p + 1][j]);
                        t[p][k][v] ^= (cy as u64) << 32 | cx as u64;
                    }
                    b += 1;
                }
                v += 1;
            }
            k += 1;
        }
        p += 1;
    }
    t
};

/// The scramble seed of a 2-D request's second coordinate: mixed, so that its low bits (which
/// scramble the point's leading digits) do not follow from those of the first coordinate's seed.
/// (`hash * SEED_1` alone would share its lowest bit with `hash * SEED_0`: the leading digits of
/// x and y would be flipped together, and an unshuffled index's point, say sample 0, would fall
/// in two of the four quadrants only.)
#[inline]
fn y_seed(hash: u32) -> u32 {
    mix(hash.wrapping_mul(SEED_1))
}

/// 32 bits as a number in [0, 1): the top 24, exactly representable in f32. On the soft-float
/// cores the float is built from the bits (the leading one's position gives the exponent), not
/// by a conversion and a multiply: the same number.
#[inline]
pub(crate) fn to_unit(bits: u32) -> f32 {
    let v = bits >> 8;
    if SOFT_FLOAT { unit_from_bits(v) } else { v as f32 * (1.0 / 16_777_216.0) }
}

/// `v as f32 * 2^-24` for `v` below 2^24, from the bits: v = m 2^-shift with the leading one of
/// m at bit 23, so v 2^-24 has biased exponent 126 - shift, and m's leading one adds the last 1
/// to the exponent field. (Out of line: RV32IMC has no count-leading-zeros instruction, and
/// its inline expansion at every call costs flash.)
#[inline(never)]
fn unit_from_bits(v: u32) -> f32 {
    if v == 0 {
        return 0.0;
    }
    let shift = v.leading_zeros().saturating_sub(8);
    f32::from_bits(((125 - shift.min(23)) << 23).wrapping_add(v << shift))
}

/// `(x.reverse_bits(), y.reverse_bits())`. On 64-bit hosts as one 64-bit reversal (x86 has no
/// bit-reverse instruction: one shift-and-mask sequence instead of two); elsewhere (the
/// Cortex-M's `RBIT`, the M0's and RV32's 32-bit sequences) as two 32-bit ones. The same bits.
#[inline]
fn reverse_pair(x: u32, y: u32) -> (u32, u32) {
    #[cfg(target_pointer_width = "64")]
    {
        let r = (u64::from(y) << 32 | u64::from(x)).reverse_bits();
        ((r >> 32) as u32, r as u32)
    }
    #[cfg(not(target_pointer_width = "64"))]
    {
        (x.reverse_bits(), y.reverse_bits())
    }
}

crate::choices! {
    /// The closed set of sample streams.
    pub enum SamplerKind: "sampler" {
        /// Padded Owen-scrambled Sobol: every 2-D request is a scrambled (0, 2)-sequence.
        Sobol = "sobol", "padded Owen-scrambled Sobol (stratified)";
        /// Independent uniform numbers (PCG).
        Independent = "independent", "independent uniform numbers (PCG)";
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

    /// The next Sobol request: its hash and its point's two coordinates before scrambling,
    /// bit-reversed. The first [`JOINT_REQUESTS`] take the Sobol dimensions of their
    /// [`JOINT_PAIRS`] entry of the index itself; every later one dimensions 0 and 1 of a
    /// shuffled index, an Owen scramble of the index's reversed digits (a nested uniform
    /// shuffle: the first 2^m samples get one aligned block of 2^m indices), so the pairing of
    /// points across those requests is random.
    #[inline]
    fn sobol_request(&mut self) -> (u32, u32, u32) {
        // A Weyl sequence of request seeds, mixed.
        self.state = self.state.wrapping_add(0x9e37_79b9);
        let hash = mix(self.state);
        let d = self.dim;
        self.dim = self.dim.saturating_add(1);
        let index = match JOINT_PAIRS.get(d as usize) {
            Some(0) => self.index,
            Some(&pair) => {
                let (x, y) = sobol_pair_reversed(pair, self.index);
                return (hash, x, y);
            }
            None => owen_reversed(self.index_reversed, hash).reverse_bits(),
        };
        // Sobol dimension 0 is the bit-reversed index: in the reversed domain, the index.
        (hash, index, sobol1_reversed(index))
    }

    /// The next 32 random bits (for sobol: the next 1-D request's digits).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        match self.kind {
            SamplerKind::Independent => self.pcg_next(),
            SamplerKind::Sobol => {
                let (hash, x, _) = self.sobol_request();
                owen_reversed(x, hash.wrapping_mul(SEED_0)).reverse_bits()
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
    /// of a stratified pair (see [`LightSampler::select`](crate::light::LightSampler)).
    #[inline]
    pub fn next_2d_reusable(&mut self) -> (u32, f32) {
        match self.kind {
            SamplerKind::Independent => {
                let x = self.pcg_next();
                (x, to_unit(self.pcg_next()))
            }
            SamplerKind::Sobol => {
                let (hash, x, y) = self.sobol_request();
                let (s0, s1) = (hash.wrapping_mul(SEED_0), y_seed(hash));
                let (x, y) = reverse_pair(owen_reversed(x, s0), owen_reversed(y, s1));
                (x, to_unit(y))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_numbers_from_the_bits_are_the_converted_ones() {
        // Every 24-bit value: the soft-float cores' construction gives the host's numbers.
        for v in 0..1u32 << 24 {
            let want = v as f32 * (1.0 / 16_777_216.0);
            assert_eq!(unit_from_bits(v).to_bits(), want.to_bits(), "{v}");
        }
    }

    #[test]
    fn the_pair_reversal_is_two_32_bit_reversals() {
        let mut rng = Sampler::with_kind(SamplerKind::Independent, 1, 2, 3);
        for (x, y) in [(0, 0), (1, 0), (0, 1), (u32::MAX, 0), (0x8000_0001, 0x1234_5678)]
            .into_iter()
            .chain((0..1000).map(|_| (rng.next_u32(), rng.next_u32())))
        {
            assert_eq!(reverse_pair(x, y), (x.reverse_bits(), y.reverse_bits()), "{x:08x} {y:08x}");
        }
    }

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

    /// The t of the (t, m, 2)-net that the 2^m points `pts` form: the smallest t such that
    /// every elementary interval of area 2^(t - m) holds 2^t points (m + 1: not even that).
    fn t_value(pts: &[(f32, f32)], m: u32) -> u32 {
        (0..=m)
            .find(|&t| {
                let k = m - t;
                (0..=k).all(|a| {
                    let (nx, ny) = (1u32 << a, 1u32 << (k - a));
                    let mut count = [0u16; 256];
                    for &(x, y) in pts {
                        count[((x * nx as f32) as u32 * ny + (y * ny as f32) as u32) as usize] += 1;
                    }
                    count[..1 << k].iter().all(|&c| c == 1 << t)
                })
            })
            .unwrap_or(m + 1)
    }

    /// The first three 2-D requests of the first 2^m samples of a pixel (m <= 8).
    fn joint_points(pixel: u32, m: u32) -> [[(f32, f32); 256]; 4] {
        let mut pts = [[(0.0, 0.0); 256]; 4];
        for i in 0..1u32 << m {
            let mut s = Sampler::with_kind(SamplerKind::Sobol, 42, pixel, i);
            for p in pts.iter_mut() {
                let q = s.next_2d();
                p[i as usize] = (q.x, q.y);
            }
        }
        pts
    }

    #[test]
    fn every_2d_request_of_a_power_of_two_prefix_is_a_net() {
        // t of Sobol dimensions (2, 3) (the pixel position) and (4, 5) (the BSDF sample) for
        // m = 0..=8 (scrambling keeps it); the light sample and the padded requests are
        // (0, 2)-sequences.
        let t_joint = [[0u32, 0, 1, 2, 0, 1, 1, 1, 1], [0, 0, 1, 2, 0, 1, 1, 2, 3]];
        for m in 0..=8u32 {
            for pixel in [0u32, 17, 90_001] {
                let pts = joint_points(pixel, m);
                let n = 1usize << m;
                let t: [u32; 4] = core::array::from_fn(|d| t_value(&pts[d][..n], m));
                let want = [t_joint[0][m as usize], 0, t_joint[1][m as usize], 0];
                assert_eq!(t, want, "m {m} pixel {pixel}");
            }
        }
    }

    #[test]
    fn the_joint_requests_are_stratified_together() {
        // Every pair of coordinates of the pixel position, the light and the BSDF request (Sobol
        // dimensions 0 to 5) is a (t, m, 2)-net with t <= 3 up to 256 samples (randomly paired,
        // as padded requests are, they would almost never be); the padded fourth request is not
        // stratified with them.
        for pixel in [3u32, 1234] {
            let m = 8;
            let pts = joint_points(pixel, m);
            let coord = |c: usize| -> [f32; 256] {
                core::array::from_fn(|i| if c.is_multiple_of(2) { pts[c / 2][i].0 } else { pts[c / 2][i].1 })
            };
            for a in 0..6 {
                for b in a + 1..6 {
                    let (ca, cb) = (coord(a), coord(b));
                    let pair: [(f32, f32); 256] = core::array::from_fn(|i| (ca[i], cb[i]));
                    let t = t_value(&pair, m);
                    if a / 2 != b / 2 {
                        assert!(t <= 3, "pixel {pixel} coordinates {a} {b}: t {t}");
                    }
                }
                let (ca, cpad) = (coord(a), coord(6));
                let pair: [(f32, f32); 256] = core::array::from_fn(|i| (ca[i], cpad[i]));
                assert!(t_value(&pair, m) > 3, "pixel {pixel} coordinate {a} with the padded request");
            }
        }
    }

    /// Sobol direction numbers of the primitive polynomial of degree `s` with inner coefficients
    /// `a` and initial numbers `m` (Joe and Kuo 2008), bit-reversed as in the kernel's table.
    fn joe_kuo_reversed(s: usize, a: u32, m_init: &[u32]) -> [u32; 32] {
        let mut m = [0u32; 32];
        m[..s].copy_from_slice(m_init);
        for k in s..32 {
            let mut v = m[k - s] ^ (m[k - s] << s);
            for i in 1..s {
                if (a >> (s - 1 - i)) & 1 == 1 {
                    v ^= m[k - i] << i;
                }
            }
            m[k] = v;
        }
        core::array::from_fn(|k| (m[k] << (31 - k)).reverse_bits())
    }

    #[test]
    fn a_joint_pair_is_the_xor_of_its_columns_over_the_index_bits() {
        // Whichever way `sobol_pair_reversed` walks the index (bit by bit, or by nibbles on
        // 64-bit hosts), it is the xor of the table's columns over the set bits.
        let mut rng = Sampler::new(11, 12, 13);
        for d in 1..=2u32 {
            let row = 2 * (d as usize - 1);
            for i in (0..4096).chain((0..4096).map(|_| rng.next_u32())).chain([u32::MAX, 1 << 31]) {
                let (mut x, mut y) = (0, 0);
                for j in (0..32).filter(|j| i >> j & 1 == 1) {
                    x ^= SOBOL_2_TO_5_REVERSED[row][j];
                    y ^= SOBOL_2_TO_5_REVERSED[row + 1][j];
                }
                assert_eq!(sobol_pair_reversed(d, i), (x, y), "pair {d} index {i}");
            }
        }
    }

    #[test]
    fn the_table_holds_joe_kuo_dimensions_2_to_5() {
        let want = [
            joe_kuo_reversed(2, 1, &[1, 3]),
            joe_kuo_reversed(3, 1, &[1, 3, 1]),
            joe_kuo_reversed(3, 2, &[1, 1, 1]),
            joe_kuo_reversed(4, 1, &[1, 1, 3, 3]),
        ];
        assert_eq!(SOBOL_2_TO_5_REVERSED, want);
        // The pair of request 1 is the columns' xor over the index bits.
        let (x, y) = sobol_pair_reversed(1, 0b1011);
        assert_eq!(x, want[0][0] ^ want[0][1] ^ want[0][3]);
        assert_eq!(y, want[1][0] ^ want[1][1] ^ want[1][3]);
        assert_eq!(sobol_pair_reversed(2, 1 << 31), (want[2][31], want[3][31]));
    }

    #[test]
    fn every_coordinate_pair_of_one_sample_is_uniform_over_pixels() {
        // Sample 0 of 4096 pixels: every pair of the first three requests' six coordinates (and
        // of a padded one's) fills the four quadrants evenly (chi-square, 3 degrees of freedom,
        // below 16.3: p = 0.001); flipping the leading digits of x and y together would leave
        // two quadrants empty.
        for index in [0u32, 5] {
            let pts: [[f32; 8]; 4096] = core::array::from_fn(|pixel| {
                let mut s = Sampler::with_kind(SamplerKind::Sobol, 9, pixel as u32, index);
                let mut c = [0.0f32; 8];
                for k in 0..4 {
                    let q = s.next_2d();
                    (c[2 * k], c[2 * k + 1]) = (q.x, q.y);
                }
                c
            });
            for a in 0..8 {
                for b in a + 1..8 {
                    let mut count = [0u32; 4];
                    for p in &pts {
                        count[usize::from(p[a] >= 0.5) * 2 + usize::from(p[b] >= 0.5)] += 1;
                    }
                    // sum (c - 1024)^2 / 1024, in integers: 16.3 * 1024 ~ 16_700.
                    let chi = count.iter().map(|&c| (c as i64 - 1024).pow(2)).sum::<i64>();
                    assert!(chi < 16_700, "index {index} coordinates {a} {b}: {count:?}");
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
    }
}
