//! The cases' scenes: a builder (a black material for the lights, a floor of a receiver,
//! sphere and quad lights), the receivers' materials, shading points and directions, and the
//! closed forms the cases share.

use crate::harness::S;
use picomis::{Film, Hit, Material, MaterialId, Ray, Rgb, Scene, Shape, Vec3};
use picomis_tests::{camera, d3, floor_corners, shading_hit, sphere_irradiance_at};
use std::f64::consts::PI;

/// Albedo of every Lambertian receiver (grey: channel 0 stands for all three).
pub const RHO: f32 = 0.8;
/// Reflectance of every GGX receiver.
pub const R_GGX: f32 = 0.9;

/// A case's scene being built, with the black material of its lights.
pub struct Setup {
    pub scene: Box<S>,
    black: MaterialId,
}

impl Setup {
    pub fn new() -> Self {
        let mut scene: Box<S> = Box::new(Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap());
        let black = scene.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        Setup { scene, black }
    }

    /// A scene whose object 0 is a floor (y = 0, facing +y, 100 x 100) of `receiver`.
    pub fn floor(receiver: Material) -> Self {
        let mut s = Setup::new();
        s.add(Shape::quad(floor_corners(50.0)).unwrap(), receiver);
        s
    }

    pub fn add(&mut self, shape: Shape, material: Material) -> usize {
        let m = self.scene.add_material(material).unwrap();
        self.scene.add_shape(shape, m).unwrap().index()
    }

    pub fn sphere_light(&mut self, c: Vec3, r: f32, radiance: f32) {
        let id = self.scene.add_shape(Shape::sphere(c, r).unwrap(), self.black).unwrap();
        self.scene.add_area_light(id, Rgb::splat(radiance)).unwrap();
    }

    pub fn quad_light(&mut self, corners: [Vec3; 4], radiance: f32) {
        let id = self.scene.add_shape(Shape::quad(corners).unwrap(), self.black).unwrap();
        self.scene.add_area_light(id, Rgb::splat(radiance)).unwrap();
    }
}

pub fn lambertian() -> Material {
    Material::lambertian(Rgb::splat(RHO)).unwrap()
}

pub fn ggx(alpha: f32) -> Material {
    Material::ggx_conductor(alpha, Rgb::splat(R_GGX)).unwrap()
}

/// Reflected radiance of a Lambertian receiver under irradiance `e`.
pub fn lambert_out(e: f64) -> f64 {
    f64::from(RHO) / PI * e
}

/// The shading point that a camera ray from `origin` towards `target` finds (f32 rounding of the
/// intersection included: the shadow-ray acne test), and the direction back to the eye.
pub fn view(scene: &S, origin: Vec3, target: Vec3, object: usize) -> (Hit, Vec3) {
    let ray = Ray { origin, dir: (target - origin).normalize() };
    let hit = scene.intersect(&ray, 0.0, f32::INFINITY, None).expect("the view ray hits the scene");
    assert_eq!(hit.object.index(), object, "the view ray must hit object {object} first");
    assert!(hit.front, "the view ray must hit the front side");
    (hit, -ray.dir)
}

/// A direction `deg` degrees from +y towards +x (or towards -x for negative angles).
pub fn tilt(deg: f32) -> Vec3 {
    let t = deg.to_radians();
    Vec3::new(t.sin(), t.cos(), 0.0)
}

/// Shading point at the origin of the floor, normal +y.
pub fn origin_hit() -> Hit {
    shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y)
}

/// A general viewing direction above the floor.
pub fn wo_default() -> Vec3 {
    Vec3::new(0.3, 0.9, -0.2).normalize()
}

/// Sphere irradiance at hit (per the hit's own f32 point and normal).
pub fn sphere_e(hit: &Hit, c: Vec3, r: f32, radiance: f32) -> f64 {
    sphere_irradiance_at(d3(hit.point.p), d3(hit.point.n), d3(c), f64::from(r), f64::from(radiance))
}
