//! Generates the list of built-in scenes from the workspace's `scenes/*.json`: each file is
//! loaded (strictly) by picomis-format, which also writes the module (`builtins_rust`).

use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let dir = manifest.join("../scenes");
    println!("cargo::rerun-if-changed={}", dir.display());
    let mut paths: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    let mut scenes = Vec::new();
    for path in paths {
        println!("cargo::rerun-if-changed={}", path.display());
        let file = picomis_format::SceneFile::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let path = path.canonicalize().expect("canonical path");
        scenes.push((path.display().to_string(), file));
    }
    let code = picomis_format::builtins_rust(&scenes).unwrap_or_else(|e| panic!("{e}"));
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("builtins.rs");
    fs::write(&out, code).unwrap_or_else(|e| panic!("writing {}: {e}", out.display()));
}
