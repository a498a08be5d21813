//! No overflow on valid input: the largest emission a scene accepts, and the bound on one sample's
//! contribution, keep every running sum of a pixel and its total radiance finite.
//! (Camera-sample counts are u64: `RenderStats`, tested in the kernel's debug-build unit tests.)

use picomis::{
    CameraDesc, Estimate, Field, Film, FovAxis, Heuristic, MAX_CONTRIBUTION, MAX_EMISSION, Material, Method,
    RenderSettings, Rgb, SceneError, Shape, SphereSampling, TechniqueEstimate, Vec3,
};
use picomis_host::{HostScene, renderer};

/// The scenes' type: the host's (the settings are chosen at run time).
type S = HostScene;

fn camera() -> CameraDesc {
    CameraDesc {
        origin: Vec3::new(0.0, 1.0, 4.0),
        target: Vec3::new(0.0, 0.5, 0.0),
        up: Vec3::Y,
        fov_deg: 40.0,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    }
}

/// A Lambertian floor under a sphere light of `radiance`, and a point light of `intensity`.
fn scene(radiance: f32, intensity: f32) -> Result<S, SceneError> {
    let mut s = S::new(camera(), Film::new(16, 12)?)?;
    let white = s.add_material(Material::lambertian(Rgb::splat(0.8))?)?;
    let black = s.add_material(Material::lambertian(Rgb::ZERO)?)?;
    let floor =
        [Vec3::new(-3., 0., 3.), Vec3::new(3., 0., 3.), Vec3::new(3., 0., -3.), Vec3::new(-3., 0., -3.)];
    s.add_shape(Shape::quad(floor)?, white)?;
    let bulb = s.add_shape(Shape::sphere(Vec3::new(0.0, 0.6, 0.0), 0.3)?, black)?;
    s.add_area_light(bulb, Rgb::splat(radiance))?;
    s.add_point_light(Vec3::new(1.0, 0.5, 1.0), Rgb::splat(intensity))?;
    Ok(s)
}

fn next_up(v: f32) -> f32 {
    f32::from_bits(v.to_bits() + 1)
}

#[test]
fn emission_above_the_maximum_is_rejected() {
    assert!(scene(MAX_EMISSION, MAX_EMISSION).is_ok());
    for too_much in [next_up(MAX_EMISSION), 1e30, f32::MAX] {
        assert_eq!(scene(too_much, 1.0).err(), Some(SceneError::OutOfRange(Field::Radiance)), "{too_much}");
        assert_eq!(scene(1.0, too_much).err(), Some(SceneError::OutOfRange(Field::Intensity)), "{too_much}");
    }
}

#[test]
fn the_brightest_valid_scene_renders_finite_pixels() {
    let s = scene(MAX_EMISSION, MAX_EMISSION).unwrap();
    let film = s.film();
    let mut lit = 0;
    for (method, spheres) in [
        (Method::Mis(Heuristic::Power { beta: 2.0 }), SphereSampling::Cone),
        (Method::Mis(Heuristic::Balance), SphereSampling::Area),
        (Method::BsdfOnly, SphereSampling::Cone),
        (Method::LightOnly, SphereSampling::Area),
    ] {
        let settings = RenderSettings::new(method, 2, 2, 64, 3).unwrap().with_sphere_sampling(spheres);
        let it = renderer(&s, &settings).unwrap();
        for y in 0..film.height() {
            for x in 0..film.width() {
                let e = it.render_pixel(x, y);
                let parts = [e.emitted, e.light.contribution, e.bsdf.contribution, e.radiance()];
                assert!(parts.iter().all(|p| p.is_finite()), "{method:?} pixel ({x}, {y}): {e:?}");
                assert!(e.light.weight_sum.is_finite() && e.bsdf.weight_sum.is_finite());
                if e.radiance().x > 1e15 {
                    lit += 1;
                }
            }
        }
    }
    assert!(lit > 100, "the render hardly saw the light ({lit} bright pixels): vacuous");
}

#[test]
fn the_largest_sums_stay_finite() {
    // The sums the estimator's `render_pixel` forms before dividing by spp, in the worst case:
    // 2^16 samples per technique per camera sample, each at the bound, and 2^32 camera samples;
    // emitted light at the maximum in every camera sample.
    let part = Rgb::splat(MAX_CONTRIBUTION * 2f32.powi(16) * 2f32.powi(32));
    let worst = Estimate {
        emitted: Rgb::splat(MAX_EMISSION * 2f32.powi(32)),
        light: TechniqueEstimate { contribution: part, weight_sum: 2f32.powi(48), found: u32::MAX },
        bsdf: TechniqueEstimate { contribution: part, weight_sum: 2f32.powi(48), found: u32::MAX },
    };
    assert!(worst.radiance().is_finite(), "{:?}", worst.radiance());
    let mut merged = worst;
    merged.merge(&Estimate::default());
    assert_eq!(merged.light.found, u32::MAX);
    // The bound is what keeps it finite: at 1e38 per sample the same sums overflow.
    let unbounded = Rgb::splat(1e38 * 2f32.powi(48));
    assert!(!(unbounded + unbounded).is_finite());
}
