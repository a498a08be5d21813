//! The arithmetic of the scene's ray queries: f32 (the default, every target) or fixed point
//! (`kernel/src/query/fixed.rs`, feature `fixed`), for cores without an FPU. Shading stays f32 either
//! way; only the ray queries dispatch on it, so the estimator is written once. The type itself is
//! always there (a study method names its arithmetic, the host's `picomis_host::study::Extras`); a scene runs in
//! fixed point only with the feature (`Scene::enable_arith`).

crate::choices! {
    /// The number type of the scene's ray queries.
    pub enum Arith: "arithmetic" {
        /// IEEE single precision (soft-float calls on cores without an FPU).
        F32 = "f32", "IEEE single precision";
        /// Integers at a scale chosen from the scene's extent (`query/fixed.rs`): the same bits
        /// on every machine.
        Fixed = "fixed", "integers at a scale chosen from the scene's extent, as on FPU-less cores";
    }
}
