//! Every light equally likely.

use crate::light::sample::{LightChoice, ShadingPoint};
use crate::light::select::{LightSelection, Residual, Select, choice};
use crate::num::Frame;
use crate::sampling::UniformIndex;
use crate::scene::{LightId, Outgoing, Scene};

/// Every light equally likely: P(light) = 1 / (number of lights).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uniform {
    lights: UniformIndex,
}

impl Uniform {
    /// Uniform selection among `n` lights.
    #[inline]
    pub fn among(n: usize) -> Self {
        Uniform { lights: UniformIndex::new(n) }
    }
}

impl<const L: usize> Select<L> for Uniform {
    const KIND: LightSelection = LightSelection::Uniform;
    const LOCAL: bool = false;
    type At = ();

    fn new<const S: usize, const M: usize>(scene: &Scene<S, L, M>) -> Self {
        Self::among(scene.lights().len())
    }

    #[inline(always)]
    fn at(&self, _: &ShadingPoint, _: &Frame, _: &Outgoing, _: Residual) {}

    #[inline]
    fn select(&self, _: &(), bits: u32) -> Option<(LightChoice, f32)> {
        self.lights.sample_reusing(bits).map(choice)
    }

    #[inline]
    fn pmf(&self, _: &(), light: LightId) -> f32 {
        self.lights.pmf(light.index())
    }
}
