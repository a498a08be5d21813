//! What the two fuzz harnesses (`fuzz.rs`: the JSON loader; `fuzz_mitsuba.rs`: the Mitsuba 3
//! importer) share: case counts, a runner with a fixed seed, byte-level edits, and the check that
//! an accepted scene builds and renders finite pixels; and the estimator of the lecture's
//! strategies that they and `mitsuba.rs` render with ([`render_pixel`]).

#![allow(dead_code)]

use picomis::integrator::{control_variate, model};
use picomis::light::select::Uniform;
use picomis::light::{lobe, quad, sphere};
use picomis::{
    Direct, Estimate, Film, Heuristic, Integrator, Lights, Method, Preset, RenderSettings, Scene, SceneError,
    SphereSampling,
};
use picomis_format::SceneFile;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// The lecture's strategies ([`Preset::Lecture`]) with spheres sampled by `Sp`.
type Lecture<Sp> = Direct<Lights<Uniform, Sp, quad::ByArea, lobe::Off>, control_variate::Off, model::Multi>;

/// The settings of `method` (`n_light` and `n_bsdf` samples, `spp`, `seed`) with the lecture's
/// strategies and sphere lights sampled by `spheres`: what [`render_pixel`] renders.
pub fn lecture_settings(
    method: Method,
    (n_light, n_bsdf): (u16, u16),
    spp: u32,
    seed: u32,
    spheres: SphereSampling,
) -> Result<RenderSettings, SceneError> {
    let s = RenderSettings::new(method, n_light, n_bsdf, spp, seed)?;
    Ok(s.with_strategies_of(Preset::Lecture).with_sphere_sampling(spheres))
}

/// The HDR estimate of pixel `(x, y)` of `scene` rendered with `settings`, whose strategies are
/// the lecture's but for sphere sampling ([`lecture_settings`]): the estimator monomorphised for
/// either sphere sampling ([`SceneError::StrategyMismatch`] for other strategies).
pub fn render_pixel<const S: usize, const L: usize, const M: usize>(
    scene: &Scene<S, L, M>,
    settings: &RenderSettings,
    x: u32,
    y: u32,
) -> Result<Estimate, SceneError> {
    Ok(match settings.sphere_sampling() {
        SphereSampling::Area => {
            Integrator::<Lecture<sphere::ByArea>, S, L, M>::new(scene, settings)?.render_pixel(x, y)
        }
        SphereSampling::Cone => {
            Integrator::<Lecture<sphere::InCone>, S, L, M>::new(scene, settings)?.render_pixel(x, y)
        }
    })
}

/// `default` cases, or `PICOMIS_FUZZ_CASES` for a long run.
pub fn cases(default: u32) -> u32 {
    std::env::var("PICOMIS_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// A runner drawing `cases` inputs from a fixed ChaCha seed: CI runs the same inputs every time
/// (the long, coverage-guided search is `scripts/fuzz.sh`).
pub fn runner(cases: u32) -> TestRunner {
    let config =
        Config { cases, failure_persistence: None, rng_algorithm: RngAlgorithm::ChaCha, ..Config::default() };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[0xF2; 32]))
}

/// An accepted scene: too many objects for the build is an error; otherwise it builds and a few
/// pixels at a tiny resolution are finite with several methods.
pub fn renders_finite(scene: &SceneFile) -> Result<(), TestCaseError> {
    let c = scene.counts();
    if c.shapes > 64 || c.lights > 64 || c.materials > 64 {
        prop_assert!(scene.build::<64, 64, 64>().is_err());
        return Ok(());
    }
    let film = Film::new(4, 3).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let built = scene
        .build_with_film::<64, 64, 64>(film)
        .map_err(|e| TestCaseError::fail(format!("accepted scene failed to build: {e}")))?;
    for (method, spheres) in [
        (Method::Mis(Heuristic::Power { beta: 2.0 }), SphereSampling::Cone),
        (Method::Mis(Heuristic::Balance), SphereSampling::Area),
        (Method::BsdfOnly, SphereSampling::Cone),
    ] {
        let settings = lecture_settings(method, (1, 1), 2, 3, spheres)
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        for (x, y) in [(0, 0), (2, 1), (3, 2)] {
            let e = render_pixel(&built, &settings, x, y).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert!(e.radiance().is_finite(), "non-finite pixel {} in an accepted scene", e.radiance());
        }
    }
    Ok(())
}

/// One byte-level edit of a file.
#[derive(Clone, Debug)]
pub enum ByteEdit {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize, usize),
    Splice(usize, usize, usize),
}

/// Edits that insert bytes of `alphabet` (the format's syntax) and splice up to `max_splice` bytes.
pub fn byte_edit(alphabet: &'static [u8], max_splice: usize) -> impl Strategy<Value = ByteEdit> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| ByteEdit::Flip(i, b)),
        (any::<usize>(), prop::sample::select(alphabet.to_vec())).prop_map(|(i, b)| ByteEdit::Insert(i, b)),
        (any::<usize>(), 1usize..64).prop_map(|(i, n)| ByteEdit::Delete(i, n)),
        (any::<usize>(), any::<usize>(), 1usize..max_splice).prop_map(|(a, b, n)| ByteEdit::Splice(a, b, n)),
    ]
}

/// `text` with `edits` applied (positions wrap around its length).
pub fn apply(text: &str, edits: &[ByteEdit]) -> String {
    let mut b = text.as_bytes().to_vec();
    for e in edits {
        let len = b.len().max(1);
        match *e {
            ByteEdit::Flip(i, x) => {
                if let Some(v) = b.get_mut(i % len) {
                    *v ^= x;
                }
            }
            ByteEdit::Insert(i, x) => b.insert((i % len).min(b.len()), x),
            ByteEdit::Delete(i, n) => {
                let start = (i % len).min(b.len());
                let end = (start + n).min(b.len());
                b.drain(start..end);
            }
            ByteEdit::Splice(from, to, n) => {
                let start = (from % len).min(b.len());
                let chunk: Vec<u8> = b[start..(start + n).min(b.len())].to_vec();
                let at = (to % len).min(b.len());
                b.splice(at..at, chunk);
            }
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}
