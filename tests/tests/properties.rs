//! Property tests of the kernel on random valid scenes, with proptest on a fixed seed
//! and ChaCha (the same cases on every run, no failure files).
//!
//! A random scene holds a ground (a floor up to 2000 across or a sphere of radius up to 50 under
//! everything) and up to five spheres (radius 1e-4 to 5, some containing the camera or one
//! another) and quads (small, tilted, or floors up to 2000 across), each Lambertian or GGX
//! (alpha 1e-4 to 1) or black, some emitting (radiance 0 or 1e-2 to 1e5), plus up to two point
//! lights (intensity 0 or 1e-2 to 1e3) and a random camera. Settings are random too: every
//! method (power beta 0.25 to 4, cutoff alpha 0 to 1), 0 to 3 samples per technique, 1 to 3
//! camera samples, any seed, sphere lights by area or cone, with and without lobe mixing, every light selection (uniform, by power,
//! by contribution).
//!
//! Properties:
//! 1. `render_pixel` outputs are finite and non-negative everywhere (radiance, emission, both
//!    technique contributions), every technique's weight sum is finite and between 0 and its
//!    number of samples that found light, which is at most spp x its sample count, and a method
//!    using one technique gives each of its samples weight exactly 1.
//! 2. At random points on every shape, for random view directions (a quarter of them grazing,
//!    cos down to 1e-6), for the directions the kernel itself draws (light samples, BSDF samples
//!    traced to an emitter) and for uniform random directions: every pdf (`Material::pdf` and
//!    `eval_pdf`, `BsdfSample::pdf`, `LightSample::pdf`, `Scene::light_pdf`) is finite and
//!    non-negative, sampled ones positive; each technique's pdf is positive wherever the other
//!    one found light it can produce (a light hit by a BSDF ray has a light pdf, a light sample
//!    with f > 0 has a BSDF pdf); re-evaluated at the sample, a light sample's pdf is the
//!    sample's own (exactly for the cone; with lobe mixing, by the light sampler of the settings'
//!    strategies, the mixture's, its lobe part included: a test double whose pdf leaves that part
//!    out fails, `a_mixture_pdf_without_the_lobe_part_fails`) and a BSDF sample's pdf and weight are eval_pdf's (to
//!    the rounding of the direction, see [`check_bsdf_sample`]); the weights of every heuristic
//!    on these q = n p are in [0, 1], 0 where q = 0 and sum to 1 (within 1e-5) wherever some
//!    q > 0; and each sample's weighted contribution, computed as the estimator does, is finite
//!    (so the estimator's own filter of non-finite contributions never has to act).
//! 3. An image depends only on the seed: rendered row-major, in reverse, tile by tile in a
//!    shuffled order, and on 2, 3 and 4 threads taking pixels or tiles as they come, every pixel
//!    has the same bits (every field of its `Estimate`), and the tone-mapped framebuffers written
//!    through `render` and through `render_tile` per shuffled tile on several threads are equal
//!    byte for byte (and equal to `tone_map` of the pixel estimates).
//!
//! Each property also counts what its cases exercised (lit pixels, BSDF rays hitting lights,
//! near-mirror GGX, pdfs re-evaluated, ...) and fails if a count falls below a floor: a change
//! of the generators cannot make it pass vacuously.

use embedded_graphics_core::Pixel;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics_core::primitives::{PointsIter, Rectangle};
use picomis::integrator::{control_variate, model};
use picomis::light::lobe::{self, LOBE_SHARE, LobeSampler};
use picomis::light::sphere::SphereSampler;
use picomis::light::{LightStrategies, Lights};
use picomis::num::Frame;
use picomis::sampling::{sample_cosine_hemisphere, sample_uniform_sphere};
use picomis::{
    CameraDesc, Direct, Estimate, Film, FovAxis, Heuristic, Integrator, Light, LightId, LightSampler,
    LightSelection, LobeMixing, Material, Method, QuadSampling, Ray, RenderSettings, Rgb, Sampler, Scene,
    ShadingPoint, Shape, ShapeId, SphereSampling, SurfacePoint, Vec3, tiles, tone_map,
};
use picomis_host::{HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene, Renderer, renderer};
use picomis_tests::{LightChoices, VisitLights};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseResult, TestRng, TestRunner};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The scenes' type: the host's (their settings are drawn at run time).
type S = HostScene;

/// The light sampler of a random scene with the strategies `Lt`.
type Sampling<'a, Lt> = LightSampler<'a, Lt, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

/// The estimator of `settings` on `scene` (the host's, for the strategies the settings name).
fn estimator<'a>(
    scene: &'a S,
    settings: &'a RenderSettings,
) -> Result<Box<dyn Renderer + 'a>, TestCaseError> {
    renderer(scene, settings).map_err(|e| TestCaseError::fail(format!("{settings:?}: {e}")))
}

/// Runs `test` on `cases` values of `strategy` drawn from a fixed ChaCha seed (no failure
/// files, `PROPTEST_*` variables have no say), and panics with the (shrunk) failing input.
fn check_property<T: Strategy>(cases: u32, strategy: T, test: impl Fn(T::Value) -> TestCaseResult)
where
    T::Value: std::fmt::Debug,
{
    if let Err(e) = run_property(cases, u32::MAX, strategy, test) {
        panic!("{e}");
    }
}

/// [`check_property`] returning the failure (after at most `shrink` shrinking steps) instead of
/// panicking: for the tests that show a property can fail.
fn run_property<T: Strategy>(
    cases: u32,
    shrink: u32,
    strategy: T,
    test: impl Fn(T::Value) -> TestCaseResult,
) -> Result<(), String>
where
    T::Value: std::fmt::Debug,
{
    let config = Config {
        cases,
        max_shrink_iters: shrink,
        failure_persistence: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        ..Config::default()
    };
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &[0x57; 32]);
    TestRunner::new_with_rng(config, rng).run(&strategy, test).map_err(|e| e.to_string())
}

/// Counts of what the cases exercised, so that a property that checks nothing fails.
#[derive(Default)]
struct Tally(RefCell<BTreeMap<&'static str, u64>>);

impl Tally {
    fn add(&self, what: &'static str) {
        *self.0.borrow_mut().entry(what).or_default() += 1;
    }

    /// Asserts that every `(what, at_least)` happened often enough, and prints the counts.
    #[track_caller]
    fn require(&self, minimum: &[(&'static str, u64)]) {
        let counts = self.0.borrow();
        println!("{counts:?}");
        for &(what, at_least) in minimum {
            let n = counts.get(what).copied().unwrap_or(0);
            assert!(
                n >= at_least,
                "only {n} cases of '{what}' (at least {at_least} needed): the property is near vacuous"
            );
        }
    }
}
// ---------------------------------------------------------------------------------------------
// Random scenes

#[derive(Clone, Copy, Debug)]
enum MaterialSpec {
    Lambertian(Rgb),
    Ggx(f32, Rgb),
}

#[derive(Clone, Copy, Debug)]
enum ShapeSpec {
    Sphere(Vec3, f32),
    Quad(Vec3, Vec3, Vec3),
}

#[derive(Clone, Copy, Debug)]
struct ObjectSpec {
    shape: ShapeSpec,
    material: MaterialSpec,
    radiance: Option<f32>,
}

#[derive(Clone, Debug)]
struct SceneSpec {
    objects: Vec<ObjectSpec>,
    points: Vec<(Vec3, f32)>,
    eye: Vec3,
    target: Vec3,
    fov: f32,
}

fn vec3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn log_uniform(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f32.powf(e))
}

fn colour() -> impl Strategy<Value = Rgb> {
    (0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0).prop_map(|(r, g, b)| Rgb::new(r, g, b))
}

fn material() -> impl Strategy<Value = MaterialSpec> {
    prop_oneof![
        3 => colour().prop_map(MaterialSpec::Lambertian),
        3 => (log_uniform(1e-4, 1.0), colour()).prop_map(|(a, c)| MaterialSpec::Ggx(a, c)),
        1 => Just(MaterialSpec::Lambertian(Rgb::ZERO)),
    ]
}

fn shape() -> impl Strategy<Value = ShapeSpec> {
    prop_oneof![
        3 => (vec3(3.0), log_uniform(1e-4, 5.0)).prop_map(|(c, r)| ShapeSpec::Sphere(c, r)),
        2 => (vec3(3.0), vec3(4.0), vec3(4.0)).prop_map(|(p0, e1, e2)| ShapeSpec::Quad(p0, e1, e2)),
        // A floor or ceiling, up to 2000 across, facing up or down.
        1 => (-2.0f32..2.0, log_uniform(1.0, 1e3), any::<bool>()).prop_map(|(y, h, up)| {
            let (e1, e2) = (Vec3::new(2.0 * h, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0 * h));
            let p0 = Vec3::new(-h, y, -h);
            if up { ShapeSpec::Quad(p0, e2, e1) } else { ShapeSpec::Quad(p0, e1, e2) }
        }),
    ]
}

fn object() -> impl Strategy<Value = ObjectSpec> {
    let radiance =
        prop_oneof![2 => Just(None), 1 => Just(Some(0.0)), 4 => log_uniform(1e-2, 1e5).prop_map(Some)];
    (shape(), material(), radiance).prop_map(|(shape, material, radiance)| ObjectSpec {
        shape,
        material,
        radiance,
    })
}

/// A receiver under everything else (most pixels see something): a floor up to 2000 across
/// or a sphere of radius up to 50 whose top is near y = -1, reflecting, rarely emitting.
fn ground() -> impl Strategy<Value = ObjectSpec> {
    let shape = prop_oneof![
        (log_uniform(2.0, 1e3), -1.5f32..-0.5).prop_map(|(h, y)| {
            ShapeSpec::Quad(Vec3::new(-h, y, -h), Vec3::new(0.0, 0.0, 2.0 * h), Vec3::new(2.0 * h, 0.0, 0.0))
        }),
        log_uniform(1.0, 50.0).prop_map(|r| ShapeSpec::Sphere(Vec3::new(0.0, -1.0 - r, 0.0), r)),
    ];
    let radiance = prop_oneof![4 => Just(None), 1 => log_uniform(1e-2, 1e2).prop_map(Some)];
    (shape, material(), radiance).prop_map(|(shape, material, radiance)| ObjectSpec {
        shape,
        material,
        radiance,
    })
}

fn scene_spec() -> impl Strategy<Value = SceneSpec> {
    let intensity = prop_oneof![1 => Just(0.0f32), 3 => log_uniform(1e-2, 1e3)];
    let eye = (vec3(6.0), 0.5f32..4.0).prop_map(|(v, y)| Vec3::new(v.x, y, v.z));
    (
        ground(),
        prop::collection::vec(object(), 0..=5),
        prop::collection::vec((vec3(4.0), intensity), 0..=2),
        eye,
        vec3(1.0),
        10.0f32..120.0,
    )
        .prop_map(|(ground, mut objects, points, eye, target, fov)| {
            objects.insert(0, ground);
            SceneSpec { objects, points, eye, target, fov }
        })
}
/// The kernel scene of a spec on a `width` x `height` film. Shapes the kernel rejects
/// (degenerate random quads) are left out; `None` for a camera it rejects.
fn build(spec: &SceneSpec, width: u32, height: u32) -> Option<S> {
    let film = Film::new(width, height).unwrap();
    let desc = |up| CameraDesc {
        origin: spec.eye,
        target: spec.target,
        up,
        fov_deg: spec.fov,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    };
    let mut scene: S = Scene::new(desc(Vec3::Y), film).or_else(|_| Scene::new(desc(Vec3::X), film)).ok()?;
    for o in &spec.objects {
        let shape = match o.shape {
            ShapeSpec::Sphere(c, r) => Shape::sphere(c, r),
            ShapeSpec::Quad(p0, e1, e2) => Shape::quad([p0, p0 + e1, p0 + e1 + e2, p0 + e2]),
        };
        let Ok(shape) = shape else { continue };
        let material = match o.material {
            MaterialSpec::Lambertian(c) => Material::lambertian(c),
            MaterialSpec::Ggx(a, c) => Material::ggx_conductor(a, c),
        }
        .unwrap();
        let m = scene.add_material(material).unwrap();
        let id = scene.add_shape(shape, m).unwrap();
        if let Some(l) = o.radiance {
            scene.add_area_light(id, Rgb::splat(l)).unwrap();
        }
    }
    for &(p, i) in &spec.points {
        scene.add_point_light(p, Rgb::new(i, 0.5 * i, 0.25 * i)).unwrap();
    }
    Some(scene)
}

fn heuristic() -> impl Strategy<Value = Heuristic> {
    prop_oneof![
        Just(Heuristic::Average),
        Just(Heuristic::Balance),
        Just(Heuristic::Power { beta: 2.0 }),
        (0.25f32..4.0).prop_map(|beta| Heuristic::Power { beta }),
        Just(Heuristic::Maximum),
        (0.0f32..=1.0).prop_map(|alpha| Heuristic::Cutoff { alpha }),
    ]
}

fn settings() -> impl Strategy<Value = RenderSettings> {
    let method =
        prop_oneof![Just(Method::LightOnly), Just(Method::BsdfOnly), heuristic().prop_map(Method::Mis)];
    let selection = 0..LightSelection::ALL.len();
    let quads = prop::sample::select(QuadSampling::ALL.to_vec());
    (method, 0u16..=3, 0u16..=3, 1u32..=3, any::<u32>(), any::<bool>(), selection, quads).prop_map(
        |(method, n_light, n_bsdf, spp, seed, cone, selection, quads)| {
            // Lobe mixing by the seed's low bit (the other draws stay those of the cases before
            // it existed).
            let spheres = if cone { SphereSampling::Cone } else { SphereSampling::Area };
            let lobe = LobeMixing::ALL[(seed & 1) as usize];
            let s = RenderSettings::new(method, n_light, n_bsdf, spp, seed)
                .or_else(|_| RenderSettings::new(method, n_light.max(1), n_bsdf.max(1), spp, seed))
                .unwrap();
            s.with_sphere_sampling(spheres)
                .with_light_selection(LightSelection::ALL[selection])
                .with_quad_sampling(quads)
                .with_lobe_mixing(lobe)
        },
    )
}

// ---------------------------------------------------------------------------------------------
// 1. Finite render_pixel outputs

fn finite_non_negative(c: Rgb) -> bool {
    c.is_finite() && c.min_element() >= 0.0
}

fn check_estimate(e: &Estimate, settings: &RenderSettings, at: (u32, u32), tally: &Tally) -> TestCaseResult {
    let (n_light, n_bsdf) = settings.technique_samples();
    prop_assert!(finite_non_negative(e.emitted), "pixel {at:?}: emitted {}", e.emitted);
    prop_assert!(finite_non_negative(e.radiance()), "pixel {at:?}: radiance {}", e.radiance());
    let single = |m: Method| settings.method() == m;
    for (name, t, n, alone) in [
        ("light", &e.light, n_light, single(Method::LightOnly)),
        ("BSDF", &e.bsdf, n_bsdf, single(Method::BsdfOnly)),
    ] {
        prop_assert!(
            finite_non_negative(t.contribution),
            "pixel {at:?}: {name} contribution {}",
            t.contribution
        );
        prop_assert!(
            t.weight_sum.is_finite() && t.weight_sum >= 0.0 && t.weight_sum <= t.found as f32 * (1.0 + 1e-6),
            "pixel {at:?}: {name} weight sum {} over {} samples that found light",
            t.weight_sum,
            t.found
        );
        prop_assert!(
            t.found <= settings.spp() * u32::from(n),
            "pixel {at:?}: {name} found {} > spp x {n}",
            t.found
        );
        if alone {
            prop_assert_eq!(t.weight_sum, t.found as f32, "pixel {:?}: {} alone must weigh 1", at, name);
        }
        if t.found > 0 {
            tally.add(if name == "light" {
                "pixel lit by light samples"
            } else {
                "pixel lit by BSDF samples"
            });
        }
    }
    if e.radiance().max_element() > 0.0 {
        tally.add("pixel with radiance > 0");
    }
    Ok(())
}

#[test]
fn render_pixel_outputs_are_finite() {
    let tally = Tally::default();
    check_property(3000, (scene_spec(), settings()), |(spec, settings)| {
        let Some(scene) = build(&spec, 6, 4) else { return Ok(()) };
        tally.add("scene");
        let it = estimator(&scene, &settings)?;
        for y in 0..4 {
            for x in 0..6 {
                check_estimate(&it.render_pixel(x, y), &settings, (x, y), &tally)?;
            }
        }
        Ok(())
    });
    tally.require(&[
        ("scene", 2900),
        ("pixel with radiance > 0", 9000),
        ("pixel lit by light samples", 4000),
        ("pixel lit by BSDF samples", 400),
    ]);
}
// ---------------------------------------------------------------------------------------------
// 2. Pdfs and weights at random surface points

use picomis_tests::heuristics;

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
fn check_bsdf_sample(
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
    let tol = 1e-4 + 16.0 * err / (lever * cos_y);
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

// ---------------------------------------------------------------------------------------------
// 3. Determinism across orders and threads

const W: u32 = 12;
const H: u32 = 8;

/// Every field of an estimate, as bits.
fn bits(e: &Estimate) -> [u32; 13] {
    let c = |v: Rgb| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let (em, l, b) = (c(e.emitted), c(e.light.contribution), c(e.bsdf.contribution));
    [
        em[0],
        em[1],
        em[2],
        l[0],
        l[1],
        l[2],
        e.light.weight_sum.to_bits(),
        e.light.found,
        b[0],
        b[1],
        b[2],
        e.bsdf.weight_sum.to_bits(),
        e.bsdf.found,
    ]
}

type Image = Vec<[u32; 13]>;

fn pixel_bits(it: &dyn Renderer, i: u32) -> [u32; 13] {
    bits(&it.render_pixel(i % W, i / W))
}

/// Renders pixel indices in `order` into a row-major image.
fn render_in_order(it: &dyn Renderer, order: impl Iterator<Item = u32>) -> Image {
    let mut img = vec![[0; 13]; (W * H) as usize];
    for i in order {
        img[i as usize] = pixel_bits(it, i);
    }
    img
}

/// A permutation of 0..n from `seed` (Fisher-Yates on the kernel's own generator).
fn shuffled(n: usize, seed: u32) -> Vec<usize> {
    let mut v: Vec<usize> = (0..n).collect();
    let mut rng = Sampler::new(seed, 0x5AFF, 0);
    for i in (1..n).rev() {
        let j = (rng.next_u32() as usize) % (i + 1);
        v.swap(i, j);
    }
    v
}

/// Pixel indices of the tiles of `tile` pixels, tiles in a shuffled order.
fn tile_order(tile: Size, seed: u32) -> Vec<u32> {
    let all: Vec<Rectangle> = tiles(Film::new(W, H).unwrap(), tile).collect();
    let mut out = Vec::new();
    for t in shuffled(all.len(), seed) {
        let r = all[t];
        for y in r.rows() {
            for x in r.columns() {
                out.push(y as u32 * W + x as u32);
            }
        }
    }
    out
}

/// `threads` threads take the work items `0..jobs` as they come; `work` returns the pixels it
/// rendered. The merged image does not depend on which thread took which item.
fn render_threaded(
    threads: usize,
    jobs: usize,
    work: impl Fn(usize) -> Vec<(u32, [u32; 13])> + Sync,
) -> Image {
    let next = AtomicUsize::new(0);
    let img = Mutex::new(vec![[0; 13]; (W * H) as usize]);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                loop {
                    let job = next.fetch_add(1, Ordering::Relaxed);
                    if job >= jobs {
                        break;
                    }
                    let done = work(job);
                    let mut img = img.lock().unwrap();
                    for (i, b) in done {
                        img[i as usize] = b;
                    }
                }
            });
        }
    });
    img.into_inner().unwrap()
}

/// A framebuffer of tone-mapped pixels (the host's stand-in for a display), any size.
struct Framebuffer {
    area: Rectangle,
    pixels: Vec<Rgb888>,
}

impl Framebuffer {
    fn new(area: Rectangle) -> Self {
        Self { area, pixels: vec![Rgb888::new(1, 2, 3); (area.size.width * area.size.height) as usize] }
    }

    fn bytes(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|c| [c.r(), c.g(), c.b()]).collect()
    }
}

impl OriginDimensions for Framebuffer {
    fn size(&self) -> Size {
        self.area.size
    }
}

impl DrawTarget for Framebuffer {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            let (x, y) = (p.x - self.area.top_left.x, p.y - self.area.top_left.y);
            let w = self.area.size.width as i32;
            if (0..w).contains(&x) && (0..self.area.size.height as i32).contains(&y) {
                self.pixels[(y * w + x) as usize] = c;
            }
        }
        Ok(())
    }
}

fn check_determinism(scene: &S, settings: &RenderSettings, tile: Size, seed: u32) -> TestCaseResult {
    let n = W * H;
    let it = &*estimator(scene, settings)?;
    let reference = render_in_order(it, 0..n);
    let mut variants = vec![
        ("reverse order".to_string(), render_in_order(it, (0..n).rev())),
        (format!("shuffled {tile:?} tiles"), render_in_order(it, tile_order(tile, seed).into_iter())),
    ];
    let order = shuffled(n as usize, seed);
    for threads in [2, 3, 4] {
        let per_pixel = render_threaded(threads, n as usize, |j| {
            let i = order[j] as u32;
            vec![(i, pixel_bits(it, i))]
        });
        variants.push((format!("{threads} threads, shuffled pixels"), per_pixel));
        let all: Vec<Rectangle> = tiles(scene.film(), tile).collect();
        let per_tile = render_threaded(threads, all.len(), |j| {
            let r = all[j];
            r.rows()
                .flat_map(|y| r.columns().map(move |x| y as u32 * W + x as u32))
                .map(|i| (i, pixel_bits(it, i)))
                .collect()
        });
        variants.push((format!("{threads} threads, {tile:?} tiles"), per_tile));
    }
    for (name, img) in &variants {
        if let Some(i) = (0..n as usize).find(|&i| img[i] != reference[i]) {
            prop_assert!(
                false,
                "{name}: pixel ({}, {}) differs: {:?} vs {:?}",
                i as u32 % W,
                i as u32 / W,
                img[i],
                reference[i]
            );
        }
    }

    // The same through the DrawTarget path of the estimator of the settings' strategies.
    LightChoices::of(settings).visit(DrawPaths { scene, settings, tile, seed })
}

/// The DrawTarget path of [`check_determinism`], through the estimator of the light strategies
/// `Lt`, without the control variate, in the multi-sample model (what [`settings`] draws).
struct DrawPaths<'a> {
    scene: &'a S,
    settings: &'a RenderSettings,
    tile: Size,
    seed: u32,
}

/// The estimator of the light strategies `Lt`, without the control variate, in the multi-sample
/// model.
type DrawIntegrator<'a, Lt> =
    Integrator<'a, Direct<Lt, control_variate::Off, model::Multi>, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>;

impl VisitLights<HOST_LIGHTS> for DrawPaths<'_> {
    type Output = TestCaseResult;
    fn visit<Lt: LightStrategies<HOST_LIGHTS>>(self) -> TestCaseResult {
        let (scene, settings) = (self.scene, self.settings);
        let it = DrawIntegrator::<Lt>::new(scene, settings)
            .map_err(|e| TestCaseError::fail(format!("{settings:?}: {e}")))?;
        check_draw_paths(&it, self.tile, self.seed)
    }
}

/// `render` in row-major tiles, and `render_tile` per shuffled tile on 3 threads, each into its
/// own framebuffer, copied into one: the same bytes, and those of `tone_map` of the pixels.
fn check_draw_paths<Lt: LightStrategies<HOST_LIGHTS>>(
    it: &DrawIntegrator<'_, Lt>,
    tile: Size,
    seed: u32,
) -> TestCaseResult {
    let (n, scene) = (W * H, it.scene());
    let full = Rectangle::new(embedded_graphics_core::geometry::Point::zero(), Size::new(W, H));
    let mut whole = Framebuffer::new(full);
    let stats = it.render(tile, &mut whole, |_, _| {}).unwrap();
    prop_assert_eq!(stats.pixels, n);
    let mapped: Vec<u8> = (0..n)
        .flat_map(|i| {
            let c = tone_map(it.render_pixel(i % W, i / W).radiance());
            [c.r(), c.g(), c.b()]
        })
        .collect();
    prop_assert!(whole.bytes() == mapped, "render() differs from tone_map(render_pixel)");
    let all: Vec<Rectangle> = tiles(scene.film(), tile).collect();
    let order = shuffled(all.len(), seed ^ 1);
    let parts = Mutex::new(Vec::new());
    let next = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..3 {
            s.spawn(|| {
                loop {
                    let j = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&t) = order.get(j) else { break };
                    let mut fb = Framebuffer::new(all[t]);
                    it.render_tile(&all[t], &mut fb).unwrap();
                    parts.lock().unwrap().push(fb);
                }
            });
        }
    });
    let mut merged = Framebuffer::new(full);
    for fb in parts.into_inner().unwrap() {
        let pixels = fb.area.points().zip(fb.pixels.iter().copied()).map(|(p, c)| Pixel(p, c));
        merged.draw_iter(pixels).unwrap();
    }
    prop_assert!(merged.bytes() == whole.bytes(), "render_tile on 3 threads differs from render()");
    Ok(())
}

#[test]
fn images_depend_only_on_the_seed() {
    let tally = Tally::default();
    let tile = (1u32..=7, 1u32..=5).prop_map(|(w, h)| Size::new(w, h));
    check_property(64, (scene_spec(), settings(), tile, any::<u32>()), |(spec, settings, tile, seed)| {
        let Some(scene) = build(&spec, W, H) else { return Ok(()) };
        let it = estimator(&scene, &settings)?;
        let lit = (0..W * H).filter(|&i| it.render_pixel(i % W, i / W).radiance().max_element() > 0.0);
        if lit.count() > 10 {
            tally.add("image with more than 10 lit pixels");
        }
        check_determinism(&scene, &settings, tile, seed)
    });
    tally.require(&[("image with more than 10 lit pixels", 15)]);
}
