//! The cost of one camera sample (primary ray, emission, one light and one BSDF sample) per
//! method on each built-in scene, built with the scene's own capacities. Pixels are visited in a
//! scrambled order, so every measurement averages over the whole image.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use picomis::camera_sample;
use picomis_bench::{
    MEASUREMENT, PixelCycle, SAMPLE_SIZE, WARM_UP, build, builtin_scenes, for_scene, methods,
};
use picomis_format::SceneFile;

fn scene_group<const S: usize, const L: usize, const M: usize>(file: &SceneFile, c: &mut Criterion) {
    let scene = build::<S, L, M>(file);
    let mut group = c.benchmark_group(format!("camera_sample/{}", file.name()));
    group.throughput(Throughput::Elements(1));
    for m in methods() {
        let settings = picomis_bench::settings(&m);
        // The method's arithmetic of the ray queries; a scene it cannot represent is skipped.
        let mut scene = scene.clone();
        if let Err(e) = m.extras.prepare(&mut scene) {
            eprintln!("camera_sample/{}/{}: skipped: {e}", file.name(), m.label);
            continue;
        }
        let mut pixels = PixelCycle::new(scene.film());
        group.bench_function(BenchmarkId::from_parameter(m.label), |b| {
            b.iter(|| {
                let (x, y, s) = pixels.next_pixel();
                black_box(camera_sample(&scene, &settings, x, y, s))
            })
        });
    }
    group.finish();
}

fn camera_samples(c: &mut Criterion) {
    for file in builtin_scenes() {
        for_scene!(&file, scene_group, c);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(SAMPLE_SIZE).warm_up_time(WARM_UP).measurement_time(MEASUREMENT);
    targets = camera_samples
}
criterion_main!(benches);
