//! The z-scores of one check of tests/tests/unbiased.rs's case "(e) four lights" (three sphere
//! lights and a quad light over a Lambertian floor, against the closed form) on many sample
//! streams: is a failure chance (z of mean 0 and spread 1 over the streams) or a bias (a mean of
//! z away from 0)? Issue 37, item 11, and the sharper standard error of the 32 scrambles.
//!
//! ```text
//! cargo run --release -p picomis-tests --example four_lights_streams -- \
//!     [--selection uniform|power|contribution] [--spheres area|cone] [--method NAME] \
//!     [--sampler independent|sobol] [--streams 100] [--first 20000] [--n 200000] [--light K] \
//!     [--list S1,S2,..]
//! ```
//!
//! Each stream's run is the check's: `n` estimates at the origin of the floor towards the
//! suite's view direction, with seed 2024, one light sample and one BSDF sample. For the
//! independent stream the standard error is the independent-sample formula (the suite's); for
//! sobol it is the spread of the 32 independent scrambles ([`picomis_tests::direct_run`]).
//! `--light K` keeps light K's radiance only (the others black, so that under uniform selection
//! every sample is the same and the estimate is light K's part of the whole) and compares with
//! its part of the closed form. `--list` runs the given streams instead of `--first` onwards.
//! Prints every stream's z per channel, then per channel the mean and standard deviation of z
//! (with the mean's standard error, sd / sqrt(streams)), the mean relative error with its
//! standard error, and how many streams lie beyond |z| = 3 and 4. `--blocks B` prints instead
//! the z of B consecutive blocks of each stream's estimates (independent stream); `--replicas
//! on` the sobol runs' 32 scrambles: their distribution over all streams, the variance of the
//! runs' means against the scrambles' (1 when they are independent) and each run's spread.
//!
//! Measured (issue 37):
//! - the check that moved from stream 7000 to 7050 (power selection, area sampling, the maximum
//!   heuristic, independent: stream 7007 gives z -4.59 -4.35 -3.23): streams 7000 to 7999 give
//!   z of mean +0.010 ± 0.032, spread 1.005, 3 beyond 3 and 1 (7007) beyond 4, relative error
//!   +4.6e-5 ± 1.2e-4; 7007 continued (`--n 3200000`) gives z -0.46: chance;
//! - uniform selection, area sampling, power heuristic, sobol with the scrambles' spread (stream
//!   6004: z -3.33 -4.33 -5.03): streams 6000 to 6999 give relative errors +5e-6 ± 1.0e-5,
//!   +6e-6 ± 9e-6, +7e-6 ± 8.5e-6 (no bias), z spread 1.02 to 1.075 (Student's t31: 1.034) but
//!   6 |z| > 4 in 3,000 (1.1 expected); the scrambles are independent (variance ratio 1.056,
//!   1.032, 0.961 ± 0.045) and near normal (kurtosis 3.14, 3.06, 2.96); 6004's scrambles have a
//!   spread 0.57 of the usual (P about 1e-4 under chi-square): its mean is 2.9 standard errors
//!   low, its z of -5.03 comes from the small spread.

use picomis::{
    Film, LightSelection, Material, Method, RenderSettings, Rgb, SamplerKind, Scene, Shape, SphereSampling,
    Vec3,
};
use picomis_host::HostScene;
use picomis_tests::{
    DVec3, camera, d3, direct_run, floor_corners, lambert_polygon_irradiance, quad_corners, rgb64,
    shading_hit, sphere_irradiance,
};
use std::f64::consts::PI;

const ALBEDO: Rgb = Rgb::new(0.8, 0.5, 0.2);
const SEED: u32 = 2024;

/// The lights of case (e): three spheres (centre, radius, radiance) and a quad's corners and
/// radiance.
fn lights() -> ([(Vec3, f32, Rgb); 3], [Vec3; 4], Rgb) {
    let spheres = [
        (Vec3::new(2.0, 2.5, 0.0), 0.9, Rgb::new(1.0, 1.5, 2.0)),
        (Vec3::new(-1.5, 2.0, 1.0), 0.3, Rgb::new(30.0, 20.0, 10.0)),
        (Vec3::new(-0.5, 3.0, -2.0), 0.5, Rgb::new(2.0, 2.0, 2.0)),
    ];
    let corners = quad_corners(Vec3::new(0.5, 2.0, 1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    (spheres, corners, Rgb::new(0.5, 0.3, 0.8))
}

/// Case (e)'s scene, every light black but `only` when given, and each light's part of the
/// exact reflected radiance at the origin.
fn scene(only: Option<usize>) -> (HostScene, [[f64; 3]; 4]) {
    let (spheres, corners, ql) = lights();
    let lit = |k: usize, l: Rgb| if only.is_none_or(|o| o == k) { l } else { Rgb::ZERO };
    let mut s: HostScene = Scene::new(camera(), Film::new(8, 8).unwrap()).unwrap();
    let white = s.add_material(Material::lambertian(ALBEDO).unwrap()).unwrap();
    let black = s.add_material(Material::lambertian(Rgb::ZERO).unwrap()).unwrap();
    s.add_shape(Shape::quad(floor_corners(50.0)).unwrap(), white).unwrap();
    let out = |e: f64, l: Rgb| {
        let (a, l) = (rgb64(ALBEDO), rgb64(l));
        [0, 1, 2].map(|c| a[c] / PI * e * l[c])
    };
    let mut parts = [[0.0; 3]; 4];
    for (k, (c, r, l)) in spheres.into_iter().enumerate() {
        let id = s.add_shape(Shape::sphere(c, r).unwrap(), black).unwrap();
        s.add_area_light(id, lit(k, l)).unwrap();
        let v = d3(c);
        parts[k] = out(sphere_irradiance(1.0, f64::from(r), v.length(), v.y / v.length()), lit(k, l));
    }
    let id = s.add_shape(Shape::quad(corners).unwrap(), black).unwrap();
    s.add_area_light(id, lit(3, ql)).unwrap();
    let e = lambert_polygon_irradiance(DVec3::ZERO, DVec3::Y, &corners.map(d3), 1.0);
    parts[3] = out(e, lit(3, ql));
    (s, parts)
}

struct Args {
    selection: LightSelection,
    spheres: SphereSampling,
    method: Method,
    sampler: SamplerKind,
    streams: Vec<u32>,
    n: u32,
    light: Option<usize>,
    blocks: u32,
    replicas: bool,
}

fn args() -> Args {
    let mut a = Args {
        selection: LightSelection::Power,
        spheres: SphereSampling::Area,
        method: Method::from_name("maximum").unwrap(),
        sampler: SamplerKind::Independent,
        streams: Vec::new(),
        n: 200_000,
        light: None,
        blocks: 0,
        replicas: false,
    };
    let (mut count, mut first) = (100u32, 20_000u32);
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().unwrap_or_else(|| panic!("{flag} needs a value"));
        match flag.as_str() {
            "--selection" => a.selection = LightSelection::from_name(&value).expect("a light selection"),
            "--spheres" => a.spheres = SphereSampling::from_name(&value).expect("a sphere sampling"),
            "--method" => a.method = Method::from_name(&value).expect("a method"),
            "--sampler" => a.sampler = SamplerKind::from_name(&value).expect("a sampler"),
            "--streams" => count = value.parse().expect("a count"),
            "--first" => first = value.parse().expect("a stream"),
            "--n" => a.n = value.parse().expect("a count"),
            "--light" => a.light = Some(value.parse().expect("a light index")),
            "--replicas" => a.replicas = value == "on",
            "--blocks" => a.blocks = value.parse().expect("a count"),
            "--list" => a.streams = value.split(',').map(|s| s.parse().expect("a stream")).collect(),
            _ => panic!("unknown flag {flag}"),
        }
    }
    if a.streams.is_empty() {
        a.streams = (first..first + count).collect();
    }
    a
}

fn main() {
    let a = args();
    let (scene, parts) = scene(a.light);
    let exact: [f64; 3] = [0, 1, 2].map(|c| parts.iter().map(|p| p[c]).sum());
    let settings = RenderSettings::new(a.method, 1, 1, 1, SEED)
        .unwrap()
        .with_sphere_sampling(a.spheres)
        .with_light_selection(a.selection)
        .with_sampler(a.sampler);
    println!(
        "case (e) four lights, {:?}, {:?}, {:?}, {:?}, light {:?}, n = {}, exact {:.6e} {:.6e} {:.6e}",
        a.method, a.selection, a.spheres, a.sampler, a.light, a.n, exact[0], exact[1], exact[2]
    );
    if a.replicas {
        replicas(&scene, &settings, &a.streams, a.n, exact);
        return;
    }
    if a.blocks > 0 {
        for &stream in &a.streams {
            blocks(&scene, &settings, stream, a.n, a.blocks, exact);
        }
        return;
    }
    // Two threads: the streams are independent.
    let results: Vec<(u32, [(f64, f64); 3])> = std::thread::scope(|s| {
        let chunks: Vec<Vec<u32>> =
            a.streams.chunks(a.streams.len().div_ceil(2)).map(|c| c.to_vec()).collect();
        let handles: Vec<_> = chunks
            .into_iter()
            .map(|chunk| {
                let (scene, settings) = (&scene, &settings);
                s.spawn(move || {
                    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
                    let wo = Vec3::new(0.3, 0.9, -0.2).normalize();
                    chunk
                        .into_iter()
                        .map(|stream| {
                            let run = direct_run(scene, settings, &hit, wo, stream, a.n);
                            (
                                stream,
                                [0, 1, 2].map(|c| {
                                    let e = run.total(c);
                                    (e.z(exact[c]), (e.mean - exact[c]) / exact[c])
                                }),
                            )
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    for (stream, z) in &results {
        println!("stream {stream}: z {:+.2} {:+.2} {:+.2}", z[0].0, z[1].0, z[2].0);
    }
    let k = results.len() as f64;
    for c in 0..3 {
        let zs: Vec<f64> = results.iter().map(|r| r.1[c].0).collect();
        let rel: Vec<f64> = results.iter().map(|r| r.1[c].1).collect();
        let mean = zs.iter().sum::<f64>() / k;
        let sd = (zs.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
        let rel_mean = rel.iter().sum::<f64>() / k;
        let rel_sd = (rel.iter().map(|r| (r - rel_mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt();
        let beyond = |t: f64| zs.iter().filter(|z| z.abs() > t).count();
        let (min, max) = zs.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &z| (lo.min(z), hi.max(z)));
        println!(
            "channel {c}: {} streams, z mean {mean:+.3} ± {:.3}, sd {sd:.3}, min {min:+.2}, max {max:+.2}, \
             |z| > 3: {}, |z| > 4: {}; rel. error mean {rel_mean:+.2e} ± {:.1e}",
            zs.len(),
            sd / k.sqrt(),
            beyond(3.0),
            beyond(4.0),
            rel_sd / k.sqrt()
        );
    }
}

/// The z-score of each of `count` consecutive blocks of the `n` estimates of `stream` (estimate
/// i from (seed, stream, i), the independent stream's order), channel by channel: where in the
/// run a deviation comes from.
fn blocks(scene: &HostScene, settings: &RenderSettings, stream: u32, n: u32, count: u32, exact: [f64; 3]) {
    let it = picomis_host::renderer(scene, settings).unwrap();
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let wo = Vec3::new(0.3, 0.9, -0.2).normalize();
    let size = n / count;
    for b in 0..count {
        let mut st = picomis_tests::RgbStats::default();
        for i in b * size..(b + 1) * size {
            let mut sampler = picomis::Sampler::with_kind(settings.sampler(), settings.seed(), stream, i);
            let (light, bsdf) = it.estimate_direct(&hit, wo, &mut sampler);
            st.push(light.contribution + bsdf.contribution);
        }
        let z = [0, 1, 2].map(|c| (st.0[c].mean() - exact[c]) / st.0[c].stderr());
        let max = st.0[0].mean() + st.0[0].stderr() * 0.0;
        println!(
            "stream {stream}, estimates {}..{}: z {:+.2} {:+.2} {:+.2} (mean {max:.4e})",
            b * size,
            (b + 1) * size,
            z[0],
            z[1],
            z[2]
        );
    }
}

/// The sobol runs' scrambles one by one: each scramble's mean relative error per channel over
/// every stream, standardised by their spread across all streams, with their skewness and
/// kurtosis (3 for a normal distribution): whether the 32 scrambles' means are normal, as
/// Student's t of their spread assumes. Prints the runs' most extreme scrambles.
fn replicas(scene: &HostScene, settings: &RenderSettings, streams: &[u32], n: u32, exact: [f64; 3]) {
    let hit = shading_hit(picomis::ShapeId::new(0), Vec3::ZERO, Vec3::Y);
    let wo = Vec3::new(0.3, 0.9, -0.2).normalize();
    let per = n / picomis_tests::SCRAMBLES;
    let mut all: Vec<(u32, u32, [f64; 3])> = Vec::new();
    for &stream in streams {
        for j in 0..picomis_tests::SCRAMBLES {
            let st = picomis_tests::direct_stats(
                scene,
                settings,
                &hit,
                wo,
                picomis_tests::scramble_stream(stream, j),
                per,
            );
            all.push((stream, j, [0, 1, 2].map(|c| st.total.0[c].mean() / exact[c] - 1.0)));
        }
    }
    if streams.len() <= 3 {
        for r in &all {
            println!(
                "stream {} scramble {:2}: rel. error {:+.3e} {:+.3e} {:+.3e}",
                r.0, r.1, r.2[0], r.2[1], r.2[2]
            );
        }
    }
    let k = all.len() as f64;
    for c in 0..3 {
        let mean = all.iter().map(|r| r.2[c]).sum::<f64>() / k;
        let var = all.iter().map(|r| (r.2[c] - mean).powi(2)).sum::<f64>() / k;
        let m3 = all.iter().map(|r| (r.2[c] - mean).powi(3)).sum::<f64>() / k;
        let m4 = all.iter().map(|r| (r.2[c] - mean).powi(4)).sum::<f64>() / k;
        println!(
            "channel {c}: {} scrambles of {per}: mean rel. error {mean:+.2e} ± {:.1e}, sd {:.2e}, skewness {:+.2}, \
             kurtosis {:.2}",
            all.len(),
            (var / k).sqrt(),
            var.sqrt(),
            m3 / var.powf(1.5),
            m4 / (var * var)
        );
        // Between the runs: the variance of the runs' means against the scrambles' variance over
        // their number (1 when the scrambles of a run are independent).
        let runs: Vec<f64> = streams
            .iter()
            .map(|&st| {
                let v: Vec<f64> = all.iter().filter(|r| r.0 == st).map(|r| r.2[c]).collect();
                v.iter().sum::<f64>() / v.len() as f64
            })
            .collect();
        let r = runs.len() as f64;
        let between = runs.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (r - 1.0);
        println!(
            "  variance of the runs' means / (scrambles' variance / {}): {:.3} (1 ± {:.3} if independent)",
            picomis_tests::SCRAMBLES,
            between / (var / f64::from(picomis_tests::SCRAMBLES)),
            (2.0 / (r - 1.0)).sqrt()
        );
        // Each run's spread of its scrambles against the spread over all runs: for independent
        // normal scrambles, (s / sigma)^2 is chi-square with 31 degrees of freedom over 31 (mean
        // 1, sd 0.254; below 0.5, 0.4 and 0.33 with probabilities 9.2e-3, 1.2e-3 and 1.6e-4).
        let spreads: Vec<f64> = streams
            .iter()
            .map(|&st| {
                let v: Vec<f64> = all.iter().filter(|r| r.0 == st).map(|r| r.2[c]).collect();
                let m = v.iter().sum::<f64>() / v.len() as f64;
                v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() as f64 - 1.0) / var
            })
            .collect();
        let sm = spreads.iter().sum::<f64>() / r;
        let ssd = (spreads.iter().map(|x| (x - sm).powi(2)).sum::<f64>() / (r - 1.0)).sqrt();
        let below = |t: f64| spreads.iter().filter(|&&x| x < t).count();
        println!(
            "  each run's (s / sigma)^2: mean {sm:.3}, sd {ssd:.3}, below 0.5: {}, below 0.4: {}, below 0.33: {}",
            below(0.5),
            below(0.4),
            below(0.33)
        );
        let mut sorted: Vec<_> = all.iter().map(|r| ((r.2[c] - mean) / var.sqrt(), r.0, r.1)).collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let show = |v: &[(f64, u32, u32)]| {
            v.iter()
                .map(|(z, s, j)| format!("{z:+.1} (stream {s}, scramble {j})"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!("  lowest: {}", show(&sorted[..5]));
        println!("  highest: {}", show(&sorted[sorted.len() - 5..]));
    }
}
