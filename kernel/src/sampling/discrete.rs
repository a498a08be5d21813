//! Discrete distributions drawn with the bits of one random number.

use crate::num::{clamp, positive_finite};

/// An entry drawn from a discrete distribution with 32 random bits (see
/// [`Sampler::next_2d_reusable`](crate::sampling::sampler::Sampler::next_2d_reusable)), and the bits rescaled
/// within the entry's share: given the entry, `reused` is uniform in [0, 1) and independent of
/// the choice, so it can stand in for a fresh random number (Mitsuba's `sample_reuse`; here
/// exact on the integer grid of the bits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscreteSample {
    /// The entry.
    pub index: usize,
    /// Its probability.
    pub probability: f32,
    /// The bits rescaled within the entry's share, in [0, 1).
    pub reused: f32,
}

/// The largest f32 below one.
const ONE_BELOW: f32 = 1.0 - 1.0 / 16_777_216.0;

/// `n` equally likely entries, with their probability 1 / n computed once
/// ([`UniformIndex::sample_reusing`], [`UniformIndex::pmf`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformIndex {
    n: usize,
    pmf: f32,
}

impl UniformIndex {
    /// `n` entries (none: nothing is drawn).
    #[inline]
    pub fn new(n: usize) -> Self {
        Self { n, pmf: if n == 0 { 0.0 } else { 1.0 / n as f32 } }
    }

    /// One entry from 32 random bits: the integer part of `bits x n / 2^32`, and its fractional
    /// part as [`DiscreteSample::reused`] (24 bits of it). `None` when there are no entries.
    #[inline]
    pub fn sample_reusing(&self, bits: u32) -> Option<DiscreteSample> {
        let n = self.n;
        if n == 0 {
            return None;
        }
        let scaled = u64::from(bits) * n as u64;
        let index = ((scaled >> 32) as usize).min(n - 1);
        // The top 24 bits of the fraction (built from the bits on the soft-float cores).
        let reused = crate::sampling::sampler::to_unit(scaled as u32);
        Some(DiscreteSample { index, probability: self.pmf, reused })
    }

    /// The probability of entry `i`: 1 / n for each of the `n` (to within 2^-32 of what
    /// [`UniformIndex::sample_reusing`] realises), 0 beyond.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        if i < self.n { self.pmf } else { 0.0 }
    }
}

/// How many equally likely values a random number from
/// [`Sampler::next_f32`](crate::sampling::sampler::Sampler::next_f32) takes: its 24 bits, 2^24.
pub const GRID: u32 = 1 << 24;

/// The smallest sum of weights [`GridDistribution::new`] scales onto the grid as it is: 2^-100
/// (below about 2^-104, 2^24 / sum would be beyond f32).
pub const TINY_TOTAL: f32 = f32::from_bits(0x0d80_0000);

/// 2^64, the factor by which [`GridDistribution::new`] scales weights whose sum is below
/// [`TINY_TOTAL`] (and 2^-64 for a sum beyond f32): exact, and enough, since the smallest
/// positive f32 times 2^64 is above [`TINY_TOTAL`] and the largest times 2^-64 below 2^64.
const TWO_64: f32 = 18_446_744_073_709_551_616.0;

/// The sum of the positive entries of `weights` (adding zero instead of the others changes no
/// bit of a positive sum, and a sum that is not positive is refused either way).
#[inline]
fn positive_sum(weights: &[f32]) -> f32 {
    let mut total = 0.0f32;
    for &w in weights {
        total += if w > 0.0 { w } else { 0.0 };
    }
    total
}

/// A discrete distribution on the grid of the random number it is sampled with: entry `i` owns
/// a run of the 2^24 equally likely values of `u`, so the probability [`GridDistribution::pmf`]
/// reports is exactly the one [`GridDistribution::sample`] realises. Every positive weight gets
/// at least one value: a share rounded to none would never be drawn while its pmf still lowered
/// the other technique's MIS weights (a bias).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GridDistribution<const N: usize> {
    /// Where each entry's run of grid values ends (cumulative); empty when no weight is positive.
    ends: heapless::Vec<u32, N>,
}

impl<const N: usize> GridDistribution<N> {
    /// The distribution proportional to `weights` (at most `N` are read); entries whose weight is
    /// not positive get no value. Empty (it samples nothing) when no weight is positive, or one
    /// is infinite. Weights whose sum is beyond f32, or so small that the scale onto the grid
    /// would be (below [`TINY_TOTAL`]), are first scaled by a power of two
    /// (`GridDistribution::rescaled`): the same distribution, every positive weight still
    /// positive.
    pub fn new(weights: &[f32]) -> Self {
        let weights = weights.get(..N).unwrap_or(weights);
        let total = positive_sum(weights);
        if total < TINY_TOTAL && total > 0.0 {
            return Self::rescaled(weights, TWO_64);
        }
        if total == f32::INFINITY {
            return Self::rescaled(weights, 1.0 / TWO_64);
        }
        Self::with_total(weights, total)
    }

    /// [`GridDistribution::new`] of `weights` times `factor`, a power of two, each positive
    /// weight at least [`f32::MIN_POSITIVE`] (weights beyond f32 stay infinite): for sums out of
    /// the range the grid's scale can take. Out of line: no ordinary scene comes here.
    #[cold]
    #[inline(never)]
    fn rescaled(weights: &[f32], factor: f32) -> Self {
        let mut scaled = [0.0f32; N];
        for (s, &w) in scaled.iter_mut().zip(weights) {
            *s = if w > 0.0 { (w * factor).max(f32::MIN_POSITIVE) } else { 0.0 };
        }
        let scaled = scaled.get(..weights.len()).unwrap_or(&scaled);
        Self::with_total(scaled, positive_sum(scaled))
    }

    /// The distribution proportional to `weights` (at most `N`), whose positive ones sum to
    /// `total`; empty unless `total` is positive and finite.
    #[inline]
    fn with_total(weights: &[f32], total: f32) -> Self {
        let mut ends = heapless::Vec::new();
        if !positive_finite(total) {
            return Self { ends };
        }
        // Each share rounded to the grid, at least one value if positive; the rounding difference
        // (at most N values either way) goes to the largest entry, which has at least GRID / N.
        let scale = GRID as f32 / total;
        let mut end = 0u32;
        let mut largest = (0, 0);
        for (i, &w) in weights.iter().enumerate() {
            // Clamped before the conversion (the same value: the share is at least 0.5), so it
            // fits an i32, whose conversion is the cheaper one on x86.
            let c = if w > 0.0 { clamp(w * scale + 0.5, 1.0, GRID as f32) as i32 as u32 } else { 0 };
            end += c;
            if c > largest.1 {
                largest = (i, c);
            }
            // `weights` has at most N entries.
            let _ = ends.push(end);
        }
        // The largest entry's run, and every end after it, moves by the rounding difference.
        let shift = (largest.1 + GRID).saturating_sub(end).wrapping_sub(largest.1);
        for e in ends.iter_mut().skip(largest.0) {
            *e = e.wrapping_add(shift);
        }
        Self { ends }
    }

    /// True when nothing can be sampled (no positive weight).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.ends.last().is_none_or(|&end| end == 0)
    }

    /// The entry owning the grid value of `u` in [0, 1), and its probability.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        // u = k / 2^24 exactly for the sampler's numbers; others are clamped into the grid.
        let k = ((u * GRID as f32) as u32).min(GRID - 1);
        self.sample_reusing(k << 8).map(|s| (s.index, s.probability))
    }

    /// The entry owning the grid value of the top 24 of the 32 random `bits` (the value
    /// [`GridDistribution::sample`] takes), its probability, and the bits rescaled within its
    /// run: (value - start + low 8 bits / 256) / (run length).
    #[inline]
    pub fn sample_reusing(&self, bits: u32) -> Option<DiscreteSample> {
        let k = bits >> 8;
        let index = self.ends.iter().position(|&end| k < end)?;
        let (start, end) = self.run(index);
        let count = end - start;
        // Below count x 256 <= 2^32: (k - start) < count <= 2^24.
        let fine = ((k - start) << 8) | (bits & 0xff);
        let reused = (fine as f32 / (count as f32 * 256.0)).min(ONE_BELOW);
        Some(DiscreteSample { index, probability: count as f32 * (1.0 / GRID as f32), reused })
    }

    /// The run of grid values entry `i` owns (empty past the end).
    #[inline]
    fn run(&self, i: usize) -> (u32, u32) {
        let start = match i.checked_sub(1) {
            Some(j) => self.ends.get(j).copied().unwrap_or(0),
            None => 0,
        };
        (start, self.ends.get(i).copied().unwrap_or(start))
    }

    /// The probability of entry `i` under [`GridDistribution::sample`]: its share of the grid.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        let (start, end) = self.run(i);
        (end - start) as f32 * (1.0 / GRID as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_indices_split_the_bits_into_index_and_remainder() {
        for n in [1usize, 3, 5, 32] {
            let mut count = [0u32; 32];
            // Sums of the reused numbers in units of 2^-24 (exact: they lie on that grid).
            let mut sum = [0u64; 32];
            for j in 0..(1u32 << 16) {
                let uniform = UniformIndex::new(n);
                let s = uniform.sample_reusing(j << 16 | 0x8000).unwrap();
                assert!(s.index < n && (0.0..1.0).contains(&s.reused) && s.probability == 1.0 / n as f32);
                assert!(uniform.pmf(s.index) == s.probability && uniform.pmf(n) == 0.0);
                count[s.index] += 1;
                sum[s.index] += (s.reused * 16_777_216.0) as u64;
            }
            for i in 0..n {
                // Share 1/n within 1e-3, and mean reused number 1/2 within 1e-3.
                let (c, n64) = (u64::from(count[i]), n as u64);
                assert!((c * n64).abs_diff(65_536) * 1000 < 65_536, "n {n}, entry {i}: {c}");
                assert!((2 * sum[i]).abs_diff(c << 24) * 500 < c << 24, "n {n}, entry {i}");
            }
        }
        assert_eq!(UniformIndex::new(0).sample_reusing(7), None);
    }

    #[test]
    fn grid_distributions_realise_their_pmf_exactly() {
        // Shares from 1 down to 1e-14: each positive weight gets at least one grid value.
        let w = [0.0, 1e5, 1e-9, 3.0, 0.0, 1e-3];
        let d = GridDistribution::<6>::new(&w);
        let mut counts = [0u32; 6];
        for k in 0..GRID {
            let (i, p) = d.sample(k as f32 / GRID as f32).unwrap();
            assert_eq!(p, d.pmf(i));
            counts[i] += 1;
        }
        for (i, c) in counts.iter().enumerate() {
            assert_eq!(*c as f32 / GRID as f32, d.pmf(i), "entry {i}");
            assert_eq!(*c > 0, w[i] > 0.0, "entry {i}");
        }
        assert_eq!(counts.iter().sum::<u32>(), GRID);
        // Reuse: within each entry's run the rescaled bits are evenly spread over [0, 1).
        // Sums in units of 2^-24 (exact: the rescaled numbers lie on that grid).
        let mut sums = [0u64; 6];
        for k in 0..GRID {
            let s = d.sample_reusing(k << 8 | 0x80).unwrap();
            assert!((0.0..1.0).contains(&s.reused), "{s:?}");
            assert_eq!((s.index, s.probability), d.sample(k as f32 / GRID as f32).unwrap());
            sums[s.index] += (s.reused * 16_777_216.0) as u64;
        }
        for (i, sum) in sums.iter().enumerate() {
            // Mean 1/2 within 1e-6.
            let n = u64::from(counts[i]);
            assert!(n == 0 || (2 * sum).abs_diff(n << 24) * 500_000 < n << 24, "entry {i}: sum {sum} of {n}");
        }
        assert!(GridDistribution::<2>::new(&[0.0, -1.0]).is_empty());
        assert!(GridDistribution::<2>::new(&[f32::INFINITY, 1.0]).is_empty());
        assert_eq!(GridDistribution::<2>::new(&[0.0]).sample(0.5), None);
        assert_eq!(d.pmf(9), 0.0);
    }

    /// Weights whose sum is below 2^-104 (2^24 / sum beyond f32) or beyond f32 give the
    /// distribution of the same weights scaled into range, every positive weight at least one
    /// grid value, the probabilities summing to one. (Before: the tiny sums' scale was infinite,
    /// every share took the whole grid and the probabilities summed to 3; the sums beyond f32
    /// gave an empty distribution.)
    #[test]
    fn sums_out_of_range_keep_the_distribution() {
        let shape = [3.0f32, 1.0, 0.0, 2.0];
        let want = GridDistribution::<4>::new(&shape);
        for scale in [1e-40f32, 1e-36, 1e38] {
            let w = shape.map(|x| x * scale);
            let d = GridDistribution::<4>::new(&w);
            let sum: f32 = (0..4).map(|i| d.pmf(i)).sum();
            assert_eq!(sum, 1.0, "{w:?}");
            for i in 0..4 {
                assert!((d.pmf(i) - want.pmf(i)).abs() <= 1.0 / GRID as f32, "{w:?}: entry {i}");
            }
        }
        // A faint weight beside two at f32's largest keeps a value; an infinite one empties it.
        let d = GridDistribution::<3>::new(&[f32::MAX, f32::MAX, 1e-30]);
        assert!(d.pmf(2) > 0.0 && (d.pmf(0) - 0.5).abs() < 1e-6, "{d:?}");
        assert_eq!((0..3).map(|i| d.pmf(i)).sum::<f32>(), 1.0);
        assert!(GridDistribution::<2>::new(&[f32::INFINITY, 1.0]).is_empty());
        // The smallest positive weight alone, and beside larger tiny ones.
        assert_eq!(GridDistribution::<1>::new(&[f32::from_bits(1)]).pmf(0), 1.0);
        let d = GridDistribution::<2>::new(&[f32::from_bits(1), 1e-33]);
        assert!(d.pmf(0) > 0.0 && d.pmf(1) > 0.99, "{d:?}");
        assert_eq!(TINY_TOTAL, 2.0f32.powi(-100));
        assert_eq!(TWO_64, 2.0f32.powi(64));
    }
}
