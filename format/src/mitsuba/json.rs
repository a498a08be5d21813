//! Writing a `picomis-scene/1` file: the serde model of what the importer produces (field order
//! as in `scenes/FORMAT.md`), printed with serde_json (f32 values as their shortest decimal form,
//! which reads back to the same bits).

use std::collections::BTreeMap;

use serde::Serialize;

#[derive(Serialize)]
pub(crate) struct FileOut {
    pub format: &'static str,
    pub name: String,
    pub description: String,
    pub source: String,
    pub film: FilmOut,
    pub camera: CameraOut,
    pub integrator: IntegratorOut,
    pub materials: BTreeMap<String, MaterialOut>,
    pub shapes: Vec<ShapeOut>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<PointOut>,
}

#[derive(Serialize)]
pub(crate) struct FilmOut {
    pub width: u32,
    pub height: u32,
    pub pixel_filter: &'static str,
}

#[derive(Serialize)]
pub(crate) struct CameraOut {
    #[serde(rename = "type")]
    pub kind: &'static str,
    pub origin: [f32; 3],
    pub target: [f32; 3],
    pub up: [f32; 3],
    pub fov_deg: f32,
    pub fov_axis: &'static str,
    pub near_clip: f32,
}

#[derive(Serialize)]
pub(crate) struct IntegratorOut {
    #[serde(rename = "type")]
    pub kind: &'static str,
    pub emitter_samples: u16,
    pub bsdf_samples: u16,
    pub hide_emitters: bool,
    pub mis: &'static str,
}

#[derive(Clone, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(crate) enum MaterialOut {
    Lambertian { albedo: [f32; 3] },
    GgxConductor { alpha: f32, fresnel: &'static str, specular_reflectance: [f32; 3] },
}

#[derive(Serialize)]
pub(crate) struct EmitterOut {
    #[serde(rename = "type")]
    pub kind: &'static str,
    pub radiance: [f32; 3],
}

#[derive(Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub(crate) enum ShapeOut {
    Quad {
        #[serde(skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        p0: [f32; 3],
        p1: [f32; 3],
        p2: [f32; 3],
        p3: [f32; 3],
        material: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        emitter: Option<EmitterOut>,
    },
    Sphere {
        #[serde(skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        center: [f32; 3],
        radius: f32,
        material: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        emitter: Option<EmitterOut>,
    },
}

#[derive(Serialize)]
pub(crate) struct PointOut {
    #[serde(rename = "type")]
    pub kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub position: [f32; 3],
    pub intensity: [f32; 3],
}

impl FileOut {
    /// The file's text: pretty-printed JSON with a final newline.
    pub(crate) fn to_text(&self) -> String {
        // Serializing plain structs of finite numbers and strings cannot fail.
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }
}
