//! What firmware/budget.json holds: the cores, their figures, and each figure's stated target.
//! Every other part of the budget asks these definitions.

use std::fmt;

/// A rise above budget.json by more than this many percent fails the budget check.
pub const TOLERANCE_PERCENT: u32 = 2;
/// The best settings' (the defaults') flash text target, bytes (the lecture settings' is per
/// core: [`Core::lecture_flash_target`]).
pub const TARGET_FLASH: u32 = 32768;
/// Static RAM besides the framebuffer, bytes.
pub const TARGET_RAM: u32 = 4096;
/// Peak stack, bytes.
pub const TARGET_STACK: u32 = 4096;

/// A core the firmware is measured on.
#[derive(Debug, PartialEq, Eq)]
pub struct Core {
    /// The key prefix in budget.json (`m4f_...`).
    pub key: &'static str,
    /// The table's column name.
    pub name: &'static str,
    /// The instructions-per-camera-sample target.
    pub instructions_target: u32,
    /// The lecture settings' flash text target, bytes.
    pub lecture_flash_target: u32,
    /// Whether the core has a fixed-point build (feature `fixed`; the cores without an FPU): its
    /// instructions per camera sample are a budget too, and the target is held against it rather
    /// than against the f32 build.
    pub fixed: bool,
}

/// The cores, in the table's (and budget.json's) order.
pub static CORES: [Core; 3] = [
    Core {
        key: "m4f",
        name: "Cortex-M4F",
        instructions_target: 2000,
        lecture_flash_target: 28672,
        fixed: false,
    },
    Core {
        key: "m0",
        name: "Cortex-M0",
        instructions_target: 20000,
        lecture_flash_target: 32768,
        fixed: true,
    },
    Core {
        key: "rv32imc",
        name: "RV32IMC",
        instructions_target: 20000,
        lecture_flash_target: 32768,
        fixed: true,
    },
];

/// One measured figure of a core.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// Instructions per camera sample, the lecture's strategies (PICOMIS_PRESET=lecture).
    Instructions,
    /// Flash text of the board build, the lecture's strategies, bytes.
    FlashText,
    /// Rodata of the board build, the lecture's strategies, bytes (reported, not a budget).
    Rodata,
    /// Static RAM besides the framebuffer, bytes.
    StaticRam,
    /// Peak stack of the QEMU build, bytes.
    PeakStack,
    /// Instructions per camera sample of the fixed-point build.
    FixedInstructions,
    /// Instructions per camera sample, the best preset (the defaults).
    BestInstructions,
    /// Flash text of the board build, the best preset, bytes.
    BestFlashText,
    /// Instructions per camera sample, the best preset built for size (profile firmware-small).
    BestSmallInstructions,
    /// Flash text of the board build, the best preset built for size, bytes.
    BestSmallFlashText,
}

use Figure::*;

/// The lecture settings' figures of every core, in budget.json's order.
const LECTURE: [Figure; 5] = [Instructions, FlashText, Rodata, StaticRam, PeakStack];
/// The best preset's figures of every core: built for speed, then for size.
const BEST: [Figure; 4] = [BestInstructions, BestFlashText, BestSmallInstructions, BestSmallFlashText];

impl Figure {
    /// The key's part after the core's prefix.
    pub fn suffix(self) -> &'static str {
        match self {
            Instructions => "instructions_per_camera_sample",
            FlashText => "flash_text_bytes",
            Rodata => "rodata_bytes",
            StaticRam => "static_ram_bytes",
            PeakStack => "peak_stack_bytes",
            FixedInstructions => "fixed_instructions_per_camera_sample",
            BestInstructions => "best_instructions_per_camera_sample",
            BestFlashText => "best_flash_text_bytes",
            BestSmallInstructions => "best_small_instructions_per_camera_sample",
            BestSmallFlashText => "best_small_flash_text_bytes",
        }
    }

    /// Whether a rise of the figure fails the budget check (all but rodata).
    pub fn is_budget(self) -> bool {
        self != Rodata
    }

    /// The figure's stated target on `core`, if it has one: instructions per camera sample (the
    /// fixed-point build's on the cores that have one, whose f32 build is not held to it; every
    /// core's best preset built for speed), flash text (the lecture settings' per core, the best
    /// settings' [`TARGET_FLASH`] built either way), static RAM, peak stack. The build for size
    /// trades instructions for flash: its instructions are a budget without a target.
    pub fn target(self, core: &Core) -> Option<u32> {
        match self {
            Instructions => (!core.fixed).then_some(core.instructions_target),
            FixedInstructions | BestInstructions => Some(core.instructions_target),
            FlashText => Some(core.lecture_flash_target),
            BestFlashText | BestSmallFlashText => Some(TARGET_FLASH),
            StaticRam => Some(TARGET_RAM),
            PeakStack => Some(TARGET_STACK),
            Rodata | BestSmallInstructions => None,
        }
    }
}

/// One figure of one core: a key of budget.json (`m0_flash_text_bytes`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    pub core: &'static Core,
    pub figure: Figure,
}

impl Key {
    /// The key's stated target, if it has one ([`Figure::target`]).
    pub fn target(self) -> Option<u32> {
        self.figure.target(self.core)
    }
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}_{}", self.core.key, self.figure.suffix())
    }
}

/// Every figure key of budget.json, in the file's order: each core's lecture figures, the
/// fixed-point builds', each core's best preset figures.
pub fn written_keys() -> Vec<Key> {
    let lecture = CORES.iter().flat_map(|core| LECTURE.map(|figure| Key { core, figure }));
    let fixed = CORES.iter().filter(|core| core.fixed).map(|core| Key { core, figure: FixedInstructions });
    let best = CORES.iter().flat_map(|core| BEST.map(|figure| Key { core, figure }));
    lecture.chain(fixed).chain(best).collect()
}

/// The keys the budget check compares, in its order.
pub fn budget_keys() -> Vec<Key> {
    written_keys().into_iter().filter(|key| key.figure.is_budget()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(keys: &[Key]) -> Vec<String> {
        keys.iter().map(Key::to_string).collect()
    }

    #[test]
    fn keys_in_budget_json_order() {
        let keys = names(&written_keys());
        assert_eq!(keys.len(), 3 * 5 + 2 + 3 * 4);
        assert_eq!(keys[0], "m4f_instructions_per_camera_sample");
        assert_eq!(keys[14], "rv32imc_peak_stack_bytes");
        assert_eq!(
            keys[15..17],
            ["m0_fixed_instructions_per_camera_sample", "rv32imc_fixed_instructions_per_camera_sample"]
        );
        assert_eq!(
            keys[17..21],
            [
                "m4f_best_instructions_per_camera_sample",
                "m4f_best_flash_text_bytes",
                "m4f_best_small_instructions_per_camera_sample",
                "m4f_best_small_flash_text_bytes"
            ]
        );
        assert_eq!(keys[28], "rv32imc_best_small_flash_text_bytes");
        let budgets = names(&budget_keys());
        assert_eq!(budgets.len(), keys.len() - 3);
        assert!(budgets.iter().all(|key| !key.ends_with("rodata_bytes")));
    }

    #[test]
    fn targets() {
        let target = |core: usize, figure| Key { core: &CORES[core], figure }.target();
        assert_eq!(target(0, Instructions), Some(2000));
        // The cores with a fixed-point build hold its instructions to the target, not f32's.
        assert_eq!(target(1, Instructions), None);
        assert_eq!(target(1, FixedInstructions), Some(20000));
        assert_eq!(target(2, BestInstructions), Some(20000));
        assert_eq!(target(0, FlashText), Some(28672));
        assert_eq!(target(0, BestFlashText), Some(TARGET_FLASH));
        assert_eq!(target(1, BestSmallFlashText), Some(TARGET_FLASH));
        assert_eq!(target(1, BestSmallInstructions), None);
        assert_eq!(target(2, StaticRam), Some(TARGET_RAM));
        assert_eq!(target(2, PeakStack), Some(TARGET_STACK));
        assert_eq!(target(0, Rodata), None);
    }
}
