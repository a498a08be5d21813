//! The cost of one camera sample (primary ray, emission, one light and one BSDF sample) per
//! method of the study on each built-in scene (the host's list, then "defaults": the scene file's
//! own integrator, as `picomis-sim study` has it), built as the host's scene and rendered by the
//! estimator of each method's settings (`picomis_host::renderer`). Pixels are visited in a
//! scrambled order, so every measurement averages over the whole image.

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use picomis::RenderSettings;
use picomis_bench::{
    HostScene, MEASUREMENT, PixelCycle, SAMPLE_SIZE, WARM_UP, builtin_scenes, host_scene, methods,
};
use picomis_format::SceneFile;

/// Times camera samples of `scene` with `settings` as benchmark `label` of `group`.
fn bench(
    group: &mut BenchmarkGroup<'_, WallTime>,
    label: &str,
    scene: &HostScene,
    settings: &RenderSettings,
) {
    let renderer = picomis_host::renderer(scene, settings).unwrap_or_else(|e| panic!("{label}: {e}"));
    let mut pixels = PixelCycle::new(scene.film());
    group.bench_function(BenchmarkId::from_parameter(label), |b| {
        b.iter(|| {
            let (x, y, s) = pixels.next_pixel();
            black_box(renderer.camera_sample(x, y, s))
        })
    });
}

fn scene_group(file: &SceneFile, c: &mut Criterion) {
    let scene = host_scene(file);
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
        bench(&mut group, m.label, &scene, &settings);
    }
    // The scene file's own integrator, as `picomis-sim render` renders it.
    bench(&mut group, "defaults", &scene, &file.default_settings());
    group.finish();
}

fn camera_samples(c: &mut Criterion) {
    for file in builtin_scenes() {
        scene_group(&file, c);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(SAMPLE_SIZE).warm_up_time(WARM_UP).measurement_time(MEASUREMENT);
    targets = camera_samples
}
criterion_main!(benches);
