//! The GGX rough conductor against an independent formulation, written here in f64 from the
//! papers and never calling the kernel:
//!
//! - Walter, Marschner, Li, Torrance 2007, "Microfacet models for refraction through rough
//!   surfaces": f_r(wo, wi) = F G D / (4 |wo.n| |wi.n|) (eq. 20), GGX D(m) = a^2 chi+(m.n) /
//!   (pi cos^4(theta_m) (a^2 + tan^2(theta_m))^2) (eq. 33); Fresnel F = 1, times the reflectance.
//! - Heitz 2014, "Understanding the masking-shadowing function in microfacet-based BRDFs": Smith
//!   G1 = 1 / (1 + Lambda), GGX Lambda(theta) = (-1 + sqrt(1 + a^2 tan^2 theta)) / 2 (eq. 72),
//!   and the separable masking-shadowing G2 = G1(wo) G1(wi) (eq. 98), which is what the kernel
//!   documents (`Material::GgxConductor`); the height-correlated G2 = 1 / (1 + Lambda(wo) +
//!   Lambda(wi)) (eq. 99) is computed too, to show that the comparison tells the two apart.
//! - Heitz 2018, "Sampling the GGX distribution of visible normals": D_wo(m) = G1(wo) max(0,
//!   wo.m) D(m) / cos(theta_o) (eq. 1), and the reflection Jacobian 1 / (4 wo.m) (Walter eq. 14):
//!   pdf(wi) = D_wo(m) / (4 wo.m).
//!
//! Checks: `Material::eval_pdf` equals the reference on a grid of directions and roughnesses
//! (alpha 0.02 to 1, where G1(wi) matters) within a bound on f32 rounding; `Material::sample`
//! returns the reference pdf and weight f cos / pdf; and a white furnace: the directional albedo
//! of the conductor (reflectance 1), estimated with the kernel's sampler, equals a quadrature of
//! the reference in f64 within 4 combined standard errors (Monte Carlo and quadrature error,
//! both estimated). Every figure is printed (`--nocapture`).

use picomis::{Material, Rgb, Sampler, Vec2, Vec3};

type V = [f64; 3];

fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalize(a: V) -> V {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

fn tan2(v: V) -> f64 {
    (v[0] * v[0] + v[1] * v[1]) / (v[2] * v[2])
}

/// Walter et al. 2007, eq. 33 (in the local frame, n = z).
fn d_ggx(m: V, a: f64) -> f64 {
    if m[2] <= 0.0 {
        return 0.0;
    }
    let cos2 = m[2] * m[2];
    let k = a * a + tan2(m);
    a * a / (std::f64::consts::PI * cos2 * cos2 * k * k)
}

/// Heitz 2014, eq. 72.
fn lambda(v: V, a: f64) -> f64 {
    (-1.0 + (1.0 + a * a * tan2(v)).sqrt()) / 2.0
}

/// Smith G1 with the facet term chi+(v.m / v.n) (Heitz 2014, eq. 43).
fn g1(v: V, m: V, a: f64) -> f64 {
    if v[2] <= 0.0 || dot(v, m) <= 0.0 {
        return 0.0;
    }
    1.0 / (1.0 + lambda(v, a))
}

#[derive(Clone, Copy, PartialEq)]
enum Masking {
    Separable,
    HeightCorrelated,
}

/// f(wo, wi) cos(theta_i) and the visible-normal pdf of wi, in f64.
fn reference(wo: V, wi: V, a: f64, masking: Masking) -> (f64, f64) {
    if wo[2] <= 0.0 || wi[2] <= 0.0 {
        return (0.0, 0.0);
    }
    let m = normalize([wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]]);
    let d = d_ggx(m, a);
    let g2 = match masking {
        Masking::Separable => g1(wo, m, a) * g1(wi, m, a),
        Masking::HeightCorrelated if dot(wo, m) > 0.0 && dot(wi, m) > 0.0 => {
            1.0 / (1.0 + lambda(wo, a) + lambda(wi, a))
        }
        Masking::HeightCorrelated => 0.0,
    };
    let f = d * g2 / (4.0 * wo[2] * wi[2]);
    let d_visible = g1(wo, m, a) * dot(wo, m).max(0.0) * d / wo[2];
    (f * wi[2], d_visible / (4.0 * dot(wo, m)))
}

fn dir(theta_deg: f64, phi_deg: f64) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32)
}

fn d64(v: Vec3) -> V {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

const ALPHAS: [f32; 9] = [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.85, 1.0];
const THETAS: [f64; 8] = [0.0, 10.0, 25.0, 40.0, 55.0, 70.0, 80.0, 87.0];
const PHIS: [f64; 5] = [0.0, 45.0, 90.0, 135.0, 180.0];
const REFLECTANCE: [f32; 3] = [0.9, 0.5, 0.25];

/// Relative error allowed between the f32 kernel and the f64 reference on the same f32 inputs:
/// each of the about 30 operations of D, G1(wo), G1(wi) and the half vector rounds by at most
/// half an ulp (2^-24), and none of them cancels (D's denominator and Lambda's sqrt add positive
/// terms), so the relative error stays below 30 x 2^-24 ~ 1.8e-6 up to a small factor for the
/// sensitivity of D to the half vector (at most 2 in the log-log slope): 64 x 2^-24 ~ 3.8e-6.
const REL_TOL: f64 = 64.0 * f32::EPSILON as f64 / 2.0;

fn rel(kernel: f64, reference: f64) -> f64 {
    if reference == 0.0 { kernel.abs() } else { (kernel - reference).abs() / reference.abs() }
}

#[test]
fn eval_and_pdf_match_the_papers_formulas() {
    let mut worst_f = (0.0f64, String::new());
    let mut worst_pdf = (0.0f64, String::new());
    let mut compared = 0;
    // How far the height-correlated G2 lies from the kernel where masking of wi matters.
    let mut correlated_gap = 0.0f64;
    for &alpha in &ALPHAS {
        let m = Material::ggx_conductor(alpha, Rgb::from_array(REFLECTANCE)).unwrap();
        for &to in &THETAS {
            for &ti in &THETAS {
                for &phi in &PHIS {
                    let (wo, wi) = (dir(to, 0.0), dir(ti, 180.0 + phi));
                    let (f, pdf) = m.eval_pdf(wo, wi);
                    let (rf, rpdf) = reference(d64(wo), d64(wi), f64::from(alpha), Masking::Separable);
                    let (hf, _) = reference(d64(wo), d64(wi), f64::from(alpha), Masking::HeightCorrelated);
                    let at = format!("alpha {alpha} theta_o {to} theta_i {ti} phi {phi}");
                    assert!(rf.is_finite() && rpdf.is_finite() && rf >= 0.0, "{at}: reference {rf} {rpdf}");
                    for (c, &r) in [f.x, f.y, f.z].iter().zip(&REFLECTANCE) {
                        let e = rel(f64::from(*c), f64::from(r) * rf);
                        if e > worst_f.0 {
                            worst_f = (e, at.clone());
                        }
                    }
                    let e = rel(f64::from(pdf), rpdf);
                    if e > worst_pdf.0 {
                        worst_pdf = (e, at.clone());
                    }
                    if alpha >= 0.3 && rf > 1e-3 {
                        correlated_gap = correlated_gap.max(rel(f64::from(f.x) / 0.9, hf));
                    }
                    compared += 1;
                }
            }
        }
    }
    println!(
        "GGX eval vs f64 reference: {compared} direction pairs, alpha {ALPHAS:?}; max relative error \
         f cos {:.2e} ({}), pdf {:.2e} ({}); tolerance {REL_TOL:.2e}; largest gap to the \
         height-correlated G2 (alpha >= 0.3): {correlated_gap:.3}",
        worst_f.0, worst_f.1, worst_pdf.0, worst_pdf.1
    );
    assert!(worst_f.0 < REL_TOL, "f cos differs from the reference by {:.2e} at {}", worst_f.0, worst_f.1);
    assert!(
        worst_pdf.0 < REL_TOL,
        "pdf differs from the reference by {:.2e} at {}",
        worst_pdf.0,
        worst_pdf.1
    );
    // The grid can tell the two masking forms apart (so it checks G1(wi), not just D).
    assert!(correlated_gap > 0.05, "the height-correlated form is within {correlated_gap} of the kernel");
}

#[test]
fn samples_carry_the_reference_pdf_and_weight() {
    // The weight must match to REL_TOL. The sample's pdf comes from the drawn normal m, the
    // reference's from m recomputed out of the rounded wi: a rounding of wi by ~2^-24 / cos(theta_o)
    // moves m by as much and D by a relative ~4 delta / alpha, which the pdf tolerance adds.
    let (mut worst_w, mut worst_pdf) = (0.0f64, 0.0f64); // error / tolerance
    let mut n = 0;
    for &alpha in &ALPHAS {
        let m = Material::ggx_conductor(alpha, Rgb::ONE).unwrap();
        for (k, &to) in THETAS.iter().enumerate() {
            let wo = dir(to, 30.0);
            let pdf_tol =
                REL_TOL + 4.0 * f64::from(f32::EPSILON) / 2.0 / (f64::from(alpha) * f64::from(wo.z));
            for i in 0..256u32 {
                let u = Sampler::new(11, k as u32, i).next_2d();
                let Some(s) = m.sample(wo, u) else { continue };
                let (rf, rpdf) = reference(d64(wo), d64(s.wi), f64::from(alpha), Masking::Separable);
                // Heitz 2018: the weight of a visible-normal sample is f cos / pdf = G1(wi) (F = 1).
                worst_w = worst_w.max(rel(f64::from(s.weight.x), rf / rpdf) / REL_TOL);
                worst_pdf = worst_pdf.max(rel(f64::from(s.pdf), rpdf) / pdf_tol);
                n += 1;
            }
        }
    }
    println!(
        "GGX samples vs f64 reference: {n} samples; largest error / tolerance: weight {worst_w:.3}, pdf {worst_pdf:.3}"
    );
    assert!(n > 10_000);
    assert!(worst_w < 1.0 && worst_pdf < 1.0, "a sample's weight or pdf is off the reference");
}

/// Directional albedo of the reference (reflectance 1) by the midpoint rule on an n x n grid over
/// the GGX normal distribution: m(u, v) has tan^2(theta_m) = a^2 u / (1 - u) and phi = 2 pi v,
/// whose density D(m) cos(theta_m) turns the albedo into
/// rho = integral of G2 (wo.m) / (cos(theta_o) cos(theta_m)) [wi above the horizon] du dv.
/// The integrand is continuous (G1(wi) and wo.m vanish at the edges of its support), so the rule
/// converges as 1/n^2.
fn albedo_by_normals(wo: V, a: f64, n: usize) -> f64 {
    let mut sum = 0.0;
    for i in 0..n {
        let u = (i as f64 + 0.5) / n as f64;
        let tan_t = a * (u / (1.0 - u)).sqrt();
        let cos_t = 1.0 / (1.0 + tan_t * tan_t).sqrt();
        let sin_t = tan_t * cos_t;
        for j in 0..n {
            let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / n as f64;
            let m = [sin_t * phi.cos(), sin_t * phi.sin(), cos_t];
            let om = dot(wo, m);
            if om <= 0.0 {
                continue;
            }
            let wi = [2.0 * om * m[0] - wo[0], 2.0 * om * m[1] - wo[1], 2.0 * om * m[2] - wo[2]];
            if wi[2] <= 0.0 {
                continue;
            }
            sum += g1(wo, m, a) * g1(wi, m, a) * om / (wo[2] * cos_t);
        }
    }
    sum / (n * n) as f64
}

/// The same albedo integrated over wi instead (midpoint rule in cos(theta_i) and phi_i): an
/// independent check of the quadrature where the lobe is wide enough for it (alpha >= 0.3).
fn albedo_by_directions(wo: V, a: f64, n: usize) -> f64 {
    // Midpoint rule: d(mu) = 1/n over [0, 1], d(phi) = pi/n over [0, 2 pi); dw = d(mu) d(phi).
    let mut total = 0.0;
    for i in 0..n {
        let mu = (i as f64 + 0.5) / n as f64;
        let s = (1.0 - mu * mu).sqrt();
        for j in 0..2 * n {
            let phi = std::f64::consts::PI * (j as f64 + 0.5) / n as f64;
            total += reference(wo, [s * phi.cos(), s * phi.sin(), mu], a, Masking::Separable).0;
        }
    }
    total * std::f64::consts::PI / (n * n) as f64
}

#[test]
fn white_furnace_albedo_matches_quadrature() {
    const N_MC: u32 = 1 << 18;
    let mut checked = 0;
    for (k, &alpha) in [0.05f32, 0.1, 0.3, 0.5, 0.75, 1.0].iter().enumerate() {
        let m = Material::ggx_conductor(alpha, Rgb::ONE).unwrap();
        for (l, &to) in [0.0f64, 30.0, 60.0, 80.0].iter().enumerate() {
            let wo = dir(to, 0.0);
            let a = f64::from(alpha);
            let q = albedo_by_normals(d64(wo), a, 1024);
            let q_half = albedo_by_normals(d64(wo), a, 512);
            // Midpoint rule, error ~ c / n^2: the n = 1024 error is about (q_half - q) / 3.
            let q_err = (q - q_half).abs() / 3.0 + 1e-12;
            // The kernel's albedo: the mean of the sample weights f cos / pdf (0 for no sample).
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for i in 0..N_MC {
                let u: Vec2 = Sampler::new(0xA1BE, (k * 16 + l) as u32, i).next_2d();
                let w = m.sample(wo, u).map_or(0.0, |s| f64::from(s.weight.x));
                sum += w;
                sum2 += w * w;
            }
            let n = f64::from(N_MC);
            let mean = sum / n;
            let se = ((sum2 / n - mean * mean).max(0.0) / (n - 1.0)).sqrt();
            let z = (mean - q) / (se * se + q_err * q_err).sqrt();
            let cross = if alpha >= 0.3 {
                let qd = albedo_by_directions(d64(wo), a, 1024);
                format!(", over directions {qd:.6}")
            } else {
                String::new()
            };
            println!(
                "white furnace alpha {alpha} theta_o {to}: quadrature {q:.6} (error ~{q_err:.1e}{cross}), \
                 kernel {mean:.6} +- {se:.1e}, z {z:+.2}"
            );
            if alpha >= 0.3 {
                let qd = albedo_by_directions(d64(wo), a, 1024);
                assert!((qd - q).abs() < 1e-3, "the two quadratures disagree: {q} against {qd}");
            }
            assert!(q > 0.0 && q <= 1.0 + 1e-9, "albedo {q} outside (0, 1]");
            // Non-vacuous: a 1 % error in the albedo would be > 4 combined standard errors.
            assert!(4.0 * (se * se + q_err * q_err).sqrt() < 0.01 * q, "se {se} q_err {q_err}");
            assert!(
                z.abs() < 4.0,
                "alpha {alpha} theta_o {to}: kernel albedo {mean} vs quadrature {q}, z {z}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 24);
}
