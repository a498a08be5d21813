//! Shared setup of the picomis Criterion benchmarks (`benches/`): the built-in scenes loaded
//! from `scenes/*.json` (built as the host's one scene type, [`HostScene`], whose estimator for
//! any settings is [`picomis_host::renderer`]), the methods under study, tables of random
//! numbers, and synthetic scenes for the scaling curves. Nothing here is timed; the benchmarks
//! time kernel calls only.
//!
//! Run them with `cargo bench -p picomis-bench` (a few minutes on 2 cores); one group with e.g.
//! `cargo bench -p picomis-bench --bench camera_sample -- veach_mis`.
#![deny(missing_docs)]

use std::time::Duration;

use picomis::{CameraDesc, Film, FovAxis, Material, RenderSettings, Rgb, Sampler, Scene, Shape, Vec2, Vec3};
use picomis_format::SceneFile;
pub use picomis_host::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene};

/// Criterion samples per benchmark (kept small: `cargo bench -p picomis-bench` takes minutes).
pub const SAMPLE_SIZE: usize = 20;
/// Criterion warm-up time per benchmark.
pub const WARM_UP: Duration = Duration::from_millis(300);
/// Criterion measurement time per benchmark.
pub const MEASUREMENT: Duration = Duration::from_millis(900);

/// The methods of the study (`picomis-sim study`), from the kernel's one list of them: the
/// benchmarks time exactly the list the study charts.
pub use picomis_host::study::{StudyMethod, study_methods as methods};

/// Settings of one camera sample of `m`: one light and one BSDF sample (as the built-in scenes'
/// integrator blocks ask), 1 spp.
pub fn settings(m: &StudyMethod) -> RenderSettings {
    m.settings(1, 1, 1, 0).expect("study methods have valid settings")
}

/// Every built-in scene file, sorted by name (the list of `picomis-builtins`).
pub fn builtin_scenes() -> Vec<SceneFile> {
    picomis_builtins::BUILTINS
        .iter()
        .map(|b| SceneFile::parse(b.json, b.name).unwrap_or_else(|e| panic!("{e}")))
        .collect()
}

/// Builds `file` as the host's scene (panics on a bad built-in scene: a bench setup error, not
/// user data).
pub fn host_scene(file: &SceneFile) -> HostScene {
    build::<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>(file)
}

/// Builds `file` with capacities `S`, `L`, `M` (for the benchmarks of typed kernel parts; panics
/// on a bad built-in scene).
pub fn build<const S: usize, const L: usize, const M: usize>(file: &SceneFile) -> Scene<S, L, M> {
    file.build::<S, L, M>().unwrap_or_else(|e| panic!("{e}"))
}

/// Visits pixels in a scrambled order (a stride coprime with the pixel count), so every run of
/// consecutive camera samples sees a representative mix of the image.
#[derive(Clone, Debug)]
pub struct PixelCycle {
    width: u32,
    pixels: u32,
    stride: u32,
    at: u32,
    sample: u32,
}

impl PixelCycle {
    /// A cycle over `film`'s pixels.
    pub fn new(film: Film) -> Self {
        let pixels = film.pixels();
        let mut stride = 7919 % pixels.max(1);
        while gcd(stride, pixels) != 1 {
            stride += 1;
        }
        Self { width: film.width(), pixels, stride: stride.max(1), at: 0, sample: 0 }
    }

    /// The next pixel `(x, y)` and its camera sample index.
    #[inline]
    pub fn next_pixel(&mut self) -> (u32, u32, u32) {
        let (p, sample) = (self.at, self.sample);
        self.at = (self.at + self.stride) % self.pixels;
        if self.at == 0 {
            self.sample = self.sample.wrapping_add(1);
        }
        (p % self.width, p / self.width, sample)
    }
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// A table of random inputs for the sampling routines, cycled by index.
#[derive(Clone, Debug)]
pub struct Inputs {
    /// Uniform points in [0, 1)^2.
    pub u: Vec<Vec2>,
    /// Uniform numbers in [0, 1).
    pub u1: Vec<f32>,
    /// Unit directions in the upper hemisphere (cosine-distributed), e.g. `wo`.
    pub wo: Vec<Vec3>,
    /// Unit directions in the upper hemisphere, independent of `wo`, e.g. `wi`.
    pub wi: Vec<Vec3>,
}

/// Entries in an [`Inputs`] table (a power of two: indices wrap with a mask).
pub const INPUTS: usize = 1024;

impl Inputs {
    /// A fixed table (seeded, the same on every run).
    pub fn new() -> Self {
        let mut s = Sampler::new(0xbe9c, 0, 0);
        let u: Vec<Vec2> = (0..INPUTS).map(|_| s.next_2d()).collect();
        let u1 = (0..INPUTS).map(|_| s.next_f32()).collect();
        let wo = (0..INPUTS).map(|_| picomis::sampling::sample_cosine_hemisphere(s.next_2d())).collect();
        let wi = (0..INPUTS).map(|_| picomis::sampling::sample_cosine_hemisphere(s.next_2d())).collect();
        Self { u, u1, wo, wi }
    }
}

impl Default for Inputs {
    fn default() -> Self {
        Self::new()
    }
}

/// Most shapes of a synthetic scaling scene (the host's capacity).
pub const SYNTH_SHAPES: usize = HOST_SHAPES;
/// Most lights of a synthetic scaling scene (its light slots).
pub const SYNTH_LIGHTS: usize = 16;
/// A synthetic scaling scene: a host scene, rendered with any settings by
/// [`picomis_host::renderer`].
pub type SynthScene = HostScene;

/// A synthetic scene: a diffuse floor quad; `visible` spheres on a 9 x 7 grid on the floor
/// (alternately diffuse and glossy); and `slots` small spheres on a 4 x 4 grid high above, out of
/// the camera's view, of which the first `lights` emit (the others are black). The emitted power
/// in total is the same for every `lights`, and the visible image does not depend on `slots` or
/// `lights` beyond its lighting. Needs `1 <= lights <= slots <= 16`, `visible <= 63` and
/// `1 + visible + slots <= 64`.
pub fn synthetic_scene(visible: usize, slots: usize, lights: usize) -> SynthScene {
    assert!(lights >= 1 && lights <= slots && slots <= SYNTH_LIGHTS && visible <= 63);
    assert!(1 + visible + slots <= SYNTH_SHAPES);
    let camera = CameraDesc {
        origin: Vec3::new(0.0, 6.0, 9.0),
        target: Vec3::new(0.0, 0.0, 0.0),
        up: Vec3::Y,
        fov_deg: 45.0,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    };
    let film = Film::new(96, 64).expect("valid film");
    let mut scene = SynthScene::new(camera, film).expect("valid camera");
    let diffuse = scene.add_material(Material::lambertian(Rgb::splat(0.6)).expect("albedo")).expect("room");
    let glossy =
        scene.add_material(Material::ggx_conductor(0.1, Rgb::splat(0.9)).expect("ggx")).expect("room");
    let black = scene.add_material(Material::lambertian(Rgb::ZERO).expect("albedo")).expect("room");
    let floor = [
        Vec3::new(-6.0, 0.0, 6.0),
        Vec3::new(6.0, 0.0, 6.0),
        Vec3::new(6.0, 0.0, -6.0),
        Vec3::new(-6.0, 0.0, -6.0),
    ];
    scene.add_shape(Shape::quad(floor).expect("quad"), diffuse).expect("room");
    for i in 0..visible {
        let (gx, gz) = ((i % 9) as f32 - 4.0, (i / 9) as f32 - 3.0);
        let shape = Shape::sphere(Vec3::new(gx * 1.2, 0.35, gz * 1.2), 0.3).expect("sphere");
        scene.add_shape(shape, if i % 2 == 0 { diffuse } else { glossy }).expect("room");
    }
    for i in 0..slots {
        let (gx, gz) = ((i % 4) as f32 - 1.5, (i / 4) as f32 - 1.5);
        let shape = Shape::sphere(Vec3::new(gx * 1.5, 5.0, gz * 1.5 - 1.0), 0.2).expect("sphere");
        let id = scene.add_shape(shape, black).expect("room");
        if i < lights {
            scene.add_area_light(id, Rgb::splat(400.0 / lights as f32)).expect("room");
        }
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_cycle_visits_every_pixel_once_per_round() {
        let film = Film::new(7, 5).unwrap();
        let mut c = PixelCycle::new(film);
        let mut seen = [0; 35];
        for _ in 0..35 {
            let (x, y, s) = c.next_pixel();
            assert_eq!(s, 0);
            seen[(y * 7 + x) as usize] += 1;
        }
        assert!(seen.iter().all(|&n| n == 1));
        assert_eq!(c.next_pixel().2, 1);
    }

    #[test]
    fn builtin_scenes_build_and_synthetic_scenes_hold_their_counts() {
        let scenes = builtin_scenes();
        assert!(scenes.len() >= 5);
        for f in &scenes {
            let scene = host_scene(f);
            let (s, l) = (scene.objects().len(), scene.lights().len());
            assert_eq!((s, l), (f.counts().shapes, f.counts().lights), "{}", f.name());
            // With their own counts as capacities too (a firmware's build), every slot used.
            let own = picomis_builtins::with_builtin_capacities!(f.name(), <S, L, M> => {
                let scene = build::<S, L, M>(f);
                (scene.objects().len(), scene.lights().len(), S, L)
            });
            assert_eq!(own, Some((s, l, s, l)), "{}", f.name());
        }
        let s = synthetic_scene(47, 16, 16);
        assert_eq!((s.objects().len(), s.lights().len()), (64, 16));
        let s = synthetic_scene(0, 1, 1);
        assert_eq!((s.objects().len(), s.lights().len()), (2, 1));
        // The high spheres are out of view: no camera ray through the film hits them.
        let s = synthetic_scene(0, 16, 16);
        for (i, j) in [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (0.0, 0.5), (1.0, 0.5)] {
            let (ray, _) = s.camera().ray(picomis::Vec2::new(i, j));
            assert!(s.intersect(&ray, 0.0, f32::INFINITY, None).is_none_or(|h| h.object.index() == 0));
        }
        assert!(methods().iter().any(|m| m.label == "balance"), "the study's baseline is benchmarked");
    }
}
