//! Coverage-guided fuzzing of the Mitsuba 3 XML importer: no input may panic, and every
//! accepted file must be a valid scene that builds and renders finite pixels.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
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
    common::check_accepted(&scene);
});
