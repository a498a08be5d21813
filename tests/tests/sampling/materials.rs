//! Chi-square: BSDF sampling through `Material::sample` against `Material::pdf` (Lambertian and
//! GGX, smooth and rough, down to grazing views), each sample's pdf and weight checked too.

use crate::{CHI2_TESTS, N_CHI2};
use picomis::{Material, Rgb, Vec3};
use picomis_tests::{Cap, DVec3, d3, f3, histogram};
use std::f64::consts::PI;

/// Checks one material's `sample` against its `pdf` for one `wo`; also that every sample's pdf
/// and weight agree with `pdf` and `eval`.
fn check_material(label: &str, m: Material, wo: Vec3, seed: u32) {
    let cap = Cap::new(DVec3::Z, PI / 2.0);
    let mut worst_pdf: f64 = 0.0;
    let mut worst_weight: f64 = 0.0;
    let h = histogram(
        48,
        96,
        N_CHI2,
        seed,
        |u| {
            let s = m.sample(wo, u)?;
            let pdf = f64::from(m.pdf(wo, s.wi));
            worst_pdf = worst_pdf.max((pdf / f64::from(s.pdf) - 1.0).abs());
            let expect = f64::from(m.eval(wo, s.wi).x) / f64::from(s.pdf);
            worst_weight = worst_weight.max((f64::from(s.weight.x) - expect).abs() / expect.max(1e-3));
            Some(s.wi)
        },
        |w| cap.coords(d3(*w)),
    );
    assert!(worst_pdf < 1e-3, "{label}: sample pdf and Material::pdf disagree by {worst_pdf:e}");
    assert!(worst_weight < 1e-3, "{label}: sample weight and eval/pdf disagree by {worst_weight:e}");
    let pdf = |w: DVec3| f64::from(m.pdf(wo, f3(w)));
    h.assert_matches(label, cap.density(pdf), CHI2_TESTS);
}

pub fn direction(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

#[test]
fn chi2_lambertian_material() {
    let m = Material::lambertian(Rgb::new(0.9, 0.5, 0.1)).unwrap();
    check_material("lambertian", m, direction(40.0, 30.0), 20);
}

#[test]
fn chi2_ggx_smooth() {
    for (k, theta_o) in [0.0, 45.0, 80.0, 88.0].into_iter().enumerate() {
        for alpha in [0.05, 0.2] {
            let m = Material::ggx_conductor(alpha, Rgb::ONE).unwrap();
            let label = format!("GGX alpha {alpha}, theta_o {theta_o}");
            check_material(&label, m, direction(theta_o, 30.0), 30 + k as u32 + (alpha * 100.0) as u32);
        }
    }
}

#[test]
fn chi2_ggx_rough() {
    for (k, theta_o) in [0.0, 45.0, 80.0, 88.0].into_iter().enumerate() {
        for alpha in [0.5, 1.0] {
            let m = Material::ggx_conductor(alpha, Rgb::ONE).unwrap();
            let label = format!("GGX alpha {alpha}, theta_o {theta_o}");
            check_material(&label, m, direction(theta_o, -70.0), 60 + k as u32 + (alpha * 10.0) as u32);
        }
    }
}
