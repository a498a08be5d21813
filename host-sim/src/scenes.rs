//! Built-in scenes and the choice of kernel capacities.
//!
//! Each built-in scene (a `picomis-scene/1` file in the workspace's `scenes/`, listed with its
//! object counts by the `picomis-builtins` crate) is built as `Scene<S, L, M>` with its own
//! counts, exactly as a firmware build of that scene would be. Any other file is built with
//! the host capacities [`HOST_SHAPES`], [`HOST_LIGHTS`] and [`HOST_MATERIALS`]; a file with more
//! objects is rejected with "too many shapes for this build", naming the file and the entry.

use std::path::Path;

use picomis::{Film, Scene};
use picomis_format::{LoadError, SceneFile};

use crate::SimError;

/// Shapes a user scene file may hold in this build.
pub const HOST_SHAPES: usize = 64;
/// Lights (area emitters plus point lights) a user scene file may hold in this build.
pub const HOST_LIGHTS: usize = 32;
/// Materials a user scene file may hold in this build.
pub const HOST_MATERIALS: usize = 32;

pub use picomis_builtins::{BUILTINS, Builtin};

/// Does something with a kernel scene of any capacity (the capacities are chosen by
/// [`dispatch`]; a closure cannot be generic over them).
pub trait SceneVisitor {
    /// What the visit returns.
    type Output;
    /// Uses `scene`.
    fn visit<const S: usize, const L: usize, const M: usize>(self, scene: Scene<S, L, M>) -> Self::Output;
}

/// Builds `file` for `film` with the capacities of built-in scene `builtin` (its own counts), or
/// with the host capacities for any other file, and hands it to `visitor`.
pub fn dispatch<V: SceneVisitor>(
    builtin: Option<&str>,
    file: &SceneFile,
    film: Film,
    visitor: V,
) -> Result<V::Output, LoadError> {
    picomis_builtins::with_builtin_capacities!(
        builtin.unwrap_or(""),
        <S, L, M> => Ok(visitor.visit(file.build_with_film::<S, L, M>(film)?)),
        _ => Ok(visitor.visit(file.build_with_film::<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>(film)?))
    )
}

/// The built-in scene called `name`.
pub fn find_builtin(name: &str) -> Option<&'static Builtin> {
    picomis_builtins::find(name)
}

/// The built-in scene used when no scene is named.
pub const DEFAULT_SCENE: &str = "veach_mis";

/// A loaded scene file and, for a built-in scene, its name (which selects its capacities).
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The validated file.
    pub file: SceneFile,
    /// The built-in scene it is, if any.
    pub builtin: Option<&'static str>,
}

impl Loaded {
    /// Builds the kernel scene for `film` with the right capacities and hands it to `visitor`.
    pub fn visit<V: SceneVisitor>(&self, film: Film, visitor: V) -> Result<V::Output, LoadError> {
        dispatch(self.builtin, &self.file, film, visitor)
    }
}

/// Resolves the SCENE argument: a path to a scene file, or the name of a built-in scene (the
/// Veach scene when absent). An argument that looks like a path (it has a `/` or ends in
/// `.json`) is always a file; otherwise a built-in name wins over a file of that name.
pub fn load(scene: Option<&str>) -> Result<Loaded, SimError> {
    let arg = scene.unwrap_or(DEFAULT_SCENE);
    let looks_like_path =
        arg.contains(std::path::MAIN_SEPARATOR) || arg.contains('/') || arg.ends_with(".json");
    if !looks_like_path {
        if let Some(b) = find_builtin(arg) {
            let file = SceneFile::parse(b.json, b.name)?;
            return Ok(Loaded { file, builtin: Some(b.name) });
        }
        if !Path::new(arg).exists() {
            let names: Vec<&str> = BUILTINS.iter().map(|b| b.name).collect();
            return Err(SimError::Load(LoadError {
                file: arg.into(),
                entry: "file".into(),
                reason: format!(
                    "no such file, and no built-in scene of that name (built-in: {})",
                    names.join(", ")
                ),
            }));
        }
    }
    let file = SceneFile::load(Path::new(arg))?;
    Ok(Loaded { file, builtin: None })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Capacities;
    impl SceneVisitor for Capacities {
        type Output = (usize, usize, usize, usize, usize, usize);
        fn visit<const S: usize, const L: usize, const M: usize>(
            self,
            scene: Scene<S, L, M>,
        ) -> Self::Output {
            (S, L, M, scene.objects().len(), scene.lights().len(), scene.materials().len())
        }
    }

    #[test]
    fn builtins_are_built_with_exactly_their_own_counts() {
        assert!(BUILTINS.len() >= 5);
        for b in BUILTINS {
            let loaded = load(Some(b.name)).unwrap();
            assert_eq!(loaded.builtin, Some(b.name));
            let c = loaded.file.counts();
            // The generated list holds picomis-format's counts.
            assert_eq!((c.shapes, c.lights, c.materials), (b.shapes, b.lights, b.materials), "{}", b.name);
            let film = loaded.file.film();
            let (s, l, m, ns, nl, nm) = loaded.visit(film, Capacities).unwrap();
            assert_eq!((s, l, m), (b.shapes, b.lights, b.materials), "{}", b.name);
            assert_eq!((ns, nl, nm), (s, l, m), "{}: every slot is used", b.name);
            assert_eq!(loaded.file.name(), b.name);
        }
    }

    #[test]
    fn files_get_the_host_capacities() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v.json");
        std::fs::write(&path, find_builtin("veach_mis").unwrap().json).unwrap();
        let loaded = load(path.to_str()).unwrap();
        assert_eq!(loaded.builtin, None);
        let (s, l, m, ns, ..) = loaded.visit(loaded.file.film(), Capacities).unwrap();
        assert_eq!((s, l, m, ns), (HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS, 11));
    }

    #[test]
    fn unknown_names_are_errors() {
        let e = load(Some("no_such_scene")).unwrap_err();
        assert!(e.to_string().starts_with("no_such_scene: file: no such file"), "{e}");
    }
}
