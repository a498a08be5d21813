//! The methods of the study: the host's list ([`study_methods`], the one the benchmarks time),
//! then "defaults", the scene's own integrator: the best preset under the scene file's
//! integrator block under the command line's integrator flags, as `picomis-sim render` renders
//! the scene ([`crate::integrator::integrator`]).

use picomis::{Arith, Preset, RenderSettings};
use picomis_host::study::{Extras, StudyMethod, study_methods};

/// The label of the method that renders with the scene's own integrator.
pub const DEFAULTS: &str = "defaults";

/// The methods of the study: [`study_methods`], then [`DEFAULTS`] (here with the best preset's
/// settings: each scene's study puts its own integrator's in its place, [`defaults`]).
pub fn methods() -> Vec<StudyMethod> {
    let mut all = study_methods().to_vec();
    all.push(defaults(&Preset::Best.settings()));
    all
}

/// Index in [`methods`] of the [`DEFAULTS`] method.
pub fn defaults_index() -> usize {
    study_methods().len()
}

/// The [`DEFAULTS`] method with the options of `settings` (a scene's integrator; its sample
/// counts are its own, not the study method's: they are not part of a [`StudyMethod`]).
pub fn defaults(settings: &RenderSettings) -> StudyMethod {
    StudyMethod {
        label: DEFAULTS,
        title: "defaults (best preset, scene's integrator)",
        method: settings.method(),
        spheres: settings.sphere_sampling(),
        extras: Extras {
            sampler: settings.sampler(),
            selection: settings.light_selection(),
            model: settings.mis_model(),
            quads: settings.quad_sampling(),
            control_variate: settings.control_variate(),
            lobe: settings.lobe_mixing(),
            arith: Arith::F32,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_come_last_with_the_settings_they_are_given() {
        let all = methods();
        assert_eq!(all.len(), study_methods().len() + 1);
        assert_eq!(all[defaults_index()].label, DEFAULTS);
        assert!(all[..defaults_index()].iter().all(|m| m.label != DEFAULTS));
        // Its options are those of the settings: applied to the same method and counts, they
        // give the settings back.
        let s = Preset::Best
            .settings()
            .with_light_selection(picomis::LightSelection::Contribution)
            .with_lobe_mixing(picomis::LobeMixing::On)
            .with_spp(4)
            .unwrap()
            .with_seed(9);
        let (n_light, n_bsdf) = s.sample_counts();
        assert_eq!(defaults(&s).settings(n_light, n_bsdf, 4, 9), Ok(s));
    }
}
