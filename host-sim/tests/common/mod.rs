//! Running the built `picomis-sim` binary in tests.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs `picomis-sim` with `args` in folder `dir` (progress bars off: stderr is not a terminal).
pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_picomis-sim"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("running picomis-sim")
}

/// Runs `picomis-sim` and asserts that it succeeded.
pub fn run_ok(dir: &Path, args: &[&str]) -> Output {
    let out = run_in(dir, args);
    assert!(out.status.success(), "picomis-sim {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    out
}

/// The files in `dir`, sorted.
pub fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}
