//! The cost of each sampling routine: `picomis::sampling::*`, `Material::sample/eval/pdf`,
//! `LightSampler::sample/pdf` of one light (typed light strategies), the MIS weights, the sampler,
//! and `Scene::intersect` / `Scene::unoccluded` on the Veach scene. Inputs cycle through fixed
//! tables of random numbers.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use picomis::light::select::Uniform;
use picomis::light::sphere::{self, SphereSampler};
use picomis::light::{lobe, quad};
use picomis::sampling::*;
use picomis::{
    CameraDesc, Film, FovAxis, Heuristic, LightId, LightSampler, Lights, Material, Method, Rgb, Sampler,
    Scene, ShadingPoint, Shape, ShapeId, SurfacePoint, Vec3,
};
use picomis_bench::{INPUTS, Inputs, MEASUREMENT, SAMPLE_SIZE, WARM_UP, build, builtin_scenes};

const MASK: usize = INPUTS - 1;

/// Benchmarks `f(i)` for i cycling through the input tables.
fn cycle<T>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    mut f: impl FnMut(usize) -> T,
) {
    let mut i = 0usize;
    group.bench_function(name, |b| {
        b.iter(|| {
            i = (i + 1) & MASK;
            black_box(f(black_box(i)))
        })
    });
}

fn routines(c: &mut Criterion) {
    let t = Inputs::new();
    let mut g = c.benchmark_group("sampling");
    g.throughput(Throughput::Elements(1));
    cycle(&mut g, "sample_concentric_disk", |i| sample_concentric_disk(t.u[i]));
    cycle(&mut g, "sample_cosine_hemisphere", |i| sample_cosine_hemisphere(t.u[i]));
    cycle(&mut g, "cosine_hemisphere_pdf", |i| cosine_hemisphere_pdf(t.wi[i].z));
    cycle(&mut g, "sample_uniform_sphere", |i| sample_uniform_sphere(t.u[i]));
    cycle(&mut g, "cone_one_minus_cos", |i| cone_one_minus_cos(t.u1[i] * 0.5));
    cycle(&mut g, "sample_uniform_cone", |i| sample_uniform_cone(t.u[i], 0.05));
    cycle(&mut g, "uniform_cone_pdf", |i| uniform_cone_pdf(t.u1[i] * 0.1));
    cycle(&mut g, "ggx_d", |i| ggx_d(t.wi[i], 0.05));
    cycle(&mut g, "ggx_g1", |i| ggx_g1(t.wi[i], 0.05));
    cycle(&mut g, "sample_ggx_vndf", |i| sample_ggx_vndf(t.wo[i], 0.05, t.u[i]));
    cycle(&mut g, "ggx_vndf_pdf", |i| ggx_vndf_pdf(t.wo[i], t.wi[i], 0.05));
    let weights: Vec<f32> = (0..16).map(|k| 1.0 + k as f32).collect();
    let discrete = GridDistribution::<16>::new(&weights);
    cycle(&mut g, "grid_distribution_sample_16", |i| discrete.sample(t.u1[i]));
    cycle(&mut g, "grid_distribution_pmf_16", |i| discrete.pmf(i & 15));
    let mut sampler = Sampler::new(1, 2, 3);
    cycle(&mut g, "sampler_new_next_2d", |i| {
        sampler = Sampler::new(7, i as u32, 0);
        sampler.next_2d()
    });
    g.finish();
}

fn materials(c: &mut Criterion) {
    let t = Inputs::new();
    let mut g = c.benchmark_group("material");
    g.throughput(Throughput::Elements(1));
    let list = [
        ("lambertian", Material::lambertian(Rgb::splat(0.5)).unwrap()),
        ("ggx_0.005", Material::ggx_conductor(0.005, Rgb::ONE).unwrap()),
        ("ggx_0.1", Material::ggx_conductor(0.1, Rgb::ONE).unwrap()),
    ];
    for (name, m) in list {
        cycle(&mut g, &format!("{name}/sample"), |i| m.sample(t.wo[i], t.u[i]));
        cycle(&mut g, &format!("{name}/eval"), |i| m.eval(t.wo[i], t.wi[i]));
        cycle(&mut g, &format!("{name}/pdf"), |i| m.pdf(t.wo[i], t.wi[i]));
    }
    g.finish();
}

/// A scene of one light: an area light on `shape`, or a point light without one.
type OneLight = Scene<1, 1, 1>;

fn one_light(shape: Option<Shape>) -> OneLight {
    let camera = CameraDesc {
        origin: Vec3::new(0.0, 1.0, 4.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_deg: 40.0,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    };
    let mut scene = OneLight::new(camera, Film::new(4, 4).expect("a film")).expect("a camera");
    match shape {
        Some(shape) => {
            let black = scene.add_material(Material::lambertian(Rgb::ZERO).expect("albedo")).expect("room");
            let id = scene.add_shape(shape, black).expect("room");
            scene.add_area_light(id, Rgb::splat(10.0)).expect("room");
        }
        None => {
            scene.add_point_light(Vec3::new(0.0, 2.0, 0.0), Rgb::splat(10.0)).expect("room");
        }
    }
    scene
}

/// `LightSampler::sample` and `pdf` of the one light of `scene`, spheres sampled by `Sp` (quads
/// by area), from the shading points `xs` on a floor.
fn light_case<Sp: SphereSampler>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    scene: &OneLight,
    xs: &[Vec3],
    t: &Inputs,
) {
    let lights = LightSampler::<Lights<Uniform, Sp, quad::ByArea, lobe::Off>, 1, 1, 1>::new(scene);
    let diffuse = Material::lambertian(Rgb::splat(0.5)).expect("valid albedo");
    let at: Vec<ShadingPoint> =
        xs.iter().map(|&p| ShadingPoint { p, n: Vec3::Y, wo: Vec3::Y, bsdf: diffuse }).collect();
    let light = LightId::new(0);
    cycle(g, &format!("{name}/sample"), |i| lights.sample(light, &at[i], t.u[i]));
    // Points on the light seen from each x, as a BSDF ray would find them.
    let shape = scene.objects().first().map(|o| o.shape);
    let ys: Vec<SurfacePoint> = (0..INPUTS)
        .map(|i| {
            let s = lights.sample(light, &at[i], t.u[(i + 1) & MASK]);
            let p = s.map_or(Vec3::new(0.0, 2.0, 0.0), |s| xs[i] + s.wi * s.distance);
            SurfacePoint { p, n: shape.map_or(Vec3::Y, |sh| sh.normal_at(p)) }
        })
        .collect();
    cycle(g, &format!("{name}/pdf"), |i| lights.pdf(light, &at[i], &ys[i]));
}

fn lights(c: &mut Criterion) {
    let t = Inputs::new();
    let mut g = c.benchmark_group("light");
    g.throughput(Throughput::Elements(1));
    // Shading points on a 4 x 4 floor patch; lights 2 units above it.
    let xs: Vec<Vec3> = t.u.iter().map(|u| Vec3::new(4.0 * u.x - 2.0, 0.0, 4.0 * u.y - 2.0)).collect();
    let sphere = Shape::sphere(Vec3::new(0.0, 2.0, 0.0), 0.3).unwrap();
    let quad = Shape::quad([
        Vec3::new(-0.5, 2.0, -0.5),
        Vec3::new(-0.5, 2.0, 0.5),
        Vec3::new(0.5, 2.0, 0.5),
        Vec3::new(0.5, 2.0, -0.5),
    ])
    .unwrap();
    light_case::<sphere::ByArea>(&mut g, "sphere_area", &one_light(Some(sphere)), &xs, &t);
    light_case::<sphere::InCone>(&mut g, "sphere_cone", &one_light(Some(sphere)), &xs, &t);
    light_case::<sphere::InCone>(&mut g, "quad", &one_light(Some(quad)), &xs, &t);
    light_case::<sphere::InCone>(&mut g, "point", &one_light(None), &xs, &t);
    g.finish();
}

fn heuristics(c: &mut Criterion) {
    let t = Inputs::new();
    let mut g = c.benchmark_group("heuristic");
    g.throughput(Throughput::Elements(1));
    // The kernel's heuristics (default parameters) and one power heuristic with a fractional beta.
    let mut list: Vec<Method> = Method::ALL.into_iter().filter(|m| matches!(m, Method::Mis(_))).collect();
    list.push(Method::Mis(Heuristic::Power { beta: 1.5 }));
    for m in list {
        let Method::Mis(h) = m else { continue };
        let name = match (m.beta(), m.alpha()) {
            (Some(p), _) | (_, Some(p)) => format!("{m}_{p}"),
            _ => m.to_string(),
        };
        cycle(&mut g, &name, |i| h.weights([t.u[i].x * 10.0, t.u[i].y]));
    }
    g.finish();
}

fn scene_queries(c: &mut Criterion) {
    let t = Inputs::new();
    let file = builtin_scenes().into_iter().find(|f| f.name() == "veach_mis").expect("veach_mis scene");
    let scene = build::<11, 5, 6>(&file);
    let rays: Vec<_> = t.u.iter().map(|&u| scene.camera().ray(u).0).collect();
    let hits: Vec<_> = rays.iter().map(|r| scene.intersect(r, 0.0, f32::INFINITY, None)).collect();
    let mut g = c.benchmark_group("scene/veach_mis");
    g.throughput(Throughput::Elements(1));
    cycle(&mut g, "intersect_camera_ray", |i| scene.intersect(&rays[i], 0.0, f32::INFINITY, None));
    // Shadow rays from the visible points towards the second light's centre.
    let target = Vec3::new(-1.25, 0.0, 0.0);
    let shadow: Vec<_> = hits
        .iter()
        .map(|h| {
            let p = h.map_or(Vec3::new(0.0, -4.0, 0.0), |h| h.point.p);
            let d = target - p;
            (
                picomis::Ray { origin: p, dir: d.normalize() },
                d.length(),
                h.map_or(ShapeId::new(0), |h| h.object),
            )
        })
        .collect();
    cycle(&mut g, "unoccluded_shadow_ray", |i| {
        let (ray, dist, a) = &shadow[i];
        scene.unoccluded(ray, *dist, *a, Some(ShapeId::new(7)))
    });
    let lights =
        LightSampler::<Lights<Uniform, sphere::InCone, quad::ByArea, lobe::Off>, 11, 5, 6>::new(&scene);
    let diffuse = Material::lambertian(Rgb::splat(0.5)).expect("valid albedo");
    cycle(&mut g, "sample_light_cone", |i| {
        let p = shadow[i].0.origin;
        let point = ShadingPoint { p, n: Vec3::Y, wo: Vec3::Y, bsdf: diffuse };
        // (Uniform selection reads nothing at the point: its selection there is `()`.)
        let chosen = lights.select(&lights.selection_at(&point), t.u1[i])?;
        lights.sample(chosen.light, &point, t.u[i]).map(|s| s.pdf * chosen.probability)
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(SAMPLE_SIZE).warm_up_time(WARM_UP).measurement_time(MEASUREMENT);
    targets = routines, materials, lights, heuristics, scene_queries
}
criterion_main!(benches);
