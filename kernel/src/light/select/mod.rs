//! How a light is chosen for a light sample when a scene has several: one strategy per file,
//! each a type that implements [`Select`], chosen once per render (pbrt-v4's `LightSampler`).
//! A strategy keeps only the tables it needs, built from the scene once
//! ([`Select::new`]); what depends on the shading point is computed there once
//! ([`Select::at`]) and read by both [`Select::select`] and [`Select::pmf`], so the light drawn
//! and the probability the MIS weights use cannot disagree.
//!
//! | file | strategy |
//! |---|---|
//! | `uniform.rs` | [`Uniform`]: every light equally likely |
//! | `power.rs` | [`ByPower`]: in proportion to emitted power |
//! | `contribution.rs` | [`ByContribution`]: in proportion to the estimated contribution at the shading point |
//! | `every.rs` | [`Every`]: no choice, one sample of every light |
//! | `importance.rs` | the cones and importances that selection by contribution estimates with |

mod contribution;
mod every;
pub mod importance;
mod power;
mod uniform;

pub use contribution::{ByContribution, CONTRIBUTION_FLOOR};
pub use every::Every;
pub use power::ByPower;
pub use uniform::Uniform;

use crate::light::sample::{LightChoice, ShadingPoint};
use crate::num::Frame;
use crate::scene::{LightId, Outgoing, Scene};

crate::choices! {
    /// How a light is chosen when a scene has several.
    pub enum LightSelection: "light selection" {
        /// Every light equally likely ([`Uniform`]).
        Uniform = "uniform", "every light equally likely";
        /// Proportional to emitted power ([`ByPower`]).
        Power = "power", "proportional to emitted power";
        /// Proportional to each light's estimated contribution at the shading point
        /// ([`ByContribution`]).
        Contribution = "contribution", "proportional to the estimated contribution at the shading point";
        /// No choice: each light sample is one sample of every light ([`Every`]).
        Every = "every", "no choice: each light sample is one sample of every light (a shadow ray each)";
    }
}

/// A light-selection strategy for scenes of at most `L` lights.
pub trait Select<const L: usize>: Sized + Sync + 'static {
    /// Its name among the settings.
    const KIND: LightSelection;
    /// Whether [`Select::at`] may depend on the shading point (then it is worth a copy of the
    /// point on the microcontrollers, see the estimator).
    const LOCAL: bool;
    /// Whether a light sample is one sample of every light, each with probability
    /// [`Select::pmf`] (one), rather than of the one light [`Select::select`] chooses (which
    /// then chooses none).
    const EVERY: bool = false;
    /// What the choice reads at one shading point.
    type At: Clone + core::fmt::Debug;

    /// The strategy for `scene`'s lights (its tables, built once).
    fn new<const S: usize, const M: usize>(scene: &Scene<S, L, M>) -> Self;

    /// The selection at `point`, whose frame (from its normal) is `frame` and whose BSDF is
    /// `seen` from its `wo` (local, in `frame`), with what the control variate leaves to
    /// sampling there (`residual`: a strategy that depends on the point follows it; the others
    /// may give such lights samples that add nothing or little).
    fn at(&self, point: &ShadingPoint, frame: &Frame, seen: &Outgoing, residual: Residual) -> Self::At;

    /// Chooses a light with the top 24 of the 32 random `bits` (on the 2^24 grid of
    /// [`Sampler::next_f32`](crate::sampling::Sampler::next_f32)), and returns with it the bits
    /// rescaled within the chosen light's share of the numbers
    /// ([`DiscreteSample::reused`](crate::sampling::DiscreteSample::reused)): uniform in [0, 1)
    /// and independent of the choice, so that selection and the point on the light stay one
    /// stratified 2-D sample. `None` when the scene has no light (or none can contribute here).
    fn select(&self, at: &Self::At, bits: u32) -> Option<(LightChoice, f32)>;

    /// The probability with which [`Select::select`] chooses `light` at `at`.
    fn pmf(&self, at: &Self::At, light: LightId) -> f32;
}

/// What the control variate leaves to sampling at a shading point (see [`Select::at`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Residual {
    /// Bit k: light k's part is exact here (in closed form, and nothing can block it): nothing
    /// is left to sample.
    pub exact: u64,
}

/// The light drawn from a discrete distribution's sample, with its rescaled bits.
#[inline]
pub(crate) fn choice(drawn: crate::sampling::DiscreteSample) -> (LightChoice, f32) {
    (LightChoice { light: LightId::new(drawn.index as u16), probability: drawn.probability }, drawn.reused)
}
