//! Coverage-guided fuzzing of the scene loader: no input may panic, and every accepted scene
//! must build and render finite pixels. See the README ("Where methods fail" / fuzzing).
#![no_main]

use libfuzzer_sys::fuzz_target;
use picomis::{Film, Heuristic, Method, RenderSettings, render_pixel};
use picomis_format::SceneFile;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(scene) = SceneFile::parse(text, "fuzz.json") else { return };
    let Ok(film) = Film::new(3, 2) else { return };
    let Ok(built) = scene.build_with_film::<64, 64, 64>(film) else {
        let c = scene.counts();
        assert!(c.shapes > 64 || c.lights > 64 || c.materials > 64, "valid scene failed to build");
        return;
    };
    let settings = RenderSettings::new(Method::Mis(Heuristic::Power { beta: 2.0 }), 1, 1, 2, 1).unwrap();
    for (x, y) in [(0, 0), (2, 1)] {
        assert!(render_pixel(&built, &settings, x, y).radiance().is_finite());
    }
});
