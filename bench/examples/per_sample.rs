//! Cost of a camera sample on one core: renders every pixel of a built-in scene or a scene file (default
//! veach_mis) at SPP samples (default 4) with the scene's integrator block (by the estimator of
//! the settings, `picomis_host::renderer`), the sampler named by the second argument (default:
//! the best preset's), the quad-light sampling named by the fourth
//! (default: the scene's) and the method named by the fifth (default: the scene's),
//! single-threaded, and prints ns per camera sample and a checksum of the bits. Small enough to
//! run under `valgrind --tool=callgrind` for instruction counts per camera sample:
//!
//! `cargo run --release -p picomis-bench --example per_sample -- veach_mis sobol 4 [solid-angle [balance]]`
//!
//! The environment variable `PICOMIS_LIGHT_SELECTION` (uniform, power, contribution) overrides
//! the scene's light selection.

use std::hint::black_box;
use std::time::Instant;

use picomis::{LightSelection, Method, Preset, QuadSampling, RenderSettings, SamplerKind};
use picomis_bench::{builtin_scenes, host_scene};
use picomis_format::SceneFile;

fn run(
    file: &SceneFile,
    sampler: SamplerKind,
    spp: u32,
    quads: Option<QuadSampling>,
    method: Option<Method>,
    selection: Option<LightSelection>,
) {
    let scene = host_scene(file);
    let mut settings = file.default_settings().with_sampler(sampler);
    let quads = quads.unwrap_or(settings.quad_sampling());
    settings = settings.with_quad_sampling(quads);
    if let Some(m) = method {
        let (n_light, n_bsdf) = file.default_settings().sample_counts();
        settings = RenderSettings::new(m, n_light, n_bsdf, 1, settings.seed())
            .expect("valid settings")
            .with_sampler(sampler)
            .with_light_selection(settings.light_selection())
            .with_sphere_sampling(settings.sphere_sampling())
            .with_quad_sampling(quads);
    }
    if let Some(selection) = selection {
        settings = settings.with_light_selection(selection);
    }
    let renderer = picomis_host::renderer(&scene, &settings).expect("settings the kernel accepts");
    let film = scene.film();
    let start = Instant::now();
    let mut checksum = 0u32;
    for s in 0..spp {
        for y in 0..film.height() {
            for x in 0..film.width() {
                let e = black_box(renderer.camera_sample(x, y, s));
                let r = e.radiance();
                checksum = checksum.rotate_left(5) ^ r.x.to_bits() ^ r.y.to_bits() ^ r.z.to_bits();
            }
        }
    }
    let n = f64::from(spp) * f64::from(film.pixels());
    let ns = start.elapsed().as_secs_f64() * 1e9 / n;
    println!(
        "{}: {} {spp} spp, quads {quads}, lights by {}, {}, {n} camera samples, {ns:.1} ns per camera sample, checksum {checksum:08x}",
        file.name(),
        sampler.name(),
        settings.light_selection().name(),
        settings.method()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("veach_mis", String::as_str);
    let sampler =
        args.get(2).and_then(|s| SamplerKind::from_name(s)).unwrap_or(Preset::Best.settings().sampler());
    let spp = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(4);
    let quads = args.get(4).map(|s| QuadSampling::from_name(s).expect("a quad sampling name"));
    let method = args.get(5).map(|s| Method::from_name(s).expect("a method name"));
    let selection = std::env::var("PICOMIS_LIGHT_SELECTION")
        .ok()
        .map(|s| LightSelection::from_name(&s).expect("a light selection name"));
    let files = builtin_scenes();
    let file = match files.iter().find(|f| f.name() == name) {
        Some(f) => f.clone(),
        None => SceneFile::load(std::path::Path::new(name)).expect("a built-in scene name or a scene file"),
    };
    run(&file, sampler, spp, quads, method, selection);
}
