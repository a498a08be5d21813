//! `picomis-scene/1` to Mitsuba 3 XML, so that anyone with `pip install mitsuba` can render the
//! same scene. Every f32 is written in its shortest decimal form and quads as `matrix`
//! transforms computed exactly in f64, so importing the export gives back the same values, bit
//! for bit (see the round-trip tests).

use std::collections::BTreeSet;
use std::fmt::Write;

use picomis::{FovAxis, Heuristic, Material, Method, Rgb, Vec3};

use super::SHAPE_ID_SUFFIX;
use super::transform::{V3, cross, normalize};
use crate::{Geometry, LoadError, SceneFile, Step};

/// A Mitsuba 3 scene and what it could not keep.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Export {
    /// The XML text.
    pub xml: String,
    /// Notes on what Mitsuba cannot express (e.g. a default method other than the power
    /// heuristic with beta 2, the one Mitsuba's `direct` integrator uses).
    pub notes: Vec<String>,
}

fn esc(s: &str) -> String {
    s.chars()
        .flat_map(|c| match c {
            '&' => "&amp;".chars().collect::<Vec<_>>(),
            '<' => "&lt;".chars().collect(),
            '>' => "&gt;".chars().collect(),
            '"' => "&quot;".chars().collect(),
            '\'' => "&apos;".chars().collect(),
            c if c.is_control() => vec![' '],
            c => vec![c],
        })
        .collect()
}

fn vec3(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

fn rgb(name: &str, c: Rgb) -> String {
    format!("<rgb name=\"{name}\" value=\"{}\"/>", vec3(c))
}

/// Comment text: `--` may not appear inside an XML comment.
fn comment(s: &str) -> String {
    esc(s).replace("--", "- -")
}

/// Writes `scene` (parsed from `text`, which gives the names) as Mitsuba 3 XML.
pub(crate) fn export(scene: &SceneFile, text: &str) -> Result<Export, LoadError> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| LoadError {
        file: scene.file.clone(),
        entry: "file".into(),
        reason: e.to_string(),
    })?;
    // Materials are built in the order of their sorted names (picomis-format reads them into a
    // BTreeMap), so the k-th material step has the k-th sorted name.
    let mut material_names: Vec<String> = value
        .get("materials")
        .and_then(|m| m.as_object())
        .map(|m| m.keys().cloned().collect())
        .unwrap_or_default();
    material_names.sort();
    let entry_name = |list: &str, i: usize| -> Option<String> {
        value.get(list)?.get(i)?.get("name")?.as_str().map(str::to_string)
    };

    let mut notes = Vec::new();
    let mut x = String::new();
    let mut line = |s: String| {
        x += &s;
        x.push('\n');
    };
    line("<?xml version=\"1.0\" encoding=\"utf-8\"?>".into());
    line(format!(
        "<!-- {}: written by picomis-sim export from {}.",
        comment(&scene.name),
        comment(&scene.file)
    ));
    if !scene.description.is_empty() {
        line(format!("     {}", comment(&scene.description)));
    }
    line("     Render with: mitsuba -m scalar_rgb -D spp=1024 this.xml -->".into());
    line("<scene version=\"3.0.0\">".into());
    line("    <default name=\"spp\" value=\"64\"/>".into());
    line("    <default name=\"seed\" value=\"0\"/>".into());
    let settings = scene.default_settings();
    let (light_samples, bsdf_samples) = settings.sample_counts();
    match settings.method() {
        Method::Mis(Heuristic::Power { beta: 2.0 }) => {}
        other => notes.push(format!(
            "{}: the scene's default method {other:?} is not kept: Mitsuba's direct integrator always uses the power heuristic (beta 2)",
            scene.file
        )),
    }
    line("    <integrator type=\"direct\">".into());
    line(format!("        <integer name=\"emitter_samples\" value=\"{}\"/>", light_samples));
    line(format!("        <integer name=\"bsdf_samples\" value=\"{}\"/>", bsdf_samples));
    line("        <boolean name=\"hide_emitters\" value=\"false\"/>".into());
    line("    </integrator>".into());

    let c = scene.camera;
    line("    <sensor type=\"perspective\">".into());
    line(format!("        <float name=\"fov\" value=\"{}\"/>", c.fov_deg));
    let axis = match c.fov_axis {
        FovAxis::X => "x",
        FovAxis::Y => "y",
    };
    line(format!("        <string name=\"fov_axis\" value=\"{axis}\"/>"));
    line(format!("        <float name=\"near_clip\" value=\"{}\"/>", c.near_clip));
    line("        <float name=\"far_clip\" value=\"10000000\"/>".into());
    line("        <transform name=\"to_world\">".into());
    line(format!(
        "            <lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>",
        vec3(c.origin),
        vec3(c.target),
        vec3(c.up)
    ));
    line("        </transform>".into());
    line("        <sampler type=\"independent\">".into());
    line("            <integer name=\"sample_count\" value=\"$spp\"/>".into());
    line("            <integer name=\"seed\" value=\"$seed\"/>".into());
    line("        </sampler>".into());
    line("        <film type=\"hdrfilm\">".into());
    line(format!("            <integer name=\"width\" value=\"{}\"/>", scene.film.width()));
    line(format!("            <integer name=\"height\" value=\"{}\"/>", scene.film.height()));
    line("            <string name=\"pixel_format\" value=\"rgb\"/>".into());
    line("            <rfilter type=\"box\"/>".into());
    line("        </film>".into());
    line("    </sensor>".into());

    let mut materials = Vec::new();
    // Every id the document holds so far: the materials', then the shapes' and point lights'.
    let mut ids: BTreeSet<String> = material_names.iter().cloned().collect();
    let (mut shape_index, mut light_index) = (0, 0);
    for step in &scene.steps {
        match step {
            Step::Material(m) => {
                let id = material_names
                    .get(materials.len())
                    .cloned()
                    .unwrap_or_else(|| format!("material{}", materials.len()));
                materials.push(id.clone());
                let id = esc(&id);
                match m {
                    Material::Lambertian { albedo } => {
                        line(format!("    <bsdf type=\"diffuse\" id=\"{id}\">"));
                        line(format!("        {}", rgb("reflectance", *albedo)));
                    }
                    Material::GgxConductor { alpha, reflectance } => {
                        line(format!("    <bsdf type=\"roughconductor\" id=\"{id}\">"));
                        line("        <string name=\"material\" value=\"none\"/>".into());
                        line("        <string name=\"distribution\" value=\"ggx\"/>".into());
                        line(format!("        <float name=\"alpha\" value=\"{alpha}\"/>"));
                        line(format!("        {}", rgb("specular_reflectance", *reflectance)));
                    }
                }
                line("    </bsdf>".into());
            }
            Step::Shape { geometry, material, emitter, .. } => {
                let id = match entry_name("shapes", shape_index) {
                    Some(n) => format!(" id=\"{}\"", esc(&unique_id(n, &mut ids))),
                    None => String::new(),
                };
                shape_index += 1;
                match geometry {
                    Geometry::Sphere { center, radius } => {
                        line(format!("    <shape type=\"sphere\"{id}>"));
                        line(format!(
                            "        <point name=\"center\" x=\"{}\" y=\"{}\" z=\"{}\"/>",
                            center.x, center.y, center.z
                        ));
                        line(format!("        <float name=\"radius\" value=\"{radius}\"/>"));
                    }
                    Geometry::Quad(p) => {
                        let [p0, p1, _, p3] = p.map(|v| v.to_array().map(f64::from));
                        line(format!(
                            "    <!-- quad p0 = [{}] p1 = [{}] p3 = [{}] -->",
                            vec3(p[0]),
                            vec3(p[1]),
                            vec3(p[3])
                        ));
                        line(format!("    <shape type=\"rectangle\"{id}>"));
                        line("        <transform name=\"to_world\">".into());
                        line(format!("            <matrix value=\"{}\"/>", rectangle_matrix(p0, p1, p3)));
                        line("        </transform>".into());
                    }
                }
                let mat = materials.get(*material).cloned().unwrap_or_default();
                line(format!("        <ref id=\"{}\"/>", esc(&mat)));
                if let Some(radiance) = emitter {
                    line("        <emitter type=\"area\">".into());
                    line(format!("            {}", rgb("radiance", *radiance)));
                    line("        </emitter>".into());
                }
                line("    </shape>".into());
            }
            Step::PointLight { position, intensity, .. } => {
                let id = match entry_name("lights", light_index) {
                    Some(n) => format!(" id=\"{}\"", esc(&unique_id(n, &mut ids))),
                    None => String::new(),
                };
                light_index += 1;
                line(format!("    <emitter type=\"point\"{id}>"));
                line(format!(
                    "        <point name=\"position\" x=\"{}\" y=\"{}\" z=\"{}\"/>",
                    position.x, position.y, position.z
                ));
                line(format!("        {}", rgb("intensity", *intensity)));
                line("    </emitter>".into());
            }
        }
    }
    line("</scene>".into());
    Ok(Export { xml: x, notes })
}

/// `name` as an id not yet in `ids` (then added): itself, else with [`SHAPE_ID_SUFFIX`] once
/// or more.
fn unique_id(name: String, ids: &mut BTreeSet<String>) -> String {
    let mut id = name;
    while ids.contains(&id) {
        id.push_str(SHAPE_ID_SUFFIX);
    }
    ids.insert(id.clone());
    id
}

/// The 4x4 `to_world` (row-major) mapping Mitsuba's rectangle [-1, 1]^2 onto the quad: corner
/// (-1, -1) to p0, (1, -1) to p1, (-1, 1) to p3, and +z along cross(p1 - p0, p3 - p0). With f32
/// corners every entry and the importer's x·X + y·Y + T are exact in f64, so the corners come
/// back with the same bits.
fn rectangle_matrix(p0: V3, p1: V3, p3: V3) -> String {
    let half = |a: V3, b: V3| [0, 1, 2].map(|i| (a[i] - b[i]) / 2.0);
    let (ex, ey) = (half(p1, p0), half(p3, p0));
    let t = [0, 1, 2].map(|i| (p1[i] + p3[i]) / 2.0);
    let n = normalize(cross(ex, ey)).unwrap_or([0.0, 0.0, 1.0]);
    let mut s = String::new();
    for r in 0..3 {
        let _ = write!(s, "{} {} {} {} ", ex[r], ey[r], n[r], t[r]);
    }
    s + "0 0 0 1"
}
