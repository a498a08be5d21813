//! Loading `picomis-scene/1` files: the Veach scene, and every class of bad input.

use picomis::Preset;
use picomis_format::{Counts, LoadError, SceneFile, firmware_settings};

const VEACH: &str = include_str!("../../scenes/veach_mis.json");

fn veach() -> serde_json::Value {
    serde_json::from_str(VEACH).unwrap()
}

fn load(v: &serde_json::Value) -> Result<SceneFile, LoadError> {
    SceneFile::parse(&v.to_string(), "test.json")
}

/// Asserts that loading fails, naming the file, the entry and the reason.
fn rejects(v: &serde_json::Value, entry: &str, reason: &str) {
    let e = match load(v) {
        Ok(_) => panic!("accepted a bad scene (expected {entry}: {reason})"),
        Err(e) => e,
    };
    assert_eq!(e.file, "test.json");
    assert!(e.entry.contains(entry), "entry {:?} should name {entry:?} ({e})", e.entry);
    assert!(e.reason.contains(reason), "reason {:?} should say {reason:?}", e.reason);
    assert!(e.to_string().starts_with("test.json: "));
}

#[test]
fn veach_scene_loads_with_its_own_counts() {
    let s = load(&veach()).unwrap();
    assert_eq!(s.name(), "veach_mis");
    assert_eq!(s.counts(), Counts { shapes: 11, lights: 5, materials: 6 });
    let scene = s.build::<11, 5, 6>().unwrap();
    assert_eq!(scene.objects().len(), 11);
    assert_eq!(scene.lights().len(), 5);
    assert_eq!((scene.film().width(), scene.film().height()), (384, 256));
    // The integrator block makes valid settings (checked at load), and they are the defaults.
    assert_eq!(Ok(s.default_settings()), s.integrator().settings(1, 0));
}

#[test]
fn capacity_overflow_names_the_entry() {
    let s = load(&veach()).unwrap();
    let e = s.build::<10, 5, 6>().unwrap_err();
    assert!(e.entry.contains("shapes[10]") && e.reason.contains("too many shapes"), "{e}");
    let e = s.build::<11, 4, 6>().unwrap_err();
    assert!(e.reason.contains("too many lights"), "{e}");
    let e = s.build::<11, 5, 5>().unwrap_err();
    assert!(e.reason.contains("too many materials"), "{e}");
}

#[test]
fn malformed_json() {
    let e = SceneFile::parse("{ \"format\": ", "bad.json").unwrap_err();
    assert_eq!(e.file, "bad.json");
    assert!(e.reason.contains("EOF") || e.reason.contains("line"), "{e}");
}

#[test]
fn unknown_keys_and_types() {
    let mut v = veach();
    v["colour"] = 1.into();
    rejects(&v, "colour", "unknown field");
    let mut v = veach();
    v["shapes"][6]["radius_mm"] = 3.into();
    rejects(&v, "shapes[6]", "unknown field");
    let mut v = veach();
    v["shapes"][6]["type"] = "torus".into();
    rejects(&v, "shapes[6]", "unknown variant");
    let mut v = veach();
    v["shapes"][6]["radius"] = "big".into();
    rejects(&v, "shapes[6] \"light_r0_03333\".radius", "invalid type");
    let mut v = veach();
    v["materials"]["plate1"]["fresnel"] = "schlick".into();
    rejects(&v, "materials.plate1", "unknown variant");
    let mut v = veach();
    v["format"] = "picomis-scene/2".into();
    rejects(&v, "format", "expected");
}

#[test]
fn non_finite_and_out_of_range_numbers() {
    let text = VEACH.replacen("\"radius\": 0.03333", "\"radius\": 1e999", 1);
    let e = SceneFile::parse(&text, "test.json").unwrap_err();
    assert!(e.entry.contains("shapes[6]"), "{e}");
    let mut v = veach();
    v["shapes"][6]["radius"] = (-1.0).into();
    rejects(&v, "shapes[6] \"light_r0_03333\"", "radius must be positive");
    let mut v = veach();
    v["shapes"][6]["radius"] = 1e39.into(); // finite in JSON, infinite in f32
    rejects(&v, "shapes[6]", "radius is not a finite number");
    let mut v = veach();
    v["materials"]["plate1"]["alpha"] = 0.0.into();
    rejects(&v, "materials.plate1", "alpha is out of range");
    let mut v = veach();
    v["materials"]["floor_diffuse"]["albedo"][1] = 1.5.into();
    rejects(&v, "materials.floor_diffuse", "albedo is out of range");
    let mut v = veach();
    v["shapes"][7]["emitter"]["radiance"][0] = (-3.0).into();
    rejects(&v, "shapes[7]", "radiance is out of range");
    let mut v = veach();
    v["camera"]["fov_deg"] = 180.0.into();
    rejects(&v, "camera", "fov_deg is out of range");
    let mut v = veach();
    v["camera"]["up"] = serde_json::json!([0.0, -0.95782628, -0.2873478]);
    let _ = load(&v); // nearly parallel but not exactly: accepted or rejected, never a panic
    v["camera"]["up"] = serde_json::json!([0.0, 0.0, 0.0]);
    rejects(&v, "camera", "up");
    let mut v = veach();
    v["film"]["width"] = 0.into();
    rejects(&v, "film", "film size is out of range");
    let mut v = veach();
    v["film"]["width"] = (-5).into();
    rejects(&v, "film.width", "invalid value");
    let mut v = veach();
    v["integrator"]["mis"] = "magic".into();
    rejects(&v, "integrator.mis", "unknown method");
    let mut v = veach();
    v["integrator"]["emitter_samples"] = 0.into();
    v["integrator"]["bsdf_samples"] = 0.into();
    rejects(&v, "integrator.light_samples", "both sample counts are zero");
    let mut v = veach();
    v["integrator"]["mis_model"] = "two".into();
    rejects(&v, "integrator.mis_model", "unknown MIS model");
    let mut v = veach();
    v["integrator"]["mis_model"] = "one".into();
    v["integrator"]["c_light"] = 1.5.into();
    rejects(&v, "integrator.c_light", "c_light is out of range");
}

#[test]
fn degenerate_shapes() {
    let mut v = veach();
    let p0 = v["shapes"][0]["p0"].clone();
    v["shapes"][0]["p1"] = p0.clone();
    v["shapes"][0]["p2"] = v["shapes"][0]["p3"].clone();
    rejects(&v, "shapes[0] \"plate1\"", "zero area");
    let mut v = veach();
    v["shapes"][0]["p2"][1] = 5.0.into();
    rejects(&v, "shapes[0]", "not a parallelogram");
    let mut v = veach();
    v["shapes"][0]["normal"] = serde_json::json!([0.0, -0.782413, -0.62276]);
    rejects(&v, "shapes[0]", "normal");
    let mut v = veach();
    v["shapes"][0]["material"] = "gold".into();
    rejects(&v, "shapes[0]", "unknown material");
}

#[test]
fn point_lights_are_counted_and_validated() {
    let mut v = veach();
    v["lights"] = serde_json::json!([{ "type": "point", "position": [0, 3, 0], "intensity": [5, 5, 5] }]);
    let s = load(&v).unwrap();
    assert_eq!(s.counts().lights, 6);
    assert_eq!(s.build::<11, 6, 6>().unwrap().lights().len(), 6);
    v["lights"][0]["intensity"][2] = (-1.0).into();
    rejects(&v, "lights[0]", "intensity is out of range");
}

#[test]
fn method_names_and_parameters_come_from_the_kernel() {
    for m in picomis::Method::ALL {
        let mut v = veach();
        v["integrator"]["mis"] = m.name().into();
        assert_eq!(load(&v).unwrap().default_settings().method(), m, "{m}");
    }
    let mut v = veach();
    v["integrator"]["beta"] = 0.0.into();
    rejects(&v, "integrator.beta", "power-heuristic beta is out of range");
    v["integrator"]["beta"] = 3.0.into();
    assert_eq!(load(&v).unwrap().default_settings().method().beta(), Some(3.0));
    v["integrator"]["mis"] = "cutoff".into();
    v["integrator"]["alpha"] = 2.0.into();
    rejects(&v, "integrator.alpha", "cutoff alpha is out of range");
}

#[test]
fn quad_sampling_names_come_from_the_kernel() {
    let best = Preset::Best.settings();
    assert_eq!(load(&veach()).unwrap().default_settings().quad_sampling(), best.quad_sampling());
    for q in picomis::QuadSampling::ALL {
        let mut v = veach();
        v["integrator"]["quad_sampling"] = q.name().into();
        let s = load(&v).unwrap();
        assert_eq!(s.default_settings().quad_sampling(), q, "{q}");
        // The firmware's settings carry it too, where the scene has a quad light (Veach has
        // none: there quads by area, the same bits).
        assert!(!s.light_kinds().quads);
        assert_eq!(firmware_settings(&s).quad_sampling(), picomis::QuadSampling::Area, "{q}");
        v["shapes"][5]["emitter"] = serde_json::json!({ "type": "area", "radiance": [1.0, 1.0, 1.0] });
        let s = load(&v).unwrap();
        assert!(s.light_kinds().quads);
        assert_eq!(firmware_settings(&s).quad_sampling(), q, "{q}");
        let named = s.to_rust().contains(&format!("picomis::QuadSampling::{q:?})"));
        assert!(named, "{q}: the firmware's settings do not name it");
    }
    let mut v = veach();
    v["integrator"]["quad_sampling"] = "cone".into();
    rejects(
        &v,
        "integrator.quad_sampling",
        "unknown quad sampling \"cone\" (expected area, solid-angle, solid-angle-cosine, auto or by-size)",
    );
}

#[test]
fn firmware_names_by_size_only_where_it_differs_from_auto() {
    use picomis::{ControlVariate, QuadSampling};
    let best = Preset::Best.settings();
    assert_eq!(
        (best.control_variate(), best.quad_sampling()),
        (ControlVariate::BySize, QuadSampling::BySize)
    );
    // Veach: five lights, so the control variate `by-size` is `auto`, and the firmware names
    // `auto`'s type (no size rule linked).
    let s = load(&veach()).unwrap();
    assert_eq!(s.default_settings().control_variate(), ControlVariate::BySize);
    assert_eq!(firmware_settings(&s).control_variate(), ControlVariate::Auto);
    assert!(s.to_rust().contains("picomis::ControlVariate::Auto)"));
    // One area light (the sphere lights removed, the first plate made a light): `by-size`
    // differs from `auto` there, and stays.
    let mut v = veach();
    v["shapes"] = serde_json::Value::Array(
        v["shapes"].as_array().unwrap().iter().filter(|s| s.get("emitter").is_none()).cloned().collect(),
    );
    v["shapes"][0]["emitter"] = serde_json::json!({ "type": "area", "radiance": [1.0, 1.0, 1.0] });
    let one = load(&v).unwrap();
    assert_eq!(one.counts().lights, 1);
    assert_eq!(firmware_settings(&one).control_variate(), ControlVariate::BySize);
    assert_eq!(firmware_settings(&one).quad_sampling(), QuadSampling::BySize);
    // Quads `by-size` differ from `auto` only at Lambertian receivers: with none, `auto`.
    for m in v["materials"].as_object_mut().unwrap().values_mut() {
        if m["type"] == "lambertian" {
            *m = serde_json::json!({ "type": "ggx_conductor", "alpha": 0.2, "fresnel": "one", "specular_reflectance": [0.5, 0.5, 0.5] });
        }
    }
    let glossy = load(&v).unwrap();
    assert_eq!(firmware_settings(&glossy).quad_sampling(), QuadSampling::Auto);
    assert_eq!(firmware_settings(&glossy).control_variate(), ControlVariate::Off);
}

#[test]
fn light_selection_names_come_from_the_kernel() {
    let best = Preset::Best.settings();
    assert_eq!(load(&veach()).unwrap().default_settings().light_selection(), best.light_selection());
    for l in picomis::LightSelection::ALL {
        let mut v = veach();
        v["integrator"]["light_selection"] = l.name().into();
        let s = load(&v).unwrap();
        assert_eq!(s.default_settings().light_selection(), l, "{l:?}");
        // The firmware's settings carry it too (Veach has five lights: every selection applies).
        assert_eq!(firmware_settings(&s).light_selection(), l, "{l:?}");
        let named = s.to_rust().contains(&format!("picomis::LightSelection::{l:?})"));
        assert!(named, "{l:?}: the firmware's settings do not name it");
    }
    let mut v = veach();
    v["integrator"]["light_selection"] = "random".into();
    rejects(
        &v,
        "integrator.light_selection",
        "unknown light selection \"random\" (expected uniform, power, contribution or every)",
    );
    let mut v = veach();
    v["integrator"]["sampler"] = "halton".into();
    rejects(&v, "integrator.sampler", "unknown sampler \"halton\" (expected sobol or independent)");
}

#[test]
fn generated_rust_names_every_step_with_exact_bits() {
    let s = load(&veach()).unwrap();
    let code = s.to_rust();
    assert!(code.contains("pub const SHAPES: usize = 11;"));
    assert!(code.contains("pub const LIGHTS: usize = 5;"));
    assert!(code.contains("pub const MATERIALS: usize = 6;"));
    assert_eq!(code.matches("scene.add_shape(").count(), 11);
    assert_eq!(code.matches("scene.add_area_light(").count(), 5);
    assert_eq!(code.matches("scene.add_material(").count(), 6);
    // 0.03333 as f32 bits.
    assert!(code.contains(&format!("{:#010x}", 0.03333f32.to_bits())));
}
