//! Render settings: which techniques, how many samples, how they are combined, by which
//! strategies, and the seed; and the presets they start from ([`Preset`]): the settings that
//! measure best, which every render gets unless told otherwise, and the lecture's.

use crate::error::{Field, SceneError};
use crate::integrator::control_variate::ControlVariate;
use crate::integrator::mis::{Heuristic, Method};
use crate::integrator::model::MisModel;
use crate::light::{LightSelection, LobeMixing, QuadSampling, SphereSampling};
use crate::sampling::SamplerKind;

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

crate::choices! {
    /// Where a render's settings start from, before a scene file's integrator block and the
    /// command line's flags change any of them.
    pub enum Preset: "preset" {
        /// The settings that measure best: what every render gets unless told otherwise (a sample
        /// of every light, lobe mixing, quads and the control variate by their rules).
        Best = "best", "the settings that measure best (the default): every light sampled, lobe mixing, quads and the control variate by their rules";
        /// The lecture's estimator: every light equally likely, quad lights by area, light
        /// samples from the light alone, no control variate.
        Lecture = "lecture", "the lecture's estimator: lights equally likely, quads by area, no lobe mixing, no control variate";
    }
}

impl Preset {
    /// The preset's settings: the power heuristic with one light and one BSDF sample per camera
    /// sample, 1 spp, seed 0, and the preset's strategies.
    pub const fn settings(self) -> RenderSettings {
        let lecture = RenderSettings {
            method: Method::Mis(Heuristic::Power { beta: Heuristic::DEFAULT_BETA }),
            light_samples: 1,
            bsdf_samples: 1,
            spp: 1,
            seed: 0,
            spheres: SphereSampling::Cone,
            selection: LightSelection::Uniform,
            model: MisModel::Multi,
            quads: QuadSampling::Area,
            control_variate: ControlVariate::Off,
            sampler: SamplerKind::Sobol,
            lobe: LobeMixing::Off,
        };
        match self {
            Preset::Lecture => lecture,
            // Measured on every built-in scene and on the test scenes of `tests/scenes/`
            // (`host-sim/examples/defaults.rs`, docs/defaults.md): each light sample one sample
            // of every light (no selection noise: docs/techniques/every-light.md), light
            // samples also from near-mirror lobes, quads by area except where a Lambertian
            // receiver's normal meets a large one (solid angle) or a sharp GGX receiver sees one
            // (solid angle, warped by the cosine where the warp fits), and the control variate by
            // its rule, by size where a scene has one light. Each applies only where it can help
            // (several lights; a GGX lobe narrower than a light; a quad light; a Lambertian
            // receiver of area lights) and leaves the image unchanged elsewhere.
            Preset::Best => RenderSettings {
                selection: LightSelection::Every,
                lobe: LobeMixing::On,
                quads: QuadSampling::BySize,
                control_variate: ControlVariate::BySize,
                ..lecture
            },
        }
    }
}

/// Where the estimator reads its settings: those it was built with (a host chooses them at run
/// time), or a constant ([`ConstSettings`]: a firmware's scene file fixes them, and the compiler
/// folds every one into the code: the loops over the sample counts, the sample stream, the
/// combination method, so that for the power heuristic with beta = 2 no `powf` is linked).
pub trait SettingsSource: 'static {
    /// The settings of an estimator built with `given`.
    fn settings(given: &RenderSettings) -> RenderSettings;
}

/// The settings the estimator was built with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Given;

impl SettingsSource for Given {
    #[inline(always)]
    fn settings(given: &RenderSettings) -> RenderSettings {
        *given
    }
}

/// Settings fixed at compile time (an estimator is built with the same ones only).
pub trait ConstSettings: 'static {
    /// The settings.
    const SETTINGS: RenderSettings;
}

impl<T: ConstSettings> SettingsSource for T {
    #[inline(always)]
    fn settings(_: &RenderSettings) -> RenderSettings {
        T::SETTINGS
    }
}

impl RenderSettings {
    /// Settings with `method`, `n_light` light and `n_bsdf` BSDF samples per camera sample, `spp`
    /// camera samples per pixel, and the plain strategies of the lecture ([`Preset::Lecture`]:
    /// the estimator exactly as the method names it, what the tests of each technique need). The
    /// best strategies are [`Preset::Best`]'s: `Preset::Best.settings().with_method(method)`.
    /// Rejects a method left with no samples, a power heuristic whose beta is not finite and
    /// positive, a cutoff alpha outside [0, 1], and `spp` = 0.
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
        Self { method, light_samples, bsdf_samples, spp, seed, ..Preset::Lecture.settings() }.checked()
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
        self.checked()
    }

    /// The same settings with another quad-light sampling strategy.
    pub const fn with_quad_sampling(mut self, quads: QuadSampling) -> Self {
        self.quads = quads;
        self
    }

    /// The same settings with the analytic control variate on, off or by its rule. On and auto
    /// need the light technique, whose part the closed form is: a method and model that draw
    /// light samples (named here without them, either is an error).
    pub const fn with_control_variate(mut self, control_variate: ControlVariate) -> Result<Self, SceneError> {
        self.control_variate = control_variate;
        if let ControlVariate::On | ControlVariate::Auto | ControlVariate::BySize = control_variate {
            if self.technique_samples().0 == 0 {
                return Err(SceneError::ControlVariateWithoutLight);
            }
        }
        Ok(self)
    }

    /// These settings after a change of method, model or sample counts: a control variate that
    /// is on needs the light technique (an error without it); one by its rule (auto, as the best
    /// preset has it) yields to a method without light samples and is off.
    const fn checked(self) -> Result<Self, SceneError> {
        if self.technique_samples().0 > 0 {
            return Ok(self);
        }
        match self.control_variate {
            ControlVariate::On => Err(SceneError::ControlVariateWithoutLight),
            ControlVariate::Auto | ControlVariate::BySize => {
                Ok(Self { control_variate: ControlVariate::Off, ..self })
            }
            ControlVariate::Off => Ok(self),
        }
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

    /// The same settings with light samples that also follow a glossy receiver's lobe, or not.
    pub const fn with_lobe_mixing(mut self, lobe: LobeMixing) -> Self {
        self.lobe = lobe;
        self
    }

    /// The same settings with the strategies of `preset` (the method, the sample counts, spp
    /// and seed are kept).
    pub const fn with_strategies_of(self, preset: Preset) -> Self {
        let p = preset.settings();
        Self {
            spheres: p.spheres,
            selection: p.selection,
            model: p.model,
            quads: p.quads,
            control_variate: p.control_variate,
            sampler: p.sampler,
            lobe: p.lobe,
            ..self
        }
    }

    /// The same settings with another method (validated like [`Self::new`], and against the
    /// control variate: see [`Self::with_control_variate`]).
    pub const fn with_method(self, method: Method) -> Result<Self, SceneError> {
        let s = match Self::new(method, self.light_samples, self.bsdf_samples, self.spp, self.seed) {
            Ok(s) => s,
            Err(e) => return Err(e),
        };
        Self { method: s.method, ..self }.checked()
    }

    /// The same settings with `light_samples` light and `bsdf_samples` BSDF samples per camera
    /// sample (validated like [`Self::new`]).
    pub const fn with_sample_counts(self, light_samples: u16, bsdf_samples: u16) -> Result<Self, SceneError> {
        match Self::new(self.method, light_samples, bsdf_samples, self.spp, self.seed) {
            Ok(_) => Self { light_samples, bsdf_samples, ..self }.checked(),
            Err(e) => Err(e),
        }
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
    pub const fn technique_samples(&self) -> (u16, u16) {
        match self.model {
            MisModel::Multi => self.method.sample_counts(self.light_samples, self.bsdf_samples),
            MisModel::One { .. } => {
                let c = self.c_light();
                (if c > 0.0 { 1 } else { 0 }, if c < 1.0 { 1 } else { 0 })
            }
        }
    }
    /// Light and BSDF samples per camera sample, as requested (see
    /// [`RenderSettings::technique_samples`] for those drawn).
    pub fn sample_counts(&self) -> (u16, u16) {
        (self.light_samples, self.bsdf_samples)
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
    pub const fn c_light(&self) -> f32 {
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
