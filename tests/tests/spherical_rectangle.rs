//! Quad lights sampled uniformly in solid angle (`QuadSampling::SolidAngle`: spherical
//! rectangles, Ureña, Fajardo and King 2013), and in solid angle warped by the receiver's cosine
//! (`QuadSampling::SolidAngleCosine`: Hart et al. 2020), against their pdf:
//!
//! 1. chi-square tests (10^6 samples charted on the rectangle's own (s, t) coordinates, expected
//!    counts from integrating the light sampler's `pdf` times the Jacobian A cos(theta_y) / d^2
//!    over each cell; Sidak-corrected) for rectangles overhead, off to the side, huge and close,
//!    and seen at a low angle; for the cosine warp also receivers tilted so that the horizon cuts
//!    the rectangle (halfway: a vertical receiver), and facing away from it;
//! 2. the kernel's solid angle (1 / pdf) against Van Oosterom and Strackee's formula in f64
//!    wherever the kernel trusts it, and the fallback to area sampling where it does not (tiny
//!    and grazing rectangles, parallelograms), decided identically by sampling and pdf, for both
//!    strategies;
//! 3. irradiance by light sampling alone with the cosine warp: unbiased (z-scores against f64
//!    quadrature, horizon cuts included), and with less variance than uniform solid angle where
//!    the cosine varies over the rectangle.

use picomis::light::quad::{self, QuadSampler};
use picomis::light::select::Uniform;
use picomis::light::{lobe, sphere};
use picomis::sampling::spherical_rectangle;
use picomis::{
    Film, LightId, LightSample, LightSampler, Lights, Material, QuadSampling, Rgb, Sampler, Scene,
    ShadingPoint, Shape, SurfacePoint, Vec2, Vec3,
};
use picomis_tests::{
    DVec3, Stats, assert_unbiased, camera, d3, histogram, integrate_adaptive, polygon_solid_angle,
    quad_corners,
};

/// Chi-square tests in this file (Sidak correction): 5 uniform, 8 cosine-warped, 2 `auto` (one
/// warped, one not).
const CHI2_TESTS: usize = 15;
const N_CHI2: usize = 1_000_000;

/// A scene holding one quad light.
struct QuadLight {
    scene: Scene<1, 1, 1>,
    light: LightId,
}

/// The light sampler of a [`QuadLight`] drawing on quads by `Q` (uniform selection, spheres in
/// their cone, no lobe mixing).
type QuadLightSampler<'a, Q> = LightSampler<'a, Lights<Uniform, sphere::InCone, Q, lobe::Off>, 1, 1, 1>;

impl QuadLight {
    fn sample(&self, at: &ShadingPoint, u: Vec2, quads: QuadSampling) -> Option<LightSample> {
        match quads {
            QuadSampling::Area => self.sample_by::<quad::ByArea>(at, u),
            QuadSampling::SolidAngle => self.sample_by::<quad::SolidAngle>(at, u),
            QuadSampling::SolidAngleCosine => self.sample_by::<quad::SolidAngleCosine>(at, u),
            QuadSampling::Auto => self.sample_by::<quad::Adaptive>(at, u),
            QuadSampling::BySize => self.sample_by::<quad::BySize>(at, u),
        }
    }

    fn sample_by<Q: QuadSampler>(&self, at: &ShadingPoint, u: Vec2) -> Option<LightSample> {
        QuadLightSampler::<Q>::new(&self.scene).sample(self.light, at, u)
    }

    fn pdf(&self, at: &ShadingPoint, y: &SurfacePoint, quads: QuadSampling) -> f32 {
        match quads {
            QuadSampling::Area => self.pdf_by::<quad::ByArea>(at, y),
            QuadSampling::SolidAngle => self.pdf_by::<quad::SolidAngle>(at, y),
            QuadSampling::SolidAngleCosine => self.pdf_by::<quad::SolidAngleCosine>(at, y),
            QuadSampling::Auto => self.pdf_by::<quad::Adaptive>(at, y),
            QuadSampling::BySize => self.pdf_by::<quad::BySize>(at, y),
        }
    }

    fn pdf_by<Q: QuadSampler>(&self, at: &ShadingPoint, y: &SurfacePoint) -> f32 {
        QuadLightSampler::<Q>::new(&self.scene).pdf(self.light, at, y)
    }
}

/// A receiver at `p` with unit normal `n`.
fn receiver(p: Vec3, n: Vec3) -> ShadingPoint {
    ShadingPoint {
        p,
        n: n.normalize(),
        wo: n.normalize(),
        bsdf: picomis::Material::lambertian(picomis::Rgb::ONE).expect("valid albedo"),
    }
}

fn quad_light(corners: [Vec3; 4]) -> (QuadLight, Shape) {
    let mut scene: Scene<1, 1, 1> = Scene::new(camera(), Film::new(4, 4).unwrap()).unwrap();
    let m = scene.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let shape = Shape::quad(corners).unwrap();
    let id = scene.add_shape(shape, m).unwrap();
    let light = scene.add_area_light(id, Rgb::ONE).unwrap();
    (QuadLight { scene, light }, shape)
}

/// A rectangle facing -y (towards a receiver below it).
fn rect(p0: Vec3, a: f32, b: f32) -> [Vec3; 4] {
    quad_corners(p0, Vec3::new(a, 0.0, 0.0), Vec3::new(0.0, 0.0, b))
}

fn pdf(light: &QuadLight, shape: &Shape, at: &ShadingPoint, p: Vec3, quads: QuadSampling) -> f64 {
    let y = SurfacePoint { p, n: shape.normal_at(p) };
    f64::from(light.pdf(at, &y, quads))
}

/// The chi-square cases: a name, the light's corners, the receiver's normal and the strategy.
fn chi2_cases() -> Vec<(String, [Vec3; 4], Vec3, QuadSampling)> {
    let rects = [
        ("overhead", rect(Vec3::new(-0.5, 1.0, -0.5), 1.0, 1.0)),
        ("off to the side", rect(Vec3::new(1.0, 0.8, 0.3), 1.5, 0.7)),
        ("huge and close", rect(Vec3::new(-50.0, 0.2, -50.0), 100.0, 100.0)),
        ("low angle", rect(Vec3::new(3.0, 0.5, -1.0), 2.0, 2.0)),
        ("long and thin", rect(Vec3::new(-20.0, 1.0, 0.0), 40.0, 0.1)),
    ];
    let mut cases = Vec::new();
    for quads in [QuadSampling::SolidAngle, QuadSampling::SolidAngleCosine] {
        for (name, corners) in rects {
            cases.push((format!("{name}, {}", quads.name()), corners, Vec3::Y, quads));
        }
    }
    let cosine = QuadSampling::SolidAngleCosine;
    let (overhead, side) = (rects[0].1, rects[1].1);
    // The horizon cuts the light: corners below it get the floor weight.
    cases.push(("overhead, receiver tilted 60 degrees".into(), overhead, Vec3::new(1.732, 1.0, 0.0), cosine));
    // Wholly below the horizon: every weight is the floor (uniform in solid angle).
    cases.push(("off to the side, receiver facing away".into(), side, Vec3::new(-1.0, 0.05, 0.0), cosine));
    // A vertical receiver under the light: its horizon runs through the light's middle.
    cases.push(("overhead, vertical receiver".into(), overhead, Vec3::new(1.0, 1e-3, 0.0), cosine));
    // `auto`: warped (the cosine peaks beyond the light's edge), and not (it peaks inside it).
    cases.push(("off to the side, auto".into(), side, Vec3::Y, QuadSampling::Auto));
    cases.push(("huge and close, auto".into(), rects[2].1, Vec3::Y, QuadSampling::Auto));
    cases
}

#[test]
fn chi2_against_the_pdf() {
    let x = Vec3::new(0.1, 0.0, -0.2);
    let cases = chi2_cases();
    assert_eq!(cases.len(), CHI2_TESTS);
    for (k, (name, corners, normal, quads)) in cases.into_iter().enumerate() {
        let at = receiver(x, normal);
        let (light, shape) = quad_light(corners);
        assert!(shape.normal_at(corners[0]).y < 0.0, "{name}: the light must face the receiver");
        let r = shape.as_rectangle().unwrap();
        let d = r.p0 - x;
        let sr =
            spherical_rectangle(Vec3::new(d.dot(r.ex), d.dot(r.ey), d.dot(r.n)), r.lengths.x, r.lengths.y)
                .unwrap_or_else(|| panic!("{name}: must be sampled in solid angle"));
        let exact = polygon_solid_angle(d3(x), &corners.map(d3));
        let rel = f64::from(sr.solid_angle()) / exact - 1.0;
        println!("{name}: solid angle {exact:.6e}, kernel relative error {rel:+.2e}");
        assert!(rel.abs() < 1e-5, "{name}: solid angle {} vs {exact}", sr.solid_angle());
        let (p0, e1, e2) = (d3(corners[0]), d3(corners[1] - corners[0]), d3(corners[3] - corners[0]));
        let area = e1.cross(e2).length();
        let ny = e1.cross(e2) * (1.0 / area);
        let chart = |p: DVec3| {
            let v = p - p0;
            Some((v.dot(e1) / e1.length_squared(), v.dot(e2) / e2.length_squared()))
        };
        let h = histogram(
            48,
            48,
            N_CHI2,
            500 + k as u32,
            |u| light.sample(&at, u, quads),
            |s| chart(d3(x) + d3(s.wi) * f64::from(s.distance)),
        );
        let density = |s: f64, t: f64| {
            let p = p0 + e1 * s + e2 * t;
            let v = p - d3(x);
            let d2 = v.length_squared();
            let jacobian = area * ny.dot(v).abs() / (d2 * d2.sqrt());
            pdf(&light, &shape, &at, picomis_tests::f3(p), quads) * jacobian
        };
        let c2 = h.assert_matches(&format!("spherical rectangle, {name}"), density, CHI2_TESTS);
        println!("{name}: {c2:?}");
    }
}

#[test]
fn solid_angle_is_accurate_or_falls_back_to_area() {
    // A sweep of rectangles from tiny to huge, overhead to grazing, near to far: wherever the
    // kernel samples in solid angle, its solid angle matches f64 to 2e-4; elsewhere the pdf is
    // the area pdf, the same decision in sampling and pdf.
    let x = Vec3::ZERO;
    let at = receiver(x, Vec3::Y);
    let (mut trusted, mut fallback, mut worst) = (0, 0, 0.0f64);
    for size in [1e-4f32, 1e-2, 1.0, 1e2, 1e4] {
        for height in [1e-3f32, 1e-1, 1.0, 10.0] {
            for offset in [0.0f32, 1.0, 30.0, 1e3] {
                let corners = rect(Vec3::new(offset - 0.5 * size, height, -0.5 * size), size, size);
                let (light, shape) = quad_light(corners);
                let r = shape.as_rectangle().unwrap();
                let d = r.p0 - x;
                let local = Vec3::new(d.dot(r.ex), d.dot(r.ey), d.dot(r.n));
                let centre = corners[0] + (corners[2] - corners[0]) * 0.5;
                let p_sa = pdf(&light, &shape, &at, centre, QuadSampling::SolidAngle);
                let p_cos = pdf(&light, &shape, &at, centre, QuadSampling::SolidAngleCosine);
                let p_area = pdf(&light, &shape, &at, centre, QuadSampling::Area);
                let p_auto = pdf(&light, &shape, &at, centre, QuadSampling::Auto);
                match spherical_rectangle(local, r.lengths.x, r.lengths.y) {
                    Some(sr) => {
                        trusted += 1;
                        let exact = polygon_solid_angle(d3(x), &corners.map(d3));
                        let rel = (f64::from(sr.solid_angle()) / exact - 1.0).abs();
                        worst = worst.max(rel);
                        assert!(rel < 2e-4, "size {size} height {height} offset {offset}: {rel:e}");
                        assert_eq!(p_sa, f64::from(1.0 / sr.solid_angle()));
                        assert!(
                            p_cos.is_finite() && p_cos > 0.0,
                            "size {size} height {height} offset {offset}"
                        );
                        assert!(
                            p_auto == p_sa || p_auto == p_cos,
                            "size {size} height {height} offset {offset}"
                        );
                    }
                    None => {
                        fallback += 1;
                        assert_eq!(p_sa, p_area, "size {size} height {height} offset {offset}");
                        assert_eq!(p_cos, p_area, "size {size} height {height} offset {offset}");
                        assert_eq!(p_auto, p_area, "size {size} height {height} offset {offset}");
                    }
                }
            }
        }
    }
    println!("{trusted} sampled in solid angle (worst relative error {worst:.2e}), {fallback} by area");
    assert!(trusted >= 30 && fallback >= 5, "{trusted} {fallback}");
    // A parallelogram that is not a rectangle is sampled by area.
    let skew = quad_corners(Vec3::new(-0.5, 1.0, -0.5), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.3, 0.0, 1.0));
    let (light, shape) = quad_light(skew);
    assert!(shape.as_rectangle().is_none());
    let c = Vec3::new(0.1, 1.0, 0.0);
    for quads in [QuadSampling::SolidAngle, QuadSampling::SolidAngleCosine, QuadSampling::Auto] {
        assert_eq!(pdf(&light, &shape, &at, c, quads), pdf(&light, &shape, &at, c, QuadSampling::Area));
    }
    // Behind the light: nothing, in both.
    let (light, _) = quad_light(rect(Vec3::new(-0.5, -1.0, -0.5), 1.0, 1.0));
    let u = Vec2::new(0.3, 0.6);
    assert!(light.sample(&at, u, QuadSampling::SolidAngle).is_none());
    assert!(light.sample(&at, u, QuadSampling::SolidAngleCosine).is_none());
    assert!(light.sample(&at, u, QuadSampling::Auto).is_none());
}

/// Irradiance sum of L max(0, n . wi) / pdf over `n` light samples of `quads`.
fn irradiance_stats(light: &QuadLight, at: &ShadingPoint, quads: QuadSampling, n: u32, seed: u32) -> Stats {
    let mut rng = Sampler::new(seed, 0, 0);
    let mut stats = Stats::new();
    for _ in 0..n {
        let value = light
            .sample(at, rng.next_2d(), quads)
            .map_or(0.0, |s| f64::from(s.radiance.x) * f64::from(at.n.dot(s.wi)).max(0.0) / f64::from(s.pdf));
        assert!(value.is_finite(), "{quads:?}: {value}");
        stats.push(value);
    }
    stats
}

/// Irradiance at `at` from a light of unit radiance on `corners` (a rectangle), by f64
/// quadrature of cos_x cos_y / d^2 over it, clipped to the receiver's horizon.
fn irradiance_quadrature(at: &ShadingPoint, corners: [Vec3; 4]) -> f64 {
    let (x, n) = (d3(at.p), d3(at.n));
    let (p0, e1, e2) = (d3(corners[0]), d3(corners[1] - corners[0]), d3(corners[3] - corners[0]));
    let area = e1.cross(e2).length();
    let ny = e1.cross(e2) * (1.0 / area);
    let integrand = |s: f64, t: f64| {
        let v = p0 + e1 * s + e2 * t - x;
        let d2 = v.length_squared();
        (n.dot(v).max(0.0) * ny.dot(v).abs()) / (d2 * d2) * area
    };
    integrate_adaptive(&integrand, [0.0, 1.0], [0.0, 1.0], 1e-10, 12)
}

#[test]
fn cosine_warp_is_unbiased_and_lowers_variance() {
    const N: u32 = 200_000;
    let x = Vec3::new(0.1, 0.0, -0.2);
    // (name, light, receiver normal, whether the warp must lower the variance: wherever the
    // cosine varies between the corners)
    let cases = [
        ("overhead", rect(Vec3::new(-0.5, 1.0, -0.5), 1.0, 1.0), Vec3::Y, true),
        ("off to the side", rect(Vec3::new(1.0, 0.8, 0.3), 1.5, 0.7), Vec3::Y, true),
        // Every corner is seen at a grazing angle (cosine 3e-3, floored at 0.01): the warp is
        // nearly uniform and cannot see the cosine's peak in the middle.
        ("huge and close", rect(Vec3::new(-50.0, 0.2, -50.0), 100.0, 100.0), Vec3::Y, false),
        ("low angle", rect(Vec3::new(3.0, 0.5, -1.0), 2.0, 2.0), Vec3::Y, true),
        ("horizon cuts it", rect(Vec3::new(-0.5, 1.0, -0.5), 1.0, 1.0), Vec3::new(1.732, 1.0, 0.0), true),
        ("vertical receiver", rect(Vec3::new(-0.5, 1.0, -0.5), 1.0, 1.0), Vec3::new(1.0, 1e-3, 0.0), true),
    ];
    for (k, (name, corners, normal, lowers)) in cases.into_iter().enumerate() {
        let (light, _) = quad_light(corners);
        let at = receiver(x, normal);
        let exact = irradiance_quadrature(&at, corners);
        let uniform = irradiance_stats(&light, &at, QuadSampling::SolidAngle, N, 700 + k as u32);
        let warped = irradiance_stats(&light, &at, QuadSampling::SolidAngleCosine, N, 800 + k as u32);
        let auto = irradiance_stats(&light, &at, QuadSampling::Auto, N, 900 + k as u32);
        let by_size = irradiance_stats(&light, &at, QuadSampling::BySize, N, 1000 + k as u32);
        let rel = |s: &Stats| s.variance() / (exact * exact);
        println!(
            "{name}: E = {exact:.6e}; relative variance {:.3e} (solid angle) vs {:.3e} (cosine-warped), ratio {:.2}",
            rel(&uniform),
            rel(&warped),
            uniform.variance() / warped.variance()
        );
        assert_unbiased(&format!("{name}, solid angle"), &uniform, exact, 0.02);
        assert_unbiased(&format!("{name}, cosine-warped"), &warped, exact, 0.02);
        assert_unbiased(&format!("{name}, auto"), &auto, exact, 0.02);
        assert_unbiased(&format!("{name}, by size"), &by_size, exact, 0.02);
        if lowers {
            // Fourth-moment standard errors of the two variances: the gap must exceed them.
            let gap = uniform.variance() - warped.variance();
            let se = uniform.variance_stderr().hypot(warped.variance_stderr());
            assert!(gap > 4.0 * se, "{name}: the warp must lower the variance ({gap:e} vs 4 x {se:e})");
        }
    }
}

/// `by-size` takes the area's way where a Lambertian receiver sees the rectangle small and steep
/// (its diagonal under 1.5 times both heights: of the centre above the receiver's plane, of the
/// receiver above the light's) or where the receiver's normal misses it, and the solid angle's
/// where it sees it large or at a slant and its normal meets it; a rough GGX receiver (alpha at
/// least `BySize::ROUGH`) always the area's, a sharper one always `auto`'s. Unbiased either way
/// (z-scores against quadrature).
#[test]
fn by_size_draws_small_steep_quads_by_area() {
    const N: u32 = 200_000;
    let x = Vec3::new(0.1, 0.0, -0.2);
    let lambertian = receiver(x, Vec3::Y);
    let ggx = |alpha| ShadingPoint {
        bsdf: picomis::Material::ggx_conductor(alpha, picomis::Rgb::ONE).expect("valid GGX"),
        ..lambertian
    };
    let (rough, sharp) = (ggx(quad::BySize::ROUGH), ggx(0.05));
    // (name, light, whether a Lambertian receiver at `x` draws it by area)
    let cases = [
        // Diagonal 0.71 at height 3: small and steep.
        ("small, high overhead", rect(Vec3::new(-0.15, 3.0, -0.45), 0.5, 0.5), true),
        // Diagonal 1.70 at height 1: large.
        ("overhead", rect(Vec3::new(-0.6, 1.0, -0.6), 1.2, 1.2), false),
        // Diagonal 0.85 at distance 1.23, at a slant (height 0.3), and the normal misses it.
        ("off to the side, low", rect(Vec3::new(1.0, 0.3, -0.5), 0.6, 0.6), true),
        // At a slant (height 0.3), and the normal meets it.
        ("low, over the receiver", rect(Vec3::new(-0.5, 0.3, -0.6), 1.0, 0.6), false),
    ];
    for (k, (name, corners, by_area)) in cases.into_iter().enumerate() {
        let (light, shape) = quad_light(corners);
        let centre = (corners[0] + corners[2]) * 0.5;
        let area = pdf(&light, &shape, &lambertian, centre, QuadSampling::Area);
        let solid_angle = pdf(&light, &shape, &lambertian, centre, QuadSampling::SolidAngle);
        let by_size = pdf(&light, &shape, &lambertian, centre, QuadSampling::BySize);
        assert!(area != solid_angle, "{name}: the two ways must differ here for the check to see the choice");
        assert_eq!(by_size, if by_area { area } else { solid_angle }, "{name}: by area {by_area}");
        let rough_pdf = pdf(&light, &shape, &rough, centre, QuadSampling::BySize);
        assert_eq!(rough_pdf, pdf(&light, &shape, &rough, centre, QuadSampling::Area), "{name}, rough GGX");
        let sharp_pdf = pdf(&light, &shape, &sharp, centre, QuadSampling::BySize);
        assert_eq!(sharp_pdf, pdf(&light, &shape, &sharp, centre, QuadSampling::Auto), "{name}, sharp GGX");
        let exact = irradiance_quadrature(&lambertian, corners);
        let stats = irradiance_stats(&light, &lambertian, QuadSampling::BySize, N, 1100 + k as u32);
        assert_unbiased(&format!("{name}, by size"), &stats, exact, 0.02);
    }
}
