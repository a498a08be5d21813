//! Coverage-guided fuzzing of the scene loader: no input may panic, and every accepted scene
//! must build and render finite pixels. See the README ("Where methods fail" / fuzzing).
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use picomis_format::SceneFile;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(scene) = SceneFile::parse(text, "fuzz.json") else { return };
    common::check_accepted(&scene);
});
