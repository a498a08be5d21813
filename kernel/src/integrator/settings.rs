//! Render settings: which techniques, how many samples, how they are combined, and the seed.

use crate::error::{Field, SceneError};
use crate::integrator::mis::Method;
use crate::integrator::model::MisModel;
use crate::light::lobe::LobeMixing;
use crate::light::{LightSelection, QuadSampling, SphereSampling};
use crate::sampling::sampler::SamplerKind;

/// Validated settings for one render. A seed fully determines the image.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderSettings {
    method: Method,
    light_samples: u16,
    bsdf_samples: u16,
    spp: u32,
    seed: u32,
    spheres: SphereSampling,
    selection: LightSelection,
    model: MisModel,
    quads: QuadSampling,
    control_variate: ControlVariate,
    sampler: SamplerKind,
    lobe: LobeMixing,
}

/// Whether the unoccluded light reaching a Lambertian receiver is computed in closed form, with
/// Monte Carlo left for the shadows only (see [`crate::integrator::closed_form`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ControlVariate {
    /// Every light is estimated by sampling alone.
    Off,
    /// Integral f V = integral f (closed form) + integral f (V - 1) (sampled with MIS).
    On,
}

impl ControlVariate {
    /// The default (a constant, for the settings' `const` constructors).
    pub const DEFAULT: Self = ControlVariate::Off;
}

impl Default for ControlVariate {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl RenderSettings {
    /// Settings with `n_light` light and `n_bsdf` BSDF samples per camera sample, `spp` camera
    /// samples per pixel. Rejects a method left with no samples, a power heuristic whose beta is
    /// not finite and positive, a cutoff alpha outside [0, 1], and `spp` = 0.
    pub const fn new(
        method: Method,
        light_samples: u16,
        bsdf_samples: u16,
        spp: u32,
        seed: u32,
    ) -> Result<Self, SceneError> {
        let method = match method.validated() {
            Ok(m) => m,
            Err(e) => return Err(e),
        };
        if spp == 0 {
            return Err(SceneError::NonPositive(Field::SamplesPerPixel));
        }
        if let (0, 0) = method.sample_counts(light_samples, bsdf_samples) {
            return Err(SceneError::NoTechnique);
        }
        Ok(Self {
            method,
            light_samples,
            bsdf_samples,
            spp,
            seed,
            spheres: SphereSampling::DEFAULT,
            selection: LightSelection::DEFAULT,
            model: MisModel::DEFAULT,
            quads: QuadSampling::DEFAULT,
            control_variate: ControlVariate::DEFAULT,
            sampler: SamplerKind::DEFAULT,
            lobe: LobeMixing::DEFAULT,
        })
    }

    /// The same settings with another MIS model. The one-sample model's `c_light` must be in
    /// [0, 1] (0 and 1 are BSDF or light sampling alone).
    pub const fn with_mis_model(mut self, model: MisModel) -> Result<Self, SceneError> {
        self.model = match model {
            MisModel::Multi => model,
            MisModel::One { c_light } => match MisModel::one(c_light) {
                Ok(m) => m,
                Err(e) => return Err(e),
            },
        };
        Ok(self)
    }

    /// The same settings with another quad-light sampling strategy.
    pub const fn with_quad_sampling(mut self, quads: QuadSampling) -> Self {
        self.quads = quads;
        self
    }

    /// The same settings with the analytic control variate on or off.
    pub const fn with_control_variate(mut self, control_variate: ControlVariate) -> Self {
        self.control_variate = control_variate;
        self
    }

    /// The same settings with another sphere-light sampling strategy.
    pub const fn with_sphere_sampling(mut self, spheres: SphereSampling) -> Self {
        self.spheres = spheres;
        self
    }

    /// The same settings with another light-selection strategy.
    pub const fn with_light_selection(mut self, selection: LightSelection) -> Self {
        self.selection = selection;
        self
    }

    /// The same settings with another sample stream.
    pub const fn with_sampler(mut self, sampler: SamplerKind) -> Self {
        self.sampler = sampler;
        self
    }

    /// The same settings with light samples that also follow a glossy receiver's lobe, or not;
    /// [`LobeMixing::On`] is an error in a build without the kernel's `lobe` feature.
    pub const fn with_lobe_mixing(mut self, lobe: LobeMixing) -> Result<Self, SceneError> {
        self.lobe = match lobe.validated() {
            Ok(l) => l,
            Err(e) => return Err(e),
        };
        Ok(self)
    }

    /// The same settings with another seed.
    pub const fn with_seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// The same settings with another number of samples per pixel (at least 1, as in [`Self::new`]).
    pub const fn with_spp(mut self, spp: u32) -> Result<Self, SceneError> {
        if spp == 0 {
            return Err(SceneError::NonPositive(Field::SamplesPerPixel));
        }
        self.spp = spp;
        Ok(self)
    }

    /// The combination method.
    pub fn method(&self) -> Method {
        self.method
    }
    /// Light and BSDF samples actually drawn per camera sample (in the one-sample model: at most
    /// one of either, whatever the counts, as `c_light` allows).
    pub fn technique_samples(&self) -> (u16, u16) {
        match self.model {
            MisModel::Multi => self.method.sample_counts(self.light_samples, self.bsdf_samples),
            MisModel::One { .. } => {
                let c = self.c_light();
                (u16::from(c > 0.0), u16::from(c < 1.0))
            }
        }
    }
    /// Camera samples per pixel.
    pub fn spp(&self) -> u32 {
        self.spp
    }
    /// Seed.
    pub fn seed(&self) -> u32 {
        self.seed
    }
    /// Sphere-light sampling strategy.
    pub fn sphere_sampling(&self) -> SphereSampling {
        self.spheres
    }
    /// Light-selection strategy.
    pub fn light_selection(&self) -> LightSelection {
        self.selection
    }
    /// The MIS model.
    pub fn mis_model(&self) -> MisModel {
        self.model
    }
    /// Probability of the light technique in the one-sample model: `c_light` for a heuristic,
    /// 1 for light sampling alone and 0 for BSDF sampling alone.
    pub fn c_light(&self) -> f32 {
        match (self.method, self.model) {
            (Method::LightOnly, _) => 1.0,
            (Method::BsdfOnly, _) => 0.0,
            (Method::Mis(_), MisModel::One { c_light }) => c_light,
            (Method::Mis(_), MisModel::Multi) => crate::integrator::model::DEFAULT_C_LIGHT,
        }
    }
    /// Quad-light sampling strategy.
    pub fn quad_sampling(&self) -> QuadSampling {
        self.quads
    }
    /// The analytic control variate.
    pub fn control_variate(&self) -> ControlVariate {
        self.control_variate
    }
    /// Sample stream.
    pub fn sampler(&self) -> SamplerKind {
        self.sampler
    }
    /// Whether light samples also follow a glossy receiver's lobe.
    pub fn lobe_mixing(&self) -> LobeMixing {
        self.lobe
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::mis::Heuristic;

    #[test]
    fn rejects_invalid_settings() {
        let p = |beta| Method::Mis(Heuristic::Power { beta });
        assert_eq!(RenderSettings::new(p(f32::NAN), 1, 1, 1, 0), Err(SceneError::OutOfRange(Field::Beta)));
        assert_eq!(RenderSettings::new(p(0.0), 1, 1, 1, 0), Err(SceneError::OutOfRange(Field::Beta)));
        let c = Method::Mis(Heuristic::Cutoff { alpha: 1.5 });
        assert_eq!(RenderSettings::new(c, 1, 1, 1, 0), Err(SceneError::OutOfRange(Field::CutoffAlpha)));
        assert_eq!(RenderSettings::new(Method::LightOnly, 0, 4, 1, 0), Err(SceneError::NoTechnique));
        assert_eq!(
            RenderSettings::new(Method::BsdfOnly, 1, 1, 0, 0),
            Err(SceneError::NonPositive(Field::SamplesPerPixel))
        );
        let ok = RenderSettings::new(p(2.0), 1, 0, 1, 0).unwrap();
        assert_eq!(ok.with_spp(0), Err(SceneError::NonPositive(Field::SamplesPerPixel)));
        assert_eq!(ok.with_spp(8).map(|s| s.spp()), Ok(8));
        let bad = MisModel::One { c_light: 1.5 };
        assert_eq!(ok.with_mis_model(bad), Err(SceneError::OutOfRange(Field::CLight)));
        let one = ok.with_mis_model(MisModel::One { c_light: 0.25 }).unwrap();
        assert_eq!(one.c_light(), 0.25);
        let light = RenderSettings::new(Method::LightOnly, 1, 1, 1, 0).unwrap();
        assert_eq!(light.with_mis_model(MisModel::One { c_light: 0.25 }).unwrap().c_light(), 1.0);
    }
}
