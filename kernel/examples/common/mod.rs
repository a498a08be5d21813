//! The scene both examples render: a floor, a back wall, a glossy ball, a small sphere light and
//! a quad light in the ceiling, with the strategies of `Preset::Best`.

use picomis::integrator::{control_variate, model};
use picomis::light::{lobe, quad, select, sphere};
use picomis::{
    CameraDesc, Direct, Film, FovAxis, Integrator, Lights, Material, Rgb, Scene, SceneError, Shape, Vec3,
};

/// Room for the scene: shapes, lights, materials (checked when they are added).
pub const SHAPES: usize = 5;
/// Lights.
pub const LIGHTS: usize = 2;
/// Materials.
pub const MATERIALS: usize = 3;

/// The scene's type: its storage is inside it, no heap.
pub type Demo = Scene<SHAPES, LIGHTS, MATERIALS>;

/// The strategies of `Preset::Best` (what `Preset::Best.settings()` names): lights chosen by
/// their estimated contribution, spheres sampled in their cone, quads in solid angle
/// (cosine-warped where the warp fits; by area where a Lambertian receiver sees them small and
/// steep), light samples also from glossy lobes, the control variate by its rule (by size in a
/// scene of one light), the multi-sample model.
pub type Best = Direct<
    Lights<select::ByContribution<LIGHTS>, sphere::InCone, quad::BySize, lobe::On>,
    control_variate::BySize,
    model::Multi,
>;

/// The estimator of a `Demo` scene with the strategies `Best`.
pub type DemoIntegrator<'a> = Integrator<'a, Best, SHAPES, LIGHTS, MATERIALS>;

/// The scene for a `width` x `height` film.
pub fn scene(width: u32, height: u32) -> Result<Demo, SceneError> {
    let camera = CameraDesc {
        origin: Vec3::new(0.0, 1.3, 4.5),
        target: Vec3::new(0.0, 0.8, 0.0),
        up: Vec3::Y,
        fov_deg: 45.0,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    };
    let mut scene = Demo::new(camera, Film::new(width, height)?)?;
    let white = scene.add_material(Material::lambertian(Rgb::splat(0.75))?)?;
    let gold = scene.add_material(Material::ggx_conductor(0.08, Rgb::new(0.95, 0.75, 0.35))?)?;
    let black = scene.add_material(Material::lambertian(Rgb::ZERO)?)?;

    // Quads are parallelograms given by their corners in order; the front side (the one that
    // reflects, and emits) is the one the normal (p1 - p0) x (p3 - p0) points to.
    let floor = [
        Vec3::new(-3.0, 0.0, 3.0),
        Vec3::new(3.0, 0.0, 3.0),
        Vec3::new(3.0, 0.0, -2.0),
        Vec3::new(-3.0, 0.0, -2.0),
    ];
    let wall = [
        Vec3::new(-3.0, 0.0, -2.0),
        Vec3::new(3.0, 0.0, -2.0),
        Vec3::new(3.0, 3.0, -2.0),
        Vec3::new(-3.0, 3.0, -2.0),
    ];
    scene.add_shape(Shape::quad(floor)?, white)?;
    scene.add_shape(Shape::quad(wall)?, white)?;
    scene.add_shape(Shape::sphere(Vec3::new(-0.6, 0.6, 0.0), 0.6)?, gold)?;

    // A small bright sphere light, and a larger, dimmer panel facing down.
    let bulb = scene.add_shape(Shape::sphere(Vec3::new(1.0, 1.5, 0.4), 0.15)?, black)?;
    scene.add_area_light(bulb, Rgb::new(40.0, 36.0, 30.0))?;
    let panel = [
        Vec3::new(-1.2, 2.8, -1.2),
        Vec3::new(-0.2, 2.8, -1.2),
        Vec3::new(-0.2, 2.8, -0.2),
        Vec3::new(-1.2, 2.8, -0.2),
    ];
    let panel = scene.add_shape(Shape::quad(panel)?, black)?;
    scene.add_area_light(panel, Rgb::new(3.0, 3.5, 4.5))?;
    Ok(scene)
}
