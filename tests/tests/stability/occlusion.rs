//! Group 5, occlusion and shadow-ray self-intersection: lit surfaces shaded where camera rays hit
//! them, lights hidden behind occluders, walls and spheres touching the shading point.

use crate::harness::{Case, Reference, run_group};
use crate::scenes::{Setup, lambert_out, lambertian, origin_hit, sphere_e, view, wo_default};
use picomis::{Hit, Shape, Vec3};
use picomis_tests::{d3, floor_corners, lambert_polygon_irradiance, quad_corners, shading_hit};

/// A Lambertian sphere lit by a sphere light, shaded where a camera ray hits it.
pub fn lit_sphere() -> Case {
    let mut s = Setup::new();
    s.add(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), lambertian());
    let c = Vec3::new(1.0, 3.0, 1.0);
    s.sphere_light(c, 0.5, 4.0);
    // 16 points on the upper cap (up to 31 degrees from the top), each found by a camera ray.
    let targets = (0..16).map(|j| {
        let (phi, s) = (j as f32 * std::f32::consts::FRAC_PI_8, if j % 2 == 0 { 0.3 } else { 0.6 });
        Vec3::new(s * phi.cos(), 1.0, s * phi.sin()).normalize()
    });
    let points: Vec<(Hit, Vec3)> =
        targets.map(|t| view(&s.scene, t + (t + Vec3::new(-0.3, 0.2, -0.3)) * 2.0, t, 0)).collect();
    let exact = points.iter().map(|(hit, _)| lambert_out(sphere_e(hit, c, 0.5, 4.0))).sum::<f64>() / 16.0;
    Case::at_points("lit Lambertian sphere at 16 camera-ray hits", s.scene, points, Reference::Exact(exact))
}

/// A tilted Lambertian quad lit by a quad light, shaded where camera rays hit it.
pub fn lit_quad() -> Case {
    let mut s = Setup::new();
    let (p0, e1, e2) = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(0.0, 0.2, 2.0), Vec3::new(2.0, 0.3, 0.0));
    s.add(Shape::quad(quad_corners(p0, e1, e2)).unwrap(), lambertian());
    let corners =
        quad_corners(Vec3::new(-0.3, 2.0, -0.2), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    s.quad_light(corners, 3.0);
    // A 4 x 4 grid of points, each found by a camera ray.
    let grid = [0.15, 0.38, 0.62, 0.85];
    let targets = grid.iter().flat_map(|&a| grid.iter().map(move |&b| p0 + e1 * a + e2 * b));
    let points: Vec<(Hit, Vec3)> =
        targets.map(|t| view(&s.scene, t + Vec3::new(-3.0, 1.0, 0.5), t, 0)).collect();
    let exact = points
        .iter()
        .map(|(hit, _)| {
            let (x, n) = (d3(hit.point.p), d3(hit.point.n));
            assert!(corners.iter().all(|&v| n.dot(d3(v) - x) > 0.0), "the light must be above the horizon");
            lambert_out(lambert_polygon_irradiance(x, n, &corners.map(d3), 3.0))
        })
        .sum::<f64>()
        / 16.0;
    Case::at_points(
        "lit Lambertian quad (quad light) at 16 camera-ray hits",
        s.scene,
        points,
        Reference::Exact(exact),
    )
}

pub fn sphere_behind_quad() -> Case {
    let mut s = Setup::floor(lambertian());
    s.sphere_light(Vec3::new(0.0, 3.0, 0.0), 0.5, 10.0);
    s.add(Shape::quad(floor_corners(2.0).map(|v| v + Vec3::Y * 1.5)).unwrap(), lambertian());
    Case::new("sphere light behind a quad occluder", s.scene, origin_hit(), wo_default(), Reference::Zero)
}

pub fn quad_behind_sphere() -> Case {
    let mut s = Setup::floor(lambertian());
    let corners =
        quad_corners(Vec3::new(-0.5, 3.0, -0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    s.quad_light(corners, 10.0);
    s.add(Shape::sphere(Vec3::new(0.0, 1.5, 0.0), 1.0).unwrap(), lambertian());
    Case::new("quad light behind a sphere occluder", s.scene, origin_hit(), wo_default(), Reference::Zero)
}

pub fn wall_touching_floor() -> Case {
    let mut s = Setup::floor(lambertian());
    // A wall in the plane x = 0 standing on the floor (its lower edge at y = 0 exactly), the
    // light behind it, the shading point 1e-5 in front of it.
    let wall = quad_corners(Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.0, 0.0, 10.0));
    s.add(Shape::quad(wall).unwrap(), lambertian());
    s.sphere_light(Vec3::new(2.0, 1.0, 0.0), 0.5, 10.0);
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::new(-1e-5, 0.0, 0.0), Vec3::Y);
    Case::new(
        "light behind a wall touching the floor, 1e-5 from it",
        s.scene,
        hit,
        Vec3::new(-1.0, 1.0, 0.2),
        Reference::Zero,
    )
}

/// A shading point on a sphere facing a second sphere `gap` away, the light behind the second.
pub fn sphere_next_to_sphere(gap: f32) -> Case {
    let mut s = Setup::new();
    s.add(Shape::sphere(Vec3::ZERO, 1.0).unwrap(), lambertian());
    s.add(Shape::sphere(Vec3::new(2.0 + gap, 0.0, 0.0), 1.0).unwrap(), lambertian());
    s.sphere_light(Vec3::new(6.0, 0.0, 0.0), 0.5, 10.0);
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::X, Vec3::X);
    let label = if gap > 0.0 {
        format!("sphere next to a sphere (gap {gap:.0e}), light behind")
    } else {
        "touching spheres, shading at the contact, light behind".to_string()
    };
    Case::new(label, s.scene, hit, Vec3::new(1.0, 1.0, 0.0), Reference::Zero)
}

/// Group 5's cases.
pub fn occlusion_cases() -> Vec<Case> {
    vec![
        lit_sphere(),
        lit_quad(),
        sphere_behind_quad(),
        quad_behind_sphere(),
        wall_touching_floor(),
        sphere_next_to_sphere(1e-3),
        sphere_next_to_sphere(0.0),
    ]
}

#[test]
fn occlusion_and_self_intersection() {
    run_group(5, occlusion_cases());
}
