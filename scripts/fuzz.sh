#!/usr/bin/env bash
# Long, coverage-guided fuzzing of the scene loader with cargo-fuzz (libFuzzer).
#   scripts/fuzz.sh [SECONDS]      (default 600)
# The short run that is part of the test command is the proptest harness in
# format/tests/fuzz.rs. cargo-fuzz needs nightly-only flags; this machine has a stable toolchain
# only, so RUSTC_BOOTSTRAP=1 unlocks them for this build (the fuzz crate is its own workspace).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds="${1:-600}"
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
mkdir -p corpus/load_scene
cp ../scenes/*.json corpus/load_scene/
RUSTC_BOOTSTRAP=1 cargo fuzz run load_scene -- -max_total_time="$seconds" -max_len=16384 -rss_limit_mb=512 -timeout=5 2>&1 \
  | tee /tmp/picomis-fuzz.log | grep -E '^#[0-9]+ +(DONE|pulse)|ERROR|panicked|Done [0-9]+ runs' || true
grep -q 'ERROR' /tmp/picomis-fuzz.log && { echo "fuzz: crash found, see fuzz/artifacts/" >&2; exit 1; }
echo "fuzz: no crash"
