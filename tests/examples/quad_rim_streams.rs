//! The stability suite's case "GGX alpha 1e-3, 2 x 2 quad light, mirror direction +2e-3 rad
//! above its edge" (tests/tests/stability, near_mirrors.rs) on many sample streams, against a
//! reference independent of every sampler: an adaptive quadrature over the quad of the kernel's
//! own `Material::eval` (f cos, f32) times the radiance, cos_y / d^2 (f64 sums). Is light
//! sampling with lobe mixing biased there (docs/stability.md, "Open": -9.9e-4, z -5.8 against
//! the suite's balance reference), or is the reference, or the test's standard error, off?
//!
//! ```text
//! cargo run --release -p picomis-tests --example quad_rim_streams -- \
//!     [--method light|bsdf|balance|power|...] [--lobe on|off] [--sampler independent|sobol] \
//!     [--outside 2e-3] [--alpha 1e-3] [--streams 100] [--first 1000] [--n 200000]
//! ```
//!
//! Each stream's run is the suite's: `n` estimates at the origin of the floor seen from 40
//! degrees off the normal (quads sampled by area, uniform selection); for sobol the standard
//! error is the spread of the 32 independent scrambles ([`picomis_tests::direct_run`]). Prints
//! the reference, every stream's z, and the mean and spread of z with the pooled relative
//! error of all streams and its standard error.
//!
//! Measured (issue 37, 200 streams each): BSDF sampling -1.9e-6 ± 6.3e-5 and balance -3.6e-5 ±
//! 1.6e-5 against the quadrature (1.3168405e-1; of the kernel's f32 f cos, -1.3e-5); light
//! sampling alone with lobe mixing -5.7e-4 ± 1.1e-4 (sobol) and -4.8e-4 ± 2.5e-4 (independent),
//! its z of mean -8.7 and spread 6.5 (sobol): runs that miss a rare sliver of the quad fall
//! short with a small spread, a few that meet it overshoot (see `quad_rim_pdf`).

use picomis::num::Frame;
use picomis::{
    Film, LightSelection, LobeMixing, Material, Method, QuadSampling, RenderSettings, Rgb, SamplerKind,
    Scene, Shape, Vec3,
};
use picomis_host::HostScene;
use picomis_tests::{
    DVec3, camera, d3, direct_run, f3, floor_corners, ggx_f_cos, integrate_adaptive, quad_corners,
    shading_hit,
};

const SEED: u32 = 0x0057_AB1E;
const R_GGX: f32 = 0.9;

/// The case's scene (a GGX floor, object 0, and the quad light: a wall at x = 3 facing the
/// receiver whose upper edge lies `outside` radians below the mirror direction of a view 40
/// degrees off the normal), the view direction, and the quad's corners.
fn scene(alpha: f32, outside: f32) -> (HostScene, Vec3, [Vec3; 4]) {
    let mut s: HostScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    let metal = s.add_material(Material::ggx_conductor(alpha, Rgb::splat(R_GGX)).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), metal).unwrap();
    let t = (-40.0f32).to_radians();
    let wo = Vec3::new(t.sin(), t.cos(), 0.0);
    let top = 3.0 / ((40.0f32).to_radians() + outside).tan();
    let corners =
        quad_corners(Vec3::new(3.0, top - 2.0, -1.0), Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 2.0, 0.0));
    let id = s.add_shape(Shape::quad(corners).unwrap(), black).unwrap();
    s.add_area_light(id, Rgb::ONE).unwrap();
    (s, wo, corners)
}

/// The reflected radiance at the origin (normal +y) towards `wo`: the integral over the quad
/// (radiance 1) of f cos times cos_y / d^2, by adaptive Gauss-Legendre quadrature on bands that
/// narrow towards the upper edge and the plane z = 0, where the lobe's tail is. f cos is the
/// kernel's `Material::eval` (f32; `kernel`), or its model in f64: R D(m) G1(wo) G1(wi) /
/// (4 cos_o) with GGX's D and Smith's G1 (R = [`R_GGX`]), free of f32's rounding.
fn reference(material: &Material, alpha: f64, wo: Vec3, corners: [Vec3; 4], kernel: bool) -> f64 {
    let frame = Frame::from_normal(Vec3::Y);
    let wo_local = frame.to_local(wo);
    let (p0, e1, e2) = (d3(corners[0]), d3(corners[1] - corners[0]), d3(corners[3] - corners[0]));
    let normal = e1.cross(e2);
    let (area, n) = (normal.length(), normal.normalize());
    let wo64 = d3(wo).normalize();
    let model = |wi: DVec3| ggx_f_cos(wo64, wi, alpha, f64::from(R_GGX));
    let f = |s: f64, t: f64| {
        let y = p0 + e1 * s + e2 * t;
        let d2 = y.length_squared();
        let wi = y / d2.sqrt();
        let cos_y = -n.dot(wi);
        if cos_y <= 0.0 {
            return 0.0;
        }
        let fcos =
            if kernel { f64::from(material.eval(wo_local, frame.to_local(f3(wi))).x) } else { model(wi) };
        fcos * cos_y / d2 * area
    };
    // Bands in t (towards the upper edge, t = 1) and in s (about z = 0, s = 1/2).
    let tb = [0.0, 0.5, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.998, 0.999, 0.9995, 0.9998, 0.9999, 1.0];
    let sb = [
        0.0, 0.3, 0.45, 0.48, 0.49, 0.495, 0.498, 0.499, 0.5, 0.501, 0.502, 0.505, 0.51, 0.52, 0.55, 0.7, 1.0,
    ];
    // The kernel's f32 values are noisy at 1e-7: no deep refinement of the noise.
    let (tol, depth) = if kernel { (1e-9, 6) } else { (1e-13, 12) };
    let mut sum = 0.0;
    for s in sb.windows(2) {
        for t in tb.windows(2) {
            sum += integrate_adaptive(&f, [s[0], s[1]], [t[0], t[1]], tol, depth);
        }
    }
    sum
}

fn main() {
    let (mut method, mut lobe, mut sampler) =
        (Method::from_name("light").unwrap(), LobeMixing::On, SamplerKind::Sobol);
    let (mut alpha, mut outside, mut count, mut first, mut n) =
        (1e-3f32, 2e-3f32, 100u32, 1000u32, 200_000u32);
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let v = it.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--method" => method = Method::from_name(&v).expect("a method"),
            "--lobe" => lobe = LobeMixing::from_name(&v).expect("on or off"),
            "--sampler" => sampler = SamplerKind::from_name(&v).expect("a sampler"),
            "--alpha" => alpha = v.parse().expect("a number"),
            "--outside" => outside = v.parse().expect("a number"),
            "--streams" => count = v.parse().expect("a count"),
            "--first" => first = v.parse().expect("a stream"),
            "--n" => n = v.parse().expect("a count"),
            _ => panic!("unknown flag {flag}"),
        }
    }
    let (scene, wo, corners) = scene(alpha, outside);
    let exact = reference(&scene.materials()[1], f64::from(alpha), wo, corners, false);
    let of_kernel = reference(&scene.materials()[1], f64::from(alpha), wo, corners, true);
    let settings = RenderSettings::new(method, 1, 1, 1, SEED)
        .unwrap()
        .with_light_selection(LightSelection::Uniform)
        .with_quad_sampling(QuadSampling::Area)
        .with_lobe_mixing(lobe)
        .with_sampler(sampler);
    println!(
        "quad rim, alpha {alpha:e}, outside {outside:e}: {method:?}, lobe {lobe:?}, {sampler:?}, n = {n}; \
         quadrature reference {exact:.7e} (of the kernel's f32 f cos: {of_kernel:.7e}, {:+.1e})",
        of_kernel / exact - 1.0
    );
    let streams: Vec<u32> = (first..first + count).collect();
    let results: Vec<(u32, f64, f64, f64)> = std::thread::scope(|s| {
        let handles: Vec<_> = streams
            .chunks(streams.len().div_ceil(2))
            .map(|chunk| {
                let (scene, settings) = (&scene, &settings);
                s.spawn(move || {
                    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
                    chunk
                        .iter()
                        .map(|&stream| {
                            let e = direct_run(scene, settings, &hit, wo, stream, n).total(0);
                            (stream, e.mean, e.stderr, e.z(exact))
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    for (stream, mean, se, z) in &results {
        println!(
            "stream {stream}: mean {mean:.6e} ± {se:.1e}, rel. error {:+.2e}, z {z:+.2}",
            mean / exact - 1.0
        );
    }
    let k = results.len() as f64;
    let zs: Vec<f64> = results.iter().map(|r| r.3).collect();
    let zm = zs.iter().sum::<f64>() / k;
    let zsd = (zs.iter().map(|z| (z - zm).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
    let means: Vec<f64> = results.iter().map(|r| r.1).collect();
    let m = means.iter().sum::<f64>() / k;
    let msd = (means.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
    let rms_se = (results.iter().map(|r| r.2 * r.2).sum::<f64>() / k).sqrt();
    println!(
        "{} streams: z mean {zm:+.3} ± {:.3}, sd {zsd:.3}, |z| > 3: {}, |z| > 4: {}; pooled mean {m:.7e}, rel. \
         error {:+.3e} ± {:.1e}; spread of the runs' means / their mean standard error: {:.3}",
        zs.len(),
        zsd / k.sqrt(),
        zs.iter().filter(|z| z.abs() > 3.0).count(),
        zs.iter().filter(|z| z.abs() > 4.0).count(),
        m / exact - 1.0,
        msd / k.sqrt() / exact,
        msd / rms_se
    );
}
