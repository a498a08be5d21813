//! How the cost of one camera sample (balance heuristic, one light and one BSDF sample) grows
//! with the scene: against the number of shapes (a floor, one sphere light out of view and 0 to
//! 62 visible spheres: 2 to 64 shapes) and against the number of lights (always 33 shapes: a
//! floor, 16 visible spheres and 16 spheres out of view of which 1 to 16 emit; lights chosen
//! by every light selection). The kernel intersects every shape (no acceleration structure), so
//! the first curve should be about linear; uniform light selection is O(1), selection by power
//! a linear scan over the lights, selection by contribution an estimate per light at every
//! shading point.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use picomis::{Heuristic, LightSelection, Method, RenderSettings};
use picomis_bench::{MEASUREMENT, PixelCycle, SAMPLE_SIZE, SynthScene, WARM_UP, synthetic_scene};

fn balance() -> RenderSettings {
    RenderSettings::new(Method::Mis(Heuristic::Balance), 1, 1, 1, 0).expect("valid settings")
}

/// Camera samples of `scene` by the estimator of `settings` (`picomis_host::renderer`).
fn run(b: &mut criterion::Bencher<'_>, scene: &SynthScene, settings: &RenderSettings) {
    let renderer = picomis_host::renderer(scene, settings).expect("settings the kernel accepts");
    let mut pixels = PixelCycle::new(scene.film());
    b.iter(|| {
        let (x, y, s) = pixels.next_pixel();
        black_box(renderer.camera_sample(x, y, s))
    })
}

fn shapes(c: &mut Criterion) {
    let mut group = c.benchmark_group("scaling/shapes");
    group.throughput(Throughput::Elements(1));
    let settings = balance();
    for n in [2usize, 4, 8, 16, 32, 64] {
        let scene = synthetic_scene(n - 2, 1, 1);
        group.bench_with_input(BenchmarkId::from_parameter(n), &scene, |b, scene| run(b, scene, &settings));
    }
    group.finish();
}

fn lights(c: &mut Criterion) {
    for selection in LightSelection::ALL {
        let mut group = c.benchmark_group(format!("scaling/lights_{}", selection.name()));
        group.throughput(Throughput::Elements(1));
        let settings = balance().with_light_selection(selection);
        for n in [1usize, 2, 4, 8, 16] {
            let scene = synthetic_scene(16, 16, n);
            group.bench_with_input(BenchmarkId::from_parameter(n), &scene, |b, scene| {
                run(b, scene, &settings)
            });
        }
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(SAMPLE_SIZE).warm_up_time(WARM_UP).measurement_time(MEASUREMENT);
    targets = shapes, lights
}
criterion_main!(benches);
