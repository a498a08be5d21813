//! The browser page's WebAssembly for `picomis-sim serve`, built into the binary (`src/page.rs`)
//! so that an installed `picomis-sim` serves the page with no source tree and no separate step.
//!
//! Writes `$OUT_DIR/picomis.wasm`: the crate `picomis-web` (`web/wasm`) built for
//! `wasm32-unknown-unknown` in the workspace's `wasm` profile (the one `scripts/web.sh build`
//! uses), by a cargo of its own whose target folder lies in `$OUT_DIR` (the outer build's folder
//! is locked by the outer cargo). The file is empty, and `PICOMIS_WASM_MISSING` says why, when:
//! - the `wasm32-unknown-unknown` target is not installed (a `cargo:warning`; `serve` then says
//!   how to get it, and `serve --dir` still serves a folder);
//! - the build script runs under clippy, which checks and links no binary.
//!
//! `PICOMIS_WASM=FILE` embeds a WebAssembly built elsewhere instead (e.g. `web/picomis.wasm`).
//! The build reruns when a source file of the WebAssembly changes (from its dep-info file).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

const TARGET: &str = "wasm32-unknown-unknown";
const PROFILE: &str = "wasm";
const CRATE_FILE: &str = "picomis_web.wasm";

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=PICOMIS_WASM");
    println!("cargo::rerun-if-env-changed=CLIPPY_ARGS");
    let out = PathBuf::from(env("OUT_DIR"));
    let wasm = out.join("picomis.wasm");
    let result = if let Some(file) = std::env::var_os("PICOMIS_WASM") {
        println!("cargo::rerun-if-changed={}", Path::new(&file).display());
        let bytes = std::fs::read(&file)
            .unwrap_or_else(|e| fail(&format!("PICOMIS_WASM={}: {e}", Path::new(&file).display())));
        Ok(bytes)
    } else if std::env::var_os("CLIPPY_ARGS").is_some() {
        Err("this build was checked by clippy, which links no binary".to_string())
    } else {
        build(&out)
    };
    let bytes = result.unwrap_or_else(|why| {
        println!("cargo::rustc-env=PICOMIS_WASM_MISSING={why}");
        Vec::new()
    });
    std::fs::write(&wasm, bytes).unwrap_or_else(|e| fail(&format!("{}: {e}", wasm.display())));
}

fn env(name: &str) -> OsString {
    std::env::var_os(name).unwrap_or_else(|| fail(&format!("{name} is not set")))
}

fn fail(message: &str) -> ! {
    panic!("picomis-sim build.rs: {message}")
}

/// Builds `picomis-web` for the page; `Err(why)` when the target is not installed.
fn build(out: &Path) -> Result<Vec<u8>, String> {
    let manifest_dir = PathBuf::from(env("CARGO_MANIFEST_DIR"));
    let workspace = manifest_dir.parent().unwrap_or_else(|| fail("host-sim has no parent folder"));
    let rustc = env("RUSTC");
    let sysroot = Command::new(&rustc)
        .args(["--print", "sysroot"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
        .unwrap_or_else(|| fail("rustc --print sysroot failed"));
    let rustlib = sysroot.join("lib/rustlib");
    // Rustup rewrites `components` when a target is added; without rustup, watch the folder.
    let components = rustlib.join("components");
    let watch = if components.is_file() { components } else { rustlib.clone() };
    println!("cargo::rerun-if-changed={}", watch.display());
    if !rustlib.join(TARGET).is_dir() {
        let why = format!(
            "the {TARGET} target is not installed: `rustup target add {TARGET}`, then build picomis-sim again"
        );
        println!("cargo::warning=picomis-sim is built without the browser page's WebAssembly: {why}");
        return Err(why);
    }

    let target_dir = out.join("wasm-target");
    let mut cargo = Command::new(env("CARGO"));
    cargo
        .current_dir(workspace)
        .args(["build", "--quiet", "-p", "picomis-web", "--target", TARGET, "--profile", PROFILE])
        .env("CARGO_TARGET_DIR", &target_dir)
        .env("RUSTC", &rustc);
    // What the outer build sets for host code or for clippy must not reach the WebAssembly.
    for var in [
        "RUSTFLAGS",
        "CARGO_ENCODED_RUSTFLAGS",
        "CARGO_BUILD_RUSTFLAGS",
        "CARGO_BUILD_TARGET",
        "RUSTC_WORKSPACE_WRAPPER",
        "CLIPPY_ARGS",
    ] {
        cargo.env_remove(var);
    }
    let output = cargo.output().unwrap_or_else(|e| fail(&format!("running cargo: {e}")));
    if !output.status.success() {
        fail(&format!(
            "building the page's WebAssembly (cargo build -p picomis-web --target {TARGET} --profile {PROFILE}) failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let built = target_dir.join(TARGET).join(PROFILE);
    watch_sources(&built.join(CRATE_FILE.replace(".wasm", ".d")), workspace);
    let file = built.join(CRATE_FILE);
    Ok(std::fs::read(&file).unwrap_or_else(|e| fail(&format!("{}: {e}", file.display()))))
}

/// Reruns this script when a workspace file the WebAssembly was built from changes: its sources
/// (from the dep-info file `dep_info`) and the manifests of their crates, and the lock file.
fn watch_sources(dep_info: &Path, workspace: &Path) {
    let text =
        std::fs::read_to_string(dep_info).unwrap_or_else(|e| fail(&format!("{}: {e}", dep_info.display())));
    let mut watched = vec![workspace.join("Cargo.toml"), workspace.join("Cargo.lock")];
    for line in text.lines() {
        // `target: dep dep ...`, spaces in paths escaped with a backslash.
        let Some((_, deps)) = line.split_once(": ") else { continue };
        let mut path = String::new();
        let mut chars = deps.chars();
        let mut paths = Vec::new();
        while let Some(c) = chars.next() {
            match c {
                '\\' => path.extend(chars.next()),
                ' ' => paths.push(std::mem::take(&mut path)),
                c => path.push(c),
            }
        }
        paths.push(path);
        for p in paths.into_iter().filter(|p| !p.is_empty()).map(PathBuf::from) {
            if !p.starts_with(workspace) || p.starts_with(workspace.join("target")) {
                continue; // registry sources do not change; generated files follow their inputs
            }
            if let Some(manifest) =
                p.ancestors().map(|d| d.join("Cargo.toml")).find(|m| m.is_file() && m.starts_with(workspace))
            {
                watched.push(manifest);
            }
            watched.push(p);
        }
    }
    watched.sort();
    watched.dedup();
    for p in watched {
        println!("cargo::rerun-if-changed={}", p.display());
    }
}
