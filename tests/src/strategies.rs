//! Light strategies named at run time, for suites that sweep them through the kernel's typed
//! light sampler ([`picomis::LightSampler`], generic over its strategies): [`LightChoices`] names
//! them by their settings' enums and [`LightChoices::visit`] calls a [`VisitLights`] with the
//! matching types, [`picomis::Lights`]`<Sel, Sp, Q, Lb>`.

use picomis::light::select::{ByContribution, ByPower, Every, Uniform};
use picomis::light::{LightStrategies, Lights, Select, lobe, quad, sphere};
use picomis::{LightSelection, LobeMixing, QuadSampling, RenderSettings, SphereSampling};

/// What [`LightChoices::visit`] calls with the light strategies as a type, for scenes of at most
/// `L` lights.
pub trait VisitLights<const L: usize> {
    /// What the visit returns.
    type Output;
    /// Called once, with the strategies as the type `Lt`.
    fn visit<Lt: LightStrategies<L>>(self) -> Self::Output;
}

/// The light strategies by name: light selection, sphere and quad sampling, lobe mixing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightChoices {
    /// How a light is chosen.
    pub selection: LightSelection,
    /// How sphere lights are sampled.
    pub spheres: SphereSampling,
    /// How quad lights are sampled.
    pub quads: QuadSampling,
    /// Whether a glossy receiver's lobe joins the light samples.
    pub lobe: LobeMixing,
}

impl LightChoices {
    /// `selection` and `spheres`, with quads by area and no lobe mixing.
    pub fn new(selection: LightSelection, spheres: SphereSampling) -> Self {
        LightChoices { selection, spheres, quads: QuadSampling::Area, lobe: LobeMixing::Off }
    }

    /// The light strategies of `settings`.
    pub fn of(settings: &RenderSettings) -> Self {
        LightChoices {
            selection: settings.light_selection(),
            spheres: settings.sphere_sampling(),
            quads: settings.quad_sampling(),
            lobe: settings.lobe_mixing(),
        }
    }

    /// The same choices with quads sampled by `quads`.
    pub fn with_quad_sampling(self, quads: QuadSampling) -> Self {
        LightChoices { quads, ..self }
    }

    /// The same choices with lobe mixing `lobe`.
    pub fn with_lobe_mixing(self, lobe: LobeMixing) -> Self {
        LightChoices { lobe, ..self }
    }

    /// Calls `visitor` with the strategy types these choices name.
    pub fn visit<const L: usize, V: VisitLights<L>>(self, visitor: V) -> V::Output {
        match self.selection {
            LightSelection::Uniform => self.spheres::<L, Uniform, V>(visitor),
            LightSelection::Power => self.spheres::<L, ByPower<L>, V>(visitor),
            LightSelection::Contribution => self.spheres::<L, ByContribution<L>, V>(visitor),
            LightSelection::Every => self.spheres::<L, Every, V>(visitor),
        }
    }

    fn spheres<const L: usize, Sel: Select<L>, V: VisitLights<L>>(self, v: V) -> V::Output {
        match self.spheres {
            SphereSampling::Area => self.quads::<L, Sel, sphere::ByArea, V>(v),
            SphereSampling::Cone => self.quads::<L, Sel, sphere::InCone, V>(v),
        }
    }

    fn quads<const L: usize, Sel: Select<L>, Sp: sphere::SphereSampler, V: VisitLights<L>>(
        self,
        v: V,
    ) -> V::Output {
        match self.quads {
            QuadSampling::Area => self.lobes::<L, Sel, Sp, quad::ByArea, V>(v),
            QuadSampling::SolidAngle => self.lobes::<L, Sel, Sp, quad::SolidAngle, V>(v),
            QuadSampling::SolidAngleCosine => self.lobes::<L, Sel, Sp, quad::SolidAngleCosine, V>(v),
            QuadSampling::Auto => self.lobes::<L, Sel, Sp, quad::Adaptive, V>(v),
            QuadSampling::BySize => self.lobes::<L, Sel, Sp, quad::BySize, V>(v),
        }
    }

    fn lobes<
        const L: usize,
        Sel: Select<L>,
        Sp: sphere::SphereSampler,
        Q: quad::QuadSampler,
        V: VisitLights<L>,
    >(
        self,
        v: V,
    ) -> V::Output {
        match self.lobe {
            LobeMixing::Off => v.visit::<Lights<Sel, Sp, Q, lobe::Off>>(),
            LobeMixing::On => v.visit::<Lights<Sel, Sp, Q, lobe::On>>(),
        }
    }
}
