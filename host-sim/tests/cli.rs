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
        // Negative numbers reach the value parsers (not clap's "to pass '-1' as a value" tip).
        (&["--spp", "-1"], "invalid value '-1' for '--spp <SPP>': -1 is not in 1.."),
        (&["--seed", "-1"], "invalid value '-1' for '--seed <SEED>': -1 is not in 0.."),
        (&["--width", "-5"], "invalid value '-5' for '--width <W>': -5 is not in 1..=16384"),
        (&["--light-samples", "-1"], "invalid value '-1' for '--light-samples <N>'"),
        (&["-j", "-1"], "invalid value '-1' for '--threads <N>'"),
        (&["--threads", "2000"], "invalid value '2000' for '--threads <N>'"),
        (&["--pixel", "3"], "invalid value '3' for '--pixel <X,Y>': expected X,Y"),
        (&["--pixel", "-1,2"], "invalid value '-1,2' for '--pixel <X,Y>': expected X,Y"),
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
        // A value that starts with '-' is read as the value (no "use '-- -1'"); an unknown flag
        // keeps clap's tip.
        assert!(reason.contains("unexpected argument") || !stderr.contains("-- -"), "{flags:?}: {stderr}");
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
    let Command::View { args: view, .. } =
        Cli::parse_from([&["picomis-sim", "view"][..], &flags].concat()).command
    else {
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

#[test]
fn the_help_groups_the_flags_under_headings() {
    let dir = tempfile::tempdir().unwrap();
    let help = |command: &str| String::from_utf8(run_ok(dir.path(), &[command, "--help"]).stdout).unwrap();
    let render = help("render");
    let headings: Vec<&str> = render.lines().filter(|l| !l.starts_with(' ') && l.ends_with(':')).collect();
    assert_eq!(
        headings,
        ["Arguments:", "Options:", "Scene:", "Sampling:", "Integrator:", "MIS:", "Output:", "Performance:"],
        "{render}"
    );
    // Under each heading its own flags.
    let section = |name: &str| -> String {
        render
            .lines()
            .skip_while(|l| *l != name)
            .skip(1)
            .take_while(|l| l.is_empty() || l.starts_with(' '))
            .collect()
    };
    for (heading, flags) in [
        ("Scene:", &["--width", "--height", "--arith"][..]),
        ("Sampling:", &["--spp", "--seed", "--light-samples", "--bsdf-samples", "--light-selection"]),
        ("MIS:", &["--mis <M>", "--beta", "--mis-model", "--control-variate"]),
        ("Output:", &["-o, --out", "--digest", "--pixel <X,Y>"]),
        ("Performance:", &["-j, --threads <N>"]),
    ] {
        for flag in flags {
            assert!(section(heading).contains(flag), "{flag} under {heading}: {render}");
        }
    }
    for command in ["figure", "study", "view"] {
        assert!(help(command).contains("-j, --threads <N>"), "{command}");
    }
}

#[test]
fn threads_do_not_change_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let render = |threads: &[&str], name: &str| {
        let args = [
            &["render", "veach_mis", "--width", "48", "--height", "32", "--spp", "3", "--digest", "-o", name]
                [..],
            threads,
        ]
        .concat();
        let out = run_ok(dir.path(), &args);
        let stderr = String::from_utf8(out.stderr).unwrap();
        (String::from_utf8(out.stdout).unwrap(), stderr, read(dir.path(), name))
    };
    let (digest1, stderr1, one) = render(&["-j", "1"], "one.pfm");
    let (digest2, stderr2, two) = render(&["--threads", "2"], "two.pfm");
    assert!(digest1.starts_with("hdr-digest "), "{digest1}");
    assert_eq!(digest1, digest2, "the digest of every pixel's estimate");
    assert_eq!(one, two, "the image");
    assert!(stderr1.contains(" on 1 thread -> one.pfm"), "{stderr1}");
    assert!(stderr2.contains(" on 2 threads -> two.pfm"), "{stderr2}");
    let (digest0, _, _) = render(&["-j", "0"], "all.pfm");
    assert_eq!(digest0, digest1);
    assert_eq!(files(dir.path()), ["all.pfm", "one.pfm", "two.pfm"]);
}

/// Runs `picomis-sim args` with the memory limit `limit` (bytes) in `dir`.
fn run_with_limit(dir: &Path, args: &[&str], limit: &str) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_picomis-sim"))
        .args(args)
        .env("PICOMIS_MEMORY_LIMIT", limit)
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn a_render_larger_than_memory_is_refused_before_it_allocates() {
    use picomis_sim::memory::render_bytes;
    use picomis_sim::output::Format;

    let dir = tempfile::tempdir().unwrap();
    let refused = |args: &[&str], limit: &str, reason: &str| {
        let out = run_with_limit(dir.path(), args, limit);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(reason),
            "{args:?}: {stderr:?} should say {reason:?}"
        );
        assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(files(dir.path()).is_empty(), "{args:?} wrote a file");
    };
    // The film: some 20 GB (refused here under a limit of 1 GB whatever the machine has).
    refused(
        &["render", "veach_mis", "--width", "16384", "--height", "16384", "-o", "big.png"],
        "1000000000",
        "veach_mis: a 16384x16384 render to big.png needs about ",
    );
    // The need is computed from the film and the format: a small render just over the limit is
    // refused, and runs at the limit.
    let film = picomis::Film::new(24, 16).unwrap();
    for (name, format) in [("a.png", Format::Png), ("a.exr", Format::Exr), ("a.pfm", Format::Pfm)] {
        let need = render_bytes(film, format);
        let args = ["render", "box_quad", "--width", "24", "--height", "16", "--spp", "1", "-o", name];
        refused(
            &args,
            &(need - 1).to_string(),
            &format!("a 24x16 render to {name} needs about {}", picomis_sim::memory::human(need)),
        );
        let out = run_with_limit(dir.path(), &args, &need.to_string());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        std::fs::remove_file(dir.path().join(name)).unwrap();
    }
    refused(
        &["figure", "lambert_sphere", "--spp", "1"],
        "1000",
        "lambert_sphere: a figure of 6 64x48 renders needs",
    );
    refused(
        &["render", "box_quad", "--spp", "1"],
        "lots",
        "PICOMIS_MEMORY_LIMIT=lots: expected a number of bytes",
    );
}

/// The fields of `--pixel`'s table row `part`: [samples, found, mean weight, red, green, blue]
/// (the pixel row has only the colour).
fn row<'a>(table: &'a str, part: &str) -> Vec<&'a str> {
    let line = table.lines().find(|l| l.split_whitespace().next() == Some(part)).expect(part);
    line.split_whitespace().skip(1).collect()
}

fn rgb(fields: &[&str]) -> [f32; 3] {
    let n = fields.len();
    [0, 1, 2].map(|i| fields[n - 3 + i].parse::<f32>().unwrap())
}

#[test]
fn pixel_breaks_the_estimate_down_by_technique() {
    use picomis_sim::output::read_pfm;

    let dir = tempfile::tempdir().unwrap();
    let mut both_techniques = 0;
    for (settings, pixels) in [
        // The best preset (the control variate's closed form is in the light part).
        (&["--spp", "4", "--seed", "3"][..], &[(36, 14), (36, 22), (30, 10), (12, 20)][..]),
        // The lecture's strategies: every light by sampling, balance weights.
        (
            &["--spp", "5", "--preset", "lecture", "--mis", "balance"],
            &[(30, 18), (36, 18), (20, 10), (24, 14)],
        ),
    ] {
        let base = [&["render", "veach_mis", "--width", "48", "--height", "32"][..], settings].concat();
        run_ok(dir.path(), &[&base[..], &["-o", "image.pfm"]].concat());
        let image = read_pfm(&dir.path().join("image.pfm")).unwrap();
        for &(x, y) in pixels {
            let at = format!("{x},{y}");
            let out = run_ok(dir.path(), &[&base[..], &["--pixel", &at, "-j", "1"]].concat());
            let table = String::from_utf8(out.stdout).unwrap();
            let title = table.lines().next().unwrap();
            assert!(
                title.starts_with("veach_mis: 48x32, ") && title.ends_with(&format!("; pixel ({x}, {y})")),
                "{table}"
            );
            let (emitted, light, bsdf, pixel) =
                (row(&table, "emitted"), row(&table, "light"), row(&table, "bsdf"), row(&table, "pixel"));
            // The parts add up to the pixel's value ...
            let (e, l, b, p) = (rgb(&emitted), rgb(&light), rgb(&bsdf), rgb(&pixel));
            for c in 0..3 {
                let sum = e[c] + l[c] + b[c];
                let tolerance = 2.0 * f32::EPSILON * (e[c].abs() + l[c].abs() + b[c].abs());
                assert!(
                    (sum - p[c]).abs() <= tolerance,
                    "({x}, {y}) channel {c}: {sum} != {}: {table}",
                    p[c]
                );
            }
            // ... which is the image's value there, bit for bit.
            let v = image.get(x, y);
            assert_eq!(p, [v.x, v.y, v.z], "({x}, {y}): {table}");
            // Counts and weights are what the columns say.
            let spp: u32 = settings[1].parse().unwrap();
            assert_eq!(emitted[0], spp.to_string(), "{table}");
            // One sample of each technique per camera sample; under the best preset a light
            // sample is one of each of Veach's five lights.
            let lights = if settings.contains(&"lecture") { 1 } else { 5 };
            for (t, n) in [(&light, lights), (&bsdf, 1)] {
                let (drawn, found): (u32, u32) = (t[0].parse().unwrap(), t[1].parse().unwrap());
                assert_eq!(drawn, spp * n, "{n} sample(s) of the technique per camera sample: {table}");
                assert!(found <= drawn, "{table}");
                if found > 0 {
                    let w: f32 = t[2].parse().unwrap();
                    assert!((0.0..=1.0).contains(&w), "{table}");
                } else {
                    assert_eq!(t[2], "-", "{table}");
                }
            }
            if l.iter().any(|&v| v > 0.0) && b.iter().any(|&v| v > 0.0) {
                both_techniques += 1;
            }
        }
    }
    assert!(both_techniques >= 4, "most checked pixels have light from both techniques");

    // No image is written; the pixel must lie on the film; it is no image, so no --out.
    assert_eq!(files(dir.path()), ["image.pfm"]);
    let args = ["render", "lambert_sphere", "--spp", "1"];
    for (flags, reason) in [
        (
            &["--pixel", "16,0"][..],
            "error: --pixel 16,0: outside the 16x12 film (X from 0 to 15, Y from 0 to 11)",
        ),
        (&["--pixel", "0,12"], "error: --pixel 0,12: outside the 16x12 film"),
        (
            &["--pixel", "1,1", "-o", "a.png"],
            "the argument '--pixel <X,Y>' cannot be used with '--out <FILE>'",
        ),
    ] {
        let out = run_in(dir.path(), &[&args[..], &["--height", "12"], flags].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.starts_with("error: ") && stderr.contains(reason), "{flags:?}: {stderr}");
    }
    assert_eq!(files(dir.path()), ["image.pfm"]);
}
