//! (a) A Lambertian plane under a sphere light (theta 0 and 60 degrees); (b) under a quad light
//! (Lambert's polygon formula); (d) under a point light plus a sphere light (BSDF sampling
//! cannot see the point light: it gets exactly the sphere's part).

use crate::harness::{
    ALBEDO, MAX_REL_STDERR, N, add, check_methods, lambert_out, methods, report, scaled, settings, sphere_e,
    z_max,
};
use picomis::{Film, LightSelection, Material, Method, Rgb, Scene, Shape, SphereSampling, Vec3};
use picomis_host::HostScene;
use picomis_tests::{
    DVec3, assert_unbiased_rgb_within, camera, d3, direct_stats, floor_corners, lambert_polygon_irradiance,
    quad_corners, shading_hit,
};

pub type SphereScene = HostScene;

pub const SPHERE_L: Rgb = Rgb::new(4.0, 2.0, 1.0);

/// A floor (object 0) under a sphere light of radius `r` whose centre is at distance `d`,
/// `theta` degrees off the normal of the origin.
pub fn sphere_scene(theta_deg: f32, r: f32, d: f32) -> (SphereScene, Vec3) {
    let mut s: SphereScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let t = theta_deg.to_radians();
    let c = Vec3::new(d * t.sin(), d * t.cos(), 0.0);
    let bulb = s.add_shape(Shape::sphere(c, r).unwrap(), black).unwrap();
    s.add_area_light(bulb, SPHERE_L).unwrap();
    (s, c)
}

fn check_sphere(theta_deg: f32, stream: u32) {
    let (r, d) = (1.0, 3.0);
    let (scene, c) = sphere_scene(theta_deg, r, d);
    let exact = lambert_out(scaled(SPHERE_L, sphere_e(c, r)));
    // Cross-check the closed form: (rho/pi) pi L (r/d)^2 cos(theta).
    let t = f64::from(theta_deg).to_radians();
    let direct = 0.8 * 4.0 * (1.0f64 / 3.0).powi(2) * t.cos();
    assert!((exact[0] / direct - 1.0).abs() < 1e-6, "{exact:?} vs {direct}");
    for (k, spheres) in [SphereSampling::Area, SphereSampling::Cone].into_iter().enumerate() {
        let label = format!("(a) sphere light at {theta_deg} deg");
        let stream = stream + 100 * k as u32;
        check_methods(&label, &scene, &methods(), (1, 1), spheres, LightSelection::Uniform, exact, stream);
    }
}

#[test]
fn a_sphere_light_overhead() {
    check_sphere(0.0, 1000);
}

#[test]
fn a_sphere_light_at_60_degrees() {
    check_sphere(60.0, 2000);
}

// ---------------------------------------------------------------------------------------------
// (b) a quad light, Lambert's polygon formula

#[test]
fn b_quad_light() {
    let mut s: HostScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    // Tilted, off-centre, facing down towards the origin.
    let corners =
        quad_corners(Vec3::new(-0.6, 1.5, 0.8), Vec3::new(0.0, 0.3, -1.4), Vec3::new(1.1, 0.2, 0.1));
    let q = Shape::quad(corners).unwrap();
    assert!(q.normal_at(corners[0]).dot(-corners[0]) > 0.0, "the light must face the origin");
    let id = s.add_shape(q, black).unwrap();
    let radiance = Rgb::new(3.0, 1.0, 2.0);
    s.add_area_light(id, radiance).unwrap();
    let e = lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0);
    let exact = lambert_out(scaled(radiance, e));
    check_methods(
        "(b) quad light",
        &s,
        &methods(),
        (1, 1),
        SphereSampling::Cone,
        LightSelection::Uniform,
        exact,
        3000,
    );
}

// ---------------------------------------------------------------------------------------------
// (d) a point light plus a sphere light

#[test]
fn d_point_light_plus_sphere_light() {
    let (mut scene, c) = sphere_scene(30.0, 0.8, 3.0);
    let p = Vec3::new(-1.0, 2.0, 1.5);
    let intensity = Rgb::new(2.0, 3.0, 1.0);
    scene.add_point_light(p, intensity).unwrap();
    let sphere_part = lambert_out(scaled(SPHERE_L, sphere_e(c, 0.8)));
    // E = I cos(theta) / d^2.
    let pv = d3(p);
    let point_part = lambert_out(scaled(intensity, pv.y / pv.length() / pv.length_squared()));
    let total = add(sphere_part, point_part);
    let mis: Vec<(String, Method)> = methods().into_iter().filter(|(_, m)| *m != Method::BsdfOnly).collect();
    for (k, spheres) in [SphereSampling::Area, SphereSampling::Cone].into_iter().enumerate() {
        for (j, selection) in LightSelection::ALL.into_iter().enumerate() {
            let stream = 5000 + 100 * (3 * k + j) as u32;
            check_methods("(d) point + sphere", &scene, &mis, (1, 1), spheres, selection, total, stream);
        }
    }
    // BSDF sampling alone cannot hit a point light: it converges to the sphere's part only.
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let st = direct_stats(&scene, &settings(Method::BsdfOnly, 1, 1), &hit, Vec3::Y, 5900, N);
    report("(d) BSDF only (sphere part)", &st.total, sphere_part);
    assert_unbiased_rgb_within(
        "(d) BSDF only misses the point light",
        &st.total,
        sphere_part,
        MAX_REL_STDERR,
        z_max(),
    );
    for (c, s) in st.total.0.iter().enumerate() {
        let z = (total[c] - s.mean()) / s.stderr();
        assert!(z > 20.0, "the point light's share should be far outside BSDF-only's noise (z = {z})");
    }
}
