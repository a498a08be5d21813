//! Cost of a camera sample on one core: renders every pixel of a built-in scene (default
//! veach_mis) at SPP samples (default 4) with the scene's integrator block and the sampler named
//! by the second argument (default: the default), single-threaded, and prints ns per camera
//! sample and a checksum of the bits. Small enough to run under
//! `valgrind --tool=callgrind` for instruction counts per camera sample:
//!
//! `cargo run --release -p picomis-bench --example per_sample -- veach_mis sobol 4`

use std::hint::black_box;
use std::time::Instant;

use picomis::{SamplerKind, camera_sample};
use picomis_bench::{build, builtin_scenes, for_scene};
use picomis_format::SceneFile;

fn run<const S: usize, const L: usize, const M: usize>(file: &SceneFile, sampler: SamplerKind, spp: u32) {
    let scene = build::<S, L, M>(file);
    let settings = file.default_settings().expect("valid built-in settings").with_sampler(sampler);
    let film = scene.film();
    let start = Instant::now();
    let mut checksum = 0u32;
    for s in 0..spp {
        for y in 0..film.height() {
            for x in 0..film.width() {
                let e = black_box(camera_sample(&scene, &settings, x, y, s));
                let r = e.radiance();
                checksum = checksum.rotate_left(5) ^ r.x.to_bits() ^ r.y.to_bits() ^ r.z.to_bits();
            }
        }
    }
    let n = f64::from(spp) * f64::from(film.pixels());
    let ns = start.elapsed().as_secs_f64() * 1e9 / n;
    println!(
        "{}: {} {spp} spp, {n} camera samples, {ns:.1} ns per camera sample, checksum {checksum:08x}",
        file.name(),
        sampler.name()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("veach_mis", String::as_str);
    let sampler = args.get(2).and_then(|s| SamplerKind::from_name(s)).unwrap_or_default();
    let spp = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(4);
    let files = builtin_scenes();
    let file = files.iter().find(|f| f.name() == name).expect("a built-in scene name");
    for_scene!(file, run, sampler, spp);
}
