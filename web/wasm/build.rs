//! Embeds the built-in scenes: every `../../scenes/*.json`, sorted by name, as the host's
//! `picomis-sim` does (the list of built-in scenes is that folder).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let dir = manifest.join("../../scenes");
    println!("cargo::rerun-if-changed={}", dir.display());
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    let mut code = String::from("&[\n");
    for path in &files {
        println!("cargo::rerun-if-changed={}", path.display());
        let name = path.file_stem().and_then(|s| s.to_str()).expect("UTF-8 file name");
        let path = path.canonicalize().expect("canonical path");
        writeln!(
            code,
            "    Builtin {{ name: {name:?}, json: include_str!({:?}) }},",
            path.display().to_string()
        )
        .expect("write to String");
    }
    code.push(']');
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("builtin_scenes.rs");
    fs::write(&out, code).unwrap_or_else(|e| panic!("writing {}: {e}", out.display()));
}
