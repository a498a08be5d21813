//! The methods of the speed-against-accuracy study (`picomis-sim study`), the one list of them:
//! the study charts them and the benchmarks (`bench/`) time them, both reading it here. Each is a
//! [`Method`] with its sphere-light sampling and the further [`Extras`] it sets (the render
//! settings, and the arithmetic of the scene's ray queries), named for files and titled for charts.

use picomis::integrator::model::DEFAULT_C_LIGHT;
use picomis::{
    Arith, ControlVariate, Heuristic, LightSelection, LobeMixing, Method, MisModel, Preset, QuadSampling,
    RenderSettings, SamplerKind, Scene, SceneError, SphereSampling,
};

/// A method of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyMethod {
    /// Short name (CSV, file names).
    pub label: &'static str,
    /// Name in charts and tables.
    pub title: &'static str,
    /// The combination.
    pub method: Method,
    /// How sphere lights are sampled.
    pub spheres: SphereSampling,
    /// Everything else: sample stream, light selection, and what goes beyond the lecture.
    pub extras: Extras,
}

/// What a study method sets besides its combination and sphere sampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extras {
    /// The sample stream.
    pub sampler: SamplerKind,
    /// How a light is chosen among several.
    pub selection: LightSelection,
    /// The MIS model.
    pub model: MisModel,
    /// How quad lights are sampled.
    pub quads: QuadSampling,
    /// The analytic control variate.
    pub control_variate: ControlVariate,
    /// Light samples also from a glossy receiver's lobe (only in builds with the kernel's `lobe`
    /// feature: elsewhere such a method's settings are an error).
    pub lobe: LobeMixing,
    /// The arithmetic of the scene's ray queries: not a render setting but the scene's
    /// (`Extras::prepare`, feature `fixed`).
    pub arith: Arith,
}

impl Default for Extras {
    /// The lecture's estimator ([`Preset::Lecture`]: uniform light selection, which the Veach
    /// region study needs) with its stratified sample stream.
    fn default() -> Self {
        Extras::of(Preset::Lecture)
    }
}

impl Extras {
    /// The options of `preset`, in f32.
    pub fn of(preset: Preset) -> Self {
        let s = preset.settings();
        Extras {
            sampler: s.sampler(),
            selection: s.light_selection(),
            model: s.mis_model(),
            quads: s.quad_sampling(),
            control_variate: s.control_variate(),
            lobe: s.lobe_mixing(),
            arith: Arith::F32,
        }
    }

    /// `settings` with these options.
    pub fn apply(&self, settings: RenderSettings) -> Result<RenderSettings, SceneError> {
        settings
            .with_sampler(self.sampler)
            .with_light_selection(self.selection)
            .with_mis_model(self.model)?
            .with_quad_sampling(self.quads)
            .with_lobe_mixing(self.lobe)
            .with_control_variate(self.control_variate)
    }

    /// Runs `scene`'s ray queries in this arithmetic ([`Scene::enable_arith`]): the scene's
    /// [`SceneError::NotRepresentable`] when the arithmetic cannot represent it.
    pub fn prepare<const S: usize, const L: usize, const M: usize>(
        &self,
        scene: &mut Scene<S, L, M>,
    ) -> Result<(), SceneError> {
        scene.enable_arith(self.arith)
    }

    /// These options in f32: the method that the same seed and spp compare a fixed-point method
    /// with (the same random numbers).
    pub fn in_f32(&self) -> Extras {
        Extras { arith: Arith::F32, ..*self }
    }
}

impl StudyMethod {
    /// The render settings of this method with `n_light` light and `n_bsdf` BSDF samples per
    /// camera sample (see [`RenderSettings::new`]).
    pub fn settings(
        &self,
        n_light: u16,
        n_bsdf: u16,
        spp: u32,
        seed: u32,
    ) -> Result<RenderSettings, SceneError> {
        RenderSettings::new(self.method, n_light, n_bsdf, spp, seed)
            .and_then(|s| self.extras.apply(s.with_sphere_sampling(self.spheres)))
    }
}

/// The methods of the study, in the lecture's order, with the default sample stream and uniform
/// light selection; then the power heuristic with independent random numbers (what the
/// stratified stream gains), with lights chosen by power and by contribution, and with lobe
/// mixing, and what goes beyond the lecture, each against balance; last, the power heuristic with the scene's ray
/// queries in fixed point (against f32 power, same seeds). The heuristics sample sphere lights
/// by cone. (The
/// Veach region study renders each light alone, which leaves the selection probabilities
/// unchanged only under uniform selection: it leaves out the methods that choose otherwise.)
pub fn study_methods() -> [StudyMethod; 17] {
    let mis = Method::Mis;
    let (cone, area) = (SphereSampling::Cone, SphereSampling::Area);
    let study = |label, title, method, spheres| StudyMethod {
        label,
        title,
        method,
        spheres,
        extras: Extras::default(),
    };
    let power = mis(Heuristic::Power { beta: Heuristic::DEFAULT_BETA });
    let balance = mis(Heuristic::Balance);
    [
        study("bsdf", "BSDF sampling", Method::BsdfOnly, cone),
        study("light_area", "light sampling (area)", Method::LightOnly, area),
        study("light_cone", "light sampling (cone)", Method::LightOnly, cone),
        study("average", "average", mis(Heuristic::Average), cone),
        study("balance", "balance", balance, cone),
        study("power", "power (\u{3b2} = 2)", power, cone),
        study("maximum", "maximum", mis(Heuristic::Maximum), cone),
        study(
            "cutoff",
            "cutoff (\u{3b1} = 0.1)",
            mis(Heuristic::Cutoff { alpha: Heuristic::DEFAULT_ALPHA }),
            cone,
        ),
        // The sample stream: what the stratified default gains over independent numbers.
        StudyMethod {
            extras: Extras { sampler: SamplerKind::Independent, ..Extras::default() },
            ..study("power_independent", "power, independent numbers", power, cone)
        },
        // Light selection: by power, and by estimated contribution at the shading point.
        StudyMethod {
            extras: Extras { selection: LightSelection::Power, ..Extras::default() },
            ..study("power_by_power", "power, lights by power", power, cone)
        },
        StudyMethod {
            extras: Extras { selection: LightSelection::Contribution, ..Extras::default() },
            ..study("power_by_contribution", "power, lights by contribution", power, cone)
        },
        // Light samples also from a near-mirror's lobe where it meets a light (uniform
        // selection, so that the Veach region study keeps it).
        StudyMethod {
            extras: Extras { lobe: LobeMixing::On, ..Extras::default() },
            ..study("power_lobe", "power, lobe mixing", power, cone)
        },
        // Beyond the lecture, each against balance.
        StudyMethod {
            extras: Extras { model: MisModel::One { c_light: DEFAULT_C_LIGHT }, ..Extras::default() },
            ..study("one_balance", "one-sample balance (c = 0.5)", balance, cone)
        },
        StudyMethod {
            extras: Extras { quads: QuadSampling::SolidAngle, ..Extras::default() },
            ..study("balance_sa", "balance, quads by solid angle", balance, cone)
        },
        StudyMethod {
            extras: Extras { quads: QuadSampling::SolidAngleCosine, ..Extras::default() },
            ..study("balance_sac", "balance, quads by solid angle x cosine", balance, cone)
        },
        StudyMethod {
            extras: Extras { control_variate: ControlVariate::On, ..Extras::default() },
            ..study("balance_cv", "balance + control variate", balance, cone)
        },
        // The scene's ray queries in fixed point (cores without an FPU), against f32 power.
        StudyMethod {
            extras: Extras { arith: Arith::Fixed, ..Extras::default() },
            ..study("power_fixed", "power, fixed-point ray queries", power, cone)
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn study_methods_are_valid_distinct_and_titled_with_the_defaults() {
        let all = study_methods();
        for (i, m) in all.iter().enumerate() {
            assert!(m.settings(1, 1, 1, 0).is_ok(), "{}", m.label);
            assert!(all[..i].iter().all(|o| o.label != m.label && o != m), "{} twice", m.label);
        }
        // Each of the kernel's methods, and both sphere samplings, is in the list.
        assert!(Method::ALL.iter().all(|k| all.iter().any(|m| m.method == *k)));
        assert!(all.iter().any(|m| m.spheres == SphereSampling::Area));
        // Every arithmetic is in the list, and every fixed-point method has its f32 twin.
        assert!(all.iter().any(|m| m.extras.arith == Arith::Fixed));
        for m in all.iter().filter(|m| m.extras.arith != Arith::F32) {
            let twin = all
                .iter()
                .find(|o| o.method == m.method && o.spheres == m.spheres && o.extras == m.extras.in_f32());
            assert_eq!(twin.map(|t| t.label), Some("power"), "{}", m.label);
        }
        // The titles state the kernel's defaults.
        let title = |label| all.iter().find(|m| m.label == label).map(|m| m.title);
        assert_eq!(title("power"), Some(format!("power (\u{3b2} = {})", Heuristic::DEFAULT_BETA).as_str()));
        assert_eq!(
            title("cutoff"),
            Some(format!("cutoff (\u{3b1} = {})", Heuristic::DEFAULT_ALPHA).as_str())
        );
        assert_eq!(
            title("one_balance"),
            Some(format!("one-sample balance (c = {DEFAULT_C_LIGHT})").as_str())
        );
    }
}
