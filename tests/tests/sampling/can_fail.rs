//! The chi-square tests of this suite can fail: a GGX alpha off by 5% and a cone 1% too wide are
//! detected at the suite's significance.

use crate::materials::direction;
use crate::{CHI2_TESTS, N_CHI2};
use picomis::sampling::{cone_one_minus_cos, sample_uniform_cone};
use picomis::{Material, Rgb};
use picomis_tests::{Cap, DVec3, cone_measure, d3, f3, histogram};
use std::f64::consts::PI;

#[test]
fn chi2_detects_small_errors() {
    let level = picomis_tests::sidak(0.01, CHI2_TESTS);
    let cap = Cap::new(DVec3::Z, PI / 2.0);
    // GGX samples of alpha 0.2 against the pdf of alpha 0.21.
    let wo = direction(45.0, 30.0);
    let m = Material::ggx_conductor(0.2, Rgb::ONE).unwrap();
    let wrong = Material::ggx_conductor(0.21, Rgb::ONE).unwrap();
    let h = histogram(48, 96, N_CHI2, 30, |u| m.sample(wo, u).map(|s| s.wi), |w| cap.coords(d3(*w)));
    let (e, _) = h.expected(cap.density(|w: DVec3| f64::from(wrong.pdf(wo, f3(w)))));
    let c = picomis_tests::chi2_pooled(&h.observed, &e).unwrap();
    assert!(c.p_value < level, "GGX alpha off by 5% not detected: {c:?}");
    // Cone samples against a cone 1% wider: samples are missing near its edge.
    let r_over_d = 0.1f64;
    let omc = cone_one_minus_cos((r_over_d * r_over_d) as f32);
    let theta_c = 1.01 * r_over_d.asin();
    let wide = cone_measure(theta_c.sin());
    let cone = Cap::new(DVec3::Z, 1.25 * theta_c);
    let h = histogram(40, 64, N_CHI2, 12, |u| Some(sample_uniform_cone(u, omc)), |w| cone.coords(d3(*w)));
    let (e, _) = h.expected(|a, _| if a * cone.theta_max <= theta_c { cone.jacobian(a) / wide } else { 0.0 });
    let c = picomis_tests::chi2_pooled(&h.observed, &e).unwrap();
    assert!(c.p_value < level, "cone 1% too wide not detected: {c:?}");
}
