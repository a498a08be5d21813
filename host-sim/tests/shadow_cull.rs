//! Shadow-ray culling by receiver and light (`picomis::shadow_cull`) on every built-in scene: from
//! the surface points camera rays find (every pixel of a 64x48 film, at jittered points), the
//! culled queries answer as the full ones, for
//! - shadow rays to points drawn on every light by every sphere and quad sampling strategy
//!   (`Scene::shadow_unoccluded` against `Scene::unoccluded`);
//! - BSDF-like rays towards those points and in random directions
//!   (`Scene::emitter_hit_from_surface` against `Scene::emitter_hit`, hit record bit for bit).
//!
//! The check is not vacuous: it counts blocked shadow rays and lights found, and on Veach the
//! masks leave out most objects.

use picomis::light::lobe;
use picomis::light::quad::{self, QuadSampler};
use picomis::light::select::Uniform;
use picomis::light::sphere::{self, SphereSampler};
use picomis::sampling::sample_uniform_sphere;
use picomis::{
    Arith, Film, LightId, LightSample, LightSampler, Lights, Ray, Sampler, ShadingPoint, ShapeId, Vec2,
};
use picomis_sim::scenes::{self, BUILTINS, HOST_LIGHTS, HOST_MATERIALS, HOST_SHAPES, HostScene};

/// Jittered camera rays per pixel.
const PER_PIXEL: u32 = 2;
/// Points drawn on each light per strategy, and random directions, per surface point.
const DRAWS: u32 = 2;

#[derive(Default)]
struct Counts {
    shadow_rays: u64,
    blocked: u64,
    directions: u64,
    lights_found: u64,
    /// Objects the shadow rays test, and objects in the scene, summed over the shadow rays.
    tested: u64,
    all: u64,
}

/// Draws a point on a light as seen from a shading point.
type Draw<'a> = Box<dyn Fn(LightId, &ShadingPoint, Vec2) -> Option<LightSample> + 'a>;

/// [`LightSampler::sample`] of `scene`'s lights with spheres sampled by `Sp` and quads by `Q`.
fn draw<Sp: SphereSampler, Q: QuadSampler>(scene: &HostScene) -> Draw<'_> {
    let lights =
        LightSampler::<Lights<Uniform, Sp, Q, lobe::Off>, HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>::new(
            scene,
        );
    Box::new(move |light, at, u| lights.sample(light, at, u))
}

/// The check of `scene` in the arithmetic of the ray queries given.
fn check_scene(mut scene: HostScene, arith: Arith) -> Counts {
    scene.enable_arith(arith).expect("every built-in scene can be represented in fixed point");
    let scene = &scene;
    let film = scene.film();
    let (w, h) = (film.width(), film.height());
    let mut rng = Sampler::new(9, w, h);
    let mut c = Counts::default();
    // Every sphere sampling with every quad sampling.
    let samplers: [Draw<'_>; 6] = [
        draw::<sphere::ByArea, quad::ByArea>(scene),
        draw::<sphere::ByArea, quad::SolidAngle>(scene),
        draw::<sphere::ByArea, quad::SolidAngleCosine>(scene),
        draw::<sphere::InCone, quad::ByArea>(scene),
        draw::<sphere::InCone, quad::SolidAngle>(scene),
        draw::<sphere::InCone, quad::SolidAngleCosine>(scene),
    ];
    for y in 0..h {
        for x in 0..w {
            for _ in 0..PER_PIXEL {
                let j = rng.next_2d();
                let uv = Vec2::new((x as f32 + j.x) / w as f32, (y as f32 + j.y) / h as f32);
                let (ray, t_near) = scene.camera().ray(uv);
                let Some(hit) = scene.intersect_camera(&ray, t_near, x, y) else { continue };
                let Some(bsdf) = scene.material(hit.object).copied() else { continue };
                let at = ShadingPoint { p: hit.point.p, n: hit.point.n, wo: -ray.dir, bsdf };
                for (l, _) in scene.lights().iter().enumerate() {
                    let light = LightId::new(l as u16);
                    for lights in &samplers {
                        for _ in 0..DRAWS {
                            let Some(ls) = lights(light, &at, rng.next_2d()) else { continue };
                            let shadow = Ray { origin: at.p, dir: ls.wi };
                            let full = scene.unoccluded(&shadow, ls.distance, hit.object, ls.emitter);
                            let culled = scene.shadow_unoccluded(&shadow, ls.distance, hit.object, light);
                            assert_eq!(
                                culled, full,
                                "pixel ({x}, {y}), light {l}: {shadow:?} to {}",
                                ls.distance
                            );
                            c.shadow_rays += 1;
                            c.blocked += u64::from(!full);
                            let candidates = scene.shadow_candidates(hit.object, light);
                            let n = scene.objects().len();
                            c.tested +=
                                (0..n).filter(|&i| i >= 32 || candidates >> i & 1 == 1).count() as u64;
                            c.all += n as u64;
                            // A BSDF ray in the same direction: the light it finds, if any.
                            check_emitter_hit(scene, &shadow, hit.object, &mut c);
                        }
                    }
                }
                for _ in 0..DRAWS {
                    let out = Ray { origin: at.p, dir: sample_uniform_sphere(rng.next_2d()) };
                    check_emitter_hit(scene, &out, hit.object, &mut c);
                }
            }
        }
    }
    c
}

/// The culled BSDF-ray query from a point of `receiver` answers as the full one.
fn check_emitter_hit(scene: &HostScene, out: &Ray, receiver: ShapeId, c: &mut Counts) {
    let full = scene.emitter_hit(out, receiver);
    let culled = scene.emitter_hit_from_surface(out, receiver);
    assert_eq!(format!("{culled:?}"), format!("{full:?}"), "{out:?} from {receiver:?}");
    c.directions += 1;
    c.lights_found += u64::from(full.is_some());
}

#[test]
fn culled_shadow_queries_answer_as_the_full_ones_on_every_builtin_scene() {
    check(Arith::F32);
}

/// The fixed-point queries cull the same objects: their hits are within about 1e-7 of the
/// scene's extent of the exact geometry too, far inside the margin.
#[test]
fn culled_fixed_point_shadow_queries_answer_as_the_full_ones_on_every_builtin_scene() {
    check(Arith::Fixed);
}

fn check(arith: Arith) {
    let film = Film::new(64, 48).unwrap();
    for b in BUILTINS {
        let loaded = scenes::load(Some(b.name)).unwrap();
        let c = check_scene(loaded.build(film).unwrap(), arith);
        println!(
            "{} ({arith:?}): {} shadow rays, {:.1} % blocked, {:.2} of {:.0} objects tested per ray; {} BSDF-like rays, {:.1} % find a light",
            b.name,
            c.shadow_rays,
            100.0 * c.blocked as f64 / c.shadow_rays as f64,
            c.tested as f64 / c.shadow_rays as f64,
            c.all as f64 / c.shadow_rays as f64,
            c.directions,
            100.0 * c.lights_found as f64 / c.directions as f64
        );
        assert!(c.shadow_rays > 10_000 && c.directions > 5_000, "{}: too few rays", b.name);
        if b.name == "veach_mis" || b.name == "box_quad" || b.name == "point_lights" {
            assert!(c.blocked > 100, "{}: {} blocked shadow rays", b.name, c.blocked);
        }
        if b.name == "veach_mis" {
            // 11 objects; the masks leave about a quarter of them.
            assert!(c.tested * 2 < c.all, "{}: {} of {} objects tested", b.name, c.tested, c.all);
        }
        if b.name != "point_lights" {
            assert!(c.lights_found > 1000, "{}: {} BSDF-like rays found a light", b.name, c.lights_found);
        }
    }
}
