//! Coverage-guided fuzzing of the Mitsuba 3 XML importer: no input may panic, and every
//! accepted file must be a valid scene that builds and renders finite pixels.
#![no_main]

use libfuzzer_sys::fuzz_target;
use picomis::{Film, Heuristic, Method, RenderSettings, render_pixel};
use picomis_format::{SceneFile, mitsuba};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let json = match mitsuba::import(text, "fuzz.xml", "fuzz") {
        Ok(json) => json,
        Err(e) => {
            assert!(e.file.starts_with("fuzz.xml") && e.to_string().lines().count() == 1, "{e}");
            return;
        }
    };
    let scene = SceneFile::parse(&json, "fuzz.json").expect("an imported file is a valid scene");
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
