//! Chi-square: a light's own sampling through `LightSampler::sample` against
//! `LightSampler::pdf` (one light): sphere lights by cone and by area, a quad light by area.

use crate::charts::{QuadChart, VisibleCap};
use crate::one_light::{LIGHT, at, pdf_towards, quad_light, quad_points, sample_point, setup, sphere_light};
use crate::{CHI2_TESTS, N_CHI2};
use picomis::light::sphere::{self, InCone};
use picomis::{SurfacePoint, Vec3};
use picomis_tests::{Cap, DVec3, d3, histogram};

#[test]
fn chi2_sphere_light_by_cone() {
    let (x, dir) = setup();
    for (k, r_over_d) in [0.5f32, 0.1, 1e-2].into_iter().enumerate() {
        let d = 3.0;
        let (light, shape) = sphere_light(x + dir * d, r_over_d * d);
        let lights = light.sampler::<InCone>();
        let (c, r) = shape.as_sphere().unwrap();
        let theta_s = (f64::from(r) / (d3(c) - d3(x)).length()).asin();
        let cap = Cap::new(d3(c) - d3(x), 1.25 * theta_s);
        let h = histogram(
            40,
            64,
            N_CHI2,
            100 + k as u32,
            |u| lights.sample(LIGHT, &at(x), u),
            |s| cap.coords(d3(s.wi)),
        );
        let pdf = |w: DVec3| pdf_towards(&lights, &shape, x, w);
        h.assert_matches(&format!("sphere light by cone, r/d = {r_over_d}"), cap.density(pdf), CHI2_TESTS);
    }
}

#[test]
fn chi2_sphere_light_by_area() {
    let (x, dir) = setup();
    for (k, r_over_d) in [0.8f32, 0.3, 0.05].into_iter().enumerate() {
        let d = 2.0;
        let (light, shape) = sphere_light(x + dir * d, r_over_d * d);
        let lights = light.sampler::<sphere::ByArea>();
        let (c, r) = shape.as_sphere().unwrap();
        let chart = VisibleCap::new(x, c, r);
        let h = histogram(
            32,
            64,
            N_CHI2,
            110 + k as u32,
            |u| lights.sample(LIGHT, &at(x), u),
            |s| chart.coords(sample_point(x, s.wi, s.distance)),
        );
        let pdf = |p: Vec3, n: Vec3| f64::from(lights.pdf(LIGHT, &at(x), &SurfacePoint { p, n }));
        let label = format!("sphere light by area, r/d = {r_over_d}");
        let c2 = h.assert_matches(&label, chart.density(pdf), CHI2_TESTS);
        // About half of the points lie on the far side: P(no sample) = (1 + r/d) / 2.
        let none = h.observed[h.cells() + 1] / N_CHI2 as f64;
        let p_none = 0.5 * (1.0 + f64::from(r) / (d3(c) - d3(x)).length());
        let se = (p_none * (1.0 - p_none) / N_CHI2 as f64).sqrt();
        assert!(
            (none - p_none).abs() < 4.0 * se,
            "{label}: {none} far-side samples, expected {p_none} ({c2:?})"
        );
    }
}

#[test]
fn chi2_quad_light_by_area() {
    let (light, shape, corners) = quad_light();
    let lights = light.sampler::<InCone>();
    for (k, x) in quad_points().into_iter().enumerate() {
        // The light faces x.
        assert!(shape.normal_at(corners[0]).dot(x - corners[0]) > 0.0);
        let chart = QuadChart::new(x, corners);
        let h = histogram(
            32,
            32,
            N_CHI2,
            120 + k as u32,
            |u| lights.sample(LIGHT, &at(x), u),
            |s| chart.coords(sample_point(x, s.wi, s.distance)),
        );
        let pdf = |p: Vec3, n: Vec3| f64::from(lights.pdf(LIGHT, &at(x), &SurfacePoint { p, n }));
        h.assert_matches(&format!("quad light by area from {x}"), chart.density(pdf), CHI2_TESTS);
    }
}
