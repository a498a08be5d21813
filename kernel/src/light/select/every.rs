//! Every light at once: each light sample is one sample of every light.

use crate::light::sample::{LightChoice, ShadingPoint};
use crate::light::select::{LightSelection, Residual, Select};
use crate::num::Frame;
use crate::scene::{LightId, Outgoing, Scene};

/// No choice: each light sample draws one point on every light ([`Select::EVERY`]), each with
/// probability one, so the light technique has no selection noise at all (the estimator sums
/// the lights' estimates). It costs a shadow ray per light: worth it where the scene has a few
/// lights whose shares of a pixel vary (point lights, whose samples carry no other noise), not
/// where one light dominates each point. Lights whose part is exact at a shading point (the
/// control variate's, [`Residual`]) are skipped: probability zero there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Every {
    lights: usize,
}

impl<const L: usize> Select<L> for Every {
    const KIND: LightSelection = LightSelection::Every;
    const LOCAL: bool = false;
    const EVERY: bool = true;
    type At = Residual;

    fn new<const S: usize, const M: usize>(scene: &Scene<S, L, M>) -> Self {
        Every { lights: scene.lights().len() }
    }

    #[inline(always)]
    fn at(&self, _: &ShadingPoint, _: &Frame, _: &Outgoing, residual: Residual) -> Residual {
        residual
    }

    /// No light is chosen: the estimator samples each one ([`Select::EVERY`]).
    #[inline]
    fn select(&self, _: &Residual, _: u32) -> Option<(LightChoice, f32)> {
        None
    }

    /// One for every light of the scene but those exact at this point; zero for those and
    /// beyond the lights.
    #[inline]
    fn pmf(&self, at: &Residual, light: LightId) -> f32 {
        let i = light.index();
        let exact = i < 64 && at.exact & (1 << i) != 0;
        if i < self.lights && !exact { 1.0 } else { 0.0 }
    }
}
