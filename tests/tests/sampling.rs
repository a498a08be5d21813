//! Every sampling routine of the kernel against its pdf.
//!
//! 1. Chi-square tests (Mitsuba style): 10^6 samples histogrammed on a chart of the sample space
//!    (a polar grid of directions, or the light's own surface), expected counts from integrating
//!    the kernel's pdf numerically over each cell, cells with < 5 expected pooled, significance
//!    0.01 Sidak-corrected over the [`CHI2_TESTS`] tests of this file. Samplers that may return
//!    nothing get a "no sample" cell holding the pdf's missing mass.
//! 2. E[1/p(X)] = measure of the support (z < 4 on the standard error): hemisphere 2 pi, sphere
//!    4 pi, cone 2 pi (1 - cos theta_max) down to r/d = 1e-6, a sphere light's cone by area
//!    sampling, a quad light's solid angle (Van Oosterom-Strackee).

use picomis::light::select::{ByContribution, ByPower, Uniform};
use picomis::light::sphere::{InCone, SphereSampler};
use picomis::light::{LightStrategies, Lights, Select, lobe, quad, sphere};
use picomis::sampling::{
    cone_one_minus_cos, cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_cone,
    sample_uniform_sphere, uniform_cone_pdf, uniform_sphere_pdf,
};
use picomis::{
    Film, Light, LightId, LightSampler, LightSelection, Material, Rgb, Sampler, Scene, ShadingPoint, Shape,
    ShapeId, SphereSampling, SurfacePoint, Vec2, Vec3,
};
use picomis_tests::{
    Cap, DVec3, Histogram2d, LightChoices, Stats, VisitLights, assert_chi2, assert_unbiased, camera,
    channel_mean, cone_measure, d3, f3, frame, histogram, polygon_solid_angle, quad_corners,
};
use std::f64::consts::PI;

/// Number of chi-square tests in this file (for the Sidak correction).
const CHI2_TESTS: usize = 42;
/// Samples per chi-square test.
const N_CHI2: usize = 1_000_000;
/// Samples per E[1/p] test.
const N_MEASURE: usize = 200_000;

// ---------------------------------------------------------------------------------------------
// Charts of light surfaces

/// The part of a sphere (centre `c`, radius `r`) visible from `x`, charted by
/// a = (1 - cos psi) / (1 - r/d) (area-uniform) and b = phi / 2 pi, psi measured at the centre
/// from the axis towards `x`. The visible cap is exactly psi < acos(r/d).
struct VisibleCap {
    x: DVec3,
    c: DVec3,
    r: f64,
    frame: [DVec3; 3],
    omc_max: f64,
}

impl VisibleCap {
    fn new(x: Vec3, c: Vec3, r: f32) -> Self {
        let (x, c, r) = (d3(x), d3(c), f64::from(r));
        let d = (x - c).length();
        Self { x, c, r, frame: frame(x - c), omc_max: 1.0 - r / d }
    }

    fn coords(&self, y: DVec3) -> Option<(f64, f64)> {
        let [t, b, axis] = self.frame;
        let n = (y - self.c).normalize();
        let a = 0.5 * (n - axis).length_squared() / self.omc_max;
        let phi = n.dot(b).atan2(n.dot(t)).rem_euclid(2.0 * PI);
        (a <= 1.0).then_some((a, phi / (2.0 * PI)))
    }

    /// Chart density of a solid-angle pdf given as a function of the point and its normal:
    /// pdf * cos_y / |x - y|^2 * dA/d(a, b), dA/d(a, b) = r^2 (1 - r/d) 2 pi.
    fn density<'a>(&'a self, pdf: impl Fn(Vec3, Vec3) -> f64 + 'a) -> impl Fn(f64, f64) -> f64 + 'a {
        move |a, b| {
            let [t, bt, axis] = self.frame;
            let omc = a * self.omc_max;
            let sin = (omc * (2.0 - omc)).sqrt();
            let (sp, cp) = (b * 2.0 * PI).sin_cos();
            let n = t * (sin * cp) + bt * (sin * sp) + axis * (1.0 - omc);
            let y = self.c + n * self.r;
            let v = self.x - y;
            let d2 = v.length_squared();
            let cos_y = n.dot(v) / d2.sqrt();
            pdf(f3(y), f3(n)) * cos_y / d2 * self.r * self.r * self.omc_max * 2.0 * PI
        }
    }
}

/// A parallelogram light charted by its own (s, t) coordinates.
struct QuadChart {
    x: DVec3,
    p0: DVec3,
    e1: DVec3,
    e2: DVec3,
    n: DVec3,
    w: DVec3,
    area: f64,
}

impl QuadChart {
    fn new(x: Vec3, corners: [Vec3; 4]) -> Self {
        let (p0, e1, e2) = (d3(corners[0]), d3(corners[1] - corners[0]), d3(corners[3] - corners[0]));
        let c = e1.cross(e2);
        Self { x: d3(x), p0, e1, e2, n: c.normalize(), w: c * (1.0 / c.length_squared()), area: c.length() }
    }

    fn coords(&self, y: DVec3) -> Option<(f64, f64)> {
        let d = y - self.p0;
        let (s, t) = (d.cross(self.e2).dot(self.w), self.e1.cross(d).dot(self.w));
        ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)).then_some((s, t))
    }

    /// Chart density of a solid-angle pdf: pdf * cos_y / |x - y|^2 * area.
    fn density<'a>(&'a self, pdf: impl Fn(Vec3, Vec3) -> f64 + 'a) -> impl Fn(f64, f64) -> f64 + 'a {
        move |s, t| {
            let y = self.p0 + self.e1 * s + self.e2 * t;
            let v = self.x - y;
            let d2 = v.length_squared();
            let cos_y = self.n.dot(v).abs() / d2.sqrt();
            pdf(f3(y), f3(self.n)) * cos_y / d2 * self.area
        }
    }
}

/// A scene whose only light is one emitting shape.
type OneLightScene = Scene<1, 1, 1>;

/// The light of a [`OneLightScene`].
const LIGHT: LightId = LightId::new(0);

/// The light sampler of a [`OneLightScene`] drawing on spheres by `Sp` (quads by area, no lobe
/// mixing): a light's own sampling technique, `sample` / `pdf` of the one light.
type OneLightSampler<'a, Sp> = LightSampler<'a, Lights<Uniform, Sp, quad::ByArea, lobe::Off>, 1, 1, 1>;

/// An emitting shape (radiance 1) as the only light of a scene.
struct OneLight {
    scene: OneLightScene,
}

impl OneLight {
    fn new(shape: Shape) -> Self {
        let mut scene: OneLightScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
        let black = scene.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
        let id = scene.add_shape(shape, black).unwrap();
        scene.add_area_light(id, Rgb::ONE).unwrap();
        OneLight { scene }
    }

    /// The emitting shape.
    fn shape(&self) -> &Shape {
        &self.scene.objects()[0].shape
    }

    /// The light's sampler drawing on spheres by `Sp`.
    fn sampler<Sp: SphereSampler>(&self) -> OneLightSampler<'_, Sp> {
        LightSampler::new(&self.scene)
    }
}

/// The shading point at `x` as the light sampler sees it: with spheres by area or cone, quads by
/// area and no lobe mixing, a light sample depends on its position alone.
fn at(x: Vec3) -> ShadingPoint {
    ShadingPoint { p: x, n: Vec3::Y, wo: Vec3::Y, bsdf: Material::lambertian(Rgb::ONE).unwrap() }
}

/// An emitting sphere as the only light of a scene, and its shape.
fn sphere_light(c: Vec3, r: f32) -> (OneLight, Shape) {
    let light = OneLight::new(Shape::sphere(c, r).unwrap());
    let shape = *light.shape();
    (light, shape)
}

/// Solid-angle pdf of a light's sampling technique at a direction from `x`, found as the kernel's
/// estimator finds it: trace the direction to the shape, then ask the sampler's `pdf` (0 on a
/// miss).
fn pdf_towards<Sp: SphereSampler>(
    lights: &OneLightSampler<'_, Sp>,
    shape: &Shape,
    x: Vec3,
    dir: DVec3,
) -> f64 {
    let ray = picomis::Ray { origin: x, dir: f3(dir.normalize()) };
    match shape.intersect(&ray, 0.0, f32::INFINITY) {
        Some(t) => {
            let p = ray.at(t);
            let y = SurfacePoint { p, n: shape.normal_at(p) };
            f64::from(lights.pdf(LIGHT, &at(x), &y))
        }
        None => 0.0,
    }
}

/// Point reached by a light sample: x + wi * distance (f64).
fn sample_point(x: Vec3, wi: Vec3, distance: f32) -> DVec3 {
    d3(x) + d3(wi) * f64::from(distance)
}

// ---------------------------------------------------------------------------------------------
// Chi-square: sampling routines of picomis::sampling

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

// ---------------------------------------------------------------------------------------------
// Chi-square: BSDF sampling through Material::sample / Material::pdf

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

fn direction(theta_deg: f32, phi_deg: f32) -> Vec3 {
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

// ---------------------------------------------------------------------------------------------
// Chi-square: a light's own sampling through LightSampler::sample / LightSampler::pdf (one light)

/// A shading point and a unit direction off every axis.
fn setup() -> (Vec3, Vec3) {
    (Vec3::new(0.3, -0.2, 0.1), Vec3::new(0.48, 0.8, -0.36).normalize())
}

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

/// A tilted parallelogram light facing the shading points of [`quad_points`], as the only light of
/// a scene, its shape and its corners.
fn quad_light() -> (OneLight, Shape, [Vec3; 4]) {
    let corners =
        quad_corners(Vec3::new(-0.6, 1.5, 0.8), Vec3::new(0.0, 0.3, -1.4), Vec3::new(1.1, 0.2, 0.1));
    let shape = Shape::quad(corners).unwrap();
    (OneLight::new(shape), shape, corners)
}

fn quad_points() -> [Vec3; 2] {
    [Vec3::new(0.1, 0.0, -0.2), Vec3::new(1.5, 0.5, 2.0)]
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

// ---------------------------------------------------------------------------------------------
// Chi-square: the light sampler, LightSampler::select / pmf and sample / pdf

type LightScene = Scene<4, 5, 1>;

/// A sphere light, a quad light, a point light and a dark point light, of different powers.
fn light_scene() -> LightScene {
    let mut s: LightScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let sphere = s.add_shape(Shape::sphere(Vec3::new(-1.0, 2.0, 0.5), 0.4).unwrap(), black).unwrap();
    s.add_area_light(sphere, Rgb::new(3.0, 2.0, 1.0)).unwrap();
    let (_, quad, _) = quad_light();
    let q = s.add_shape(quad, black).unwrap();
    s.add_area_light(q, Rgb::new(0.5, 1.0, 2.0)).unwrap();
    s.add_point_light(Vec3::new(1.0, 3.0, -1.0), Rgb::new(2.0, 2.0, 0.5)).unwrap();
    s.add_point_light(Vec3::new(0.0, 3.0, 0.0), Rgb::ZERO).unwrap();
    s
}

/// Power of each light of [`light_scene`], computed independently: pi L A (area lights),
/// 4 pi I (point lights), the mean of each one's channels.
fn light_powers(s: &LightScene) -> Vec<f64> {
    s.lights()
        .iter()
        .map(|l| match l {
            Light::Area { radiance, .. } => {
                PI * channel_mean(*radiance) * f64::from(s.light_shape(l).unwrap().area())
            }
            Light::Point { intensity, .. } => 4.0 * PI * channel_mean(*intensity),
        })
        .collect()
}

/// Each light's importance at a receiver at `x` with normal `n`, computed independently in
/// f64 from its documented formula: the channel mean of the radiance times the solid angle (spheres:
/// pi r^2 / d^2; quads: A cos / d^2) times min(1, cos theta + sin theta_max), theta the angle
/// between `n` and the direction to the light's centre, theta_max the half-angle of its bounding
/// cone; the channel mean of the intensity times the cosine over d^2 for point lights.
fn light_importances(s: &LightScene, x: DVec3, n: DVec3) -> Vec<f64> {
    let cosine = |axis: DVec3, sin_max: f64| (axis.dot(n) + sin_max).clamp(0.0, 1.0);
    s.lights()
        .iter()
        .map(|l| match l {
            Light::Area { radiance, .. } => {
                let shape = s.light_shape(l).unwrap();
                let v = d3(shape.centroid()) - x;
                let (d, r) = (v.length(), f64::from(shape.bounding_radius()));
                let solid_angle = match shape.as_sphere() {
                    Some(_) => PI * (r / d).powi(2),
                    None => {
                        f64::from(shape.area()) * d3(shape.normal_at(shape.centroid())).dot(-v) / d.powi(3)
                    }
                };
                channel_mean(*radiance) * solid_angle * cosine(v * (1.0 / d), r / d)
            }
            Light::Point { position, intensity } => {
                let v = d3(*position) - x;
                channel_mean(*intensity) * cosine(v.normalize(), 0.0) / v.length_squared()
            }
        })
        .collect()
}

#[test]
fn chi2_light_selection() {
    let s = light_scene();
    let powers = light_powers(&s);
    let total: f64 = powers.iter().sum();
    // A Lambertian receiver: selection by contribution is by importance (f cos is albedo / pi
    // times the largest cosine for every light).
    let importance = light_importances(&s, DVec3::ZERO, DVec3::Y);
    let total_importance: f64 = importance.iter().sum();
    for (k, selection) in LightSelection::ALL.into_iter().enumerate() {
        let (exact, tolerance): (Vec<f64>, f64) = match selection {
            LightSelection::Uniform => (vec![0.25; 4], 1e-6),
            LightSelection::Power => (powers.iter().map(|p| p / total).collect(), 1e-6),
            // f32 arithmetic against f64.
            LightSelection::Contribution => (importance.iter().map(|p| p / total_importance).collect(), 1e-4),
        };
        match selection {
            LightSelection::Uniform => check_selection::<Uniform>(&s, k as u32, &exact, tolerance),
            LightSelection::Power => check_selection::<ByPower<5>>(&s, k as u32, &exact, tolerance),
            LightSelection::Contribution => {
                check_selection::<ByContribution<5>>(&s, k as u32, &exact, tolerance)
            }
        }
    }
}

/// One selection `Sel` of [`chi2_light_selection`]: its pmf at a Lambertian receiver at the
/// origin against `exact` (to `tolerance`), and its choices against its pmf (chi-square).
fn check_selection<Sel: Select<5>>(s: &LightScene, k: u32, exact: &[f64], tolerance: f64) {
    let selection = Sel::KIND;
    let lights = LightSampler::<Lights<Sel, InCone, quad::ByArea, lobe::Off>, 4, 5, 1>::new(s);
    let bsdf = Material::lambertian(Rgb::splat(0.5)).unwrap();
    let at = lights.selection_at(&ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo: Vec3::Y, bsdf });
    for (i, e) in exact.iter().enumerate() {
        let p = f64::from(lights.pmf(&at, LightId::new(i as u16)));
        assert!((p - e).abs() < tolerance * e.max(1.0), "{selection:?}: P(light {i}) = {p}, expected {e}");
    }
    let mut rng = Sampler::new(200 + k, 0, 0);
    let mut observed = vec![0.0; 4];
    for _ in 0..N_CHI2 {
        let chosen = lights.select(&at, rng.next_f32()).unwrap();
        assert_eq!(chosen.probability, lights.pmf(&at, chosen.light));
        observed[chosen.light.index()] += 1.0;
    }
    let expected: Vec<f64> = exact.iter().map(|p| p * N_CHI2 as f64).collect();
    assert_chi2(&format!("light selection {selection:?}"), &observed, &expected, CHI2_TESTS);
}

/// Light selection by power is exact: every light is chosen with exactly the probability the
/// MIS weights are given (`pmf`), counted over all 2^24 values the sampler's random number takes,
/// even where the powers span 14 orders of magnitude (a share of 1e-14 is far below one grid
/// value, 6e-8: before the grid distribution such a light was never chosen while its pmf still
/// lowered the BSDF samples' weights, so its light went missing).
#[test]
fn power_selection_realises_its_pmf_exactly() {
    let powers = [1e-9f32, 1e5, 1e-6, 1.0, 1e-3, 1e3, 1e-9];
    let mut s: Scene<1, 7, 1> = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    for (i, p) in powers.iter().enumerate() {
        let intensity = Rgb::splat(p / (4.0 * std::f32::consts::PI));
        s.add_point_light(Vec3::new(i as f32, 3.0, 0.0), intensity).unwrap();
    }
    let lights = LightSampler::<Lights<ByPower<7>, InCone, quad::ByArea, lobe::Off>, 1, 7, 1>::new(&s);
    let bsdf = Material::lambertian(Rgb::ONE).unwrap();
    // (By power the selection does not depend on the point: what it reads there is `()`.)
    #[allow(clippy::let_unit_value)]
    let at = lights.selection_at(&ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo: Vec3::Y, bsdf });
    const GRID: u32 = 1 << 24;
    let mut counts = [0u64; 7];
    for k in 0..GRID {
        // Exactly the values `Sampler::next_f32` returns.
        let chosen = lights.select(&at, k as f32 / GRID as f32).unwrap();
        counts[chosen.light.index()] += 1;
    }
    let total: f64 = powers.iter().map(|&p| f64::from(p)).sum();
    for (i, &c) in counts.iter().enumerate() {
        let pmf = f64::from(lights.pmf(&at, LightId::new(i as u16)));
        let realised = c as f64 / f64::from(GRID);
        assert_eq!(realised, pmf, "light {i} (power {:e}): chosen {c} times", powers[i]);
        assert!(c > 0, "light {i} (power {:e}) is never chosen", powers[i]);
        // Each share is rounded to the grid (at least one value); the largest light takes the
        // rounding of all, at most one grid value per light.
        let share = f64::from(powers[i]) / total;
        let tolerance = powers.len() as f64 / f64::from(GRID);
        assert!((pmf - share).abs() <= tolerance, "light {i}: pmf {pmf:e}, share {share:e}");
    }
}

#[test]
fn chi2_scene_light_sampling() {
    // The light sampler's selection then a point, against pmf x pdf (the light technique's pdf
    // p_l = P(light) p_w): one chart per area light, one cell per point light, one for "no sample".
    let s = light_scene();
    let mut k = 0;
    for spheres in [SphereSampling::Cone, SphereSampling::Area] {
        for selection in LightSelection::ALL {
            k += 1;
            LightChoices::new(selection, spheres).visit(SceneLightSampling { s: &s, spheres, selection, k });
        }
    }
}

/// One case of [`chi2_scene_light_sampling`] (the `k`-th), with the light sampler's strategies
/// as a type.
struct SceneLightSampling<'a> {
    s: &'a LightScene,
    spheres: SphereSampling,
    selection: LightSelection,
    k: u32,
}

impl VisitLights<5> for SceneLightSampling<'_> {
    type Output = ();
    fn visit<Lt: LightStrategies<5>>(self) {
        scene_light_sampling::<Lt>(self.s, self.spheres, self.selection, self.k);
    }
}

fn scene_light_sampling<Lt: LightStrategies<5>>(
    s: &LightScene,
    spheres: SphereSampling,
    selection: LightSelection,
    k: u32,
) {
    let x = Vec3::new(0.2, 0.0, 0.3);
    let sphere = s.objects()[0].shape;
    let (c, r) = sphere.as_sphere().unwrap();
    let cone = Cap::new(d3(c) - d3(x), 1.25 * (f64::from(r) / (d3(c) - d3(x)).length()).asin());
    let cap = VisibleCap::new(x, c, r);
    let quad_chart = QuadChart::new(x, quad_light().2);
    let label = format!("scene light sampling {spheres:?} {selection:?}");
    let mut hs = Histogram2d::new(40, 64);
    let mut hq = Histogram2d::new(24, 24);
    let (mut point, mut none) = ([0.0; 2], 0.0);
    let lights = LightSampler::<Lt, 4, 5, 1>::new(s);
    let bsdf = Material::lambertian(Rgb::ONE).unwrap();
    let shading = ShadingPoint { p: x, n: Vec3::Y, wo: Vec3::Y, bsdf };
    let at = lights.selection_at(&shading);
    let mut rng = Sampler::new(300 + k, 0, 0);
    for _ in 0..N_CHI2 {
        let u_select = rng.next_f32();
        let u = rng.next_2d();
        let chosen = lights.select(&at, u_select).unwrap();
        let sample = lights.sample(chosen.light, &shading, u);
        match sample.map(|ls| (ls, ls.emitter.map(ShapeId::index))) {
            Some((ls, Some(0))) => match spheres {
                SphereSampling::Cone => hs.add(cone.coords(d3(ls.wi))),
                SphereSampling::Area => hs.add(cap.coords(sample_point(x, ls.wi, ls.distance))),
            },
            Some((ls, Some(_))) => hq.add(quad_chart.coords(sample_point(x, ls.wi, ls.distance))),
            Some((ls, None)) => {
                // A point light (the bright one, or the dark one under uniform
                // selection): a delta light whose pdf is its selection probability.
                assert!(ls.delta && ls.pdf == 1.0);
                let i = if ls.radiance == Rgb::ZERO { 3 } else { 2 };
                assert_eq!(chosen.light, LightId::new(i), "{label}");
                point[usize::from(i) - 2] += 1.0;
            }
            None => none += 1.0,
        }
    }
    let n = N_CHI2 as f64;
    let pdf_at = |light: u16, p: Vec3, nrm: Vec3| {
        let light = LightId::new(light);
        let p_omega = lights.pdf(light, &shading, &SurfacePoint { p, n: nrm });
        f64::from(lights.pmf(&at, light)) * f64::from(p_omega)
    };
    let (es, ts) = match spheres {
        SphereSampling::Cone => {
            let ray_pdf = |w: DVec3| {
                let ray = picomis::Ray { origin: x, dir: f3(w) };
                sphere.intersect(&ray, 0.0, f32::INFINITY).map_or(0.0, |t| {
                    let p = ray.at(t);
                    pdf_at(0, p, sphere.normal_at(p))
                })
            };
            hs.cell_expectations(n, cone.density(ray_pdf))
        }
        SphereSampling::Area => hs.cell_expectations(n, cap.density(|p, nrm| pdf_at(0, p, nrm))),
    };
    let (eq, tq) = hq.cell_expectations(n, quad_chart.density(|p, nrm| pdf_at(1, p, nrm)));
    let p_point = [2, 3].map(|i| n * f64::from(lights.pmf(&at, LightId::new(i))));
    let mut observed = hs.observed[..=hs.cells()].to_vec();
    observed.extend_from_slice(&hq.observed[..=hq.cells()]);
    observed.extend_from_slice(&[point[0], point[1], none]);
    let mut expected = es[..=hs.cells()].to_vec();
    expected.extend_from_slice(&eq[..=hq.cells()]);
    expected.extend_from_slice(&[
        p_point[0],
        p_point[1],
        (n * (1.0 - ts - tq) - p_point[0] - p_point[1]).max(0.0),
    ]);
    assert_chi2(&label, &observed, &expected, CHI2_TESTS);
}

// ---------------------------------------------------------------------------------------------
// E[1/p(X)] = measure of the support

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

// ---------------------------------------------------------------------------------------------
// The chi-square tests above can fail

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
