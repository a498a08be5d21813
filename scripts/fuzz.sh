#!/usr/bin/env bash
# Long, coverage-guided fuzzing of the scene loaders with cargo-fuzz (libFuzzer): the JSON scene
# loader (target load_scene) and the Mitsuba 3 XML importer (target import_mitsuba).
#   scripts/fuzz.sh [SECONDS] [TARGET...]   (default 600 seconds for each of both targets)
# The short runs that are part of the test command are the proptest harnesses in
# format/tests/fuzz.rs and format/tests/fuzz_mitsuba.rs. cargo-fuzz needs nightly-only flags;
# this machine has a stable toolchain only, so RUSTC_BOOTSTRAP=1 unlocks them for this build (the
# fuzz crate is its own workspace).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds="${1:-600}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(load_scene import_mitsuba)
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
mkdir -p corpus/load_scene corpus/import_mitsuba
cp ../scenes/*.json corpus/load_scene/
cp ../format/tests/data/*.xml corpus/import_mitsuba/
for target in "${targets[@]}"; do
  log="/tmp/picomis-fuzz-$target.log"
  RUSTC_BOOTSTRAP=1 cargo fuzz run "$target" -- -max_total_time="$seconds" -max_len=16384 -rss_limit_mb=512 -timeout=5 2>&1 \
    | tee "$log" | grep -E '^#[0-9]+ +(DONE|pulse)|ERROR|panicked|Done [0-9]+ runs' || true
  grep -q 'ERROR' "$log" && { echo "fuzz $target: crash found, see fuzz/artifacts/$target/" >&2; exit 1; }
  echo "fuzz $target: no crash"
done
