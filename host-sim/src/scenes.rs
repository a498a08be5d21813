//! Scenes: the built-in ones (every `picomis-scene/1` file in the workspace's `scenes/`, listed
//! by the `picomis-builtins` crate) and files, loaded and built as the host's one scene type,
//! [`HostScene`] (room for [`HOST_SHAPES`] shapes, [`HOST_LIGHTS`] lights and
//! [`HOST_MATERIALS`] materials); a file with more objects is rejected with "too many shapes for
//! this build", naming the file and the entry.

use std::path::Path;

use picomis::Film;
use picomis_format::{LoadError, SceneFile};
pub use picomis_host::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene};

use crate::SimError;

pub use picomis_builtins::{BUILTINS, Builtin};

/// The built-in scene called `name`.
pub fn find_builtin(name: &str) -> Option<&'static Builtin> {
    picomis_builtins::find(name)
}

/// The built-in scene used when no scene is named.
pub const DEFAULT_SCENE: &str = "veach_mis";

/// A loaded scene file and, for a built-in scene, its name.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The validated file.
    pub file: SceneFile,
    /// The built-in scene it is, if any.
    pub builtin: Option<&'static str>,
}

impl Loaded {
    /// Builds the kernel scene for `film`.
    pub fn build(&self, film: Film) -> Result<HostScene, LoadError> {
        self.file.build_with_film(film)
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

    #[test]
    fn builtins_are_built_with_every_object() {
        assert!(BUILTINS.len() >= 5);
        for b in BUILTINS {
            let loaded = load(Some(b.name)).unwrap();
            assert_eq!(loaded.builtin, Some(b.name));
            let c = loaded.file.counts();
            // The generated list holds picomis-format's counts.
            assert_eq!((c.shapes, c.lights, c.materials), (b.shapes, b.lights, b.materials), "{}", b.name);
            let scene = loaded.build(loaded.file.film()).unwrap();
            let built = (scene.objects().len(), scene.lights().len(), scene.materials().len());
            assert_eq!(built, (b.shapes, b.lights, b.materials), "{}", b.name);
            assert_eq!(loaded.file.name(), b.name);
        }
    }

    #[test]
    fn files_load_like_builtins() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v.json");
        std::fs::write(&path, find_builtin("veach_mis").unwrap().json).unwrap();
        let loaded = load(path.to_str()).unwrap();
        assert_eq!(loaded.builtin, None);
        assert_eq!(loaded.build(loaded.file.film()).unwrap().objects().len(), 11);
    }

    #[test]
    fn unknown_names_are_errors() {
        let e = load(Some("no_such_scene")).unwrap_err();
        assert!(e.to_string().starts_with("no_such_scene: file: no such file"), "{e}");
    }
}
