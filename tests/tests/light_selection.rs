//! Light selection by contribution, where the probabilities depend on the shading point and the
//! BSDF (unbiasedness of the estimates it feeds is checked in tests/tests/unbiased.rs):
//!
//! 1. exactness: over all 2^24 values of the random number, `select` chooses each light exactly
//!    as often as `pmf` says, at shading points on Lambertian and near-mirror GGX receivers;
//! 2. no zero probability for a light that contributes: at 3,000 random shading points (random
//!    normal, view direction and BSDF: Lambertian or GGX, alpha 1e-3 to 1) every light of which
//!    one of 64 light samples carries f L > 0 (visibility aside) has pmf > 0;
//! 3. W1 across the techniques: for each light sample drawn at those points, the weight the
//!    light sample gets (from the probability `select` reported) and the weight a BSDF sample
//!    in the same direction gets (from `pmf`, as the estimator computes it) sum to one, for every
//!    heuristic.
//!
//! 4. at the extremes of the scene's range, with every selection strategy: lights at the emission
//!    cap ([`MAX_EMISSION`], 1e20) seen from 1e-12 (their strengths and the sum of the weights
//!    beyond f32) or from 1e-9 (a sum near f32's largest) beside faint lights, and lights 1e-34
//!    bright alone (a sum too small for the grid's scale): every light keeps a positive
//!    probability, the probabilities sum to one, and `select` realises them exactly.
//!
//! Scene: sphere lights straddling the horizon, tiny and big; a quad light seen from both sides;
//! a bright and a dark point light.

use picomis::light::select::{ByContribution, ByPower, Uniform};
use picomis::light::{Select, lobe, quad, sphere};
use picomis::num::Frame;
use picomis::sampling::sample_uniform_sphere;
use picomis::{
    Film, Heuristic, LightId, LightSampler, Lights, MAX_EMISSION, Material, Method, Rgb, Sampler, Scene,
    ShadingPoint, Shape, SurfacePoint, Technique, Vec3,
};
use picomis_tests::{camera, heuristics, quad_corners};

type LightScene = Scene<5, 6, 1>;

fn scene() -> LightScene {
    let mut s: LightScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let spheres = [
        (Vec3::new(2.0, 0.2, 0.0), 0.5, Rgb::new(4.0, 2.0, 1.0)),
        (Vec3::new(0.0, 3.0, 1.0), 1e-3, Rgb::splat(1e5)),
        (Vec3::new(-4.0, 3.0, -1.0), 2.0, Rgb::new(0.5, 0.5, 1.0)),
    ];
    for (c, r, l) in spheres {
        let id = s.add_shape(Shape::sphere(c, r).unwrap(), black).unwrap();
        s.add_area_light(id, l).unwrap();
    }
    let corners = quad_corners(Vec3::new(-1.0, 1.5, 2.0), Vec3::new(2.0, 0.5, 0.0), Vec3::new(0.0, 0.8, 1.5));
    let q = s.add_shape(Shape::quad(corners).unwrap(), black).unwrap();
    s.add_area_light(q, Rgb::new(1.0, 3.0, 2.0)).unwrap();
    s.add_point_light(Vec3::new(1.0, 2.0, -2.0), Rgb::splat(5.0)).unwrap();
    s.add_point_light(Vec3::new(-1.0, 2.0, -2.0), Rgb::ZERO).unwrap();
    s
}

fn ggx(alpha: f32) -> Material {
    Material::ggx_conductor(alpha, Rgb::new(0.9, 0.7, 0.5)).unwrap()
}

/// Light sampling by contribution (spheres in their cone, quads by area, no lobe mixing).
type ByContributionSampler<'a> =
    LightSampler<'a, Lights<ByContribution<6>, sphere::InCone, quad::ByArea, lobe::Off>, 5, 6, 1>;

/// Light sampling by contribution in `s`.
fn by_contribution(s: &LightScene) -> ByContributionSampler<'_> {
    LightSampler::new(s)
}

#[test]
fn contribution_selection_realises_its_pmf_exactly() {
    let s = scene();
    let lights = by_contribution(&s);
    let wo = Vec3::new(-0.5, 0.75, 0.1).normalize();
    let points = [
        ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo, bsdf: Material::lambertian(Rgb::splat(0.5)).unwrap() },
        ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo, bsdf: ggx(1e-3) },
        ShadingPoint {
            p: Vec3::new(0.5, 0.0, 1.0),
            n: Vec3::new(0.3, 1.0, 0.0).normalize(),
            wo,
            bsdf: ggx(0.2),
        },
        ShadingPoint { p: Vec3::new(0.0, 2.0, 3.0), n: -Vec3::Z, wo: -Vec3::Z, bsdf: ggx(0.05) },
    ];
    const GRID: u32 = 1 << 24;
    for (k, point) in points.iter().enumerate() {
        let at = lights.selection_at(point);
        let mut counts = [0u64; 6];
        for u in 0..GRID {
            // Exactly the values `Sampler::next_f32` returns.
            let chosen = lights.select(&at, u as f32 / GRID as f32).unwrap();
            assert_eq!(chosen.probability, lights.pmf(&at, chosen.light), "point {k}");
            counts[chosen.light.index()] += 1;
        }
        let mut total = 0.0;
        for (i, &c) in counts.iter().enumerate() {
            let pmf = f64::from(lights.pmf(&at, LightId::new(i as u16)));
            assert_eq!(c as f64 / f64::from(GRID), pmf, "point {k}, light {i}: chosen {c} times");
            total += pmf;
        }
        assert_eq!(total, 1.0, "point {k}");
        // The dark point light is never chosen; several lights are.
        assert_eq!(counts[5], 0, "point {k}");
        assert!(counts.iter().filter(|&&c| c > 0).count() >= 2, "point {k}: {counts:?}");
        println!("point {k}: pmf {:?}", (0..6).map(|i| lights.pmf(&at, LightId::new(i))).collect::<Vec<_>>());
    }
    // The BSDF moves the probabilities: the near-mirror receiver favours other lights than the
    // Lambertian one at the same point.
    let (a, b) = (lights.selection_at(&points[0]), lights.selection_at(&points[1]));
    let moved: f32 =
        (0..6).map(|i| (lights.pmf(&a, LightId::new(i)) - lights.pmf(&b, LightId::new(i))).abs()).sum();
    assert!(moved > 0.2, "the BSDF changed the probabilities by {moved} only");
}

/// A random shading point: position near the lights, any normal, a view direction above it, and
/// a Lambertian or GGX (alpha 1e-3 to 1) receiver.
fn random_point(rng: &mut Sampler) -> ShadingPoint {
    let u = rng.next_2d();
    let p = Vec3::new(6.0 * u.x - 3.0, rng.next_f32() - 0.5, 6.0 * u.y - 3.0);
    let n = sample_uniform_sphere(rng.next_2d());
    let w = sample_uniform_sphere(rng.next_2d());
    let wo = if w.dot(n) > 0.0 { w } else { -w };
    let bsdf = match rng.next_f32() {
        x if x < 0.3 => Material::lambertian(Rgb::splat(0.6)).unwrap(),
        _ => ggx(10f32.powf(-3.0 * rng.next_f32())),
    };
    ShadingPoint { p, n, wo, bsdf }
}

#[test]
fn every_light_that_contributes_can_be_chosen() {
    let s = scene();
    let lights = by_contribution(&s);
    let mut rng = Sampler::new(13, 0, 0);
    let (mut contributing, mut points) = (0, 0);
    for _ in 0..3000 {
        let point = random_point(&mut rng);
        let frame = Frame::from_normal(point.n);
        let wo = frame.to_local(point.wo);
        let at = lights.selection_at(&point);
        for i in 0..6 {
            let light = LightId::new(i);
            let contributes = (0..64).any(|_| {
                lights.sample(light, &point, rng.next_2d()).is_some_and(|ls| {
                    let f = point.bsdf.eval(wo, frame.to_local(ls.wi)) * ls.radiance;
                    f.max_element() > 0.0
                })
            });
            if contributes {
                contributing += 1;
                let pmf = lights.pmf(&at, light);
                assert!(pmf > 0.0, "light {i} contributes at {point:?} but its pmf is {pmf}");
            }
        }
        points += 1;
    }
    // Not vacuous: most points see several contributing lights.
    assert!(contributing > 2 * points, "{contributing} contributing lights at {points} points");
}

#[test]
fn the_light_and_bsdf_weights_of_a_direction_sum_to_one() {
    let s = scene();
    let lights = by_contribution(&s);
    let mut rng = Sampler::new(14, 0, 0);
    let mut checked = 0;
    for _ in 0..3000 {
        let point = random_point(&mut rng);
        let frame = Frame::from_normal(point.n);
        let wo = frame.to_local(point.wo);
        let at = lights.selection_at(&point);
        let Some(chosen) = lights.select(&at, rng.next_f32()) else { continue };
        let Some(ls) = lights.sample(chosen.light, &point, rng.next_2d()) else { continue };
        let (f, p_bsdf) = point.bsdf.eval_pdf(wo, frame.to_local(ls.wi));
        if ls.delta || f == Rgb::ZERO {
            continue;
        }
        // The light sample's own pdf, as `light_sample` computes it.
        let q_light = chosen.probability * ls.pdf;
        // The same direction as a BSDF sample would see it: the pmf of the light it hits.
        let shape = s.light_shape(s.light(chosen.light).unwrap()).unwrap();
        let p = point.p + ls.wi * ls.distance;
        let y = SurfacePoint { p, n: shape.normal_at(p) };
        let q_light_seen_by_bsdf = lights.pmf(&at, chosen.light) * lights.pdf(chosen.light, &point, &y);
        for h in heuristics().into_iter().chain([Heuristic::Power { beta: 2.0 }]) {
            let m = Method::Mis(h);
            let w_light = m.weight(Technique::Light, q_light, p_bsdf);
            let w_bsdf = m.weight(Technique::Bsdf, q_light_seen_by_bsdf, p_bsdf);
            let sum = w_light + w_bsdf;
            assert!(
                (sum - 1.0).abs() < 1e-3,
                "{h:?} at {point:?}, light {:?}: w_light {w_light} + w_bsdf {w_bsdf} = {sum}",
                chosen.light
            );
        }
        checked += 1;
    }
    assert!(checked > 1000, "only {checked} light samples checked");
}

/// Scenes at the extremes of the range, each light above the origin's horizon.
type ExtremeScene = Scene<1, 4, 1>;

/// `cap` point lights at the emission cap, 1e-12 (or `d`) above the origin and as far apart, and
/// two faint lights far above: a point light of intensity 1 at 3,000 (importance 1.1e-7 at the
/// origin) and a sphere light of radiance 1 and radius 1 at 3,000 (3.3e-7).
fn cap_scene(cap: usize, d: f32) -> ExtremeScene {
    let mut s: ExtremeScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    for k in 0..cap {
        s.add_point_light(Vec3::new(k as f32 * d, d, 0.0), Rgb::splat(MAX_EMISSION)).unwrap();
    }
    s.add_point_light(Vec3::new(0.0, 3000.0, 0.0), Rgb::ONE).unwrap();
    let id = s.add_shape(Shape::sphere(Vec3::new(1000.0, 3000.0, 0.0), 1.0).unwrap(), black).unwrap();
    s.add_area_light(id, Rgb::ONE).unwrap();
    s
}

/// Three point lights of intensity 1e-34 and a sphere light of radiance 1e-34 around the
/// origin: the sums of their powers (5e-33) and importances (4e-34) are below 2^-104, where
/// 2^24 / sum is beyond f32.
fn faint_scene() -> ExtremeScene {
    let mut s: ExtremeScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let faint = Rgb::splat(1e-34);
    for x in [-1.0, 0.0, 1.0] {
        s.add_point_light(Vec3::new(x, 1.0, 0.5), faint).unwrap();
    }
    let id = s.add_shape(Shape::sphere(Vec3::new(0.0, 2.0, -1.0), 0.5).unwrap(), black).unwrap();
    s.add_area_light(id, faint).unwrap();
    s
}

/// Every light of `s` (all above the origin's horizon, all emitting) keeps a positive probability
/// under selection `Sel` at the origin (normal +y, seen from +y) of a Lambertian, a near-mirror
/// and a rough GGX receiver; the probabilities sum to one, and over all 2^24 values of the
/// random number `select` chooses each light as often as `pmf` says (exactly, but for uniform's
/// rounding of 1 / n).
fn every_light_keeps_its_probability<Sel: Select<4>>(label: &str, s: &ExtremeScene) {
    let lights = LightSampler::<Lights<Sel, sphere::InCone, quad::ByArea, lobe::Off>, 1, 4, 1>::new(s);
    const GRID: u32 = 1 << 24;
    let n = s.lights().len();
    for bsdf in [Material::lambertian(Rgb::splat(0.5)).unwrap(), ggx(1e-2), ggx(0.5)] {
        let point = ShadingPoint { p: Vec3::ZERO, n: Vec3::Y, wo: Vec3::Y, bsdf };
        let at = lights.selection_at(&point);
        let pmf: Vec<f32> = (0..n).map(|i| lights.pmf(&at, LightId::new(i as u16))).collect();
        let label = format!("{label}, {:?}, {bsdf:?}: pmf {pmf:?}", Sel::KIND);
        assert!(pmf.iter().all(|&p| p > 0.0), "{label}: a light without a probability");
        // Exactly for the grid's distributions; uniform's 1 / n to within f32's rounding.
        assert!((pmf.iter().map(|&p| f64::from(p)).sum::<f64>() - 1.0).abs() < 1e-6, "{label}");
        let mut counts = vec![0u32; n];
        for u in 0..GRID {
            let chosen =
                lights.select(&at, u as f32 / GRID as f32).unwrap_or_else(|| panic!("{label}: none"));
            assert_eq!(chosen.probability, pmf[chosen.light.index()], "{label}");
            counts[chosen.light.index()] += 1;
        }
        for (i, &c) in counts.iter().enumerate() {
            // Exactly for the grid's distributions (selection by power and by contribution);
            // within one value of the grid for uniform's 1 / n.
            let off = (f64::from(c) - f64::from(pmf[i]) * f64::from(GRID)).abs();
            assert!(off < 1.0, "{label}, light {i}: chosen {c} times");
        }
    }
}

fn with_every_selection(label: &str, s: &ExtremeScene) {
    every_light_keeps_its_probability::<Uniform>(label, s);
    every_light_keeps_its_probability::<ByPower<4>>(label, s);
    every_light_keeps_its_probability::<ByContribution<4>>(label, s);
}

#[test]
fn every_light_keeps_a_probability_beside_lights_at_the_emission_cap() {
    // Two lights at the cap 1e-12 away: strengths 1e44, beyond f32, and so is the sum of the
    // weights. (Before the strengths were clamped, the lights at the cap had no cone and
    // probability zero; before the sum was divided by the largest weight, the floor share
    // vanished against it; with the division alone, the faint lights' weights, 1e-7 / 3.4e38,
    // rounded to zero.)
    with_every_selection("two lights at the cap 1e-12 away", &cap_scene(2, 1e-12));
    // One light at the cap 1e-9 away: a finite sum of 1e38, whose floor share 0.1 / 1e38 times
    // a faint light's 1e-7 rounds to zero on a GGX receiver unless kept.
    with_every_selection("one light at the cap 1e-9 away", &cap_scene(1, 1e-9));
}

#[test]
fn faint_lights_keep_their_probabilities() {
    // Before: 2^24 / sum was infinite, every share took the whole grid and the ends wrapped: the
    // probabilities summed to more than one and the first light was never chosen.
    with_every_selection("lights of 1e-34", &faint_scene());
}
