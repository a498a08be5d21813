//! The one description of the integrator's settings: the scene file's `integrator` block and
//! the command line's flags are the same type, [`IntegratorDesc`], key for key (a flag's name is
//! its key in kebab case: `"lobe_mixing": "on"` is `--lobe-mixing on`). Every option is a
//! kernel [`Choice`], read and written by its name; [`IntegratorDesc::settings`] turns the keys
//! into validated kernel settings, starting from a [`Preset`].

use std::fmt;

#[cfg(feature = "cli")]
use picomis::Heuristic;
use picomis::choice::{Choice, Names};
use picomis::{
    ControlVariate, LightSelection, LobeMixing, Method, MisModel, Preset, QuadSampling, RenderSettings,
    SamplerKind, SphereSampling,
};
use serde::{Deserialize, Serialize};

/// The integrator's type: direct lighting (the only one).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorType {
    /// Direct lighting with MIS.
    #[default]
    Direct,
}

/// Every setting of the integrator; a key that is absent keeps the value it has underneath
/// ([`IntegratorDesc::over`]): the scene file's under the command line's, the preset's under the
/// scene file's.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields)]
pub struct IntegratorDesc {
    /// The integrator (scene files only: `"type": "direct"`).
    #[serde(rename = "type", default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(skip))]
    pub kind: Option<IntegratorType>,
    /// Where the settings start from: the measured best (default) or the lecture's estimator.
    /// On the command line it replaces the scene file's integrator block.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "P", value_parser = choice_parser::<Preset>(), help_heading = "Integrator"))]
    pub preset: Option<Preset>,
    /// Combination method of the light and BSDF techniques.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "M", value_parser = choice_parser::<Method>(), help_heading = "MIS"))]
    pub mis: Option<Method>,
    /// Power-heuristic exponent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "B", allow_negative_numbers = true, help_heading = "MIS",
        help = format!("Power-heuristic exponent (default {})", Heuristic::DEFAULT_BETA)))]
    pub beta: Option<f32>,
    /// Cutoff-heuristic threshold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "A", allow_negative_numbers = true, help_heading = "MIS",
        help = format!("Cutoff-heuristic threshold (default {})", Heuristic::DEFAULT_ALPHA)))]
    pub alpha: Option<f32>,
    /// Light samples per camera sample (scene files also say `emitter_samples`, Mitsuba's name).
    #[serde(default, alias = "emitter_samples", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", help_heading = "Sampling"))]
    pub light_samples: Option<u16>,
    /// BSDF samples per camera sample.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", help_heading = "Sampling"))]
    pub bsdf_samples: Option<u16>,
    /// Sample stream.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "S", value_parser = choice_parser::<SamplerKind>(), help_heading = "Sampling"))]
    pub sampler: Option<SamplerKind>,
    /// How a light is chosen among several.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "S", value_parser = choice_parser::<LightSelection>(), help_heading = "Sampling"))]
    pub light_selection: Option<LightSelection>,
    /// How sphere lights are sampled.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "S", value_parser = choice_parser::<SphereSampling>(), help_heading = "Sampling"))]
    pub sphere_sampling: Option<SphereSampling>,
    /// How quad lights are sampled.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "Q", value_parser = choice_parser::<QuadSampling>(), help_heading = "Sampling"))]
    pub quad_sampling: Option<QuadSampling>,
    /// Light samples also from a glossy receiver's lobe where it is narrower than the light.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "ON", value_parser = choice_parser::<LobeMixing>(), help_heading = "Sampling"))]
    pub lobe_mixing: Option<LobeMixing>,
    /// MIS model: every technique draws its samples (multi), or one sample of one technique.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "MODEL", value_parser = choice_parser::<MisModel>(), help_heading = "MIS"))]
    pub mis_model: Option<MisModel>,
    /// Probability of the light technique in the one-sample model, in [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "C", allow_negative_numbers = true, help_heading = "MIS")
    )]
    pub c_light: Option<f32>,
    /// Unoccluded light on Lambertian receivers in closed form, Monte Carlo for the shadows only.
    #[serde(default, with = "choice", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_name = "ON", value_parser = choice_parser::<ControlVariate>(), help_heading = "MIS"))]
    pub control_variate: Option<ControlVariate>,
    /// Whether emitters seen directly are hidden (scene files only; must be false).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(skip))]
    pub hide_emitters: Option<bool>,
}

/// Why a description's keys do not make valid settings: the key (snake case, as in a scene file)
/// and the reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct KeyError {
    /// The key.
    pub key: &'static str,
    /// What is wrong.
    pub reason: String,
}

impl KeyError {
    fn new(key: &'static str, reason: impl fmt::Display) -> Self {
        KeyError { key, reason: reason.to_string() }
    }

    /// The key as a command-line flag: `--light-samples`.
    pub fn flag(&self) -> String {
        format!("--{}", self.key.replace('_', "-"))
    }
}

impl fmt::Display for KeyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.key, self.reason)
    }
}

impl IntegratorDesc {
    /// The keys of `self` over those of `below`: each key set here replaces the one below. A
    /// preset set here starts over from it: nothing below is kept.
    pub fn over(&self, below: &IntegratorDesc) -> IntegratorDesc {
        if self.preset.is_some() {
            return self.clone();
        }
        macro_rules! or {
            ($($k:ident),+) => { IntegratorDesc { $($k: self.$k.or(below.$k),)+ } };
        }
        or!(
            kind,
            preset,
            mis,
            beta,
            alpha,
            light_samples,
            bsdf_samples,
            sampler,
            light_selection,
            sphere_sampling,
            quad_sampling,
            lobe_mixing,
            mis_model,
            c_light,
            control_variate,
            hide_emitters
        )
    }

    /// The kernel settings these keys describe, starting from the preset (the measured best when
    /// none is named), with `spp` camera samples per pixel and `seed`. The error names the key.
    pub fn settings(&self, spp: u32, seed: u32) -> Result<RenderSettings, KeyError> {
        let base = self.preset.unwrap_or(Preset::Best).settings();
        if self.hide_emitters == Some(true) {
            return Err(KeyError::new("hide_emitters", "hiding emitters is not supported (use false)"));
        }
        // A method named here comes with its default parameter, then beta or alpha.
        let method = self.mis.unwrap_or(base.method());
        let name = method.name();
        let method = method.with_parameters(self.beta, self.alpha).map_err(|e| match self.beta {
            Some(_) if method.beta().is_some() => KeyError::new("beta", e),
            _ => KeyError::new("alpha", e),
        })?;
        if let (Some(beta), None) = (self.beta, method.beta()) {
            return Err(KeyError::new(
                "beta",
                format!("{beta}: only the power heuristic has a beta (mis is {name})"),
            ));
        }
        if let (Some(alpha), None) = (self.alpha, method.alpha()) {
            return Err(KeyError::new(
                "alpha",
                format!("{alpha}: only the cutoff heuristic has an alpha (mis is {name})"),
            ));
        }
        let (base_light, base_bsdf) = base.sample_counts();
        let (n_light, n_bsdf) =
            (self.light_samples.unwrap_or(base_light), self.bsdf_samples.unwrap_or(base_bsdf));
        let settings = RenderSettings::new(method, n_light, n_bsdf, spp, seed).map_err(|e| {
            let key = if spp == 0 { "spp" } else { "light_samples" };
            KeyError::new(key, format!("{e} (mis {name}, {n_light} light and {n_bsdf} BSDF samples)"))
        })?;
        let model = match (self.mis_model.unwrap_or(base.mis_model()), self.c_light) {
            (MisModel::Multi, Some(c)) => {
                return Err(KeyError::new(
                    "c_light",
                    format!("{c}: only the one-sample model (mis_model one) has a c"),
                ));
            }
            (MisModel::Multi, None) => MisModel::Multi,
            (MisModel::One { c_light }, c) => MisModel::One { c_light: c.unwrap_or(c_light) },
        };
        // (The control variate last: it depends on the method and the model.)
        let settings = settings
            .with_sampler(self.sampler.unwrap_or(base.sampler()))
            .with_light_selection(self.light_selection.unwrap_or(base.light_selection()))
            .with_sphere_sampling(self.sphere_sampling.unwrap_or(base.sphere_sampling()))
            .with_quad_sampling(self.quad_sampling.unwrap_or(base.quad_sampling()))
            .with_lobe_mixing(self.lobe_mixing.unwrap_or(base.lobe_mixing()))
            .with_control_variate(ControlVariate::Off)
            .and_then(|s| s.with_mis_model(model))
            .map_err(|e| KeyError::new("c_light", e))?;
        // The preset's control variate belongs to the light technique: without light samples,
        // none; one named here is an error then.
        let control_variate = match self.control_variate {
            Some(cv) => cv,
            None if settings.technique_samples().0 == 0 => ControlVariate::Off,
            None => base.control_variate(),
        };
        settings
            .with_control_variate(control_variate)
            .map_err(|e| KeyError::new("control_variate", format!("{e} (mis {name})")))
    }

    /// The keys that describe `settings` completely (every key set; no preset).
    pub fn of(settings: &RenderSettings) -> IntegratorDesc {
        let method = settings.method();
        let (light_samples, bsdf_samples) = settings.sample_counts();
        let c_light = match settings.mis_model() {
            MisModel::One { c_light } => Some(c_light),
            MisModel::Multi => None,
        };
        IntegratorDesc {
            kind: None,
            preset: None,
            mis: Some(method),
            beta: method.beta(),
            alpha: method.alpha(),
            light_samples: Some(light_samples),
            bsdf_samples: Some(bsdf_samples),
            sampler: Some(settings.sampler()),
            light_selection: Some(settings.light_selection()),
            sphere_sampling: Some(settings.sphere_sampling()),
            quad_sampling: Some(settings.quad_sampling()),
            lobe_mixing: Some(settings.lobe_mixing()),
            mis_model: Some(settings.mis_model()),
            c_light,
            control_variate: Some(settings.control_variate()),
            hide_emitters: None,
        }
    }

    /// The settings beyond the method and sample counts that differ from `preset`'s, as
    /// `key value` pairs (for a render's one-line summary).
    pub fn differences(settings: &RenderSettings, preset: Preset) -> Vec<(&'static str, String)> {
        let base = preset.settings();
        let mut out = Vec::new();
        let mut note = |key, differs: bool, value: String| {
            if differs {
                out.push((key, value));
            }
        };
        note("sampler", settings.sampler() != base.sampler(), settings.sampler().name().into());
        note(
            "light_selection",
            settings.light_selection() != base.light_selection(),
            settings.light_selection().name().into(),
        );
        note(
            "sphere_sampling",
            settings.sphere_sampling() != base.sphere_sampling(),
            settings.sphere_sampling().name().into(),
        );
        note(
            "quad_sampling",
            settings.quad_sampling() != base.quad_sampling(),
            settings.quad_sampling().name().into(),
        );
        note(
            "lobe_mixing",
            settings.lobe_mixing() != base.lobe_mixing(),
            settings.lobe_mixing().name().into(),
        );
        let model = settings.mis_model();
        let model_text = match model {
            MisModel::One { c_light } => format!("one (c_light {c_light})"),
            MisModel::Multi => "multi".into(),
        };
        note("mis_model", model != base.mis_model(), model_text);
        note(
            "control_variate",
            settings.control_variate() != base.control_variate(),
            settings.control_variate().name().into(),
        );
        out
    }
}

/// Serde for an optional [`Choice`], by name; an unknown name is an error that lists the names.
mod choice {
    use super::*;

    pub fn serialize<S: serde::Serializer, T: Choice>(v: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(c) => s.serialize_str(c.name()),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>, T: Choice>(d: D) -> Result<Option<T>, D::Error> {
        let name = String::deserialize(d)?;
        match T::from_name(&name) {
            Some(c) => Ok(Some(c)),
            None => Err(serde::de::Error::custom(format!(
                "unknown {} {name:?} (expected {})",
                T::WHAT,
                Names::<T>::of()
            ))),
        }
    }
}

/// The command-line value parser of a [`Choice`]: its names, with their summaries in the help.
#[cfg(feature = "cli")]
pub fn choice_parser<T: Choice + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    let names: Vec<PossibleValue> =
        T::ALL.iter().map(|c| PossibleValue::new(c.name()).help(c.summary())).collect();
    PossibleValuesParser::new(names)
        .try_map(|name| T::from_name(&name).ok_or_else(|| format!("unknown {} {name:?}", T::WHAT)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use picomis::Heuristic;

    fn desc(json: &str) -> Result<IntegratorDesc, String> {
        serde_json::from_str(json).map_err(|e| e.to_string())
    }

    #[test]
    fn every_key_reads_back_as_written() {
        let settings = Preset::Lecture
            .settings()
            .with_light_selection(LightSelection::Contribution)
            .with_lobe_mixing(LobeMixing::On)
            .with_mis_model(MisModel::One { c_light: 0.25 })
            .unwrap();
        let d = IntegratorDesc::of(&settings);
        let json = serde_json::to_string(&d).unwrap();
        assert!(
            json.contains(r#""lobe_mixing":"on""#) && json.contains(r#""light_selection":"contribution""#),
            "{json}"
        );
        let back: IntegratorDesc = serde_json::from_str(&json).unwrap();
        assert_eq!(back.settings(1, 0), Ok(settings));
    }

    #[test]
    fn unknown_keys_and_values_name_what_is_valid() {
        let e = desc(r#"{"lobe_mixng": "on"}"#).unwrap_err();
        assert!(e.contains("unknown field `lobe_mixng`") && e.contains("lobe_mixing"), "{e}");
        let e = desc(r#"{"light_selection": "random"}"#).unwrap_err();
        assert!(
            e.contains(
                r#"unknown light selection "random" (expected uniform, power, contribution or every)"#
            ),
            "{e}"
        );
    }

    #[test]
    fn keys_over_keys_and_presets_over_all() {
        let file = desc(r#"{"mis": "balance", "lobe_mixing": "on"}"#).unwrap();
        let cli = IntegratorDesc { lobe_mixing: Some(LobeMixing::Off), ..Default::default() };
        let both = cli.over(&file);
        assert_eq!(
            (both.mis, both.lobe_mixing),
            (Some(Method::Mis(Heuristic::Balance)), Some(LobeMixing::Off))
        );
        let lecture = IntegratorDesc { preset: Some(Preset::Lecture), ..Default::default() };
        assert_eq!(
            lecture.over(&file).settings(4, 1),
            Ok(Preset::Lecture.settings().with_spp(4).unwrap().with_seed(1))
        );
    }

    #[test]
    fn keys_that_do_not_apply_are_errors() {
        let e = desc(r#"{"mis": "balance", "beta": 3}"#).unwrap().settings(1, 0).unwrap_err();
        assert_eq!(e.key, "beta");
        let e = desc(r#"{"c_light": 0.5}"#).unwrap().settings(1, 0).unwrap_err();
        assert_eq!((e.key, e.flag()), ("c_light", "--c-light".to_string()));
        let e = desc(r#"{"mis": "bsdf", "control_variate": "on"}"#).unwrap().settings(1, 0).unwrap_err();
        assert_eq!(e.key, "control_variate");
        let e = desc(r#"{"mis_model": "one", "c_light": 2}"#).unwrap().settings(1, 0).unwrap_err();
        assert_eq!(e.key, "c_light");
    }
}
