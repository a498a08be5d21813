//! Build script: the memory layout for cortex-m-rt's `link.x` (with the RP2040's boot loader
//! section), the linker scripts (`link.x`, defmt's `defmt.x`), and the scene: the
//! picomis-scene/1 file (`PICOMIS_SCENE`, default the repository's `scenes/veach_mis.json`)
//! built for the display's 320 x 240 pixels (landscape), as Rust (`OUT_DIR/picomis_scene.rs`:
//! the scene's image, its settings as constants, its strategy types).

use std::env;
use std::path::PathBuf;

/// The display's size in pixels: the film the scene is built for (main.rs takes the display
/// size from the scene's film).
const DISPLAY: (u32, u32) = (320, 240);

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");

    println!("cargo:rerun-if-env-changed=PICOMIS_SCENE");
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let scene = env::var_os("PICOMIS_SCENE")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest.join("../../scenes/veach_mis.json"));
    // `PICOMIS_PRESET=lecture`: the course's estimator instead of the file's integrator block
    // (smaller and faster per sample; see the README's frame times).
    let preset = picomis_format::build::preset_from_env().unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    let firmware = picomis_format::build::Firmware {
        preset,
        ..picomis_format::build::Firmware::new(manifest.join(scene), DISPLAY.0, DISPLAY.1)
    };
    if let Err(e) = firmware.generate() {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
