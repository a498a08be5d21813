//! A pixel's mean at high sample counts: a Lambertian plane under a sphere light, seen through a
//! one-pixel film so narrow that the plane's radiance is the same over the pixel (to 1e-8).
//! Nothing can block the light, so the control variate (the defaults) has it all in closed form,
//! rho L r^2 / d^2 below the sphere's centre, and every camera sample is that value up to its last
//! bits: what remains is how the samples are summed. A plain f32 running sum of 2^18 of them comes
//! out 3.0e-3 low (each addition rounds at 2^-24 of the sum, all the same way; +1.1e-5 at 2^12);
//! the kernel's `PixelSum` keeps it within 4.1e-6 of the exact value at both counts (the rest is
//! the closed form's own f32 rounding).

use picomis::{CameraDesc, Film, FovAxis, Material, Preset, Rgb, Shape, Vec3};
use picomis_host::{HostScene, renderer};

const RHO: f32 = 0.5;
const RADIANCE: f32 = 901.803;

/// The plane y = 0, the sphere light of radius `r` at height `d` above the origin, the camera
/// 28 units away at 45 degrees with a field of view of 0.0005 degrees.
fn scene(r: f32, d: f32) -> HostScene {
    let camera = CameraDesc {
        origin: Vec3::new(20.0, 20.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_deg: 0.0005,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    };
    let mut s = HostScene::new(camera, Film::new(1, 1).unwrap()).unwrap();
    let plane = s.add_material(Material::lambertian(Rgb::splat(RHO)).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let corners = [
        Vec3::new(-50., 0., -50.),
        Vec3::new(-50., 0., 50.),
        Vec3::new(50., 0., 50.),
        Vec3::new(50., 0., -50.),
    ];
    s.add_shape(Shape::quad(corners).unwrap(), plane).unwrap();
    let bulb = s.add_shape(Shape::sphere(Vec3::new(0.0, d, 0.0), r).unwrap(), black).unwrap();
    s.add_area_light(bulb, Rgb::splat(RADIANCE)).unwrap();
    s
}

#[test]
fn the_mean_of_many_samples_keeps_the_exact_value() {
    for (r, d) in [(0.9f32, 5.0f32), (0.1, 5.0), (0.03333, 2.0)] {
        let exact = f64::from(RHO) * f64::from(RADIANCE) * f64::from(r * r) / f64::from(d * d);
        let s = scene(r, d);
        for spp in [1u32 << 12, 1 << 18] {
            let settings = Preset::Best.settings().with_spp(spp).unwrap().with_seed(7);
            let pixel = renderer(&s, &settings).unwrap().render_pixel(0, 0).radiance();
            let rel = f64::from(pixel.x) / exact - 1.0;
            println!("r {r}, d {d}, {spp} spp: {:.7} against {exact:.7}, {rel:+.2e}", pixel.x);
            assert!(rel.abs() < 2e-5, "r {r}, d {d}, {spp} spp: {} against {exact}, {rel:+.2e}", pixel.x);
        }
    }
}
