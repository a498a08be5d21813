//! The arithmetic of the scene's ray queries: f32 (the default, every target) or fixed point
//! (`kernel/src/fixed.rs`, feature `fixed`), for cores without an FPU. Shading stays f32 either
//! way; only the ray queries dispatch on it, so the estimator is written once. The type itself is
//! always there (a study method names its arithmetic, [`crate::study::Extras`]); a scene runs in
//! fixed point only with the feature (`Scene::enable_arith`).

/// The number type of the scene's ray queries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Arith {
    /// IEEE single precision (soft-float calls on cores without an FPU).
    #[default]
    F32,
    /// Integers at a scale chosen from the scene's extent (`kernel/src/fixed.rs`): the same bits
    /// on every machine.
    Fixed,
}

impl Arith {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Arith::F32 => "f32",
            Arith::Fixed => "fixed",
        }
    }

    /// The arithmetic named `name` (`f32` or `fixed`).
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "f32" => Some(Arith::F32),
            "fixed" => Some(Arith::Fixed),
            _ => None,
        }
    }
}
