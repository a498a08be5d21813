//! Fuzzing the scene loader (a proptest harness: cargo-fuzz needs a nightly toolchain).
//!
//! Inputs: arbitrary bytes; byte-level mutations (flips, inserts, deletes, splices) of every
//! built-in scene; and structured mutations of their JSON (numbers replaced by edge values, keys
//! dropped or added, values retyped). Properties: loading never panics; every error names the
//! file, an entry and a reason; every accepted scene builds and renders finite pixels.
//!
//! Short run (part of the test command): the default case counts below. Long run:
//! `PICOMIS_FUZZ_CASES=200000 cargo test --release -p picomis-format --test fuzz -- --nocapture`.

mod common;

use common::{apply, byte_edit, cases, runner};
use picomis_format::SceneFile;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use serde_json::Value;
use std::sync::atomic::{AtomicU32, Ordering};

/// Bytes of the JSON syntax that byte edits insert.
const JSON_BYTES: &[u8] = b"{}[]\",:-.eE0123456789 ntfu\\";

/// Inputs accepted (and rendered) so far, per test: a fuzzer that only ever sees rejected
/// inputs would be vacuous.
static ACCEPTED: [AtomicU32; 3] = [AtomicU32::new(0), AtomicU32::new(0), AtomicU32::new(0)];

/// The built-in scenes: (name, text).
fn scenes() -> Vec<(&'static str, &'static str)> {
    picomis_builtins::BUILTINS.iter().map(|b| (b.name, b.json)).collect()
}

#[test]
fn the_inputs_are_the_same_on_every_run() {
    let strategy = proptest::collection::vec(any::<u8>(), 0..512);
    let draw = || {
        let mut r = runner(1);
        (0..16).map(|_| strategy.new_tree(&mut r).unwrap().current()).collect::<Vec<_>>()
    };
    let first = draw();
    assert_eq!(first, draw(), "two runners drew different inputs: the seed is not fixed");
    assert!(first.iter().any(|v| v.len() > 1), "the strategy drew only empty inputs");
}

/// Loads; on success builds and renders a few pixels at a tiny resolution.
fn check(text: &str, tally: usize) -> Result<(), TestCaseError> {
    match SceneFile::parse(text, "fuzz.json") {
        Err(e) => {
            prop_assert_eq!(e.file.as_str(), "fuzz.json");
            prop_assert!(!e.entry.is_empty() && !e.reason.is_empty(), "{}", e);
        }
        Ok(scene) => {
            if let Some(t) = ACCEPTED.get(tally) {
                t.fetch_add(1, Ordering::Relaxed);
            }
            common::renders_finite(&scene)?;
        }
    }
    Ok(())
}

#[test]
fn arbitrary_bytes_never_panic() {
    let n = cases(3000);
    runner(n)
        .run(&proptest::collection::vec(any::<u8>(), 0..512), |bytes| {
            check(&String::from_utf8_lossy(&bytes), 0)
        })
        .unwrap();
    println!("fuzz: {n} arbitrary inputs tried, {} accepted", ACCEPTED[0].load(Ordering::Relaxed));
}

#[test]
fn byte_mutations_of_builtin_scenes_never_panic() {
    let n = cases(3000);
    let scenes = scenes();
    let strategy = (0..scenes.len(), proptest::collection::vec(byte_edit(JSON_BYTES, 128), 1..6));
    runner(n).run(&strategy, |(i, edits)| check(&apply(scenes[i].1, &edits), 1)).unwrap();
    let accepted = ACCEPTED[1].load(Ordering::Relaxed);
    println!("fuzz: {n} byte-mutated scenes tried, {accepted} accepted and rendered");
    assert!(accepted > 0, "no mutated scene was accepted: the render path went untested");
}

/// Edge values a number (or any leaf) is replaced with.
fn edge_value() -> impl Strategy<Value = Value> {
    prop_oneof![
        prop::sample::select(vec![
            0.0, -0.0, 1.0, -1.0, 1e-45, -1e-45, 1e-38, 1e-7, 0.5, 1.0000001, 179.99999, 180.0, 1e30, 3.4e38,
            1e39, -1e39, 1e300, 16384.0, 16385.0, 65536.0,
        ])
        .prop_map(Value::from),
        any::<i64>().prop_map(Value::from),
        any::<f32>().prop_filter("finite", |v| v.is_finite()).prop_map(|v| Value::from(f64::from(v))),
        Just(Value::Null),
        Just(Value::from("x")),
        Just(Value::from(true)),
        Just(Value::Array(vec![])),
        Just(serde_json::json!([1, 2])),
        Just(serde_json::json!({})),
    ]
}

#[derive(Clone, Debug)]
enum TreeEdit {
    Replace(usize, Value),
    Remove(usize),
    AddKey(usize, String),
    Duplicate(usize),
}

fn tree_edit() -> impl Strategy<Value = TreeEdit> {
    prop_oneof![
        4 => (any::<usize>(), edge_value()).prop_map(|(i, v)| TreeEdit::Replace(i, v)),
        1 => any::<usize>().prop_map(TreeEdit::Remove),
        1 => (any::<usize>(), "[a-z_]{1,8}").prop_map(|(i, k)| TreeEdit::AddKey(i, k)),
        1 => any::<usize>().prop_map(TreeEdit::Duplicate),
    ]
}

/// Visits every node (pre-order) and applies `f` to the `target`-th one.
fn visit(v: &mut Value, target: &mut usize, f: &mut dyn FnMut(&mut Value)) -> bool {
    if *target == 0 {
        f(v);
        return true;
    }
    *target -= 1;
    match v {
        Value::Array(a) => a.iter_mut().any(|c| visit(c, target, f)),
        Value::Object(o) => o.values_mut().any(|c| visit(c, target, f)),
        _ => false,
    }
}

fn count(v: &Value) -> usize {
    1 + match v {
        Value::Array(a) => a.iter().map(count).sum(),
        Value::Object(o) => o.values().map(count).sum(),
        _ => 0,
    }
}

fn edit_tree(mut v: Value, edits: &[TreeEdit]) -> Value {
    for e in edits {
        let n = count(&v);
        match e {
            TreeEdit::Replace(i, new) => {
                visit(&mut v, &mut (i % n), &mut |node| *node = new.clone());
            }
            TreeEdit::Remove(i) => {
                visit(&mut v, &mut (i % n), &mut |node| match node {
                    Value::Object(o) => {
                        let key = o.keys().nth(o.len() / 2).cloned();
                        if let Some(k) = key {
                            o.remove(&k);
                        }
                    }
                    Value::Array(a) => {
                        a.pop();
                    }
                    _ => {}
                });
            }
            TreeEdit::AddKey(i, k) => {
                visit(&mut v, &mut (i % n), &mut |node| {
                    if let Value::Object(o) = node {
                        o.insert(k.clone(), Value::from(1));
                    }
                });
            }
            TreeEdit::Duplicate(i) => {
                visit(&mut v, &mut (i % n), &mut |node| {
                    if let Value::Array(a) = node {
                        if let Some(first) = a.first().cloned() {
                            // Grow arrays (shape and light lists) past small capacities.
                            for _ in 0..40 {
                                a.push(first.clone());
                            }
                        }
                    }
                });
            }
        }
    }
    v
}

#[test]
fn structured_mutations_of_builtin_scenes_never_panic() {
    let n = cases(3000);
    let trees: Vec<Value> = scenes().iter().map(|(_, t)| serde_json::from_str(t).unwrap()).collect();
    let strategy = (0..trees.len(), proptest::collection::vec(tree_edit(), 1..4));
    runner(n)
        .run(&strategy, |(i, edits)| check(&edit_tree(trees[i].clone(), &edits).to_string(), 2))
        .unwrap();
    let accepted = ACCEPTED[2].load(Ordering::Relaxed);
    println!("fuzz: {n} structurally mutated scenes tried, {accepted} accepted and rendered");
    assert!(
        accepted > n / 20,
        "too few mutated scenes were accepted ({accepted}): the render path went untested"
    );
}

#[test]
fn builtin_scenes_are_accepted_and_render() {
    for (name, text) in scenes() {
        let scene = SceneFile::parse(text, name).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.name(), name);
        check(text, 3).unwrap();
    }
}

#[test]
fn deeply_nested_input_is_an_error_not_a_stack_overflow() {
    let deep = "[".repeat(100_000);
    assert!(SceneFile::parse(&deep, "deep.json").is_err());
    let deep_obj = format!("{{\"format\":{}", "{\"a\":".repeat(50_000));
    assert!(SceneFile::parse(&deep_obj, "deep.json").is_err());
}
