//! One emitting shape as the only light of a scene, its light sampler, and the shading points,
//! sphere and quad lights the tests of a light's own sampling share.

use picomis::light::select::Uniform;
use picomis::light::sphere::SphereSampler;
use picomis::light::{Lights, lobe, quad};
use picomis::{Film, LightId, LightSampler, Material, Rgb, Scene, ShadingPoint, Shape, SurfacePoint, Vec3};
use picomis_tests::{DVec3, camera, d3, f3, quad_corners};

/// A scene whose only light is one emitting shape.
type OneLightScene = Scene<1, 1, 1>;

/// The light of a [`OneLightScene`].
pub const LIGHT: LightId = LightId::new(0);

/// The light sampler of a [`OneLightScene`] drawing on spheres by `Sp` (quads by area, no lobe
/// mixing): a light's own sampling technique, `sample` / `pdf` of the one light.
pub type OneLightSampler<'a, Sp> = LightSampler<'a, Lights<Uniform, Sp, quad::ByArea, lobe::Off>, 1, 1, 1>;

/// An emitting shape (radiance 1) as the only light of a scene.
pub struct OneLight {
    scene: OneLightScene,
}

impl OneLight {
    pub fn new(shape: Shape) -> Self {
        let mut scene: OneLightScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
        let black = scene.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        let id = scene.add_shape(shape, black).unwrap();
        scene.add_area_light(id, Rgb::ONE).unwrap();
        OneLight { scene }
    }

    /// The emitting shape.
    pub fn shape(&self) -> &Shape {
        &self.scene.objects()[0].shape
    }

    /// The light's sampler drawing on spheres by `Sp`.
    pub fn sampler<Sp: SphereSampler>(&self) -> OneLightSampler<'_, Sp> {
        LightSampler::new(&self.scene)
    }
}

/// The shading point at `x` as the light sampler sees it: with spheres by area or cone, quads by
/// area and no lobe mixing, a light sample depends on its position alone.
pub fn at(x: Vec3) -> ShadingPoint {
    ShadingPoint { p: x, n: Vec3::Y, wo: Vec3::Y, bsdf: Material::lambertian(Rgb::ONE).unwrap() }
}

/// An emitting sphere as the only light of a scene, and its shape.
pub fn sphere_light(c: Vec3, r: f32) -> (OneLight, Shape) {
    let light = OneLight::new(Shape::sphere(c, r).unwrap());
    let shape = *light.shape();
    (light, shape)
}

/// Solid-angle pdf of a light's sampling technique at a direction from `x`, found as the kernel's
/// estimator finds it: trace the direction to the shape, then ask the sampler's `pdf` (0 on a
/// miss).
pub fn pdf_towards<Sp: SphereSampler>(
    lights: &OneLightSampler<'_, Sp>,
    shape: &Shape,
    x: Vec3,
    dir: DVec3,
) -> f64 {
    let ray = picomis::Ray { origin: x, dir: f3(dir.normalize()) };
    match shape.intersect(&ray, 0.0, f32::INFINITY) {
        Some(t) => {
            let p = ray.at(t);
            let y = SurfacePoint { p, n: shape.normal_at(p) };
            f64::from(lights.pdf(LIGHT, &at(x), &y))
        }
        None => 0.0,
    }
}

/// Point reached by a light sample: x + wi * distance (f64).
pub fn sample_point(x: Vec3, wi: Vec3, distance: f32) -> DVec3 {
    d3(x) + d3(wi) * f64::from(distance)
}

/// A shading point and a unit direction off every axis.
pub fn setup() -> (Vec3, Vec3) {
    (Vec3::new(0.3, -0.2, 0.1), Vec3::new(0.48, 0.8, -0.36).normalize())
}

/// A tilted parallelogram light facing the shading points of [`quad_points`], as the only light of
/// a scene, its shape and its corners.
pub fn quad_light() -> (OneLight, Shape, [Vec3; 4]) {
    let corners =
        quad_corners(Vec3::new(-0.6, 1.5, 0.8), Vec3::new(0.0, 0.3, -1.4), Vec3::new(1.1, 0.2, 0.1));
    let shape = Shape::quad(corners).unwrap();
    (OneLight::new(shape), shape, corners)
}

pub fn quad_points() -> [Vec3; 2] {
    [Vec3::new(0.1, 0.0, -0.2), Vec3::new(1.5, 0.5, 2.0)]
}
