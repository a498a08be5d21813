//! # picomis-builtins
//!
//! The built-in scenes, the one list of them: every `picomis-scene/1` file in the workspace's
//! `scenes/` folder, embedded, with the kernel capacities it needs (its own object counts, as a
//! firmware build of it uses). The list and the [`with_builtin_capacities!`] dispatch are
//! generated at build time by picomis-format from the files themselves, so nothing here is
//! counted or listed by hand. The simulator, the benchmarks and the tests all read it.
//!
//! ```
//! let names: Vec<&str> = picomis_builtins::BUILTINS.iter().map(|b| b.name).collect();
//! assert!(names.contains(&"veach_mis"));
//! let capacities = picomis_builtins::with_builtin_capacities!("veach_mis", <S, L, M> => (S, L, M));
//! assert_eq!(capacities, Some((11, 5, 6)));
//! ```
#![no_std]
#![deny(missing_docs)]

/// A built-in scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Builtin {
    /// Name (the file's `name`, which is also its file stem).
    pub name: &'static str,
    /// The scene file's text.
    pub json: &'static str,
    /// The file's description.
    pub description: &'static str,
    /// Shapes: the scene's shape capacity.
    pub shapes: usize,
    /// Area emitters plus point lights: the scene's light capacity.
    pub lights: usize,
    /// Materials: the scene's material capacity.
    pub materials: usize,
}

include!(concat!(env!("OUT_DIR"), "/builtins.rs"));

/// The built-in scene called `name`.
pub fn find(name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|b| b.name == name)
}
