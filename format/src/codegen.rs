//! Rust source for firmware build scripts: the scene as a `build(film)` function with the
//! scene's own capacities. Floats are written as their exact bit patterns.

use std::fmt::Write;

use picomis::integrator::type_paths;
use picomis::{
    ControlVariate, FovAxis, LightSelection, LobeMixing, Material, Method, QuadSampling, RenderSettings,
    SphereSampling, Vec3,
};

use crate::{Geometry, SceneFile, Step};

fn f(v: f32) -> String {
    format!("f32::from_bits({:#010x}) /* {v:?} */", v.to_bits())
}

fn v3(v: Vec3) -> String {
    format!("Vec3::new({}, {}, {})", f(v.x), f(v.y), f(v.z))
}

/// The method as its entry in the kernel's list, with its parameters as exact bits.
fn method(m: Method) -> String {
    let opt = |v: Option<f32>| v.map_or("None".to_string(), |v| format!("Some({})", f(v)));
    let index = Method::ALL.iter().position(|x| x.name() == m.name()).unwrap_or(0);
    format!("Method::ALL[{index}] /* {m} */.with_parameters({}, {})", opt(m.beta()), opt(m.alpha()))
}

/// The settings of the file's integrator block with the strategies a scene's content makes
/// equivalent replaced by the smallest (the same bits): no quad lights, quads by area (and the
/// type `quad::Absent`, which leaves out every strategy's code for quad lights); no sphere
/// lights, spheres by area (`sphere::Absent`); one light, no selection by contribution; lobe mixing only with
/// a GGX receiver and an area light; the control variate only with a Lambertian receiver and an
/// area light, and `by-size` only where it differs from `auto` (a scene whose one light is an
/// area light); quads `by-size` only with a receiver on which it differs from `auto` (a
/// Lambertian or rough GGX one).
pub fn firmware_settings(s: &SceneFile) -> RenderSettings {
    let settings = s.default_settings();
    let (lights, materials) = (s.light_kinds(), s.material_kinds());
    let area_lights = lights.spheres || lights.quads;
    let selection = match settings.light_selection() {
        LightSelection::Contribution | LightSelection::Every if s.counts().lights <= 1 => {
            LightSelection::Uniform
        }
        other => other,
    };
    let quads = match settings.quad_sampling() {
        _ if !lights.quads => QuadSampling::Area,
        QuadSampling::BySize if !materials.quads_by_size => QuadSampling::Auto,
        other => other,
    };
    let spheres = if lights.spheres { settings.sphere_sampling() } else { SphereSampling::Area };
    let lobe = if materials.ggx && area_lights { settings.lobe_mixing() } else { LobeMixing::Off };
    let one_area_light = s.counts().lights == 1 && area_lights;
    let cv = match settings.control_variate() {
        _ if !(materials.lambertian && area_lights) => ControlVariate::Off,
        ControlVariate::BySize if !one_area_light => ControlVariate::Auto,
        other => other,
    };
    let s = settings
        .with_light_selection(selection)
        .with_quad_sampling(quads)
        .with_sphere_sampling(spheres)
        .with_lobe_mixing(lobe);
    s.with_control_variate(cv).unwrap_or(s)
}

/// The firmware's settings (`settings()`, a `const fn`: the render sees every setting as a
/// constant) and strategies (`Strategies<C>`, the types [`firmware_settings`] names).
fn strategies(o: &mut String, s: &SceneFile) {
    let settings = firmware_settings(s);
    let m = settings.method();
    let (n_light, n_bsdf) = settings.sample_counts();
    let lights = s.counts().lights;
    let kinds = s.light_kinds();
    let path = |p: &str| p.replace("<L>", &format!("<{lights}>"));
    let _ = writeln!(
        o,
        "/// The strategies of the file's integrator block that this scene uses, with the settings read\n\
         /// from `C` (a `picomis::integrator::ConstSettings` type: every setting a constant)."
    );
    let _ = writeln!(
        o,
        "pub type Strategies<C> = picomis::Direct<picomis::Lights<{}, {}, {}, {}>, {}, {}, C>;",
        path(type_paths::selection(settings.light_selection())),
        if kinds.spheres {
            path(type_paths::spheres(settings.sphere_sampling()))
        } else {
            type_paths::NO_SPHERES.into()
        },
        if kinds.quads {
            path(type_paths::quads(settings.quad_sampling()))
        } else {
            type_paths::NO_QUADS.into()
        },
        path(type_paths::lobe(settings.lobe_mixing())),
        path(type_paths::control_variate(settings.control_variate())),
        path(type_paths::model(settings.mis_model())),
    );
    let _ =
        writeln!(o, "/// The integrator of the file (1 spp, seed 0), with the strategies of `Strategies`.");
    let _ = writeln!(o, "pub const fn settings() -> Result<picomis::RenderSettings, picomis::SceneError> {{");
    let _ = writeln!(
        o,
        "    macro_rules! ok {{ ($e:expr) => {{ match $e {{ Ok(v) => v, Err(e) => return Err(e) }} }}; }}"
    );
    let _ = writeln!(o, "    let method = ok!({});", method(m));
    let _ = writeln!(o, "    let s = ok!(picomis::RenderSettings::new(method, {n_light}, {n_bsdf}, 1, 0));");
    let _ = writeln!(
        o,
        "    let s = s.with_sampler(picomis::SamplerKind::{:?}).with_light_selection(picomis::LightSelection::{:?}).with_sphere_sampling(picomis::SphereSampling::{:?}).with_quad_sampling(picomis::QuadSampling::{:?}).with_lobe_mixing(picomis::LobeMixing::{:?});",
        settings.sampler(),
        settings.light_selection(),
        settings.sphere_sampling(),
        settings.quad_sampling(),
        settings.lobe_mixing()
    );
    let model = match settings.mis_model() {
        picomis::MisModel::One { c_light } => format!("picomis::MisModel::One {{ c_light: {} }}", f(c_light)),
        picomis::MisModel::Multi => "picomis::MisModel::Multi".into(),
    };
    let _ = writeln!(o, "    let s = ok!(s.with_mis_model({model}));");
    let _ =
        writeln!(o, "    s.with_control_variate(picomis::ControlVariate::{:?})", settings.control_variate());
    let _ = writeln!(o, "}}");
}

pub(crate) fn module(s: &SceneFile) -> String {
    let c = s.counts;
    let cam = s.camera;
    let mut o = String::new();
    // `write!` into a String cannot fail.
    let _ = writeln!(o, "// Generated by picomis-format from {:?}. Do not edit.", s.file);
    let _ = writeln!(o, "#[allow(unused_imports, clippy::all)]");
    let _ = writeln!(o, "use picomis::{{CameraDesc, FovAxis, Material, Method, Rgb, Shape, Vec3}};");
    let _ = writeln!(o, "/// Scene name.\npub const NAME: &str = {:?};", s.name);
    let _ =
        writeln!(o, "/// Shapes in the scene (its shape capacity).\npub const SHAPES: usize = {};", c.shapes);
    let _ =
        writeln!(o, "/// Lights in the scene (its light capacity).\npub const LIGHTS: usize = {};", c.lights);
    let _ = writeln!(
        o,
        "/// Materials in the scene (its material capacity).\npub const MATERIALS: usize = {};",
        c.materials
    );
    let _ = writeln!(o, "/// Film width of the file.\npub const WIDTH: u32 = {};", s.film.width());
    let _ = writeln!(o, "/// Film height of the file.\npub const HEIGHT: u32 = {};", s.film.height());
    let _ = writeln!(o, "/// The scene type, sized by the scene.");
    let _ = writeln!(o, "pub type SceneT = picomis::Scene<SHAPES, LIGHTS, MATERIALS>;");
    let _ = writeln!(o, "/// The camera of the file.");
    let _ = writeln!(o, "pub fn camera() -> CameraDesc {{");
    let axis = match cam.fov_axis {
        FovAxis::X => "FovAxis::X",
        FovAxis::Y => "FovAxis::Y",
    };
    let _ = writeln!(
        o,
        "    CameraDesc {{ origin: {}, target: {}, up: {}, fov_deg: {}, fov_axis: {axis}, near_clip: {} }}",
        v3(cam.origin),
        v3(cam.target),
        v3(cam.up),
        f(cam.fov_deg),
        f(cam.near_clip)
    );
    let _ = writeln!(o, "}}");
    let _ = writeln!(o, "/// Builds the scene for `film`.");
    let _ = writeln!(o, "pub fn build(film: picomis::Film) -> Result<SceneT, picomis::SceneError> {{");
    let _ = writeln!(o, "    let mut scene = SceneT::new(camera(), film)?;");
    let _ = writeln!(o, "    populate(&mut scene)?;");
    let _ = writeln!(o, "    Ok(scene)\n}}");
    let _ =
        writeln!(o, "/// Adds the materials, shapes and lights of the file to an empty scene (in place: a");
    let _ =
        writeln!(o, "/// firmware can fill a scene that lives in a `static` without a copy on the stack).");
    let _ = writeln!(o, "pub fn populate(scene: &mut SceneT) -> Result<(), picomis::SceneError> {{");
    let mut materials = 0;
    for step in &s.steps {
        match step {
            Step::Material(m) => {
                let expr = match *m {
                    Material::Lambertian { albedo } => format!("Material::lambertian({})", v3(albedo)),
                    Material::GgxConductor { alpha, reflectance } => {
                        format!("Material::ggx_conductor({}, {})", f(alpha), v3(reflectance))
                    }
                };
                let _ = writeln!(o, "    let m{materials} = scene.add_material({expr}?)?;");
                materials += 1;
            }
            Step::Shape { entry, geometry, material, emitter } => {
                let shape = match geometry {
                    Geometry::Sphere { center, radius } => {
                        format!("Shape::sphere({}, {})", v3(*center), f(*radius))
                    }
                    Geometry::Quad(p) => {
                        format!("Shape::quad([{}, {}, {}, {}])", v3(p[0]), v3(p[1]), v3(p[2]), v3(p[3]))
                    }
                };
                let _ = writeln!(o, "    // {entry}");
                let _ = writeln!(o, "    let shape = scene.add_shape({shape}?, m{material})?;");
                if let Some(r) = emitter {
                    let _ = writeln!(o, "    scene.add_area_light(shape, {})?;", v3(*r));
                }
                let _ = writeln!(o, "    let _ = shape;");
            }
            Step::PointLight { entry, position, intensity } => {
                let _ = writeln!(o, "    // {entry}");
                let _ = writeln!(o, "    scene.add_point_light({}, {})?;", v3(*position), v3(*intensity));
            }
        }
    }
    let _ = writeln!(o, "    Ok(())\n}}");
    strategies(&mut o, s);
    o
}
