//! Mitsuba 3 XML in and out (`picomis_format::mitsuba`): the Veach scene as Mitsuba renders it
//! imports to the scene of `scenes/veach_mis.json`; every transform form, the point emitter and
//! `<default>`s give the corners worked out by hand; every class of unsupported or bad input is a
//! one-line error naming the line and the element; and exporting then importing every built-in
//! scene gives back the same scene, bit for bit.

mod common;

use common::{lecture_settings, render_pixel};
use picomis::{Film, Heuristic, Method, SphereSampling};
use picomis_format::{SceneFile, mitsuba};
use serde_json::Value;

const SCENES: [(&str, &str); 5] = [
    ("veach_mis", include_str!("../../scenes/veach_mis.json")),
    ("lambert_sphere", include_str!("../../scenes/lambert_sphere.json")),
    ("box_quad", include_str!("../../scenes/box_quad.json")),
    ("point_lights", include_str!("../../scenes/point_lights.json")),
    ("stress", include_str!("../../scenes/stress.json")),
];

const VEACH_XML: &str = include_str!("data/veach_mis.xml");
const TRANSFORMS_XML: &str = include_str!("data/transforms.xml");

fn json(text: &str) -> Value {
    serde_json::from_str(text).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    match v {
        Value::Number(n) => vec![n.as_f64().unwrap()],
        Value::Array(a) => a.iter().flat_map(floats).collect(),
        other => panic!("not numbers: {other}"),
    }
}

/// The same JSON values, numbers compared as f64 (`0` equals `0.0`).
fn same(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(a, b)| same(a, b)),
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| same(v, w)))
        }
        _ => a == b,
    }
}

macro_rules! assert_same {
    ($a:expr, $b:expr, $($what:tt)*) => {
        assert!(same(&$a, &$b), "{}: {} vs {}", format!($($what)*), $a, $b)
    };
}

/// `a` and `b` agree to a relative 1e-6 of the largest magnitude (f32 rounding of f64 transforms).
fn assert_close(a: &Value, b: &Value, what: &str) {
    let (a, b) = (floats(a), floats(b));
    assert_eq!(a.len(), b.len(), "{what}");
    let scale = a.iter().chain(&b).fold(1.0f64, |m, v| m.max(v.abs()));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-6 * scale, "{what}: {a:?} vs {b:?}");
    }
}

/// The material of `shape` in `file`.
fn material<'a>(file: &'a Value, shape: &Value) -> &'a Value {
    &file["materials"][shape["material"].as_str().unwrap()]
}

#[test]
fn veach_xml_imports_to_the_json_scene() {
    let imported = json(&mitsuba::import(VEACH_XML, "veach_mis.xml", "veach_mis").unwrap());
    let reference = json(SCENES[0].1);
    assert_same!(imported["film"], reference["film"], "film");
    assert_same!(imported["camera"], reference["camera"], "camera");
    assert_same!(imported["integrator"], reference["integrator"], "integrator");
    let (shapes, ref_shapes) =
        (imported["shapes"].as_array().unwrap(), reference["shapes"].as_array().unwrap());
    assert_eq!(shapes.len(), ref_shapes.len());
    for r in ref_shapes {
        let name = &r["name"];
        let s = shapes.iter().find(|s| &s["name"] == name).unwrap_or_else(|| panic!("no shape {name}"));
        assert_eq!(s["type"], r["type"], "{name}");
        assert_same!(s["emitter"], r["emitter"], "{name}");
        assert_same!(material(&imported, s), material(&reference, r), "{name}");
        match r["type"].as_str().unwrap() {
            "sphere" => {
                assert_same!(s["center"], r["center"], "{name}");
                assert_same!(s["radius"], r["radius"], "{name}");
            }
            _ => {
                // The JSON gives corners; the XML the matrices Mitsuba was given.
                for p in ["p0", "p1", "p2", "p3"] {
                    assert_close(&s[p], &r[p], &format!("{name}.{p}"));
                }
            }
        }
    }
    // The imported file is a valid scene with the same shapes and lights (each inline BSDF of
    // the XML is a material of its own: 11 where the JSON shares 6).
    let (a, b) = (
        SceneFile::parse(&imported.to_string(), "imported").unwrap().counts(),
        SceneFile::parse(SCENES[0].1, "veach_mis").unwrap().counts(),
    );
    assert_eq!((a.shapes, a.lights, a.materials), (b.shapes, b.lights, 11));
}

#[test]
fn every_transform_form_the_point_emitter_and_defaults() {
    let text = mitsuba::import(TRANSFORMS_XML, "transforms.xml", "transforms").unwrap();
    let v = json(&text);
    assert_eq!(v["name"], "transforms");
    assert_eq!((v["film"]["width"].as_u64(), v["film"]["height"].as_u64()), (Some(64), Some(48)));
    assert_eq!(v["camera"]["fov_axis"], "y", "smaller axis of a 64x48 film");
    assert_close(&v["camera"]["near_clip"], &serde_json::json!(0.01), "Mitsuba's default near_clip");
    assert_eq!(v["integrator"]["emitter_samples"], 2, "shading_samples");
    assert_eq!(v["integrator"]["bsdf_samples"], 1);
    let shape =
        |name: &str| v["shapes"].as_array().unwrap().iter().find(|s| s["name"] == name).unwrap().clone();
    let corners = |name: &str| {
        let s = shape(name);
        Value::Array(["p0", "p1", "p2", "p3"].iter().map(|p| s[*p].clone()).collect())
    };
    // scale (2, 3, 1), rotate -90 about x, translate (0, -1, 0): normal +y.
    let floor = serde_json::json!([[-2, -1, 3], [2, -1, 3], [2, -1, -3], [-2, -1, -3]]);
    assert_close(&corners("floor"), &floor, "floor");
    assert_eq!(material(&v, &shape("floor"))["albedo"], serde_json::json!([0.5, 0.5, 0.5]));
    let wall = serde_json::json!([[-1, -1, -2], [1, -1, -2], [1, 1, -2], [-1, 1, -2]]);
    assert_close(&corners("wall"), &wall, "lookat wall");
    let m = material(&v, &shape("wall"));
    assert_eq!((m["type"].as_str(), m["alpha"].as_f64()), (Some("ggx_conductor"), Some(0.2)));
    // det < 0: p1 and p3 swap so that cross(p1 - p0, p3 - p0) is Mitsuba's normal (+z).
    let mirrored = serde_json::json!([[4, -1, 0], [4, 1, 0], [2, 1, 0], [2, -1, 0]]);
    assert_close(&corners("mirrored"), &mirrored, "mirrored");
    assert_eq!(
        material(&v, &shape("mirrored"))["albedo"],
        serde_json::json!([0.5, 0.5, 0.5]),
        "Mitsuba's default BSDF"
    );
    let lamp = shape("lamp");
    assert_close(&lamp["center"], &serde_json::json!([1, 2, 0.5]), "lamp");
    assert_close(&lamp["radius"], &serde_json::json!(0.25), "lamp");
    assert_eq!(lamp["emitter"]["radiance"], serde_json::json!([20.0, 18.0, 16.0]));
    let lights = v["lights"].as_array().unwrap();
    assert_eq!(lights.len(), 2);
    assert_eq!(lights[0]["position"], serde_json::json!([-1.0, 2.0, 1.0]));
    assert_eq!(lights[0]["intensity"], serde_json::json!([5.0, 5.0, 5.0]));
    assert_close(&lights[1]["position"], &serde_json::json!([0.5, 3, -0.5]), "point light to_world");
    assert_eq!(lights[1]["intensity"], serde_json::json!([2.0, 2.0, 2.0]));
    // The floor faces up: a pixel looking at it is lit.
    let scene = SceneFile::parse(&text, "t").unwrap().build::<8, 8, 8>().unwrap();
    let settings =
        lecture_settings(Method::Mis(Heuristic::Balance), (1, 1), 16, 0, SphereSampling::Cone).unwrap();
    assert!(render_pixel(&scene, &settings, 32, 40).unwrap().radiance().max_element() > 0.0);
}

/// A small valid scene; line 6 is `@@`, where most cases put their element.
const TEMPLATE: &str = r#"<?xml version="1.0"?>
<scene version="3.0.0">
    <integrator type="direct"/>
    <sensor type="perspective"><float name="fov" value="40"/><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="6"/></film></sensor>
    <shape type="sphere"><float name="radius" value="0.5"/><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
@@
</scene>
"#;

/// Every class of input outside the subset: (find, replace, line, element, reason).
const ERRORS: &[(&str, &str, u32, &str, &str)] = &[
    (
        "@@",
        "<bsdf type=\"plastic\" id=\"p\"/>",
        6,
        "<bsdf type=\"plastic\" id=\"p\">",
        "not modelled by picomis (diffuse, roughconductor)",
    ),
    (
        "@@",
        "<shape type=\"sphere\"><bsdf type=\"twosided\"/></shape>",
        6,
        "<bsdf type=\"twosided\">",
        "not modelled by picomis (diffuse, roughconductor)",
    ),
    ("@@", "<shape type=\"obj\"/>", 6, "<shape type=\"obj\">", "not modelled by picomis (sphere, rectangle)"),
    (
        "@@",
        "<emitter type=\"constant\"/>",
        6,
        "<emitter type=\"constant\">",
        "not modelled by picomis (point",
    ),
    ("@@", "<emitter type=\"area\"/>", 6, "<emitter type=\"area\">", "belongs inside a <shape>"),
    ("@@", "<texture type=\"bitmap\"/>", 6, "<texture type=\"bitmap\">", "not modelled by picomis"),
    ("@@", "<include filename=\"x.xml\"/>", 6, "<include>", "not modelled by picomis"),
    (
        "<integrator type=\"direct\"/>",
        "<integrator type=\"path\"/>",
        3,
        "<integrator type=\"path\">",
        "not modelled by picomis (direct)",
    ),
    ("<integrator type=\"direct\"/>", "", 2, "<scene>", "no <integrator type=\"direct\">"),
    (
        "<integrator type=\"direct\"/>",
        "<integrator type=\"direct\"><boolean name=\"hide_emitters\" value=\"true\"/></integrator>",
        3,
        "<boolean name=\"hide_emitters\">",
        "hiding emitters is not modelled",
    ),
    (
        "<integrator type=\"direct\"/>",
        "<integrator type=\"direct\"><integer name=\"emitter_samples\" value=\"0\"/><integer name=\"bsdf_samples\" value=\"0\"/></integrator>",
        3,
        "<integrator type=\"direct\">",
        "both sample counts are zero",
    ),
    (
        "<integrator type=\"direct\"/>",
        "<integrator type=\"direct\"><integer name=\"emitter_samples\" value=\"-1\"/></integrator>",
        3,
        "<integer name=\"emitter_samples\">",
        "out of range",
    ),
    (
        "<integrator type=\"direct\"/>",
        "<integrator type=\"direct\"><integer name=\"max_depth\" value=\"2\"/></integrator>",
        3,
        "<integer name=\"max_depth\">",
        "parameter not modelled by picomis for <integrator type=\"direct\">",
    ),
    (
        "type=\"perspective\"",
        "type=\"orthographic\"",
        4,
        "<sensor type=\"orthographic\">",
        "not modelled by picomis (perspective)",
    ),
    (
        "<float name=\"fov\" value=\"40\"/>",
        "",
        4,
        "<sensor type=\"perspective\">",
        "missing <float name=\"fov\">",
    ),
    ("value=\"40\"", "value=\"abc\"", 4, "<float name=\"fov\">", "\"abc\" is not a number"),
    ("value=\"40\"", "value=\"inf\"", 4, "<float name=\"fov\">", "must be finite"),
    ("value=\"40\"", "value=\"$fov\"", 4, "<float name=\"fov\">", "unknown parameter $fov"),
    ("value=\"40\"", "value=\"200\"", 4, "<sensor type=\"perspective\">", "fov"),
    (
        "<float name=\"fov\" value=\"40\"/>",
        "<rgb name=\"fov\" value=\"40\"/>",
        4,
        "<rgb name=\"fov\">",
        "expected a <float> or <integer> parameter",
    ),
    (
        "<float name=\"fov\" value=\"40\"/>",
        "<float name=\"fov\" value=\"40\"/><float name=\"fov\" value=\"30\"/>",
        4,
        "<float name=\"fov\">",
        "given twice",
    ),
    (
        "<float name=\"fov\" value=\"40\"/>",
        "<float name=\"fov\" value=\"40\"/><string name=\"fov_axis\" value=\"diagonal\"/>",
        4,
        "<string name=\"fov_axis\">",
        "not modelled (x, y, smaller, larger)",
    ),
    ("<lookat", "<translate x=\"1\"/><lookat", 4, "<transform name=\"to_world\">", "must be one <lookat>"),
    ("up=\"0,1,0\"", "up=\"0,0,1\"", 4, "<sensor type=\"perspective\">", "up"),
    (
        "<film type=\"hdrfilm\">",
        "<film type=\"hdrfilm\"><rfilter type=\"gaussian\"/>",
        4,
        "<rfilter type=\"gaussian\">",
        "not modelled by picomis (box)",
    ),
    (
        "<film type=\"hdrfilm\">",
        "<film type=\"hdrfilm\"><integer name=\"crop_width\" value=\"2\"/>",
        4,
        "<integer name=\"crop_width\">",
        "parameter not modelled",
    ),
    (
        "type=\"hdrfilm\"",
        "type=\"specfilm\"",
        4,
        "<film type=\"specfilm\">",
        "not modelled by picomis (hdrfilm)",
    ),
    ("value=\"0.5\"/>", "value=\"-0.5\"/>", 5, "<shape type=\"sphere\">", "radius"),
    (
        "<rgb name=\"radiance\" value=\"1\"/>",
        "<rgb name=\"radiance\" value=\"-1\"/>",
        5,
        "<rgb name=\"radiance\">",
        "radiance must be >= 0",
    ),
    (
        "<rgb name=\"radiance\" value=\"1\"/>",
        "<rgb name=\"radiance\" value=\"1, 2\"/>",
        5,
        "<rgb name=\"radiance\">",
        "expected 1 or 3 numbers",
    ),
    (
        "<rgb name=\"radiance\" value=\"1\"/>",
        "<spectrum name=\"radiance\" value=\"400:1, 700:2\"/>",
        5,
        "<spectrum name=\"radiance\">",
        "is not a number",
    ),
    (
        "<shape type=\"sphere\">",
        "<shape type=\"sphere\"><boolean name=\"flip_normals\" value=\"true\"/>",
        5,
        "<boolean name=\"flip_normals\">",
        "flipped normals are not modelled",
    ),
    (
        "@@",
        "<shape type=\"sphere\"><transform name=\"to_world\"><scale x=\"1\" y=\"2\"/></transform></shape>",
        6,
        "<transform name=\"to_world\">",
        "uniform scale",
    ),
    (
        "@@",
        "<shape type=\"sphere\"><transform name=\"to_world\"><scale x=\"-1\" y=\"-1\" z=\"-1\"/></transform></shape>",
        6,
        "<transform name=\"to_world\">",
        "inside out",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><transform name=\"to_world\"><scale z=\"0\"/></transform></shape>",
        6,
        "<shape type=\"rectangle\">",
        "singular",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><transform name=\"to_world\"><matrix value=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1\"/></transform></shape>",
        6,
        "<matrix>",
        "projective",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><transform name=\"to_world\"><matrix value=\"1 0 0 0\"/></transform></shape>",
        6,
        "<matrix>",
        "expected 16 (or 9) numbers",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><transform name=\"to_world\"><skew value=\"1\"/></transform></shape>",
        6,
        "<skew>",
        "not modelled by picomis (matrix, translate, rotate, scale, lookat)",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><transform name=\"to_world\"><rotate angle=\"10\"/></transform></shape>",
        6,
        "<transform name=\"to_world\">",
        "non-zero axis",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><ref id=\"nowhere\"/></shape>",
        6,
        "<ref id=\"nowhere\">",
        "no <bsdf id=\"nowhere\">",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><bsdf type=\"roughconductor\"/></shape>",
        6,
        "<bsdf type=\"roughconductor\">",
        "beckmann",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><string name=\"material\" value=\"Au\"/></bsdf></shape>",
        6,
        "<string name=\"material\">",
        "not modelled (none",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha_u\" value=\"0.1\"/></bsdf></shape>",
        6,
        "<float name=\"alpha_u\">",
        "anisotropic",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0\"/></bsdf></shape>",
        6,
        "<bsdf type=\"roughconductor\">",
        "alpha",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"2\"/></bsdf></shape>",
        6,
        "<bsdf type=\"diffuse\">",
        "albedo",
    ),
    (
        "@@",
        "<shape type=\"rectangle\"><bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\"/></bsdf></shape>",
        6,
        "<texture type=\"bitmap\" name=\"reflectance\">",
        "not modelled by picomis inside <bsdf type=\"diffuse\">",
    ),
    (
        "@@",
        "<bsdf type=\"diffuse\" id=\"a\"/><bsdf type=\"diffuse\" id=\"a\"/>",
        6,
        "<bsdf type=\"diffuse\" id=\"a\">",
        "duplicate id",
    ),
    ("@@", "<bsdf type=\"diffuse\"/>", 6, "<bsdf type=\"diffuse\">", "needs an `id`"),
    (
        "@@",
        "<emitter type=\"point\"><point name=\"position\" value=\"1 2\"/></emitter>",
        6,
        "<point name=\"position\">",
        "expected 1 or 3 numbers",
    ),
    (
        "@@",
        "<emitter type=\"point\"><rgb name=\"intensity\" value=\"-1\"/></emitter>",
        6,
        "<emitter type=\"point\">",
        "intensity must be >= 0",
    ),
    (
        "@@",
        "<emitter type=\"point\"><point name=\"position\" value=\"1 2 3\"/><transform name=\"to_world\"/></emitter>",
        6,
        "<transform name=\"to_world\">",
        "not both",
    ),
    ("<scene version=\"3.0.0\">", "<scene version=\"0.6.0\">", 2, "<scene>", "version \"0.6.0\""),
    ("</scene>", "", 1, "xml", "never closed"),
    // Found by the long fuzz run: the XML parser's message quoted a newline.
    ("<integrator type=\"direct\"/>", "<integrator type=\"direct\"/\n>", 3, "xml", "expected '>' not '\\n'"),
    (
        "<integrator type=\"direct\"/>",
        "<integrator type=\"direct\"></integratr>",
        3,
        "xml",
        "expected 'integrator' tag, not 'integratr'",
    ),
];

fn case(find: &str, replace: &str) -> String {
    assert!(TEMPLATE.contains(find), "{find}");
    TEMPLATE.replacen(find, replace, 1).replace("@@", "")
}

#[test]
fn the_template_is_valid_and_every_error_class_names_line_and_element() {
    mitsuba::import(&case("@@", ""), "ok.xml", "ok").unwrap();
    for &(find, replace, line, element, reason) in ERRORS {
        let text = case(find, replace);
        let e = mitsuba::import(&text, "bad.xml", "bad").expect_err(replace);
        let msg = e.to_string();
        assert_eq!(e.file, format!("bad.xml:{line}"), "{msg}");
        assert_eq!(e.entry, element, "{msg}");
        assert!(e.reason.contains(reason), "{msg:?} should say {reason:?}");
        assert_eq!(msg.lines().count(), 1, "{msg}");
    }
    // Root element.
    let e = mitsuba::import("<scenery version=\"3.0.0\"/>", "bad.xml", "bad").unwrap_err();
    assert_eq!(e.to_string(), "bad.xml:1: <scenery>: the root element must be <scene>");
    // The message of the issue.
    let text = case("@@", "<bsdf type=\"plastic\"/>");
    let e = mitsuba::import(
        &text.replace("<bsdf type=\"plastic\"/>", "<shape type=\"sphere\"><bsdf type=\"plastic\"/></shape>"),
        "scene.xml",
        "s",
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "scene.xml:6: <bsdf type=\"plastic\">: not modelled by picomis (diffuse, roughconductor)"
    );
}

/// Renders a few pixels of `scene` with a few methods: the exact f32 bits.
fn pixels(scene: &SceneFile) -> Vec<u32> {
    let film = Film::new(24, 16).unwrap();
    let built = scene.build_with_film::<64, 64, 64>(film).unwrap();
    let mut bits = Vec::new();
    for (method, spheres) in [
        (Method::Mis(Heuristic::Power { beta: 2.0 }), SphereSampling::Cone),
        (Method::Mis(Heuristic::Balance), SphereSampling::Area),
        (Method::BsdfOnly, SphereSampling::Cone),
    ] {
        let settings = lecture_settings(method, (1, 1), 4, 7, spheres).unwrap();
        for y in 0..16 {
            for x in 0..24 {
                let e = render_pixel(&built, &settings, x, y).unwrap();
                bits.extend(e.radiance().to_array().map(f32::to_bits));
            }
        }
    }
    bits
}

#[test]
fn export_then_import_gives_back_every_builtin_scene_bit_for_bit() {
    for (name, text) in SCENES {
        let original = SceneFile::parse(text, name).unwrap();
        let export = mitsuba::export(text, name).unwrap();
        assert!(export.notes.is_empty(), "{name}: {:?}", export.notes);
        // Mitsuba's ids are one namespace (it refuses a file that repeats one): shapes named like
        // their material (Veach's plates) get another id.
        let doc = roxmltree::Document::parse(&export.xml).unwrap();
        let mut ids: Vec<&str> =
            doc.descendants().filter(|n| !n.has_tag_name("ref")).filter_map(|n| n.attribute("id")).collect();
        let all = ids.len();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), all, "{name}: an id is repeated in the exported XML");
        let json1 = mitsuba::import(&export.xml, "exported.xml", name).unwrap();
        let imported = SceneFile::parse(&json1, name).unwrap();
        assert_eq!(imported.counts(), original.counts(), "{name}");
        assert_eq!(imported.camera(), original.camera(), "{name}");
        assert_eq!(imported.film(), original.film(), "{name}");
        let (a, b) = (imported.default_settings(), original.default_settings());
        assert_eq!(a.method(), b.method(), "{name}");
        assert_eq!(a.sample_counts(), b.sample_counts(), "{name}");
        let (a, b) = (pixels(&imported), pixels(&original));
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert!(differ == 0, "{name}: the image changed ({differ} of {} values differ)", a.len());
        // Names and values survive: the same JSON values as the original (but description).
        let (a, b) = (json(&json1), json(text));
        assert_same!(a["materials"], b["materials"], "{name}");
        for (s, r) in a["shapes"].as_array().unwrap().iter().zip(b["shapes"].as_array().unwrap()) {
            for key in ["type", "name", "material", "emitter", "center", "radius", "p0", "p1", "p3"] {
                assert_same!(s[key], r[key], "{name}: {key}");
            }
        }
        assert_eq!(
            a.get("lights").map(|l| l.as_array().unwrap().len()),
            b.get("lights").map(|l| l.as_array().unwrap().len())
        );
        // And the round trip is a fixed point: the same bytes of JSON and of XML.
        let export2 = mitsuba::export(&json1, name).unwrap();
        let json2 = mitsuba::import(&export2.xml, "exported.xml", name).unwrap();
        assert!(json2 == json1, "{name}: the second round trip changed the JSON");
    }
}

#[test]
fn the_veach_xml_round_trips_too() {
    let json1 = mitsuba::import(VEACH_XML, "veach_mis.xml", "veach_mis").unwrap();
    let xml = mitsuba::export(&json1, "veach_mis.json").unwrap().xml;
    let json2 = mitsuba::import(&xml, "again.xml", "veach_mis").unwrap();
    assert!(json1 == json2, "the second round trip changed the JSON");
}

#[test]
fn methods_mitsuba_cannot_express_are_noted() {
    let text = SCENES[1].1.replace("\"mis\": \"power\"", "\"mis\": \"balance\"");
    assert_ne!(text, SCENES[1].1);
    let export = mitsuba::export(&text, "balance.json").unwrap();
    assert_eq!(export.notes.len(), 1);
    assert!(export.notes[0].contains("power heuristic"), "{:?}", export.notes);
}
