//! The serde model of a `picomis-scene/1` file and its lowering into validated [`Step`]s.

use std::collections::BTreeMap;

use picomis::{CameraDesc, Emission, Film, FovAxis, Light, Material, SceneError, Vec3};
use serde::Deserialize;

use crate::{Counts, Geometry, LoadError, SceneFile, Step, check_camera};

const FORMAT: &str = "picomis-scene/1";

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDesc {
    format: String,
    name: String,
    #[serde(default)]
    description: String,
    #[serde(default)]
    #[allow(dead_code)]
    source: String,
    film: FilmDesc,
    camera: CameraFile,
    integrator: crate::IntegratorDesc,
    materials: BTreeMap<String, serde_json::Value>,
    shapes: Vec<serde_json::Value>,
    #[serde(default)]
    lights: Vec<serde_json::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FilmDesc {
    width: u32,
    height: u32,
    #[serde(default)]
    #[allow(dead_code)]
    pixel_filter: PixelFilter,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "snake_case")]
enum PixelFilter {
    #[default]
    Box,
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum CameraType {
    Perspective,
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum AxisDesc {
    X,
    Y,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    #[serde(rename = "type")]
    #[allow(dead_code)]
    kind: CameraType,
    origin: [f32; 3],
    target: [f32; 3],
    up: [f32; 3],
    fov_deg: f32,
    fov_axis: AxisDesc,
    #[serde(default)]
    near_clip: f32,
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum Fresnel {
    One,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LambertianDesc {
    #[serde(rename = "type")]
    _kind: String,
    albedo: [f32; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GgxDesc {
    #[serde(rename = "type")]
    _kind: String,
    alpha: f32,
    #[allow(dead_code)]
    fresnel: Fresnel,
    specular_reflectance: [f32; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EmitterDesc {
    #[serde(rename = "type")]
    #[allow(dead_code)]
    kind: EmitterType,
    radiance: [f32; 3],
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum EmitterType {
    Area,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct QuadDesc {
    #[serde(rename = "type")]
    _kind: String,
    #[serde(default)]
    #[allow(dead_code)]
    name: Option<String>,
    p0: [f32; 3],
    p1: [f32; 3],
    p2: [f32; 3],
    p3: [f32; 3],
    material: String,
    #[serde(default)]
    normal: Option<[f32; 3]>,
    #[serde(default)]
    emitter: Option<EmitterDesc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereDesc {
    #[serde(rename = "type")]
    _kind: String,
    #[serde(default)]
    #[allow(dead_code)]
    name: Option<String>,
    center: [f32; 3],
    radius: f32,
    material: String,
    #[serde(default)]
    emitter: Option<EmitterDesc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PointDesc {
    #[serde(rename = "type")]
    _kind: String,
    #[serde(default)]
    #[allow(dead_code)]
    name: Option<String>,
    position: [f32; 3],
    intensity: [f32; 3],
}

/// The `type` and `name` of an entry, for dispatch and for naming it in errors.
fn kind_and_name(v: &serde_json::Value) -> (Option<&str>, Option<&str>) {
    (v.get("type").and_then(|t| t.as_str()), v.get("name").and_then(|t| t.as_str()))
}

/// Deserializes one typed entry, naming the entry and the field path in errors.
fn typed<T: serde::de::DeserializeOwned>(
    v: &serde_json::Value,
    file: &str,
    entry: &str,
) -> Result<T, LoadError> {
    serde_path_to_error::deserialize(v).map_err(|e| {
        let path = e.path().to_string();
        let entry =
            if path == "." || path.is_empty() { entry.to_string() } else { format!("{entry}.{path}") };
        LoadError { file: file.into(), entry, reason: e.into_inner().to_string() }
    })
}

fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

fn entry_name(kind: &str, i: usize, name: Option<&str>) -> String {
    match name {
        Some(n) => format!("{kind}[{i}] {n:?}"),
        None => format!("{kind}[{i}]"),
    }
}

fn unknown_type(found: Option<&str>, expected: &str) -> String {
    match found {
        Some(t) => format!("unknown variant `{t}`, expected one of {expected}"),
        None => format!("missing or non-string field `type` (expected one of {expected})"),
    }
}

/// Deserializes strictly and lowers into validated steps.
pub(crate) fn lower(text: &str, file: &str) -> Result<SceneFile, LoadError> {
    let fail = |entry: &str, reason: String| LoadError { file: file.into(), entry: entry.into(), reason };
    let de = &mut serde_json::Deserializer::from_str(text);
    let desc: FileDesc = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let entry = if path == "." || path.is_empty() { "file".to_string() } else { path };
        // serde_json's message ends with "at line L column C": keep it, it locates the error.
        fail(&entry, e.into_inner().to_string())
    })?;
    let kernel = |entry: &str, e: SceneError| fail(entry, e.to_string());

    if desc.format != FORMAT {
        return Err(fail("format", format!("expected {FORMAT:?}, found {:?}", desc.format)));
    }
    let film = Film::new(desc.film.width, desc.film.height).map_err(|e| kernel("film", e))?;
    let c = &desc.camera;
    let camera = CameraDesc {
        origin: v3(c.origin),
        target: v3(c.target),
        up: v3(c.up),
        fov_deg: c.fov_deg,
        fov_axis: match c.fov_axis {
            AxisDesc::X => FovAxis::X,
            AxisDesc::Y => FovAxis::Y,
        },
        near_clip: c.near_clip,
    };
    check_camera(camera, film).map_err(|e| kernel("camera", e))?;

    desc.integrator.settings(1, 0).map_err(|e| fail(&format!("integrator.{}", e.key), e.reason))?;

    let mut steps = Vec::new();
    let mut material_index = BTreeMap::new();
    for (i, (name, m)) in desc.materials.iter().enumerate() {
        let entry = format!("materials.{name}");
        let material = match kind_and_name(m).0 {
            Some("lambertian") => {
                let d: LambertianDesc = typed(m, file, &entry)?;
                Material::lambertian(v3(d.albedo))
            }
            Some("ggx_conductor") => {
                let d: GgxDesc = typed(m, file, &entry)?;
                Material::ggx_conductor(d.alpha, v3(d.specular_reflectance))
            }
            other => return Err(fail(&entry, unknown_type(other, "lambertian, ggx_conductor"))),
        }
        .map_err(|e| kernel(&entry, e))?;
        material_index.insert(name.as_str(), i);
        steps.push(Step::Material(material));
    }

    let mut lights = 0;
    for (i, s) in desc.shapes.iter().enumerate() {
        let (kind, name) = kind_and_name(s);
        let entry = entry_name("shapes", i, name);
        let (material, emitter, geometry, normal) = match kind {
            Some("quad") => {
                let d: QuadDesc = typed(s, file, &entry)?;
                let corners = [v3(d.p0), v3(d.p1), v3(d.p2), v3(d.p3)];
                (d.material, d.emitter, Geometry::Quad(corners), d.normal)
            }
            Some("sphere") => {
                let d: SphereDesc = typed(s, file, &entry)?;
                (d.material, d.emitter, Geometry::Sphere { center: v3(d.center), radius: d.radius }, None)
            }
            other => return Err(fail(&entry, unknown_type(other, "quad, sphere"))),
        };
        let shape = geometry.shape().map_err(|e| kernel(&entry, e))?;
        if let Some(n) = normal {
            let n = v3(n);
            let computed = shape.normal_at(Vec3::ZERO);
            let agrees = n.try_normalize().is_some_and(|n| n.dot(computed) > 0.999);
            if !agrees {
                return Err(fail(
                    &entry,
                    format!("normal {n} disagrees with cross(p1 - p0, p3 - p0) = {computed}"),
                ));
            }
        }
        let &material = material_index
            .get(material.as_str())
            .ok_or_else(|| fail(&entry, format!("unknown material {material:?}")))?;
        let emitter = match emitter {
            Some(EmitterDesc { radiance, .. }) => {
                let r = Emission::radiance(v3(radiance)).map_err(|e| kernel(&entry, e))?;
                lights += 1;
                Some(r.rgb())
            }
            None => None,
        };
        steps.push(Step::Shape { entry, geometry, material, emitter });
    }

    for (i, l) in desc.lights.iter().enumerate() {
        let (kind, name) = kind_and_name(l);
        let entry = entry_name("lights", i, name);
        let d: PointDesc = match kind {
            Some("point") => typed(l, file, &entry)?,
            other => return Err(fail(&entry, unknown_type(other, "point"))),
        };
        let (position, intensity) = (v3(d.position), v3(d.intensity));
        Light::point(position, intensity).map_err(|e| kernel(&entry, e))?;
        lights += 1;
        steps.push(Step::PointLight { entry, position, intensity });
    }

    let counts = Counts { shapes: desc.shapes.len(), lights, materials: desc.materials.len() };
    Ok(SceneFile {
        file: file.into(),
        name: desc.name,
        description: desc.description,
        film,
        camera,
        integrator: desc.integrator,
        steps,
        counts,
    })
}
