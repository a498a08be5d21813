//! What the estimator returns: the radiance of a camera sample or a pixel, split into what the
//! surface emits and what each technique found, with the techniques' MIS weights and counts (the
//! lecture's weight and contribution images come from these).

use crate::num::Rgb;

/// The largest contribution one sample may add (per channel, already divided by the technique's
/// sample count); a larger one is dropped like a NaN or an infinity. The bound keeps every
/// running sum finite: at most 2^16 samples per technique per camera sample and 2^32 camera
/// samples per pixel give at most 2^48 x 1e22 ~ 2.8e36 per part, and the three parts of
/// [`Estimate::radiance`] (emitted light is at most [`MAX_EMISSION`](crate::scene::MAX_EMISSION))
/// stay far below `f32::MAX` ~ 3.4e38. Valid scenes reach it only with emission near the
/// maximum seen through a pdf near zero.
pub const MAX_CONTRIBUTION: f32 = 1e22;

/// One technique's share of an estimate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TechniqueEstimate {
    /// Weighted contribution, already divided by the technique's sample count.
    pub contribution: Rgb,
    /// Sum of the MIS weights of the samples that found light.
    pub weight_sum: f32,
    /// Number of samples that found light (non-zero integrand).
    pub found: u32,
}

impl TechniqueEstimate {
    #[inline]
    pub(crate) fn add(&mut self, contribution: Rgb, weight: f32) {
        // Never let a NaN or infinity leave the estimator, nor a value that could overflow a sum.
        let bounded = |v: f32| v.abs() <= MAX_CONTRIBUTION; // false for NaN
        if bounded(contribution.x) && bounded(contribution.y) && bounded(contribution.z) {
            self.contribution += contribution;
            self.weight_sum += weight;
            self.found = self.found.saturating_add(1);
        }
    }

    /// Mean weight of the samples that found light (0 when none did).
    pub fn mean_weight(&self) -> f32 {
        if self.found > 0 { self.weight_sum / self.found as f32 } else { 0.0 }
    }

    fn merge(&mut self, other: &Self) {
        self.contribution += other.contribution;
        self.weight_sum += other.weight_sum;
        self.found = self.found.saturating_add(other.found);
    }
}

/// Radiance estimate of a camera sample or a pixel, split by where it came from.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimate {
    /// Radiance emitted by the surface the camera sees.
    pub emitted: Rgb,
    /// Direct light found by light sampling.
    pub light: TechniqueEstimate,
    /// Direct light found by BSDF sampling.
    pub bsdf: TechniqueEstimate,
}

impl Estimate {
    /// Total radiance.
    #[inline]
    pub fn radiance(&self) -> Rgb {
        self.emitted + self.light.contribution + self.bsdf.contribution
    }

    /// Adds another estimate (for averaging camera samples).
    pub fn merge(&mut self, other: &Self) {
        self.emitted += other.emitted;
        self.light.merge(&other.light);
        self.bsdf.merge(&other.bsdf);
    }

    /// Scales the radiance parts by `s` (weights and counts are left as sums).
    pub fn scale(&mut self, s: f32) {
        self.emitted *= s;
        self.light.contribution *= s;
        self.bsdf.contribution *= s;
    }
}
