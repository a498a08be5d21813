//! Fuzzing the Mitsuba 3 XML importer like the JSON loader (`fuzz.rs`; cargo-fuzz target
//! `import_mitsuba` in `fuzz/` for long runs): it reads files from anywhere.
//!
//! Inputs: arbitrary bytes; byte-level mutations of valid XML files (the Veach scene as Mitsuba
//! renders it, the transform test file, and the export of every built-in scene); and structured
//! mutations of them (attribute values replaced by edge values, elements deleted, duplicated or
//! moved). Properties: importing never panics; every error is one line naming `fuzz.xml`, a line
//! or entry and a reason; every accepted file is a valid `picomis-scene/1` file that builds and
//! renders finite pixels.
//!
//! Long run: `PICOMIS_FUZZ_CASES=200000 cargo test --release -p picomis-format --test fuzz_mitsuba`.

use std::sync::atomic::{AtomicU32, Ordering};

mod common;

use common::{apply, byte_edit, cases, runner};
use picomis_format::{SceneFile, mitsuba};
use proptest::prelude::*;

/// Bytes of the XML syntax that byte edits insert.
const XML_BYTES: &[u8] = b"<>/=\"'$&;-.eE0123456789 ,xyz";

static ACCEPTED: [AtomicU32; 3] = [AtomicU32::new(0), AtomicU32::new(0), AtomicU32::new(0)];

const SCENES: [&str; 5] = [
    include_str!("../../scenes/veach_mis.json"),
    include_str!("../../scenes/lambert_sphere.json"),
    include_str!("../../scenes/box_quad.json"),
    include_str!("../../scenes/point_lights.json"),
    include_str!("../../scenes/stress.json"),
];

/// The seed files: two hand-written XML files and the export of every built-in scene.
fn seeds() -> Vec<String> {
    let mut v =
        vec![include_str!("data/veach_mis.xml").to_string(), include_str!("data/transforms.xml").to_string()];
    v.extend(SCENES.iter().map(|s| mitsuba::export(s, "builtin").unwrap().xml));
    v
}

/// Imports; on success loads, builds and renders a few pixels at a tiny resolution.
fn check(text: &str, tally: usize) -> Result<(), TestCaseError> {
    match mitsuba::import(text, "fuzz.xml", "fuzz") {
        Err(e) => {
            prop_assert!(e.file.starts_with("fuzz.xml"), "{}", e);
            prop_assert!(!e.entry.is_empty() && !e.reason.is_empty(), "{}", e);
            prop_assert_eq!(e.to_string().lines().count(), 1, "{}", e);
        }
        Ok(json) => {
            ACCEPTED[tally].fetch_add(1, Ordering::Relaxed);
            let scene =
                SceneFile::parse(&json, "fuzz.json").map_err(|e| TestCaseError::fail(e.to_string()))?;
            common::renders_finite(&scene)?;
        }
    }
    Ok(())
}

#[test]
fn arbitrary_bytes_never_panic() {
    let n = cases(2000);
    runner(n)
        .run(&proptest::collection::vec(any::<u8>(), 0..512), |bytes| {
            check(&String::from_utf8_lossy(&bytes), 0)
        })
        .unwrap();
    println!("fuzz_mitsuba: {n} arbitrary inputs tried, {} accepted", ACCEPTED[0].load(Ordering::Relaxed));
}

#[test]
fn byte_mutations_of_valid_files_never_panic() {
    let seeds = seeds();
    for s in &seeds {
        mitsuba::import(s, "seed.xml", "seed").unwrap();
    }
    let n = cases(4000);
    let strategy = (0..seeds.len(), proptest::collection::vec(byte_edit(XML_BYTES, 160), 1..5));
    runner(n).run(&strategy, |(i, edits)| check(&apply(&seeds[i], &edits), 1)).unwrap();
    let accepted = ACCEPTED[1].load(Ordering::Relaxed);
    println!("fuzz_mitsuba: {n} byte-mutated files tried, {accepted} accepted and rendered");
    assert!(accepted > 0, "no mutated file was accepted: the render path went untested");
}

/// Values an attribute is replaced with.
const EDGE: [&str; 24] = [
    "0",
    "-0",
    "1",
    "-1",
    "1e-45",
    "1e-38",
    "0.5",
    "1.0000001",
    "179.99999",
    "180",
    "1e30",
    "3.4e38",
    "1e39",
    "-1e39",
    "nan",
    "inf",
    "-inf",
    "16385",
    "65536",
    "",
    "x",
    "1, 2",
    "0 0 0",
    "$nothing",
];

#[derive(Clone, Debug)]
enum TreeEdit {
    /// Replace the i-th attribute value.
    Value(usize, &'static str),
    /// Delete, duplicate or move the i-th line (one element per line in the seeds).
    DeleteLine(usize),
    DuplicateLine(usize, u8),
    MoveLine(usize, usize),
}

fn tree_edit() -> impl Strategy<Value = TreeEdit> {
    prop_oneof![
        4 => (any::<usize>(), prop::sample::select(EDGE.to_vec())).prop_map(|(i, v)| TreeEdit::Value(i, v)),
        1 => any::<usize>().prop_map(TreeEdit::DeleteLine),
        1 => (any::<usize>(), 1u8..70).prop_map(|(i, k)| TreeEdit::DuplicateLine(i, k)),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| TreeEdit::MoveLine(a, b)),
    ]
}

/// Byte ranges of the attribute values in `text`.
fn values(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = text[from..].find("=\"") {
        let start = from + i + 2;
        let Some(len) = text[start..].find('"') else { break };
        out.push((start, start + len));
        from = start + len + 1;
    }
    out
}

fn edit_tree(text: &str, edits: &[TreeEdit]) -> String {
    let mut t = text.to_string();
    for e in edits {
        match *e {
            TreeEdit::Value(i, v) => {
                let ranges = values(&t);
                if !ranges.is_empty() {
                    let (a, b) = ranges[i % ranges.len()];
                    t.replace_range(a..b, v);
                }
            }
            TreeEdit::DeleteLine(i) | TreeEdit::DuplicateLine(i, _) | TreeEdit::MoveLine(i, _) => {
                let mut lines: Vec<String> = t.lines().map(str::to_string).collect();
                let n = lines.len().max(1);
                let k = i % n;
                if k < lines.len() {
                    match *e {
                        TreeEdit::DeleteLine(_) => {
                            lines.remove(k);
                        }
                        TreeEdit::DuplicateLine(_, times) => {
                            let l = lines[k].clone();
                            for _ in 0..times {
                                lines.insert(k, l.clone());
                            }
                        }
                        TreeEdit::MoveLine(_, to) => {
                            let l = lines.remove(k);
                            let at = to % (lines.len() + 1);
                            lines.insert(at, l);
                        }
                        TreeEdit::Value(..) => {}
                    }
                }
                t = lines.join("\n");
            }
        }
    }
    t
}

#[test]
fn structured_mutations_of_valid_files_never_panic() {
    let seeds = seeds();
    let n = cases(4000);
    let strategy = (0..seeds.len(), proptest::collection::vec(tree_edit(), 1..4));
    runner(n).run(&strategy, |(i, edits)| check(&edit_tree(&seeds[i], &edits), 2)).unwrap();
    let accepted = ACCEPTED[2].load(Ordering::Relaxed);
    println!("fuzz_mitsuba: {n} structurally mutated files tried, {accepted} accepted and rendered");
    assert!(accepted > n / 20, "too few mutated files accepted ({accepted}): the render path went untested");
}
