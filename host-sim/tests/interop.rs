//! `picomis-sim import` and `export` on the command line: bad XML is one line naming the file,
//! line and element, exit code 2, no panic and no output file; every built-in scene exported to
//! Mitsuba 3 XML and imported back renders the same bytes.

mod common;

use common::{files, run_in, run_ok};

const VEACH_XML: &str = include_str!("../../format/tests/data/veach_mis.xml");

#[test]
fn bad_xml_is_one_line_exit_2_and_writes_nothing() {
    let cases = [
        (
            "<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n    <bsdf type=\"plastic\"/>\n  </shape>\n</scene>\n",
            "error: bad.xml:3: <bsdf type=\"plastic\">: not modelled by picomis (diffuse, roughconductor)",
        ),
        ("<scene version=\"3.0.0\"><shape", "error: bad.xml:1: xml: "),
        ("", "error: bad.xml:1: xml: "),
        ("\u{feff}<scene version=\"3.0.0\"/>", "error: bad.xml:1: <scene>: no <sensor"),
    ];
    for (text, message) in cases {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("bad.xml"), text).unwrap();
        let out = run_in(dir.path(), &["import", "bad.xml", "--out", "bad.json"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.starts_with(message), "{stderr:?} should start with {message:?}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert_eq!(files(dir.path()), ["bad.xml"], "a file was written");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = run_in(dir.path(), &["import", "missing.xml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: missing.xml: file: "));
    let out = run_in(dir.path(), &["export", "no_such_scene", "--mitsuba", "x.xml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(files(dir.path()).is_empty());
}

#[test]
fn the_veach_xml_imports_and_renders() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("veach_mis.xml"), VEACH_XML).unwrap();
    run_ok(dir.path(), &["import", "veach_mis.xml"]);
    let json = std::fs::read_to_string(dir.path().join("veach_mis.json")).unwrap();
    assert!(json.contains("\"name\": \"veach_mis\""));
    run_ok(dir.path(), &["render", "./veach_mis.json", "--spp", "1", "--width", "48", "--out", "v.png"]);
}

#[test]
fn every_builtin_scene_survives_export_and_import_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let list = run_ok(d, &["scenes"]);
    let names: Vec<String> = String::from_utf8_lossy(&list.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect();
    assert!(names.len() >= 5, "{names:?}");
    for name in &names {
        let xml = format!("{name}.xml");
        run_ok(d, &["export", name, "--mitsuba", &xml]);
        run_ok(d, &["import", &xml, "--out", &format!("{name}.json")]);
        let rendered = |scene: &str, out: &str| {
            run_ok(d, &["render", scene, "--spp", "2", "--width", "40", "--mis", "balance", "--out", out]);
            std::fs::read(d.join(out)).unwrap()
        };
        let a = rendered(name, &format!("{name}_a.pfm"));
        let b = rendered(&format!("./{name}.json"), &format!("{name}_b.pfm"));
        assert_eq!(a, b, "{name}: the image changed in the round trip");
        // Exporting the import gives the same XML again (names, values: all kept).
        run_ok(d, &["export", &format!("./{name}.json"), "--mitsuba", &format!("{name}_2.xml")]);
        // All but the header comment (which names the source file and its description).
        let strip =
            |s: String| s.lines().skip_while(|l| !l.starts_with("<scene")).collect::<Vec<_>>().join("\n");
        let x1 = strip(std::fs::read_to_string(d.join(&xml)).unwrap());
        let x2 = strip(std::fs::read_to_string(d.join(format!("{name}_2.xml"))).unwrap());
        assert_eq!(x1, x2, "{name}");
    }
}
