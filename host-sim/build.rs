//! Embeds the built-in scenes (`../scenes/*.json`) and generates a dispatch that builds each one
//! with its own kernel capacities, `Scene<shapes, lights, materials>`, counted here from the JSON.
//! The counts follow picomis-format's `Counts`: shapes, area emitters plus point lights, and
//! materials; a unit test checks that both agree.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let dir = manifest.join("../scenes");
    println!("cargo::rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();

    let mut table = String::new();
    let mut arms = String::new();
    for path in &files {
        println!("cargo::rerun-if-changed={}", path.display());
        let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
        let json: serde_json::Value =
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let stem = path.file_stem().and_then(|s| s.to_str()).expect("UTF-8 file name");
        let name = json["name"].as_str().unwrap_or_else(|| panic!("{}: no name", path.display()));
        assert_eq!(name, stem, "{}: a built-in scene's name must match its file name", path.display());
        let shapes = json["shapes"].as_array().map_or(0, Vec::len);
        let emitters =
            json["shapes"].as_array().map_or(0, |s| s.iter().filter(|s| s.get("emitter").is_some()).count());
        let points = json.get("lights").and_then(|l| l.as_array()).map_or(0, Vec::len);
        let lights = emitters + points;
        let materials = json["materials"].as_object().map_or(0, |m| m.len());
        let description = json["description"].as_str().unwrap_or("");
        writeln!(
            table,
            "    Builtin {{ name: {name:?}, json: include_str!({path:?}), description: {description:?}, \
             shapes: {shapes}, lights: {lights}, materials: {materials} }},",
            path = path.canonicalize().expect("canonical path").display().to_string(),
        )
        .expect("write to String");
        writeln!(arms, "        {name:?} => Ok(visitor.visit(file.build_with_film::<{shapes}, {lights}, {materials}>(film)?)),")
            .expect("write to String");
    }

    let code = format!(
        "/// The built-in scenes, sorted by name.\n\
         pub const BUILTINS: &[Builtin] = &[\n{table}];\n\n\
         /// Builds `file` for `film` with the capacities of built-in scene `builtin` (its own\n\
         /// counts), or with the host capacities for any other file, and hands it to `visitor`.\n\
         pub fn dispatch<V: SceneVisitor>(\n    builtin: Option<&str>,\n    file: &SceneFile,\n    film: Film,\n    visitor: V,\n\
         ) -> Result<V::Output, LoadError> {{\n    match builtin.unwrap_or(\"\") {{\n{arms}        \
         _ => Ok(visitor.visit(file.build_with_film::<HOST_SHAPES, HOST_LIGHTS, HOST_MATERIALS>(film)?)),\n    }}\n}}\n"
    );
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("builtin_scenes.rs");
    fs::write(&out, code).unwrap_or_else(|e| panic!("writing {}: {e}", out.display()));
}
