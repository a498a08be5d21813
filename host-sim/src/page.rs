//! The browser page (`web/`) built into the binary, so that `picomis-sim serve` needs neither
//! the source tree nor a separate build step: the page's files, and its WebAssembly (the kernel
//! as the crate `picomis-web`, compiled by `build.rs` for `wasm32-unknown-unknown` when that
//! target is installed).

/// The name under which the page loads its WebAssembly (`web/worker.js`).
pub const WASM_FILE: &str = "picomis.wasm";

/// The page's files besides the WebAssembly, by name, as `web/` holds them.
pub const FILES: [(&str, &[u8]); 4] = [
    ("index.html", include_bytes!("../../web/index.html")),
    ("main.js", include_bytes!("../../web/main.js")),
    ("style.css", include_bytes!("../../web/style.css")),
    ("worker.js", include_bytes!("../../web/worker.js")),
];

/// The WebAssembly `build.rs` wrote (empty when it could not build one).
const WASM: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/picomis.wasm"));

/// Why `build.rs` built no WebAssembly.
const WASM_MISSING: Option<&str> = option_env!("PICOMIS_WASM_MISSING");

/// The page's WebAssembly, or why this binary has none.
pub fn wasm() -> Result<&'static [u8], &'static str> {
    match WASM_MISSING {
        Some(why) => Err(why),
        None if WASM.is_empty() => Err("the build wrote an empty WebAssembly file"),
        None => Ok(WASM),
    }
}

/// The page's file `name` (a name of [`FILES`] or [`WASM_FILE`]); `None` for any other name.
pub fn file(name: &str) -> Option<&'static [u8]> {
    if name == WASM_FILE {
        return wasm().ok();
    }
    FILES.iter().find(|(n, _)| *n == name).map(|(_, bytes)| *bytes)
}
