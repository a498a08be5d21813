//! Random valid scenes and settings (module docs of the suite): their proptest strategies and the
//! kernel scene of a drawn spec.

use picomis::{
    CameraDesc, Film, FovAxis, Heuristic, LightSelection, LobeMixing, Material, Method, QuadSampling,
    RenderSettings, Rgb, Scene, Shape, SphereSampling, Vec3,
};
use picomis_host::HostScene;
use proptest::prelude::*;

/// The scenes' type: the host's (their settings are drawn at run time).
pub type S = HostScene;

#[derive(Clone, Copy, Debug)]
enum MaterialSpec {
    Lambertian(Rgb),
    Ggx(f32, Rgb),
}

#[derive(Clone, Copy, Debug)]
enum ShapeSpec {
    Sphere(Vec3, f32),
    Quad(Vec3, Vec3, Vec3),
}

#[derive(Clone, Copy, Debug)]
struct ObjectSpec {
    shape: ShapeSpec,
    material: MaterialSpec,
    radiance: Option<f32>,
}

#[derive(Clone, Debug)]
pub struct SceneSpec {
    objects: Vec<ObjectSpec>,
    points: Vec<(Vec3, f32)>,
    eye: Vec3,
    target: Vec3,
    fov: f32,
}

fn vec3(range: f32) -> impl Strategy<Value = Vec3> {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn log_uniform(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f32.powf(e))
}

fn colour() -> impl Strategy<Value = Rgb> {
    (0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0).prop_map(|(r, g, b)| Rgb::new(r, g, b))
}

fn material() -> impl Strategy<Value = MaterialSpec> {
    prop_oneof![
        3 => colour().prop_map(MaterialSpec::Lambertian),
        3 => (log_uniform(1e-4, 1.0), colour()).prop_map(|(a, c)| MaterialSpec::Ggx(a, c)),
        1 => Just(MaterialSpec::Lambertian(Rgb::ZERO)),
    ]
}

fn shape() -> impl Strategy<Value = ShapeSpec> {
    prop_oneof![
        3 => (vec3(3.0), log_uniform(1e-4, 5.0)).prop_map(|(c, r)| ShapeSpec::Sphere(c, r)),
        2 => (vec3(3.0), vec3(4.0), vec3(4.0)).prop_map(|(p0, e1, e2)| ShapeSpec::Quad(p0, e1, e2)),
        // A floor or ceiling, up to 2000 across, facing up or down.
        1 => (-2.0f32..2.0, log_uniform(1.0, 1e3), any::<bool>()).prop_map(|(y, h, up)| {
            let (e1, e2) = (Vec3::new(2.0 * h, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0 * h));
            let p0 = Vec3::new(-h, y, -h);
            if up { ShapeSpec::Quad(p0, e2, e1) } else { ShapeSpec::Quad(p0, e1, e2) }
        }),
    ]
}

fn object() -> impl Strategy<Value = ObjectSpec> {
    let radiance =
        prop_oneof![2 => Just(None), 1 => Just(Some(0.0)), 4 => log_uniform(1e-2, 1e5).prop_map(Some)];
    (shape(), material(), radiance).prop_map(|(shape, material, radiance)| ObjectSpec {
        shape,
        material,
        radiance,
    })
}

/// A receiver under everything else (most pixels see something): a floor up to 2000 across
/// or a sphere of radius up to 50 whose top is near y = -1, reflecting, rarely emitting.
fn ground() -> impl Strategy<Value = ObjectSpec> {
    let shape = prop_oneof![
        (log_uniform(2.0, 1e3), -1.5f32..-0.5).prop_map(|(h, y)| {
            ShapeSpec::Quad(Vec3::new(-h, y, -h), Vec3::new(0.0, 0.0, 2.0 * h), Vec3::new(2.0 * h, 0.0, 0.0))
        }),
        log_uniform(1.0, 50.0).prop_map(|r| ShapeSpec::Sphere(Vec3::new(0.0, -1.0 - r, 0.0), r)),
    ];
    let radiance = prop_oneof![4 => Just(None), 1 => log_uniform(1e-2, 1e2).prop_map(Some)];
    (shape, material(), radiance).prop_map(|(shape, material, radiance)| ObjectSpec {
        shape,
        material,
        radiance,
    })
}

pub fn scene_spec() -> impl Strategy<Value = SceneSpec> {
    let intensity = prop_oneof![1 => Just(0.0f32), 3 => log_uniform(1e-2, 1e3)];
    let eye = (vec3(6.0), 0.5f32..4.0).prop_map(|(v, y)| Vec3::new(v.x, y, v.z));
    (
        ground(),
        prop::collection::vec(object(), 0..=5),
        prop::collection::vec((vec3(4.0), intensity), 0..=2),
        eye,
        vec3(1.0),
        10.0f32..120.0,
    )
        .prop_map(|(ground, mut objects, points, eye, target, fov)| {
            objects.insert(0, ground);
            SceneSpec { objects, points, eye, target, fov }
        })
}
/// The kernel scene of a spec on a `width` x `height` film. Shapes the kernel rejects
/// (degenerate random quads) are left out; `None` for a camera it rejects.
pub fn build(spec: &SceneSpec, width: u32, height: u32) -> Option<S> {
    let film = Film::new(width, height).unwrap();
    let desc = |up| CameraDesc {
        origin: spec.eye,
        target: spec.target,
        up,
        fov_deg: spec.fov,
        fov_axis: FovAxis::Y,
        near_clip: 0.0,
    };
    let mut scene: S = Scene::new(desc(Vec3::Y), film).or_else(|_| Scene::new(desc(Vec3::X), film)).ok()?;
    for o in &spec.objects {
        let shape = match o.shape {
            ShapeSpec::Sphere(c, r) => Shape::sphere(c, r),
            ShapeSpec::Quad(p0, e1, e2) => Shape::quad([p0, p0 + e1, p0 + e1 + e2, p0 + e2]),
        };
        let Ok(shape) = shape else { continue };
        let material = match o.material {
            MaterialSpec::Lambertian(c) => Material::lambertian(c),
            MaterialSpec::Ggx(a, c) => Material::ggx_conductor(a, c),
        }
        .unwrap();
        let m = scene.add_material(material).unwrap();
        let id = scene.add_shape(shape, m).unwrap();
        if let Some(l) = o.radiance {
            scene.add_area_light(id, Rgb::splat(l)).unwrap();
        }
    }
    for &(p, i) in &spec.points {
        scene.add_point_light(p, Rgb::new(i, 0.5 * i, 0.25 * i)).unwrap();
    }
    Some(scene)
}

fn heuristic() -> impl Strategy<Value = Heuristic> {
    prop_oneof![
        Just(Heuristic::Average),
        Just(Heuristic::Balance),
        Just(Heuristic::Power { beta: 2.0 }),
        (0.25f32..4.0).prop_map(|beta| Heuristic::Power { beta }),
        Just(Heuristic::Maximum),
        (0.0f32..=1.0).prop_map(|alpha| Heuristic::Cutoff { alpha }),
    ]
}

pub fn settings() -> impl Strategy<Value = RenderSettings> {
    let method =
        prop_oneof![Just(Method::LightOnly), Just(Method::BsdfOnly), heuristic().prop_map(Method::Mis)];
    let selection = 0..LightSelection::ALL.len();
    let quads = prop::sample::select(QuadSampling::ALL.to_vec());
    (method, 0u16..=3, 0u16..=3, 1u32..=3, any::<u32>(), any::<bool>(), selection, quads).prop_map(
        |(method, n_light, n_bsdf, spp, seed, cone, selection, quads)| {
            // Lobe mixing by the seed's low bit (the other draws stay those of the cases before
            // it existed).
            let spheres = if cone { SphereSampling::Cone } else { SphereSampling::Area };
            let lobe = LobeMixing::ALL[(seed & 1) as usize];
            let s = RenderSettings::new(method, n_light, n_bsdf, spp, seed)
                .or_else(|_| RenderSettings::new(method, n_light.max(1), n_bsdf.max(1), spp, seed))
                .unwrap();
            s.with_sphere_sampling(spheres)
                .with_light_selection(LightSelection::ALL[selection])
                .with_quad_sampling(quads)
                .with_lobe_mixing(lobe)
        },
    )
}
