//! Entry point: load the scene, render it progressively into the static framebuffer, log
//! statistics, and (under QEMU) hand the framebuffer to the host and exit with a status. What
//! build.rs generated is in `board.rs`; panics and faults are `fault.rs`. The scene slot and the
//! tile-by-tile draw are picomis-embedded's, as on the boards (`boards/`).

use core::ptr;

use embedded_graphics::prelude::*;
use picomis_embedded::{LoadError, SceneSlot};

use crate::board::{FB_BYTES, Fb, config, scene};
use crate::status;
use crate::{arch, clock, stack};

/// The framebuffer, in .bss.
static mut FRAMEBUFFER: Fb = Fb::new();

#[cfg_attr(target_arch = "arm", cortex_m_rt::entry)]
#[cfg_attr(target_arch = "riscv32", riscv_rt::entry)]
fn main() -> ! {
    let code = if cfg!(feature = "softfloat-check") { crate::fpcheck::run() } else { run() };
    finish(code)
}

#[cfg(feature = "qemu")]
fn finish(code: u32) -> ! {
    crate::semihosting::exit(code)
}

#[cfg(not(feature = "qemu"))]
fn finish(code: u32) -> ! {
    info!("picomis: finished with status {}", code);
    arch::halt()
}

/// FNV-1a over the framebuffer bytes, logged so runs can be compared without the file.
fn fnv1a(data: &[u8]) -> u32 {
    data.iter().fold(0x811c_9dc5u32, |h, &b| (h ^ u32::from(b)).wrapping_mul(0x0100_0193))
}

/// The scene, in static memory rather than on the stack.
static SCENE: SceneSlot<scene::SceneT> = SceneSlot::new();

/// Loads the scene into [`SCENE`] from its image (`scene::IMAGE`, built by build.rs on the host:
/// the firmware carries none of the code that builds a scene); with `fixed`, the ray queries in
/// fixed point (the copies of the shapes are filled inside the scene). Not inlined: the stack
/// peak of the load is measured on its own.
#[inline(never)]
fn load_scene() -> Result<&'static scene::SceneT, LoadError> {
    SCENE.load(scene::load)
}

fn run() -> u32 {
    stack::init();
    arch::init();
    info!(
        "picomis-firmware: board {} (QEMU {}), scene {} from {}",
        config::BOARD,
        config::QEMU_MACHINE,
        scene::NAME,
        config::SCENE_FILE
    );
    #[cfg(feature = "fixed")]
    info!("ray queries in fixed point (feature fixed)");
    let scene = match load_scene() {
        Ok(s) => s,
        Err(_e) => {
            #[cfg(feature = "fixed")]
            if let LoadError::Scene(picomis::SceneError::NotRepresentable { entry, reason }) = _e {
                info!(
                    "error: fixed point cannot represent shape {} of scene {}: {}",
                    u32::from(entry),
                    scene::NAME,
                    reason.as_str()
                );
                return status::NOT_REPRESENTABLE;
            }
            info!("error: scene {} could not be loaded from its image", scene::NAME);
            #[cfg(feature = "rtt")]
            defmt::error!("scene error: {}", _e);
            return status::SCENE;
        }
    };
    let settings = &scene::SETTINGS;
    info!(
        "film {}x{}, {} spp, seed {}, {} shapes, {} lights, {} materials, tiles {}x{}",
        config::WIDTH,
        config::HEIGHT,
        settings.spp(),
        settings.seed(),
        scene.objects().len(),
        scene.lights().len(),
        scene.materials().len(),
        config::TILE,
        config::TILE
    );
    #[cfg(feature = "rtt")]
    defmt::info!("settings: {}", settings);
    let Ok(integrator) = scene::integrator(scene) else {
        info!("error: the settings do not name the strategies the firmware was built with");
        return status::SETTINGS;
    };

    // Peak stack of the scene load, then start over for the render and what follows.
    let (build_peak, _) = stack::peak();
    info!(
        "stack peak of the scene load: {} bytes (scene {} bytes, in .bss)",
        build_peak,
        core::mem::size_of::<scene::SceneT>() as u32
    );
    stack::repaint();

    // SAFETY: `main` runs once and is the only code touching the framebuffer.
    let fb: &mut Fb = unsafe { &mut *ptr::addr_of_mut!(FRAMEBUFFER) };
    let start = clock::ticks();
    let tile = Size::new(config::TILE, config::TILE);
    // (With `rtt`, picomis-embedded logs the progress itself, at debug level.)
    let Ok(stats) = picomis_embedded::draw(&integrator, tile, fb, |_progress| {
        #[cfg(not(feature = "rtt"))]
        info!(
            "progress: rows 0..{} of {}, {} pixels",
            _progress.rows, _progress.height, _progress.stats.pixels
        );
    });
    let ticks = clock::ticks() - start;
    info!(
        "rendered {} pixels, {} camera samples in {} SysTick ticks ({} per camera sample)",
        stats.pixels,
        stats.camera_samples,
        ticks,
        // u32 division: u64 division is a library call.
        u32::try_from(ticks).unwrap_or(u32::MAX)
            / u32::try_from(stats.camera_samples).unwrap_or(u32::MAX).max(1)
    );
    #[cfg(feature = "rtt")]
    defmt::info!("stats: {}", stats);
    info!("framebuffer: {} bytes, fnv1a {}", FB_BYTES as u32, fnv1a(fb.data()));

    #[cfg(feature = "qemu")]
    {
        let path = config::OUT_PATH;
        let name = core::str::from_utf8(&path[..path.len() - 1]).unwrap_or("?");
        if crate::semihosting::write_file(path, fb.data()).is_err() {
            info!("error: could not write {} on the host", name);
            return status::HOST_FILE;
        }
        info!("framebuffer written to host file {}", name);
    }

    #[cfg(feature = "qemu")]
    crate::digest::report(&integrator);

    #[cfg(feature = "measure")]
    crate::measure::run(&integrator, fb);

    let (render_peak, size) = stack::peak();
    info!(
        "stack peak: {} of {} bytes (scene load {}, render and output {})",
        build_peak.max(render_peak),
        size,
        build_peak,
        render_peak
    );
    status::OK
}
