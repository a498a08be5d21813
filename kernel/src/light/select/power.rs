//! Lights in proportion to their emitted power.

use crate::light::sample::{LightChoice, ShadingPoint};
use crate::light::select::{LightSelection, Residual, Select, Uniform, choice};
use crate::num::Frame;
use crate::sampling::GridDistribution;
use crate::scene::{LightId, Outgoing, Scene};

/// Proportional to emitted power (the mean of its channels, [`Light::power`](crate::scene::Light::power)),
/// on the grid of the random number (see [`GridDistribution`]): every light that emits is
/// chosen with exactly the probability the weights are given. Uniform when no light has power.
#[derive(Clone, Debug, PartialEq)]
pub struct ByPower<const L: usize> {
    powers: GridDistribution<L>,
    /// Where no light has power.
    uniform: Uniform,
}

impl<const L: usize> Select<L> for ByPower<L> {
    const KIND: LightSelection = LightSelection::Power;
    const LOCAL: bool = false;
    type At = ();

    fn new<const S: usize, const M: usize>(scene: &Scene<S, L, M>) -> Self {
        let mut powers = heapless::Vec::<f32, L>::new();
        for light in scene.lights() {
            // At most L lights: every push fits.
            let _ = powers.push(light.power(scene.light_shape(light)));
        }
        ByPower { powers: GridDistribution::new(&powers), uniform: Uniform::among(scene.lights().len()) }
    }

    #[inline(always)]
    fn at(&self, _: &ShadingPoint, _: &Frame, _: &Outgoing, _: Residual) {}

    #[inline]
    fn select(&self, at: &(), bits: u32) -> Option<(LightChoice, f32)> {
        if self.powers.is_empty() {
            return <Uniform as Select<L>>::select(&self.uniform, at, bits);
        }
        self.powers.sample_reusing(bits).map(choice)
    }

    #[inline]
    fn pmf(&self, at: &(), light: LightId) -> f32 {
        if self.powers.is_empty() {
            return <Uniform as Select<L>>::pmf(&self.uniform, at, light);
        }
        // (Zero beyond the lights.)
        self.powers.pmf(light.index())
    }
}
