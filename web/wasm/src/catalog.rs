//! What the page can choose from: the built-in scenes, the methods, the light-selection and
//! sphere-sampling strategies, lobe mixing. Each list comes from its one definition (`picomis-builtins`, the
//! kernel's `Method::ALL` and enums); this file only hands them to the page.

use picomis::{Heuristic, LightSelection, LobeMixing, Method, SphereSampling};
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
                let (method, beta, alpha) = method_parts(f.default_method());
                let (light, bsdf) = f.default_samples();
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
    json!({
        "scenes": scenes,
        "default_scene": SCENES.iter().position(|b| b.name == DEFAULT_SCENE).unwrap_or(0),
        "methods": METHODS.map(|m| m.name()),
        "sphere_sampling": SPHERE_SAMPLING.map(SphereSampling::name),
        "default_sphere_sampling": SPHERE_SAMPLING.iter().position(|s| *s == SphereSampling::default()).unwrap_or(0),
        "lobe_mixing": LOBE_MIXING.map(LobeMixing::name),
        "default_lobe_mixing": LOBE_MIXING.iter().position(|l| *l == LobeMixing::default()).unwrap_or(0),
        "light_selection": LIGHT_SELECTION.map(LightSelection::name),
        "default_light_selection": LIGHT_SELECTION.iter().position(|s| *s == LightSelection::default()).unwrap_or(0),
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
            let (i, beta, alpha) = method_parts(f.default_method());
            assert_eq!(method(i, beta, alpha), Ok(f.default_method()), "{}", b.name);
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
    }
}
