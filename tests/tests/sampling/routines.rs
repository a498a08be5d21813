//! Chi-square: the sampling routines of `picomis::sampling` (cosine hemisphere, uniform sphere,
//! uniform cone) against their pdfs.

use crate::{CHI2_TESTS, N_CHI2};
use picomis::sampling::{
    cone_one_minus_cos, cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_cone,
    sample_uniform_sphere, uniform_cone_pdf, uniform_sphere_pdf,
};
use picomis_tests::{Cap, DVec3, d3, histogram};
use std::f64::consts::PI;

#[test]
fn chi2_cosine_hemisphere() {
    let cap = Cap::new(DVec3::Z, PI / 2.0);
    let h = histogram(32, 64, N_CHI2, 1, |u| Some(sample_cosine_hemisphere(u)), |w| cap.coords(d3(*w)));
    let pdf = |w: DVec3| f64::from(cosine_hemisphere_pdf(w.z as f32));
    h.assert_matches("cosine hemisphere", cap.density(pdf), CHI2_TESTS);
}

#[test]
fn chi2_uniform_sphere() {
    let cap = Cap::new(DVec3::Z, PI);
    let h = histogram(40, 80, N_CHI2, 2, |u| Some(sample_uniform_sphere(u)), |w| cap.coords(d3(*w)));
    h.assert_matches("uniform sphere", cap.density(|_| f64::from(uniform_sphere_pdf())), CHI2_TESTS);
}

#[test]
fn chi2_uniform_cone() {
    // The cone a sphere of radius r subtends at distance d; the chart reaches 1.25 theta_max so
    // that samples outside the cone are caught, and the cone's edge is a cell edge (a = 0.8).
    for (k, r_over_d) in [0.999f64, 0.5, 0.1, 1e-2, 1e-3, 1e-6].into_iter().enumerate() {
        let omc = cone_one_minus_cos((r_over_d * r_over_d) as f32);
        let theta_c = r_over_d.asin();
        let cap = Cap::new(DVec3::Z, 1.25 * theta_c);
        let h = histogram(
            40,
            64,
            N_CHI2,
            10 + k as u32,
            |u| Some(sample_uniform_cone(u, omc)),
            |w| cap.coords(d3(*w)),
        );
        let pdf = f64::from(uniform_cone_pdf(omc));
        let density =
            |a: f64, _b: f64| if a * cap.theta_max <= theta_c { pdf * cap.jacobian(a) } else { 0.0 };
        h.assert_matches(&format!("uniform cone r/d = {r_over_d:e}"), density, CHI2_TESTS);
    }
}
