//! What the page can choose from: the built-in scenes, the methods, the light-selection and
//! sphere-sampling strategies, lobe mixing. Each list comes from its one definition
//! (`picomis-builtins`, the kernel's [`Choice`] lists: `Method::ALL` and the strategies' `ALL`),
//! and each default from the best preset ([`Preset::Best`], what `picomis-sim render` starts
//! from); this file only hands them to the page.

use picomis::{Choice, Heuristic, LightSelection, LobeMixing, Method, Preset, SphereSampling};
use picomis_format::SceneFile;
use serde_json::{Value, json};

pub use picomis_builtins::Builtin;

/// The built-in scenes, sorted by name (`picomis_builtins::BUILTINS`: every `scenes/*.json`).
pub const SCENES: &[Builtin] = picomis_builtins::BUILTINS;

/// The scene shown first.
pub const DEFAULT_SCENE: &str = "veach_mis";

/// The methods, by index: the kernel's list (each with its default parameters).
pub const METHODS: [Method; Method::ALL.len()] = Method::ALL;

/// Sphere-light sampling strategies, by index: the kernel's list (named as `picomis-sim render
/// --sphere-sampling`).
pub const SPHERE_SAMPLING: [SphereSampling; SphereSampling::ALL.len()] = SphereSampling::ALL;

/// Lobe mixing off and on, by index (named as `picomis-sim render --lobe-mixing`).
pub const LOBE_MIXING: [LobeMixing; LobeMixing::ALL.len()] = LobeMixing::ALL;

/// Light-selection strategies, by index: the kernel's list (named as `picomis-sim render
/// --light-selection`).
pub const LIGHT_SELECTION: [LightSelection; LightSelection::ALL.len()] = LightSelection::ALL;

/// The index in `list` of `default` (0 if absent).
fn index_of<C: Choice>(list: &[C], default: C) -> usize {
    list.iter().position(|c| *c == default).unwrap_or(0)
}

/// `m` as (index in [`METHODS`], beta, alpha), with the kernel's defaults for the parameters
/// `m` does not have.
pub fn method_parts(m: Method) -> (usize, f32, f32) {
    let index = METHODS.iter().position(|a| a.name() == m.name()).unwrap_or(0);
    (index, m.beta().unwrap_or(Heuristic::DEFAULT_BETA), m.alpha().unwrap_or(Heuristic::DEFAULT_ALPHA))
}

/// Method `index` of [`METHODS`] with `beta` and `alpha` where it has them, validated.
pub fn method(index: usize, beta: f32, alpha: f32) -> Result<Method, String> {
    let m = METHODS.get(index).ok_or_else(|| format!("no method number {index}"))?;
    m.with_parameters(Some(beta), Some(alpha)).map_err(|e| format!("{m}: {e}"))
}

/// Everything the page needs to build its controls, as JSON: scenes with their film and the
/// defaults of their integrator block, methods, strategies and their defaults.
pub fn info() -> Value {
    let scenes: Vec<Value> = SCENES
        .iter()
        .map(|b| match SceneFile::parse(b.json, b.name) {
            Ok(f) => {
                let settings = f.default_settings();
                let (method, beta, alpha) = method_parts(settings.method());
                let (light, bsdf) = settings.sample_counts();
                json!({
                    "name": b.name, "description": f.description(),
                    "width": f.film().width(), "height": f.film().height(),
                    "method": method, "beta": beta, "alpha": alpha,
                    "light_samples": light, "bsdf_samples": bsdf,
                })
            }
            Err(e) => json!({ "name": b.name, "error": e.to_string() }),
        })
        .collect();
    let best = Preset::Best.settings();
    json!({
        "scenes": scenes,
        "default_scene": SCENES.iter().position(|b| b.name == DEFAULT_SCENE).unwrap_or(0),
        "methods": METHODS.map(|m| m.name()),
        "sphere_sampling": SPHERE_SAMPLING.map(SphereSampling::name),
        "default_sphere_sampling": index_of(&SPHERE_SAMPLING, best.sphere_sampling()),
        "lobe_mixing": LOBE_MIXING.map(LobeMixing::name),
        "default_lobe_mixing": index_of(&LOBE_MIXING, best.lobe_mixing()),
        "light_selection": LIGHT_SELECTION.map(LightSelection::name),
        "default_light_selection": index_of(&LIGHT_SELECTION, best.light_selection()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_parses_and_its_method_round_trips() {
        assert!(SCENES.len() >= 5);
        assert!(SCENES.iter().any(|b| b.name == DEFAULT_SCENE));
        for b in SCENES {
            let f = SceneFile::parse(b.json, b.name).unwrap();
            assert_eq!(f.name(), b.name);
            let (i, beta, alpha) = method_parts(f.default_settings().method());
            assert_eq!(method(i, beta, alpha), Ok(f.default_settings().method()), "{}", b.name);
        }
        for i in 0..METHODS.len() {
            let m = method(i, 3.0, 0.25).unwrap();
            assert_eq!(method_parts(m), (i, m.beta().unwrap_or(2.0), m.alpha().unwrap_or(0.1)), "{m}");
        }
        assert_eq!(method(4, 3.0, 0.25).map(|m| m.beta()), Ok(Some(3.0)));
        assert!(
            method(4, -1.0, 0.25).is_err() && method(6, 2.0, 1.5).is_err() && method(7, 2.0, 0.1).is_err()
        );
        let info = info();
        assert_eq!(info["scenes"].as_array().unwrap().len(), SCENES.len());
        assert_eq!(
            info["sphere_sampling"][info["default_sphere_sampling"].as_u64().unwrap() as usize],
            "cone"
        );
        // Every default is the best preset's, by name.
        let best = Preset::Best.settings();
        let default =
            |list: &str| info[list][info[format!("default_{list}")].as_u64().unwrap() as usize].clone();
        assert_eq!(default("sphere_sampling"), best.sphere_sampling().name());
        assert_eq!(default("light_selection"), best.light_selection().name());
        assert_eq!(default("lobe_mixing"), best.lobe_mixing().name());
    }
}
