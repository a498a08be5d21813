//! The command line: every class of bad input is an error naming the file, the entry and the
//! reason, with exit code 2, no panic and no image written; and the outputs that do get written.

mod common;

use std::path::Path;

use common::{files, run_in, run_ok};
use serde_json::{Value, json};

const LAMBERT: &str = include_str!("../../scenes/lambert_sphere.json");

fn lambert() -> Value {
    serde_json::from_str(LAMBERT).unwrap()
}

/// Runs `render` (and `figure`) on scene text `text` written to `bad.json`, and checks that it
/// fails cleanly: exit code 2, `error: bad.json: <entry>: <reason>`, no panic, no output file.
fn rejects_scene(text: &str, entry: &str, reason: &str) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.json"), text).unwrap();
    for command in ["render", "figure"] {
        let out = run_in(dir.path(), &[command, "bad.json", "--spp", "1", "--out", "out.png"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{command}: exit code for {entry}: {reason}; stderr: {stderr}"
        );
        let prefix = format!("error: bad.json: {entry}");
        assert!(stderr.starts_with(&prefix), "{command}: {stderr:?} should start with {prefix:?}");
        assert!(stderr.contains(reason), "{command}: {stderr:?} should say {reason:?}");
        assert!(!stderr.contains("panicked"), "{command} panicked: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
        assert_eq!(files(dir.path()), ["bad.json"], "{command} wrote a file");
    }
}

fn rejects(v: &Value, entry: &str, reason: &str) {
    rejects_scene(&serde_json::to_string_pretty(v).unwrap(), entry, reason);
}

#[test]
fn unknown_key() {
    let mut v = lambert();
    v["shapes"][1]["colour"] = json!(1);
    rejects(&v, "shapes[1] \"sphere_light\".colour", "unknown field `colour`");
    let mut v = lambert();
    v["colour"] = json!("red");
    rejects(&v, "colour", "unknown field `colour`");
}

#[test]
fn unknown_type() {
    let mut v = lambert();
    v["shapes"][1]["type"] = json!("cube");
    rejects(&v, "shapes[1] \"sphere_light\"", "unknown variant `cube`");
    let mut v = lambert();
    v["materials"]["plane_diffuse"]["type"] = json!("velvet");
    rejects(&v, "materials.plane_diffuse", "unknown variant `velvet`");
}

#[test]
fn wrong_type() {
    let mut v = lambert();
    v["shapes"][1]["radius"] = json!("big");
    rejects(&v, "shapes[1] \"sphere_light\".radius", "invalid type: string \"big\", expected f32");
    let mut v = lambert();
    v["film"]["width"] = json!(64.5);
    rejects(&v, "film.width", "invalid type");
}

#[test]
fn non_finite_numbers() {
    // JSON has no NaN or infinity: 1e999 overflows f64, 1e39 overflows f32, "NaN" is a string.
    rejects_scene(
        &LAMBERT.replace("\"radius\": 0.5", "\"radius\": 1e999"),
        "shapes[1].radius",
        "number out of range",
    );
    rejects_scene(
        &LAMBERT.replace("\"radius\": 0.5", "\"radius\": 1e39"),
        "shapes[1] \"sphere_light\"",
        "radius is not a finite number",
    );
    let mut v = lambert();
    v["shapes"][1]["emitter"]["radiance"] = json!(["NaN", 1.0, 1.0]);
    rejects(&v, "shapes[1] \"sphere_light\".emitter.radiance[0]", "invalid type: string \"NaN\"");
    rejects_scene(
        &LAMBERT.replace("\"albedo\": [0.8, 0.8, 0.8]", "\"albedo\": [0.8, 1e39, 0.8]"),
        "materials.plane_diffuse",
        "albedo is not a finite number",
    );
}

#[test]
fn out_of_range_numbers() {
    let mut v = lambert();
    v["shapes"][1]["radius"] = json!(-0.5);
    rejects(&v, "shapes[1] \"sphere_light\"", "radius must be positive");
    let mut v = lambert();
    v["shapes"][1]["emitter"]["radiance"] = json!([-1.0, 1.0, 1.0]);
    rejects(&v, "shapes[1] \"sphere_light\"", "radiance is out of range");
    let mut v = lambert();
    v["camera"]["fov_deg"] = json!(180.0);
    rejects(&v, "camera", "fov_deg is out of range");
}

#[test]
fn degenerate_quads() {
    // Zero area: all corners on one line.
    let mut v = lambert();
    let q = &mut v["shapes"][0];
    q["p1"] = json!([0.0, 0.0, 20.0]);
    q["p2"] = json!([-20.0, 0.0, 20.0]);
    q["p3"] = json!([-40.0, 0.0, 20.0]);
    q.as_object_mut().unwrap().remove("normal");
    rejects(&v, "shapes[0] \"plane\"", "quad has zero area");
    // Not a parallelogram: p2 != p1 + p3 - p0.
    let mut v = lambert();
    v["shapes"][0]["p2"] = json!([20.0, 0.0, -25.0]);
    rejects(&v, "shapes[0] \"plane\"", "not a parallelogram");
}

#[test]
fn too_many_objects_for_the_build() {
    // Scenes get the host capacity of 64 shapes.
    let mut v = lambert();
    let shapes = v["shapes"].as_array_mut().unwrap();
    for i in 0..70 {
        shapes.push(json!({
            "type": "sphere", "name": format!("ball{i}"), "center": [f64::from(i) * 0.1 - 3.0, 3.0, -5.0],
            "radius": 0.01, "material": "plane_diffuse"
        }));
    }
    rejects(&v, "shapes[64] \"ball62\"", "too many shapes for this build (it holds 64)");
}

#[test]
fn malformed_json() {
    rejects_scene(&LAMBERT[..300], "", "EOF while parsing");
    rejects_scene("{ \"format\": \"picomis-scene/1\", }", "", "trailing comma");
    rejects_scene("", "", "EOF while parsing");
}

#[test]
fn missing_file_and_unknown_scene() {
    let dir = tempfile::tempdir().unwrap();
    for (arg, reason) in [
        ("missing.json", "No such file"),
        ("no_such_scene", "no such file, and no built-in scene of that name"),
    ] {
        let out = run_in(dir.path(), &["render", arg, "--out", "out.png"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.starts_with(&format!("error: {arg}: file: ")) && stderr.contains(reason), "{stderr}");
        assert!(!stderr.contains("panicked"));
        assert!(files(dir.path()).is_empty());
    }
}

#[test]
fn bad_flag_values() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--mis", "foo"], "invalid value 'foo' for '--mis"),
        (&["--mis", "power", "--beta", "0"], "power-heuristic beta is out of range"),
        (&["--beta", "-1"], "power-heuristic beta is out of range"),
        (&["--beta", "nan"], "power-heuristic beta is out of range"),
        (&["--mis", "balance", "--beta", "3"], "only the power heuristic has a beta"),
        (&["--mis", "cutoff", "--alpha", "1.5"], "cutoff alpha is out of range"),
        (&["--mis", "power", "--alpha", "0.2"], "only the cutoff heuristic has an alpha"),
        (&["--mis", "light", "--light-samples", "0"], "both sample counts are zero"),
        (&["--spp", "0"], "invalid value '0' for '--spp"),
        (&["--spp", "many"], "invalid value 'many' for '--spp"),
        (&["--sphere-sampling", "disk"], "invalid value 'disk' for '--sphere-sampling"),
        (&["--light-selection", "random"], "invalid value 'random' for '--light-selection"),
        (&["--width", "0"], "invalid value '0' for '--width"),
        (&["--height", "20000"], "invalid value '20000' for '--height"),
        (&["--light-samples", "70000"], "invalid value '70000' for '--light-samples"),
        (&["--seed", "-1"], "unexpected argument '-1'"),
        (&["--frobnicate"], "unexpected argument '--frobnicate'"),
        (&["--mis-model", "one", "--c-light", "1.5"], "c_light is out of range"),
        (&["--mis-model", "one", "--c-light", "nan"], "c_light is not a finite number"),
        // (The reason names the key as a scene file does: picomis-format's message.)
        (&["--c-light", "0.5"], "--c-light: 0.5: only the one-sample model (mis_model one) has a c"),
        (&["--mis-model", "two"], "invalid value 'two' for '--mis-model"),
        (&["--quad-sampling", "cone"], "invalid value 'cone' for '--quad-sampling"),
        (&["--control-variate", "yes"], "invalid value 'yes' for '--control-variate"),
    ];
    for (flags, reason) in cases {
        let mut args = vec!["render", "lambert_sphere", "--out", "out.png"];
        args.extend_from_slice(flags);
        let out = run_in(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flags:?}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(reason),
            "{flags:?}: {stderr:?} should say {reason:?}"
        );
        assert!(!stderr.contains("panicked"), "{flags:?}: {stderr}");
        assert!(files(dir.path()).is_empty(), "{flags:?} wrote a file");
    }
    // Output paths are checked before rendering.
    for (out_arg, reason) in
        [("x.jpg", "unknown image format \"jpg\""), ("no/such/dir/x.png", "does not exist")]
    {
        let out = run_in(dir.path(), &["render", "lambert_sphere", "--out", out_arg]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.starts_with(&format!("error: {out_arg}: ")) && stderr.contains(reason), "{stderr}");
    }
    let out = run_in(dir.path(), &["figure", "lambert_sphere", "--out", "f.exr"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("the figure is written as PNG"));
    assert!(files(dir.path()).is_empty());
}

#[test]
fn the_help_lists_the_kernels_methods() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_ok(dir.path(), &["render", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    // The values of --mis (other flags have values of the same names: `power` light selection).
    let mis = help.lines().skip_while(|l| !l.trim_start().starts_with("--mis <")).collect::<Vec<_>>();
    for m in picomis::Method::ALL {
        let line = mis.iter().find(|l| l.trim_start().starts_with(&format!("- {}:", m.name())));
        assert!(line.is_some_and(|l| l.trim_end().ends_with(m.summary())), "{m}: {help}");
    }
    // The parameters' defaults are the kernel's.
    let (beta, alpha) = (picomis::Heuristic::DEFAULT_BETA, picomis::Heuristic::DEFAULT_ALPHA);
    assert!(
        help.contains(&format!("Power-heuristic exponent (default {beta})"))
            && help.contains(&format!("Cutoff-heuristic threshold (default {alpha})")),
        "{help}"
    );
}

#[test]
fn scenes_lists_the_builtins() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_ok(dir.path(), &["scenes"]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    let names: Vec<&str> = stdout.lines().filter_map(|l| l.split_whitespace().next()).collect();
    assert_eq!(names, ["box_quad", "lambert_sphere", "point_lights", "stress", "veach_mis"]);
    let veach: Vec<&str> = stdout.lines().last().unwrap().split_whitespace().take(9).collect();
    assert_eq!(veach, ["veach_mis", "384x256", "11", "shapes", "5", "lights", "6", "materials", "Veach"]);
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap()
}

#[test]
fn every_format_holds_the_same_render() {
    use embedded_graphics::pixelcolor::RgbColor;
    use picomis_sim::output::{read_exr, read_pfm, rgb565};

    let dir = tempfile::tempdir().unwrap();
    let base =
        ["render", "box_quad", "--width", "24", "--height", "16", "--spp", "4", "--seed", "3", "--out"];
    for name in ["a.pfm", "a.exr", "a.png", "a.rgb565"] {
        let mut args = base.to_vec();
        args.push(name);
        let out = run_ok(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.starts_with("box_quad: 24x16, 4 spp, power (beta 2), 1 light + 1 bsdf samples, "),
            "{stderr}"
        );
        assert!(stderr.contains("camera samples/s") && stderr.trim_end().ends_with(name), "{stderr}");
    }
    assert_eq!(files(dir.path()), ["a.exr", "a.pfm", "a.png", "a.rgb565"], "no temporary files are left");
    let pfm = read_pfm(&dir.path().join("a.pfm")).unwrap();
    assert_eq!((pfm.width, pfm.height), (24, 16));
    assert!(pfm.data.iter().any(|c| c.y > 0.05), "the box is lit");
    assert_eq!(read_exr(&dir.path().join("a.exr")).unwrap(), pfm, "EXR and PFM hold the same floats");

    let raw = read(dir.path(), "a.rgb565");
    let expected: Vec<u8> = pfm.data.iter().flat_map(|&c| rgb565(c).to_le_bytes()).collect();
    assert_eq!(raw, expected);

    let decoder = png::Decoder::new(std::io::Cursor::new(read(dir.path(), "a.png")));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height, info.color_type), (24, 16, png::ColorType::Rgb));
    let expected: Vec<u8> = pfm
        .data
        .iter()
        .flat_map(|&c| {
            let t = picomis::tone_map(c);
            [t.r(), t.g(), t.b()]
        })
        .collect();
    assert_eq!(&buf[..info.buffer_size()], &expected[..]);
}

#[test]
fn rgb565_is_the_embedded_graphics_framebuffer() {
    use embedded_graphics::framebuffer::{Framebuffer, buffer_size};
    use embedded_graphics::geometry::Size;
    use embedded_graphics::pixelcolor::Rgb565;
    use embedded_graphics::pixelcolor::raw::{LittleEndian, RawU16};
    use picomis::integrator::{control_variate, model};
    use picomis::light::select::Uniform;
    use picomis::light::{lobe, quad, sphere};
    use picomis::{Direct, Film, Heuristic, Integrator, Lights, Method, Preset, RenderSettings};
    use picomis_format::SceneFile;

    const W: usize = 24;
    const H: usize = 16;
    let dir = tempfile::tempdir().unwrap();
    // The lecture's strategies, named as types below (the best preset's may change).
    run_ok(
        dir.path(),
        &[
            "render", "box_quad", "--width", "24", "--height", "16", "--spp", "4", "--seed", "3", "--preset",
            "lecture", "--out", "a.rgb565",
        ],
    );

    // What the firmware does: its scene with its own capacities, the estimator of the strategy
    // types its settings name, rendered tile by tile into an embedded-graphics framebuffer.
    type Lecture =
        Direct<Lights<Uniform, sphere::InCone, quad::ByArea, lobe::Off>, control_variate::Off, model::Multi>;
    let file = SceneFile::parse(include_str!("../../scenes/box_quad.json"), "box_quad").unwrap();
    let scene = file.build_with_film::<7, 1, 4>(Film::new(W as u32, H as u32).unwrap()).unwrap();
    let settings = RenderSettings::new(Method::Mis(Heuristic::Power { beta: 2.0 }), 1, 1, 4, 3)
        .unwrap()
        .with_strategies_of(Preset::Lecture);
    let integrator = Integrator::<Lecture, 7, 1, 4>::new(&scene, &settings).unwrap();
    let mut fb = Framebuffer::<Rgb565, RawU16, LittleEndian, W, H, { buffer_size::<Rgb565>(W, H) }>::new();
    integrator.render(Size::new(8, 8), &mut fb, |_, _| {}).unwrap();
    assert_eq!(read(dir.path(), "a.rgb565"), fb.data());
}

#[test]
fn renders_are_deterministic_and_independent_of_threads() {
    let dir = tempfile::tempdir().unwrap();
    let render = |threads: &str, seed: &str, name: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_picomis-sim"))
            .args(["render", "point_lights", "--width", "40", "--height", "30", "--spp", "2", "--seed", seed])
            .args(["--out", name])
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(out.status.success());
        read(dir.path(), name)
    };
    let one = render("1", "5", "a.pfm");
    assert_eq!(render("2", "5", "b.pfm"), one);
    assert_eq!(render("3", "5", "c.pfm"), one);
    assert_ne!(render("2", "6", "d.pfm"), one, "another seed gives another image");
}

#[test]
fn builtin_and_file_capacities_give_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("copy.json"), include_str!("../../scenes/stress.json")).unwrap();
    let args = ["--width", "40", "--height", "24", "--spp", "2"];
    run_ok(dir.path(), &[&["render", "stress", "--out", "a.pfm"][..], &args].concat());
    run_ok(dir.path(), &[&["render", "copy.json", "--out", "b.pfm"][..], &args].concat());
    assert_eq!(read(dir.path(), "a.pfm"), read(dir.path(), "b.pfm"));
}

#[test]
fn defaults_and_aspect_ratio() {
    let dir = tempfile::tempdir().unwrap();
    // No scene: the Veach scene, written to veach_mis.png here.
    let out = run_ok(dir.path(), &["render", "--spp", "1", "--width", "48"]);
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("veach_mis: 48x32, 1 spp, power (beta 2)"));
    assert_eq!(files(dir.path()), ["veach_mis.png"]);
    let out =
        run_ok(dir.path(), &["render", "lambert_sphere", "--spp", "1", "--height", "12", "--mis", "cutoff"]);
    assert!(
        String::from_utf8_lossy(&out.stderr).starts_with("lambert_sphere: 16x12, 1 spp, cutoff (alpha 0.1)")
    );
    assert_eq!(files(dir.path()), ["lambert_sphere.png", "veach_mis.png"]);
}

#[test]
fn figure_is_a_labelled_png() {
    let dir = tempfile::tempdir().unwrap();
    run_ok(dir.path(), &["figure", "lambert_sphere", "--spp", "1"]);
    assert_eq!(files(dir.path()), ["lambert_sphere_figure.png"]);
    let decoder = png::Decoder::new(std::io::Cursor::new(read(dir.path(), "lambert_sphere_figure.png")));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    // Four columns of panels (64x48 scaled by 5 to 320x240) and three rows.
    assert_eq!((info.width, info.height), (4 * 320 + 5 * 14, 96 + 3 * (28 + 240 + 14) + 10));
}

/// A pass of N spp in `picomis-sim view FLAGS` has the settings of
/// `picomis-sim render --spp N FLAGS`.
#[test]
fn a_view_pass_renders_what_render_renders() {
    use clap::Parser;
    use picomis_sim::cli::{Cli, Command, settings};
    use picomis_sim::view::ViewState;

    let flags = ["--mis", "cutoff", "--alpha", "0.2", "--light-selection", "power", "--seed", "5"];
    let loaded = picomis_sim::scenes::load(Some("veach_mis")).unwrap();
    let Command::View(view) = Cli::parse_from([&["picomis-sim", "view"][..], &flags].concat()).command else {
        panic!("not view")
    };
    let Command::Render(render) =
        Cli::parse_from([&["picomis-sim", "render", "--spp", "8"][..], &flags].concat()).command
    else {
        panic!("not render")
    };
    let state = ViewState::new(&loaded, &view).unwrap();
    let (from_view, from_render) = (state.settings(8).unwrap(), settings(&loaded, &render).unwrap());
    assert_eq!(from_view, from_render);
    // And the flags did reach them: not the defaults.
    assert_ne!(
        from_render,
        settings(&loaded, &{
            let Command::Render(r) = Cli::parse_from(["picomis-sim", "render", "--spp", "8"]).command else {
                panic!("not render")
            };
            r
        })
        .unwrap()
    );
}
