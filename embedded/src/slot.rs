//! The scene in static memory: a `static` that starts as [`Scene::EMPTY`] (no code runs to
//! build it, and it is never on the stack) and is filled in place, once.

use core::cell::{Cell, UnsafeCell};

use critical_section::Mutex;
use picomis::{Scene, SceneError};

/// Why [`SceneSlot::load`] gave no scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LoadError {
    /// The slot was loaded before (a slot is loaded once).
    Taken,
    /// The scene could not be loaded (e.g. its image does not hold a scene of these
    /// capacities), or with the `fixed` feature, the fixed-point format cannot represent it.
    Scene(SceneError),
}

impl From<SceneError> for LoadError {
    fn from(e: SceneError) -> Self {
        LoadError::Scene(e)
    }
}

impl core::fmt::Display for LoadError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LoadError::Taken => f.write_str("the scene slot was loaded before"),
            LoadError::Scene(e) => write!(f, "{e}"),
        }
    }
}

/// A place for one scene in static memory, loaded once.
///
/// ```ignore
/// static SCENE: SceneSlot<scene::SceneT> = SceneSlot::new();
/// let scene: &'static scene::SceneT = SCENE.load(scene::load)?;
/// ```
pub struct SceneSlot<T> {
    scene: UnsafeCell<T>,
    taken: Mutex<Cell<bool>>,
}

// SAFETY: the scene is reached only through `load`, which hands out the one `&mut` once (the
// flag is tested and set in a critical section) and shared references after it; `T: Send`
// because the loading context may differ from the one that declared the static.
unsafe impl<T: Send + Sync> Sync for SceneSlot<T> {}

impl<const S: usize, const L: usize, const M: usize> SceneSlot<Scene<S, L, M>> {
    /// An empty slot (for a `static`: [`Scene::EMPTY`] is a constant, so no code builds it).
    pub const fn new() -> Self {
        SceneSlot { scene: UnsafeCell::new(Scene::EMPTY), taken: Mutex::new(Cell::new(false)) }
    }

    /// Fills the scene in place with `fill` (the generated module's `load`, which reads the
    /// scene's image) and returns it for the rest of the program. With the `fixed` feature the
    /// ray queries then run in fixed point. A slot is loaded once: a second call is
    /// [`LoadError::Taken`], even when the first one failed.
    pub fn load(
        &'static self,
        fill: impl FnOnce(&mut Scene<S, L, M>) -> Result<(), SceneError>,
    ) -> Result<&'static Scene<S, L, M>, LoadError> {
        if critical_section::with(|cs| self.taken.borrow(cs).replace(true)) {
            return Err(LoadError::Taken);
        }
        // SAFETY: the flag was clear, so no reference to the scene exists and none will be made
        // again but through this one.
        let scene = unsafe { &mut *self.scene.get() };
        fill(scene)?;
        #[cfg(feature = "fixed")]
        scene.enable_arith(picomis::Arith::Fixed)?;
        Ok(scene)
    }
}

impl<const S: usize, const L: usize, const M: usize> Default for SceneSlot<Scene<S, L, M>> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slot_is_loaded_once() {
        static SLOT: SceneSlot<Scene<2, 1, 2>> = SceneSlot::new();
        let mut calls = 0;
        let scene = SLOT.load(|_| {
            calls += 1;
            Ok(())
        });
        assert!(scene.is_ok());
        assert_eq!(
            SLOT.load(|_| {
                calls += 1;
                Ok(())
            })
            .err(),
            Some(LoadError::Taken)
        );
        assert_eq!(calls, 1, "the second load must not touch the scene");
    }

    #[test]
    fn a_failed_fill_is_reported_and_the_slot_stays_taken() {
        static SLOT: SceneSlot<Scene<2, 1, 2>> = SceneSlot::new();
        assert_eq!(
            SLOT.load(|_| Err(SceneError::BadImage)).err(),
            Some(LoadError::Scene(SceneError::BadImage))
        );
        assert_eq!(SLOT.load(|_| Ok(())).err(), Some(LoadError::Taken));
    }

    #[test]
    fn the_generated_loader_fills_the_scene_from_its_image() {
        // A scene image as a build script writes it, loaded the way a firmware does.
        static SLOT: SceneSlot<Scene<2, 1, 2>> = SceneSlot::new();
        let built = crate::draw::tests::scene();
        let mut words = [0u32; 4096];
        let mut n = 0;
        built.write_image(&mut |w| {
            words[n] = w;
            n += 1;
        });
        let loaded = SLOT.load(|s| s.load_image(&words[..n])).expect("the image loads");
        assert_eq!(loaded.film(), built.film());
        assert_eq!(loaded.objects().len(), built.objects().len());
        assert_eq!(loaded.lights().len(), built.lights().len());
    }
}
