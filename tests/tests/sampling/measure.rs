//! E[1/p(X)] = measure of the support: hemisphere, sphere, cones down to r/d = 1e-6, sphere lights
//! by cone and by area, a quad light's solid angle.

use crate::N_MEASURE;
use crate::materials::direction;
use crate::one_light::{LIGHT, at, quad_light, quad_points, setup, sphere_light};
use picomis::light::sphere::{self, InCone};
use picomis::sampling::{
    cone_one_minus_cos, cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_cone,
    sample_uniform_sphere, uniform_cone_pdf, uniform_sphere_pdf,
};
use picomis::{Material, Rgb, Sampler, Vec2};
use picomis_tests::{Stats, assert_unbiased, cone_measure, d3, polygon_solid_angle};
use std::f64::consts::PI;

/// Mean of 1/pdf over `n` draws (0 for a draw that returns nothing).
fn inverse_pdf_stats(seed: u32, n: usize, mut draw: impl FnMut(Vec2) -> Option<f32>) -> Stats {
    let mut st = Stats::new();
    let mut rng = Sampler::new(seed, 0x1D, 0);
    for _ in 0..n {
        st.push(draw(rng.next_2d()).map_or(0.0, |pdf| 1.0 / f64::from(pdf)));
    }
    st
}

#[test]
fn measure_hemisphere_and_sphere() {
    let st = inverse_pdf_stats(1, N_MEASURE, |u| Some(cosine_hemisphere_pdf(sample_cosine_hemisphere(u).z)));
    assert_unbiased("E[1/p] cosine hemisphere", &st, 2.0 * PI, 0.01);
    let m = Material::lambertian(Rgb::splat(0.5)).unwrap();
    let wo = direction(60.0, 10.0);
    let st = inverse_pdf_stats(2, N_MEASURE, |u| m.sample(wo, u).map(|s| s.pdf));
    assert_unbiased("E[1/p] Lambertian Material::sample", &st, 2.0 * PI, 0.01);
    let st = inverse_pdf_stats(3, N_MEASURE, |u| {
        let w = sample_uniform_sphere(u);
        assert!((w.length() - 1.0).abs() < 1e-5);
        Some(uniform_sphere_pdf())
    });
    assert_unbiased("E[1/p] uniform sphere", &st, 4.0 * PI, 0.01);
}

#[test]
fn measure_cone_down_to_tiny_spheres() {
    for r_over_d in [0.5f64, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6] {
        let r32 = r_over_d as f32;
        let omc = cone_one_minus_cos(r32 * r32);
        // Exact for the f32 ratio the kernel was given.
        let exact = cone_measure(f64::from(r32));
        let st = inverse_pdf_stats(4, 10_000, |u| {
            let w = sample_uniform_cone(u, omc);
            assert!(w.is_finite());
            Some(uniform_cone_pdf(omc))
        });
        assert_unbiased(&format!("E[1/p] uniform cone r/d = {r_over_d:e}"), &st, exact, 0.01);
    }
}

#[test]
fn measure_sphere_light_by_cone_down_to_tiny_spheres() {
    let (x, dir) = setup();
    for r_over_d in [1e-2f32, 1e-3, 1e-4, 1e-5, 1e-6] {
        let d = 2.0f32;
        let (light, shape) = sphere_light(x + dir * d, r_over_d * d);
        let lights = light.sampler::<InCone>();
        let (c, r) = shape.as_sphere().unwrap();
        let exact = cone_measure(f64::from(r) / (d3(c) - d3(x)).length());
        let mut min_cos: f64 = 1.0;
        let axis = (d3(c) - d3(x)).normalize();
        let st = inverse_pdf_stats(5, 10_000, |u| {
            let s = lights.sample(LIGHT, &at(x), u)?;
            min_cos = min_cos.min(d3(s.wi).normalize().dot(axis));
            Some(s.pdf)
        });
        assert_unbiased(&format!("E[1/p] sphere light by cone, r/d = {r_over_d:e}"), &st, exact, 0.01);
        // Every direction stays in the cone (to f32 precision of a world direction).
        let theta = min_cos.clamp(-1.0, 1.0).acos();
        assert!(
            theta <= f64::from(r_over_d).asin() + 2e-7,
            "r/d = {r_over_d:e}: a direction {theta:e} rad off the axis"
        );
    }
}

#[test]
fn measure_sphere_light_by_area() {
    let (x, dir) = setup();
    for r_over_d in [0.5f32, 0.1, 1e-2, 1e-3] {
        let d = 2.0f32;
        let (light, shape) = sphere_light(x + dir * d, r_over_d * d);
        let lights = light.sampler::<sphere::ByArea>();
        let (c, r) = shape.as_sphere().unwrap();
        let exact = cone_measure(f64::from(r) / (d3(c) - d3(x)).length());
        let st = inverse_pdf_stats(6, N_MEASURE, |u| lights.sample(LIGHT, &at(x), u).map(|s| s.pdf));
        assert_unbiased(&format!("E[1/p] sphere light by area, r/d = {r_over_d:e}"), &st, exact, 0.01);
    }
}

#[test]
fn measure_quad_light() {
    let (light, _, corners) = quad_light();
    let lights = light.sampler::<sphere::ByArea>();
    let verts = corners.map(d3);
    for x in quad_points() {
        let exact = polygon_solid_angle(d3(x), &verts);
        let st = inverse_pdf_stats(7, N_MEASURE, |u| lights.sample(LIGHT, &at(x), u).map(|s| s.pdf));
        assert_unbiased(&format!("E[1/p] quad light from {x}"), &st, exact, 0.01);
    }
}
