//! Property 2: pdfs and weights at random surface points: finite non-negative pdfs, each
//! technique's pdf positive where the other found light, light and BSDF samples' pdfs
//! re-evaluated, weights partitioning unity; and a test double showing the lobe-mixing check
//! can fail.

use crate::finite::finite_non_negative;
use crate::runner::{Tally, check_property, run_property};
use crate::scenes::{S, build, scene_spec, settings};
use picomis::light::lobe::{self, LOBE_SHARE, LobeSampler};
use picomis::light::quad::QuadSampler;
use picomis::light::sphere::SphereSampler;
use picomis::light::{LightStrategies, Lights};
use picomis::num::Frame;
use picomis::sampling::{sample_cosine_hemisphere, sample_uniform_sphere, spherical_rectangle_cosines};
use picomis::{
    Film, Light, LightId, LightSampler, LightSelection, LobeMixing, Material, QuadSampling, Ray,
    RenderSettings, Rgb, Sampler, Scene, ShadingPoint, Shape, ShapeId, SphereSampling, SurfacePoint, Vec3,
};
use picomis_host::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES};
use picomis_tests::{LightChoices, VisitLights, heuristics};
use proptest::prelude::*;
use proptest::test_runner::TestCaseResult;

/// The light sampler of a random scene with the strategies `Lt`.
type Sampling<'a, Lt> = LightSampler<'a, Lt, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

/// Every heuristic's weights on `q`: in [0, 1], 0 where q is 0 (W2), summing to 1 where some
/// q > 0 (W1); and the weighted contribution w[technique] `unweighted` of the sample (as the
/// estimator computes it) is finite and non-negative.
fn check_weights(q: [f32; 2], technique: usize, unweighted: Rgb, what: &str) -> TestCaseResult {
    for h in heuristics() {
        let w = h.weights(q);
        let c = unweighted * w[technique];
        prop_assert!(finite_non_negative(c), "{what}: {h:?} {q:?} -> {w:?}, contribution {c}");
        prop_assert!(
            w.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
            "{what}: {h:?} {q:?} -> {w:?}"
        );
        for (wi, qi) in w.iter().zip(q) {
            if qi.is_nan() || qi <= 0.0 {
                prop_assert_eq!(*wi, 0.0, "{}: W2 broken, {:?} {:?} -> {:?}", what, h, q, w);
            }
        }
        if q.iter().any(|&v| v > 0.0) {
            let sum = w[0] + w[1];
            prop_assert!((sum - 1.0).abs() <= 1e-5, "{what}: W1 broken, {h:?} {q:?} -> {w:?} (sum {sum})");
        }
    }
    Ok(())
}

fn pdf_ok(p: f32) -> bool {
    p.is_finite() && p >= 0.0
}

/// A view direction in the local frame: cosine-distributed, or grazing (cos down to 1e-6).
fn local_wo(rng: &mut Sampler) -> Vec3 {
    let w = sample_cosine_hemisphere(rng.next_2d());
    if rng.next_f32() < 0.25 {
        let cos = 10f32.powf(-6.0 * rng.next_f32());
        let s = (1.0 - cos * cos).sqrt();
        let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
        return Vec3::new(s * phi.cos(), s * phi.sin(), cos);
    }
    if w.z > 0.0 { w } else { Vec3::Z }
}

/// Checks the pdfs and weights at `points` random points on each object of `scene`, with the
/// light sampler of the settings' strategies (selection, sphere and quad sampling, lobe mixing).
fn check_pdfs(scene: &S, settings: &RenderSettings, points: u32, tally: &Tally) -> TestCaseResult {
    LightChoices::of(settings).visit(PdfCheck { scene, settings, points, tally, lobe_pdf: LobePdf::Kept })
}

/// Whether the light pdf the check re-evaluates is the light sampler's own, or a broken one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LobePdf {
    /// `LightSampler::pdf`: with lobe mixing, the mixture's.
    Kept,
    /// A test double of a wrong mixture: where the lobe joins the light samples, the samples are
    /// the mixture's but the pdf leaves out the lobe's part, (1 - LOBE_SHARE) p_light only (the
    /// light's own pdf read from the same strategies without lobe mixing). The check must fail.
    LeftOut,
}

/// [`check_pdfs`] with its light sampler's strategies as a type.
struct PdfCheck<'a> {
    scene: &'a S,
    settings: &'a RenderSettings,
    points: u32,
    tally: &'a Tally,
    lobe_pdf: LobePdf,
}

/// The light strategies `Lt` without lobe mixing: the light's own part of the mixture.
type OwnPart<Lt> = Lights<
    <Lt as LightStrategies<HOST_LIGHTS>>::Selection,
    <Lt as LightStrategies<HOST_LIGHTS>>::Spheres,
    <Lt as LightStrategies<HOST_LIGHTS>>::Quads,
    lobe::Off,
>;

impl VisitLights<HOST_LIGHTS> for PdfCheck<'_> {
    type Output = TestCaseResult;
    fn visit<Lt: LightStrategies<HOST_LIGHTS>>(self) -> TestCaseResult {
        let lights = Sampling::<Lt>::new(self.scene);
        let (settings, points, tally) = (self.settings, self.points, self.tally);
        match self.lobe_pdf {
            LobePdf::Kept => {
                check_pdfs_with(&lights, &|l, at, y| lights.pdf(l, at, y), settings, points, tally)
            }
            LobePdf::LeftOut => {
                let own = Sampling::<OwnPart<Lt>>::new(self.scene);
                let pdf = |l: LightId, at: &ShadingPoint, y: &SurfacePoint| {
                    let shape = self.scene.light(l).and_then(|light| self.scene.light_shape(light));
                    match shape.and_then(|shape| Lt::Lobe::towards::<Lt::Spheres, Lt::Quads>(shape, at)) {
                        Some(_) => (1.0 - LOBE_SHARE) * own.pdf(l, at, y),
                        None => lights.pdf(l, at, y),
                    }
                };
                check_pdfs_with(&lights, &pdf, settings, points, tally)
            }
        }
    }
}

/// The light pdf a check re-evaluates: light, shading point, the point found on the light.
type LightPdf<'a> = dyn Fn(LightId, &ShadingPoint, &SurfacePoint) -> f32 + 'a;

/// [`check_pdfs`] with the light sampler `lights` drawing the light samples and `light_pdf` evaluating
/// the light technique's pdf (`lights.pdf`, but for the test double of [`LobePdf::LeftOut`]).
fn check_pdfs_with<Lt: LightStrategies<HOST_LIGHTS>>(
    lights: &Sampling<'_, Lt>,
    light_pdf: &LightPdf<'_>,
    settings: &RenderSettings,
    points: u32,
    tally: &Tally,
) -> TestCaseResult {
    let scene = lights.scene();
    let (n_l, n_b) = settings.technique_samples();
    let counts = [(1.0, 1.0), (f32::from(n_l), f32::from(n_b))];
    let mut rng = Sampler::new(settings.seed(), 0x9DF, 0);
    for (object, o) in scene.objects().iter().enumerate() {
        let object = ShapeId::new(object as u16);
        let material = *scene.material(object).unwrap();
        for _ in 0..points {
            let y = o.shape.sample_area(rng.next_2d());
            let (p, frame) = (y.p, Frame::from_normal(y.n));
            let wo = local_wo(&mut rng);
            let at = format!("object {object:?} at {p} (n {}), wo {wo}", y.n);

            // Any direction, including below the surface.
            let wr = sample_uniform_sphere(rng.next_2d());
            let (f, pdf) = material.eval_pdf(wo, wr);
            prop_assert!(finite_non_negative(f) && pdf_ok(pdf), "{at}: eval_pdf({wr}) = {f}, {pdf}");
            prop_assert_eq!(pdf, material.pdf(wo, wr));

            // A light sample.
            let (u_select, u) = (rng.next_f32(), rng.next_2d());
            let point = ShadingPoint { p, n: y.n, wo: frame.to_world(wo), bsdf: material };
            let shading = lights.selection_at(&point);
            let chosen = lights.select(&shading, u_select);
            let sample = chosen.and_then(|c| Some((c, lights.sample(c.light, &point, u)?)));
            if let Some((chosen, ls)) = sample {
                let what = format!("{at}: light sample {ls:?} of {chosen:?}");
                prop_assert!(ls.pdf.is_finite() && ls.pdf > 0.0, "{what}: pdf");
                prop_assert_eq!(chosen.probability, lights.pmf(&shading, chosen.light));
                // The light technique's pdf: selection times the direction's pdf.
                let p_light = chosen.probability * ls.pdf;
                prop_assert!(p_light.is_finite() && p_light > 0.0, "{what}: pdf");
                prop_assert!(
                    finite_non_negative(ls.radiance) && ls.distance.is_finite() && ls.distance >= 0.0,
                    "{what}"
                );
                prop_assert!((ls.wi.length() - 1.0).abs() < 1e-3, "{what}: |wi| != 1");
                let (f, p_bsdf) = material.eval_pdf(wo, frame.to_local(ls.wi));
                prop_assert!(finite_non_negative(f) && pdf_ok(p_bsdf), "{what}: f {f}, BSDF pdf {p_bsdf}");
                prop_assert!(f == Rgb::ZERO || p_bsdf > 0.0, "{what}: f = {f} > 0 but the BSDF pdf is 0");
                let unweighted = f * ls.radiance / p_light;
                prop_assert!(finite_non_negative(unweighted), "{what}: f L / p = {unweighted}");
                if ls.delta {
                    prop_assert!(ls.emitter.is_none(), "{what}: a delta light on a shape");
                } else {
                    for (c_l, c_b) in counts {
                        check_weights([c_l * p_light, c_b * p_bsdf], 0, unweighted / c_l.max(1.0), &what)?;
                    }
                    let emitter = ls.emitter.and_then(|i| scene.emitter(i).map(|(l, _)| (i, l)));
                    prop_assert!(emitter.is_some(), "{what}: an area-light sample without its emitter");
                    if let Some((i, light)) = emitter {
                        prop_assert_eq!(light, chosen.light, "{}: the sample's emitter", what);
                        let shape = &scene.objects()[i.index()].shape;
                        tally.add(check_sample_pdf::<Lt>(light_pdf, shape, light, &point, &ls, &what)?);
                    }
                    if f != Rgb::ZERO {
                        tally.add("light sample with f > 0");
                    }
                }
            }

            // A BSDF sample, traced to the first emitter.
            let Some(bs) = material.sample(wo, rng.next_2d()) else { continue };
            let what = format!("{at}: BSDF sample {bs:?}");
            prop_assert!(bs.pdf.is_finite() && bs.pdf > 0.0 && bs.wi.z > 0.0, "{what}");
            prop_assert!(finite_non_negative(bs.weight), "{what}: weight");
            tally.add(check_bsdf_sample(&material, wo, &bs, &what)?);
            let ray = Ray { origin: p, dir: frame.to_world(bs.wi) };
            if let Some((hit, light, radiance)) = scene.emitter_hit(&ray, object) {
                let p_light = lights.pmf(&shading, light) * light_pdf(light, &point, &hit.point);
                prop_assert!(pdf_ok(p_light), "{what}: light pdf {p_light} at {hit:?}");
                if radiance != Rgb::ZERO {
                    prop_assert!(
                        p_light > 0.0,
                        "{what}: hit light {light:?} at {hit:?}, but its light pdf is 0"
                    );
                    tally.add("BSDF sample hitting a light");
                    if matches!(material, Material::GgxConductor { alpha, .. } if alpha < 1e-3) {
                        tally.add("BSDF sample hitting a light, GGX alpha < 1e-3");
                    }
                }
                for (c_l, c_b) in counts {
                    check_weights(
                        [c_l * p_light, c_b * bs.pdf],
                        1,
                        bs.weight * radiance / c_b.max(1.0),
                        &what,
                    )?;
                }
            }
        }
    }
    Ok(())
}

/// A BSDF sample's pdf and weight re-evaluated by `Material::eval_pdf` at the direction it
/// drew: the pdf the light technique's weights use must be the one the sample was drawn with,
/// and weight = f cos / pdf (for GGX R G1(wi): D cancels, so this holds to rounding).
///
/// The pdf can only agree to the rounding of the direction: eval_pdf recomputes the half vector
/// from wo + wi, whose components carry ~2.4e-7 of rounding, so its direction is known to
/// delta ~ 2.4e-7 / |wo + wi| rad (far worse than 1e-7 for grazing reflections, where wo + wi
/// nearly cancels). With t = tan(theta_m) / alpha, D is proportional to 1 / (1 + t^2)^2; moving
/// t by T = delta / alpha changes D by a factor of at most (1 + T + T^2)^2 (here with twice
/// that delta, for safety).
pub fn check_bsdf_sample(
    material: &Material,
    wo: Vec3,
    bs: &picomis::BsdfSample,
    what: &str,
) -> Result<&'static str, TestCaseError> {
    let (f, pdf) = material.eval_pdf(wo, bs.wi);
    let alpha = match *material {
        Material::GgxConductor { alpha, .. } => alpha,
        Material::Lambertian { .. } => 1.0,
    };
    let t = 2.0 * 2.4e-7 / ((wo + bs.wi).length() * alpha);
    let tol = (1.0 + t + t * t).powi(2) - 1.0 + 1e-4;
    let rel = (pdf / bs.pdf - 1.0).abs();
    prop_assert!(rel <= tol, "{what}: eval_pdf gives pdf {pdf} (rel {rel:e} > {tol:e})");
    if f.min_element() > 1e-30 {
        let weight = f / pdf;
        let rel = ((weight - bs.weight).abs() / weight).max_element();
        prop_assert!(rel <= 1e-4, "{what}: f / pdf = {weight} vs weight (rel {rel:e})");
    }
    Ok(match (alpha < 1e-2, tol < 1e-2) {
        (_, false) => "BSDF sample re-evaluated, pdf rounding above 1%",
        (true, true) => "BSDF sample re-evaluated, GGX alpha < 1e-2",
        (false, true) => "BSDF sample re-evaluated",
    })
}

/// The rounding of a cosine-warped quad's pdf re-evaluated at a point, relative: the point's u
/// comes back through `invert_spherical_rectangle_sample`, whose corner terms (atan2, up to pi)
/// are divided by the solid angle, and the bilinear pdf's slope is at most the ratio of its
/// largest corner weight to its smallest. Zero where `Q` does not warp.
fn warp_rounding<Q: QuadSampler>(shape: &Shape, at: &ShadingPoint) -> f32 {
    if !matches!(Q::KIND, QuadSampling::SolidAngleCosine | QuadSampling::Auto | QuadSampling::BySize) {
        return 0.0;
    }
    let Some((rect, sr)) = Q::seen(shape, at) else { return 0.0 };
    let n = Vec3::new(at.n.dot(rect.ex), at.n.dot(rect.ey), at.n.dot(rect.n));
    let w = spherical_rectangle_cosines(&sr, n);
    let (lo, hi) = w.iter().fold((f32::INFINITY, 0.0f32), |(lo, hi), &c| (lo.min(c), hi.max(c)));
    16.0 * f32::EPSILON * core::f32::consts::PI / sr.solid_angle() * (hi / lo)
}

/// The pdf of a light sample re-evaluated by `LightSampler::pdf` (`pdf`) at the point it found
/// equals the sample's own pdf: exactly for the cone (it depends on the shading point only), to
/// rounding of the re-constructed point for area sampling (checked where that rounding is below
/// 1%), and where the receiver's lobe joins the light samples (the strategies `Lt` name lobe
/// mixing), to the rounding of the direction through the lobe: the mixture's pdf, the lobe's part
/// included.
fn check_sample_pdf<Lt: LightStrategies<HOST_LIGHTS>>(
    pdf: &LightPdf<'_>,
    shape: &Shape,
    light: LightId,
    at: &ShadingPoint,
    ls: &picomis::LightSample,
    what: &str,
) -> Result<&'static str, TestCaseError> {
    let p = at.p;
    let yp = p + ls.wi * ls.distance;
    let y = SurfacePoint { p: yp, n: shape.normal_at(yp) };
    let again = pdf(light, at, &y);
    prop_assert!(pdf_ok(again), "{what}: light_pdf {again}");
    let outside = |(c, r): (Vec3, f32)| (c - p).length_squared() > r * r;
    // With lobe mixing at a GGX receiver, the lobe's part of the pdf depends on the direction:
    // re-evaluated from the point, to the rounding of the direction through the GGX lobe (at
    // most 1/alpha per unit of angle), plus the light's own part's rounding.
    let by_lobe = Lt::Lobe::towards::<Lt::Spheres, Lt::Quads>(shape, at).is_some();
    let by_cone = <Lt::Spheres as SphereSampler>::KIND == SphereSampling::Cone
        && shape.as_sphere().is_some_and(outside)
        && !by_lobe;
    let cos_y = y.n.dot(-ls.wi);
    // Rounding of the re-constructed point (~1e-7 of the coordinates) moves the pdf
    // p_A d^2 / cos(theta_y) by about that error over the distance, and over the radius
    // through the normal of a sphere, each divided by cos(theta_y).
    let err = f32::EPSILON * (p.abs().max_element() + yp.abs().max_element());
    let lever = shape.as_sphere().map_or(ls.distance, |(_, r)| r.min(ls.distance));
    let tol = 1e-4 + 16.0 * err / (lever * cos_y) + warp_rounding::<Lt::Quads>(shape, at);
    if by_cone {
        prop_assert_eq!(again, ls.pdf, "{}: cone pdf re-evaluated", what);
        Ok("light sample pdf re-evaluated (cone)")
    } else if by_lobe {
        let Material::GgxConductor { alpha, .. } = at.bsdf else { unreachable!() };
        let tol = tol + 64.0 * err / (ls.distance * alpha);
        if tol < 1e-2 {
            let rel = (again / ls.pdf - 1.0).abs();
            prop_assert!(rel < tol, "{what}: lobe-mixing pdf {again} vs sample pdf {} (rel {rel:e})", ls.pdf);
            Ok("light sample pdf re-evaluated (lobe mixing)")
        } else {
            Ok("light sample pdf not re-evaluated (rounding)")
        }
    } else if cos_y > 0.0 && tol < 1e-2 {
        let rel = (again / ls.pdf - 1.0).abs();
        prop_assert!(
            rel < tol,
            "{what}: light_pdf at the sampled point {again} vs sample pdf {} (rel {rel:e})",
            ls.pdf
        );
        Ok("light sample pdf re-evaluated (area)")
    } else {
        Ok("light sample pdf not re-evaluated (rounding)")
    }
}

#[test]
fn pdfs_are_finite_and_weights_partition_unity() {
    let tally = Tally::default();
    check_property(2000, (scene_spec(), settings()), |(spec, settings)| {
        let Some(scene) = build(&spec, 4, 4) else { return Ok(()) };
        check_pdfs(&scene, &settings, 32, &tally)
    });
    tally.require(&[
        ("light sample with f > 0", 15_000),
        ("light sample pdf re-evaluated (cone)", 13_000),
        ("light sample pdf re-evaluated (lobe mixing)", 1_000),
        ("light sample pdf re-evaluated (area)", 20_000),
        ("BSDF sample hitting a light", 6_000),
        ("BSDF sample hitting a light, GGX alpha < 1e-3", 600),
        ("BSDF sample re-evaluated", 80_000),
        ("BSDF sample re-evaluated, GGX alpha < 1e-2", 15_000),
    ]);
}
/// The lobe-mixing check above can fail: with the test double of a mixture whose pdf leaves out
/// the lobe's part ([`LobePdf::LeftOut`]), on the same random scenes with lobe mixing on, the
/// re-evaluated pdf of a lobe-mixing light sample disagrees with the sample's own.
#[test]
fn a_mixture_pdf_without_the_lobe_part_fails() {
    let on = settings().prop_map(|s| s.with_lobe_mixing(LobeMixing::On));
    let tally = Tally::default();
    let result = run_property(400, 0, (scene_spec(), on), |(spec, settings)| {
        let Some(scene) = build(&spec, 4, 4) else { return Ok(()) };
        let check = PdfCheck {
            scene: &scene,
            settings: &settings,
            points: 32,
            tally: &tally,
            lobe_pdf: LobePdf::LeftOut,
        };
        LightChoices::of(&settings).visit(check)
    });
    println!("{result:?}");
    let failure = result.expect_err("a mixture pdf without the lobe's part must fail the check");
    assert!(failure.contains("lobe-mixing pdf"), "failed, but not on the mixture's pdf: {failure}");
}

/// The point lights of a scene carry no pdf: `LightSampler::pdf` is 0 for them.
#[test]
fn point_lights_have_no_light_pdf() {
    let mut scene: S = Scene::new(picomis_tests::camera(), Film::new(4, 4).unwrap()).unwrap();
    scene.add_point_light(Vec3::Y, Rgb::ONE).unwrap();
    assert!(matches!(scene.lights()[0], Light::Point { .. }));
    let y = SurfacePoint { p: Vec3::Y, n: -Vec3::Y };
    /// The light pdf of the point light at `y`, by the sampler of the strategies `Lt`.
    struct PointPdf<'a>(&'a S, SurfacePoint);
    impl VisitLights<HOST_LIGHTS> for PointPdf<'_> {
        type Output = f32;
        fn visit<Lt: LightStrategies<HOST_LIGHTS>>(self) -> f32 {
            let lights = Sampling::<Lt>::new(self.0);
            let at = ShadingPoint {
                p: Vec3::ZERO,
                n: Vec3::Y,
                wo: Vec3::Y,
                bsdf: Material::lambertian(Rgb::ONE).unwrap(),
            };
            lights.pdf(LightId::new(0), &at, &self.1)
        }
    }
    for (spheres, lobe) in SphereSampling::ALL.into_iter().zip(LobeMixing::ALL) {
        let choices = LightChoices::new(LightSelection::Uniform, spheres).with_lobe_mixing(lobe);
        assert_eq!(choices.visit(PointPdf(&scene, y)), 0.0, "{choices:?}");
    }
}
