#!/usr/bin/env bash
# The one test command of picomis (README: "Test"). CI runs exactly this (.ci/run).
# It installs what it needs (rustup targets and components, QEMU from Debian's packages), then:
# format, lints, docs, all host tests, kernel cross-builds for Cortex-M, firmware under QEMU.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> %s\n' "$*"; }

step "toolchain: targets and components"
rustup component add rustfmt clippy llvm-tools >/dev/null 2>&1 || true
installed=$(rustup target list --installed)
for t in thumbv7em-none-eabihf thumbv6m-none-eabi riscv32imc-unknown-none-elf; do
  grep -qx "$t" <<<"$installed" || rustup target add "$t"
done

step "Debian packages for the view window: SDL2, Xvfb, ImageMagick (import)"
missing=()
command -v Xvfb >/dev/null || missing+=(xvfb)
command -v import >/dev/null || missing+=(imagemagick)
dpkg -s libsdl2-dev >/dev/null 2>&1 || missing+=(libsdl2-dev)
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy -D warnings (host crates, all targets)"
cargo clippy --all-targets -- -D warnings
cargo clippy -p picomis-sim --all-targets --features window -- -D warnings

step "kernel: no f64, no alloc"
# Code lines only: doc comments may name f64 (to say why it is avoided).
if grep -rnE '\bf64\b|extern crate alloc|alloc::' kernel/src | grep -vE '^[^:]+:[0-9]+:\s*//'; then
  echo "the kernel must not use f64 or alloc" >&2
  exit 1
fi

step "kernel cross-builds (thumbv7em-none-eabihf, thumbv6m-none-eabi, riscv32imc-unknown-none-elf; with and without defmt)"
scripts/symbols.sh --self-test
for t in thumbv7em-none-eabihf thumbv6m-none-eabi riscv32imc-unknown-none-elf; do
  cargo build -p picomis --release --target "$t"
  # The built kernel, not its source: no f64 routine, no allocator symbol (the firmware ELFs are
  # checked the same way by scripts/firmware.sh test).
  scripts/symbols.sh "${CARGO_TARGET_DIR:-target}/$t/release/libpicomis.rlib"
  cargo build -p picomis --release --target "$t" --features defmt
  cargo clippy -p picomis --target "$t" --features defmt -- -D warnings
  # The fixed-point ray queries (feature fixed: the firmware's `fixed` builds).
  cargo clippy -p picomis --target "$t" --features defmt,fixed -- -D warnings
done

step "docs (-D warnings)"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps -p picomis -p picomis-format

step "crates.io packages: cargo publish --dry-run (picomis, picomis-format)"
# Packaged together: picomis-format's picomis resolves to the kernel packaged beside it. Each
# package is built from its .crate alone. --allow-dirty: the suite also runs on uncommitted trees.
# Cargo takes a registry package of the same name and version for unchanged: it reuses an earlier
# run's extraction of the packaged kernel (in CARGO_HOME's registry sources) and its build, so
# picomis-format would be verified against a stale kernel (one without a variant added since).
# Remove both first; the verification builds in a target folder of its own.
rm -rf "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/picomis-[0-9]* "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/picomis-format-[0-9]*
publish_target="${CARGO_TARGET_DIR:-target}/publish"
rm -rf "$publish_target"/debug/.fingerprint/picomis-* "$publish_target"/debug/deps/libpicomis*
CARGO_TARGET_DIR="$publish_target" cargo publish --dry-run --allow-dirty -p picomis -p picomis-format

step "kernel unit tests in a debug build (overflow checks on: RenderStats of a 4096x4096 film at 256 spp)"
cargo test -p picomis --lib
# With the fixed-point ray queries: their i64 products under overflow checks.
cargo test -p picomis --lib --features fixed

step "host tests (release: the statistical suites are compute-bound)"
cargo test --release

step "README firmware table == firmware/budget.json"
scripts/budget.sh readme --check

step "view window under Xvfb: screenshot and simulator dump equal render --out F.rgb565"
cargo test --release -p picomis-sim --features window --test window

if [ -x scripts/firmware.sh ]; then
  step "firmware under QEMU: M4F, M0 and RV32IMC, pixels equal to the host's; soft float and dot products bit for bit"
  scripts/firmware.sh test
  step "firmware budgets: instructions per camera sample, flash text, static RAM, peak stack"
  scripts/firmware.sh budget
  step "firmware crates: rustfmt and clippy -D warnings for every target (firmware, picomis-embedded, picomis-softfloat)"
  scripts/firmware.sh lint
  step "board examples (STM32F4 + ST7789, RP2040 + ILI9341): build for their targets, clippy and rustfmt clean"
  scripts/firmware.sh boards
fi

step "browser: the kernel as WebAssembly in headless Chromium, pixels equal to the host's"
scripts/web.sh test
