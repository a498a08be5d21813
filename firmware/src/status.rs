//! Exit statuses under QEMU (`scripts/firmware.sh` reads them).

/// Rendered and written to the host.
pub const OK: u32 = 0;
/// The scene could not be loaded from its image.
pub const SCENE: u32 = 3;
/// The settings could not be built.
pub const SETTINGS: u32 = 4;
/// The framebuffer could not be written to the host.
#[allow(dead_code)]
pub const HOST_FILE: u32 = 5;
/// The fixed-point format cannot represent the scene (feature `fixed`; the log names the shape).
#[allow(dead_code)]
pub const NOT_REPRESENTABLE: u32 = 7;
/// Panic.
#[allow(dead_code)]
pub const PANIC: u32 = 101;
/// HardFault.
#[allow(dead_code)]
pub const HARD_FAULT: u32 = 102;
