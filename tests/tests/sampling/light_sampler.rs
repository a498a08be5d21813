//! Chi-square: the light sampler of a scene of four lights, `LightSampler::select` against `pmf`
//! for every selection (and selection by power realising its pmf exactly), and `sample` against
//! pmf x pdf.

use crate::charts::{QuadChart, VisibleCap};
use crate::one_light::{quad_light, sample_point};
use crate::{CHI2_TESTS, N_CHI2};
use picomis::light::select::{ByContribution, ByPower, Every, Uniform};
use picomis::light::sphere::InCone;
use picomis::light::{LightStrategies, Lights, Select, lobe, quad};
use picomis::{
    Film, Light, LightId, LightSampler, LightSelection, Material, Rgb, Sampler, Scene, ShadingPoint, Shape,
    ShapeId, SphereSampling, SurfacePoint, Vec3,
};
use picomis_tests::{
    Cap, DVec3, Histogram2d, LightChoices, VisitLights, assert_chi2, camera, channel_mean, d3, f3,
};
use std::f64::consts::PI;

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
            // No choice: every light is sampled, each with probability one (checked below).
            LightSelection::Every => (vec![1.0; 4], 0.0),
        };
        match selection {
            LightSelection::Uniform => check_selection::<Uniform>(&s, k as u32, &exact, tolerance),
            LightSelection::Power => check_selection::<ByPower<5>>(&s, k as u32, &exact, tolerance),
            LightSelection::Contribution => {
                check_selection::<ByContribution<5>>(&s, k as u32, &exact, tolerance)
            }
            LightSelection::Every => check_every(&s, &exact),
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

/// [`Every`] chooses no light and gives each of the scene's lights probability one (`exact`),
/// none beyond them.
fn check_every(s: &LightScene, exact: &[f64]) {
    let lights = LightSampler::<Lights<Every, InCone, quad::ByArea, lobe::Off>, 4, 5, 1>::new(s);
    let bsdf = Material::lambertian(Rgb::splat(0.5)).unwrap();
    let at = lights.selection_at(&ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo: Vec3::Y, bsdf });
    for (i, e) in exact.iter().enumerate() {
        assert_eq!(f64::from(lights.pmf(&at, LightId::new(i as u16))), *e, "P(light {i})");
    }
    assert_eq!(lights.pmf(&at, LightId::new(exact.len() as u16)), 0.0, "beyond the lights");
    assert!(lights.select(&at, 0.5).is_none(), "every: no choice");
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
        // (`every` chooses no light: each light's sampling is the one checked here under the
        // other selections, and its pmf of one in `chi2_light_selection`.)
        for selection in LightSelection::ALL.into_iter().filter(|&s| s != LightSelection::Every) {
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
