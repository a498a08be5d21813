//! Build script of the firmware:
//! - picks the board from the target (thumbv7em: STM32F405, thumbv6m: nRF51822 / micro:bit,
//!   riscv32: FE310 / HiFive1) and
//!   copies its memory layout to OUT_DIR as `board-memory.x`, which the root `memory.x` includes;
//! - turns the scene file (`PICOMIS_SCENE`, default `scenes/veach_mis.json`; with
//!   `PICOMIS_PRESET`, a preset's settings instead of its integrator block) into Rust with
//!   `picomis_format::SceneFile::to_rust` and the scene built for the film as an image
//!   (`SceneFile::image_rust`; OUT_DIR/scene.rs);
//! - writes the render configuration from `PICOMIS_WIDTH/HEIGHT/SPP/SEED/TILE/OUT` and
//!   `PICOMIS_MEASURE_*` (OUT_DIR/config.rs);
//! - passes the linker scripts (`link.x`, and `defmt.x` with the `rtt` feature).

use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

type BoxError = Box<dyn std::error::Error>;

/// A board: its memory file in `boards/`, its QEMU machine, and the default film.
struct Board {
    name: &'static str,
    memory: &'static str,
    qemu_machine: &'static str,
    width: u32,
    height: u32,
}

const BOARDS: [Board; 3] = [
    Board {
        name: "stm32f405",
        memory: "stm32f405.x",
        qemu_machine: "netduinoplus2",
        width: 160,
        height: 120,
    },
    Board { name: "nrf51822", memory: "nrf51822.x", qemu_machine: "microbit", width: 64, height: 48 },
    Board { name: "fe310", memory: "fe310.x", qemu_machine: "sifive_e", width: 64, height: 48 },
];

fn var(name: &str) -> Option<String> {
    println!("cargo:rerun-if-env-changed={name}");
    env::var(name).ok().filter(|v| !v.trim().is_empty())
}

fn number(name: &str) -> Result<Option<u32>, BoxError> {
    match var(name) {
        Some(v) => Ok(Some(v.trim().parse().map_err(|e| format!("{name}={v:?}: {e}"))?)),
        None => Ok(None),
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("picomis-firmware build script: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), BoxError> {
    println!("cargo:rerun-if-changed=build.rs");
    let out = PathBuf::from(env::var("OUT_DIR")?);
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR")?);
    let root = manifest.parent().ok_or("firmware/ has no parent directory")?.to_path_buf();
    let target = env::var("TARGET")?;
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        // A host build (e.g. `cargo build --workspace`) compiles only a stub main.
        return Ok(());
    }

    // Board and memory layout.
    let board_name = match var("PICOMIS_BOARD") {
        Some(b) => b,
        None if target.starts_with("thumbv7em") => "stm32f405".into(),
        None if target.starts_with("thumbv6m") => "nrf51822".into(),
        None if target.starts_with("riscv32") => "fe310".into(),
        None => return Err(format!("no default board for target {target}; set PICOMIS_BOARD").into()),
    };
    let board = BOARDS
        .iter()
        .find(|b| b.name == board_name)
        .ok_or_else(|| format!("unknown PICOMIS_BOARD {board_name:?} (stm32f405, nrf51822 or fe310)"))?;
    let memory_file = manifest.join("boards").join(board.memory);
    let memory = fs::read_to_string(&memory_file).map_err(|e| format!("{}: {e}", memory_file.display()))?;
    println!("cargo:rerun-if-changed={}", memory_file.display());
    println!("cargo:rerun-if-changed={}", root.join("memory.x").display());
    fs::write(out.join("board-memory.x"), &memory)?;
    // Found only when the linker does not run in the workspace root (whose memory.x includes
    // board-memory.x): the same layout either way.
    fs::write(out.join("memory.x"), &memory)?;
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    if env::var_os("CARGO_FEATURE_RTT").is_some() {
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    }
    // RV32: the compiler's memcpy calls go to src/arch/riscv_memcpy.s (which reaches
    // compiler-builtins' as __real_memcpy), and without the F extension its soft-float calls to
    // picomis-softfloat's routines.
    if target.starts_with("riscv32") {
        println!("cargo:rustc-link-arg-bins=--wrap=memcpy");
        let features = env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
        if !features.split(',').any(|f| f == "f") {
            for symbol in picomis_softfloat::RV32_WRAPPED {
                println!("cargo:rustc-link-arg-bins=--wrap={symbol}");
            }
        }
    }

    // Scene.
    let scene_arg = var("PICOMIS_SCENE").unwrap_or_else(|| "scenes/veach_mis.json".into());
    let scene_path = resolve(&root, &manifest, &scene_arg);

    // Render configuration.
    let width = number("PICOMIS_WIDTH")?.unwrap_or(board.width);
    let height = number("PICOMIS_HEIGHT")?.unwrap_or(board.height);
    if !(1..=4096).contains(&width) || !(1..=4096).contains(&height) {
        return Err(format!("film {width}x{height}: each side must be 1..=4096").into());
    }
    // The scene module: the scene built for this film as an image, the settings as constants
    // and the strategy types they name (`PICOMIS_PRESET`: a preset's settings instead of the
    // file's block). The same generator a user's build script calls.
    let preset = picomis_format::build::preset_from_env()?;
    let firmware = picomis_format::build::Firmware {
        preset,
        spp: number("PICOMIS_SPP")?,
        seed: number("PICOMIS_SEED")?,
        module_file: "scene.rs".into(),
        ..picomis_format::build::Firmware::new(&scene_path, width, height)
    };
    firmware.generate().map_err(|e| e.to_string())?;
    let tile = number("PICOMIS_TILE")?.unwrap_or(16).max(1);
    let repeat = number("PICOMIS_MEASURE_REPEAT")?.unwrap_or(3).max(1);
    let out_file = var("PICOMIS_OUT").unwrap_or_else(|| "picomis-fb.rgb565".into());
    if out_file.contains('\0') {
        return Err("PICOMIS_OUT contains a NUL byte".into());
    }
    let mut c = String::new();
    writeln!(c, "// Generated by firmware/build.rs. Do not edit.")?;
    writeln!(c, "/// Board the firmware was built for.\npub const BOARD: &str = {:?};", board.name)?;
    writeln!(
        c,
        "/// QEMU machine emulating the board.\npub const QEMU_MACHINE: &str = {:?};",
        board.qemu_machine
    )?;
    writeln!(c, "/// Scene file the scene was generated from.\npub const SCENE_FILE: &str = {scene_arg:?};")?;
    writeln!(c, "/// Film and framebuffer width.\npub const WIDTH: u32 = {width};")?;
    writeln!(c, "/// Film and framebuffer height.\npub const HEIGHT: u32 = {height};")?;
    writeln!(c, "/// Film width as usize (framebuffer type).\npub const W: usize = {width};")?;
    writeln!(c, "/// Film height as usize (framebuffer type).\npub const H: usize = {height};")?;
    writeln!(c, "/// Tile side in pixels.\npub const TILE: u32 = {tile};")?;
    writeln!(
        c,
        "/// Renders of the film per measurement.\n#[allow(dead_code)]\npub const MEASURE_REPEAT: u32 = {repeat};"
    )?;
    let mut path = out_file.into_bytes();
    path.push(0);
    writeln!(
        c,
        "/// Host file (NUL-terminated) the framebuffer is written to under QEMU.\n#[allow(dead_code)]\npub const OUT_PATH: &[u8] = &{path:?};"
    )?;
    fs::write(out.join("config.rs"), c)?;
    Ok(())
}

/// A scene path: absolute, or relative to the workspace root, or else to firmware/.
fn resolve(root: &Path, manifest: &Path, p: &str) -> PathBuf {
    let p = Path::new(p);
    if p.is_absolute() || root.join(p).exists() || !manifest.join(p).exists() {
        root.join(p)
    } else {
        manifest.join(p)
    }
}
